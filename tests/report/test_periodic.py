"""paper-periodic.md: tables come from the result objects; conclusions are computed."""

import pytest
from PIL import Image
from scipy.optimize import brentq
from scipy.special import mathieu_b

from gfrf.report._format import num
from gfrf.report.periodic import _delta_signs, _formula_table, write
from gfrf.report.periodic_checks import _grid_table, conclusion_checks, error_grid


@pytest.fixture(scope="module")
def grid():
    return error_grid("1/4", (0.05, 0.2), (0.05, 0.5))


def test_table_shows_grid_values(grid):
    text = _grid_table(grid)
    r = grid.rows[("averaging (58)", 0.2, 0.5)]
    assert f"{num(r.delta_error, 2)} / {num(r.max_error, 2)}" in text
    assert len(grid.labels()) == 6


def test_conclusions_computed(grid):
    checks = {c.claim: c for c in conclusion_checks(grid)}
    # amplitude dependence (conclusion 1) holds for the averaging method
    assert checks["(1) accuracy drops as the initial angle grows: averaging (58)"].holds
    # conclusion 3 fails against a residual-optimised HAM: it beats perturbation/averaging
    key = [k for k in checks if "h minimising" in k and "eps = 0.2" in k][0]
    assert not checks[key].holds
    r = grid.rows
    assert r[("homotopy, order 2", 0.2, 0.5)].max_error < \
        r[("perturbation, order 2 (paper)", 0.2, 0.5)].max_error


@pytest.mark.slow
def test_write_quick_is_deterministic(tmp_path):
    p1 = write(tmp_path / "a", quick=True)
    p2 = write(tmp_path / "b", quick=True)
    text = p1.read_text(encoding="utf-8")
    assert text == p2.read_text(encoding="utf-8")
    lines = text.splitlines()
    assert lines[0].startswith("# ") and all(lines[i].startswith("> ") for i in (2, 3, 4))
    assert "gfrf report --out reports/" in text
    for png in ("stability", "fig2", "fig3", "fig6", "fig7", "fig8", "fig9", "fig10", "ham-h"):
        f = p1.parent / f"paper-periodic-{png}.png"
        assert f.exists()
        assert f.read_bytes() == (p2.parent / f.name).read_bytes()
        width, height = Image.open(f).size
        assert width <= 4 * height, f"{f.name} is a {width}x{height} strip"
    # the energy cut-off in closed form and the delta = 0 crossing of the 1/4 tongue,
    # against independent values (exact rational; root of scipy's Mathieu b_1)
    assert "47104/186543" in text and "eps = 0.25251 " in text
    q = brentq(lambda q: mathieu_b(1, q), 0.5, 1.5, xtol=1e-15)
    assert f"eps = {q / 2:.12f}" in text


def test_upper_side_grid():
    g = error_grid("1/4", (0.1,), (0.5,), "upper")
    assert g.labels() == ["energy (49)", "averaging case 3"]
    text = _grid_table(g)
    r = g.rows[("averaging case 3", 0.1, 0.5)]
    assert "x(pi) = 0.5" in text and f"{num(r.delta_error, 2)} / {num(r.max_error, 2)}" in text


def test_delta_signs_counts_and_locates_negative_delta():
    text = _delta_signs({"Figure 2": [(0.1, 0.2), (0.5, -0.02)], "Figure 6": [(0.01, 0.25)]})
    assert text.startswith("2 of 3 orbits have delta > 0 (delta from 0.2 to 0.25)")
    assert text.endswith("delta <= 0 only in Figure 2 at eps = 0.5")


def test_formula_table_marks_inherited_errors():
    from gfrf.periodic.formulas import FormulaCheck

    row = FormulaCheck(equation="(48)", quantity="q", printed="p", regenerated="r", agrees=False,
                       corrected="c", note="n", inherits="(47) second")
    assert "| no (inherits (47) second) |" in _formula_table([row])


def _comparison(label: str, delta_error: float, max_error: float, branch: str = "1/4"):
    from gfrf.periodic.compare import PeriodicComparison

    return PeriodicComparison(method=label.split(",")[0].split(" ")[0], branch=branch, eps=0.1,
                              order=None, amplitude_method=0.5, amplitude_exact=0.5,
                              delta_method=0.2 + delta_error, delta_exact=0.2,
                              delta_error=delta_error, max_error=max_error, seconds=0.0)


