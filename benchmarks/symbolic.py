"""What the benchmark takes from the SymPy derivation of a mechanism, and prints from it.

The comparisons of `make bench` are built from the derivation alone (``derive()``), the
way a SymPy user would build them without this project's code generator: the same
expressions, turned into straight-line programs by ``sympy.cse`` and printed by SymPy's own
printers, to numpy (``lambdify``), to mpmath (the 40-digit reference) and to C (``ccode``,
the "naive" C).
"""
from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from graphlib import TopologicalSorter

import numpy as np
import sympy as sp

from codegen.compiler.derivation import derive
from codegen.compiler.emission.plan import build_plan
from codegen.compiler.verification import Report, verify
from codegen.compiler.model import load as load_model

#: One assignment of a straight-line program: symbol = expression.
Assignment = tuple[sp.Symbol, sp.Expr]


@dataclass(frozen=True)
class Symbolic:
    """The expressions the benchmark needs of one mechanism, from its derivation."""

    parameters: tuple[sp.Symbol, ...]   # in the order of the library's C struct
    theta: sp.Symbol
    theta_d: sp.Symbol
    theta_dd: sp.Symbol                 # the name of thetaddot's output in the library
    thetaddot: sp.Expr                  # solved from the reduced equation (36)
    #: sigma_0..sigma_n as a program (definitions, coefficients); None when G is transcendental
    sigma: tuple[tuple[Assignment, ...], tuple[sp.Expr, ...]] | None
    residual: sp.Expr                   # G on the declared branch
    scale: sp.Expr                      # the size G is measured against
    mass: sp.Expr                       # M, B, K of the declared mode
    damping: sp.Expr
    stiffness: sp.Expr
    derive_seconds: float               # derive() in this process, cold
    verification: Report                # generate's check of the plan against the model


def symbolic(name: str, parameter_names: Sequence[str]) -> Symbolic:
    """Derive the shipped mechanism ``name``; its parameters ordered as ``parameter_names``."""
    mechanism = load_model(name)
    start = time.perf_counter()
    derivation = derive(mechanism)
    seconds = time.perf_counter() - start
    verification = verify(mechanism, build_plan(derivation))
    by_name = {str(s): s for s in mechanism.symbols}
    if set(by_name) != set(parameter_names):
        raise RuntimeError(f"{name}: the derivation's parameters {sorted(by_name)} are not "
                           f"the library's {sorted(parameter_names)}")
    reduction, equilibrium = derivation.reduction, derivation.equilibrium
    polynomial, linearisation = equilibrium.polynomial, derivation.linearisation
    return Symbolic(
        parameters=tuple(by_name[n] for n in parameter_names),
        theta=reduction.theta, theta_d=reduction.theta_d, theta_dd=reduction.theta_dd,
        thetaddot=reduction.angular_acceleration,
        sigma=(tuple(polynomial.definitions), tuple(polynomial.coefficients))
        if polynomial is not None else None,
        residual=equilibrium.residual, scale=equilibrium.branches[0].scale,
        mass=linearisation.mass, damping=linearisation.damping,
        stiffness=linearisation.stiffness, derive_seconds=seconds, verification=verification)


@lru_cache(maxsize=None)
def straight_line(outputs: tuple[sp.Expr, ...], definitions: tuple[Assignment, ...] = ()
                  ) -> tuple[list[Assignment], list[sp.Expr]]:
    """``outputs`` as a straight-line program: ``sympy.cse`` over the definitions' right-hand
    sides and the outputs together, the definitions kept as assignments of their own, all in
    dependency order (a common subexpression may use a definition, and a definition a
    common subexpression). Returns (assignments, the outputs in their terms); cached, as
    the numpy and the C printers of a mechanism share it."""
    # cse of the explicit sigma expressions took minutes for the four-bar (its shared graph
    # expands to ~30,000 operations); over the derivation's own program it takes seconds.
    rhs = [e for _, e in definitions]
    replacements, reduced = sp.cse(rhs + list(outputs), symbols=sp.numbered_symbols("cse_"))
    assignments = dict(replacements)
    assignments.update((s, e) for (s, _), e in zip(definitions, reduced[:len(rhs)]))
    order = TopologicalSorter({s: [f for f in e.free_symbols if f in assignments]
                               for s, e in assignments.items()}).static_order()
    return [(s, assignments[s]) for s in order], reduced[len(rhs):]


def numpy_function(arguments: Sequence[sp.Symbol], outputs: Sequence[sp.Expr],
                   definitions: Sequence[Assignment] = ()) -> Callable[..., list[np.ndarray]]:
    """``lambdify`` to numpy of the outputs' straight-line program; the function returns
    one array per output, broadcast to the arguments' shape (a constant output too)."""
    program, reduced = straight_line(tuple(outputs), tuple(definitions))
    function = sp.lambdify(arguments, reduced, modules="numpy",
                           cse=lambda exprs: (program, exprs))

    def evaluate(*values: np.ndarray) -> list[np.ndarray]:
        # a square root of a negative radicand is NaN: the mechanism does not assemble there
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            return np.broadcast_arrays(*function(*values), *values)[:len(reduced)]

    return evaluate


def scalar_function(arguments: Sequence[sp.Symbol], output: sp.Expr, modules: str = "mpmath"
                    ) -> Callable[..., object]:
    """``lambdify`` of one expression's straight-line program for scalar arguments: to mpmath
    (evaluated at whatever mp.dps is current at the call), or to Python's math module (the
    fastest a float-by-float caller such as scipy's solve_ivp can have)."""
    program, (reduced,) = straight_line((output,))
    return sp.lambdify(arguments, reduced, modules=modules, cse=lambda exprs: (program, exprs))


def naive_c(prefix: str, symbols: Symbolic) -> str:
    """naive.c: SymPy's ccode of the same thetaddot (and sigma) as the library, after cse,
    as the plain double functions bench.c declares."""
    fields = {s: sp.Symbol(f"p->{s}") for s in symbols.parameters}
    parts = [f"/* naive.c for {prefix}, written by benchmarks/run.py: sympy.ccode after "
             "sympy.cse */", "#include <math.h>", f'#include "{prefix}.h"', ""]
    program, (value,) = straight_line((symbols.thetaddot,))
    parts.append(_c_function(
        f"double naive_thetaddot(const {prefix}_params *p, double {symbols.theta}, "
        f"double {symbols.theta_d})", program, ["return {};"], [value], fields))
    if symbols.sigma is not None:
        definitions, coefficients = symbols.sigma
        program, values = straight_line(coefficients, definitions)
        parts.append(_c_function(f"void naive_sigma(const {prefix}_params *p, double *sigma)",
                                 program, [f"sigma[{i}] = {{}};" for i in range(len(values))],
                                 values, fields))
    return "\n".join(parts)


def _c_function(signature: str, program: Sequence[Assignment], statements: Sequence[str],
                values: Sequence[sp.Expr], fields: dict[sp.Symbol, sp.Symbol]) -> str:
    """A C function: each assignment a const double, then each statement with its value."""
    def code(expr: sp.Expr) -> str:
        return sp.ccode(sp.sympify(expr).xreplace(fields), standard="c99")

    body = [f"    const double {s} = {code(e)};" for s, e in program]
    body += [f"    {statement.format(code(v))}" for statement, v in zip(statements, values)]
    return signature + "\n{\n" + "\n".join(body) + "\n}\n"
