"""Simulation speed at matched error: gfrf against plain ``solve_ivp`` written by hand.

The hanging pendulum (rho = 0.8) as its polynomial ODE ``theta'' + 0.05 theta' +
2.45 theta - (2.45/6) theta^3 = u``, driven at its 0.25 Hz peak, ``u = 0.05*sin(1.565*t)``,
over 200 s, 2001 output samples.  Baseline: what a user writes without gfrf, the ODE
typed by hand as a Python function ``f(t, y)`` with the forcing a function of t, given
to ``scipy.integrate.solve_ivp`` with RK45, DOP853 and LSODA over a sweep of rtol (atol
= 1e-3 rtol).  gfrf: its default path (``simulate`` with ``method="auto"``: RK45 at rtol
>= 1e-4, DOP853 below, on the generated system) swept over the same tolerances (atol =
1e-3 rtol; the default rtol is 1e-8), and its fast path (compiled fixed-step RK4) swept
over the step.  The default path is also compared with plain RK45 on two more bundled
models, each typed by hand from its equation: the cart-pole (physical equation, eqs
(8)-(9)) in closed loop with its eq (15) controller, theta(0) = 0.2618 rad, reference
``0.02*sin(t)``, 100 s; and the Duffing oscillator, ``u = 0.5*sin(1.3*t)``, 200 s.
Error: max |y - y_ref| on the samples against DOP853 at rtol 1e-13 (atol 1e-15) on the
hand-written ODE.  A speed-up at equal error divides a method's time by the fast
path's (or gfrf default's) time interpolated log-log at the same error.  All in one
run, best of three (gfrf and plain solve_ivp alternating); numba compile or cache load
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

from gfrf._atomic import atomic_write_figure
from gfrf._data import MODELS_DIR
from gfrf.bench import BenchSection, best_of, figure_dir, load_note
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim.simulation import auto_method, simulate
from gfrf.sim.system import build_system

__all__ = ["run", "measure"]

_INPUT = "0.05*sin(1.565*t)"
_T_END = 200.0
_DAMPING, _STIFFNESS = 0.05, 2.45
_CUBIC = _STIFFNESS / 6.0
_DEFAULT_RTOL = 1e-8  # gfrf.sim.simulation's default
_PLAIN = ("RK45", "DOP853", "LSODA")
_DEFAULT = "gfrf default (auto)"

Curve = list[tuple[float, float, float]]  # (setting, seconds, error)


def _by_hand(t: float, y: np.ndarray) -> list[float]:
    """The pendulum's polynomial ODE as a user types it, forcing a function of t."""
    u = 0.05 * math.sin(1.565 * t)
    return [y[1], u - _DAMPING * y[1] - _STIFFNESS * y[0] + _CUBIC * y[0] ** 3]


# Cart-pole (models/cartpole.toml): ((M+m) 4/3 - m cos^2) th'' - (M+m) g/L sin th
# + m th'^2 sin cos + cos u / L = 0 with u = C(r - th) = a e'' + b e' + c e, e = r - th,
# solved for th''.
_M, _m, _L, _g = 0.145, 0.03, 0.125, 9.8
_A, _B, _C = 15.6, 379.3, 0.1331


def _cartpole_by_hand(t: float, y: np.ndarray) -> list[float]:
    """The cart-pole loop as a user types it from eqs (8)-(9) and (15)."""
    r, dr, ddr = 0.02 * math.sin(t), 0.02 * math.cos(t), -0.02 * math.sin(t)
    co, si = math.cos(y[0]), math.sin(y[0])
    lead = (_M + _m) * 4 / 3 - _m * co ** 2 - _A * co / _L
    rest = (_M + _m) * _g / _L * si - _m * y[1] ** 2 * si * co \
        - co * (_A * ddr + _B * (dr - y[1]) + _C * (r - y[0])) / _L
    return [y[1], rest / lead]


def _duffing_by_hand(t: float, y: np.ndarray) -> list[float]:
    """The Duffing oscillator of models/duffing.toml as a user types it."""
    u = 0.5 * math.sin(1.3 * t)
    return [y[1], u - 0.2 * y[1] - y[0] - 0.5 * y[0] ** 3]


#: Further bundled models for the default path against plain RK45: (label, file,
#: closed loop, hand-written f, input, initial state, t_end in s).
_MODELS = (
    ("cart-pole loop", "cartpole.toml", True, _cartpole_by_hand, "0.02*sin(t)",
     (0.2618, 0.0), 100.0),
    ("Duffing", "duffing.toml", False, _duffing_by_hand, "0.5*sin(1.3*t)", (0.0, 0.0), 200.0),
)


