"""A planar mechanism, with one coordinate or several, written as data.

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


def parameter(name: str, unit: str, description: str, value: str) -> Parameter:
    """A real parameter symbol with its unit, meaning and example value."""
    return Parameter(sp.Symbol(name, real=True), unit, description, value)


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
class Torque:
    """A constant torque acting on an angle expression of the coordinates (CCW positive)."""

    torque: sp.Expr
    angle: sp.Expr


@dataclass(frozen=True)
class Sketch:
    """How ``mechvib draw`` draws the mechanism; the derivation never reads it.

    ``points``: named points besides the mechanism's ``points`` (fixed points, attachments),
    as expressions of the parameters and coordinates; ``links``: bars and bodies, each a
    polyline through named points; ``sliders``: (point, guide direction [rad]) for a block
    sliding on a guide; ``fixed``: points fixed to the ground; ``springs``: (point, point)
    for a spring (with its damper, if any) between two points; ``angle``: (vertex point,
    direction the angle is measured from [rad], direction of the moving line [rad]), to
    mark the independent coordinate."""

    points: dict[str, tuple[sp.Expr, sp.Expr]] = field(default_factory=dict)
    links: tuple[tuple[str, ...], ...] = ()
    sliders: tuple[tuple[str, sp.Expr], ...] = ()
    fixed: tuple[str, ...] = ()
    springs: tuple[tuple[str, str], ...] = ()
    angle: tuple[str, sp.Expr, sp.Expr] | None = None


def distance(p: tuple[sp.Expr, sp.Expr], q: tuple[sp.Expr, sp.Expr]) -> sp.Expr:
    """|p - q|: a *length* root (only its positive sign is physical).

    Where the two points share an axis (a spring along a slide), SymPy would write the root
    of the one square left as |u|, whose derivative sign(u) differentiates to DiracDelta(u);
    the square is expanded instead, so that the length stays a root like any other."""
    differences = [a - b for a, b in zip(p, q)]
    radicand = sum(d**2 for d in differences)
    if sum(d != 0 for d in differences) == 1:
        radicand = sp.expand(radicand)
    return sp.sqrt(radicand)


@dataclass(frozen=True)
class Requirement:
    """A condition valid parameters satisfy; ``code`` names the failure (a C enum suffix)."""

    condition: sp.Basic  # a relational (or And/Or of them) in the parameter symbols
    code: str
    message: str


@dataclass(frozen=True, eq=False)  # identity hash: derivations are cached per mechanism
class Mechanism:
    """Everything the method needs to know about one mechanism.

    The square roots of the closed-form position analysis are of two kinds, and the model
    says which is which:
    - ``polar_pairs`` names (length, angle) coordinate pairs that enter the constraints only
      as ``length*cos(angle)`` and ``length*sin(angle)``: the length is a *length* root
      (only its positive sign is physical), as is every ``distance`` in a spring or damper;
    - ``assembly_modes`` are expressions of the coordinates, each positive in the assembly
      mode the model describes: an angle of known length fixed by a quadratic (a dyad's
      circle meeting a line or another circle) takes the sign that makes them hold; the
      other sign is the mechanism's other assembly mode.
    The independent coordinate ranges over (range_centre - pi, range_centre + pi]; when
    ``periodic`` (an angle of a closed mechanism), theta and theta + 2 pi are the same state,
    otherwise (a spring that winds) different ones, and equilibria outside the range are not
    sought. A mechanism with n degrees of freedom names its n independent coordinates in a
    tuple, and gives a range centre and a periodicity for each (tuples of n): its range is
    their box. No inertia is required: statics need none, and an equilibrium where M vanishes
    is reported with its frequency undefined.
    ``equations`` maps each named result to the paper's equation label, for comments.
    """

    name: str
    parameters: tuple[Parameter, ...]
    coordinates: tuple[Coordinate, ...]
    independent: str | tuple[str, ...]
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
    assembly_modes: tuple[sp.Expr, ...] = ()
    torques: tuple[Torque, ...] = ()
    range_centre: sp.Expr | tuple[sp.Expr, ...] = sp.S.Zero
    periodic: bool | tuple[bool, ...] = True
    title: str = ""
    equations: dict[str, str] = field(default_factory=dict)
    sketch: Sketch | None = None  # how `mechvib draw` draws it (None: its points and bodies)

    @property
    def independents(self) -> tuple[str, ...]:
        """The independent coordinates' names (one for a 1-DOF mechanism)."""
        return (self.independent,) if isinstance(self.independent, str) else self.independent

    @property
    def dof(self) -> int:
        return len(self.independents)

    @property
    def centres(self) -> tuple[sp.Expr, ...]:
        """Each independent coordinate's range centre."""
        return self.range_centre if isinstance(self.range_centre, tuple) else (
            self.range_centre,) * self.dof

    @property
    def periodics(self) -> tuple[bool, ...]:
        """Whether each independent coordinate is periodic."""
        return self.periodic if isinstance(self.periodic, tuple) else (self.periodic,) * self.dof

    def coordinate(self, name: str) -> sp.Expr:
        return next(c.function for c in self.coordinates if c.name == name)

    @property
    def q(self) -> sp.Matrix:
        return sp.Matrix([c.function for c in self.coordinates])

    @property
    def symbols(self) -> tuple[sp.Symbol, ...]:
        return tuple(p.symbol for p in self.parameters)

    def freezer(self) -> dict:
        """Coordinate functions q_i(t) -> plain symbols named after them."""
        return {c.function: sp.Symbol(c.name, real=True) for c in self.coordinates}

    def example(self) -> dict[sp.Symbol, sp.Rational]:
        return {p.symbol: sp.Rational(p.example_value) for p in self.parameters}
