"""The exact value of a coefficient as the user wrote it, kept beside its double.

The parser reads every number twice: as a double (the path of estimates, kernels and
simulation) and as the exact rational the decimal literal writes (``0.2`` is 1/5,
``2.45/6`` is 49/120; ``+ - * /`` and integer powers of rationals stay rational).  The
proofs (exact rational checks and ball-arithmetic enclosures) use the exact value, so a
proven statement is about the model as written, not about its rounding to doubles.

A :class:`Written` value belongs to one double: a coefficient changed afterwards (a
rescaling, a sweep point) no longer matches it, and the double is then the model (as it
is for models built from python-control objects or identified from data, whose
coefficients *are* doubles).  A written coefficient that is not rational (``pi``,
``sqrt(2)``, ``sin(1)``) has no exact rational value: :func:`coefficient_bounds`
widens its double by a relative 2^-50 (plus 2^-1074) so the interval contains the real
value, and the exact rational engines refuse it.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

__all__ = ["Written", "exact_value", "coefficient_bounds", "float_as_written", "as_fraction",
           "IRRATIONAL_WIDTH"]

#: Relative half-width around the double of an irrational written coefficient (the double
#: is the value rounded from >= 30 digits, within a few units in its last place).
IRRATIONAL_WIDTH = Fraction(1, 2**50)
_TINY = Fraction(1, 2**1074)


@dataclass(frozen=True)
class Written:
    """The exact value of a written coefficient and the double it belongs to.

    Attributes
    ----------
    of : float
        The double the parser computed for the coefficient.
    value : Fraction or None
        The exact rational value as written; None when it is not rational.
    """

    of: float
    value: Fraction | None


def exact_value(coefficient: float, written: Written | None) -> Fraction | None:
    """The exact value a proof must use for a coefficient.

    Parameters
    ----------
    coefficient : float
        The coefficient's double.
    written : Written or None
        What the parser recorded; None for a coefficient that never was text.

    Returns
    -------
    Fraction or None
        The written rational when ``written`` belongs to this double; the double's own
        exact value when there is no written value or the coefficient changed since (the
        double is then the model); None for an irrational written coefficient.
    """
    if written is None or written.of != coefficient:
        return Fraction(coefficient)
    return written.value


def coefficient_bounds(coefficient: float, written: Written | None
                       ) -> tuple[Fraction, Fraction]:
    """Rational bounds containing the coefficient as written.

    Equal bounds for a rational coefficient; for an irrational one (``pi``,
    ``sqrt(2)``), the double widened by the relative :data:`IRRATIONAL_WIDTH` plus
    2^-1074.

    Parameters
    ----------
    coefficient : float
        The coefficient's double.
    written : Written or None
        What the parser recorded.

    Returns
    -------
    tuple of Fraction
        ``(lo, hi)``.
    """
    value = exact_value(coefficient, written)
    if value is not None:
        return value, value
    c = Fraction(coefficient)
    radius = abs(c) * IRRATIONAL_WIDTH
    if abs(coefficient) < 2.0 ** -1000:  # subnormal range: an absolute rounding error too
        radius += _TINY
    return c - radius, c + radius


def float_as_written(value: float | int) -> Fraction:
    """The exact value of a number handed over as a Python or TOML number.

    An int is itself; a float is read as the shortest decimal that gives it back (its
    ``repr``), which is the literal as written whenever the literal has at most 15
    significant digits (``0.145`` is 29/200, not the double next to it).

    Parameters
    ----------
    value : float or int
        A finite number.

    Returns
    -------
    Fraction
    """
    if isinstance(value, int):
        return Fraction(value)
    return Fraction(repr(float(value)))


def as_fraction(number: Any) -> Fraction | None:
    """A sympy number as a Fraction, None when it is not rational.

    Parameters
    ----------
    number : sympy.Expr
        An exact sympy number.

    Returns
    -------
    Fraction or None
    """
    if getattr(number, "is_Rational", False):
        return Fraction(int(number.p), int(number.q))
    return None
