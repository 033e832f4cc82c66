"""Random one-degree-of-freedom mechanisms, built in Python from a seed: a crank (angle theta)
driving either a slider through a connecting rod (an RRP dyad) or a rocker through a coupler
(an RRR dyad), with random lengths, masses, springs between random body points and random
anchors, random point forces, torques, gravity and dampers. Every number is a parameter
(its example value the drawn one), so that the model is data exactly as a user writes it.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from codegen.compiler.model.mechanism import (Body, Coordinate, Damper, Mechanism,
                                              PointForce, Requirement, Spring, Torque, distance, parameter)


class _Parameters:
    """Collects the parameters a model draws: ``draw(name, unit, lo, hi)`` is the symbol,
    ``values[name]`` the value drawn."""

    def __init__(self, rng):
        self.rng, self.list, self.values = rng, [], {}

    def draw(self, name: str, unit: str, lo: float, hi: float) -> sp.Symbol:
        value = float(self.rng.uniform(lo, hi))
        self.list.append(parameter(name, unit, name, repr(value)))
        self.values[name] = value
        return self.list[-1].symbol


def _bar(name, mass, start, end, length, angle) -> Body:
    """A uniform bar from start to end: its centre, and inertia m L^2 / 12 about it."""
    centre = ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2)
    return Body(name, mass, centre, inertia=mass * length**2 / 12, angle=angle)


def _on(origin, angle, along, across):
    """The point ``along`` a body's axis from origin and ``across`` to its left."""
    c, s = sp.cos(angle), sp.sin(angle)
    return (origin[0] + along * c - across * s, origin[1] + along * s + across * c)


def random_mechanism(seed: int, kind: str | None = None) -> Mechanism:
    """kind: "slider" or "four_bar" (None: drawn)."""
    rng = np.random.default_rng(seed)
    P = _Parameters(rng)
    theta = Coordinate("theta", "rad", "crank angle")
    phi = Coordinate("phi", "rad", "rod (coupler) angle")
    a = P.draw("a", "m", 0.05, 0.2)
    a_value = P.values["a"]
    l = P.draw("l", "m", 0.6 * a_value, 3.0 * a_value)   # a short rod: limit positions
    t, f = theta.function, phi.function
    A = (a * sp.cos(t), a * sp.sin(t))
    crank = _bar("crank", P.draw("m_1", "kg", 0.1, 2.0), (0, 0), A, a, t)
    lengths = [a, l]   # declared positive: a length that divides a position has a sign
    slider = rng.random() < 0.5 if kind is None else kind == "slider"
    if slider:
        x = Coordinate("x", "m", "slider position")
        e = P.draw("e", "m", -a_value, a_value)
        B = (x.function, e)
        constraints = (A[0] + l * sp.cos(f) - B[0], A[1] + l * sp.sin(f) - e)
        mode = B[0] - A[0]
        third, third_coordinate = Body("slider", P.draw("m_3", "kg", 0.1, 3.0), B), x
        third_points = [B]
    else:
        psi = Coordinate("psi", "rad", "rocker angle")
        d = P.draw("d", "m", 1.0 * a_value, 3.0 * a_value)
        b = P.draw("b", "m", 0.6 * a_value, 3.0 * a_value)
        b_value = P.values["b"]
        B = (d + b * sp.cos(psi.function), b * sp.sin(psi.function))
        constraints = (A[0] + l * sp.cos(f) - B[0], A[1] + l * sp.sin(f) - B[1])
        mode = (d - A[0]) * (B[1] - A[1]) + A[1] * (B[0] - A[0])
        third = _bar("rocker", P.draw("m_3", "kg", 0.1, 2.0), (d, 0), B, b, psi.function)
        third_coordinate = psi
        lengths += [d, b]
        third_points = [B, _on((d, 0), psi.function, P.draw("r_4", "m", 0, b_value), 0)]
    rod = _bar("rod", P.draw("m_2", "kg", 0.1, 2.0), A, B, l, f)
    size = 3.0 * a_value
    points = [A, _on(A, f, P.draw("u", "m", -a_value, 2 * a_value),
                     P.draw("w", "m", -a_value, a_value)), *third_points]
    springs, dampers, forces, torques = [], [], [], []
    for i in range(int(rng.integers(1, 3))):
        anchor = (P.draw(f"x_S{i}", "m", -size, size), P.draw(f"y_S{i}", "m", -size, size))
        length = distance(points[rng.integers(len(points))], anchor)
        springs.append(Spring(P.draw(f"k_{i}", "N/m", 10, 2000),
                              P.draw(f"l_{i}", "m", 0, size), length))
        if rng.random() < 0.5:
            dampers.append(Damper(P.draw(f"c_{i}", "N s/m", 0.1, 50), length))
    coordinates = (theta, phi, third_coordinate)
    if rng.random() < 0.6:
        damped = coordinates[rng.integers(3)]
        dampers.append(Damper(P.draw("c_q", "SI", 0.1, 20), damped.function))
    if rng.random() < 0.6:
        forces.append(PointForce(points[rng.integers(len(points))],
                                 (P.draw("F_x", "N", -50, 50), P.draw("F_y", "N", -50, 50))))
    if rng.random() < 0.6:
        torques.append(Torque(P.draw("T", "N m", -5, 5),
                              (t, f, third_coordinate.function)[rng.integers(2 + (not slider))]))
    sign = 1 if rng.random() < 0.5 else -1   # either assembly mode may be the declared one
    gravity = P.draw("g", "m/s^2", 0, 10)
    return Mechanism(
        name=f"random_{seed}",
        parameters=tuple(P.list),
        coordinates=coordinates,
        independent="theta",
        constraints=constraints,
        bodies=(crank, rod, third),
        springs=tuple(springs),
        dampers=tuple(dampers),
        forces=tuple(forces),
        torques=tuple(torques),
        gravity=gravity,
        points={},
        assembly_modes=(sign * mode,),
        requirements=(Requirement(sp.And(*(x > 0 for x in lengths)), "LENGTH_NOT_POSITIVE",
                                  "link lengths must be positive"),),
        title=f"random {'slider-crank' if slider else 'four-bar'} {seed}",
    )
