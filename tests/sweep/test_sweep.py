"""Parameter sweeps: grid syntax, templates, closed-form radii, margins, dask, CLI."""

from __future__ import annotations

import csv
import json
import tomllib
from dataclasses import replace
from pathlib import Path

import mpmath as mp
import pytest

from gfrf.cli import main
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.model.template import model_template, rebuild
from gfrf.stability.criteria import parameter_margin, verdict
from gfrf.sweep.run import grid, parse_axis, sweep

MODELS = Path(__file__).resolve().parents[2] / "models"
PENDULUM = MODELS / "hanging_pendulum.toml"
CARTPOLE = MODELS / "cartpole.toml"


def table(path: Path) -> dict:
    return tomllib.loads(path.read_text(encoding="utf-8"))


def test_parse_axis_includes_both_ends() -> None:
    axis = parse_axis("rho=0.5:2:4")
    assert axis.name == "rho"
    assert axis.values == pytest.approx((0.5, 1.0, 1.5, 2.0), rel=1e-15)
    assert parse_axis("L = 3:9:1").values == (3.0,)


def test_grid_is_row_major_and_refuses_repeats() -> None:
    points = grid([parse_axis("a=1:2:2"), parse_axis("b=10:30:3")])
    assert [(p["a"], p["b"]) for p in points] == [(1, 10), (1, 20), (1, 30),
                                                   (2, 10), (2, 20), (2, 30)]
    with pytest.raises(ArgumentError, match="'a' is swept twice"):
        grid([parse_axis("a=1:2:2"), parse_axis("a=1:2:2")])


@pytest.mark.parametrize(("path", "values"), [
    (PENDULUM, {"rho": 0.37, "L": 2.9, "g": 9.7}),
    (CARTPOLE, {"a": 12.5, "b": 250.0, "c": 0.4}),
])
def test_template_matches_a_full_parse(path: Path, values: dict) -> None:
    data = table(path)
    fast = model_template(data, list(values), str(path)).instantiate(values)
    slow = rebuild(data, values, str(path))
    coefficients = {(t.y_orders, t.u_orders): t.coefficient for t in slow.plant.terms}
    assert {(t.y_orders, t.u_orders) for t in fast.plant.terms} == set(coefficients)
    for t in fast.plant.terms:
        assert t.coefficient == pytest.approx(coefficients[(t.y_orders, t.u_orders)], rel=1e-15)
    if slow.controller is not None:
        assert fast.controller.num == pytest.approx(slow.controller.num, rel=1e-15)
        assert fast.controller.den == pytest.approx(slow.controller.den, rel=1e-15)


def test_models_differing_only_in_coefficients_get_their_own_kernels() -> None:
    # Regression: Model equality ignores coefficients, and the generator cache was keyed
    # on the model only, so a sweep's second point reused the first point's kernels.
    a = parse_model("D(y) + y = u")
    b = replace(a, terms=tuple(replace(t, coefficient=2.0) if t.y_orders == (0,) else t
                               for t in a.terms))
    assert complex(kernel(a, 1)(0.0)) == pytest.approx(1.0)
    assert complex(kernel(b, 1)(0.0)) == pytest.approx(0.5)


def pendulum_radius(rho: float, length: float, g: float = 9.8) -> float:
    """Closed form r* = 2 / (3 beta sqrt(3 |c3| beta)) of theta'' + c theta' + w0^2 theta
    + c3 theta^3 = u (unit mass), with beta = sup|1/A| and c3 = -g/(6L)."""
    c, w0sq = mp.mpf(rho) / mp.mpf(length) ** 2, mp.mpf(g) / mp.mpf(length)
    beta = 1 / (c * mp.sqrt(w0sq - c ** 2 / 4)) if c ** 2 < 2 * w0sq else 1 / w0sq
    c3 = mp.mpf(g) / (6 * mp.mpf(length))
    return float(2 / (3 * beta * mp.sqrt(3 * c3 * beta)))


def test_radius_sweep_matches_the_closed_form() -> None:
    result = sweep(table(PENDULUM), [parse_axis("rho=0.2:20:3"), parse_axis("L=0.5:4:2")],
                   what="radius", progress=False)
    assert len(result.rows) == 6
    for row in result.rows:
        assert row["error"] == ""
        assert row["radius"] == pytest.approx(pendulum_radius(row["rho"], row["L"]), rel=1e-8)


