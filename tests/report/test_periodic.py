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
