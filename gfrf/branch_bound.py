"""Certified branch-and-bound for ||H_n||_inf = sup over R^n of |H_n(j w_1 .. j w_n)|.

The recursive majorant of :mod:`gfrf.majorant` bounds |H_n| by multiplying sup-norms
of factors; it is loose wherever terms cancel or resonances cannot coincide.  Here
the sup is enclosed directly (angular frequencies in rad/s throughout):

* **Tail.**  Outside the box |w_i| <= W (some |w_i| > W) a recursion on the majorant
  bounds |H_n|: either the block sum sigma satisfies |sigma| >= alpha W, and the top
  factor sigma^l / A(j sigma) is bounded by its exact sup over |sigma| >= alpha W, or
  two coordinates exceed (1 - alpha) W / (m-1) and (unless both are input slots) one
  of them sits in a lower-order factor, bounded recursively (best alpha of a few);
  H1 factors use their exact sup over |w| >= V.  W is doubled until this tail bound
  is below half the best value found (or stops decreasing: a factor s^2 H1 of
  relative degree 0, as in theta^2 theta'', does not decay, and the bracket then
  keeps the smallest tail bound met as its floor).
* **Boxes.**  Inside, each box gets a second-order Taylor enclosure: for every
  quantity of the straight-line recursion (the code of
  :func:`gfrf.compiled.kernel_source`, evaluated with :class:`_Taylor` numbers) the
  value and gradient at the box centre plus certified bounds, over the whole box, of
  |q|, |dq/dw_i| and |d^2 q / dw_i dw_j|.  Products follow Leibniz's rule; each
  1/A(j sigma_B) factor gets the exact extrema over the interval of sigma_B of |A|,
  |A'| and |2 A'^2 - A A''| (from the precomputed stationary points of those moduli),
  so coarse boxes straddling a resonance are bounded by the resonance peak, not by
  infinity.  The box bound is max over the box vertices of |H(c) + grad H(c) . d|
  (the affine part is convex in d) plus (1/2) sum_ij M_ij r_i r_j: the overestimate
  is second order in the box size, so a relative gap of 1e-6 needs boxes of relative
  size ~1e-3 only around the maximiser.
* **Search.**  Only a fundamental domain is searched: w_1 >= .. >= w_n for the
  symmetric kernel (|H_n| is invariant under permutations) and w_1 + .. + w_n >= 0
  (H_n(-w) = conj H_n(w)).  The boxes with the largest bounds are bisected (the
  coordinate contributing most to the enclosure width), boxes whose bound is below
  ``lower / (1 - tol)`` are discarded, box centres raise the lower bound and a new
  best centre is polished by Nelder-Mead.

Soundness.  The tail's one-dimensional sups are proven (Arb, :class:`gfrf.exact.SupBeyond`);
the extrema of |A|, |A'| and |2 A'^2 - A A''| over an interval use critical points
isolated exactly (Arb) and endpoint values widened by an a-priori Horner error bound,
so a cluster of lightly damped poles cannot shrink them.  The Taylor arithmetic itself
runs in double precision without outward rounding, and a box centre's value is used only
where |A| there is accurate to 1e-8 relative (elsewhere the box keeps its magnitude
bounds): the upper bound is certified in floating point (``proof = "float"``), not
proven.  Continuous-time models only.

Examples
--------
>>> from gfrf.model import parse_model
>>> r = branch_and_bound(parse_model("D(y,2) + 0.2*D(y) + y + 0.4*y**2 = u"), 2)
>>> r.converged and (r.upper - r.lower) <= 1e-6 * r.upper
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
import sympy as sp

from gfrf.compiled import _Printer, kernel_source
from gfrf.errors import ArgumentError
from gfrf.kernels import GFRFGenerator, generator
from gfrf.majorant import linear_polynomials, majorant
from gfrf.model import Model
from gfrf.simplex import nelder_mead
from gfrf.tail import tail_bound

__all__ = ["BranchBoundResult", "branch_and_bound", "box_bounds", "MAX_ORDER",
           "MAX_BOXES"]

#: Highest kernel order searched (the enclosure costs 2^n vertices and n^2 Hessian bounds).
MAX_ORDER = 5
#: Boxes bisected per vectorised step.
BATCH = 2048
#: Default budget of box evaluations of :func:`branch_and_bound` (about 10 s at order 5
#: on a 2-core 2026 machine; :func:`gfrf.norms.kernel_norm` passes its own budget).
MAX_BOXES = 200_000
#: Nelder-Mead polishings of a new best box centre per search.
MAX_POLISHES = 20


@dataclass(frozen=True)
class BranchBoundResult:
    """Bracket of ||H_n||_inf from the branch-and-bound (angular frequencies in rad/s).

    Attributes
    ----------
    lower : float
        Best |H_n| found (attained at ``argmax``).
    upper : float
        Certified upper bound: max of the tail bound and of every box bound (never above
        the recursive majorant).
    argmax : tuple of float
        Where ``lower`` is attained (rad/s).
    converged : bool
        True when ``upper - lower <= tol * upper`` was reached within the budget.
    boxes : int
        Number of boxes evaluated (the work that decided where the search stopped).
    width : float
        Half-width W (rad/s) of the searched box [-W, W]^n.
    tail : float
        Certified bound of |H_n| outside that box.
    """

    lower: float
    upper: float
    argmax: tuple[float, ...]
    converged: bool
    boxes: int
    width: float
    tail: float


# -- polynomials of sigma (real) -----------------------------------------------------
#: Relative error of |A(j sigma)| (a-priori Horner bound) above which a box centre's
#: value and slope are not used (the box keeps its magnitude bounds only).
_POINT_RTOL = 1e-8


def _cmul(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    """Product of complex polynomials given as (real part, imaginary part) fmpq_polys."""
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]


class _Modulus:
    """Bounds of |p(sigma)| over intervals, p a complex polynomial of real sigma given
    exactly by its real and imaginary parts (fmpq_polys).

    The critical points of |p|^2 are the real roots of its derivative, isolated
    rigorously (FLINT/Arb) once, and |p| is enclosed on their balls; the endpoint
    values are double-precision Horner evaluations widened by the a-priori error bound
    gamma * sum |c_k| |sigma|^k.  So ``extrema`` is a sound (min, max) even for a cluster
    of lightly damped poles, where float roots of d|p|^2 can be off by 1e-4.
    """

    def __init__(self, re: Any, im: Any) -> None:
        from flint import arb_poly

        from gfrf.exact import _PREC, _down, _precision, _real_roots, _up

        degree = max(re.degree(), im.degree(), 0)
        re_c = [float(c) for c in re.coeffs()] + [0.0] * (degree + 1 - len(re.coeffs()))
        im_c = [float(c) for c in im.coeffs()] + [0.0] * (degree + 1 - len(im.coeffs()))
        self.coef = (np.array(re_c) + 1j * np.array(im_c))[::-1]  # highest first
        self.abs_coef = np.abs(self.coef)
        self.gamma = (4 * degree + 8) * 2.0 ** -53
        squared = re * re + im * im
        slope = squared.derivative()
        lo, hi, small, large = [], [], [], []
        if slope.degree() >= 1:
            with _precision(_PREC):
                sq = arb_poly([c for c in squared.coeffs()])
                for x, _ in _real_roots(slope):
                    value = sq(x)
                    lo.append(_down(x))
                    hi.append(_up(x))
                    small.append(math.sqrt(max(_down(value), 0.0)))
                    large.append(math.sqrt(_up(value)) * (1 + 2.0 ** -52))
        self.crit_lo, self.crit_hi = np.array(lo), np.array(hi)
        self.crit_min, self.crit_max = np.array(small), np.array(large)

    def __call__(self, sigma: np.ndarray) -> np.ndarray:
        return np.polyval(self.coef, sigma)

    def error(self, sigma: np.ndarray) -> np.ndarray:
        """A-priori bound on the error of the double-precision value at sigma."""
        return self.gamma * np.polyval(self.abs_coef, np.abs(sigma))

    def extrema(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(lower bound of min, upper bound of max) of |p| over [lo, hi] (vectorised)."""
        a, b = np.abs(self(lo)), np.abs(self(hi))
        ea, eb = self.error(lo), self.error(hi)
        small = np.maximum(np.minimum(a - ea, b - eb), 0.0)
        large = np.maximum(a + ea, b + eb)
        if self.crit_lo.size:
            inside = (self.crit_lo <= hi[:, None]) & (self.crit_hi >= lo[:, None])
            small = np.minimum(small, np.where(inside, self.crit_min, np.inf).min(axis=1))
            large = np.maximum(large, np.where(inside, self.crit_max, -np.inf).max(axis=1))
        return small, large


