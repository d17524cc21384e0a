"""Averaging: regenerated (58)-(59) and first-order accuracy in eps."""

import numpy as np
import pytest
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.periodic.averaging import averaged_equations, averaging_transition
from gfrf.periodic.shooting import transition_delta


def test_regenerated_58_59_equal_printed():
    B, d, e, ph, dphi, dB = sp.symbols("B delta epsilon phi dphi dB")
    e58, e59 = averaged_equations()
    printed58 = B * (dphi + d - sp.Rational(1, 4) - d * B**2 / 8 + e * sp.cos(2 * ph) / 2
                     - e * B**2 * sp.cos(2 * ph) / 12)
    printed59 = dB + B * e * sp.sin(2 * ph) / 2 - e * B**3 * sp.sin(2 * ph) / 24
    assert sp.expand(e58 - printed58) == 0
    assert sp.expand(e59 - printed59) == 0


def test_linear_limit_is_first_order_mathieu():
    # B -> 0: delta = 1/4 - eps/2, the O(eps) part of b_1(2 eps)/4
    assert averaging_transition(0.1, 0.0) == pytest.approx(0.2)


def test_error_is_second_order_in_eps():
    errs = [abs(averaging_transition(e, 0.1) - transition_delta(e, 0.1, "1/4").delta)
            for e in (0.1, 0.05)]
    assert 3 < errs[0] / errs[1] < 5
    assert np.isfinite(errs).all()


def test_branch_zero_refused():
    with pytest.raises(ArgumentError, match="branch"):
        averaging_transition(0.1, 0.5, "0")
