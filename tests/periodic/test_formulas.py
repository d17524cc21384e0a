"""The formula-by-formula check: which printed formulas the program confirms."""

import numpy as np
import pytest

from gfrf.periodic.formulas import formula_checks


@pytest.fixture(scope="module")
def checks():
    return {(c.equation, c.quantity): c for c in formula_checks()}


def test_confirmed_formulas(checks):
    confirmed = {k[0] for k, c in checks.items() if c.agrees}
    assert {"(3)", "(10)", "(11)", "(12)", "(13)", "(15)", "(39)", "(44)", "(47) first",
            "(51)", "(58)", "(59)", "section 6, case 2", "section 6, case 3"} <= confirmed


def test_misprints_found(checks):
    wrong = {k for k, c in checks.items() if not c.agrees}
    for key in [("(1)", "kinetic energy T"), ("(30)", "γ1"), ("(29)", "x1 of the HAM"),
                ("(54)", "variation-of-constants condition"),
                ("(47) second", "θ-average of dθ/dt (times √δ(1 - a^2/6))")]:
        assert key in wrong
    assert ("(30)", "γ0") not in wrong
    for c in checks.values():
        if not c.agrees:
            assert c.corrected, c.equation


def test_47_coefficients_quoted(checks):
    note = checks[("(47) second", "θ-average of dθ/dt (times √δ(1 - a^2/6))")].note
    assert "-1/16 exactly" in note and "-7/192 as printed" in note


def test_48_49_inherit_the_47_error_and_are_counted_as_disagreeing(checks):
    for eq, quantity in (("(48)", "lower curve from (47), φ = 0"),
                         ("(49)", "upper curve from (47), φ = π/2")):
        c = checks[(eq, quantity)]
        assert not c.agrees and c.inherits == "(47) second" and c.corrected
        assert "follows exactly from the printed (47)" in c.note
    # the error they inherit: coefficient of eps a^2 in (printed - exact) of the polynomial
    # form, printed -(1/16 + 1/12)/4 = -7/192 against the exact -1/16 = -12/192
    assert "printed - exact = 5/192 ε a^2" in checks[("(48)", "lower curve from (47), φ = 0")].note
    assert "printed - exact = -5/192 ε a^2" in \
        checks[("(49)", "upper curve from (47), φ = π/2")].note
    assert all(not c.agrees for c in checks.values() if c.inherits)


def test_47_first_states_the_dropped_a6_term(checks):
    c = checks[("(47) first", "θ-average of dE/dt")]
    assert "a**6*sqrt(delta)*epsilon*sin(2*phi)/9216" in c.note
    # independent check: average the first line of (46) over theta (trapezoidal rule on
    # 64 points, exact for this trigonometric polynomial of degree 8)
    a, d, e, ph = 0.9, 0.3, 0.2, 0.4

    def rhs(th: np.ndarray) -> np.ndarray:
        s39 = 1 - a**2 / 16 - a**2 * np.cos(2 * th) / 48
        return (a**2 / 4 * np.sqrt(d) * e * (1 - a**2 * np.cos(th) ** 2 / 6)
                * (np.sin(4 * th - 2 * ph) + np.sin(2 * ph)) * s39)

    average = float(np.mean(rhs(np.linspace(0, 2 * np.pi, 64, endpoint=False))))
    printed = a**2 / 4 * np.sqrt(d) * e * (1 - a**2 / 12) * np.sin(2 * ph) * (1 - a**2 / 16)
    assert average - printed == pytest.approx(a**6 * np.sqrt(d) * e * np.sin(2 * ph) / 9216,
                                              rel=1e-9)
