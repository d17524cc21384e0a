"""Certified branch-and-bound for ||H_n||_inf = sup over R^n of |H_n(j w_1 .. j w_n)|.

The recursive majorant of :mod:`gfrf.bounds.majorant` bounds |H_n| by multiplying sup-norms
of factors; it is loose wherever terms cancel or resonances cannot coincide.  Here
the sup is enclosed directly (angular frequencies in rad/s throughout):

* **Tail.**  Outside the box |w_i| <= W (some |w_i| > W), the proven tail bound of
  :mod:`gfrf.bounds.tail` (a recursion on the majorant that places the large coordinates in
  the factors of each term).  W is doubled until it is below half the best value found
  (or stops decreasing: the bracket then keeps the smallest tail bound met as its floor).
* **Boxes.**  Inside, each box gets the enclosure of :mod:`gfrf.bounds.enclosure`: a
  third-order Taylor enclosure of the straight-line recursion (the code of
  :func:`gfrf.kernels.compiled.kernel_source`), whose tightest bound comes from the exact
  quadratic model of |H_n|^2 at the box centre, so the overestimate is third order in
  the box size.
* **Search.**  Only a fundamental domain is searched: w_1 >= .. >= w_n for the
  symmetric kernel (|H_n| is invariant under permutations) and w_1 + .. + w_n >= 0
  (H_n(-w) = conj H_n(w)).  The boxes with the largest bounds are bisected (the
  coordinate contributing most to the enclosure width; on a torus a longest side while
  a box is coarse, see :func:`_longest`), a child's bound is at most its parent's (it
  lies in the parent), boxes whose bound is below
  ``lower / (1 - tol)`` are discarded, box centres raise the lower bound and a new
  best centre is polished by Nelder-Mead.

Soundness.  The tail's one-dimensional sups are proven (Arb,
:class:`gfrf.bounds.exact_sup.SupBeyond`); the box enclosures are certified in floating point
(see :mod:`gfrf.bounds.enclosure`), so the upper bound is ``proof = "float"``, not proven.

Discrete-time (NARX) models.  H_n is a function of q_i = exp(-j w_i T), periodic in each
w_i: the search covers the torus [-pi/T, pi/T]^n (one period, no tail), the variables'
jets are those of q_i, carried as exact phase turns (the carriers of
:mod:`gfrf.bounds.enclosure`), and 1/A(q) is bounded over intervals by
:class:`gfrf.bounds.torus.InverseTrig`; the same proof level (``"float"``) results.

Examples
--------
>>> from gfrf.model.equation import parse_model
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

from gfrf.bounds.budget import (
    BOX_LIMIT,
    DEFAULT_WORK,
    LEAST_BUDGET,
    MAX_OPEN,
    MAX_ORDER,
    _compiled,
    _operations,
    box_work,
    budget_note,
    check_budget,
    default_budget,
)
from gfrf.bounds.enclosure import enclose
from gfrf.bounds.inverse import InverseA
from gfrf.bounds.majorant import linear_polynomials, majorant
from gfrf.bounds.simplex import nelder_mead
from gfrf.bounds.starts import start_points
from gfrf.bounds.tail import tail_bound
from gfrf.errors import ArgumentError
from gfrf.kernels.poles import linear_poles
from gfrf.kernels.recursion import generator
from gfrf.model.equation import Model

# the work caps live in gfrf.bounds.budget and are re-exported here, where callers look
__all__ = ["BranchBoundResult", "branch_and_bound", "box_bounds", "MAX_ORDER",
           "MAX_BOXES", "BOX_LIMIT", "MAX_OPEN", "DEFAULT_WORK", "LEAST_BUDGET",
           "check_budget", "box_work", "default_budget", "budget_note"]

#: Boxes bisected per vectorised step.
BATCH = 2048
#: Default budget of box evaluations of :func:`branch_and_bound` (about 10 s at order 5
#: on a 2-core 2026 machine; :func:`gfrf.bounds.norms.kernel_norm` passes its own budget).
MAX_BOXES = 200_000
#: Boxes evaluated after which a search continues with the fused numba loops (when
#: installed): their one-off import and cache load (~0.5 s) is then repaid by the ~50-250
#: us per box they save (pendulum and cart-pole H5), and a search that ends sooner (most
#: at orders <= 3) never imports numba.  A count of work, so the switch is deterministic.
COMPILED_FROM = 5_000
#: Budget from which the fused loops are used from the first box (a search given that
#: much work is expected to need more than COMPILED_FROM boxes).
COMPILED_BUDGET = 100_000
#: Lowest order whose searches start with the fused loops whatever the budget: every
#: bundled model's H5 search to 1e-3 evaluates more than COMPILED_FROM boxes (7,191
#: to 54,683), so a numpy phase (about 2x slower per box) never pays there; at orders
#: <= 3 they take a few hundred boxes (the cart-pole's H3: 415) and never load numba.
COMPILED_ORDER = 5
#: Side (in theta = w T, radians) above which a torus search halves a box's longest side
#: instead of the enclosure's choice (:func:`_longest`).  Measured on the identified
#: example's H5, boxes to close the gap to 1e-3 from its known sup: 47,400 at 0.2,
#: 51,300 halving a longest side always; 54,800 at 0.2 against 55,700 at 0.1 and 58,700
#: at 0.4 with the quotient-rule tables of 1/A alone.
COARSE_SIDE = 0.2
#: Nelder-Mead polishings of a new best box centre per search.
MAX_POLISHES = 20
#: Work of all polishings of one search, in evaluations of H_n times the operations of one
#: evaluation: 20 polishings of 5,000 evaluations of a 720-operation kernel (every
#: bundled model's H5 is below), a few seconds of scalar evaluations.
POLISH_WORK = 72_000_000


@dataclass(frozen=True, kw_only=True)
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
    stop : str
        Why the search stopped: ``"tol"`` (converged or no box left), ``"budget"``
        (``max_boxes`` reached), ``"open boxes"`` (:data:`MAX_OPEN` undecided boxes) or
        ``"tail"`` (the tail bound is not below the majorant: no search).
    """

    lower: float
    upper: float
    argmax: tuple[float, ...]
    converged: bool
    boxes: int
    width: float
    tail: float
    stop: str = "tol"


