"""A many-term estimate of the true radius of the norm series (float, never a proof).

:func:`radius_estimate` estimates the true radius of sum_n ||H_n|| r^n from many terms
of a lower-bound series: L_n = max over a few frequencies w of
|H_n(w, .., w, -w, .., -w)| (all splits into +w and -w), which is <= ||H_n||
(:func:`resonant_lower_bounds`).  Those values are the harmonic coefficients of the
response to a e^{jwt} + b e^{-jwt}, computed to order 24 by harmonic balance in
two-variable power series (cheap at any order, unlike the symbolic kernels).  The
radius is read off log L_n ~ n log(1/R) - (3/2) log n + c (the tail of a square-root
branch point) by least squares on the upper envelope of the upper half of the nonzero
terms (:func:`fit_radius`), and clamped into [r*, radius_upper] (the proven lower bound
of :mod:`gfrf.bounds.majorant` and the proven upper bound of
:func:`gfrf.stability.static.radius_upper`): an estimate, never a proof.  Fed the
exact static series, the same fit recovers the closed-form branch points (tested).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gfrf.model.equation import Model

__all__ = ["RadiusEstimate", "resonant_lower_bounds", "radius_estimate", "fit_radius"]

#: Kernel orders used by the estimate (harmonic balance, float).
ESTIMATE_ORDER = 24


@dataclass(frozen=True)
class RadiusEstimate:
    """The estimate of the true radius and the numbers it was clamped between.

    Attributes
    ----------
    value : float
        The estimate (never above ``upper``, never below ``lower``).
    fitted : float
        The tail fit before clamping.
    lower : float
        Proven lower bound r* it was clamped to.
    upper : float or None
        Proven upper bound it was clamped to.
    terms : int
        Number of nonzero lower bounds L_n used by the fit.
    method : str
    """

    value: float
    fitted: float
    lower: float
    upper: float | None
    terms: int
    method: str


def _atom_factors(model: Model, w: float, n: int) -> dict[int, np.ndarray]:
    """Matrix F[k, l] of the factor of an order-p atom at harmonic m = k - l."""
    orders = {o for t in model.terms for o in (*t.y_orders, *t.u_orders)}
    m = np.subtract.outer(np.arange(n + 1), np.arange(n + 1)).astype(float)
    if model.is_discrete:
        return {p: np.exp(-1j * m * w * model.sample_time * p) for p in orders}  # type: ignore[operator]
    return {p: (1j * m * w) ** p for p in orders}


def _truncated_product(p: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The leading n x n block of the 2-D convolution of two n x n arrays (the product
    of two bivariate series truncated to degree < n in each variable), as one matrix
    product of shifted copies: direct sums, no FFT rounding, no scipy.signal import."""
    n = p.shape[0]
    k = np.arange(n)
    idx = np.subtract.outer(k, k)  # idx[i, a] = i - a
    idx = np.where(idx >= 0, idx, n)  # n: the zero padding
    f_pad = np.vstack([f, np.zeros((1, n), dtype=f.dtype)])
    p_pad = np.hstack([p, np.zeros((n, 1), dtype=p.dtype)])
    shifted = f_pad[idx]  # shifted[i, a, b] = f[i - a, b]
    toeplitz = p_pad[:, idx.T]  # toeplitz[a, b, j] = p[a, j - b]
    return shifted.reshape(n, n * n) @ toeplitz.reshape(n * n, n)


def _harmonic_coefficients(model: Model, w: float, n: int) -> np.ndarray | None:
    """Y[k, l]: coefficient of a^k b^l e^{j (k - l) w t} of the response to
    u = a e^{jwt} + b e^{-jwt}; Y[k, l] = C(k + l, k) H_{k+l}(w x k, -w x l)."""
    fac = _atom_factors(model, w, n)
    a_lin = sum((c * fac[p] for p, c in model.linear_output.items()), np.zeros((n + 1, n + 1)))
    u = np.zeros((n + 1, n + 1), dtype=complex)
    if n >= 1:
        u[1, 0] = u[0, 1] = 1.0
    degree = np.add.outer(np.arange(n + 1), np.arange(n + 1))
    if np.any(np.abs(a_lin[degree <= n]) <= 1e-300):
        return None
    y = np.zeros((n + 1, n + 1), dtype=complex)
    nonlinear = [t for t in model.terms if not t.is_linear_output]
    for order in range(1, n + 1):
        size = order + 1  # entries of degree <= order only
        total = np.zeros((size, size), dtype=complex)
        for t in nonlinear:
            prod = None
            for p, base in [(p, y) for p in t.y_orders] + [(p, u) for p in t.u_orders]:
                f = fac[p][:size, :size] * base[:size, :size]
                prod = f if prod is None else _truncated_product(prod, f)
            with np.errstate(all="ignore"):
                total += t.coefficient * prod
        mask = degree[:size, :size] == order
        with np.errstate(all="ignore"):
            y[:size, :size][mask] = -total[mask] / a_lin[:size, :size][mask]
        if not np.all(np.isfinite(y[:size, :size][mask])):
            return None  # A(j m w) = 0 (a pole on the axis) or overflow: no value at w
    return y


