"""Simulation speed at matched error: gfrf against plain ``solve_ivp`` written by hand.

The hanging pendulum (rho = 0.8) as its polynomial ODE ``theta'' + 0.05 theta' +
2.45 theta - (2.45/6) theta^3 = u``, driven at its 0.25 Hz peak, ``u = 0.05*sin(1.565*t)``,
over 200 s, 2001 output samples.  Baseline: what a user writes without gfrf, the ODE
typed by hand as a Python function ``f(t, y)`` with the forcing a function of t, given
to ``scipy.integrate.solve_ivp`` with RK45, DOP853 and LSODA over a sweep of rtol (atol
= 1e-3 rtol).  gfrf: its default path (``simulate``: DOP853 on the generated system, rtol
1e-8, atol 1e-10) swept over the same tolerances, and its fast path (compiled
fixed-step RK4) swept over the step.  Error: max |theta - theta_ref| on the samples
against DOP853 at rtol 1e-13 (atol 1e-15) on the hand-written ODE.  A speed-up at equal
error divides a method's time by the fast path's (or gfrf default's) time interpolated
log-log at the same error.  All in one run, best of three; numba compile or cache load
is excluded and reported.
"""

from __future__ import annotations

import math
import os
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from gfrf._atomic import atomic_path
from gfrf.bench import BenchSection, best_of, figure_dir, load_note
from gfrf.modelfile import load_model
from gfrf.signals import parse_input
from gfrf.simulation import build_system, simulate

__all__ = ["run", "measure"]

_INPUT = "0.05*sin(1.565*t)"
_T_END = 200.0
_DAMPING, _STIFFNESS = 0.05, 2.45
_CUBIC = _STIFFNESS / 6.0
_DEFAULT_RTOL = 1e-8  # gfrf.simulation's default (atol 1e-10)
_PLAIN = ("RK45", "DOP853", "LSODA")

Curve = list[tuple[float, float, float]]  # (setting, seconds, error)


def _by_hand(t: float, y: np.ndarray) -> list[float]:
    """The pendulum's polynomial ODE as a user types it, forcing a function of t."""
    u = 0.05 * math.sin(1.565 * t)
    return [y[1], u - _DAMPING * y[1] - _STIFFNESS * y[0] + _CUBIC * y[0] ** 3]


def _plain(method: str, rtol: float, atol: float, t_eval: np.ndarray) -> np.ndarray:
    sol = solve_ivp(_by_hand, (0.0, _T_END), [0.0, 0.0], method=method, rtol=rtol, atol=atol,
                    t_eval=t_eval)
    return sol.y[0]


def measure(quick: bool) -> dict[str, Any]:
    """Run the sweeps; return curves of (setting, seconds, error) and the compile time."""
    root = Path(__file__).resolve().parents[2]
    system = build_system(load_model(root / "models" / "hanging_pendulum.toml"),
                          equation="polynomial")
    signal = parse_input(_INPUT)
    t_eval = np.linspace(0.0, _T_END, 2001)
    common = {"t_end": _T_END, "t_eval": t_eval}
    t_ref, ref = best_of(lambda: _plain("DOP853", 1e-13, 1e-15, t_eval), 1)
    start = time.perf_counter()
    first = simulate(system, signal, method="fast", dt=0.1, **common)
    compile_time = first.compile_time or (time.perf_counter() - start)
    repeat = 1 if quick else 3
    rtols = [1e-4, 1e-6, 1e-8] if quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    steps = [0.1, 0.05, 0.02, 0.01] if quick else [0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.0025]

    def err(y: np.ndarray) -> float:
        return float(np.max(np.abs(y - ref)))

    curves: dict[str, Curve] = {"gfrf fast RK4": [], "gfrf default (DOP853)": []}
    for dt in steps:
        sec, res = best_of(lambda dt=dt: simulate(system, signal, method="fast", dt=dt,
                                                **common), repeat)
        curves["gfrf fast RK4"].append((dt, sec, err(res.y)))
    for rtol in rtols:
        atol = 1e-10 if rtol == _DEFAULT_RTOL else rtol * 1e-3
        sec, res = best_of(lambda r=rtol, a=atol: simulate(system, signal, rtol=r, atol=a,
                                                         **common), repeat)
        curves["gfrf default (DOP853)"].append((rtol, sec, err(res.y)))
    for method in _PLAIN:
        curves[f"solve_ivp {method}"] = []
        for rtol in rtols:
            sec, y = best_of(lambda m=method, r=rtol: _plain(m, r, r * 1e-3, t_eval), repeat)
            curves[f"solve_ivp {method}"].append((rtol, sec, err(y)))
    auto_sec, auto = best_of(lambda: simulate(system, signal, method="fast", **common), repeat)
    return {"curves": curves, "compile_time": compile_time, "reference_time": t_ref,
            "fast_auto": (auto_sec, err(auto.y),
                          next((n for n in auto.notes if n.startswith("step doubling")), ""))}


