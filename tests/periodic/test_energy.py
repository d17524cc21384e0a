"""Energy method: regenerated (39), (44), (47) and behaviour of (48)."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.periodic.energy import energy_cutoff, energy_formulas, energy_solution, energy_transition
from gfrf.periodic.shooting import transition_delta

a, th, d, e, ph = sp.symbols("a theta delta epsilon phi", positive=True)


@pytest.fixture(scope="module")
def formulas():
    return energy_formulas()


def test_39_and_44(formulas):
    printed39 = 1 - a**2 / 16 - a**2 * sp.cos(2 * th) / 48
    assert sp.simplify(formulas["39_factor"] - printed39) == 0
    assert sp.simplify(formulas["44"] - 1 / (d * a * (1 - a**2 / 6))) == 0


def test_47_agrees_only_to_leading_order(formulas):
    # printed (47), second equation, times sqrt(delta)(1 - a^2/6):
    printed = (d * (1 - a**2 / 16) * (1 - a**2 / 6)
               + (1 - a**2 / 16) * e * sp.cos(2 * ph) * (1 - a**2 / 12) / 4)
    diff = sp.expand(formulas["47_theta"] - printed)
    # the eps*a^2 coefficient differs: exact -1/16, printed -7/192
    assert diff.coeff(e).coeff(a, 2) == -sp.Rational(5, 192) * sp.cos(2 * ph)
    assert diff.coeff(e, 0) == 0


def test_linear_limit_and_first_order_accuracy():
    assert energy_transition(0.0, 1e-8) == pytest.approx(0.25)
    errs = [abs(energy_transition(x, 1e-3) - transition_delta(x, 1e-3, "1/4").delta)
            for x in (0.02, 0.01)]
    assert 3 < errs[0] / errs[1] < 5  # O(eps^2)


def test_no_root_beyond_quarter_and_delta_must_be_positive():
    assert np.isnan(energy_transition(0.3, 0.5))
    with pytest.raises(ArgumentError, match="delta > 0"):
        energy_solution(0.3, 0.5, np.linspace(0, 1, 3))


def test_solution_starts_at_amplitude():
    x = energy_solution(0.05, 0.4, np.array([0.0, 1.0]))
    assert x[0] == pytest.approx(0.4)


def test_energy_cutoff_is_the_closed_form_of_the_printed_48():
    # the printed (48) as a quadratic in s = sqrt(delta), built from the paper's text
    s_, a_, e_ = sp.symbols("s a epsilon", positive=True)
    lhs = s_ * (1 - a_**2 / 16) * (1 + e_ * (1 - a_**2 / 12) / (4 * s_**2 * (1 - a_**2 / 6)))
    quadratic = sp.numer(sp.together(lhs - sp.Rational(1, 2)))
    disc = sp.discriminant(sp.Poly(quadratic, s_))
    cut = sp.solve(disc.subs(a_, sp.Rational(1, 2)), e_)
    assert len(cut) == 1 and cut[0] == sp.Rational(47104, 186543)
    assert energy_cutoff(Fraction(1, 2)) == Fraction(47104, 186543)
    assert float(energy_cutoff(0.5)) == pytest.approx(47104 / 186543, rel=1e-15)
    assert energy_cutoff(Fraction(0)) == Fraction(1, 4)


@pytest.mark.parametrize("variant", ["paper", "consistent"])
def test_energy_cutoff_is_where_the_real_root_disappears(variant):
    from scipy.optimize import brentq

    def has_root(eps: float) -> float:
        return 1.0 if np.isfinite(energy_transition(eps, 0.5, variant=variant)) else -1.0

    edge = brentq(has_root, 0.2, 0.3, xtol=1e-13)
    assert float(energy_cutoff(0.5, variant)) == pytest.approx(edge, abs=1e-10)
