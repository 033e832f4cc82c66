"""Every expression of the method, derived from a mechanism (Table 1)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import sympy as sp
from sympy.core import random as sympy_random

from ..model import Mechanism
from .dynamics import Dynamics, derive_dynamics
from .equilibrium import Equilibrium, derive_equilibrium
from .kinematics import Kinematics, derive_kinematics
from .names import internal
from .positions import branch_program
from .linearisation import Linearisation, derive_linearisation
from .modes import ModeQuantities, on_mode
from .reduction import Reduction, derive_reduction
from .state import StateSymbols


@dataclass(frozen=True)
class Derivation:
    """The results of each step; expressions in time functions are frozen to symbols.

    ``mechanism`` is the one derived: the user's (``user``) with every clashing name
    renamed (names.py); the two list their parameters and coordinates in the same order."""

    mechanism: Mechanism
    state: StateSymbols
    freezer: dict
    kinematics: Kinematics
    dynamics: Dynamics
    reduction: Reduction
    equilibrium: Equilibrium
    linearisation: Linearisation
    user: Mechanism

    def frozen(self, expr):
        return expr.subs(self.freezer)

    def on_mode(self, k: int) -> ModeQuantities:
        """The functions of one angle on sign choice k (linearisation.modes[k])."""
        return on_mode(k, self.reduction, self.equilibrium, self.linearisation)

    @property
    def program(self) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """A chain of dyads' straight-line program on every branch, which its expressions
        are written in (positions.write_out); () for any other mechanism."""
        solution = self.reduction.solution
        if not solution.definitions:
            return ()
        steps = {}   # branches share the steps before the roots they differ in
        for branch in self.equilibrium.branches:
            for symbol, value in branch_program(solution.roots, solution.definitions,
                                                branch.signs):
                steps.setdefault(symbol, value)
        return tuple(steps.items())


#: SymPy's multivariate factorisation (Wang's algorithm) draws random evaluation points; an
#: unlucky draw made one derivation take over ten minutes instead of seconds. Seeding SymPy's
#: generator at the start of each derivation makes its time as reproducible as its output.
RANDOM_SEED = 20261123

#: Each mechanism's derivation, once per process: keyed by the mechanism alone (its identity),
#: whatever progress callback the caller passes.
_DERIVED: dict[Mechanism, Derivation] = {}


def derive(mechanism: Mechanism, progress: Callable[[str], None] | None = None) -> Derivation:
    """Every result of the method for a mechanism; ``progress`` is told each step's name as
    it starts (a long derivation then shows where it is)."""
    if mechanism not in _DERIVED:
        _DERIVED[mechanism] = _derive(mechanism, progress or (lambda step: None))
    return _DERIVED[mechanism]


def _derive(user: Mechanism, progress: Callable[[str], None]) -> Derivation:
    sympy_random.seed(RANDOM_SEED)
    mechanism = internal(user)
    state = StateSymbols.of(mechanism)
    freezer = state.freezer(mechanism)
    progress("positions and velocities")
    kinematics = derive_kinematics(mechanism)                          # steps 3-6
    progress("equations of motion")
    dynamics = derive_dynamics(mechanism, kinematics.jacobian, state.multipliers)  # step 7
    progress("reduced equation of motion")
    reduction = derive_reduction(mechanism, state, kinematics.constraints.subs(freezer),
                                 dynamics, freezer)                    # step 7, reduced
    progress("equilibrium polynomial")
    equilibrium = derive_equilibrium(reduction.static_terms, reduction.theta,   # step 8
                                     reduction.solution.roots, mechanism.symbols,
                                     reduction.solution.definitions)
    progress("linearisation")
    linearisation = derive_linearisation(reduction)                    # steps 9-10
    return Derivation(mechanism, state, freezer, kinematics, dynamics, reduction,
                      equilibrium, linearisation, user)


__all__ = ["Derivation", "derive"]
