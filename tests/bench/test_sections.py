"""Every section of ``gfrf bench`` runs in quick mode and gives a table (the full
benchmark is only run by ``make bench``; this keeps each section's code path tested)."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from gfrf.bench import SECTION_MODULES, BenchSection


@pytest.mark.slow
@pytest.mark.parametrize("name", SECTION_MODULES)
def test_each_bench_section_runs_quickly_and_gives_a_table(
        name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GFRF_REPORT_DIR", str(tmp_path))  # its figures, if any
    section = importlib.import_module(name).run(True)
    assert isinstance(section, BenchSection)
    assert section.rows and all(len(row) == len(section.columns) for row in section.rows)
    text = section.to_markdown()
    assert text.startswith(f"## {section.title}") and "nan" not in text.lower().split()
    assert "OUTSIDE" not in text  # a baseline's value outside gfrf's certified bracket
    for figure in section.figures:
        assert (tmp_path / figure).is_file()