def box_bounds(model: Model, n: int, lo: np.ndarray, hi: np.ndarray, symmetric: bool = True,
               compiled: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Certified bounds of |H_n| on boxes, with |H_n| at the centres.

    Parameters
    ----------
    model : Model
        Continuous-time or discrete-time (NARX) model.
    n : int
        Kernel order.
    lo, hi : numpy.ndarray, shape (N, n)
        Box corners, angular frequencies in rad/s.
    symmetric : bool, optional
        Symmetric (default) or asymmetric kernel.
    compiled : bool, optional
        The fused numba loops instead of numpy (see :func:`gfrf.bounds.enclosure.enclose`).

    Returns
    -------
    bound : numpy.ndarray, shape (N,)
        sup of |H_n| over each box is at most ``bound``.
    centre_modulus : numpy.ndarray, shape (N,)
        |H_n| at the box centres.
    split : numpy.ndarray of int, shape (N,)
        Coordinate whose bisection most reduces the enclosure width.
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    if lo.ndim != 2 or lo.shape != hi.shape or lo.shape[1] != n:
        raise ArgumentError(f"lo and hi must both have shape (N, {n})")
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo <= hi)):
        raise ArgumentError("box corners must be finite with lo <= hi (rad/s)")
    return enclose(_compiled(generator(model), n, symmetric)[0], _model_inverse(model),
                   lo, hi, compiled, _input_free(model), model.sample_time)


def _input_free(model: Model) -> bool:
    """No input in a nonlinear term: every term of H_n holds each H1(w_i) once."""
    return not any(t.q for t in majorant(model).terms)


