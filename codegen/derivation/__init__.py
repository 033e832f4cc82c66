"""Layer 2: every expression of the method, derived from a mechanism (Table 1)."""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from sympy.core import random as sympy_random

from ..model import Mechanism
from .dynamics import Dynamics, derive_dynamics
from .equilibrium import Equilibrium, derive_equilibrium
from .kinematics import Kinematics, derive_kinematics
from .linearisation import Linearisation, derive_linearisation
from .reduction import Reduction, derive_reduction
from .state import StateSymbols


@dataclass(frozen=True)
class Derivation:
    """The results of each step; expressions in time functions are frozen to symbols."""

    mechanism: Mechanism
    state: StateSymbols
    freezer: dict
    kinematics: Kinematics
    dynamics: Dynamics
    reduction: Reduction
    equilibrium: Equilibrium
    linearisation: Linearisation

    def frozen(self, expr):
        return expr.subs(self.freezer)


#: SymPy's multivariate factorisation (Wang's algorithm) draws random evaluation points; an
#: unlucky draw made one derivation take over ten minutes instead of seconds. Seeding SymPy's
#: generator at the start of each derivation makes its time as reproducible as its output.
RANDOM_SEED = 20261123


@lru_cache(maxsize=None)
def derive(mechanism: Mechanism) -> Derivation:
    sympy_random.seed(RANDOM_SEED)
    state = StateSymbols.of(mechanism)
    freezer = state.freezer(mechanism)
    kinematics = derive_kinematics(mechanism)                          # steps 3-6
    dynamics = derive_dynamics(mechanism, kinematics.jacobian, state.multipliers)  # step 7
    reduction = derive_reduction(mechanism, state, kinematics.constraints.subs(freezer),
                                 dynamics, freezer)                    # step 7, reduced
    equilibrium = derive_equilibrium(reduction.static_terms, reduction.theta,   # step 8
                                     reduction.solution.roots, mechanism.symbols)
    linearisation = derive_linearisation(reduction)                    # steps 9-10
    return Derivation(mechanism, state, freezer, kinematics, dynamics, reduction,
                      equilibrium, linearisation)


__all__ = ["Derivation", "derive"]
