"""GFRFs H1..Hn by the recursive (Billings / Peyton Jones) algorithm.

For a model ``sum(terms) = 0`` with linear output part A(s) = sum a_l s^l, the n-th
order kernel is

    H_n(s_1..s_n) = -P_n(s_1..s_n) / A(s_1 + ... + s_n),

where P_n collects the contributions of every other term: pure-input terms of
degree n, and for each term with p output factors (orders l_1..l_p) and q input
factors (orders k_1..k_q) the H_{n-q,p} products of lower-order kernels,

    H_{m,p}(s_1..s_m) = sum over compositions m = m_1 + ... + m_p of
                        prod_i H_{m_i}(block_i) * (sum of block_i)^{l_i},

times prod_j s_{m+j}^{k_j} for the input factors (the Peyton Jones 1989 recursion
written in closed form).  The *asymmetric* kernel uses contiguous blocks in that
order; the *symmetric* kernel (the average over all permutations of s_1..s_n, unique
for a given system) is computed directly as a sum over ordered set partitions with
weights prod|B_i|!/n!, so no n!-term symmetrisation is ever formed.

A discrete-time model uses the backward shift q_i = exp(-j*omega_i*T) in place of
s_i = j*omega_i; the frequency sum of a block becomes the product of its q_i and a
lag l the power q^l.

Symbolic work (the polynomial P_n in the variables and in placeholders for the
lower-order kernels on each block) happens once per model, order and kind, and is
memoised; numeric evaluation compiles P_n with common-subexpression elimination
and evaluates the lower-order kernels bottom-up on arrays, so no symbolic object
is touched per point.  Angular frequencies are in rad/s.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> duffing = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
>>> H3 = kernel(duffing, 3)
>>> complex(H3(1.0, 1.0, -1.0)) == complex(-0.5 * kernel(duffing, 1)(1.0)**2
...                                         * kernel(duffing, 1)(-1.0) * kernel(duffing, 1)(1.0))
True
>>> kernel(duffing, 2).is_zero
True
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.kernels.combinatorics import compositions, ordered_set_partitions
from gfrf.kernels.compiled import MIN_POINTS, compile_pays
from gfrf.kernels.work import MAX_PLAN_TERMS, MAX_RECURSION_WORK, check_recursion_work
from gfrf.model.equation import Model, Term
from gfrf.model.scaling import normalized

__all__ = ["Kernel", "GFRFGenerator", "generator", "kernel", "check_order", "MAX_KERNEL_ORDER",
           "MAX_RECURSION_WORK", "MAX_PLAN_TERMS", "check_recursion_work"]

#: Largest kernel order the generator accepts (the symbolic sums grow like p! S(n, p)).
MAX_KERNEL_ORDER = 12
#: Terms per lambdified chunk of a recursion numerator (Python's compiler nests sums).
_CHUNK = 500
#: Points per slice of a numeric evaluation: the recursion's temporaries (a few per term)
#: then stay in cache instead of each being a fresh multi-megabyte allocation (4-5x the
#: rate at 10^6 points for the cart-pole's H3 and H5).
_SLICE = 16_384


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
        self._compiled: dict[tuple[int, bool], Any] = {}
        self._possible: dict[int, bool] = {}
        self._ufuncs: dict[tuple[int, bool], Any] = {}
        linear = model.linear_output
        self._denominator = np.array([linear.get(k, 0.0) for k in range(max(linear), -1, -1)])
        self._coefficients = {t: _exact(t.coefficient) for t in model.terms}

    # -- variables -----------------------------------------------------------------
    def variables(self, n: int) -> tuple[sp.Symbol, ...]:
        """Symbols s1..sn (s_i = j*omega_i) or, discrete, q1..qn (q_i = exp(-j*omega_i*T))."""
        prefix = "q" if self.model.is_discrete else "s"
        return tuple(sp.Symbol(f"{prefix}{i + 1}") for i in range(n))

    def _operator(self, block_vars: list[sp.Symbol], order: int) -> sp.Expr:
        """D^order applied to the block's exponential: (sum s)^l, or (prod q)^l."""
        if self.model.is_discrete:
            return sp.Mul(*block_vars) ** order
        return sp.Add(*block_vars) ** order

    def linear_part(self, var: sp.Expr) -> sp.Expr:
        """A(var) = sum a_l var^l, the linear output polynomial."""
        return sp.Add(*(self._coefficients[t] * var ** t.y_orders[0]
                        for t in self.model.terms if t.is_linear_output))

    def combined(self, variables: tuple[sp.Symbol, ...]) -> sp.Expr:
        """The variable of the sum of the frequencies: s1+..+sn, or q1*..*qn."""
        return sp.Mul(*variables) if self.model.is_discrete else sp.Add(*variables)

    # -- structure -----------------------------------------------------------------
    def structurally_nonzero(self, n: int) -> bool:
        """Whether some chain of terms can produce order n (False means H_n == 0 exactly).

        An order is reachable if a term with p output and q input factors has
        n = q + (sum of p reachable orders).  Even orders of an odd nonlinearity are
        unreachable, so they are known to vanish without any computation.
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
        """The symbolic recursion step of order ``n`` (memoised)."""
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
        """H_n as an explicit sympy expression in the variables (lower orders inlined)."""
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
        """H_n in recursive form: lower kernels appear as functions ``H_m(...)``."""
        plan = self.plan(n, symmetric)
        if plan.is_zero:
            return sp.Integer(0)
        xs = self.variables(n)
        mapping = {sym: sp.Function(f"H{len(block)}")(*(xs[i] for i in block))
                   for block, sym in zip(plan.blocks, plan.placeholders, strict=True)}
        return -plan.numerator.xreplace(mapping) / self.linear_part(self.combined(xs))

    # -- numeric form --------------------------------------------------------------
    def _compiled_numerator(self, n: int, symmetric: bool) -> Any:
        key = (n, symmetric)
        if key not in self._compiled:
            plan = self.plan(n, symmetric)
            args = [*self.variables(n), *plan.placeholders]
            # One lambdify of a sum of thousands of terms (order 9) exceeds the Python
            # compiler's recursion limit: compile it in chunks and add the parts.  The
            # numpy module itself as namespace: same printer and code as modules="numpy",
            # without its ``from numpy import *`` (which loads numpy.f2py, numpy.testing,
            # ... : 40-50 ms of start-up).
            terms = sp.Add.make_args(plan.numerator)
            parts = [sp.lambdify(args, sp.Add(*terms[i:i + _CHUNK]), modules=[np],
                                 cse=True) for i in range(0, len(terms), _CHUNK)]
            self._compiled[key] = parts[0] if len(parts) == 1 else (
                lambda *a: sum(part(*a) for part in parts))
        return self._compiled[key]

    def _to_variables(self, omegas: list[np.ndarray]) -> list[np.ndarray]:
        if self.model.is_discrete:
            return [np.exp(-1j * w * self.model.sample_time) for w in omegas]
        return [1j * w for w in omegas]

    def evaluate(self, n: int, omegas: list[np.ndarray], symmetric: bool) -> np.ndarray:
        """Numeric H_n at broadcastable arrays of angular frequencies (rad/s)."""
        shape = np.broadcast_shapes(*(np.shape(w) for w in omegas))
        if not self.structurally_nonzero(n):
            return np.zeros(shape, dtype=np.complex128)
        size = math.prod(shape)
        if size <= _SLICE:
            return self._evaluate(n, omegas, symmetric, shape)
        flat = [np.broadcast_to(w, shape).reshape(-1) for w in omegas]
        out = np.empty(size, dtype=np.complex128)
        for start in range(0, size, _SLICE):
            part = [w[start:start + _SLICE] for w in flat]
            out[start:start + _SLICE] = self._evaluate(n, part, symmetric, part[0].shape)
        return out.reshape(shape)

    def _evaluate(self, n: int, omegas: list[np.ndarray], symmetric: bool,
                  shape: tuple[int, ...]) -> np.ndarray:
        """:meth:`evaluate` on one slice (``shape``: the broadcast shape)."""
        xs = self._to_variables(omegas)
        memo: dict[tuple[int, ...], np.ndarray] = {}

        def value(block: tuple[int, ...]) -> np.ndarray:
            if block not in memo:
                m = len(block)
                plan = self.plan(m, symmetric)
                if plan.is_zero:
                    memo[block] = np.zeros((), dtype=np.complex128)
                else:
                    sub = [xs[i] for i in block]
                    lower = [value(tuple(block[j] for j in b)) for b in plan.blocks]
                    numerator = self._compiled_numerator(m, symmetric)(*sub, *lower)
                    combined = math.prod(sub) if self.model.is_discrete else sum(sub)
                    memo[block] = -numerator / np.polyval(self._denominator, combined)
            return memo[block]

        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            result = value(tuple(range(n)))
        return np.broadcast_to(np.asarray(result, dtype=np.complex128), shape).copy()


    def ufunc(self, n: int, symmetric: bool) -> Any:
        """The numba-compiled ufunc of H_n (compiled once, see :mod:`gfrf.kernels.compiled`)."""
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


@dataclass(frozen=True)
class Kernel:
    """The n-th order GFRF H_n of a model, symmetric (default) or asymmetric.

    Call it with n arrays of **angular frequencies in rad/s** (broadcast like numpy)
    to get complex128 values: ``H(w1, ..., wn)`` is H_n at s_i = j*w_i, not at
    s_i = w_i (python-control's ``sys(x)`` evaluates at s = x; here pass ``w`` for
    s = j*w).  :meth:`at_s` evaluates at complex s_i; ``.expr`` is the explicit
    sympy form in s1..sn or, for a discrete model, q1..qn (q_i = exp(-j*w_i*T)).

    Examples
    --------
    >>> import sympy as sp
    >>> from gfrf.model.equation import parse_model
    >>> H1 = kernel(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), 1)
    >>> complex(H1(1.0))  # at s = 1j rad/s: 1 / (0.2j)
    -5j
    >>> s = -0.5 + 2j
    >>> abs(complex(H1.at_s(s)) - 1 / (s**2 + 0.2*s + 1)) < 1e-15
    True
    >>> f = sp.lambdify(H1.variables, H1.expr)  # the same from the sympy form
    >>> abs(f(s) - complex(H1.at_s(s))) < 1e-15
    True
    """

    model: Model
    order: int
    symmetric: bool = True
    _gen: GFRFGenerator = field(repr=False, compare=False, default=None)  # type: ignore[assignment]

    @property
    def is_zero(self) -> bool:
        """True when H_n vanishes identically (structurally or by cancellation)."""
        if not self._gen.structurally_nonzero(self.order):
            return True
        return self._gen.plan(self.order, self.symmetric).is_zero

    @property
    def variables(self) -> tuple[sp.Symbol, ...]:
        """The symbolic variables s1..sn (or q1..qn)."""
        return self._gen.variables(self.order)

    @property
    def expr(self) -> sp.Expr:
        """Explicit sympy rational function of the variables (lower orders inlined)."""
        return self._gen.explicit(self.order, self.symmetric)

    @property
    def recursive_expr(self) -> sp.Expr:
        """Compact form in which lower-order kernels appear as ``H_m(...)`` functions."""
        return self._gen.recursive(self.order, self.symmetric)

    def __repr__(self) -> str:
        kind = "" if self.symmetric else ", asymmetric"
        return f"Kernel(H{self.order} of {self.model.text or self.model.equation()!r}{kind})"

    def _repr_latex_(self) -> str:
        return f"$H_{{{self.order}}} = {sp.latex(self.recursive_expr)}$"

    def plot(self, **options: Any) -> Any:
        """Figure of the kernel (:func:`gfrf.kernels.plot.plot_kernel`; ``omega_range``,
        ``what``, ``mark``, ``fixed``): Bode plot of H1, |H2| map, slices of Hn >= 3.
        Returns a matplotlib Figure made without pyplot (no window opens)."""
        from gfrf.kernels.plot import plot_kernel

        return plot_kernel(self, **options)

    def __call__(self, *omega: Any) -> np.ndarray:
        """Evaluate H_n at angular frequencies omega_1..omega_n in rad/s.

        Parameters
        ----------
        *omega : array_like
            n real arrays (or scalars) that broadcast together.

        Returns
        -------
        numpy.ndarray of complex128
            H_n(j*omega_1, ..., j*omega_n) with the broadcast shape (discrete models:
            at q_i = exp(-j*omega_i*T)).

        Notes
        -----
        The evaluation path is chosen by the work: the vectorised numpy recursion, or,
        for a call of millions of points where compiling pays back within the call
        (:func:`gfrf.kernels.compiled.compile_pays`, a decision on counts of points and
        operations only), the numba ufunc of :meth:`compiled`.  Both agree to rounding.

        See Also
        --------
        at_s : values at complex s_i (``H(w)`` is ``H.at_s(1j * w)``).
        """
        if len(omega) != self.order:
            raise ArgumentError(f"H{self.order} takes {self.order} angular frequencies, "
                                f"got {len(omega)}")
        arrays = []
        for w in omega:
            a = np.asarray(w, dtype=float)
            if not np.all(np.isfinite(a)):
                raise ArgumentError("angular frequencies must be finite real numbers (rad/s)")
            arrays.append(a)
        points = math.prod(np.broadcast_shapes(*(a.shape for a in arrays)))
        if points >= MIN_POINTS and not self.is_zero and compile_pays(
                self._gen, self.order, self.symmetric, points):
            try:  # millions of points: the compile pays back within this call
                with np.errstate(all="ignore"):
                    return np.asarray(self._gen.ufunc(self.order, self.symmetric)(*arrays),
                                      dtype=np.complex128)
            except ZeroDivisionError:  # a point on a pole: the numpy path gives inf/nan
                pass
        return self._gen.evaluate(self.order, arrays, self.symmetric)

    def at_s(self, *s: Any) -> np.ndarray:
        """Evaluate H_n at complex Laplace variables s_1..s_n (1/s).

        ``H.at_s(1j * w)`` equals ``H(w)``; a discrete (NARX) model is evaluated at
        q_i = exp(-s_i*T), its backward shift at s_i.

        Parameters
        ----------
        *s : array_like
            n complex arrays (or scalars) that broadcast together.

        Returns
        -------
        numpy.ndarray of complex128
            H_n(s_1, ..., s_n) with the broadcast shape (inf or nan at a pole).

        Raises
        ------
        ArgumentError
            Not n values, or a value that is not a finite complex number.

        Examples
        --------
        >>> from gfrf.model.equation import parse_model
        >>> H1 = kernel(parse_model("D(y) + 2*y = u"), 1)
        >>> complex(H1.at_s(1.0))  # 1 / (s + 2) at s = 1
        (0.3333333333333333+0j)
        """
        if len(s) != self.order:
            raise ArgumentError(f"H{self.order} takes {self.order} values of s, got {len(s)}")
        omegas = []
        for value in s:
            a = np.asarray(value)
            if a.dtype.kind not in "biufc":
                raise ArgumentError(f"s must be complex numbers (1/s), got {value!r}")
            a = a.astype(np.complex128)
            if not np.all(np.isfinite(a)):
                raise ArgumentError("s must be finite complex numbers (1/s)")
            omegas.append(-1j * a)  # s = j*omega exactly (multiplying by -1j is exact)
        return self._gen.evaluate(self.order, omegas, self.symmetric)

    def compiled(self) -> Any:
        """A numba-compiled numpy ufunc of this kernel: ``f(w1, ..., wn)`` in rad/s.

        The fast path for millions of points (no temporaries); compiled on first use
        (about a second) and cached.  No argument checking: pass finite floats.

        Raises
        ------
        ImportError
            If numba (the ``fast`` extra) is not installed.
        """
        if self.is_zero:
            return lambda *w: np.zeros(np.broadcast_shapes(*(np.shape(x) for x in w)),
                                       dtype=np.complex128)
        return self._gen.ufunc(self.order, self.symmetric)


def check_order(order: object, name: str = "order") -> int:
    """The one check of a kernel order, before any work: an integer in
    ``1..MAX_KERNEL_ORDER`` (every function and command that takes an order calls it, so
    all say the same).

    Parameters
    ----------
    order : int
        The order to check.
    name : str
        How the caller names it in the message (``"--order"``, ``"kernel order"``).

    Returns
    -------
    int
        ``order`` as a Python int.

    Raises
    ------
    ArgumentError
        ``order`` is not an integer (bool included) or is outside ``1..MAX_KERNEL_ORDER``.

    >>> check_order(13, "--order")
    Traceback (most recent call last):
    ...
    gfrf.errors.ArgumentError: --order must be an integer between 1 and ... = 12, got 13
    """
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) \
            or not 1 <= order <= MAX_KERNEL_ORDER:
        raise ArgumentError(f"{name} must be an integer between 1 and MAX_KERNEL_ORDER = "
                            f"{MAX_KERNEL_ORDER}, got {order!r}")
    return int(order)


def kernel(model: Model, n: int, symmetric: bool = True, max_terms: int | None = None
           ) -> Kernel:
    """The n-th order GFRF of ``model``.

    Parameters
    ----------
    model : Model
        A polynomial model from :func:`gfrf.model.equation.parse_model` or a model file.
    n : int
        Kernel order, 1 <= n <= :data:`MAX_KERNEL_ORDER`.
    symmetric : bool, optional
        The symmetric kernel (default; unique for the system) or the asymmetric one
        produced by the recursion in the order the model's factors are written.
    max_terms : int, optional
        Most symbolic terms of the recursion (default :data:`MAX_PLAN_TERMS`, about 9 s
        of work); see :func:`check_recursion_work`.

    Returns
    -------
    Kernel
    """
    check_order(n, "kernel order")
    if max_terms is not None and (isinstance(max_terms, bool) or not isinstance(
            max_terms, (int, np.integer)) or max_terms < 1):
        raise ArgumentError(f"max_terms (gfrf kernel --max-work) must be a positive integer, "
                            f"got {max_terms!r}")
    check_recursion_work(generator(model), int(n), bool(symmetric), max_terms)
    return Kernel(model, int(n), bool(symmetric), generator(model))