def test_damping_boundary_agrees_with_the_margin_bisection() -> None:
    mf = load_model(PENDULUM)
    margin = parameter_margin(mf, "rho", tolerance=1e-6)
    assert margin.direction == "above"
    result = sweep(table(PENDULUM), [parse_axis("rho=13:17:9")], progress=False)
    for row in result.rows:
        expected = "stable" if row["rho"] > margin.value else "inconclusive"
        assert row["verdict"] == expected, row
        direct = verdict(rebuild(table(PENDULUM), {"rho": row["rho"]}), 1, 1.0,
                         with_norms=False)
        assert direct.verdict == row["verdict"]
        assert direct.radius == pytest.approx(row["radius"], rel=1e-12)
    assert {r["verdict"] for r in result.rows} == {"stable", "inconclusive"}


def test_in_process_and_two_worker_cluster_give_identical_tables() -> None:
    pytest.importorskip("distributed")
    axes = [parse_axis("rho=1:15:3"), parse_axis("L=1:4:2")]
    local = sweep(table(PENDULUM), axes, progress=False)
    cluster = sweep(table(PENDULUM), axes, scheduler="processes", workers=2, chunk_size=2,
                    progress=False)
    assert cluster.rows == local.rows
    assert cluster.columns == local.columns


def test_invalid_point_becomes_an_error_row() -> None:
    data = {"equation": "kappa*y + D(y)**2 + y**3 = u", "parameters": {"kappa": 1.0}}
    rows = sweep(data, [parse_axis("kappa=0:1:2")], progress=False).rows
    assert "no linear term in the output" in rows[0]["error"]
    assert rows[1]["error"] == "" and rows[1]["verdict"] in ("stable", "inconclusive")


def test_cartpole_gain_sweep_marks_unstable_closed_loops() -> None:
    # Eq (12) linearised, theta'' - 67.578 theta + 39.3185 u = 0, with u = -(a s^2 + b s + c)
    # theta: (1 - 39.3185 a) s^2 - 39.3185 b s - (67.578 + 39.3185 c).  With b, c > 0 it is
    # Hurwitz (all coefficients of one sign) exactly when a > 1 / 39.3185 = 0.025433.
    rows = sweep(table(CARTPOLE), [parse_axis("a=0.0:0.05:6")], progress=False).rows
    assert [r["linear_stable"] for r in rows] == [a > 1 / 39.3185 for a in
                                                  (0.0, 0.01, 0.02, 0.03, 0.04, 0.05)]
    assert [r["verdict"] for r in rows[:3]] == ["unstable"] * 3


def test_bounded_sweep_simulates() -> None:
    rows = sweep(table(PENDULUM), [parse_axis("rho=0.05:40:2")], what="bounded",
                 amplitude=0.05, t_end=5.0, progress=False).rows
    assert [r["bounded"] for r in rows] == [True, True]
    assert rows[1]["peak"] < rows[0]["peak"]


