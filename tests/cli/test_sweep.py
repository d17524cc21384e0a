"""gfrf sweep's words: r* of unstable plants, and a sweep where every point fails."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

import gfrf.sweep.run
from gfrf.cli import main


def _file(folder: Path) -> Path:
    path = folder / "damped.toml"
    path.write_text('name = "damped"\nequation = "D(y,2) + c*D(y) + y + y**3 = u"\n'
                    "[parameters]\nc = 0.2\n", encoding="utf-8")
    return path


def test_unstable_points_are_not_given_a_stability_radius(tmp_path: Path,
                                                          capsys: pytest.CaptureFixture
                                                          ) -> None:
    """c = -1: poles 0.5 +- 0.87j (unstable); c = 0.5 stable."""
    code = main(["sweep", str(_file(tmp_path)), "--param", "c=-1:0.5:2"])
    out = capsys.readouterr().out
    assert code == 0
    assert "1 point(s) with an unstable linear part" in out
    assert "no stability radius" in out


def test_a_sweep_where_every_point_fails_says_it_once(tmp_path: Path,
                                                      capsys: pytest.CaptureFixture,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    def fail(task: Any, point: dict[str, float]) -> dict[str, Any]:
        return {**point, "error": "ModelError: the model broke"}

    monkeypatch.setattr(gfrf.sweep.run, "evaluate_point", fail)
    code = main(["sweep", str(_file(tmp_path)), "--param", "c=0.1:0.5:2"])
    out, err = capsys.readouterr()
    assert code == 1
    assert (out + err).count("2 of 2 point(s) failed") == 1
    assert err.startswith("gfrf: error: no grid point succeeded")
