"""Random chains of two dyads, built in Python from a seed (issue 30's property test): a crank
(angle theta) drives a first dyad, and a point on one of that dyad's links drives a second
one. Each dyad is drawn an RRR (a coupler and a rocker about a ground pin), an RRP (a rod
and a slider on a line through a ground point, at a drawn inclination) or an RPR (the driving
point sliding in the slot of a lever pivoted at a ground pin, a polar pair, whose lever then
drives what follows), each declared in a drawn assembly mode; the second may also be a PRR (a
collar sliding along the first dyad's link or lever, held by a bar from a ground pin). Every
pair is drawn. Lengths, masses, the driving point, springs between random joints and anchors,
a damper, a force and gravity are drawn too; every number is a parameter whose
example is the value drawn, so the model is data exactly as a user writes it.
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from codegen.compiler.model.mechanism import (Body, Coordinate, Damper, Mechanism, PointForce,
                                              Requirement, Spring, distance)

from random_mechanisms import _bar, _on, _Parameters

KINDS = ("RRR", "RRP")              # either dyad
FIRST_KINDS = (*KINDS, "RPR")        # the crank pin never reaches the slot's pin
#: The pairs the derivation solves: any first dyad, then an RRR, RRP or RPR, or a PRR (the
#: collar slides along the first dyad's link or slotted lever).
PAIRS = tuple((first, second) for first in FIRST_KINDS for second in (*KINDS, "RPR", "PRR"))


def _left_of(a, b, p):
    """Positive where p lies left of the line from a to b (an assembly-mode condition)."""
    return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])


class _Chain:
    """What the dyads add to the model as they are drawn."""

    def __init__(self, rng, P: _Parameters, scale: float):
        self.rng, self.P, self.scale = rng, P, scale
        self.coordinates, self.constraints, self.bodies = [], [], []
        self.lengths, self.modes, self.joints, self.polar = [], [], [], []

    def slot(self, k: int, start):
        """An RPR dyad: ``start`` slides in the slot of a lever pivoted at a ground pin Q, at
        distance s_k along it (a polar pair with the lever's angle). Returns the lever as
        (origin, angle, length)."""
        P, s = self.P, self.scale
        along = Coordinate(f"s_{k}", "m", f"distance along the slot of dyad {k}")
        lever = Coordinate(f"phi_{k}", "rad", f"lever angle of dyad {k}")
        pin = (P.draw(f"x_Q{k}", "m", 1.5 * s, 2.5 * s), P.draw(f"y_Q{k}", "m", -s, s))
        length = P.draw(f"L_{k}", "m", 3.0 * s, 4.0 * s)
        f, d = lever.function, along.function
        self.coordinates += [along, lever]
        self.polar.append((along.name, lever.name))
        self.lengths.append(length)
        self.constraints += [start[0] - pin[0] - d * sp.cos(f), start[1] - pin[1] - d * sp.sin(f)]
        tip = (pin[0] + length * sp.cos(f), pin[1] + length * sp.sin(f))
        self.bodies += [_bar(f"lever_{k}", P.draw(f"m_L{k}", "kg", 0.1, 2.0), pin, tip, length, f),
                        Body(f"block_{k}", P.draw(f"m_b{k}", "kg", 0.1, 1.0), start)]
        self.joints += [tip]
        return pin, f, length

    def collar(self, k: int, line):
        """A PRR dyad: a collar slides along the moving link ``line`` (origin, angle, length),
        at distance s_k from its origin, held by a bar of length L_k from a ground pin."""
        P, rng, s = self.P, self.rng, self.scale
        (origin, angle, _), sign = line, (1 if rng.random() < 0.5 else -1)
        along = Coordinate(f"s_{k}", "m", f"distance of the collar along the link, dyad {k}")
        bar = Coordinate(f"psi_{k}", "rad", f"angle of the collar's bar, dyad {k}")
        pin = (P.draw(f"x_G{k}", "m", -1.5 * s, 1.5 * s), P.draw(f"y_G{k}", "m", -1.5 * s, 1.5 * s))
        L = P.draw(f"L_{k}", "m", 0.8 * s, 2.0 * s)
        d, g = along.function, bar.function
        collar = (origin[0] + d * sp.cos(angle), origin[1] + d * sp.sin(angle))
        end = (pin[0] + L * sp.cos(g), pin[1] + L * sp.sin(g))
        self.coordinates += [along, bar]
        self.lengths.append(L)
        self.constraints += [collar[0] - end[0], collar[1] - end[1]]
        self.bodies += [Body(f"collar_{k}", P.draw(f"m_C{k}", "kg", 0.1, 1.0), collar),
                        _bar(f"bar_{k}", P.draw(f"m_g{k}", "kg", 0.1, 2.0), pin, end, L, g)]
        # the collar beyond (or short of) the foot of the perpendicular from the pin
        self.modes.append(sign * (d - ((pin[0] - origin[0]) * sp.cos(angle)
                                       + (pin[1] - origin[1]) * sp.sin(angle))))
        self.joints += [collar]

    def dyad(self, k: int, start, kind: str, line=None):
        """A dyad from the known joint ``start`` (a PRR: along the moving link ``line``):
        returns its two moving links as (origin, angle, length) for a later dyad to be
        driven from."""
        if kind == "RPR":
            return self.slot(k, start), None
        if kind == "PRR":
            return self.collar(k, line), None
        P, rng, s = self.P, self.rng, self.scale
        link = Coordinate(f"phi_{k}", "rad", f"link angle of dyad {k}")
        l = P.draw(f"l_{k}", "m", 0.8 * s, 2.0 * s)
        f = link.function
        end = (start[0] + l * sp.cos(f), start[1] + l * sp.sin(f))
        self.coordinates.append(link)
        self.lengths.append(l)
        sign = 1 if rng.random() < 0.5 else -1   # either mode may be the declared one
        if kind == "RRR":
            rocker = Coordinate(f"psi_{k}", "rad", f"rocker angle of dyad {k}")
            pin = (P.draw(f"x_O{k}", "m", -1.5 * s, 1.5 * s), P.draw(f"y_O{k}", "m", -1.5 * s, 1.5 * s))
            r = P.draw(f"r_{k}", "m", 0.8 * s, 2.0 * s)
            g = rocker.function
            joint = (pin[0] + r * sp.cos(g), pin[1] + r * sp.sin(g))
            self.coordinates.append(rocker)
            self.lengths.append(r)
            self.constraints += [end[0] - joint[0], end[1] - joint[1]]
            self.bodies += [_bar(f"link_{k}", P.draw(f"m_l{k}", "kg", 0.1, 2.0), start, end, l, f),
                            _bar(f"rocker_{k}", P.draw(f"m_r{k}", "kg", 0.1, 2.0), pin, joint, r, g)]
            self.modes.append(sign * _left_of(start, pin, joint))
            second = (pin, g, r)
        else:
            slider = Coordinate(f"x_{k}", "m", f"slider position of dyad {k}")
            alpha = P.draw(f"alpha_{k}", "rad", -0.8, 0.8)
            base = (P.draw(f"x_B{k}", "m", -s, s), P.draw(f"y_B{k}", "m", -s, s))
            x = slider.function
            joint = (base[0] + x * sp.cos(alpha), base[1] + x * sp.sin(alpha))
            self.coordinates.append(slider)
            self.constraints += [end[0] - joint[0], end[1] - joint[1]]
            self.bodies += [_bar(f"link_{k}", P.draw(f"m_l{k}", "kg", 0.1, 2.0), start, end, l, f),
                            Body(f"slider_{k}", P.draw(f"m_s{k}", "kg", 0.1, 2.0), joint)]
            # the link's end ahead of (or behind) its start along the slide
            self.modes.append(sign * ((joint[0] - start[0]) * sp.cos(alpha)
                                      + (joint[1] - start[1]) * sp.sin(alpha)))
            second = None
        self.joints += [end]
        return (start, f, l), second


def random_chain(seed: int, kinds: tuple[str, str] | None = None) -> Mechanism:
    """A crank driving two dyads in a chain (kinds drawn from PAIRS unless given)."""
    rng = np.random.default_rng(seed)
    kinds = kinds or PAIRS[rng.integers(len(PAIRS))]
    P = _Parameters(rng)
    theta = Coordinate("theta", "rad", "crank angle")
    a = P.draw("a", "m", 0.05, 0.2)
    s = 2.0 * P.values["a"]
    t = theta.function
    A = (a * sp.cos(t), a * sp.sin(t))
    chain = _Chain(rng, P, s)
    chain.lengths.append(a)
    first, rocker = chain.dyad(1, A, kinds[0])
    # the second dyad starts from a point on the first dyad's link or rocker, off its axis
    line = rocker if rocker is not None and rng.random() < 0.5 else first
    origin, angle, length = line
    driver = _on(origin, angle, P.draw("u", "m", 0.2 * s, 1.5 * s), P.draw("w", "m", -0.5 * s, 0.5 * s))
    chain.dyad(2, driver, kinds[1], line)
    points = [A, driver, *chain.joints]
    springs, dampers = [], []
    for i in range(int(rng.integers(1, 3))):
        anchor = (P.draw(f"x_S{i}", "m", -2 * s, 2 * s), P.draw(f"y_S{i}", "m", -2 * s, 2 * s))
        length = distance(points[rng.integers(len(points))], anchor)
        springs.append(Spring(P.draw(f"k_{i}", "N/m", 10, 2000), P.draw(f"l0_{i}", "m", 0, s),
                              length))
        if rng.random() < 0.5:
            dampers.append(Damper(P.draw(f"c_{i}", "N s/m", 0.1, 50), length))
    forces = (PointForce(points[rng.integers(len(points))],
                         (P.draw("F_x", "N", -20, 20), P.draw("F_y", "N", -20, 20))),)
    crank = _bar("crank", P.draw("m_c", "kg", 0.1, 2.0), (0, 0), A, a, t)
    gravity = P.draw("g", "m/s^2", 0, 10)
    return Mechanism(
        name=f"random_chain_{seed}",
        parameters=tuple(P.list),
        coordinates=(theta, *chain.coordinates),
        independent="theta",
        constraints=tuple(chain.constraints),
        bodies=(crank, *chain.bodies),
        springs=tuple(springs),
        dampers=tuple(dampers),
        forces=forces,
        torques=(),
        gravity=gravity,
        points={},
        assembly_modes=tuple(chain.modes),
        polar_pairs=tuple(chain.polar),
        requirements=(Requirement(sp.And(*(x > 0 for x in chain.lengths)), "LENGTH_NOT_POSITIVE",
                                  "link lengths must be positive"),),
        title=f"random chain {'-'.join(kinds)} {seed}",
    )