def test_cli_writes_table_map_and_json(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out, plot = tmp_path / "map.csv", tmp_path / "map.png"
    code = main(["sweep", str(PENDULUM), "--param", "rho=10:20:3", "--param", "L=3:4:2",
                 "--out", str(out), "--plot", str(plot), "--json"])
    payload = json.loads(capsys.readouterr().out)
    assert code == 0
    assert payload["points"] == 6 and payload["columns"][:2] == ["rho", "L"]
    with out.open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert [float(r["rho"]) for r in rows] == [10, 10, 15, 15, 20, 20]
    assert plot.stat().st_size > 1000


def test_cli_parquet_round_trip(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "map.parquet"
    assert main(["sweep", str(PENDULUM), "--param", "rho=1:2:2", "--what", "norm",
                 "--out", str(out)]) == 0
    capsys.readouterr()
    data = pq.read_table(out).to_pylist()
    assert [r["rho"] for r in data] == [1.0, 2.0]
    assert all(r["h1"] > 0 and r["M3"] > 0 for r in data)


def test_map_classes_and_dimension_limit(tmp_path: Path) -> None:
    from gfrf.sweep.plot import plot_stability_map, point_class

    assert point_class({"error": "bad", "linear_stable": True}) == "error"
    assert point_class({"error": "", "linear_stable": False, "verdict": "unstable"}) \
        == "linear unstable"
    assert point_class({"error": "", "linear_stable": True, "verdict": "stable"}) == "stable"
    result = sweep(table(CARTPOLE), [parse_axis("a=0:20:2"), parse_axis("b=300:400:2"),
                                     parse_axis("c=0.1:1:2")], what="radius", progress=False)
    with pytest.raises(ArgumentError, match="one or two swept parameters, got 3"):
        plot_stability_map(result, tmp_path / "x.png")


@pytest.mark.slow
def test_scheduler_address(capsys: pytest.CaptureFixture) -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1,
                                  dashboard_address=None) as cluster:
        code = main(["sweep", str(PENDULUM), "--param", "rho=14:16:3", "--json",
                     "--scheduler", cluster.scheduler_address])
    payload = json.loads(capsys.readouterr().out)
    assert code == 0
    assert payload["scheduler"] == cluster.scheduler_address
    assert [r["verdict"] for r in payload["rows"]] == ["inconclusive", "inconclusive", "stable"]


NARX = {"equation": "y[k] = a*y[k-1] + b*y[k-1]**2*u[k-2] + u[k-1]", "sample_time": 0.1,
        "parameters": {"a": 0.5, "b": -0.2}}
POLYNOMIAL_LOOP = {"equation": "D(y,2) + 0.5*D(y) - y + 0.3*y**3 = u",
                   "controller": {"equation": "u = kp*y + q*D(y) + g*y**3",
                                  "parameters": {"kp": 3.0, "q": 1.0, "g": 0.1}}}


@pytest.mark.parametrize(("data", "axes", "route"), [
    (NARX, ["a=0.2:0.9:3", "b=-0.2:-0.01:2"], "template"),
    (POLYNOMIAL_LOOP, ["kp=0.5:20:3", "g=0:0.5:2"], "template"),
    ({**NARX, "sample_time": "T", "parameters": {"T": 0.1, **NARX["parameters"]}},
     ["T=0.1:0.2:2", "a=0.3:0.6:2"], "rebuild"),
])
def test_narx_and_polynomial_controller_sweeps_match_direct_verdicts(
        data: dict, axes: list[str], route: str) -> None:
    result = sweep(data, [parse_axis(a) for a in axes], progress=False)
    assert result.columns[-2:] == ["path", "error"]
    for row in result.rows:
        assert row["error"] == "" and row["path"] == route, row
        point = {a.name: row[a.name] for a in result.axes}
        direct = verdict(rebuild(data, point), 1, 1.0, with_norms=False)
        assert (row["verdict"], row["theorem"]) == (direct.verdict, direct.theorem)
        assert row["radius"] == pytest.approx(direct.radius, rel=1e-12, abs=1e-300)
    assert (route == "rebuild") == any("re-parsed" in n for n in result.notes)


def test_polynomial_controller_template_matches_a_full_parse() -> None:
    values = {"kp": 7.5, "q": 0.25, "g": -0.4}
    fast = model_template(POLYNOMIAL_LOOP, list(values)).instantiate(values)
    slow = rebuild(POLYNOMIAL_LOOP, values)
    assert fast.controller.model.terms == slow.controller.model.terms
    assert [t.coefficient for t in fast.controller.model.terms] == pytest.approx(
        [t.coefficient for t in slow.controller.model.terms], rel=1e-15)
    rows = sweep(POLYNOMIAL_LOOP, [parse_axis("kp=0.5:20:3")], progress=False).rows
    assert {r["verdict"] for r in rows} >= {"unstable"}


def test_progress_moves_per_point_from_the_first(monkeypatch: pytest.MonkeyPatch) -> None:
    import tqdm as tqdm_module

    import gfrf.stability.criteria

    reported: list[int] = []
    seen_at_call: list[int] = []

    class Bar:
        def __init__(self, *args: object, **kwargs: object) -> None:
            pass

        def __enter__(self) -> Bar:
            return self

        def __exit__(self, *exc: object) -> None:
            pass

        def update(self, n: int) -> None:
            reported.append(n)

    real = gfrf.stability.criteria.verdict

    def counting(*args: object, **kwargs: object) -> object:
        seen_at_call.append(sum(reported))
        return real(*args, **kwargs)

    monkeypatch.setattr(tqdm_module, "tqdm", Bar)
    monkeypatch.setattr(gfrf.stability.criteria, "verdict", counting)
    data = {"equation": "D(y,2) + c*D(y) + y + 0.5*y**3 = u", "parameters": {"c": 0.2}}
    sweep(data, [parse_axis("c=0.1:0.4:5")], what="radius", progress=True)
    assert reported == [1] * 5
    assert seen_at_call == [0, 1, 2, 3, 4]  # point k starts after k points were shown


def test_map_title_drops_the_file_value_of_a_swept_parameter() -> None:
    from gfrf.sweep.plot import map_title
    from gfrf.sweep.run import Axis, SweepResult

    result = SweepResult(axes=(Axis("rho", (0.2, 1.0, 4.0)),), what="verdict", amplitude=1.0,
                         rows=[], columns=[], seconds=0.0, template_seconds=0.0,
                         scheduler="local")
    title = map_title(result, "Hanging pendulum, rho = 8 (damped variant), rho_1 = 1.29")
    assert "rho = 8" not in title and "0.8" not in title
    assert title == ("Hanging pendulum (damped variant), rho_1 = 1.29\n"
                     "swept: rho from 0.2 to 4 (3 values)")
