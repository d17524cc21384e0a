"""H_n at one point, with a pole named and overflow or underflow resolved.

Floating point gives ``nan`` for H_n both at a pole (A vanishes at the sum of some block
of the frequencies, 1/0) and far beyond the float range (j*1e308 + j*1e308 = inf).
:func:`point_value` tells them apart: when the float value is not finite it repeats
the recursion in mpmath (50 digits, unbounded exponent) and, block by block, decides
whether the denominator A(s_B) at s_B = j * sum of the block's frequencies vanishes --
exactly, in rational arithmetic, for a continuous model (A has float coefficients and
the omegas are floats, so A(j w) = 0 is a finite rational computation); for a discrete
model, where q = exp(-j w T) is transcendental, to 50 digits.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> from gfrf.kernels.recursion import kernel
>>> pv = point_value(kernel(parse_model("D(y,2) + y + 0.5*y**3 = u"), 3), [1.0, 1.0, -1.0])
>>> pv.pole is not None, pv.pole.omega
(True, 1.0)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from gfrf.kernels.recursion import Kernel

__all__ = ["Pole", "PointValue", "point_value"]

_DPS = 50


@dataclass(frozen=True)
class Pole:
    """A pole met by the recursion: A(s_B) = 0 for the block B of frequencies.

    Attributes
    ----------
    block : tuple of int
        0-based indices of the frequencies whose sum is the pole.
    omega : float
        The block's frequency sum (rad/s); the pole is at s = j*omega.
    exact : bool
        True when A(j*omega) = 0 was decided in exact rational arithmetic (continuous
        models), False when it vanished to 50 digits (discrete models).
    """

    block: tuple[int, ...]
    omega: float
    exact: bool

    def text(self, discrete: bool) -> str:
        """One sentence naming the pole.

        Parameters
        ----------
        discrete : bool
            The model is discrete (name q = exp(-j w T) instead of s = j w).

        Returns
        -------
        str
            The sentence.
        """
        names = " + ".join(f"w{i + 1}" for i in self.block)
        where = (f"q = exp(-j*{self.omega:.12g}*T)" if discrete else f"s = j*{self.omega:.12g}")
        how = "exactly" if self.exact else "to 50 digits"
        return (f"A(s) = 0 {how} at {where} ({names} = {self.omega:.12g} rad/s), "
                f"a pole of 1/A")


@dataclass(frozen=True)
class PointValue:
    """H_n at one point: a finite complex value, or the pole that makes it infinite.

    Attributes
    ----------
    value : complex or None
        The value (0 when it underflows the float range); None at a pole or when the
        magnitude exceeds the float range.
    pole : Pole or None
    method : str
        ``"float"`` (the ordinary evaluation) or ``"mpmath"`` (the fallback).
    magnitude : str
        |H_n| as a decimal string from the evaluation that produced ``value``
        (also when it exceeds the float range).
    """

    value: complex | None
    pole: Pole | None
    method: str
    magnitude: str


def point_value(k: Kernel, omega: list[float]) -> PointValue:
    """H_n(j*omega) of kernel ``k`` at one point, never nan.

    Parameters
    ----------
    k : Kernel
    omega : list of float
        n finite angular frequencies (rad/s).

    Returns
    -------
    PointValue
    """
    value = complex(k(*omega))
    if np.isfinite(value.real) and np.isfinite(value.imag):
        return PointValue(value, None, "float", f"{abs(value):.12g}")
    return _mp_value(k, omega)


def _exact_zero(coefficients: dict[int, float], x: Fraction) -> bool:
    """Whether sum a_k (j x)^k = 0 exactly (rational arithmetic)."""
    re = im = Fraction(0)
    for power, c in coefficients.items():
        term = Fraction(c) * x ** power
        part = power % 4  # j^power = 1, j, -1, -j
        if part == 0:
            re += term
        elif part == 1:
            im += term
        elif part == 2:
            re -= term
        else:
            im -= term
    return re == 0 and im == 0


def _mp_value(k: Kernel, omega: list[float]) -> PointValue:
    import mpmath

    gen = k._gen
    model = gen.model
    linear = {p: c for p, c in model.linear_output.items() if c != 0.0}
    discrete = model.is_discrete
    with mpmath.workdps(_DPS):
        if discrete:
            xs = [mpmath.exp(-1j * mpmath.mpf(w) * mpmath.mpf(model.sample_time)) for w in omega]
        else:
            xs = [1j * mpmath.mpf(w) for w in omega]
        memo: dict[tuple[int, ...], Any] = {}

        def value(block: tuple[int, ...]) -> Any:
            if block not in memo:
                plan = gen.plan(len(block), k.symmetric)
                if plan.is_zero:
                    memo[block] = mpmath.mpc(0)
                    return memo[block]
                sub = [xs[i] for i in block]
                lower = [value(tuple(block[j] for j in b)) for b in plan.blocks]
                numerator = gen.step(len(block), k.symmetric)(*sub, *lower)
                combined = mpmath.fprod(sub) if discrete else mpmath.fsum(sub)
                den = mpmath.fsum(c * combined ** p for p, c in linear.items())
                w_sum = float(sum(omega[i] for i in block))
                if discrete:
                    scale = mpmath.fsum(abs(c) for c in linear.values())
                    if abs(den) <= scale * mpmath.mpf(10) ** (-(_DPS - 10)):
                        raise _PoleFound(Pole(block, w_sum, False))
                elif _exact_zero(linear, sum((Fraction(omega[i]) for i in block), Fraction(0))):
                    raise _PoleFound(Pole(block, w_sum, True))
                memo[block] = -numerator / den
            return memo[block]

        try:
            result = mpmath.mpc(value(tuple(range(k.order))))
        except _PoleFound as found:
            return PointValue(None, found.pole, "mpmath", "inf")
        magnitude = mpmath.nstr(abs(result), 12)
        try:
            out = complex(float(result.real), float(result.imag))
        except OverflowError:
            return PointValue(None, None, "mpmath", magnitude)
        if not (np.isfinite(out.real) and np.isfinite(out.imag)):
            return PointValue(None, None, "mpmath", magnitude)
        return PointValue(out, None, "mpmath", magnitude)


class _PoleFound(Exception):
    def __init__(self, pole: Pole) -> None:
        super().__init__(pole)
        self.pole = pole
