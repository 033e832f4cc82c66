"""A planar one-degree-of-freedom mechanism, written as data.

Nothing here is derived: a mechanism lists its parameters, generalised coordinates,
position constraints, bodies, springs, dampers and applied forces. The derivation
package turns that description into every expression of the method.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

#: The independent variable of the motion.
TIME = sp.Symbol("t", real=True)


@dataclass(frozen=True)
class Parameter:
    """A constant of the mechanism, with its unit and its value in the worked example."""

    symbol: sp.Symbol
    unit: str
    description: str
    example_value: str  # exact decimal string, so the example is data, not a float


@dataclass(frozen=True)
class Coordinate:
    """A generalised coordinate q_i(t)."""

    name: str
    unit: str
    description: str

    @property
    def function(self) -> sp.Expr:
        return sp.Function(self.name, real=True)(TIME)


@dataclass(frozen=True)
class Body:
    """A rigid body: its mass at a centre of mass, and optionally a rotational inertia
    about that centre with the coordinate that gives its orientation."""

    name: str
    mass: sp.Expr
    centre: tuple[sp.Expr, sp.Expr]  # position of the centre of mass, in coordinates
    inertia: sp.Expr = sp.S.Zero
    angle: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class Spring:
    """A linear spring whose current length is an expression of the coordinates."""

    stiffness: sp.Expr
    free_length: sp.Expr
    length: sp.Expr


@dataclass(frozen=True)
class Damper:
    """A linear viscous damper acting along a length expression of the coordinates."""

    coefficient: sp.Expr
    length: sp.Expr


@dataclass(frozen=True)
class PointForce:
    """A force applied at a point (given in coordinates), with constant components."""

    point: tuple[sp.Expr, sp.Expr]
    force: tuple[sp.Expr, sp.Expr]


@dataclass(frozen=True)
class Requirement:
    """A condition valid parameters satisfy; ``code`` names the failure (a C enum suffix)."""

    condition: sp.Basic  # a relational (or And/Or of them) in the parameter symbols
    code: str
    message: str


@dataclass(frozen=True, eq=False)  # identity hash: derivations are cached per mechanism
class Mechanism:
    """Everything the method needs to know about one mechanism.

    ``polar_pairs`` names (length, angle) coordinate pairs that enter the constraints only
    as ``length*cos(angle)`` and ``length*sin(angle)``; with them the position constraints
    are linear in the dependent coordinates, so they are solved exactly in closed form.
    ``static_split`` gives the factor by which the paper divides the elastic and the load
    parts of the static generalised force (for Doughty: sin(theta) and cos(theta)).
    ``equations`` maps each named result to the paper's equation label, for comments.
    """

    name: str
    parameters: tuple[Parameter, ...]
    coordinates: tuple[Coordinate, ...]
    independent: str
    constraints: tuple[sp.Expr, ...]
    bodies: tuple[Body, ...]
    springs: tuple[Spring, ...]
    dampers: tuple[Damper, ...]
    forces: tuple[PointForce, ...]
    gravity: sp.Expr
    points: dict[str, tuple[sp.Expr, sp.Expr]]
    requirements: tuple[Requirement, ...] = ()
    singular_state: str = "a denominator of the result vanishes"
    polar_pairs: tuple[tuple[str, str], ...] = ()
    static_split: dict[str, sp.Expr] = field(default_factory=dict)
    equations: dict[str, str] = field(default_factory=dict)

    def coordinate(self, name: str) -> sp.Expr:
        return next(c.function for c in self.coordinates if c.name == name)

    @property
    def q(self) -> sp.Matrix:
        return sp.Matrix([c.function for c in self.coordinates])

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(p.symbol for p in self.parameters)

    def example(self) -> dict[sp.Symbol, sp.Rational]:
        return {p.symbol: sp.Rational(p.example_value) for p in self.parameters}
