"""The radius r* of a majorant computed on an O(1) problem and scaled back exactly.

Under y -> s y the cubic coefficient of a model scales as c3 -> c3 s^2 and the radius
of its norm series as r* -> r* / s.  The fixed-point system of
:mod:`gfrf.bounds.majorant`,

    X_l = r v_l + K_l sum_terms w_t r^q prod_i X_{l_i},

is solved numerically with absolute floors and finite-difference steps that only work
near magnitude one: a coefficient of 5e27 put r* ~ 5e-16 below them and the radius came
out 0.  :func:`scaled_majorant` substitutes X_l = alpha_l Y_l, r = beta rho with powers of
two alpha_l = beta 2^{e_l} (2^{e_l} <= v_l < 2^{e_l + 1}) and beta chosen so that the
largest nonlinear coefficient of the rho-system lies near 1:

    Y_l = rho v_l / 2^{e_l} + (K_l / alpha_l) sum_t (w_t beta^q prod_i alpha_{l_i}) rho^q prod Y.

Every new coefficient is an old one times a power of two, so it is exact in binary
floating point (checked: no overflow, no subnormal); the rho-system is the same real
system, a ball-arithmetic certificate rhs'(Y, rho) <= Y is a certificate for
rhs(alpha Y, beta rho) <= alpha Y, and r* = beta rho* exactly.  beta is picked from the
binary exponents of the coefficients by integer arithmetic, so a coefficient scaled by
4^k gives bitwise the same rho-system and r* exactly 2^-k times the old one.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> from gfrf.bounds.majorant import majorant
>>> a = scaled_plant_radius(majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")))
>>> c3 = 2 ** 79  # 0.5 * 4**40, written out exactly (proofs use the coefficients as written)
>>> b = scaled_plant_radius(majorant(parse_model(f"D(y,2) + 0.2*D(y) + y + {c3}*y**3 = u")))
>>> a.value == b.value * 2.0 ** 40, b.proof
(True, 'interval')
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from gfrf.bounds.fixed_point import Radius, radius

__all__ = ["scaled_majorant", "scaled_plant_radius", "amplitude_shift"]

_TINY = 2.0 ** -1000
"""Smallest magnitude a scaled coefficient may have (far above the subnormals)."""


def _exponent(x: float) -> int:
    """e with 2^e <= x < 2^(e + 1), for finite x > 0."""
    return math.frexp(x)[1] - 1


def _exact(value: float, exponent: int) -> float | None:
    """value * 2^exponent when that is exact (no overflow, no subnormal), else None."""
    if value == 0.0:
        return 0.0
    out = math.ldexp(value, exponent)
    if not math.isfinite(out) or abs(out) < _TINY or math.ldexp(out, -exponent) != value:
        return None
    return out


def scaled_majorant(maj: Any) -> tuple[Any, int, dict[int, int]] | None:
    """The rho-system of ``maj`` (module docstring) with the exponents of beta and alpha_l.

    Parameters
    ----------
    maj : gfrf.bounds.majorant.Majorant
        A finite majorant (this module does not import it: :mod:`.majorant` imports this).

    Returns
    -------
    tuple or None
        ``(scaled, b, a)`` with beta = 2^b and alpha_l = 2^a[l]; None when the majorant is
        not finite, has a zero linear sup, no nonlinear term, or when some scaled
        coefficient would leave the exact float range (then the caller keeps ``maj``).
    """
    if not maj.finite or any(maj.linear[ell] <= 0.0 for ell in maj.powers):
        return None
    ev = {ell: _exponent(maj.linear[ell]) for ell in maj.powers}
    gain_exp = {ell: _exponent(g) for ell, g in maj.gains.items() if g > 0.0}
    if not gain_exp:
        return None
    shift = None  # the largest -floor(c_t exponent / (d - 1)) keeps every c_t beta^(d-1) <~ 1
    for t in maj.terms:
        degree = t.q + len(t.y_orders)
        if t.weight == 0.0 or degree < 2:
            continue
        # exponent of max_l K_l w_t prod 2^{e_{l_i}} / 2^{e_l}, exactly in integers
        c = max(g + _exponent(t.weight) + sum(ev[i] for i in t.y_orders) - ev[ell]
                for ell, g in gain_exp.items())
        b_t = -math.floor(c / (degree - 1))
        shift = b_t if shift is None else min(shift, b_t)
    if shift is None:
        return None
    alpha = {ell: shift + ev[ell] for ell in maj.powers}
    linear = {ell: _exact(maj.linear[ell], -ev[ell]) for ell in maj.powers}
    gains = {ell: _exact(g, -alpha[ell]) for ell, g in maj.gains.items()}
    terms = []
    for t in maj.terms:
        w = _exact(t.weight, shift * t.q + sum(alpha[i] for i in t.y_orders))
        if w is None:
            return None
        terms.append(dataclasses.replace(t, weight=w))
    if any(v is None for v in (*linear.values(), *gains.values())):
        return None
    scaled = dataclasses.replace(maj, linear=linear, gains=gains, terms=tuple(terms))
    return scaled, shift, alpha


def scaled_plant_radius(maj: Any) -> Radius:
    """r* of the plant majorant, computed on the rho-system and scaled back exactly.

    ``proof = "interval"`` when the sups are proven and the rho-system's supersolution
    passes the ball check (``Majorant.proves``, the same real inequality as for
    ``maj``), ``"none"`` for an estimated majorant, else ``"float"``.  Without a usable
    scaling (:func:`scaled_majorant` None) the radius is computed on ``maj`` itself.

    Parameters
    ----------
    maj : Majorant
        The plant's majorant.

    Returns
    -------
    Radius
        r* and the amplitude certified below it, in the original units.
    """
    found = scaled_majorant(maj)
    if found is None:
        work, shift, alpha = maj, 0, {ell: 0 for ell in maj.powers}
    else:
        work, shift, alpha = found
    rad = radius(lambda x, r: work.rhs(x, r), len(work.powers))
    if maj.proof == "none":
        proof = "none"
    elif (maj.proof == "interval" and maj.exact and rad.solution is not None
          and 0 < rad.certified_below < math.inf
          and work.proves(rad.solution, rad.certified_below)):
        proof = "interval"
    else:
        proof = "float"
    solution = None
    if rad.solution is not None:
        solution = np.array([math.ldexp(float(y), alpha[ell])
                             for y, ell in zip(rad.solution, work.powers, strict=True)])
    return Radius(math.ldexp(rad.value, shift), math.ldexp(rad.certified_below, shift),
                  solution, proof)


def amplitude_shift(maj: Any) -> int:
    """b of beta = 2^b, the amplitude unit in which ``maj``'s problem is O(1) (0 when
    :func:`scaled_majorant` finds no scaling): the shift for
    :func:`gfrf.model.scaling.amplitude_scaled` and
    :func:`gfrf.stability.static.radius_upper`.

    Parameters
    ----------
    maj : Majorant
        The plant's majorant.

    Returns
    -------
    int
        The exponent b.
    """
    found = scaled_majorant(maj)
    return 0 if found is None else found[1]
