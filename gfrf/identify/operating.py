"""Operating points: a NARX model with a constant term, moved to its equilibrium.

Measured data rarely sit at ``y = u = 0``.  :func:`identify <gfrf.identify.fit.identify>`
fits a constant term when the data ask for it and takes the operating input ``u0``
(the mean of u when it is clearly non-zero, else 0); :func:`equilibrium` is the
model's static output ``y0`` at ``u0`` (the real root nearest the measured mean) and
:func:`shift` rewrites ``y[k] = c + sum theta_i m_i(y, u)`` exactly in the deviations
``y - y0``, ``u - u0``: a polynomial without constant, about whose zero equilibrium the
GFRFs and the verdict are taken.

Models here are dicts ``{(output lags, input lags): theta}`` of ``y[k] = sum theta*m``
(the key ``((), ())`` is the constant).

>>> shift({((), ()): 1.0, ((1,), ()): 0.5, ((), (1,)): 1.0}, y0=2.0, u0=0.0)
{((1,), ()): 0.5, ((), (1,)): 1.0}
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from gfrf.errors import ModelError

__all__ = ["equilibrium", "shift", "round_significant", "SIGNIFICANT_DIGITS"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Significant digits of identified coefficients: least squares on another CPU (another
#: BLAS summation order) changes a coefficient by a few ulps; rounded to 10 digits it is
#: the same number unless it lies within those ulps of a rounding boundary.
SIGNIFICANT_DIGITS = 10


def round_significant(value: float, digits: int = SIGNIFICANT_DIGITS) -> float:
    """``value`` rounded to ``digits`` significant decimal digits.

    Parameters
    ----------
    value : float
        The number.
    digits : int, optional
        Significant decimal digits.

    Returns
    -------
    float
        The rounded number.

    Examples
    --------
    >>> round_significant(-0.4995686297675639), round_significant(-0.49956862976756367)
    (-0.4995686298, -0.4995686298)
    """
    return float(f"{value:.{digits}g}")


def equilibrium(theta: dict[Key, float], u0: float, near: float) -> float:
    """The real static output ``y0`` of the model at constant input ``u0`` nearest ``near``.

    Solves ``y0 = sum theta * y0^p * u0^q`` (every lag at its static value).

    Parameters
    ----------
    theta : dict of Key to float
        The coefficients.
    u0 : float
        The constant input.
    near : float
        The output value the chosen equilibrium is nearest to.

    Returns
    -------
    float
        y0.

    Raises
    ------
    ModelError
        No real equilibrium exists at ``u0``.
    """
    degree = max((len(ys) for ys, _ in theta), default=0)
    poly = np.zeros(max(degree, 1) + 1)  # poly[p] multiplies y0**p
    for (ys, us), c in theta.items():
        poly[len(ys)] += c * u0 ** len(us)
    poly[1] -= 1.0
    while poly.size > 1 and poly[-1] == 0.0:
        poly = poly[:-1]
    if poly.size == 1:
        raise ModelError("the fitted model has no equilibrium (its static equation is "
                         "constant)")
    roots = np.roots(poly[::-1])
    scale = float(np.max(np.abs(poly)))
    real = []
    for r in roots:
        if abs(r.imag) <= 1e-7 * (1.0 + abs(r.real)):
            y = float(r.real)
            for _ in range(3):  # Newton polish of the real part
                value = float(np.polyval(poly[::-1], y))
                slope = float(np.polyval(np.polyder(poly[::-1]), y))
                if slope == 0.0:
                    break
                y -= value / slope
            if abs(float(np.polyval(poly[::-1], y))) <= 1e-9 * scale * max(1.0, abs(y)) ** (
                    poly.size - 1):
                real.append(y)
    if not real:
        raise ModelError(f"the fitted model has no real equilibrium at u = {u0:.6g}: no "
                         f"operating point to take the GFRFs about")
    return min(real, key=lambda y: (abs(y - near), y))


def shift(theta: dict[Key, float], y0: float, u0: float) -> dict[Key, float]:
    """The model in the deviations ``y - y0``, ``u - u0`` (exact polynomial expansion).

    ``(y0, u0)`` must be an equilibrium: the constant left over is checked to be
    rounding-small and dropped.

    Parameters
    ----------
    theta : dict of Key to float
        The coefficients in the original variables.
    y0, u0 : float
        The equilibrium.

    Returns
    -------
    dict of Key to float
        The coefficients in the deviations.
    """
    out: dict[Key, float] = {}
    for (ys, us), c in theta.items():
        factors = [("y", lag) for lag in ys] + [("u", lag) for lag in us]
        for keep in itertools.product((False, True), repeat=len(factors)):
            value = c
            new_y: list[int] = []
            new_u: list[int] = []
            for (name, lag), kept in zip(factors, keep, strict=True):
                if kept:
                    (new_y if name == "y" else new_u).append(lag)
                else:
                    value *= y0 if name == "y" else u0
            if value != 0.0:
                key = (tuple(sorted(new_y)), tuple(sorted(new_u)))
                out[key] = out.get(key, 0.0) + value
    constant = out.pop(((), ()), 0.0) - y0
    size = max([abs(y0), abs(u0), 1.0] + [abs(v) for v in theta.values()])
    if abs(constant) > 1e-8 * size ** max(1, max((len(a) + len(b) for a, b in theta),
                                                 default=1)):
        raise ModelError(f"(y0, u0) = ({y0:.6g}, {u0:.6g}) is not an equilibrium of the "
                         f"fitted model (constant {constant:.3g} left)")
    return {k: v for k, v in out.items() if v != 0.0 and math.isfinite(v)}
