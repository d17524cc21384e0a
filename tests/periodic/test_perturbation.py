"""Perturbation series: exact coefficients, Mathieu limit, convergence to shooting."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from gfrf.periodic.fourier import CosSeries, poly_divide
from gfrf.periodic.perturbation import perturbation_series
from gfrf.periodic.shooting import transition_delta

eps, a = sp.symbols("epsilon a")


@pytest.fixture(scope="module")
def series():
    return {b: perturbation_series(b, 6) for b in ("0", "1/4")}


def test_cos_series_product_identity():
    c1 = CosSeries.cos(1)
    sq = (c1 * c1)
    assert sq.harmonic(0)[0] == Fraction(1, 2) and sq.harmonic(2)[0] == Fraction(1, 2)
    q = poly_divide(np.array([0, 2, 0, -1], dtype=object), np.array([0, 1], dtype=object))
    assert list(q) == [2, 0, -1]


def test_mathieu_limit_abramowitz_stegun(series):
    # a -> 0: delta = a_0(2 eps)/4 and b_1(2 eps)/4 with A&S 20.2.25 coefficients.
    d0 = series["0"].delta_expr().subs(a, 0)
    assert sp.expand(d0 - (-eps**2 / 2 + sp.Rational(7, 32) * eps**4
                           - sp.Rational(29, 144) * eps**6)) == 0
    d14 = series["1/4"].delta_expr().subs(a, 0)
    q = 2 * eps
    b1 = 1 - q - q**2 / 8 + q**3 / 64 - q**4 / 1536 - sp.Rational(11, 36864) * q**5 \
        + sp.Rational(49, 589824) * q**6
    assert sp.expand(d14 - b1 / 4) == 0


def test_paper_second_order_formulas():
    # hand derivation (kernel normalisation = the paper's rule of eq (10)):
    # x1 = a(1 - a^2/6) cos t, delta2 = (a^2 - 2)/4, cos 2t part of x2 = a(12-8a^2+a^4)/96
    s = perturbation_series("0", 2, "kernel")
    assert sp.expand(s.harmonic_expr(1, 1) - a * (1 - a**2 / 6)) == 0
    assert sp.expand(s.delta_expr() - (a**2 - 2) / 4 * eps**2) == 0
    assert sp.expand(s.harmonic_expr(2, 2) - a * (12 - 8 * a**2 + a**4) / 96) == 0
    s = perturbation_series("1/4", 2, "kernel")
    assert sp.expand(s.delta_expr() - (sp.Rational(1, 4) - eps / 2
                                       + (a**2 / 32 - sp.Rational(1, 8)) * eps**2)) == 0
    assert s.harmonic_expr(1, 3) == a / 4
    assert sp.expand(s.harmonic_expr(2, 5) - a / 48) == 0
    assert sp.expand(s.harmonic_expr(2, 3) + a**3 / 192 + a / 16) == 0


def test_initial_normalisation_gives_amplitude(series):
    for b in ("0", "1/4"):
        assert series[b].solution(0.2, 0.5, np.array([0.0]))[0] == pytest.approx(0.5, abs=1e-14)


@pytest.mark.parametrize("branch", ["0", "1/4"])
def test_error_shrinks_with_order_and_eps(series, branch):
    # branch 1/4 uses the paper's scaling x = eps*u: the series is uniform for x(0) ~ eps
    errs = {}
    for e in (0.2, 0.1):
        amp = 0.5 if branch == "0" else 2 * e
        o = transition_delta(e, amp, branch)
        errs[e] = [abs(series[branch].delta(e, amp, k) - o.delta) for k in (2, 4, 6)]
        assert errs[e][0] > errs[e][1] > errs[e][2]
    # error of the order-2 truncation is O(eps^3): halving eps divides it by ~8
    assert 4 < errs[0.2][0] / errs[0.1][0] < 12


def test_paper_a_to_initial_displacement():
    # (16) at t = 0, to O(eps^2) in x: x(0) = eps a + eps^2 a/4 (paper's normalisation)
    s = perturbation_series("1/4", 1, "kernel")
    assert s.amplitude_of(0.1, 2.0) == pytest.approx(0.1 * 2.0 + 0.01 * 2.0 / 4, abs=1e-15)
    # (14): x(0) = a + eps a (1 - a^2/6) at first order
    s0 = perturbation_series("0", 1, "kernel")
    assert s0.amplitude_of(0.1, 0.5) == pytest.approx(0.5 + 0.1 * 0.5 * (1 - 0.25 / 6))