@lru_cache(maxsize=16)
def _inverse(den: tuple[float, ...], sample_time: float | None = None) -> Any:
    """:class:`gfrf.bounds.inverse.InverseA` of a denominator, or for a discrete model
    :class:`gfrf.bounds.torus.InverseTrig`, built once per model."""
    if sample_time is None:
        return InverseA(np.array(den))
    from gfrf.bounds.rational import discrete_rational_sup
    from gfrf.bounds.torus import InverseTrig

    peak = discrete_rational_sup(np.ones(1), np.array(den), sample_time).upper
    return InverseTrig(np.array(den), sample_time,
                       1.0 / peak if math.isfinite(peak) and peak > 0 else 0.0)


def _model_inverse(model: Model) -> Any:
    """1/A of ``model``'s linear part, for :func:`gfrf.bounds.enclosure.enclose`."""
    _, den = linear_polynomials(model)
    return _inverse(tuple(den.tolist()), model.sample_time if model.is_discrete else None)


# -- search ----------------------------------------------------------------------------
def _in_domain(lo: np.ndarray, hi: np.ndarray, symmetric: bool) -> np.ndarray:
    """Boxes that may meet the open domain {sum w > 0} and, symmetric, {w_1 > .. > w_n}.

    The tests are necessary conditions for a box to hold a point of that open set (a
    point x with lo <= x <= hi, x_1 > .. > x_n has hi_i >= x_i > x_j >= lo_j for i < j),
    so no such point is dropped; the kept boxes form a closed set, hence cover its
    closure {w_1 >= .. >= w_n, sum w >= 0} too.  A box meeting only a face of that
    closure (e.g. [a, b] x [b, c] with b < c, where w_1 = w_2 = b) is dropped: its
    points lie in the mirrored box as well.
    """
    if not symmetric:
        return hi.sum(axis=1) > 0
    greedy = np.minimum.accumulate(hi, axis=1)  # the componentwise largest sorted point
    return np.all(greedy[:, :-1] > lo[:, 1:], axis=1) & (greedy.sum(axis=1) > 0)


def _longest(side: np.ndarray, preferred: np.ndarray, coarse: float) -> np.ndarray:
    """Split axes of a torus search: in a box with a side longer than ``coarse`` (rad/s), a
    longest side (the ``preferred`` axis, the enclosure's choice, where it is one); in a
    smaller box the ``preferred`` axis.

    On a torus every factor 1/A(exp(-j sigma_B T)) of a block B depends on the sum
    sigma_B of the block's frequencies, whose interval is as wide as the sum of the
    block's sides; its Taylor bounds are poor while that sum is wide, so halving the
    longest side first narrows the most intervals.
    """
    rows = np.arange(side.shape[0])
    top = side.max(axis=1)
    longest = np.where(side[rows, preferred] >= top, preferred, np.argmax(side, axis=1))
    return np.where(top > coarse, longest, preferred)


def _polish(point: Callable[..., complex], x0: np.ndarray, scale: float, maxfev: int
            ) -> tuple[np.ndarray, float]:
    """Nelder-Mead on -log|H_n| from x0, at most ``maxfev`` evaluations."""

    def objective(x: np.ndarray) -> float:
        v = abs(point(*x))
        return -math.log(v) if v > 0 and math.isfinite(v) else 1e300

    n = x0.size
    res = nelder_mead(objective, x0, initial_simplex=np.vstack([x0, x0 + scale * np.eye(n)]),
                      xatol=1e-13 * (1 + float(np.max(np.abs(x0)))), fatol=1e-15,
                      maxiter=800 * n, maxfev=maxfev)
    return res.x, abs(point(*res.x))


def _modulus(point: Callable[..., complex], x: np.ndarray) -> float:
    """|H_n(x)|, 0 where it is not a finite number."""
    with np.errstate(all="ignore"):
        value = abs(complex(point(*x)))
    return value if math.isfinite(value) else 0.0


