"""Mathieu characteristic values against the monodromy matrix (independent methods)."""

import numpy as np
import pytest

from gfrf.periodic.floquet import (
    floquet_multipliers,
    mathieu_transition,
    monodromy,
    monodromy_transition,
    quarter_tongue_zero,
    upper_quarter_transition,
)


@pytest.mark.parametrize("eps", [0.05, 0.2, 0.5])
def test_trace_is_plus_minus_two_on_mathieu_curves(eps):
    d0 = float(mathieu_transition(eps, "0"))
    d14 = float(mathieu_transition(eps, "1/4"))
    du = float(upper_quarter_transition(eps))
    assert np.trace(monodromy(eps, d0)) == pytest.approx(2.0, abs=1e-8)
    assert np.trace(monodromy(eps, d14)) == pytest.approx(-2.0, abs=1e-8)
    assert np.trace(monodromy(eps, du)) == pytest.approx(-2.0, abs=1e-8)


@pytest.mark.parametrize("eps", [0.1, 0.3])
@pytest.mark.parametrize("branch", ["0", "1/4"])
def test_monodromy_bisection_matches_mathieu(eps, branch):
    assert monodromy_transition(eps, branch) == pytest.approx(
        float(mathieu_transition(eps, branch)), abs=1e-8)


def test_small_eps_series_abramowitz_stegun():
    # A&S 20.2.25: a_0(q) = -q^2/2 + 7 q^4/128 - ..., b_1(q) = 1 - q - q^2/8 + q^3/64 - ...
    # with q = 2 eps and delta = a/4.
    eps = 1e-2
    assert float(mathieu_transition(eps, "0")) == pytest.approx(
        -eps**2 / 2 + 7 * eps**4 / 32, abs=1e-11)
    assert float(mathieu_transition(eps, "1/4")) == pytest.approx(
        0.25 - eps / 2 - eps**2 / 8 + eps**3 / 32, abs=1e-10)


def test_multipliers_unit_product_and_stability():
    # inside the Kapitza-stabilised region (eps=0.3: -0.045 < delta < 0.08) |mu| = 1
    mu = floquet_multipliers(0.3, -0.02)
    assert np.prod(mu) == pytest.approx(1.0, abs=1e-9)
    assert np.allclose(np.abs(mu), 1.0, atol=1e-8)
    # below the branch-0 curve the upright position is unstable
    assert np.max(np.abs(floquet_multipliers(0.3, -0.2))) > 1.5


def test_quarter_tongue_reaches_negative_delta_at_the_mathieu_root():
    from scipy.optimize import brentq
    from scipy.special import mathieu_b

    # independent: root q of the characteristic value b_1(q) = 0, eps = q/2
    q = brentq(lambda q: mathieu_b(1, q), 0.5, 1.5, xtol=1e-15)
    eps0 = quarter_tongue_zero()
    assert eps0 == pytest.approx(q / 2, abs=1e-12)
    assert float(mathieu_transition(eps0 - 1e-6, "1/4")) > 0 > \
        float(mathieu_transition(eps0 + 1e-6, "1/4"))


@pytest.mark.slow
def test_quarter_tongue_zero_against_a_20_digit_integration():
    import mpmath as mp

    with mp.workdps(20):
        def trace_plus_two(e):
            f = lambda t, y: [y[1], -e * mp.cos(t) * y[0], y[3], -e * mp.cos(t) * y[2]]  # noqa: E731
            y = mp.odefun(f, 0, [1, 0, 0, 1])(2 * mp.pi)
            return y[0] + y[3] + 2

        root = mp.findroot(trace_plus_two, mp.mpf("0.454"))
    assert quarter_tongue_zero() == pytest.approx(float(root), abs=1e-12)
