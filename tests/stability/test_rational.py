"""The certificate files' rational reader: exact text only, bounded, no zero denominator."""

from __future__ import annotations

from fractions import Fraction

import pytest

from gfrf.stability._rational import read_rational


def test_reads_exact_rationals_and_integers():
    assert read_rational("-3/4", 10) == Fraction(-3, 4)
    assert read_rational("12", 10) == 12
    assert read_rational(-7, 10) == -7


@pytest.mark.parametrize("text", ["２２０", "٣/4", "1.5", "1e3", "1_000", " 1", "--3", "1/2/3",
                                  "/3", "3/", "-3/-4", True, 0.5, None, [1]])
def test_refuses_anything_but_ascii_p_over_q(text):
    with pytest.raises(ValueError):
        read_rational(text, 40)


def test_refuses_a_zero_denominator_and_a_long_text_with_value_error():
    with pytest.raises(ValueError, match="zero denominator"):
        read_rational("1/0", 40)
    with pytest.raises(ValueError, match="at most 5 characters"):
        read_rational("123456", 5)
