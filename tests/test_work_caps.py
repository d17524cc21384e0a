"""Tight brackets by default, work caps, memory caps, linear tone parsing,
CPU-independent report figures, ``gfrf bench`` from any directory."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import gfrf.bounds.branch_bound as bbm
from gfrf.bounds.branch_bound import (
    LEAST_BUDGET,
    box_bounds,
    box_work,
    branch_and_bound,
    default_budget,
)
from gfrf.bounds.norms import DEFAULT_TOL, kernel_norm
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.model.signals import FAST_TONES, parse_input
from gfrf.model.tones import read_tone_sum
from gfrf.report._format import bracket_cells

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"


def _grid_max(model: object, n: int, half: float, points: int = 20000) -> float:
    """|H_n| maximised over random points of [-half, half]^n (an independent lower bound)."""
    w = np.random.default_rng(3).uniform(-half, half, size=(n, points))
    values = np.abs(kernel(model, n)(*w))
    return float(np.max(values[np.isfinite(values)]))


def test_default_budget_is_work_from_the_kernel_size() -> None:
    pendulum = load_model(MODELS / "hanging_pendulum.toml").plant
    cartpole = load_model(MODELS / "cartpole_reduced.toml").plant
    # the reduced cart-pole's H5 code is about twice the pendulum's: fewer boxes fit
    assert box_work(cartpole, 5) > 1.5 * box_work(pendulum, 5)
    assert LEAST_BUDGET <= default_budget(cartpole, 5) < default_budget(pendulum, 5)
    # both H5 close to 1e-3 within it (measured: 7,191 and 54,683 boxes)
    assert default_budget(cartpole, 5) >= 7_191 and default_budget(pendulum, 5) >= 54_683
    assert default_budget(pendulum, 5) == default_budget(pendulum, 5)  # a count, no clock


def test_default_tolerance_is_1e_3() -> None:
    assert DEFAULT_TOL == 1e-3
    m = load_model(MODELS / "cartpole_reduced.toml").plant
    b = kernel_norm(m, 3)
    grid = _grid_max(m, 3, 20.0)
    assert b.gap <= 1e-3 and grid <= b.upper * (1 + 1e-12)
    assert b.lower >= grid * (1 - 1e-9)  # the local search beats random points


@pytest.mark.slow
def test_default_norm_order_5_closes_the_bundled_cartpole_reduced() -> None:
    m = load_model(MODELS / "cartpole_reduced.toml").plant
    b = kernel_norm(m, 5)
    assert b.gap <= 1e-3
    assert _grid_max(m, 5, 20.0) <= b.upper * (1 + 1e-12)


def _reduced_cartpole_h3() -> float:
    """||H3|| of the reduced cart-pole in closed form (see tests/bounds/test_norms.py)."""
    beta1 = 39.3185 / 67.578
    return (19.66 * beta1**2 - 11.2455 * beta1**3) / 67.578


def test_open_box_cap_stops_with_a_sound_bracket(monkeypatch: pytest.MonkeyPatch) -> None:
    m = load_model(MODELS / "cartpole_reduced.toml").plant
    monkeypatch.setattr(bbm, "MAX_OPEN", 40)
    capped = branch_and_bound(m, 3, tol=1e-14, max_boxes=200_000)
    assert capped.stop == "open boxes" and not capped.converged
    assert capped.boxes < 2000  # it stopped at the cap, not at the budget
    assert capped.lower <= _reduced_cartpole_h3() * (1 + 1e-12) <= capped.upper * (1 + 1e-12)


def test_budget_stop_is_reported_in_the_notes() -> None:
    m = load_model(MODELS / "cartpole_reduced.toml").plant
    b = kernel_norm(m, 3, tol=1e-14, max_boxes=30)
    assert any("stopped at" in note and "--max-boxes" in note for note in b.notes)
    assert b.lower <= _reduced_cartpole_h3() * (1 + 1e-12) <= b.upper * (1 + 1e-12)


def test_enclosure_reuses_inverse_jets_without_changing_bounds(
        monkeypatch: pytest.MonkeyPatch) -> None:
    import gfrf.bounds.enclosure as enclosure

    m = load_model(MODELS / "cartpole_reduced.toml").plant
    rng = np.random.default_rng(0)
    centre, radius = rng.uniform(-30, 30, (64, 3)), rng.uniform(0.01, 2.0, (64, 3))
    cached = box_bounds(m, 3, centre - radius, centre + radius)

    def fresh(self: object, block: tuple[int, ...]) -> object:
        return self._factor(block, self.inverse.point, self.inverse.bounds)  # type: ignore[attr-defined]

    monkeypatch.setattr(enclosure._Boxes, "inv_a", fresh)
    recomputed = box_bounds(m, 3, centre - radius, centre + radius)
    for a, b in zip(cached, recomputed, strict=True):
        np.testing.assert_array_equal(a, b)


def test_bracket_cells_round_outward_to_the_proven_digits() -> None:
    lower, upper, gap = bracket_cells(0.0111398, 0.0209773)
    assert (lower, upper) == ("0.0111", "0.021")  # gap 0.47: three digits
    assert float(lower) <= 0.0111398 and float(upper) >= 0.0209773
    assert float(gap) >= (0.0209773 - 0.0111398) / 0.0209773
    # two floats differing in the last bits print the same text
    x = 9195104.712345
    assert bracket_cells(x, 1.001 * x) == bracket_cells(x * (1 + 4e-16), 1.001 * x)
    # a bracket closed to rounding keeps six digits, nearest
    assert bracket_cells(0.581824, 0.581824 * (1 + 2e-16))[:2] == ("0.581824", "0.581824")
    assert bracket_cells(0.0, 0.0) == ("0", "0", "0")
    assert bracket_cells(1.0, math.inf)[1:] == ("inf", "inf")


def _tone_text(count: int) -> str:
    return " + ".join(
        f"{(-1) ** k * 0.001 * (k + 1):.5g}*{'sin' if k % 3 else 'cos'}("
        f"{(1 + 0.01 * k) * (-1) ** (k // 2):.4f}*t {'+' if k % 2 else '-'} {0.1 * k:.3g})"
        for k in range(count))


def test_tone_sum_matches_the_general_parser(monkeypatch: pytest.MonkeyPatch) -> None:
    import gfrf.model.signals as signals

    text = _tone_text(FAST_TONES + 8)
    fast = parse_input(text, max_derivative=3)
    assert fast.expr is None and len(read_tone_sum(text) or []) == FAST_TONES + 8
    monkeypatch.setattr(signals, "FAST_TONES", 10**9)
    slow = parse_input(text, max_derivative=3)  # sympy, lambdify and sp.diff
    t = np.linspace(-3.0, 40.0, 777)
    for k in range(4):
        np.testing.assert_allclose(fast.derivative(k)(t), slow.derivative(k)(t),
                                   rtol=0, atol=1e-13 * (1 + 1.05 ** (FAST_TONES * k)))
        assert fast.derivative(k)(1.3) == pytest.approx(float(slow.derivative(k)(1.3)),
                                                        abs=1e-12)
    np.testing.assert_allclose(sorted(fast.tones), sorted(slow.tones), atol=1e-14)
    assert fast.breakpoints(10.0).size == 0 and fast.impulses(10.0).size == 0
    assert read_tone_sum("sin(t)**2") is None and read_tone_sum("0.1*sin(2*pi*t)") is None


def test_two_thousand_tones_parse_in_well_under_a_second() -> None:
    text = " + ".join(f"0.001*sin({1 + 0.01 * k:.4f}*t)" for k in range(2000))
    start = time.process_time()
    u = parse_input(text, max_derivative=2)
    assert time.process_time() - start < 1.0  # CPU s (8 s without the cap)
    assert len(u.tones) == 2000
    assert float(u(0.5)) == pytest.approx(
        sum(0.001 * math.sin((1 + 0.01 * k) * 0.5) for k in range(2000)), abs=1e-12)


@pytest.mark.slow
def test_bench_runs_from_any_directory_and_writes_nothing(tmp_path: Path) -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, "-c", "import sys; from gfrf.cli import main; "
                          "sys.exit(main())", "bench", "--quick", "--only", "brackets",
                          "--json"], cwd=tmp_path, capture_output=True, text=True, env=env,
                         timeout=300)
    assert out.returncode == 0, out.stderr
    payload = json.loads(out.stdout)
    assert payload["report"] is None and payload["sections"][0]["rows"]
    assert list(tmp_path.iterdir()) == []  # no reports/ left behind


def test_a_budget_above_the_default_is_announced_with_its_time() -> None:
    from gfrf.bounds.branch_bound import budget_note

    m = load_model(MODELS / "cartpole_reduced.toml").plant
    cap = default_budget(m, 3)
    assert budget_note(m, 3, True, cap) is None
    note = budget_note(m, 3, True, 100 * cap)
    assert note is not None and "allows up to about" in note and str(cap) in note
    assert "at most 500000 open boxes, 32 MB" in note  # 500000 boxes of 2*3+2 doubles
    seconds = float(note.split("about ")[1].split(" s")[0])
    default_seconds = float(note.split("about ")[2].split(" s")[0])
    assert seconds == pytest.approx(100 * default_seconds, rel=0.1)


def test_a_kernel_order_beyond_about_10_s_is_refused_before_the_work() -> None:
    from gfrf.errors import ArgumentError
    from gfrf.kernels.recursion import MAX_PLAN_TERMS

    m = parse_model("D(y,2)+0.2*D(y)+y+0.3*y**2+0.1*D(y)**2+0.2*y*D(y)+0.1*y**3 = u")
    start = time.process_time()
    with pytest.raises(ArgumentError, match="largest order that fits is 8") as info:
        kernel(m, 12)  # runs for more than 600 s without the cap
    assert time.process_time() - start < 5.0
    assert f"MAX_PLAN_TERMS = {MAX_PLAN_TERMS}" in str(info.value) and "--max-work" in str(
        info.value)
    assert kernel(m, 5)(1.0, 1.0, 1.0, 1.0, -1.0) is not None  # small orders still answer


def test_tight_verdict_orders_share_one_work_cap(monkeypatch: pytest.MonkeyPatch) -> None:
    import gfrf.stability.theorem1 as theorem1
    from gfrf.stability.criteria import verdict

    m = load_model(MODELS / "cartpole_reduced.toml").plant
    monkeypatch.setattr(theorem1, "DEFAULT_WORK", 50 * box_work(m, 3) + box_work(m, 5))
    v = verdict(m, 5, 0.1, norms="tight")
    spent = sum(b.boxes * box_work(m, b.order) for b in v.norms if 2 <= b.order <= 5)
    assert 0 < spent <= 50 * box_work(m, 3) + box_work(m, 5) + 2 * 2048 * box_work(m, 5)
    assert all(b.upper >= b.lower for b in v.norms)
    assert v.norms[2].lower <= _reduced_cartpole_h3() * (1 + 1e-12) <= v.norms[2].upper * (
        1 + 1e-12)
