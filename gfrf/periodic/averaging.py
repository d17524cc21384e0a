"""Averaging method (eqs (53)-(59)) for the ``1/4`` branch.

``x = B cos(theta)``, ``theta = t/2 - phi`` with ``B``, ``phi`` slowly varying.  Averaging
the variational equations (56)-(57) over ``theta`` gives (58)-(59); their equilibrium
``2 phi = 0`` (case 2 of the paper) is the transition curve

    delta = (1/4 - eps/2 + eps B**2/12) / (1 - B**2/8),

on which the periodic orbit is ``x = B cos(t/2)``; ``B = x(0)`` is the API amplitude.
The other equilibrium ``2 phi = pi`` (case 3) is the upper curve (``side="upper"``)

    delta = (1/4 + eps/2 - eps B**2/12) / (1 - B**2/8),

with orbit ``x = B cos(t/2 - pi/2) = B sin(t/2)``: ``x(0) = 0`` and ``B = x(pi)`` is the
amplitude (the upper-side convention of :mod:`~gfrf.periodic.equation`).  Case 3 is
case 2 with ``eps -> -eps``.  The paper applies averaging only near ``delta = 1/4``;
branch ``"0"`` is not covered.

The derivation does not need the Taylor truncation: with ``g = sin`` (eq (3)) the
``theta``-averages of ``cos(theta) sin(B cos theta)`` and ``cos(2 theta) cos(theta)
sin(B cos theta)`` are ``J1(B)`` and ``(J1(B) - J3(B))/2`` (Bessel functions), so the
equilibria are ``2 delta J1(B) - B/4 +/- eps (J1(B) - J3(B)) = 0`` (``equation=3``);
their Taylor expansion to ``O(B**3)`` gives back the eq (4) formulas.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.special import jv

from gfrf.errors import ArgumentError
from gfrf.periodic.equation import parse_branch, parse_side
from gfrf.periodic.fourier import trig_harmonic

__all__ = ["averaged_equations", "averaging_equilibria", "averaging_solution",
           "averaging_transition"]


def _require_quarter(branch: str) -> None:
    if parse_branch(branch) != "1/4":
        raise ArgumentError("the averaging method of eqs (53)-(59) treats only the '1/4' "
                            "branch (x = B cos(t/2 - phi)); branch '0' is not covered")


def averaging_transition(eps: float | np.ndarray, amplitude: float, branch: str = "1/4",
                         side: str = "lower", equation: int = 4) -> float | np.ndarray:
    """``delta`` on the averaging transition curve for ``B = amplitude``.

    Parameters
    ----------
    eps : float or ndarray
        Excitation.
    amplitude : float
        ``B``: ``x(0)`` (lower side) or ``x(pi)`` (upper side).
    branch : {"1/4"}
        Only the ``1/4`` branch is covered.
    side : {"lower", "upper"}
        Case 2 (``2 phi = 0``) or case 3 (``2 phi = pi``) of the paper.
    equation : {4, 3}
        Truncated eq (4) or ``sin(x)`` eq (3) (Bessel-function averages).
    """
    _require_quarter(branch)
    sign = 1.0 if parse_side(side, branch) == "lower" else -1.0
    e = sign * np.asarray(eps, dtype=float)
    B = amplitude
    if equation == 4:
        return (0.25 - e / 2 + e * B * B / 12) / (1 - B * B / 8)
    if equation == 3:
        j1, j3 = jv(1, B), jv(3, B)
        return (B / 4 - e * (j1 - j3)) / (2 * j1)
    raise ArgumentError(f"unknown equation {equation!r}: expected 4 or 3")


def averaging_solution(eps: float, amplitude: float, t: np.ndarray, branch: str = "1/4",
                       side: str = "lower") -> np.ndarray:
    """Averaging orbit ``B cos(t/2)`` (lower side) or ``B sin(t/2)`` (upper side).

    The same for eq (3) and eq (4): first-order averaging gives only the harmonic.

    Parameters
    ----------
    eps : float
        The dimensionless forcing amplitude (first-order averaging's orbit does not depend
        on it).
    amplitude : float
        B, the orbit's amplitude.
    t : numpy.ndarray
        Dimensionless times.
    branch : str, optional
        Must be ``"1/4"``.
    side : str, optional
        ``"lower"`` or ``"upper"``.

    Returns
    -------
    numpy.ndarray
        x(t).
    """
    _require_quarter(branch)
    t = np.asarray(t, dtype=float)
    if parse_side(side, branch) == "upper":
        return amplitude * np.sin(t / 2)
    return amplitude * np.cos(t / 2)


def averaging_equilibria() -> dict[str, sp.Expr]:
    """Cases 2 and 3 regenerated: ``delta`` where (58)-(59) have ``B' = phi' = 0``.

    Returns
    -------
    dict
        ``"case2"`` (``2 phi = 0``) and ``"case3"`` (``2 phi = pi``): the left-hand side
        of the paper's equilibrium condition, ``(58)/B`` with ``phi' = 0`` ((59) with
        ``B' = 0`` holds on both because ``sin(2 phi) = 0``).
    """
    e58 = averaged_equations()[0]
    B, ph, dphi = sp.symbols("B phi dphi")
    out = {}
    for name, phase in (("case2", 0), ("case3", sp.pi / 2)):
        out[name] = sp.expand(sp.cancel(e58.subs({dphi: 0, ph: phase}) / B))
    return out


def averaged_equations() -> tuple[sp.Expr, sp.Expr]:
    """Regenerate (58) and (59) by averaging (56)-(57) over ``theta`` in ``[0, 2 pi]``.

    Returns
    -------
    (expr58, expr59)
        ``B*(phi' + ...)`` and ``B' + ...``, with ``phi'`` and ``B'`` as the symbols
        ``dphi`` and ``dB``; each expression equals zero on the averaged flow.
    """
    th, ph, B, d, e, dphi, dB = sp.symbols("theta phi B delta epsilon dphi dB")
    cos_t = sp.cos(2 * th + 2 * ph)  # t = 2 (theta + phi)
    f = e * B * cos_t * sp.cos(th) - (B * sp.cos(th)) ** 3 / 6 * (d + e * cos_t)
    q = sp.Rational(1, 4)
    eq56 = (d - q) * B * sp.cos(th) ** 2 + B * dphi / 2 + sp.cos(th) * f
    eq57 = (d - q) * B * sp.cos(th) * sp.sin(th) - dB / 2 + sp.sin(th) * f
    return (sp.expand(2 * trig_harmonic(eq56, th)), sp.expand(-2 * trig_harmonic(eq57, th)))
