"""Speed vs error of the simulation fast path (numba RK4) against scipy's solve_ivp.

The hanging pendulum (rho = 0.8, untruncated sin) driven at its 0.25 Hz peak,
``0.05*sin(1.565*t)``, over 200 s, 2001 output samples.  Error: max |y - y_ref| on
the samples against DOP853 at rtol 1e-12 (atol 1e-14).  The fast path sweeps its fixed
step; RK45 and DOP853 sweep rtol (atol = 1e-3 rtol).  The speed-up at equal error is
the ratio of the scipy time to the fast-path time interpolated (log-log) at the same
error.  numba compile/cache-load time is excluded from the timings and reported.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._atomic import atomic_path
from gfrf.bench import BenchSection, figure_dir
from gfrf.modelfile import load_model
from gfrf.signals import parse_input
from gfrf.simulate import build_system, simulate

__all__ = ["run", "measure"]

_INPUT = "0.05*sin(1.565*t)"
_T_END = 200.0


def _time(call: Any, repeat: int) -> tuple[float, Any]:
    best, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = call()
        best = min(best, time.perf_counter() - start)
    return best, out


def measure(quick: bool) -> dict[str, Any]:
    """Run the sweeps; return times (s), errors (rad) and the compile time."""
    root = Path(__file__).resolve().parents[2]
    system = build_system(load_model(root / "models" / "hanging_pendulum.toml"))
    signal = parse_input(_INPUT)
    t_eval = np.linspace(0.0, _T_END, 2001)
    common = {"t_end": _T_END, "t_eval": t_eval}
    ref = simulate(system, signal, method="dop853", rtol=1e-12, atol=1e-14, **common)
    compile_start = time.perf_counter()
    first = simulate(system, signal, method="fast", dt=0.1, **common)
    compile_time = first.compile_time or (time.perf_counter() - compile_start)
    repeat = 1 if quick else 3
    rtols = [1e-4, 1e-6, 1e-8] if quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    steps = [0.1, 0.05, 0.02, 0.01] if quick else [0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.0025]
    curves: dict[str, list[tuple[float, float, float]]] = {"fast": [], "rk45": [], "dop853": []}
    for dt in steps:
        sec, res = _time(lambda dt=dt: simulate(system, signal, method="fast", dt=dt,
                                                **common), repeat)
        curves["fast"].append((dt, sec, float(np.max(np.abs(res.y - ref.y)))))
    for method in ("rk45", "dop853"):
        for rtol in rtols:
            sec, res = _time(lambda m=method, r=rtol: simulate(
                system, signal, method=m, rtol=r, atol=r * 1e-3, **common), repeat)
            curves[method].append((rtol, sec, float(np.max(np.abs(res.y - ref.y)))))
    return {"curves": curves, "compile_time": compile_time, "reference_time": ref.wall_time}


def _fast_time_at(error: float, fast: list[tuple[float, float, float]]) -> float | None:
    errs = np.array([e for _, _, e in fast])
    secs = np.array([s for _, s, _ in fast])
    order = np.argsort(errs)
    errs, secs = errs[order], secs[order]
    if not errs[0] <= error <= errs[-1]:
        return None
    return float(np.exp(np.interp(np.log(error), np.log(errs), np.log(secs))))


def _figure(curves: dict[str, list[tuple[float, float, float]]], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for name, rows in curves.items():
        ax.loglog([e for _, _, e in rows], [s for _, s, _ in rows], "o-", label=name)
    ax.set_xlabel("max error vs DOP853 rtol 1e-12 (rad)")
    ax.set_ylabel("wall time (s)")
    ax.set_title("Hanging pendulum, 200 s: speed vs error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=120)
    finally:
        plt.close(fig)


def run(quick: bool) -> BenchSection:
    """The speed-vs-error section of ``gfrf bench`` (figure written to reports/)."""
    data = measure(quick)
    curves = data["curves"]
    rows: list[list[object]] = []
    for dt, sec, err in curves["fast"]:
        rows.append(["fast RK4 (numba)", f"dt = {dt:g} s", f"{err:.2e}", f"{sec * 1e3:.2f}",
                     "", ""])
    ratios = []
    for method in ("rk45", "dop853"):
        for rtol, sec, err in curves[method]:
            t_fast = _fast_time_at(err, curves["fast"])
            ratio = sec / t_fast if t_fast else None
            if ratio and method == "rk45":
                ratios.append(ratio)
            rows.append([f"solve_ivp {method.upper()}", f"rtol = {rtol:g}", f"{err:.2e}",
                         f"{sec * 1e3:.2f}", f"{t_fast * 1e3:.2f}" if t_fast else "n/a",
                         f"{ratio:.0f}x" if ratio else "outside fast range"])
    out_dir = figure_dir()
    figure = "speed-vs-error-simulation.png"
    _figure(curves, out_dir / figure)
    notes = [f"numba compile / cache load (excluded from the timings): "
             f"{data['compile_time']:.2f} s; reference run {data['reference_time']:.2f} s.",
             "Target: >= 20x faster than default RK45 at equal error; measured "
             + (f"{min(ratios):.0f}x to {max(ratios):.0f}x." if ratios else "n/a.")]
    return BenchSection(
        title="Simulation: numba RK4 vs solve_ivp (hanging pendulum, 200 s)",
        intro=__doc__.split("\n\n", 1)[1].strip().replace("\n", " "),
        columns=["method", "setting", "max error (rad)", "time (ms)",
                 "fast time at equal error (ms)", "speed-up"],
        rows=rows, notes=notes, figures=[figure])
