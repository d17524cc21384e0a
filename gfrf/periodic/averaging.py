"""Averaging method (eqs (53)-(59)) for the ``1/4`` branch.

``x = B cos(theta)``, ``theta = t/2 - phi`` with ``B``, ``phi`` slowly varying.  Averaging
the variational equations (56)-(57) over ``theta`` gives (58)-(59); their equilibrium
``2 phi = 0`` (case 2 of the paper) is the transition curve

    delta = (1/4 - eps/2 + eps B**2/12) / (1 - B**2/8),

on which the periodic orbit is ``x = B cos(t/2)``; ``B = x(0)`` is the API amplitude.
The paper applies averaging only near ``delta = 1/4``; branch ``"0"`` is not covered.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.periodic.equation import parse_branch
from gfrf.periodic.fourier import trig_harmonic

__all__ = ["averaged_equations", "averaging_solution", "averaging_transition"]


def _require_quarter(branch: str) -> None:
    if parse_branch(branch) != "1/4":
        raise ArgumentError("the averaging method of eqs (53)-(59) treats only the '1/4' "
                            "branch (x = B cos(t/2 - phi)); branch '0' is not covered")


def averaging_transition(eps: float | np.ndarray, amplitude: float,
                         branch: str = "1/4") -> float | np.ndarray:
    """``delta`` on the averaging transition curve (case ``2 phi = 0``) for ``B = amplitude``."""
    _require_quarter(branch)
    B2 = amplitude**2
    return (0.25 - np.asarray(eps) / 2 + np.asarray(eps) * B2 / 12) / (1 - B2 / 8)


def averaging_solution(eps: float, amplitude: float, t: np.ndarray,
                       branch: str = "1/4") -> np.ndarray:
    """Averaging periodic orbit ``x(t) = B cos(t/2)`` with ``B = amplitude``."""
    _require_quarter(branch)
    return amplitude * np.cos(np.asarray(t, dtype=float) / 2)


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