def _resonance_start(point: Callable[..., Any], poles: np.ndarray, n: int) -> np.ndarray:
    """The best of the start points (:func:`gfrf.bounds.starts.start_points`) built from the
    poles' frequencies {0, |Im p|}: a start whose |H_n| lets the tail width W stop
    doubling (from 0, where |H_n| may vanish, it never would)."""
    starts = start_points({0.0, *(float(abs(p.imag)) for p in poles)}, n)
    with np.errstate(all="ignore"):
        values = np.abs(np.asarray(point(*starts.T), dtype=complex))
    values = np.broadcast_to(values, starts.shape[:1]).copy()  # a constant kernel: a scalar
    values[~np.isfinite(values)] = 0.0
    return starts[int(np.argmax(values))]


def branch_and_bound(model: Model, n: int, symmetric: bool = True, lower: float = 0.0,
                     argmax: tuple[float, ...] | None = None, tol: float = 1e-6,
                     max_boxes: int = MAX_BOXES, progress: bool | None = False
                     ) -> BranchBoundResult:
    """Certified bracket of ||H_n||_inf over R^n (angular frequencies in rad/s).

    Parameters
    ----------
    model : Model
        A continuous-time model whose majorant is finite (else the tail is unbounded),
        or a discrete-time (NARX) model, whose kernels are periodic: the search covers
        the torus [-pi/T, pi/T]^n and needs no tail.
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
    progress : bool or None, optional
        tqdm progress bar of the boxes spent against the budget, with the current gap
        (on stderr); None shows it on a terminal only.  Default False.

    Returns
    -------
    BranchBoundResult
    """
    if not 2 <= n <= MAX_ORDER:
        raise ArgumentError(f"branch-and-bound order must be in 2..{MAX_ORDER}, got {n}")
    max_boxes = check_budget(max_boxes, 1)
    gen = generator(model)
    fused_start = max_boxes >= COMPILED_BUDGET or n >= COMPILED_ORDER
    taylor, point = _compiled(gen, n, symmetric)
    inverse = _model_inverse(model)
    poles = linear_poles(model)
    if model.is_discrete:  # the poles' frequencies |arg q| / T, as points j w
        poles = 1j * np.abs(poles.imag)
    elif poles.size == 0:
        poles = np.zeros(1)
    best_x = (_resonance_start(point, poles, n) if argmax is None
              else np.array(argmax, dtype=float))
    best = max(lower, _modulus(point, best_x))
    maj = majorant(model)
    leaves = _input_free(model)
    if model.is_discrete:  # a torus: [-pi/T, pi/T]^n holds a whole period, no tail
        width = math.pi / model.sample_time  # type: ignore[operator]
        return _search(taylor, point, inverse, model.sample_time, n, symmetric, best, best_x,
                       tol, max_boxes, progress, fused_start, leaves, width, 0.0,
                       float(maj.coefficients(n)[n, 0]), _operations(gen, n, symmetric, True))
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
        return BranchBoundResult(lower=best, upper=max(ceiling, best),
                                 argmax=tuple(float(x) for x in best_x), converged=False,
                                 boxes=0, width=width, tail=tail, stop="tail")
    return _search(taylor, point, inverse, None, n, symmetric, best, best_x, tol, max_boxes,
                   progress, fused_start, leaves, width, tail, ceiling,
                   _operations(gen, n, symmetric))