def _time_at(error: float, curve: Curve) -> float | None:
    """Time of ``curve`` interpolated log-log at ``error`` (None outside its range)."""
    errs = np.array([e for _, _, e in curve])
    secs = np.array([s for _, s, _ in curve])
    order = np.argsort(errs)
    errs, secs = errs[order], secs[order]
    if not errs[0] <= error <= errs[-1]:
        return None
    return float(np.exp(np.interp(np.log(error), np.log(errs), np.log(secs))))


def _figure(curves: dict[str, Curve], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for name, rows in curves.items():
        ax.loglog([e for _, _, e in rows], [s for _, s, _ in rows], "o-", label=name)
    ax.set_xlabel("max error vs DOP853 rtol 1e-13 (rad)")
    ax.set_ylabel("wall time (s)")
    ax.set_title("Hanging pendulum, 200 s: speed vs error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=120)
    finally:
        plt.close(fig)


def _span(values: list[float]) -> str:
    if not values:
        return "n/a (no overlap of the error ranges)"
    def fmt(v: float) -> str:
        return f"{v:.0f}" if v >= 10 else f"{v:.2g}"

    return f"{fmt(min(values))}x to {fmt(max(values))}x"


def run(quick: bool) -> BenchSection:
    """The speed-vs-error section of ``gfrf bench`` (figure written to reports/)."""
    load = os.getloadavg()
    data = measure(quick)
    curves: dict[str, Curve] = data["curves"]
    fast, default = curves["gfrf fast RK4"], curves["gfrf default (DOP853)"]
    rows: list[list[object]] = []
    for dt, sec, e in fast:
        rows.append(["gfrf fast RK4 (numba)", f"dt = {dt:g} s", f"{e:.2e}", f"{sec * 1e3:.2f}",
                     "", ""])
    auto_sec, auto_err, chose = data["fast_auto"]
    rows.append(["gfrf fast RK4 (numba)", f"default rtol 1e-8 ({chose or 'automatic step'})",
                 f"{auto_err:.2e}",
                 f"{auto_sec * 1e3:.2f}", "", ""])
    fast_ratio: dict[str, list[float]] = {}
    default_ratio: list[float] = []
    for name, curve in curves.items():
        if name == "gfrf fast RK4":
            continue
        for rtol, sec, e in curve:
            t_fast = _time_at(e, fast)
            ratio = sec / t_fast if t_fast else None
            if ratio:
                fast_ratio.setdefault(name, []).append(ratio)
            t_default = _time_at(e, default) if name != "gfrf default (DOP853)" else None
            if t_default and name == "solve_ivp RK45":
                default_ratio.append(t_default / sec)
            mark = " (gfrf's default)" if name.startswith("gfrf") and rtol == _DEFAULT_RTOL \
                else ""
            rows.append([name, f"rtol = {rtol:g}{mark}", f"{e:.2e}", f"{sec * 1e3:.2f}",
                         f"{t_fast * 1e3:.3g}" if t_fast else "n/a",
                         f"{ratio:.3g}x" if ratio else "outside fast range"])
    same_tol = [g[1] / p[1] for g, p in zip(default, curves["solve_ivp RK45"], strict=True)]
    out_dir = figure_dir()
    figure = "speed-vs-error-simulation.png"
    _figure(curves, out_dir / figure)
    notes = ["Fast path ahead of each method at equal error (range over its tolerances): "
             + "; ".join(f"{name} {_span(fast_ratio.get(name, []))}"
                         for name in curves if name != "gfrf fast RK4") + ".",
             f"gfrf's default path against plain solve_ivp RK45 on the hand-written ODE: "
             f"{_span(same_tol)} its time at the same rtol, {_span(default_ratio)} at equal "
             f"error (above 1x: gfrf's wrapper is slower).",
             f"numba compile / cache load of the fast path (excluded from the timings): "
             f"{data['compile_time']:.2f} s; reference run {data['reference_time']:.2f} s.",
             load_note(load)]
    return BenchSection(
        title="Simulation: gfrf fast and default paths vs plain solve_ivp (hanging pendulum)",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["method", "setting", "max error (rad)", "time (ms)",
                 "fast time at equal error (ms)", "fast speed-up"],
        rows=rows, notes=notes, figures=[figure])