class _InverseA:
    """r(sigma) = 1 / A(j sigma) with its derivatives and their bounds on intervals.

    A(j sigma), its sigma-derivatives and 2 A'^2 - A A'' are formed exactly from the
    float coefficients (highest power first) and bounded by :class:`_Modulus`.
    """

    def __init__(self, den: np.ndarray) -> None:
        from flint import fmpq, fmpq_poly

        from gfrf.exact import fractions

        low = [fmpq(c.numerator, c.denominator) for c in reversed(fractions(den))]
        unit = [(1, 0), (0, 1), (-1, 0), (0, -1)]  # j^k
        a = (fmpq_poly([c * unit[k % 4][0] for k, c in enumerate(low)]),
             fmpq_poly([c * unit[k % 4][1] for k, c in enumerate(low)]))
        da = (a[0].derivative(), a[1].derivative())
        dda = (da[0].derivative(), da[1].derivative())
        sq, prod = _cmul(da, da), _cmul(a, dda)
        self.a, self.da = _Modulus(*a), _Modulus(*da)
        self.second = _Modulus(2 * sq[0] - prod[0], 2 * sq[1] - prod[1])

    def point(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """r and dr/dsigma at points (NaN where |A| is not accurate to _POINT_RTOL)."""
        a = self.a(sigma)
        with np.errstate(divide="ignore", invalid="ignore"):
            bad = self.a.error(sigma) > _POINT_RTOL * np.abs(a)
            value, slope = 1.0 / a, -self.da(sigma) / (a * a)
        return np.where(bad, np.nan, value), np.where(bad, np.nan, slope)

    def bounds(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, ...]:
        """Sups over [lo, hi] of |r|, |r'| and |r''| = |2 a'^2 - a a''| / |a|^3."""
        a_min, _ = self.a.extrema(lo, hi)
        _, da_max = self.da.extrema(lo, hi)
        _, second_max = self.second.extrema(lo, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = np.where(a_min > 0, 1.0 / a_min, np.inf)
            return inv, _safe(da_max * inv * inv), _safe(second_max * inv ** 3)


def _safe(x: np.ndarray) -> np.ndarray:
    """NaN (0 * inf) becomes inf: an undetermined bound is no bound."""
    return np.where(np.isnan(x), np.inf, x)


# -- second-order Taylor enclosures --------------------------------------------------
class _Context:
    """Box centres c and half-widths r, shape (N, n)."""

    def __init__(self, centre: np.ndarray, radius: np.ndarray, inverse: _InverseA) -> None:
        self.c, self.r, self.inverse = centre, radius, inverse

    def variable(self, i: int) -> _Taylor:
        """x_i = j w_i."""
        size, n = self.c.shape
        g = np.zeros((size, n), dtype=complex)
        g[:, i] = 1j
        mg = np.zeros((size, n))
        mg[:, i] = 1.0
        return _Taylor(1j * self.c[:, i], g, np.abs(self.c[:, i]) + self.r[:, i], mg,
                       np.zeros((size, n, n)), self)

    def inv_a(self, block: tuple[int, ...]) -> _Taylor:
        """1 / A(j sigma_B), sigma_B = sum of the block's w_i."""
        idx = list(block)
        sigma, rho = self.c[:, idx].sum(axis=1), self.r[:, idx].sum(axis=1)
        value, slope = self.inverse.point(sigma)
        m0, m1, m2 = self.inverse.bounds(sigma - rho, sigma + rho)
        size, n = self.c.shape
        mask = np.zeros(n)
        mask[idx] = 1.0
        return _Taylor(value, slope[:, None] * mask, m0, m1[:, None] * mask,
                       _safe(m2[:, None, None] * np.outer(mask, mask)), self).tighten()


class _Taylor:
    """Value and gradient at the centres, bounds of |q|, |dq| and |d^2 q| on the boxes."""

    __slots__ = ("v", "g", "mv", "mg", "mh", "ctx")

    def __init__(self, v: np.ndarray, g: np.ndarray, mv: np.ndarray, mg: np.ndarray,
                 mh: np.ndarray, ctx: _Context) -> None:
        self.v, self.g, self.mv, self.mg, self.mh, self.ctx = v, g, mv, mg, mh, ctx

    def tighten(self) -> _Taylor:
        """Intersect the propagated bounds with the Taylor-form bounds of |q| and |dq|."""
        r = self.ctx.r
        with np.errstate(invalid="ignore"):
            mhr = _safe(np.einsum("kij,kj->ki", self.mh, r))
            self.mg = np.minimum(self.mg, np.abs(self.g) + mhr)
            form = np.abs(self.v) + np.sum(np.abs(self.g) * r + 0.5 * r * mhr, axis=1)
        self.mv = np.minimum(self.mv, _safe(form))
        return self

    def _scaled(self, c: complex) -> _Taylor:
        a = abs(c)
        return _Taylor(c * self.v, c * self.g, a * self.mv, a * self.mg, a * self.mh, self.ctx)

    def __neg__(self) -> _Taylor:
        return self._scaled(-1.0)

    def __add__(self, other: Any) -> _Taylor:
        if not isinstance(other, _Taylor):
            return _Taylor(self.v + other, self.g, self.mv + abs(other), self.mg, self.mh,
                           self.ctx)
        return _Taylor(self.v + other.v, self.g + other.g, self.mv + other.mv,
                       self.mg + other.mg, self.mh + other.mh, self.ctx).tighten()

    __radd__ = __add__

    def __sub__(self, other: Any) -> _Taylor:
        return self + (-other)

    def __rsub__(self, other: Any) -> _Taylor:
        return (-self) + other

    def __mul__(self, other: Any) -> _Taylor:
        if not isinstance(other, _Taylor):
            return self._scaled(complex(other))
        a, b = self, other
        outer = a.mg[:, :, None] * b.mg[:, None, :]
        with np.errstate(invalid="ignore"):
            mh = (a.mh * b.mv[:, None, None] + outer + outer.transpose(0, 2, 1)
                  + a.mv[:, None, None] * b.mh)
            mg = a.mg * b.mv[:, None] + a.mv[:, None] * b.mg
        return _Taylor(a.v * b.v, a.g * b.v[:, None] + a.v[:, None] * b.g, a.mv * b.mv,
                       _safe(mg), _safe(mh), self.ctx).tighten()

    __rmul__ = __mul__

    def __pow__(self, k: int) -> _Taylor:
        if not (isinstance(k, int) and k >= 1):
            raise ArgumentError(f"only positive integer powers are enclosed, got {k!r}")
        result = self
        for _ in range(k - 1):
            result = result * self
        return result


def _taylor_source(gen: GFRFGenerator, n: int, symmetric: bool) -> str:
    """Source of ``taylor_kernel(x, inv_a)``: the recursion with 1/A as a call."""
    printer = _Printer()
    lines = ["def taylor_kernel(x, inv_a):",
             f"    {', '.join(f'x{i}' for i in range(n))}, = x"]
    names: dict[tuple[int, ...], str] = {}

    def emit(block: tuple[int, ...]) -> str:
        if block in names:
            return names[block]
        plan = gen.plan(len(block), symmetric)
        if plan.is_zero:
            names[block] = "0.0"
            return "0.0"
        label = "h_" + "_".join(map(str, block))
        inner = gen.variables(len(block))
        mapping: dict[sp.Symbol, sp.Symbol] = {v: sp.Symbol(f"x{block[i]}")
                                               for i, v in enumerate(inner)}
        for sub, placeholder in zip(plan.blocks, plan.placeholders, strict=True):
            mapping[placeholder] = sp.Symbol(emit(tuple(block[j] for j in sub)))
        replacements, (reduced,) = sp.cse(plan.numerator.xreplace(mapping),
                                          symbols=sp.numbered_symbols(f"{label}_c"))
        for sym, value in replacements:
            lines.append(f"    {sym} = {printer.doprint(value)}")
        lines.append(f"    {label} = -({printer.doprint(reduced)}) * inv_a({block!r})")
        names[block] = label
        return label

    lines.append(f"    return {emit(tuple(range(n)))}")
    return "\n".join(lines) + "\n"


@lru_cache(maxsize=32)
def _compiled(gen: GFRFGenerator, n: int, symmetric: bool) -> tuple[Callable[..., Any],
                                                                     Callable[..., Any]]:
    """(Taylor enclosure function, scalar point function) of H_n."""
    namespace: dict[str, Any] = {}
    exec(compile(_taylor_source(gen, n, symmetric), f"<gfrf taylor H{n}>", "exec"),  # noqa: S102
         namespace)
    exec(compile(kernel_source(gen, n, symmetric, "point_kernel"), f"<gfrf H{n}>", "exec"),  # noqa: S102
         namespace)
    return namespace["taylor_kernel"], namespace["point_kernel"]


def box_bounds(model: Model, n: int, lo: np.ndarray, hi: np.ndarray, symmetric: bool = True
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Certified bounds of |H_n| on boxes, with the centre values.

    Parameters
    ----------
    model : Model
        Continuous-time model.
    n : int
        Kernel order.
    lo, hi : numpy.ndarray, shape (N, n)
        Box corners, angular frequencies in rad/s.
    symmetric : bool, optional
        Symmetric (default) or asymmetric kernel.

    Returns
    -------
    bound : numpy.ndarray, shape (N,)
        sup of |H_n| over each box is at most ``bound``.
    centre_value : numpy.ndarray of complex, shape (N,)
        H_n at the box centres.
    split : numpy.ndarray of int, shape (N,)
        Coordinate whose bisection most reduces the enclosure width.
    """
    if model.is_discrete:
        raise ArgumentError("the branch-and-bound handles continuous-time models only")
    _, den = linear_polynomials(model)
    return _box_bounds(_compiled(generator(model), n, symmetric)[0], _InverseA(den),
                       np.asarray(lo, float), np.asarray(hi, float))


def _box_bounds(taylor: Callable[..., Any], inverse: _InverseA, lo: np.ndarray,
                hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    centre, radius = 0.5 * (lo + hi), 0.5 * (hi - lo)
    ctx = _Context(centre, radius, inverse)
    n = centre.shape[1]
    h = taylor([ctx.variable(i) for i in range(n)], ctx.inv_a)
    signs = np.array(np.meshgrid(*([[-1.0, 1.0]] * n), indexing="ij")).reshape(n, -1)
    with np.errstate(invalid="ignore"):
        vertex = np.abs(h.v[:, None] + (h.g * radius) @ signs).max(axis=1)
        mhr = _safe(np.einsum("kij,kj->ki", h.mh, radius))
        bound = np.minimum(h.mv, _safe(vertex + 0.5 * np.sum(radius * mhr, axis=1)))
        width = radius * (np.abs(h.g) + mhr)
    return bound, h.v, np.argmax(np.where(np.isnan(width), np.inf, width), axis=1)


# -- search ----------------------------------------------------------------------------
def _in_domain(lo: np.ndarray, hi: np.ndarray, symmetric: bool) -> np.ndarray:
    """Boxes meeting {sum w >= 0} and, symmetric, {w_1 >= w_2 >= .. >= w_n}."""
    if not symmetric:
        return hi.sum(axis=1) >= 0
    greedy = np.minimum.accumulate(hi, axis=1)
    return np.all(greedy >= lo, axis=1) & (greedy.sum(axis=1) >= 0)


def _polish(point: Callable[..., complex], x0: np.ndarray, scale: float
            ) -> tuple[np.ndarray, float]:
    """Nelder-Mead on -log|H_n| from x0."""

    def objective(x: np.ndarray) -> float:
        v = abs(point(*x))
        return -math.log(v) if v > 0 and math.isfinite(v) else 1e300

    n = x0.size
    res = nelder_mead(objective, x0, initial_simplex=np.vstack([x0, x0 + scale * np.eye(n)]),
                      xatol=1e-13 * (1 + float(np.max(np.abs(x0)))), fatol=1e-15,
                      maxiter=800 * n, maxfev=1000 * n)
    return res.x, abs(point(*res.x))


def branch_and_bound(model: Model, n: int, symmetric: bool = True, lower: float = 0.0,
                     argmax: tuple[float, ...] | None = None, tol: float = 1e-6,
                     max_boxes: int = MAX_BOXES) -> BranchBoundResult:
    """Certified bracket of ||H_n||_inf over R^n (angular frequencies in rad/s).

    Parameters
    ----------
    model : Model
        Continuous-time model whose majorant is finite (else the tail is unbounded).
    n : int
        Kernel order, 2 <= n <= :data:`MAX_ORDER`.
    symmetric : bool, optional
        Symmetric (default) or asymmetric kernel.
    lower, argmax : optional
        A value already attained and where (e.g. from a local search).
    tol : float, optional
        Target relative gap (upper - lower) / upper.
    max_boxes : int, optional
        Budget of box evaluations; the search stops at the first batch that reaches
        it and returns the honest bracket with ``converged = False``.  The result
        depends on the model, ``n``, ``tol`` and this budget only, never on time.

    Returns
    -------
    BranchBoundResult
    """
    if model.is_discrete:
        raise ArgumentError("the branch-and-bound handles continuous-time models only")
    if not 2 <= n <= MAX_ORDER:
        raise ArgumentError(f"branch-and-bound order must be in 2..{MAX_ORDER}, got {n}")
    if isinstance(max_boxes, bool) or not isinstance(max_boxes, int) or max_boxes < 1:
        raise ArgumentError(f"max_boxes must be a positive integer, got {max_boxes!r}")
    gen = generator(model)
    taylor, point = _compiled(gen, n, symmetric)
    _, den = linear_polynomials(model)
    inverse = _InverseA(den)
    best_x = np.zeros(n) if argmax is None else np.array(argmax, dtype=float)
    best = max(lower, abs(point(*best_x)))
    maj = majorant(model)
    poles = np.roots(den) if den.size > 1 else np.zeros(1)
    width = 2.0 * (1.0 + float(np.max(np.abs(poles))))
    tails = [(width, tail_bound(model, n, width, maj))]
    while tails[-1][1] > 0.5 * best and len(tails) < 60 and not (
            len(tails) > 8 and tails[-1][1] >= 0.99 * tails[-5][1]):  # floor reached
        tails.append((2.0 * width, tail_bound(model, n, 2.0 * width, maj)))
        width *= 2.0
    floor = min(t for _, t in tails)
    width, tail = next((w, t) for w, t in tails if t <= max(floor * 1.01, 0.5 * best))
    ceiling = float(maj.coefficients(n)[n, 0])
    if not tail < ceiling:
        return BranchBoundResult(best, max(ceiling, best), tuple(float(x) for x in best_x),
                                 False, 0, width, tail)
    lo, hi = -width * np.ones((1, n)), width * np.ones((1, n))
    bound, value, split = _box_bounds(taylor, inverse, lo, hi)
    boxes, pruned, polishes = 1, 0.0, 0
    while True:
        threshold = max(best / (1.0 - tol), tail)  # upper >= tail whatever the boxes give
        keep = bound > threshold
        pruned = max(pruned, float(np.max(bound[~keep], initial=0.0)))
        lo, hi, bound, split = lo[keep], hi[keep], bound[keep], split[keep]
        upper = max(tail, pruned, float(np.max(bound, initial=0.0)))
        if not bound.size or boxes >= max_boxes:
            break
        take = np.argsort(bound)[::-1][:BATCH]
        rest = np.ones(bound.size, bool)
        rest[take] = False
        p_lo, p_hi, p_split = lo[take], hi[take], split[take]
        rows = np.arange(take.size)
        mid = 0.5 * (p_lo[rows, p_split] + p_hi[rows, p_split])
        left_hi, right_lo = p_hi.copy(), p_lo.copy()
        left_hi[rows, p_split] = mid
        right_lo[rows, p_split] = mid
        c_lo, c_hi = np.vstack([p_lo, right_lo]), np.vstack([left_hi, p_hi])
        inside = _in_domain(c_lo, c_hi, True) if symmetric else _in_domain(c_lo, c_hi, False)
        c_lo, c_hi = c_lo[inside], c_hi[inside]
        c_bound, c_value, c_split = _box_bounds(taylor, inverse, c_lo, c_hi)
        boxes += c_lo.shape[0]
        magnitude = np.abs(c_value)
        magnitude[~np.isfinite(magnitude)] = 0.0
        if magnitude.size and magnitude.max() > best:
            k = int(np.argmax(magnitude))
            centre = 0.5 * (c_lo[k] + c_hi[k])
            if magnitude[k] > best * (1 + tol) and polishes < MAX_POLISHES:
                polishes += 1
                x, polished = _polish(point, centre, float(np.max(c_hi[k] - c_lo[k])))
                if polished > magnitude[k]:
                    centre, magnitude[k] = x, polished
            best, best_x = float(magnitude[k]), centre
        lo, hi = np.vstack([lo[rest], c_lo]), np.vstack([hi[rest], c_hi])
        bound = np.concatenate([bound[rest], c_bound])
        split = np.concatenate([split[rest], c_split])
    upper = max(min(upper, ceiling), best)
    return BranchBoundResult(best, upper, tuple(float(x) for x in best_x),
                             upper - best <= tol * upper, boxes, width, tail)
