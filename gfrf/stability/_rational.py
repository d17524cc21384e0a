"""The one reader of an exact rational in a certificate file: ``"p/q"`` text or an integer.

Certificates carry every number as exact text so that a check never rounds.  A reader
that accepted floats, exponents, underscores or non-ASCII digits (``Fraction`` reads
``"٣"`` as 3) would let a file say something else than it shows; this one accepts an
optional minus, ASCII digits and at most one ``/``, bounded in length before any
conversion, and refuses a zero denominator with the same error as everything else.

Examples
--------
>>> read_rational("-3/4", 40)
Fraction(-3, 4)
>>> read_rational("1e3", 40)
Traceback (most recent call last):
...
ValueError: not a rational 'p/q' of at most 40 characters: '1e3'
"""

from __future__ import annotations

import re
from fractions import Fraction
from typing import Any

__all__ = ["read_rational"]

#: An optional minus, ASCII digits, an optional ``/`` and ASCII digits.
_RATIONAL = re.compile(r"-?[0-9]+(?:/([0-9]+))?")


def read_rational(text: Any, max_chars: int) -> Fraction:
    """A rational from its text ``"p/q"`` (or ``"p"``) or a JSON integer.

    Parameters
    ----------
    text : str or int
        The value as read from the JSON file.
    max_chars : int
        Longest text accepted (the format's cap), checked before conversion.

    Returns
    -------
    fractions.Fraction
        The exact value.

    Raises
    ------
    ValueError
        For anything else: a float, a bool, a longer text, an exponent, a non-ASCII
        digit, a zero denominator.
    """
    if isinstance(text, bool) or not isinstance(text, str | int):
        raise ValueError(f"a rational must be written as a string 'p/q', got {str(text)[:40]!r}")
    if isinstance(text, int):
        return Fraction(text)
    match = _RATIONAL.fullmatch(text) if len(text) <= max_chars else None
    if match is None:
        raise ValueError(f"not a rational 'p/q' of at most {max_chars} characters: "
                         f"{text[:40]!r}")
    if match.group(1) is not None and int(match.group(1)) == 0:
        raise ValueError(f"a rational with a zero denominator: {text[:40]!r}")
    return Fraction(text)
