"""Suprema of |N/D| of a rational function on the imaginary axis or the unit circle.

The sup over real angular frequencies omega (rad/s) of ``|N(j*omega) / D(j*omega)|``
is proven, not estimated: on the exact rational values of the float coefficients,
common roots of N and D are cancelled (polynomial gcd in Q[s], reported), a pole on
the imaginary axis is decided exactly (a real root of the gcd of the real and
imaginary parts of D(j*omega)), and the stationary points of |N/D|^2 (the real roots
of P'Q - PQ' with P = |N(j*omega)|^2, Q = |D(j*omega)|^2) are isolated rigorously
and |N/D| evaluated on their enclosures in ball arithmetic (FLINT/Arb through
python-flint; see :mod:`gfrf.bounds.exact_sup`).  The result is an interval ``[lower, upper]``
that provably contains the sup, with ``value`` its midpoint; clustered or lightly
damped poles only cost precision, never correctness.  Scaling N or D by any factor
does not change the method (exact arithmetic has no range limits).

A discrete-time function of the backward shift q = exp(-j*omega*T) is mapped to the
imaginary axis by the Cayley map q = (1 + s) / (1 - s) and handled the same way (a
pole at z = -1 or anywhere on the unit circle is decided exactly).

Examples
--------
>>> s = rational_sup([1.0], [1.0, 0.05, 2.45])
>>> s.lower <= 1 / (0.05 * (2.45 - 0.05**2 / 4) ** 0.5) <= s.upper
True
>>> s.proof
'interval'
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf.bounds.exact import format_roots
from gfrf.bounds.exact_sup import ExactSup, discrete_sup_abs, sup_abs
from gfrf.errors import ArgumentError

__all__ = ["SupResult", "PROOF_LEVELS", "check_proof", "rational_sup",
           "discrete_rational_sup"]


@dataclass(frozen=True, kw_only=True)
class SupResult:
    """Result of a sup of |N/D| over real angular frequencies.

    Attributes
    ----------
    value : float
        The sup (midpoint of the proven enclosure; ``math.inf`` when unbounded).
    omega : float
        An angular frequency (rad/s) where it is attained (``math.inf`` for a limit at
        infinity, the pole's frequency for a pole on the axis or the circle).
    exact : bool
        True when ``[lower, upper]`` is a proven enclosure (``proof = "interval"``).
    reason : str
        Why the sup is infinite, or empty.
    lower, upper : float
        Proven bounds ``lower <= sup <= upper`` (outward-rounded floats).
    proof : str
        ``"interval"``: the enclosure is a computer-assisted proof (exact rational
        algebra and ball arithmetic); ``"float"``: double-precision stationary points
        (``lower = upper``); ``"none"``: the same, labelled an estimate.
    cancelled : tuple of complex
        Common roots of N and D removed exactly before the sup (approximate values).
    variable : str
        The variable of those roots: ``s``, or ``q`` for a discrete function.
    """

    value: float
    omega: float
    exact: bool = True
    reason: str = ""
    lower: float = math.nan
    upper: float = math.nan
    proof: str = "interval"
    cancelled: tuple[complex, ...] = field(default=())
    variable: str = "s"

    @property
    def notes(self) -> tuple[str, ...]:
        """Human-readable notes: cancellations and the reason of an infinite sup."""
        notes = []
        if self.cancelled:
            roots = format_roots(self.cancelled, self.variable)
            notes.append(f"pole-zero cancellation (exact common factor of N and D) at "
                         f"{roots}: the sup is that of the reduced function")
        if self.reason:
            notes.append(self.reason)
        return tuple(notes)


#: The levels of proof (see the README, "Levels of proof"): ``interval`` proves,
#: ``float`` is a sound method in double precision, ``none`` labels estimates.
PROOF_LEVELS = ("none", "float", "interval")


def check_proof(proof: str) -> str:
    """``proof`` if it is one of :data:`PROOF_LEVELS`, else ArgumentError.

    Parameters
    ----------
    proof : str
        The proof level asked for.

    Returns
    -------
    str
        ``proof``.
    """
    if proof not in PROOF_LEVELS:
        raise ArgumentError(f"proof must be one of {', '.join(PROOF_LEVELS)}; got {proof!r}")
    return proof


def _result(res: ExactSup, variable: str = "s", proof: str = "interval") -> SupResult:
    return SupResult(value=res.value,
                     omega=res.omega,
                     exact=proof == "interval",
                     reason=res.reason,
                     lower=res.lower,
                     upper=res.upper,
                     proof=proof,
                     cancelled=res.cancelled,
                     variable=variable)


def _method(proof: str) -> str:
    return "interval" if check_proof(proof) == "interval" else "float"


def rational_sup(num: np.ndarray | Sequence[Any], den: np.ndarray | Sequence[Any],
                 proof: str = "interval") -> SupResult:
    """Sup over real omega (rad/s) of |N(j*omega)/D(j*omega)|, as a proven enclosure.

    Parameters
    ----------
    num, den : array_like
        Real polynomial coefficients in s, highest power first (``control.tf`` order):
        floats (taken at their exact values) or Fractions.
    proof : {"interval", "float", "none"}
        ``"interval"`` (default): proven enclosure.  ``"float"``: same exact decisions,
        stationary points by ``numpy.roots`` (``lower = upper = value``, not proven);
        ``"none"``: the float computation labelled an estimate.

    Returns
    -------
    SupResult
    """
    return _result(sup_abs(num, den, _method(proof)), "s", proof)


def discrete_rational_sup(num: np.ndarray | list[float], den: np.ndarray | list[float],
                          sample_time: float, proof: str = "interval") -> SupResult:
    """Sup over omega in [0, pi/T] of |N(q)/D(q)|, q = exp(-j*omega*T), as a proven enclosure.

    Parameters
    ----------
    num, den : array_like
        Coefficients of powers of q, *lowest* power first (``[c0, c1, ...]`` means
        c0 + c1 q + ...), as lags appear in a NARX model.
    sample_time : float
        T in seconds.
    proof : {"interval", "float", "none"}
        As in :func:`rational_sup`.

    Returns
    -------
    SupResult
    """
    return _result(discrete_sup_abs(num, den, sample_time, _method(proof)), "q", proof)
