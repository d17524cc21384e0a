"""Linear ground truth: Floquet multipliers and exact (Mathieu) transition curves.

The linearisation of eq (3)/(4) about the upright position is the Mathieu equation
``x'' + (delta + eps*cos(t)) x = 0`` (time ``t`` dimensionless, excitation period
``2*pi``).  Substituting ``t = 2*z + pi`` turns it into scipy's canonical form::

    y''(z) + (a - 2*q*cos(2*z)) y(z) = 0,   a = 4*delta,  q = 2*eps >= 0,

because ``cos(t) = cos(2z + pi) = -cos(2z)``.  Hence the transition curves are
``delta = a_r(2*eps)/4`` and ``delta = b_r(2*eps)/4`` with scipy's
``mathieu_a``/``mathieu_b``.  The two curves of the paper are

* branch ``"0"``: ``delta = a_0(2 eps)/4 = -eps**2/2 + ...`` (2*pi-periodic, ``ce_0``);
* branch ``"1/4"``: ``delta = b_1(2 eps)/4 = 1/4 - eps/2 - eps**2/8 + ...``
  (4*pi-periodic, ``se_1`` in ``z``, i.e. even in ``t`` like ``cos(t/2)``);

the upper ``1/4`` curve ``a_1(2 eps)/4`` bounds the other side of that tongue.
Independently, a transition curve is where the monodromy matrix ``M`` of one period
``2*pi`` has ``trace(M) = +2`` (branch 0) or ``-2`` (branch 1/4).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b, mathieu_cem, mathieu_sem

from gfrf.periodic.equation import parse_branch

__all__ = [
    "floquet_multipliers",
    "linear_orbit_shape",
    "mathieu_transition",
    "monodromy",
    "monodromy_transition",
    "quarter_tongue_zero",
    "upper_quarter_transition",
]


def mathieu_transition(eps: float | np.ndarray, branch: str = "0") -> np.ndarray:
    """Exact linear transition value(s) of ``delta`` on ``branch`` from Mathieu values.

    Parameters
    ----------
    eps : float or array
        Excitation amplitude(s) ``eps >= 0``.
    branch : {"0", "1/4"}
        ``"0"``: ``a_0(2 eps)/4``; ``"1/4"``: ``b_1(2 eps)/4`` (the lower curve).

    Returns
    -------
    ndarray
        ``delta`` on the curve, same shape as ``eps``.
    """
    q = 2.0 * np.asarray(eps, dtype=float)
    if parse_branch(branch) == "0":
        return mathieu_a(0, q) / 4.0
    return mathieu_b(1, q) / 4.0


def upper_quarter_transition(eps: float | np.ndarray) -> np.ndarray:
    """Upper boundary ``a_1(2 eps)/4 = 1/4 + eps/2 - ...`` of the ``1/4`` tongue (``sin(t/2)``).

    Parameters
    ----------
    eps : float or numpy.ndarray
        The dimensionless forcing amplitude.

    Returns
    -------
    numpy.ndarray
        delta on the curve.
    """
    return mathieu_a(1, 2.0 * np.asarray(eps, dtype=float)) / 4.0


def monodromy(eps: float, delta: float, rtol: float = 1e-12) -> np.ndarray:
    """Monodromy matrix over one period ``2*pi`` of ``x'' + (delta + eps cos t) x = 0``.

    Columns are the states ``(x, x')`` at ``t = 2*pi`` of the solutions starting at
    ``(1, 0)`` and ``(0, 1)``.

    Parameters
    ----------
    eps, delta : float
        The parameters of the Mathieu equation.
    rtol : float, optional
        DOP853's relative tolerance (absolute: ``rtol * 1e-2``).

    Returns
    -------
    numpy.ndarray
        The 2 x 2 matrix.
    """
    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        k = delta + eps * np.cos(t)
        return np.array([y[1], -k * y[0], y[3], -k * y[2]])

    sol = solve_ivp(rhs, (0.0, 2 * np.pi), [1.0, 0.0, 0.0, 1.0], method="DOP853",
                    rtol=rtol, atol=rtol * 1e-2)
    y = sol.y[:, -1]
    return np.array([[y[0], y[2]], [y[1], y[3]]])


def floquet_multipliers(eps: float, delta: float) -> np.ndarray:
    """Floquet multipliers (eigenvalues of the monodromy matrix; product 1).

    Parameters
    ----------
    eps, delta : float
        The parameters of the Mathieu equation.

    Returns
    -------
    numpy.ndarray
        The two multipliers (complex).
    """
    return np.linalg.eigvals(monodromy(eps, delta))


def monodromy_transition(eps: float, branch: str = "0", xtol: float = 1e-12) -> float:
    """Naive baseline: ``delta`` where ``trace(M) = +-2``, by Brent's method on ``delta``.

    The bracket is ``[-0.5 - 2 eps**2, mid]`` (branch 0) or ``[mid, 1/4]`` (branch 1/4)
    with ``mid`` halfway between the leading-order curves ``-eps**2/2`` and
    ``1/4 - eps/2``; valid for ``0 < eps <= 0.6``.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude, 0 < eps <= 0.6.
    branch : str, optional
        ``"0"`` or ``"1/4"``.
    xtol : float, optional
        Brent's absolute tolerance on delta.

    Returns
    -------
    float
        delta on the transition curve.
    """
    b = parse_branch(branch)
    mid = 0.5 * (-eps**2 / 2 + 0.25 - eps / 2 - eps**2 / 8)
    if b == "0":
        return brentq(lambda d: np.trace(monodromy(eps, d)) - 2.0, -0.5 - 2 * eps**2, mid,
                      xtol=xtol)
    return brentq(lambda d: np.trace(monodromy(eps, d)) + 2.0, mid, 0.25, xtol=xtol)


def quarter_tongue_zero(xtol: float = 1e-13) -> float:
    """``eps`` where the lower ``1/4`` curve crosses ``delta = 0`` (tongue reaches ``delta < 0``).

    Brent's method on ``eps`` of ``trace(M(eps, 0)) + 2`` (monodromy integrated with
    ``rtol = 1e-12``) over ``[0.3, 0.6]``: below the root ``delta = 0`` lies between the
    branch-0 and the lower ``1/4`` curve (``|trace| < 2``), above it inside the tongue
    (``trace < -2``); the upper curve ``a_1(2 eps)/4`` stays above ``1/4``, so the root is
    unique.  Equals ``q/2`` at the root ``q`` of scipy's ``mathieu_b(1, q)``; the
    physical inverted pendulum (``delta = -g/(L omega**2) < 0``) has ``4 pi``-periodic
    orbits of small amplitude only for ``eps`` beyond this value.

    Parameters
    ----------
    xtol : float, optional
        Brent's absolute tolerance on eps.

    Returns
    -------
    float
        The root eps.
    """
    return float(brentq(lambda e: np.trace(monodromy(e, 0.0)) + 2.0, 0.3, 0.6, xtol=xtol))


def linear_orbit_shape(eps: float, branch: str, t: np.ndarray) -> np.ndarray:
    """Linear periodic solution on ``branch`` normalised to ``x(0) = 1``, ``x'(0) = 0``.

    Uses scipy's Mathieu functions at ``z = t/2 + pi/2`` (``q = 2 eps``; scipy takes
    degrees): ``ce_0`` for branch 0, ``se_1`` for branch 1/4.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude.
    branch : str
        ``"0"`` or ``"1/4"``.
    t : numpy.ndarray
        Dimensionless times.

    Returns
    -------
    numpy.ndarray
        x(t).
    """
    z_deg = np.degrees(np.asarray(t, dtype=float) / 2 + np.pi / 2)
    q = 2.0 * eps
    if parse_branch(branch) == "0":
        return mathieu_cem(0, q, z_deg)[0] / mathieu_cem(0, q, 90.0)[0]
    return mathieu_sem(1, q, z_deg)[0] / mathieu_sem(1, q, 90.0)[0]
