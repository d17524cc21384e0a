"""Suprema of |N/D| of a rational function on the imaginary axis or the unit circle.

The sup over real angular frequencies omega (rad/s) of ``|N(j*omega) / D(j*omega)|``
is found exactly, not on a grid: with ``P(omega) = |N(j*omega)|^2`` and
``Q(omega) = |D(j*omega)|^2`` (real polynomials in omega), every interior extremum is a
real root of ``P'Q - PQ'``; the sup is the largest value at those roots, at omega = 0
and in the limit omega -> infinity.  Each root is polished by a bounded scalar search
of ``|N/D|`` to about 1e-13 relative, so the value is correct to about 1e-12 relative
(floating-point evaluation of N/D is the only error).  A pole on the imaginary axis
(|Re p| <= 1e-12 * (1 + |p|) without a cancelling zero) or a numerator of higher
degree gives an infinite sup, reported with its reason.

For a discrete-time function of the backward shift q = exp(-j*omega*T) a 4097-point
grid on [0, pi/T] locates the peak, which is then polished; that result is an
estimate (``exact = False``).

Examples
--------
>>> s = rational_sup([1.0], [1.0, 0.05, 2.45])
>>> abs(s.value - 1 / (0.05 * (2.45 - 0.05**2 / 4) ** 0.5)) < 1e-9 * s.value
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import Polynomial
from scipy.optimize import minimize_scalar

__all__ = ["SupResult", "rational_sup", "discrete_rational_sup"]

_AXIS_TOL = 1e-12


@dataclass(frozen=True)
class SupResult:
    """Result of a sup of |N/D| over real angular frequencies.

    Attributes
    ----------
    value : float
        The sup (``math.inf`` when unbounded).
    omega : float
        An angular frequency (rad/s) where it is attained (``math.inf`` for a limit at
        infinity, the pole's frequency for an imaginary-axis pole).
    exact : bool
        True when found from the stationary-point polynomial (about 1e-12 relative).
    reason : str
        Why the sup is infinite, or empty.
    """

    value: float
    omega: float
    exact: bool = True
    reason: str = ""


def _trim(coefficients: np.ndarray) -> np.ndarray:
    """Drop leading zeros of a highest-power-first coefficient array."""
    c = np.atleast_1d(np.asarray(coefficients, dtype=float))
    nz = np.flatnonzero(c)
    return c[nz[0]:] if nz.size else np.zeros(1)


def _abs_squared(coefficients: np.ndarray) -> Polynomial:
    """|F(j*omega)|^2 as a real polynomial in omega, F given highest power first."""
    low_first = coefficients[::-1].astype(complex)
    f = Polynomial(low_first * (1j ** np.arange(low_first.size)))
    g = Polynomial(np.conj(f.coef))
    return Polynomial((f * g).coef.real)


def rational_sup(num: np.ndarray | list[float], den: np.ndarray | list[float]) -> SupResult:
    """Sup over real omega (rad/s) of |N(j*omega)/D(j*omega)|, exactly.

    Parameters
    ----------
    num, den : array_like
        Real polynomial coefficients in s, highest power first (``control.tf`` order).

    Returns
    -------
    SupResult
    """
    n, d = _trim(num), _trim(den)
    if not d.any():
        raise ZeroDivisionError("denominator polynomial is zero")
    if not n.any():
        return SupResult(0.0, 0.0)
    if n.size > d.size:
        return SupResult(math.inf, math.inf,
                         reason=f"improper: numerator degree {n.size - 1} > denominator "
                                f"degree {d.size - 1}")
    scale = 1.0 + float(np.max(np.abs(np.roots(d)))) if d.size > 1 else 1.0
    n_scale = float(np.max(np.abs(n)))
    for pole in np.roots(d) if d.size > 1 else []:
        cancelled = abs(np.polyval(n, pole)) <= 1e-9 * n_scale * (1 + abs(pole)) ** (n.size - 1)
        if abs(pole.real) <= _AXIS_TOL * (1 + abs(pole)) and not cancelled:
            return SupResult(math.inf, float(abs(pole.imag)),
                             reason=f"pole on the imaginary axis at s = {pole:.6g}")

    def magnitude(w: float) -> float:
        return float(abs(np.polyval(n, 1j * w) / np.polyval(d, 1j * w)))

    p, q = _abs_squared(n), _abs_squared(d)
    stationary = (p.deriv() * q - p * q.deriv()).trim()
    candidates = [0.0]
    if stationary.degree() >= 1:
        for root in stationary.roots():
            if abs(root.imag) <= 1e-6 * (1 + abs(root)) and root.real > 0:
                candidates.append(float(root.real))
    best_w, best = 0.0, magnitude(0.0)
    for w in candidates:
        value, w = _polish(magnitude, w, scale)
        if value > best:
            best, best_w = value, w
    limit = float(abs(n[0] / d[0])) if n.size == d.size else 0.0
    if limit > best:
        return SupResult(limit, math.inf)
    return SupResult(best, best_w)


def _polish(f: object, w: float, scale: float) -> tuple[float, float]:
    """Maximise f near w by a bounded Brent search on a small bracket."""
    width = max(1e-6 * scale, 1e-3 * abs(w))
    lo, hi = max(0.0, w - width), w + width
    res = minimize_scalar(lambda x: -f(x), bounds=(lo, hi), method="bounded",  # type: ignore[operator]
                          options={"xatol": 1e-14 * max(1.0, abs(w))})
    value0 = f(w)  # type: ignore[operator]
    if -res.fun > value0:
        return float(-res.fun), float(res.x)
    return float(value0), w


def discrete_rational_sup(num: np.ndarray | list[float], den: np.ndarray | list[float],
                          sample_time: float) -> SupResult:
    """Sup over omega in [0, pi/T] of |N(q)/D(q)|, q = exp(-j*omega*T) (estimate).

    Parameters
    ----------
    num, den : array_like
        Coefficients of powers of q, *lowest* power first (``[c0, c1, ...]`` means
        c0 + c1 q + ...), as lags appear in a NARX model.
    sample_time : float
        T in seconds.

    Returns
    -------
    SupResult
        ``exact`` is False: grid of 4097 points on [0, pi/T] then bounded polishing.
    """
    n = np.asarray(num, dtype=float)
    d = np.asarray(den, dtype=float)
    nyquist = math.pi / sample_time

    def magnitude(w: float | np.ndarray) -> np.ndarray:
        q = np.exp(-1j * np.asarray(w) * sample_time)
        return np.abs(np.polyval(n[::-1], q) / np.polyval(d[::-1], q))

    grid = np.linspace(0.0, nyquist, 4097)
    with np.errstate(divide="ignore", invalid="ignore"):
        values = magnitude(grid)
    if not np.all(np.isfinite(values)):
        k = int(np.flatnonzero(~np.isfinite(values))[0])
        return SupResult(math.inf, float(grid[k]), exact=False,
                         reason="pole on the unit circle")
    k = int(np.argmax(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
    res = minimize_scalar(lambda x: -float(magnitude(x)), bounds=(lo, hi), method="bounded",
                          options={"xatol": 1e-13 * nyquist})
    if -res.fun > values[k]:
        return SupResult(float(-res.fun), float(res.x), exact=False)
    return SupResult(float(values[k]), float(grid[k]), exact=False)