def _plain(method: str, rtol: float, atol: float, t_eval: np.ndarray, f: Any = _by_hand,
           y0: tuple[float, ...] = (0.0, 0.0)) -> np.ndarray:
    sol = solve_ivp(f, (0.0, float(t_eval[-1])), list(y0), method=method, rtol=rtol,
                    atol=atol, t_eval=t_eval)
    return sol.y[0]


def _paired(calls: dict[str, Any], repeat: int) -> dict[str, tuple[float, Any]]:
    """Best wall time of each call over ``repeat`` rounds, the calls alternating in a round
    (so a change of machine load reaches all alike), and its last result."""
    best = {name: (math.inf, None) for name in calls}
    for _ in range(repeat):
        for name, call in calls.items():
            sec, out = best_of(call, 1)
            best[name] = (min(best[name][0], sec), out)
    return best


def _default_vs_rk45(rtols: list[float], repeat: int) -> dict[str, dict[str, Curve]]:
    """Per model of :data:`_MODELS`: curves of gfrf's default path and plain RK45."""
    return {label: _model_curves(file, loop, f=f, text=text, y0=y0, t_end=t_end, rtols=rtols,
                                 repeat=repeat)
            for label, file, loop, f, text, y0, t_end in _MODELS}


def _model_curves(file: str, loop: bool, f: Any, text: str, y0: tuple[float, ...],
                  t_end: float, rtols: list[float], repeat: int) -> dict[str, Curve]:
    system = build_system(load_model(MODELS_DIR / file), closed_loop=loop)
    signal = parse_input(text, max_derivative=system.n_inputs - 1)  # r'' of an improper C
    t_eval = np.linspace(0.0, t_end, 2001)
    ref = _plain("DOP853", 1e-13, 1e-15, t_eval, f, y0)
    curves: dict[str, Curve] = {"default": [], "plain": []}
    for rtol in rtols:
        runs = _paired({
            "default": lambda r=rtol: simulate(system, signal, t_end=t_end, t_eval=t_eval,
                                               initial=list(y0), rtol=r, atol=r * 1e-3).y,
            "plain": lambda r=rtol: _plain("RK45", r, r * 1e-3, t_eval, f, y0)}, repeat)
        for name, (sec, y) in runs.items():
            curves[name].append((rtol, sec, float(np.max(np.abs(y - ref)))))
    return curves


