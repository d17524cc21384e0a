"""The formula-by-formula check: which printed formulas the program confirms."""

import pytest

from gfrf.periodic.formulas import formula_checks


@pytest.fixture(scope="module")
def checks():
    return {(c.equation, c.quantity): c for c in formula_checks()}


def test_confirmed_formulas(checks):
    confirmed = {k[0] for k, c in checks.items() if c.agrees}
    assert {"(3)", "(10)", "(11)", "(12)", "(13)", "(15)", "(39)", "(44)", "(48)", "(49)",
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
