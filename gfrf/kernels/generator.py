"""The symbolic GFRF recursion of one model: plans, explicit and recursive forms.

:class:`GFRFGenerator` builds, once per model, order and kind, the polynomial P_n of the
recursion step H_n = -P_n / A(combined variables) (see :mod:`gfrf.kernels.recursion` for the
algorithm) in the variables and in placeholders for the lower-order kernels on each
block, and evaluates the kernel numerically (:mod:`gfrf.kernels.numeric`) or through a
compiled kernel (:mod:`gfrf.kernels.compiled`).  :func:`generator` memoises one per model.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from gfrf.kernels.combinatorics import compositions, ordered_set_partitions
from gfrf.kernels.numeric import evaluate, step_function
from gfrf.model.equation import Model, Term
from gfrf.model.scaling import normalized

__all__ = ["GFRFGenerator", "generator"]


@dataclass(frozen=True)
class _Plan:
    """Symbolic recursion step of one order: H_n = -numerator / A(combined variables)."""

    order: int
    numerator: sp.Expr
    blocks: tuple[tuple[int, ...], ...]
    placeholders: tuple[sp.Symbol, ...]

    @property
    def is_zero(self) -> bool:
        return self.numerator == 0


class GFRFGenerator:
    """Memoised GFRF recursion for one model.

    Use :func:`generator` (cached per model) rather than constructing it directly.

    Parameters
    ----------
    model : Model
        The polynomial model.
    """

    def __init__(self, model: Model) -> None:
        self.model = model
        self._plans: dict[tuple[int, bool], _Plan] = {}
        self._explicit: dict[tuple[int, bool], sp.Expr] = {}
        self._steps: dict[tuple[int, bool], Any] = {}
        self._possible: dict[int, bool] = {}
        self._ufuncs: dict[tuple[int, bool], Any] = {}
        linear = model.linear_output
        self._denominator = np.array([linear.get(k, 0.0) for k in range(max(linear), -1, -1)])
        self._coefficients = {t: _exact(t.coefficient) for t in model.terms}

    # -- variables -----------------------------------------------------------------
    def variables(self, n: int) -> tuple[sp.Symbol, ...]:
        """Symbols s1..sn (s_i = j*omega_i) or, discrete, q1..qn (q_i = exp(-j*omega_i*T)).

        Parameters
        ----------
        n : int
            The order of the kernel (the number of variables), >= 1.

        Returns
        -------
        tuple of sympy.Symbol
        """
        prefix = "q" if self.model.is_discrete else "s"
        return tuple(sp.Symbol(f"{prefix}{i + 1}") for i in range(n))

    def _operator(self, block_vars: list[sp.Symbol], order: int) -> sp.Expr:
        """D^order applied to the block's exponential: (sum s)^l, or (prod q)^l."""
        if self.model.is_discrete:
            return sp.Mul(*block_vars) ** order
        return sp.Add(*block_vars) ** order

    def linear_part(self, var: sp.Expr) -> sp.Expr:
        """A(var) = sum a_l var^l, the linear output polynomial.

        Parameters
        ----------
        var : sympy.Expr
            Where A is taken (s, or for a discrete model q: a lag l is q^l).

        Returns
        -------
        sympy.Expr
        """
        return sp.Add(*(self._coefficients[t] * var ** t.y_orders[0]
                        for t in self.model.terms if t.is_linear_output))

    def combined(self, variables: tuple[sp.Symbol, ...]) -> sp.Expr:
        """The variable of the sum of the frequencies: s1+..+sn, or q1*..*qn.

        Parameters
        ----------
        variables : tuple of sympy.Symbol
            The variables of a block (:meth:`variables`).

        Returns
        -------
        sympy.Expr
        """
        return sp.Mul(*variables) if self.model.is_discrete else sp.Add(*variables)

    # -- structure -----------------------------------------------------------------
    def structurally_nonzero(self, n: int) -> bool:
        """Whether some chain of terms can produce order n (False means H_n == 0 exactly).

        An order is reachable if a term with p output and q input factors has
        n = q + (sum of p reachable orders).  Even orders of an odd nonlinearity are
        unreachable, so they are known to vanish without any computation.

        Parameters
        ----------
        n : int
            The order of the kernel (the number of variables), >= 1.

        Returns
        -------
        bool
        """
        cache = self._possible
        for m in range(1, n + 1):
            if m in cache:
                continue
            reachable = False
            for t in self.model.terms:
                if t.is_linear_output:
                    continue
                p, q = len(t.y_orders), len(t.u_orders)
                rest = m - q
                if p == 0:
                    reachable = rest == 0
                elif rest >= p:
                    reachable = _sum_of_reachable(rest, p, cache)
                if reachable:
                    break
            cache[m] = reachable
        return cache[n]

    def plan(self, n: int, symmetric: bool) -> _Plan:
        """The symbolic recursion step of order ``n`` (memoised).

        Parameters
        ----------
        n : int
            The order of the kernel (the number of variables), >= 1.
        symmetric : bool
            The symmetric kernel instead of the asymmetric one.

        Returns
        -------
        _Plan
            ``numerator`` (P_n), the lower-order ``blocks`` it uses and their
            ``placeholders``; ``is_zero`` when P_n vanishes.
        """
        key = (n, symmetric)
        if key not in self._plans:
            self._plans[key] = self._build_plan(n, symmetric)
        return self._plans[key]

    def _build_plan(self, n: int, symmetric: bool) -> _Plan:
        xs = self.variables(n)
        placeholders: dict[tuple[int, ...], sp.Symbol] = {}

        def h(block: tuple[int, ...]) -> sp.Symbol:
            if block not in placeholders:
                placeholders[block] = sp.Symbol("h_" + "_".join(str(i) for i in block))
            return placeholders[block]

        numerator = []
        if self.structurally_nonzero(n):
            for term in self.model.terms:
                if term.is_linear_output:
                    continue
                for weight, y_blocks, u_slots in self._assignments(term, n, symmetric):
                    factors = [self._coefficients[term] * weight]
                    for block, order in zip(y_blocks, term.y_orders, strict=True):
                        factors.append(h(block))
                        factors.append(self._operator([xs[i] for i in block], order))
                    for slot, order in zip(u_slots, term.u_orders, strict=True):
                        factors.append(self._operator([xs[slot]], order))
                    numerator.append(sp.Mul(*factors))
        expr = sp.Add(*numerator)
        present = expr.free_symbols  # one traversal (expr.has per placeholder: quadratic)
        used = sorted((b for b, sym in placeholders.items() if sym in present),
                      key=lambda b: (len(b), b))
        return _Plan(n, expr, tuple(used), tuple(placeholders[b] for b in used))

    def _assignments(self, term: Term, n: int, symmetric: bool
                     ) -> Iterator[tuple[sp.Rational, list[tuple[int, ...]], tuple[int, ...]]]:
        """Ways of distributing n frequencies over the term's factors, with weights."""
        p, q = len(term.y_orders), len(term.u_orders)
        if q > n or (p == 0 and q != n) or (p > 0 and n - q < p):
            return
        if not symmetric:
            u_slots = tuple(range(n - q, n))
            for sizes in compositions(n - q, p):
                if not all(self.structurally_nonzero(m) for m in sizes):
                    continue
                starts = np.cumsum((0, *sizes))
                blocks = [tuple(range(starts[i], starts[i + 1])) for i in range(p)]
                yield sp.Integer(1), blocks, u_slots
            return
        # Interchangeable factors (equal derivative orders) give equal products: keep one
        # canonical order of their blocks (increasing smallest element) and count it
        # multiplicity times, which divides the symbolic work by prod(m!).
        multiplicity = math.prod(math.factorial(term.y_orders.count(o))
                                 for o in set(term.y_orders))
        multiplicity *= math.prod(math.factorial(term.u_orders.count(o))
                                  for o in set(term.u_orders))
        everything = tuple(range(n))
        for u_slots in itertools.permutations(everything, q):
            if not _canonical(term.u_orders, [(slot,) for slot in u_slots]):
                continue
            rest = tuple(i for i in everything if i not in u_slots)
            for blocks in ordered_set_partitions(rest, p):
                if not _canonical(term.y_orders, blocks):
                    continue
                if not all(self.structurally_nonzero(len(b)) for b in blocks):
                    continue
                weight = sp.Rational(multiplicity * math.prod(math.factorial(len(b))
                                                              for b in blocks),
                                     math.factorial(n))
                yield weight, blocks, u_slots

    # -- symbolic form -------------------------------------------------------------
    def explicit(self, n: int, symmetric: bool) -> sp.Expr:
        """H_n as an explicit sympy expression in the variables (lower orders inlined).

        Parameters
        ----------
        n : int
            The order of the kernel (the number of variables), >= 1.
        symmetric : bool
            The symmetric kernel instead of the asymmetric one.

        Returns
        -------
        sympy.Expr
            The rational function of :meth:`variables` ``(n)`` (memoised).
        """
        key = (n, symmetric)
        if key not in self._explicit:
            plan = self.plan(n, symmetric)
            xs = self.variables(n)
            if plan.is_zero:
                self._explicit[key] = sp.Integer(0)
            else:
                mapping = {}
                for block, sym in zip(plan.blocks, plan.placeholders, strict=True):
                    lower = self.explicit(len(block), symmetric)
                    inner = self.variables(len(block))
                    mapping[sym] = lower.xreplace({inner[i]: xs[b] for i, b in enumerate(block)})
                numerator = plan.numerator.xreplace(mapping)
                self._explicit[key] = -numerator / self.linear_part(self.combined(xs))
        return self._explicit[key]

    def recursive(self, n: int, symmetric: bool) -> sp.Expr:
        """H_n in recursive form: lower kernels appear as functions ``H_m(...)``.

        Parameters
        ----------
        n : int
            The order of the kernel (the number of variables), >= 1.
        symmetric : bool
            The symmetric kernel instead of the asymmetric one.

        Returns
        -------
        sympy.Expr
        """
        plan = self.plan(n, symmetric)
        if plan.is_zero:
            return sp.Integer(0)
        xs = self.variables(n)
        mapping = {sym: sp.Function(f"H{len(block)}")(*(xs[i] for i in block))
                   for block, sym in zip(plan.blocks, plan.placeholders, strict=True)}
        return -plan.numerator.xreplace(mapping) / self.linear_part(self.combined(xs))

    # -- numeric form --------------------------------------------------------------
    def step(self, m: int, symmetric: bool) -> Any:
        """The numerator of the recursion step of order ``m`` as a numpy function
        (:func:`gfrf.kernels.numeric.step_function`, made once).

        Parameters
        ----------
        m : int
            The order of the step, >= 1.
        symmetric : bool
            The symmetric kernel's step instead of the asymmetric one's.

        Returns
        -------
        callable
            ``f(variables..., placeholders...)`` on arrays.
        """
        key = (m, symmetric)
        if key not in self._steps:
            self._steps[key] = step_function(self, m, symmetric)
        return self._steps[key]

    def evaluate(self, n: int, omegas: list[np.ndarray], symmetric: bool) -> np.ndarray:
        """Numeric H_n at broadcastable arrays of angular frequencies (rad/s).

        Parameters
        ----------
        n : int
            The order of the kernel, >= 1.
        omegas : list of numpy.ndarray
            n arrays of angular frequencies (real, or complex for values at complex s)
            that broadcast together.
        symmetric : bool
            The symmetric kernel instead of the asymmetric one.

        Returns
        -------
        numpy.ndarray of complex128
            H_n at s_i = j*omega_i (discrete: q_i = exp(-j*omega_i*T)) with the broadcast
            shape; inf or nan at a pole.
        """
        if not self.structurally_nonzero(n):
            shape = np.broadcast_shapes(*(np.shape(w) for w in omegas))
            return np.zeros(shape, dtype=np.complex128)
        return evaluate(self, lambda m: self.step(m, symmetric), self._denominator, n,
                        omegas, symmetric)

    def ufunc(self, n: int, symmetric: bool) -> Any:
        """The compiled ufunc of H_n (compiled once, see :mod:`gfrf.kernels.compiled`).

        Parameters
        ----------
        n : int
            The order of the kernel, >= 1.
        symmetric : bool
            The symmetric kernel instead of the asymmetric one.

        Returns
        -------
        callable
            ``f(w1, ..., wn) -> complex128`` over float64 angular frequencies in rad/s.
        """
        key = (n, symmetric)
        if key not in self._ufuncs:
            from gfrf.kernels.compiled import numba_ufunc

            self._ufuncs[key] = numba_ufunc(self, n, symmetric)
        return self._ufuncs[key]


