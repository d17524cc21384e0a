"""Tests for gfrf.report and ``gfrf report``: quick build, provenance of numbers, determinism."""

from __future__ import annotations

from pathlib import Path

import pytest

from gfrf.cli import main
from gfrf.papers.gfrf_paper import coefficient_rows, paper_checks
from gfrf.report import MODELS_DIR, bundled_models, paper_gfrf, write_reports
from gfrf.report._format import bracket_cells, cell, table
from gfrf.report.analysis import analyse
from gfrf.report.paper_gfrf import check_table
from gfrf.stability.criteria import parameter_margin


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One quick build of every report (the CI setting)."""
    out = tmp_path_factory.mktemp("reports")
    write_reports(out, quick=True)
    return out


def _pages(out: Path) -> list[Path]:
    return sorted(out.glob("*.md")) + sorted((out / "models").glob("*.md"))


@pytest.mark.slow  # the quick build of every report: minutes of CPU
def test_quick_build_writes_every_report(built: Path) -> None:
    stems = {Path(p).stem for p in bundled_models()}
    assert "parametric_pendulum" not in stems
    assert {p.stem for p in (built / "models").glob("*.md")} == stems
    assert (built / "paper-gfrf.md").is_file() and (built / "README.md").is_file()
    for page in _pages(built):
        if page.name.startswith("paper-periodic"):
            continue
        lines = page.read_text(encoding="utf-8").splitlines()
        assert lines[0].startswith("# ")
        assert all(line.startswith("> ") for line in lines[2:5]), page
        assert "Regenerate: `gfrf report" in page.read_text(encoding="utf-8")
        for ref in (x.split("](")[1].split(")")[0] for x in lines if "![" in x):
            assert (page.parent / ref).is_file(), (page, ref)


@pytest.mark.slow  # the quick build of every report: minutes of CPU
def test_paper_table_cells_come_from_the_rows(built: Path) -> None:
    rows = paper_checks(MODELS_DIR)
    rendered = check_table(rows)
    assert rendered in (built / "paper-gfrf.md").read_text(encoding="utf-8")
    body = rendered.splitlines()[2:]
    assert len(body) == len(rows)
    for line, row in zip(body, rows, strict=True):
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        assert cells[0] == cell(row.section)
        assert cells[2] == cell(row.paper)
        assert cells[3] == cell(row.ours)
        assert cells[4] == ("**yes**" if row.match else "no")
        assert cells[5] == cell(row.reason)


@pytest.mark.slow  # the quick build of every report: minutes of CPU
def test_model_page_numbers_come_from_the_verdict(built: Path) -> None:
    a = analyse(str(MODELS_DIR / "hanging_pendulum.toml"), True)
    text = (built / "models" / "hanging_pendulum.md").read_text(encoding="utf-8")
    assert f"r* = **{cell(a.verdict.radius)}**" in text
    for b in a.verdict.norms:  # rounded outward to the digits the bracket proves
        lower, upper, gap = bracket_cells(b.lower, b.upper)
        assert f"| {b.order} | {lower} | {upper} | {gap} |" in text
        if b.gap > 1e-4:  # an open bracket: rounded outward (closed ones: nearest)
            assert float(lower) <= b.lower and float(upper) >= b.upper
    for c in a.verdict.conditions:
        assert cell(c.detail) in text


@pytest.mark.slow  # the quick build of every report: minutes of CPU
def test_model_page_margins_come_from_parameter_margin(built: Path) -> None:
    a = analyse(str(MODELS_DIR / "hanging_pendulum.toml"), True)
    text = (built / "models" / "hanging_pendulum.md").read_text(encoding="utf-8")
    assert "## Margins" in text
    scans = {s.parameter: s for s in a.margins}
    assert list(scans) == ["m", "L", "rho", "g"]
    rho = scans["rho"].margin
    assert rho is not None and rho.direction == "above"
    assert rho == parameter_margin(a.model_file, "rho", tolerance=rho.tolerance)
    assert "`gfrf verdict models/hanging_pendulum.toml --margin rho`" in text
    for s in scans.values():
        if s.margin is None:
            assert f"- {s.parameter} (file value {cell(s.current)}): {s.note}." in text
    assert "## Margins" not in (built / "models" / "duffing.md").read_text(encoding="utf-8")


def test_cartpole_coefficient_rows_match_closed_forms() -> None:
    rows = {r.quantity: r for r in coefficient_rows(MODELS_DIR / "cartpole.toml")}
    big_m, m, length, g = 0.145, 0.03, 0.125, 9.8
    d = 4 * big_m + m
    assert rows["eq (12) coefficient of theta"].ours == pytest.approx(-3 * (big_m + m) * g
                                                                      / (d * length))
    assert rows["eq (12) coefficient of theta**3"].ours == pytest.approx(
        (big_m + m) * g / (2 * d * length))
    assert rows["eq (12) coefficient of theta**2*D(theta,2)"].ours == pytest.approx(3 * m / d)
    assert rows["eq (12) coefficient of theta*D(theta)**2"].match
    assert rows["eq (12) coefficient of u"].ours == pytest.approx(3 / (d * length))
    assert rows["eq (12) coefficient of theta**2*u"].ours == pytest.approx(
        -3 / (2 * d * length))
    assert not rows["eq (13) linear coefficient (vs eq (12))"].match


@pytest.mark.slow  # two more quick builds
def test_two_runs_are_identical(built: Path, tmp_path: Path) -> None:
    analyse.cache_clear()
    write_reports(tmp_path, bundled_models(), quick=True)  # the model pages
    paper_gfrf.write(tmp_path, quick=True)
    for page in _pages(tmp_path):
        page = built / page.relative_to(tmp_path)
        other = tmp_path / page.relative_to(built)
        first = page.read_text(encoding="utf-8").replace(str(built), "OUT")
        assert first == other.read_text(encoding="utf-8").replace(str(tmp_path), "OUT"), page
    for png in sorted(tmp_path.rglob("*.png")):
        assert png.read_bytes() == (built / png.relative_to(tmp_path)).read_bytes(), png


def test_cli_report_one_model(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", "--quick", "--out", str(tmp_path),
                 str(MODELS_DIR / "duffing.toml")]) == 0
    assert [p.name for p in _pages(tmp_path)] == ["duffing.md"]
    assert "wrote" in capsys.readouterr().out
    assert main(["report", "--out", str(tmp_path), "not-a-model"]) == 2


def test_table_escapes_pipes() -> None:
    assert table(["||H1||"], [["a|b"]]).splitlines()[2] == "| a\\|b |"