def measure(quick: bool) -> dict[str, Any]:
    """Run the sweeps; return curves of (setting, seconds, error) and the compile time.

    Parameters
    ----------
    quick : bool
        One repeat, tolerances 1e-4, 1e-6, 1e-8 and steps 0.1 .. 0.01 s instead of three
        repeats and 1e-3 .. 1e-10, 0.2 .. 0.0025 s.

    Returns
    -------
    dict
        ``curves`` (per method, (setting, seconds, error) triples), ``compile_time``,
        ``reference_time`` (s), ``fast_auto`` (the automatic step's seconds, error and
        note) and ``models`` (the default against RK45).
    """
    system = build_system(load_model(MODELS_DIR / "hanging_pendulum.toml"),
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

    curves: dict[str, Curve] = {"gfrf fast RK4": [], _DEFAULT: []}
    for dt in steps:
        sec, res = best_of(lambda dt=dt: simulate(system, signal, method="fast", dt=dt,
                                                **common), repeat)
        curves["gfrf fast RK4"].append((dt, sec, err(res.y)))
    for method in _PLAIN:
        curves[f"solve_ivp {method}"] = []
    for rtol in rtols:
        calls = {_DEFAULT: lambda r=rtol: simulate(system, signal, rtol=r, atol=r * 1e-3,
                                                   **common).y}
        calls.update({f"solve_ivp {m}": lambda m=m, r=rtol: _plain(m, r, r * 1e-3, t_eval)
                      for m in _PLAIN})
        for name, (sec, y) in _paired(calls, repeat).items():
            curves[name].append((rtol, sec, err(y)))
    auto_sec, auto = best_of(lambda: simulate(system, signal, method="fast", **common), repeat)
    return {"curves": curves, "compile_time": compile_time, "reference_time": t_ref,
            "fast_auto": (auto_sec, err(auto.y),
                          next((n for n in auto.notes if n.startswith("step doubling")), "")),
            "models": _default_vs_rk45(rtols, repeat)}


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
    from gfrf._results import subplots

    fig, ax = subplots(figsize=(5.5, 4))
    for name, rows in curves.items():
        ax.loglog([e for _, _, e in rows], [s for _, s, _ in rows], "o-", label=name)
    ax.set_xlabel("max error vs DOP853 rtol 1e-13 (rad)")
    ax.set_ylabel("wall time (s)")
    ax.set_title("Hanging pendulum, 200 s: speed vs error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    atomic_write_figure(fig, path, dpi=120)


def _span(values: list[float]) -> str:
    if not values:
        return "n/a (no overlap of the error ranges)"
    def fmt(v: float) -> str:
        return f"{v:.0f}" if v >= 10 else f"{v:.2g}"

    low, high = fmt(min(values)), fmt(max(values))
    return f"{low}x" if low == high else f"{low}x to {high}x"


def _ratios(default: Curve, plain: Curve) -> tuple[list[float], list[float]]:
    """gfrf default time over plain RK45 time: at the same rtol, and at plain's errors."""
    same = [g[1] / q[1] for g, q in zip(default, plain, strict=True)]
    equal = [t / sec for _, sec, e in plain if (t := _time_at(e, default))]
    return same, equal


def run(quick: bool) -> BenchSection:
    """The speed-vs-error section of ``gfrf bench`` (figure written to reports/).

    Parameters
    ----------
    quick : bool
        One repeat and fewer tolerances and step sizes.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    data = measure(quick)
    curves: dict[str, Curve] = data["curves"]
    fast = curves["gfrf fast RK4"]
    rows: list[list[object]] = []
    for dt, sec, e in fast:
        rows.append(["gfrf fast RK4 (numba)", f"dt = {dt:g} s", f"{e:.2e}", f"{sec * 1e3:.2f}",
                     "", ""])
    auto_sec, auto_err, chose = data["fast_auto"]
    rows.append(["gfrf fast RK4 (numba)", f"default rtol 1e-8 ({chose or 'automatic step'})",
                 f"{auto_err:.2e}",
                 f"{auto_sec * 1e3:.2f}", "", ""])
    fast_ratio: dict[str, list[float]] = {}
    for name, curve in curves.items():
        if name == "gfrf fast RK4":
            continue
        for rtol, sec, e in curve:
            t_fast = _time_at(e, fast)
            ratio = sec / t_fast if t_fast else None
            if ratio:
                fast_ratio.setdefault(name, []).append(ratio)
            rows.append([name, _setting(name, rtol), f"{e:.2e}", f"{sec * 1e3:.2f}",
                         f"{t_fast * 1e3:.3g}" if t_fast else "n/a",
                         f"{ratio:.3g}x" if ratio else "outside fast range"])
    compared = {"hanging pendulum": _ratios(curves[_DEFAULT], curves["solve_ivp RK45"])}
    for label, model in data["models"].items():
        compared[label] = _ratios(model["default"], model["plain"])
        for name, key in ((_DEFAULT, "default"), ("solve_ivp RK45", "plain")):
            for rtol, sec, e in model[key]:
                rows.append([f"{label}: {name}", _setting(name, rtol), f"{e:.2e}",
                             f"{sec * 1e3:.2f}", "", ""])
    out_dir = figure_dir()
    figure = "speed-vs-error-simulation.png"
    _figure(curves, out_dir / figure)
    notes = ["Fast path ahead of each method at equal error (range over its tolerances): "
             + "; ".join(f"{name} {_span(fast_ratio.get(name, []))}"
                         for name in curves if name != "gfrf fast RK4") + ".",
             "gfrf's default path (method auto) against plain solve_ivp RK45 on the "
             "hand-written ODE, its time as a multiple of plain RK45's at the same rtol | "
             "at equal error (below 1x: gfrf is faster): "
             + "; ".join(f"{label} {_span(same)} | {_span(equal)}"
                         for label, (same, equal) in compared.items()) + ".",
             f"numba compile / cache load of the fast path (excluded from the timings): "
             f"{data['compile_time']:.2f} s; reference run {data['reference_time']:.2f} s.",
             load_note(load)]
    return BenchSection(
        title="Simulation: gfrf fast and default paths vs plain solve_ivp (hanging pendulum)",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["method", "setting", "max error (rad; Duffing: y)", "time (ms)",
                 "fast time at equal error (ms)", "fast speed-up"],
        rows=rows, notes=notes, figures=[figure])


def _setting(name: str, rtol: float) -> str:
    """``rtol = ...``, for gfrf's default path with the method auto ran and the default."""
    if name != _DEFAULT:
        return f"rtol = {rtol:g}"
    mark = ", the default rtol" if rtol == _DEFAULT_RTOL else ""
    return f"rtol = {rtol:g} ({auto_method(rtol)}{mark})"
