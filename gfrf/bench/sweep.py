"""Throughput of verdict sweeps (points/s) in-process and on a 2-worker dask LocalCluster.

Grid: damping rho x length L of the hanging pendulum (Theorem 1).  Timed: ``gfrf
sweep`` in-process (symbolic template once, numeric work per point), the same grid on
a LocalCluster of two single-threaded worker processes (start-up timed separately,
the cluster warmed by one small sweep), and the naive baseline a user would write,
re-parsing the model file and calling ``verdict`` at each point.  Agreement: the
largest relative difference of r* between each table and the in-process one.  The
per-point cost split times each stage on its own over the grid's models: model
(template instantiation vs full parse), kernels (GFRF plans, compilation and H1..H3
on 100 frequency points, needed only by the norm lower bounds of ``gfrf verdict``),
norms (exact sups of the majorant, ||H1||), series (the certified radius r*).
"""

from __future__ import annotations

import math
import os
import time
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._data import MODELS_DIR
from gfrf.bench import BenchSection, load_note
from gfrf.bounds.majorant import majorant, radius
from gfrf.bounds.norms import h1_norm
from gfrf.kernels.recursion import GFRFGenerator
from gfrf.model.template import model_template, rebuild
from gfrf.stability.criteria import verdict
from gfrf.sweep.run import parse_axis, sweep

__all__ = ["run"]



def _per_point(stage: Callable[[Any], Any], items: list[Any]) -> float:
    start = time.perf_counter()
    for item in items:
        stage(item)
    return (time.perf_counter() - start) / len(items)


def _kernels(model: Any) -> None:
    gen = GFRFGenerator(model)  # fresh: no memoised plans from an earlier stage
    w = np.linspace(0.1, 3.0, 100)
    for n in (1, 2, 3):
        gen.evaluate(n, [w] * n, True)


def _series(maj: Any) -> None:
    radius(lambda x, r: maj.rhs(x, r), len(maj.powers))


def _max_rel(a: list[dict], b: list[dict]) -> float:
    worst = 0.0
    for x, y in zip(a, b, strict=True):
        if x["radius"] != y["radius"]:
            worst = max(worst, abs(x["radius"] - y["radius"]) / abs(y["radius"]))
    return worst


def cost_split(path: Path, names: list[str], points: list[dict[str, float]]
               ) -> dict[str, float]:
    """Seconds per point of each stage of a verdict sweep over ``points``."""
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    start = time.perf_counter()
    template = model_template(data, names, str(path))
    split = {"template (once)": time.perf_counter() - start}
    files = [template.instantiate(p) for p in points]
    split["model: template instantiation"] = _per_point(template.instantiate, points)
    split["model: full parse (naive)"] = _per_point(lambda p: rebuild(data, p), points)
    split["kernels: H1..H3 plans + 100 points"] = _per_point(lambda mf: _kernels(mf.plant),
                                                             files)
    split["norms: majorant sups + ‖H1‖"] = _per_point(
        lambda mf: (majorant(mf.plant), h1_norm(mf.plant)), files)
    majorants = [majorant(mf.plant) for mf in files]
    split["series: certified radius r*"] = _per_point(_series, majorants)
    split["whole verdict (with_norms=False)"] = _per_point(
        lambda mf: verdict(mf, 1, 1.0, with_norms=False), files)
    return split


def run(quick: bool) -> BenchSection:
    """Time the sweeps and the cost split; return the report section.

    Parameters
    ----------
    quick : bool
        A 6 x 4 grid instead of 12 x 8.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    path = MODELS_DIR / "hanging_pendulum.toml"
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    n_rho, n_l = (6, 4) if quick else (12, 8)
    axes = [parse_axis(f"rho=0.2:20:{n_rho}"), parse_axis(f"L=0.5:6:{n_l}")]
    load_local = os.getloadavg()
    local = sweep(data, axes, progress=False)
    n = len(local.rows)
    start = time.perf_counter()
    naive = [verdict(rebuild(data, p), 1, 1.0, with_norms=False)
             for p in ({"rho": r["rho"], "L": r["L"]} for r in local.rows)]
    t_naive = time.perf_counter() - start
    naive_err = max(abs(v.radius - r["radius"]) / r["radius"]
                    for v, r in zip(naive, local.rows, strict=True))
    rows = [[f"verdict sweep, {n} points", "in-process (template once)",
             f"{local.points_per_second:.3g} pts/s", "reference",
             f"template {local.template_seconds:.3f} s"],
            [f"verdict sweep, {n} points", "naive: parse file + verdict per point",
             f"{n / t_naive:.3g} pts/s", f"{naive_err:.1e}",
             f"in-process is {t_naive / local.seconds:.2g}x faster"]]
    notes = []
    try:
        from distributed import Client, LocalCluster

        start = time.perf_counter()
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            t_start = time.perf_counter() - start
            pool = client.get_executor()
            sweep(data, [parse_axis("rho=1:2:2")], scheduler=pool, workers=2, progress=False)
            load_cluster = os.getloadavg()
            warm = sweep(data, axes, scheduler=pool, workers=2, progress=False)
        speed_up = warm.points_per_second / local.points_per_second
        rows.append([f"verdict sweep, {n} points", "dask LocalCluster, 2 worker processes",
                     f"{warm.points_per_second:.3g} pts/s",
                     f"{_max_rel(warm.rows, local.rows):.1e}",
                     f"{speed_up:.2f}x in-process; cluster start {t_start:.1f} s"])
        notes.append(f"dask LocalCluster (2 single-threaded worker processes on this "
                     f"{os.cpu_count()}-core machine): {speed_up:.2f}x the in-process rate "
                     f"({warm.points_per_second:.3g} vs {local.points_per_second:.3g} pts/s), "
                     f"measured with a 1-minute load average of {load_cluster[0]:.2f} "
                     f"(in-process run: {load_local[0]:.2f}); other work on the machine "
                     f"lowers both rates and the speed-up.")
    except ImportError:
        notes.append("dask.distributed not installed: the cluster row was skipped.")
    sample = [{"rho": r["rho"], "L": r["L"]} for r in local.rows[:: max(1, n // 12)]]
    split = cost_split(path, ["rho", "L"], sample)
    total = split["whole verdict (with_norms=False)"]
    for stage, seconds in split.items():
        share = "" if stage.startswith(("template", "whole", "model: full", "kernels")) \
            else f"{100 * seconds / total:.0f}% of a verdict"
        rows.append([f"cost split, {len(sample)} points", stage, f"{1e3 * seconds:.3g} ms",
                     "", share])
    per_point = total + split["model: template instantiation"]
    notes.append(f"10^6-point estimate from the measured {1e3 * per_point:.3g} ms per "
                 f"point: {1e6 * per_point / 3600:.3g} core-hours, e.g. "
                 f"{1e6 * per_point / 3600 / 64:.2g} h on 64 worker cores "
                 f"(tasks of 64 points: ~{math.ceil(1e6 / 64)} tasks).")
    notes.append("Kernels are not used by a verdict sweep (with_norms=False decides from "
                 "the majorant); their row is what 'gfrf verdict' adds per model for the "
                 "norm lower bounds.")
    notes.append(load_note(load_local))
    return BenchSection(
        title="Parameter sweeps: throughput and per-point cost (hanging pendulum rho x L)",
        intro=__doc__.split("\n\n", 1)[1].strip(),
        columns=["what", "method", "rate or time per point", "max rel. diff of r*", "note"],
        rows=rows, notes=notes)