def _search(taylor: Callable[..., Any], point: Callable[..., Any], inverse: Any,
            sample_time: float | None, n: int, symmetric: bool, best: float,
            best_x: np.ndarray, tol: float, max_boxes: int, progress: bool | None,
            fused_start: bool, leaves: bool, width: float, tail: float, ceiling: float,
            operations: int) -> BranchBoundResult:
    """The branch-and-bound proper over [-width, width]^n (``tail`` bounds |H_n| outside).

    Work: at most ``max_boxes`` boxes (a step bisects at most as many boxes as the budget
    has left) and :data:`POLISH_WORK` / ``operations`` point evaluations of the polishes.
    """
    lo, hi = -width * np.ones((1, n)), width * np.ones((1, n))
    bound, value, split = enclose(taylor, inverse, lo, hi, fused_start, leaves, sample_time)
    boxes, pruned, polishes, stop = 1, 0.0, 0, "tol"
    polish_points = POLISH_WORK // max(1, operations)
    from tqdm import tqdm

    bar = tqdm(total=max_boxes, initial=1, unit="box", desc=f"||H{n}|| bracket", leave=False,
               disable=None if progress is None else not progress)
    with bar:
        while True:
            threshold = max(best / (1.0 - tol), tail)  # upper >= tail whatever the boxes give
            keep = bound > threshold
            pruned = max(pruned, float(np.max(bound[~keep], initial=0.0)))
            lo, hi, bound, split = lo[keep], hi[keep], bound[keep], split[keep]
            upper = max(tail, pruned, float(np.max(bound, initial=0.0)))
            bar.set_postfix_str(f"gap {1 - best / upper if upper > 0 else 0.0:.2e}", refresh=False)
            if not bound.size:
                break
            if boxes + 2 > max_boxes or bound.size + min(bound.size, BATCH) > MAX_OPEN:
                stop = "budget" if boxes + 2 > max_boxes else "open boxes"
                break
            take = np.argsort(bound)[::-1][:min(BATCH, (max_boxes - boxes) // 2)]
            rest = np.ones(bound.size, bool)
            rest[take] = False
            p_lo, p_hi, p_split = lo[take], hi[take], split[take]
            if sample_time is not None:  # a torus: halve a long side first (see _longest)
                p_split = _longest(p_hi - p_lo, p_split, COARSE_SIDE / sample_time)
            rows = np.arange(take.size)
            mid = 0.5 * (p_lo[rows, p_split] + p_hi[rows, p_split])
            left_hi, right_lo = p_hi.copy(), p_lo.copy()
            left_hi[rows, p_split] = mid
            right_lo[rows, p_split] = mid
            c_lo, c_hi = np.vstack([p_lo, right_lo]), np.vstack([left_hi, p_hi])
            inside = _in_domain(c_lo, c_hi, symmetric)
            c_lo, c_hi = c_lo[inside], c_hi[inside]
            c_bound, c_value, c_split = enclose(taylor, inverse, c_lo, c_hi,
                                                fused_start or boxes >= COMPILED_FROM,
                                                leaves, sample_time)
            boxes += c_lo.shape[0]
            bar.update(c_lo.shape[0])
            magnitude = c_value.copy()
            magnitude[~np.isfinite(magnitude)] = 0.0
            if magnitude.size and magnitude.max() > best:
                k = int(np.argmax(magnitude))
                centre = 0.5 * (c_lo[k] + c_hi[k])
                maxfev = min(1000 * n, polish_points)
                if magnitude[k] > best * (1 + tol) and polishes < MAX_POLISHES and maxfev > 0:
                    polishes += 1
                    polish_points -= maxfev
                    x, polished = _polish(point, centre, float(np.max(c_hi[k] - c_lo[k])),
                                          maxfev)
                    if polished > magnitude[k]:
                        centre, magnitude[k] = x, polished
                best, best_x = float(magnitude[k]), centre
            lo, hi = np.vstack([lo[rest], c_lo]), np.vstack([hi[rest], c_hi])
            # a child lies in its parent: the parent's bound holds on it too
            c_bound = np.fmin(c_bound, np.concatenate([bound[take], bound[take]])[inside])
            bound = np.concatenate([bound[rest], c_bound])
            split = np.concatenate([split[rest], c_split])
    upper = max(min(upper, ceiling), best)
    converged = upper - best <= tol * upper
    return BranchBoundResult(lower=best, upper=upper, argmax=tuple(float(x) for x in best_x),
                             converged=converged, boxes=boxes, width=width, tail=tail,
                             stop="tol" if converged else stop)