def _facts(errors: dict[str, tuple[float, float]], ham_rows=None, setting_rows=None):
    """Facts of a one-cell page: ``errors`` maps a method label to (|d delta|, max|dx|)."""
    from fractions import Fraction

    from gfrf.periodic.equation import load_model
    from gfrf.report.periodic import PeriodicFacts
    from gfrf.report.periodic_checks import ErrorGrid

    def grid(branch: str, labels: list[str]) -> ErrorGrid:
        rows = {(lab, 0.1, 0.5): _comparison(lab, *errors[lab], branch) for lab in labels}
        return ErrorGrid(branch=branch, eps_values=(0.1,), amplitudes=(0.5,), rows=rows)

    labels = list(errors)
    return PeriodicFacts(
        model=load_model(), checks=(), grid14=grid("1/4", labels),
        grid0=grid("0", [lab for lab in labels if not lab.startswith(("energy", "averaging"))]),
        grid_up=ErrorGrid(branch="1/4", eps_values=(), amplitudes=(), rows={}, side="upper"),
        conclusions=(), linear_rows=[], equation3_rows=[],
        ham_setting_rows=setting_rows or [[0.01, 0.005, 1.2, -0.2, "0: none (no root)"]],
        ham_rows=ham_rows or [[0.01, 0.24, 0.2, 1e-2, -0.9, 0.24, 1e-9]],
        fig2_rows=[], fig3_rows=[], fig8_rows=[], fig6_rows=[], fig7_rows=[], fig9_rows=[],
        fig10_rows=[], orbits={"Figure 2": [(0.1, 0.2)]}, energy_edge=Fraction(1, 4),
        ham_eps=0.5, eps_zero=0.45, eps_zero_05=0.47,
        figures={k: f"{k}.png" for k in ("fig2", "fig3", "fig6", "fig7", "fig8", "fig9",
                                          "fig10", "fig45", "chart")})


HOMOTOPY_BEST = {"perturbation, order 4": (1e-5, 1e-5), "homotopy, order 4": (1e-9, 1e-8),
                 "energy (48)": (1e-3, 1e-2), "averaging (58)": (1e-3, 1e-2)}


def test_page_names_the_method_with_the_smallest_errors():
    from gfrf.report.periodic import render

    page = render(_facts(HOMOTOPY_BEST))
    assert "eq (4), homotopy, order 4 is the most accurate method on the 1/4 branch" in page
    assert "here: its order-4 transition values are the most accurate of the four" in page
    assert "{" not in page  # every field of the layout filled
    # the numbers swapped: averaging now has the smallest errors, and the sentences follow
    swapped = dict(HOMOTOPY_BEST, **{"homotopy, order 4": (1e-3, 1e-2),
                                     "averaging (58)": (1e-9, 1e-8)})
    page = render(_facts(swapped))
    assert "eq (4), averaging (58) is the most accurate method on the 1/4 branch" in page
    assert "are the most accurate of the four" not in page
    assert "not the most accurate in the tables above (averaging (58) is)" in page


def test_a_method_without_an_orbit_is_never_the_most_accurate():
    from gfrf.report.periodic import render

    errors = dict(HOMOTOPY_BEST, **{"energy (48)": (float("inf"), float("inf"))})
    facts = _facts(errors)
    assert facts.most_accurate_orbit() == facts.most_accurate_transition() == \
        "homotopy, order 4"
    assert "homotopy, order 4 is the most accurate" in render(facts)


def test_transition_and_orbit_accuracy_are_ranked_separately():
    # perturbation has the best transition value, homotopy the best orbit
    errors = dict(HOMOTOPY_BEST, **{"perturbation, order 4": (1e-12, 1e-5)})
    facts = _facts(errors)
    assert facts.most_accurate_orbit() == "homotopy, order 4"
    assert facts.most_accurate_transition() == "perturbation, order 4"


def test_homotopy_setting_sentences_follow_the_rows():
    from gfrf.report.periodic import render

    page = render(_facts(HOMOTOPY_BEST))
    assert "eps <= 0.08) has no periodic orbit of (4):" in page
    assert "its (17) has gamma_0 < 0." in page
    assert "initial guess: the paper's h is not a converged choice." in page
    # an orbit found, gamma_0 > 0, and the paper's h at least as good as the best h
    page = render(_facts(HOMOTOPY_BEST,
                         ham_rows=[[0.05, 0.24, 0.24, 1e-9, -0.9, 0.24, 1e-6]],
                         setting_rows=[[0.05, 0.005, 0.9, 0.3, "0: x(0) = 0.1; 1/4: none"]]))
    assert "has a periodic orbit of (4) only at eps = 0.05:" in page
    assert "and a periodic orbit exists only at eps = 0.05 (see below)" in page
    assert "its (17) has gamma_0 < 0 only at some of them." in page
    assert "no better than the paper's at eps = 0.05." in page