def _exact(value: float) -> sp.Rational:
    """The simplest rational that rounds to ``value`` (49/120 for 0.408333...), else its decimal."""
    simple = Fraction(value).limit_denominator(10**6)
    if float(simple) == value:
        return sp.Rational(simple.numerator, simple.denominator)
    return sp.Rational(repr(value))


def _canonical(orders: tuple[int, ...], blocks: list[tuple[int, ...]]) -> bool:
    """True if blocks of consecutive equal-order factors have increasing smallest elements."""
    return all(orders[i] != orders[i + 1] or blocks[i][0] < blocks[i + 1][0]
               for i in range(len(orders) - 1))


def _sum_of_reachable(total: int, parts: int, reachable: dict[int, bool]) -> bool:
    if parts == 1:
        return reachable.get(total, False)
    return any(reachable.get(first, False) and _sum_of_reachable(total - first, parts - 1,
                                                                   reachable)
               for first in range(1, total - parts + 2))


@lru_cache(maxsize=64)
def generator(model: Model) -> GFRFGenerator:
    """The memoised GFRF generator of ``model`` (equal models share one).

    It works on :func:`gfrf.model.scaling.normalized` ``(model)`` (every coefficient divided
    by a power of two near A's leading coefficient): the same kernels, exactly, with
    no overflow or underflow when the whole equation is scaled by 1e-200 or 1e200.
    """
    return GFRFGenerator(normalized(model))
