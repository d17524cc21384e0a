"""``gfrf sweep``: verdict, radius r*, norms or boundedness over a parameter grid.

``gfrf sweep MODEL --param NAME=START:STOP:N [--param ...] [--what verdict|radius|norm|
bounded] [--scheduler local|processes|ADDRESS] [--out FILE.csv|.parquet] [--plot FILE.png]
[--json]`` evaluates the quantity at every grid point (see :mod:`gfrf.sweep.run`), prints
a summary (points per class, range of r*, throughput), writes the table and the
stability map.  Exit code 0 when the sweep ran (whatever the verdicts), 1 when no grid
point succeeded (stderr names the cause), 2 on bad input.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections import Counter

from gfrf.cli._output import add_json_flag, check_output_file, check_plot_path, emit
from gfrf.sweep.run import (
    SCHEDULER_TIMEOUT,
    WHAT,
    SweepResult,
    check_output,
    check_scheduler,
    parse_axis,
    sweep,
)

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``sweep``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    p = subparsers.add_parser(
        "sweep", help="stability map: verdict / r* / norms / simulations over a parameter grid",
        description="Evaluate the verdict and certified radius r* (or norms, or simulated "
                    "boundedness) at every point of a grid over model-file parameters, "
                    "in-process or on a dask cluster; write the table and a stability map.")
    p.add_argument("model", metavar="MODEL",
                   help="a model file (models/*.toml; a bundled model by its name)")
    p.add_argument("--param", action="append", required=True, metavar="NAME=START:STOP:N",
                   help="a swept parameter of [parameters] or controller.parameters, N values "
                        "from START to STOP inclusive; repeat for a grid")
    p.add_argument("--what", choices=WHAT, default="verdict",
                   help="quantity per point (default verdict)")
    p.add_argument("--amplitude", type=float, default=1.0, metavar="R",
                   help="input amplitude r of the verdict and simulations (default 1)")
    p.add_argument("--order", type=int, default=5,
                   help="highest majorant order of --what norm (default 5)")
    p.add_argument("--t-end", type=float, default=50.0, metavar="T",
                   help="simulated time in s of --what bounded (default 50)")
    p.add_argument("--scheduler", default="local",
                   help="'local' (in-process, default), 'processes' (dask LocalCluster, one "
                        "worker per core) or a dask scheduler address tcp://host:port, "
                        f"which must answer within {SCHEDULER_TIMEOUT:g} s")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of --scheduler processes (default: all cores)")
    p.add_argument("--chunk", type=int, default=None, help="points per task (default: auto)")
    p.add_argument("--out", default=None, metavar="FILE",
                   help="write the table: .csv, or .parquet when pyarrow is installed")
    p.add_argument("--plot", default=None, metavar="FILE.png", help="write the stability map")
    add_json_flag(p)
    p.set_defaults(func=_sweep)


def _summary(name: str, result: SweepResult) -> list[str]:
    rows = result.rows
    lines = [f"{name}: {result.what} over "
             + " x ".join(f"{a.name} in [{a.values[0]:g}, {a.values[-1]:g}] ({len(a.values)})"
                          for a in result.axes)
             + f" = {len(rows)} points"]
    for key in ("verdict", "bounded", "linear_stable"):
        if key in result.columns:
            counts = Counter(str(r.get(key)) for r in rows if not r["error"])
            if counts:
                lines.append(f"  {key}: "
                             + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    radii = [r["radius"] for r in rows if not r["error"] and "radius" in r]
    if radii:
        finite = [x for x in radii if math.isfinite(x)]
        proofs = Counter(r["radius_proof"] for r in rows if not r["error"] and "radius" in r)
        if finite:
            lines.append(f"  r*: min {min(finite):.4g}, max {max(finite):.4g} (proof: "
                         + ", ".join(f"{k} {v}" for k, v in sorted(proofs.items())) + ")")
        unstable = sum(1 for r in rows if not r["error"] and r.get("linear_stable") is False)
        if unstable:
            lines.append(f"  {unstable} point(s) with an unstable linear part: their r* is "
                         f"for the series of L-infinity norms on the axis, not H-infinity, "
                         f"and no stability radius")
    failed_all = bool(rows) and all(r["error"] for r in rows)  # the error line says it
    lines += [f"  note: {n}" for n in result.notes[1 if failed_all else 0:]]
    # Throughput is a measurement, not a result: it is in --json only, so the same
    # command prints the same text anywhere.
    lines.append(f"  scheduler '{result.scheduler}'")
    return lines


def _sweep(args: argparse.Namespace) -> int:
    axes = [parse_axis(spec) for spec in args.param]
    check_output_file("--out", args.out)
    if args.out is not None:
        check_output(args.out)
    check_plot_path(args.plot)
    check_scheduler(args.scheduler)
    from gfrf.model.modelfile import bundled_or_path, load_model, read_table

    args.model = bundled_or_path(args.model)
    mf = load_model(args.model)  # validates the file and gives its errors their names
    data = read_table(args.model)
    result = sweep(data, axes, what=args.what, amplitude=args.amplitude, order=args.order,
                   t_end=args.t_end, scheduler=args.scheduler, workers=args.workers,
                   chunk_size=args.chunk, path=args.model)
    lines = _summary(mf.name, result)
    payload = {"model": mf.name, **result.to_dict()}
    if args.out is not None:
        lines.append(f"  table: {result.write(args.out)}")
    if args.plot:
        from gfrf.sweep.plot import plot_stability_map

        lines.append(f"  map: {plot_stability_map(result, args.plot, mf.name)}")
    emit(args, payload, "\n".join(lines))
    if result.rows and all(r["error"] for r in result.rows):  # nothing was computed
        print(f"gfrf: error: no grid point succeeded; {result.notes[0]}", file=sys.stderr)
        return 1
    return 0
