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

:func:`enclosed_sup` does the same for coefficients known only to lie in rational
intervals (a coefficient written as ``pi``): the exact sup at the midpoints, widened by
a perturbation bound that holds for every coefficient in the intervals.

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
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.bounds.exact import format_roots
from gfrf.bounds.exact_sup import ExactSup, discrete_sup_abs, sup_abs
from gfrf.errors import ArgumentError

__all__ = ["SupResult", "PROOF_LEVELS", "check_proof", "rational_sup",
           "discrete_rational_sup", "enclosed_sup"]

#: Rational bounds ``(lo, hi)`` of one coefficient.
Interval = tuple[Fraction, Fraction]


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


def discrete_rational_sup(num: np.ndarray | Sequence[Any], den: np.ndarray | Sequence[Any],
                          sample_time: float, proof: str = "interval") -> SupResult:
    """Sup over omega in [0, pi/T] of |N(q)/D(q)|, q = exp(-j*omega*T), as a proven enclosure.

    Parameters
    ----------
    num, den : array_like
        Coefficients of powers of q, *lowest* power first (``[c0, c1, ...]`` means
        c0 + c1 q + ...), as lags appear in a NARX model: floats (at their exact
        values) or Fractions.
    sample_time : float
        T in seconds.
    proof : {"interval", "float", "none"}
        As in :func:`rational_sup`.

    Returns
    -------
    SupResult
    """
    return _result(discrete_sup_abs(num, den, sample_time, _method(proof)), "q", proof)


def enclosed_sup(num: Sequence[Interval], den: Sequence[Interval],
                 sample_time: float | None = None) -> SupResult:
    """Proven enclosure of the sup of |N/D| for every N, D with coefficients in intervals.

    Equal ends everywhere: :func:`rational_sup` (or :func:`discrete_rational_sup`) on
    those exact values.  Otherwise, with N0, D0 the midpoint polynomials and R_N, R_D
    the radii: on the axis |N - N0| <= sum_k r_k |w|^k and, by Cauchy-Schwarz,
    (sum_k r_k |w|^k)^2 <= K sum_k r_k^2 w^(2k) (K nonzero radii), a polynomial in
    x = w^2; its proven sup over |D0(j w)|^2 gives b^2 (c^2 for D), so that for c < 1
    every sup lies in [(lower0 - b) / (1 + c), (upper0 + b) / (1 - c)] around the exact
    sup [lower0, upper0] of |N0/D0|.  On the unit circle |N - N0| <= sum r_k and b =
    sum r_k sup|1/D0|.  Where D0 has a root on the boundary, N0/D0 is improper or
    c >= 1, there is no enclosure: ``lower = 0``, ``upper = inf`` with the reason.

    Parameters
    ----------
    num, den : sequence of tuple of Fraction
        ``(lo, hi)`` of every coefficient, in the order of :func:`rational_sup`
        (highest power of s first) or, with ``sample_time``, of
        :func:`discrete_rational_sup` (lowest power of q first).
    sample_time : float, optional
        T in seconds of a discrete-time function; None for s.

    Returns
    -------
    SupResult
        ``proof = "interval"``.
    """
    mid_n = [(lo + hi) / 2 for lo, hi in num]
    mid_d = [(lo + hi) / 2 for lo, hi in den]
    base = (rational_sup(mid_n, mid_d) if sample_time is None else
            discrete_rational_sup(mid_n, mid_d, sample_time))
    rad_n = [(hi - lo) / 2 for lo, hi in num]
    rad_d = [(hi - lo) / 2 for lo, hi in den]
    if not any(rad_n) and not any(rad_d):
        return base
    variable = "s" if sample_time is None else "q"
    if not math.isfinite(base.upper):
        return SupResult(value=math.inf, omega=base.omega, reason=(
            "a coefficient as written is irrational and the function at its double has no "
            f"finite sup ({base.reason}): no enclosure"), lower=0.0, upper=math.inf,
            cancelled=base.cancelled, variable=variable)
    import flint

    from gfrf.bounds.exact import _PREC, _down, _precision, _up

    with _precision(_PREC):
        if sample_time is None:
            b, c = _radius_ratio(rad_n, mid_d), _radius_ratio(rad_d, mid_d)
        else:
            inverse = flint.arb(discrete_rational_sup([Fraction(1)], mid_d, sample_time).upper)
            b = inverse * flint.arb(_fmpq(sum(rad_n, Fraction(0))))
            c = inverse * flint.arb(_fmpq(sum(rad_d, Fraction(0))))
        if not (b.is_finite() and c.is_finite() and c < 1):
            return SupResult(value=math.inf, omega=base.omega, reason=(
                "a coefficient as written is irrational and its interval may move a root of "
                "the denominator onto the boundary: no enclosure"), lower=0.0,
                upper=math.inf, cancelled=base.cancelled, variable=variable)
        upper = (flint.arb(base.upper) + b) / (1 - c)
        lower = (flint.arb(base.lower) - b) / (1 + c)
        return SupResult(value=base.value, omega=base.omega, lower=max(0.0, _down(lower)),
                         upper=_up(upper), cancelled=base.cancelled, variable=variable)


def _fmpq(value: Fraction) -> Any:
    import flint

    return flint.fmpq(value.numerator, value.denominator)


def _radius_ratio(radii: Sequence[Fraction], den: Sequence[Fraction]) -> Any:
    """An arb upper bound of sup over real w of (sum_k r_k |w|^k) / |D(j w)| (highest
    power first; D has no root on the axis), inf where the ratio is unbounded."""
    import flint

    from gfrf.bounds.exact import _qpoly
    from gfrf.bounds.exact_sup import _abs2_in_x, _sup_x

    low = list(reversed(radii))
    count = sum(1 for r in low if r)
    top = flint.fmpq_poly([_fmpq(count * r * r) for r in low])
    q = _abs2_in_x(_qpoly(list(den)))
    if top.degree() < 0:
        return flint.arb(0)
    if top.degree() > q.degree():
        return flint.arb(math.inf)
    _, upper, _ = _sup_x(top, q)
    return flint.arb(upper).sqrt()
