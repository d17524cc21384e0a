"""Energy method (eqs (33)-(52)) for the ``1/4`` branch.

The paper writes (4) as ``x'' + g(x) + f(x, t) = 0`` with ``g = delta (x - x**3/6)`` and
``f = eps cos(t) (x - x**3/6)``, uses energy coordinates ``x = a cos(theta)`` (38) and
the first-order expansion (39) of the velocity, and sets ``theta = t/2 + phi``.
The resonance condition (48) (``phi = 0``) gives the transition curve: with
``s = sqrt(delta)``, ``k = 1/(2 (1 - a**2/16))`` and ``c = (1 - a**2/12)/(1 - a**2/6)``,
(48) is ``s**2 - k s + eps c/4 = 0``, so ``delta = ((k + sqrt(k**2 - eps c))/2)**2``
(the root through ``delta = 1/4`` at ``eps = 0``).  It has no real root once
``eps > k**2/c`` (about 0.25 for small ``a``): the method then gives no curve.
(47)-(48) keep only part of the ``O(eps a**2)`` terms of the ``theta``-average of (46);
``variant="consistent"`` uses the exact average instead.

The method needs ``x g(x) > 0``, i.e. ``delta > 0``: it cannot describe ``delta < 0``
(the inverted pendulum proper), because ``sqrt(delta)`` in (39) is imaginary there.
The periodic orbit is ``x = a(t) cos(theta(t))`` from integrating (50) (eq (52));
``a(0) = x(0)`` is the API amplitude.

The root ``phi = pi/2`` of (47) gives (49), the upper curve (``side="upper"``):
``s**2 - k s - eps c/4 = 0``, i.e. (48) with ``eps -> -eps``; it has a real root for
every ``eps > 0`` and reaches ``delta = 1/4 + eps/2 + O(eps**2)``.  Its system (51) is
(50) with ``eps -> -eps`` started at ``theta = pi/2`` (``x(0) = 0``); because (51) is
autonomous in ``(a, theta)`` and ``pi``-periodic in ``theta``, its orbit through the
turning point ``theta = 0`` (mod ``pi``) at ``t = pi`` is the ``-eps`` lower orbit
shifted by ``pi`` (see :mod:`~gfrf.periodic.equation`); ``a(pi) = x(pi)`` is the
upper-side amplitude.

The method is tied to eq (4) here: (39) expands ``sqrt(V(a) - V(a cos theta))`` for the
quartic potential, and the exact averages of (46) are polynomials in ``a`` only for it;
with ``V = delta (1 - cos x)`` the same steps give Bessel-function series whose first
terms are exactly the eq (4) expressions, so nothing beyond eq (4) is derived.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from gfrf.errors import ArgumentError
from gfrf.periodic.equation import parse_branch, parse_side, upper_side_times
from gfrf.periodic.fourier import trig_harmonic

__all__ = ["energy_cutoff", "energy_formulas", "energy_solution", "energy_transition"]


def _require_quarter(branch: str) -> None:
    if parse_branch(branch) != "1/4":
        raise ArgumentError("the energy method of eqs (33)-(52) treats only the '1/4' branch "
                            "(theta = t/2 + phi, delta > 0); branch '0' is not covered")


def energy_transition(eps: float | np.ndarray, amplitude: float, branch: str = "1/4",
                      variant: str = "paper", side: str = "lower") -> float | np.ndarray:
    """``delta`` on the energy-method transition curve for ``a = amplitude``.

    ``side="lower"`` is (48) (``phi = 0``), ``side="upper"`` is (49) (``phi = pi/2``,
    the same with ``eps -> -eps``).

    Both variants solve ``A s**2 - B s + C eps = 0`` for ``s = sqrt(delta)`` (root
    through ``s = 1/2`` at ``eps = 0``).  ``"paper"`` is (48) multiplied by
    ``sqrt(delta) (1 - a**2/6)``: ``A = (1 - a**2/16)(1 - a**2/6)``, ``B = (1 - a**2/6)/2``,
    ``C = (1 - a**2/16)(1 - a**2/12)/4``.  ``"consistent"`` uses the exact
    ``theta``-average of (46) (see :func:`energy_formulas`):
    ``A = 1 - 11 a**2/48 + a**4/96`` and ``C = 1/4 - a**2/16 + 31 a**4/9216``.
    NaN where there is no real root.

    Parameters
    ----------
    eps : float or numpy.ndarray
        The dimensionless forcing amplitude.
    amplitude : float
        a, the orbit's amplitude.
    branch : str, optional
        Must be ``"1/4"``.
    variant : str, optional
        ``"paper"`` or ``"consistent"``.
    side : str, optional
        ``"lower"`` or ``"upper"``.

    Returns
    -------
    float or numpy.ndarray
        delta (NaN without a real root).
    """
    _require_quarter(branch)
    A, B, C = _quadratic(amplitude, variant)
    sign = 1.0 if parse_side(side, branch) == "lower" else -1.0
    disc = B * B - 4 * A * C * sign * np.asarray(eps, dtype=float)
    with np.errstate(invalid="ignore"):
        s = (B + np.sqrt(disc)) / (2 * A)
    return np.where(disc >= 0, s * s, np.nan)


def _quadratic(amplitude: float | Fraction, variant: str
               ) -> tuple[float | Fraction, float | Fraction, float | Fraction]:
    """``(A, B, C)`` of ``A s**2 - B s + C eps = 0`` (exact for a ``Fraction`` amplitude)."""
    a2 = amplitude * amplitude
    if variant == "paper":
        A = (1 - a2 / 16) * (1 - a2 / 6)
        C = (1 - a2 / 16) * (1 - a2 / 12) / 4
    elif variant == "consistent":
        A = 1 - 11 * a2 / 48 + a2 * a2 / 96
        C = (2304 - 576 * a2 + 31 * a2 * a2) / 9216
    else:
        raise ArgumentError(f"unknown energy variant {variant!r}")
    return A, (1 - a2 / 6) / 2, C


def energy_cutoff(amplitude: float | Fraction, variant: str = "paper") -> float | Fraction:
    """``eps`` beyond which the lower-side curve (48) has no real root, in closed form.

    The discriminant ``B**2 - 4 A C eps`` of :func:`energy_transition` vanishes at
    ``eps = B**2 / (4 A C)``; for ``variant="paper"`` this is
    ``(1 - a**2/6) / (4 (1 - a**2/16)**2 (1 - a**2/12))`` (``1/4`` at ``a = 0``,
    ``47104/186543 = 0.252510...`` at ``a = 1/2``).  A ``Fraction`` amplitude gives the
    exact rational value.  The upper side (49) has a real root for every ``eps > 0``.

    Parameters
    ----------
    amplitude : float or Fraction
        a, with a**2 < 6.
    variant : str, optional
        ``"paper"`` or ``"consistent"``.

    Returns
    -------
    float or Fraction
        The cut-off eps (a Fraction for a Fraction amplitude).

    Raises
    ------
    ArgumentError
        If ``amplitude**2 >= 6`` (outside the well of the quartic potential, where
        ``1 - a**2/6 <= 0``) or for an unknown ``variant``.
    """
    if not 0 <= amplitude * amplitude < 6:
        raise ArgumentError(f"energy method needs 0 <= a < sqrt(6), got a = {amplitude}")
    A, B, C = _quadratic(amplitude, variant)
    return B * B / (4 * A * C)


def energy_solution(eps: float, amplitude: float, t: np.ndarray, delta: float | None = None,
                    branch: str = "1/4", side: str = "lower") -> np.ndarray:
    """Orbit ``x = a cos(theta)`` from integrating (50) (``phi = 0``) or (51) over ``t``.

    Parameters
    ----------
    eps, amplitude : float
        Excitation and ``x(0) = a(0)`` (lower side) or ``x(pi) = a(pi)`` (upper side).
    t : ndarray
        Sorted non-negative times.
    delta : float, optional
        Default: the energy transition value (48) or (49).
    branch : {"1/4"}
        The transition tongue; the energy method covers the 1/4 branch only.
    side : {"lower", "upper"}
        ``phi = 0`` ((48), (50)) or ``phi = pi/2`` ((49), (51)).

    Raises
    ------
    ArgumentError
        If ``delta <= 0`` or (48) has no real root.
    """
    _require_quarter(branch)
    if parse_side(side, branch) == "upper":
        s_times, index = upper_side_times(t)
        return energy_solution(-eps, amplitude, s_times, delta, branch)[index]
    if delta is None:
        delta = float(energy_transition(eps, amplitude))
    if not delta > 0:
        raise ArgumentError(f"energy method needs delta > 0 (x g(x) > 0); got delta={delta} "
                            f"(eq (48) has no real root for eps={eps}, a={amplitude})")
    sd = math.sqrt(delta)

    def rhs(_t: float, y: np.ndarray) -> list[float]:
        a, th = y
        s = 1 - a * a / 16 - a * a * math.cos(2 * th) / 48
        de = a * a / 4 * sd * eps * (1 - a * a * math.cos(th) ** 2 / 6) * math.sin(4 * th) * s
        dth = sd * s * (1 + (1 + 2 * math.cos(2 * th) + math.cos(4 * th)) * eps / 4
                        * (1 - a * a * (math.cos(2 * th) + 1) / 12) / (delta * (1 - a * a / 6)))
        return [de / (delta * a * (1 - a * a / 6)), dth]

    t = np.asarray(t, dtype=float)
    sol = solve_ivp(rhs, (0.0, float(t.max())), [amplitude, 0.0], t_eval=t, method="DOP853",
                    rtol=1e-10, atol=1e-12)
    return sol.y[0] * np.cos(sol.y[1])


def energy_formulas() -> dict[str, sp.Expr]:
    """Regenerate (39), (44) and the averages behind (47) symbolically.

    Returns
    -------
    dict
        ``"39_factor"``: ``sqrt(2(V(a)-V(a cos th)))/(a sin(th) sqrt(delta))`` expanded to
        ``O(a**4)`` (printed: ``1 - a**2/16 - a**2 cos(2 th)/48``); ``"44"``: ``da/dE``;
        ``"47_energy"``: exact ``theta``-average of the first right-hand side of (46);
        ``"47_theta"``: exact ``theta``-average of the second one, multiplied by
        ``sqrt(delta) (1 - a**2/6)`` so that it is a polynomial; ``"46_energy"`` and
        ``"46_theta"``: the right-hand sides of (46) before averaging (same factors),
        from which (50) and (51) follow with ``phi = 0`` and ``phi = pi/2``.
    """
    a, th, ph, d, e, x, c, y = sp.symbols("a theta phi delta epsilon x c y", positive=True)
    V = d * x**2 / 2 - d * x**4 / 24
    ratio2 = sp.cancel((2 * (V.subs(x, a) - V.subs(x, a * c))) / (a**2 * (1 - c**2) * d))
    root = sp.series(sp.sqrt(1 - y), y, 0, 2).removeO().subs(y, 1 - ratio2)
    factor = sp.expand(root.subs(c, sp.cos(th)))
    g = d * (x - x**3 / 6)
    dadE = sp.cancel((g.subs(x, -a) - g.subs(x, a)) / (2 * g.subs(x, -a) * g.subs(x, a)))
    s = 1 - a**2 / 16 - a**2 * sp.cos(2 * th) / 48
    en = a**2 / 4 * e * (1 - a**2 * sp.cos(th) ** 2 / 6) \
        * (sp.sin(4 * th - 2 * ph) + sp.sin(2 * ph)) * s
    tht = s * (d * (1 - a**2 / 6) + (sp.cos(2 * ph) + 2 * sp.cos(2 * th - 2 * ph)
                                     + sp.cos(4 * th - 2 * ph)) * e / 4
               * (1 - a**2 * (sp.cos(2 * th) + 1) / 12))
    return {"39_factor": factor, "44": dadE, "46_energy": sp.sqrt(d) * en, "46_theta": tht,
            "47_energy": sp.sqrt(d) * sp.expand(trig_harmonic(sp.expand(en), th)),
            "47_theta": sp.expand(trig_harmonic(sp.expand(tht), th))}
