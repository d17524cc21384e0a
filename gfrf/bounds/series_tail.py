"""Certified bound of the tail sum_{n > N} ||H_n|| a^n of the norm series at an amplitude.

The majorant M_{n,0} >= ||H_n|| (:mod:`gfrf.bounds.majorant`) has nonnegative coefficients,
and its generating function X_0(r) = sum_n M_{n,0} r^n is bounded by any nonnegative
supersolution x' of the fixed-point system at r (``rhs(x', r) <= x'``).  With such a
certificate at an amplitude rho > a, Cauchy's estimate gives M_{n,0} <= x'_0 / rho^n
for every n, so

    sum_{n > N} M_{n,0} a^n  <=  sum_{n = N+1}^{K} M_{n,0} a^n
                                 + x'_0 (a / rho)^{K+1} / (1 - a / rho),

the first K - N terms summed exactly (Arb balls, outward rounding) and the rest by the
geometric series.  K is the first order where the geometric remainder is below 1e-6 of
the sum (at most N + 200).  The supersolution is solved on the rescaled system of
:mod:`gfrf.bounds.radius_scaling` (exact powers of two) and checked in ball arithmetic.

Proof level: ``"interval"`` when the majorant's sups are proven and the supersolution
passes the ball check, ``"float"`` when the sups or the check are double precision,
``"none"`` for an estimated majorant; ``inf`` when the amplitude is not below the
certified radius of the series (the tail is then not known to be finite).

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> from gfrf.bounds.majorant import majorant
>>> maj = majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
>>> bound, proof = series_tail(maj, 0.01, 3)
>>> 0 < bound < 1e-4, proof
(True, 'interval')
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from gfrf.bounds.exact import arb_upper
from gfrf.bounds.fixed_point import certify
from gfrf.bounds.majorant import Majorant, plant_radius
from gfrf.bounds.radius_scaling import scaled_majorant

__all__ = ["series_tail", "MAX_TAIL_TERMS"]

#: Largest number of orders beyond N summed term by term (the rest is geometric).
MAX_TAIL_TERMS = 200

#: The term-by-term sum stops where the geometric remainder is this fraction of it.
_REMAINDER = 1e-6


def _rows(maj: Majorant) -> Iterator[Any]:
    """Arb balls M_{n,0} for n = 0, 1, 2, ... (outward rounding; the series recursion of
    :meth:`Majorant.coefficients` with power-series products as Arb polynomials)."""
    from flint import arb, arb_poly

    idx = {ell: i for i, ell in enumerate(maj.powers)}
    cols: list[list[Any]] = [[arb(0), arb(maj.linear[ell])] for ell in maj.powers]
    yield cols[idx[0]][0]
    yield cols[idx[0]][1]
    n = 1
    while True:
        n += 1
        total = arb(0)
        for t in maj.terms:
            rest = n - t.q
            if t.weight == 0.0 or rest < len(t.y_orders) or (not t.y_orders and rest != 0):
                continue
            acc = arb_poly([1])
            for ell in t.y_orders:
                acc = acc * arb_poly(cols[idx[ell]][:rest + 1])
                acc = arb_poly(acc.coeffs()[:rest + 1])
            coeffs = acc.coeffs()
            total += arb(t.weight) * (coeffs[rest] if rest < len(coeffs) else arb(0))
        for i, ell in enumerate(maj.powers):
            cols[i].append(arb(maj.gains[ell]) * total)
        yield cols[idx[0]][n]


def _supersolution(maj: Majorant, rho: float) -> tuple[float, bool] | None:
    """(x'_0, proven) for a supersolution x' of the fixed-point system at ``rho``."""
    found = scaled_majorant(maj)
    work, shift, alpha = (maj, 0, {ell: 0 for ell in maj.powers}) if found is None else found
    rho_scaled = math.ldexp(rho, -shift)
    x = certify(lambda y, r: work.rhs(y, r), len(work.powers), rho_scaled)
    if x is None:
        return None
    proven = work.proves(x, rho_scaled)
    return math.ldexp(float(x[0]), alpha[0]), proven


def series_tail(maj: Majorant, amplitude: float, order: int) -> tuple[float, str]:
    """Upper bound on sum_{n > order} ||H_n|| amplitude^n, and its proof level.

    Parameters
    ----------
    maj : Majorant
        The model's majorant (:func:`gfrf.bounds.majorant.majorant`).
    amplitude : float
        Input amplitude a >= 0 (for a sum of tones, the sum of their amplitudes).
    order : int
        Truncation order N >= 1 of the series.

    Returns
    -------
    tuple of (float, str)
        The bound (``inf`` when none was found: amplitude not below the certified radius,
        or an infinite majorant) and its proof level (``"interval"``, ``"float"`` or
        ``"none"``).
    """
    if amplitude == 0.0 or not any(t.weight for t in maj.terms):  # H_n = 0 for n >= 2
        return 0.0, maj.proof if maj.finite else "none"
    if not maj.finite:
        return math.inf, "none"
    rad = plant_radius(maj)
    limit = rad.certified_below
    if not amplitude < limit:
        return math.inf, "none"
    best: tuple[float, bool] | None = None
    for rho in _candidates(amplitude, limit):
        sup = _supersolution(maj, rho)
        if sup is None:
            continue
        x0, proven = sup
        bound = _bound(maj, amplitude, order, x0, rho)
        if best is None or bound < best[0]:
            best = (bound, proven)
    if best is None:
        return math.inf, "none"
    bound, proven = best
    if maj.proof == "none":
        return bound, "none"
    level = "interval" if proven and maj.proof == "interval" and maj.exact else "float"
    return bound, level


def _candidates(amplitude: float, limit: float) -> tuple[float, ...]:
    """Amplitudes rho in (amplitude, limit) at which the Cauchy estimate is tried (far
    above the amplitude when the series converges everywhere)."""
    if math.isinf(limit):
        return (amplitude * 2.0 ** 10, amplitude * 2.0 ** 20)
    return tuple(amplitude + f * (limit - amplitude) for f in (0.9, 0.5))


def _bound(maj: Majorant, amplitude: float, order: int, x0: float, rho: float) -> float:
    """The two-part bound of the module docstring, in Arb balls, with K the first order
    (at most ``order + MAX_TAIL_TERMS``) where the geometric remainder falls below
    ``_REMAINDER`` times the partial sum (the bound does not increase with K)."""
    from flint import arb

    a, ratio = arb(amplitude), arb(amplitude) / arb(rho)
    geometric = arb(x0) / (1 - ratio)
    rows = _rows(maj)
    for _ in range(order + 1):
        next(rows)
    total = arb(0)
    for n in range(order + 1, order + MAX_TAIL_TERMS + 1):
        total += next(rows) * a ** n
        remainder = geometric * ratio ** (n + 1)
        if arb_upper(remainder) <= _REMAINDER * arb_upper(total):
            break
    return arb_upper(total + remainder)