def _frequencies(model: Model) -> list[float]:
    """Resonances of the linear part (peaks, |Im p|, |p|; angles for NARX) and their
    halves and thirds (rad/s)."""
    from gfrf.bounds.local_search import frequencies as resonances
    from gfrf.kernels.poles import linear_poles

    base, _ = resonances(model, "float")
    poles = linear_poles(model)
    found = set(base) | {float(abs(p.imag)) for p in poles}
    if not model.is_discrete:
        found |= {float(abs(p)) for p in poles}
    out = {0.0}
    for f in found:
        if math.isfinite(f):
            for k in (1, 2, 3):
                out.add(round(f / k, 12))
    return sorted(out)


def resonant_lower_bounds(model: Model, n_max: int = ESTIMATE_ORDER) -> np.ndarray:
    """L_n <= ||H_n||: max of |H_n(w, .., w, -w, .., -w)| over splits and frequencies.

    Parameters
    ----------
    model : Model
    n_max : int
        Highest order.

    Returns
    -------
    numpy.ndarray
        L_0..L_{n_max} (L_0 = 0), float values (~1e-13 relative).
    """
    from scipy.special import comb

    best = np.zeros(n_max + 1)
    degree = np.add.outer(np.arange(n_max + 1), np.arange(n_max + 1))
    k_idx = np.arange(n_max + 1)[:, None] * np.ones(n_max + 1)
    weights = comb(degree, k_idx)
    for w in _frequencies(model):
        y = _harmonic_coefficients(model, w, n_max)
        if y is None:
            continue
        values = np.abs(y) / np.where(weights > 0, weights, 1.0)
        for n in range(1, n_max + 1):
            v = values[degree == n]
            v = v[np.isfinite(v)]
            if v.size:
                best[n] = max(best[n], float(np.max(v)))
    return best


#: Exponent alpha of the tail L_n ~ C R^-n n^alpha assumed by the fit: a square-root
#: branch point (a fold, the generic singularity of an algebraic map) gives -3/2.
TAIL_EXPONENT = -1.5


def fit_radius(values: np.ndarray | list[float]) -> tuple[float, int, int, int]:
    """Radius R of the tail fit log L_n = n log(1/R) + alpha log n + c, alpha = -3/2.

    The fit uses the upper half of the nonzero terms; points more than 0.02 below the
    fit (troughs of an oscillating sequence: complex-conjugate singularities, families
    of resonances taking turns) are dropped and the fit repeated on the upper envelope,
    keeping at least three points.

    Parameters
    ----------
    values : array_like
        L_0, L_1, ..., L_N (nonnegative; zeros are skipped).

    Returns
    -------
    tuple
        (R, points used, first order, last order); R is nan with fewer than four
        nonzero terms.
    """
    values = np.asarray(values, dtype=float)
    ns = [n for n in range(1, values.size) if values[n] > 0 and math.isfinite(values[n])]
    if len(ns) < 4:
        return math.nan, 0, 0, 0
    tail = ns[len(ns) // 2 - 1:]
    full = np.array(tail, dtype=float)
    target = np.log(values[tail]) - TAIL_EXPONENT * np.log(full)
    keep = list(range(len(tail)))
    coef = np.zeros(2)
    for _ in range(len(tail)):
        design = np.column_stack([full[keep], np.ones(len(keep))])
        coef, *_ = np.linalg.lstsq(design, target[keep], rcond=None)
        fit = coef[0] * full + coef[1]
        upper = [i for i in range(len(tail)) if target[i] >= fit[i] - 0.02]
        if upper == keep or len(upper) < 3:
            break
        keep = upper
    return float(math.exp(-coef[0])), len(keep), tail[0], tail[-1]


def radius_estimate(model: Model, lower: float, upper: float | None,
                    n_max: int = ESTIMATE_ORDER) -> RadiusEstimate | None:
    """Estimate of the true radius, clamped into [lower, upper].

    Parameters
    ----------
    model : Model
    lower : float
        The proven lower bound r*.
    upper : float or None
        A proven upper bound (:func:`radius_upper`), if any.
    n_max : int

    Returns
    -------
    RadiusEstimate or None
        None when fewer than four nonzero L_n exist (a polynomial map: nothing to fit).
    """
    values = resonant_lower_bounds(model, n_max)
    fitted, used, first, last = fit_radius(values)
    if not math.isfinite(fitted):
        return None
    value = fitted
    if upper is not None:
        value = min(value, upper)
    value = max(value, lower)
    return RadiusEstimate(value, fitted, lower, upper, used,
                          f"least-squares fit of log L_n = n log(1/R) - 1.5 log n + c to the "
                          f"upper envelope of orders {first}..{last}, L_n = max "
                          "|H_n(w,..,w,-w,..,-w)| over resonance frequencies (a lower bound "
                          "of ||H_n||)")
