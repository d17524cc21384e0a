"""The radius of convergence of a positive polynomial fixed-point system x = step(x, r).

The generic solver behind r* (:mod:`gfrf.bounds.majorant` explains the system): a
certificate ``step(x', r) <= x'`` for the solution x' at a slightly larger r proves
convergence at r (:func:`certify`); :func:`radius` brackets the branch point, placed by
Newton on the fold itself (:func:`_fold`), with bisection as the fallback.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Radius", "certify", "radius"]


@dataclass(frozen=True)
class Radius:
    """Radius of convergence r* of a positive fixed-point system.

    Attributes
    ----------
    value : float
        r* (``inf`` when the system is linear in x, 0 when some entry is infinite).
    certified_below : float
        An amplitude at which convergence is certified (a supersolution exists);
        within ``rel_tol`` of :func:`radius` (default 1e-10) relative of ``value``.
    solution : numpy.ndarray or None
        The fixed point at ``certified_below``.
    proof : str
        ``"interval"`` when convergence at ``certified_below`` was re-checked in ball
        arithmetic (:meth:`Majorant.proves`), else ``"float"``.
    """

    value: float
    certified_below: float
    solution: np.ndarray | None = None
    proof: str = "float"


_MARGIN = 1e-9
"""Relative step of :func:`certify`: it solves the system at r (1 + _MARGIN)."""


def certify(step: Callable[[np.ndarray, float], np.ndarray], dim: int, r: float,
            start: np.ndarray | None = None) -> np.ndarray | None:
    """A nonnegative supersolution of ``x = step(x, r)``, or None if none was found.

    Newton's method from ``start`` (or 0) solves x = step(x, r') at r' = r (1 + 1e-9).
    A nonnegative solution x' satisfies step(x', r) <= step(x', r') = x' (monotone in
    r), so the monotone iteration from 0 at amplitude r stays below x' and converges:
    that is the certificate, checked componentwise up to 1e-12 relative rounding.

    Parameters
    ----------
    step : callable
        ``step(x, r)``, nonnegative and monotone in x and r.
    dim : int
        Size of x.
    r : float
        The amplitude.
    start : numpy.ndarray, optional
        Initial guess of Newton's method; default zero.

    Returns
    -------
    numpy.ndarray or None
        The supersolution x', or None.
    """
    r_up = r * (1 + _MARGIN)
    x = np.zeros(dim) if start is None else start.copy()
    for _ in range(100):
        f = step(x, r_up) - x
        if not np.all(np.isfinite(f)):
            return None
        jac = np.empty((dim, dim))
        # finite-difference step relative to the solution's own scale (it may be ~1e-5)
        scale = max(float(np.max(np.abs(x))), float(np.max(np.abs(f))), 1e-300)
        for i in range(dim):
            h = 1e-7 * max(abs(x[i]), scale)
            e = x.copy()
            e[i] += h
            jac[:, i] = (step(e, r_up) - e - f) / h
        try:
            dx = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            return None
        x = x + dx
        if np.any(x < -1e-12 * (1 + np.max(np.abs(x)))) or not np.all(np.isfinite(x)):
            return None
        if np.max(np.abs(dx)) <= 1e-15 * (1 + np.max(np.abs(x))):
            break
    x = np.maximum(x, 0.0)
    residual = np.abs(step(x, r_up) - x)
    if np.all(residual <= 1e-12 * (x + 1e-300)) and np.all(step(x, r) <= x * (1 + 1e-12)):
        return x
    return None


def _fold_residual(step: Callable[[np.ndarray, float], np.ndarray], dim: int,
                   z: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Residual of the fold system in z = (x, v, r).

    x - step(x, r) = 0, (I - J) v = 0 with J = d step / dx (J v by a central difference)
    and c . v = 1.
    """
    x, v, r = z[:dim], z[dim:2 * dim], float(z[-1])
    h = 1e-5 * max(float(np.max(np.abs(x))), 1e-300) / max(float(np.max(np.abs(v))), 1e-300)
    jv = (step(x + h * v, r) - step(x - h * v, r)) / (2 * h)
    return np.concatenate([x - step(x, r), v - jv, [float(c @ v) - 1.0]])


