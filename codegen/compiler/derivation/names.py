"""The mechanism the derivation works on: the user's, with every name that would clash renamed.

SymPy symbols are equal when their names (and assumptions) are, so a parameter named
``theta_d`` would *be* the rate of the coordinate ``theta`` the derivation introduces, and
the result silently wrong. The generated C reads each symbol into a local of its name, so a
parameter named ``v`` or ``sin`` would hide the code's own ``v`` or libm's ``sin``. Before
anything is derived, each parameter or coordinate whose name clashes with one of those gets
a fresh internal name (the name with trailing underscores added); the emission then reads a
parameter from the struct field of the user's name. A mechanism with no such name (every
shipped one) is derived as it is, so its output does not change.
"""
from __future__ import annotations

import re
from dataclasses import replace

import sympy as sp

from ..model import Coordinate, Mechanism, Parameter
from ..model.names import c_taken

#: Symbols the derivation makes whatever the coordinates are called: time, the Lagrange
#: multipliers, the position analysis' roots, the elimination's named coefficients.
_NUMBERED = re.compile(r"(lambda|rho|w)_\d+\Z")
_FIXED = frozenset({"t", "sign"})


def _made_for(coordinate: str) -> set[str]:
    """The symbols the derivation makes for one coordinate: its rate and acceleration, and
    the unknowns of the position analysis (cos and sin, or Cartesian components)."""
    return {f"{coordinate}_d", f"{coordinate}_dd",
            *(f"{letter}_{coordinate}" for letter in "CSXYUVD"), f"sigma_{coordinate}"}


def _clashes(name: str, made: set[str], argument: bool) -> bool:
    """Whether a parameter's (or, ``argument``, a coordinate's) name is one the derivation
    makes (``made`` for the coordinates) or the generated C must not give its local."""
    return (c_taken(name, argument) or name in _FIXED or name in made
            or bool(_NUMBERED.match(name)))


def _fresh(name: str, used: set[str], made: set[str], argument: bool) -> str:
    while _clashes(name, made, argument) or name in used:
        name += "_"
    return name


def internal_names(mechanism: Mechanism) -> dict[str, str]:
    """User name -> internal name, for every parameter and coordinate that must be renamed."""
    users = {c.name for c in mechanism.coordinates} | {p.symbol.name for p in mechanism.parameters}
    renamed: dict[str, str] = {}
    # the C arguments of a library with several coordinates: arrays theta[], theta_d[]
    arrays = {"theta", "theta_d"} if mechanism.dof > 1 else set()
    others = set(arrays)  # the derivation's names of the coordinates renamed so far
    for c in mechanism.coordinates:  # coordinates first: the parameters avoid their names
        made = set().union(*(_made_for(o.name) for o in mechanism.coordinates if o is not c))
        if _clashes(c.name, made | others, argument=True):
            renamed[c.name] = _fresh(c.name, users | set(renamed.values()), made | others,
                                     argument=True)
        others |= {renamed.get(c.name, c.name)}
    made = set().union(*(_made_for(n) for n in others - arrays)) | arrays
    for p in mechanism.parameters:
        name = p.symbol.name
        if _clashes(name, made, argument=False):
            renamed[name] = _fresh(name, users | set(renamed.values()) | made, made,
                                   argument=False)
    return renamed


def internal(mechanism: Mechanism) -> Mechanism:
    """The mechanism with its clashing names renamed (itself when there are none)."""
    renamed = internal_names(mechanism)
    if not renamed:
        return mechanism
    coordinates = tuple(replace(c, name=renamed.get(c.name, c.name))
                        for c in mechanism.coordinates)
    parameters = tuple(replace(p, symbol=sp.Symbol(renamed.get(p.symbol.name, p.symbol.name),
                                                   **p.symbol.assumptions0))
                       for p in mechanism.parameters)
    subs = {old.symbol: new.symbol for old, new in zip(mechanism.parameters, parameters)}
    subs |= {old.function: new.function for old, new in zip(mechanism.coordinates, coordinates)}

    def new(expr):
        return sp.sympify(expr).xreplace(subs)

    def pair(p):
        return (new(p[0]), new(p[1]))

    def name(n: str) -> str:
        return renamed.get(n, n)

    m = mechanism
    return replace(
        m, parameters=parameters, coordinates=coordinates, independent=(name(m.independent) if isinstance(m.independent, str)
                                                      else tuple(map(name, m.independent))),
        constraints=tuple(new(e) for e in m.constraints),
        bodies=tuple(replace(b, mass=new(b.mass), centre=pair(b.centre), inertia=new(b.inertia),
                             angle=new(b.angle)) for b in m.bodies),
        springs=tuple(replace(s, stiffness=new(s.stiffness), free_length=new(s.free_length),
                              length=new(s.length)) for s in m.springs),
        dampers=tuple(replace(d, coefficient=new(d.coefficient), length=new(d.length))
                      for d in m.dampers),
        forces=tuple(replace(f, point=pair(f.point), force=pair(f.force)) for f in m.forces),
        torques=tuple(replace(t, torque=new(t.torque), angle=new(t.angle)) for t in m.torques),
        gravity=new(m.gravity), points={k: pair(p) for k, p in m.points.items()},
        requirements=tuple(replace(r, condition=new(r.condition)) for r in m.requirements),
        polar_pairs=tuple((name(a), name(b)) for a, b in m.polar_pairs),
        assembly_modes=tuple(new(e) for e in m.assembly_modes),
        range_centre=(tuple(map(new, m.range_centre)) if isinstance(m.range_centre, tuple)
                      else new(m.range_centre)))
