"""Table 1 step 8: static equilibrium G(theta) = 0, (42)-(43), and its polynomial (44)-(45).

G holds the square roots of the position analysis. Each root has two signs, and each
choice of signs is a *branch*: G on the branch where every root is positive is the
mechanism as declared; flipping an assembly-mode root gives the other assembly mode (real
equilibria of another assembly); flipping a length gives a negative length (extraneous).
When G is algebraic in cos(theta), sin(theta) after its roots, eliminating the roots
(elimination.py) gives one polynomial in tau = tan(theta/2) whose real roots are the zeros
of G on every branch; evaluating G on each branch tells them apart. When theta also
stands alone in G (a torsion spring), or G is not a polynomial in its roots (a root in a
denominator of another's radicand), no polynomial is derived: ``polynomial`` is None, the
reason is in ``no_polynomial``, and the library analyses by the certified isolation of G.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .elimination import NotPolynomial, Polynomial, eliminate
from .positions import Definition, Root, write_out


@dataclass(frozen=True)
class Branch:
    signs: tuple[int, ...]          # the sign of each root, in the order of ``roots``
    residual: sp.Expr               # G on this branch
    scale: sp.Expr                  # sum of |contributions|: the size G is measured against

    @property
    def label(self) -> str:
        return "".join("+" if s > 0 else "-" for s in self.signs)


@dataclass(frozen=True)
class Equilibrium:
    residual: sp.Expr               # G(theta), (43), roots written out
    roots: tuple[Root, ...]
    branches: tuple[Branch, ...]    # branches[0]: every root positive (the declared mode)
    polynomial: Polynomial | None   # (45) generalised; None when G is transcendental
    radicands: tuple[sp.Expr, ...]  # of every root on the declared branch, roots written out
    radicand_scales: tuple[sp.Expr, ...]  # sum of |terms| of each radicand
    no_polynomial: str = ""         # why ``polynomial`` is None (empty when it is derived)

    def branch(self, signs: tuple[int, ...]) -> Branch:
        return next(b for b in self.branches if b.signs == signs)

    @property
    def sigma(self) -> tuple[sp.Expr, ...]:
        return self.polynomial.explicit() if self.polynomial else ()


def on_branch(expr: sp.Expr, roots: tuple[Root, ...], signs: tuple[int, ...],
              definitions: tuple[Definition, ...] = ()) -> sp.Expr:
    """expr (in root symbols) with root i taken as signs[i] * sqrt(R_i), nested as needed,
    and every definition written out on that branch."""
    return write_out(expr, roots, definitions, signs)


def common_numerator(terms: tuple[sp.Expr, ...]) -> tuple[sp.Expr, tuple[sp.Expr, ...]]:
    """The numerator of sum(terms) over the least common multiple of their denominators
    (factored, so a factor shared by several terms is counted once), and the denominator's
    irreducible factors."""
    parts = [sp.fraction(sp.together(t)) for t in terms]
    needed: dict[sp.Expr, int] = {}
    factored = []
    for _, den in parts:
        _, factors = sp.factor_list(den)
        factored.append(dict(factors))
        for f, e in factors:
            needed[f] = max(needed.get(f, 0), e)
    numerator = sp.Add(*(num / c * sp.Mul(*(f ** (e - have.get(f, 0))
                                            for f, e in needed.items()))
                         for (num, den), have in zip(parts, factored)
                         for c in [sp.factor_list(den)[0]]))
    return numerator, tuple(needed)


def is_algebraic(expr: sp.Expr, theta: sp.Symbol) -> bool:
    """Whether theta enters only through cos(theta) and sin(theta)."""
    trig = {a for a in expr.atoms(sp.cos, sp.sin) if a.args[0] == theta}
    return not expr.xreplace({a: sp.Dummy() for a in trig}).has(theta) and all(
        a.args[0] == theta for a in expr.atoms(sp.cos, sp.sin) if a.has(theta))


def derive_equilibrium(terms: tuple[sp.Expr, ...], theta: sp.Symbol, roots: tuple[Root, ...],
                       parameters: tuple[sp.Symbol, ...],
                       definitions: tuple[Definition, ...] = ()) -> Equilibrium:
    """``terms``: G's contributions in the root symbols (and a chain's definitions)."""
    residual = sum(terms, sp.S.Zero)
    branches = []
    for j in range(2 ** len(roots)):  # branch j: root i negative where bit i of j is set
        signs = tuple(-1 if j >> i & 1 else 1 for i in range(len(roots)))
        # (Abs simplifies its argument by expanding it: minutes on a chain's written-out
        # terms, which are left as they are)
        branches.append(Branch(signs, on_branch(residual, roots, signs, definitions),
                               sum((sp.Abs(on_branch(t, roots, signs, definitions),
                                           evaluate=not definitions)
                                    for t in terms), sp.S.Zero)))
    declared = (1,) * len(roots)
    polynomial, no_polynomial = None, f"{theta} enters G other than through its sine and cosine"
    if definitions:
        no_polynomial = ("a chain of dyads: the elimination of its nested assembly roots is "
                         "not derived")
    elif is_algebraic(residual.subs({r.symbol: 1 for r in roots}), theta) and all(
            is_algebraic(r.radicand, theta) for r in roots):
        numerator, denominators = common_numerator(terms)
        root_symbols = {r.symbol for r in roots}
        # G is undefined where a denominator vanishes: its factors hold no equilibrium.
        spurious = tuple(f for f in denominators
                         if f.has(theta) and not f.free_symbols & root_symbols)
        try:
            polynomial, no_polynomial = eliminate(numerator, theta, roots, parameters,
                                                  spurious), ""
        except NotPolynomial as refusal:
            no_polynomial = str(refusal)
    radicands, radicand_scales = radicands_on(roots, declared, definitions)
    return Equilibrium(
        residual=on_branch(residual, roots, declared, definitions),
        roots=roots, branches=tuple(branches), polynomial=polynomial,
        radicands=radicands, radicand_scales=radicand_scales, no_polynomial=no_polynomial,
    )


def radicands_on(roots: tuple[Root, ...], signs: tuple[int, ...],
                 definitions: tuple[Definition, ...] = ()
                 ) -> tuple[tuple[sp.Expr, ...], tuple[sp.Expr, ...]]:
    """Every root's radicand on one branch (a chain's later radicands depend on the signs
    of the roots before them), and the sizes of their terms."""
    return (tuple(on_branch(r.radicand, roots, signs, definitions) for r in roots),
            tuple(on_branch(_radicand_scale(r, expand=not definitions), roots, signs,
                            definitions) for r in roots))


def _radicand_scale(root: Root, expand: bool) -> sp.Expr:
    """The size a radicand's rounding is measured against: the magnitudes of its expanded
    terms; a chain's radicands are too large to expand (minutes): P^2 + Q^2 + W^2 of an
    assembly root's P^2 + Q^2 - W^2, a length's terms as they stand."""
    if expand:
        return _magnitude(root.radicand)
    return root.scale if root.scale is not None else terms_size(root.radicand)


def terms_size(expr: sp.Expr, on=lambda term: term) -> sp.Expr:
    """Sum of |term| over expr's terms as written, each taken ``on`` a branch first (not
    expanded, nor simplified by Abs: a chain's expressions are large)."""
    return sp.Add(*(sp.Abs(on(t), evaluate=False) for t in sp.Add.make_args(expr)))


def _magnitude(expr: sp.Expr) -> sp.Expr:
    """Sum of |term| over the expanded terms: the size rounding is relative to."""
    return sum((sp.Abs(t) for t in sp.Add.make_args(sp.expand(expr))), sp.S.Zero)