def _fold(step: Callable[[np.ndarray, float], np.ndarray], dim: int, r0: float,
          x0: np.ndarray) -> tuple[float, np.ndarray] | None:
    """Branch point (r*, x*) of ``x = step(x, r)`` by Newton from a solution at r0 < r*.

    Solves x = step(x, r) together with (I - J(x, r)) v = 0, J = d step / dx, v the
    Perron vector (start: the Perron vector of J(x0, r0)).  Returns None when Newton
    does not converge to a nonnegative x with a nonnegative v.
    """
    jac = np.empty((dim, dim))
    f0 = step(x0, r0)
    for i in range(dim):
        h = 1e-7 * (abs(x0[i]) + float(np.max(np.abs(x0))) + 1e-300)
        e = x0.copy()
        e[i] += h
        jac[:, i] = (step(e, r0) - f0) / h
    values, vectors = np.linalg.eig(jac)
    if not np.all(np.isfinite(values)):
        return None
    v = np.abs(np.real(vectors[:, int(np.argmax(np.real(values)))]))
    v /= float(np.linalg.norm(v))
    z = np.concatenate([x0, v, [r0]])
    n = 2 * dim + 1
    for _ in range(50):
        f = _fold_residual(step, dim, z, v)
        if not np.all(np.isfinite(f)):
            return None
        jz = np.empty((n, n))
        scale = (float(np.max(np.abs(z[:dim]))), 1.0, 0.0)
        for i in range(n):
            h = 1e-7 * (abs(z[i]) + scale[min(i // dim, 2)] + 1e-300)
            e = z.copy()
            e[i] += h
            jz[:, i] = (_fold_residual(step, dim, e, v) - f) / h
        try:
            dz = np.linalg.solve(jz, -f)
        except np.linalg.LinAlgError:
            return None
        for _ in range(30):  # halve steps that leave r > 0, x >= 0
            if np.all(np.isfinite(dz)) and z[-1] + dz[-1] > 0 and np.all(z[:dim] + dz[:dim] >= 0):
                break
            dz = 0.5 * dz
        else:
            return None
        z = z + dz
        if abs(dz[-1]) <= 1e-13 * z[-1]:
            x, v_end = z[:dim], z[dim:2 * dim]
            tiny = 1e-9 * float(np.max(np.abs(z[:2 * dim])))
            if np.any(x < -tiny) or np.any(v_end < -tiny):
                return None
            return float(z[-1]), np.maximum(x, 0.0)
    return None


def _fold_bracket(step: Callable[[np.ndarray, float], np.ndarray], dim: int, lo: float,
                  x_lo: np.ndarray, hi: float, rel_tol: float
                  ) -> tuple[float, np.ndarray, float]:
    """The bisection bracket (lo, x_lo, hi) narrowed around the branch point.

    The branch point r_b from :func:`_fold` predicts where :func:`certify` stops
    succeeding, r_b / (1 + 1e-9).  Each end is then decided exactly as the bisection
    decides it: a certificate at 0.8 rel_tol below the prediction (else 10 and 100
    times as far) moves ``lo``, a failure at 0.1 rel_tol above it (else 10, 100, 1000
    times as far) moves ``hi``.  When both first tries succeed the bracket is already
    narrower than ``rel_tol``; otherwise the bisection finishes it.
    """
    fold = _fold(step, dim, lo, x_lo)
    if fold is None:
        return lo, x_lo, hi
    edge = fold[0] / (1 + _MARGIN)
    for k in range(3):
        r = edge * (1 - 0.8 * rel_tol * 10.0 ** k)
        if not lo < r < hi:
            break
        x = certify(step, dim, r, x_lo)
        if x is not None:
            lo, x_lo = r, x
            break
        hi = r
    for k in range(4):
        r = edge * (1 + 0.1 * rel_tol * 10.0 ** k)
        if not lo < r < hi:
            break
        x = certify(step, dim, r, x_lo)
        if x is None:
            hi = r
            break
        lo, x_lo = r, x
    return lo, x_lo, hi


def _entire(step: Callable[[np.ndarray, float], np.ndarray], dim: int) -> bool:
    """Whether the least solution of x = step(x, r) is a polynomial in r (r* = inf).

    Decided exactly from the structure of a polynomial with nonnegative coefficients:
    either nothing forces x (step(0, 1) = 0, so x = 0 for every r), or step does not
    depend on x at all (the same floats at x = 0 and at x = 1e100: an x-dependent
    monomial with a positive coefficient would change them).
    """
    zero = step(np.zeros(dim), 1.0)
    if not np.any(zero):
        return True
    with np.errstate(over="ignore", invalid="ignore"):
        big = step(np.full(dim, 1e100), 1.0)
    return bool(np.array_equal(zero, big))


def radius(step: Callable[[np.ndarray, float], np.ndarray], dim: int,
           rel_tol: float = 1e-10, fold: bool = True) -> Radius:
    """Radius of convergence in r of the positive system ``x = step(x, r)``.

    Parameters
    ----------
    step : callable
        ``step(x, r)``, nonnegative coefficients, monotone in x and r, step(0, 0) = 0.
    dim : int
        Length of x.
    rel_tol : float
        Relative width of the final bracket.
    fold : bool
        Locate the branch point directly (Newton on x = step(x, r) with
        det(I - d step/dx) = 0) and check the bracket around it; bisection is the
        fallback when that fails.  False: bisection only.

    Returns
    -------
    Radius
    """
    probe = step(np.ones(dim), 1.0)
    if not np.all(np.isfinite(probe)):
        return Radius(0.0, 0.0, None)
    if _entire(step, dim):
        return Radius(math.inf, math.inf, None)
    lo, x_lo = 0.0, np.zeros(dim)
    hi = 1.0
    while True:  # no cap: a finite radius is found in any magnitude
        x = certify(step, dim, hi, x_lo)
        if x is None:
            break
        lo, x_lo = hi, x
        hi *= 4.0
        if not math.isfinite(hi):  # certified beyond the float range
            return Radius(math.inf, lo, x_lo)
    while lo == 0.0:
        x = certify(step, dim, hi / 4.0)
        if x is None:
            hi /= 4.0
            if hi < 1e-300:
                return Radius(0.0, 0.0, None)
        else:
            lo, x_lo = hi / 4.0, x
    if fold and hi - lo > rel_tol * hi:
        lo, x_lo, hi = _fold_bracket(step, dim, lo, x_lo, hi, rel_tol)
    while hi - lo > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        x = certify(step, dim, mid, x_lo)
        if x is None:
            hi = mid
        else:
            lo, x_lo = mid, x
    return Radius(hi, lo, x_lo)
