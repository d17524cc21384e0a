"""Speed and error of the parametric-pendulum methods, all measured in one run.

Rows: each method's transition curve over ``eps`` in [0, 0.5] at ``x(0) = 0.5`` (error
against the exact curve of eq (4)); perturbation order 2/4/6 vs error vs
time; exact linear curves from Mathieu values for 1000 ``eps`` against the naive
monodromy-trace bisection; one shooting orbit to 1e-10 against shooting with
``solve_ivp`` default tolerances; the order-6 series of both branches.  The exact
transition value as ``gfrf transition --method exact`` computes it (Fourier collocation
plus one checking integration; and the exact curve) against what a user writes:
``brentq`` on ``delta`` with ``x(pi)`` or ``x'(pi)`` from ``solve_ivp(rtol=1e-10)``, all
against a tight reference (``brentq`` xtol 1e-15 on DOP853 at rtol 1e-13, atol 1e-15),
which shares no code with gfrf's collocation.  Transition-value times are the best of
:data:`REPEAT` runs for gfrf and each baseline alike.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from typing import TypeVar

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from gfrf.bench import BenchSection, best_of, load_note
from gfrf.periodic.compare import method_transition, transition_curve
from gfrf.periodic.energy import energy_transition
from gfrf.periodic.floquet import mathieu_transition, monodromy_transition
from gfrf.periodic.perturbation import perturbation_series
from gfrf.periodic.shooting import exact_transition_curve, orbit_on_transition

__all__ = ["run"]

AMPLITUDE = 0.5
#: Runs per transition-value timing (best of), the same for gfrf and every baseline.
REPEAT = 3
T = TypeVar("T")


def _timed(fn: Callable[..., T], *args: object, **kwargs: object) -> tuple[T, float]:
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def _yes(flag: bool) -> str:
    return "yes" if flag else "NO"


def _err(values: np.ndarray, exact: np.ndarray) -> str:
    ok = np.isfinite(values)
    if not ok.any():
        return "no curve"
    text = f"{np.max(np.abs(values[ok] - exact[ok])):.2e}"
    return text if ok.all() else f"{text} (no curve for {int((~ok).sum())} of {ok.size} eps)"


def _naive_shooting_delta(eps: float, amp: float) -> float:
    """Baseline: brentq on delta with x(pi) from solve_ivp at default tolerances."""
    def x_pi(delta: float) -> float:
        sol = solve_ivp(lambda t, y: [y[1], -(delta + eps * math.cos(t)) * (y[0] - y[0]**3 / 6)],
                        (0.0, math.pi), [amp, 0.0])
        return float(sol.y[0, -1])

    d0 = float(mathieu_transition(eps, "1/4"))
    return brentq(x_pi, d0 - 0.05, d0 + 0.1)


def _brentq_delta(eps: float, amp: float, branch: str, method: str = "RK45",
                  rtol: float = 1e-10, atol: float = 1e-12, xtol: float = 2e-12) -> float:
    """Baseline: ``brentq`` on delta for x(pi) = 0 (branch 1/4) or x'(pi) = 0 (branch 0)."""
    idx = 0 if branch == "1/4" else 1

    def at_pi(delta: float) -> float:
        sol = solve_ivp(lambda t, y: [y[1], -(delta + eps * math.cos(t)) * (y[0] - y[0]**3 / 6)],
                        (0.0, math.pi), [amp, 0.0], method=method, rtol=rtol, atol=atol)
        return float(sol.y[idx, -1])

    d0 = float(mathieu_transition(eps, branch))
    return brentq(at_pi, d0 - 0.05, d0 + 0.2, xtol=xtol)


def _transition_rows(quick: bool) -> tuple[list[list[object]], list[str]]:
    """gfrf's exact transition values and curve against brentq + solve_ivp, same accuracy."""
    eps_set = (0.2, 0.5) if quick else (0.1, 0.2, 0.3, 0.4, 0.5)
    cases = [(e, b) for b in ("0", "1/4") for e in eps_set]
    ref = np.array([_brentq_delta(e, AMPLITUDE, branch=b, method="DOP853", rtol=1e-13, atol=1e-15,
                                  xtol=1e-15)
                    for e, b in cases])
    baselines = (("brentq + solve_ivp RK45, rtol 1e-10, atol 1e-12", "RK45", 1e-10, 1e-12),
                 ("brentq + solve_ivp DOP853, rtol 1e-10, atol 1e-12", "DOP853", 1e-10, 1e-12),
                 ("brentq + solve_ivp DOP853, rtol 1e-12, atol 1e-14 (gfrf's check's rtol)",
                  "DOP853", 1e-12, 1e-14),
                 ("brentq + solve_ivp RK45, rtol 1e-10 (default atol 1e-6)", "RK45", 1e-10, 1e-6))
    setting = f"{len(cases)} points: eps in {list(eps_set)}, both branches, x(0) = {AMPLITUDE}"

    def err(values: list[float]) -> str:
        return f"{np.max(np.abs(np.array(values) - ref)):.1e}"

    t_ours, ours = best_of(lambda: [method_transition("exact", e, AMPLITUDE, b).delta
                                    for e, b in cases], REPEAT)
    rows: list[list[object]] = [["exact transition value (gfrf transition --method exact)",
                                 "gfrf: Fourier collocation (Newton) + one DOP853 check",
                                 setting, f"{t_ours:.4f}", err(ours), "", ""]]
    notes = [f"Transition values: best of {REPEAT} runs each; errors against brentq (xtol "
             "1e-15) on solve_ivp DOP853 at rtol 1e-13, atol 1e-15."]
    for label, method, rtol, atol in baselines:
        t_b, vals = best_of(lambda m=method, r=rtol, a=atol: [
            _brentq_delta(e, AMPLITUDE, b, m, r, a) for e, b in cases], REPEAT)
        rows.append(["exact transition value", label, setting, f"{t_b:.4f}", err(vals), "", ""])
        notes.append(f"gfrf transition --method exact takes {t_ours / t_b:.2g}x the time of "
                     f"{label} (errors {err(ours)} and {err(vals)}).")
    curve_eps = np.array(eps_set)
    for branch in ("0", "1/4"):
        sub = ref[[i for i, (_, b) in enumerate(cases) if b == branch]]
        curve, t_curve = _timed(transition_curve, "exact", curve_eps, AMPLITUDE, branch)
        naive, t_naive = _timed(lambda b=branch: [_brentq_delta(float(e), AMPLITUDE, b)
                                                  for e in curve_eps])
        for label, vals, sec in (("gfrf exact curve (collocation, continuation in eps)",
                                  curve, t_curve),
                                 (baselines[0][0], naive, t_naive)):
            rows.append([f"exact transition curve, branch {branch}", label,
                         f"{len(curve_eps)} eps", f"{sec:.3f}",
                         f"{np.max(np.abs(np.asarray(vals) - sub)):.1e}", "", ""])
        notes.append(f"Exact curve, branch {branch}: gfrf takes {t_curve / t_naive:.2g}x the "
                     f"time of brentq + solve_ivp RK45.")
    return rows, notes


def run(quick: bool) -> BenchSection:
    """Run the periodic-pendulum benchmarks and return the report section.

    Parameters
    ----------
    quick : bool
        Fewer eps values (6 instead of 26; 3 naive runs instead of 20).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    rows: list[list[object]] = []
    n_eps = 6 if quick else 26
    eps = np.linspace(0.0, 0.5, n_eps)
    eps_pos = eps.copy()
    eps_pos[0] = 1e-3  # the 1/4-branch perturbation series needs eps > 0
    for branch, methods in (("1/4", ("perturbation", "homotopy", "energy", "averaging")),
                            ("0", ("perturbation", "homotopy"))):
        exact, t_exact = _timed(exact_transition_curve, eps_pos, AMPLITUDE, branch)
        rows.append([f"transition curve, branch {branch}", "exact (collocation + shooting check)",
                     f"{n_eps} eps in [0, 0.5], x(0) = {AMPLITUDE}", f"{t_exact:.3f}",
                     "reference", "", ""])
        for m in methods:
            vals, t_m = _timed(transition_curve, m, eps_pos, AMPLITUDE, branch)
            rows.append([f"transition curve, branch {branch}", m + (" (order 4)" if m in
                                                                   ("perturbation", "homotopy")
                                                                   else ""),
                         f"{n_eps} eps in [0, 0.5], x(0) = {AMPLITUDE}", f"{t_m:.3f}",
                         _err(vals, exact), "", ""])
        for k in (2, 4, 6):
            series, t_gen = _timed(perturbation_series, branch, k)
            vals, t_ev = _timed(lambda s=series: np.array([s.delta(float(e), AMPLITUDE)
                                                           for e in eps_pos]))
            rows.append([f"perturbation order, branch {branch}", f"order {k}",
                         "series generation + curve evaluation", f"{t_gen + t_ev:.3f}",
                         _err(vals, exact), "", ""])

    many = np.linspace(0.0, 0.5, 1000)
    (d0, d1), t_mathieu = _timed(lambda: (mathieu_transition(many, "0"),
                                          mathieu_transition(many, "1/4")))
    n_naive = 3 if quick else 20
    sample = np.linspace(0.05, 0.5, n_naive)
    naive, t_naive = _timed(lambda: [(monodromy_transition(float(e), "0"),
                                      monodromy_transition(float(e), "1/4")) for e in sample])
    ref = np.array([(float(mathieu_transition(e, "0")), float(mathieu_transition(e, "1/4")))
                    for e in sample])
    rows.append(["exact linear curves (both branches)", "Mathieu values (scipy)",
                 "1000 eps", f"{t_mathieu:.4f}", "reference", "< 1 s", _yes(t_mathieu < 1.0)])
    rows.append(["exact linear curves (both branches)", "naive: monodromy trace + Brent",
                 f"{n_naive} eps, scaled to 1000", f"{t_naive * 1000 / n_naive:.1f}",
                 f"{np.max(np.abs(np.array(naive) - ref)):.1e}", "", ""])
    del d0, d1

    orbit, t_orbit = _timed(orbit_on_transition, 0.2, AMPLITUDE, "1/4")
    met = t_orbit < 0.5 and orbit.shooting_residual <= 1e-10
    rows.append(["one shooting orbit, eps = 0.2, x(0) = 0.5", "Newton + variational eqs",
                 f"relative residual {orbit.shooting_residual:.1e}", f"{t_orbit:.3f}",
                 "reference", "< 0.5 s", _yes(met)])
    naive_d, t_nd = _timed(_naive_shooting_delta, 0.2, AMPLITUDE)
    rows.append(["one shooting orbit, eps = 0.2, x(0) = 0.5",
                 "naive: Brent + solve_ivp default tolerances", "delta error",
                 f"{t_nd:.3f}", f"{abs(naive_d - orbit.delta):.1e}", "", ""])

    (_, _), t_series = _timed(lambda: (perturbation_series("0", 6),
                                       perturbation_series("1/4", 6)))
    rows.append(["perturbation series, both branches, order 6",
                 "Fourier coefficients (exact rationals)", "", f"{t_series:.3f}", "exact",
                 "< 10 s", _yes(t_series < 10.0)])

    transition_rows, transition_notes = _transition_rows(quick)
    rows += transition_rows

    no_root = np.isnan(energy_transition(eps_pos, AMPLITUDE))
    edge = float(eps_pos[no_root].min()) if no_root.any() else math.inf
    return BenchSection(
        title="Parametric pendulum: four approximate methods against shooting",
        intro=("Eq (4) of Zhang, Zhen & Li (2019). Transition-curve rows time each method "
               f"over eps in [0, 0.5] at x(0) = {AMPLITUDE} (first point eps = 1e-3) and give "
               "the max |delta - delta_exact| against the exact curve (Fourier collocation, "
               "each point checked by integration); the linear "
               "rows compare Mathieu characteristic values with a monodromy-trace bisection "
               "(independent methods)."),
        columns=["task", "method", "setting", "time (s)", "max error", "target", "met"],
        rows=rows,
        notes=[f"Energy method: eq (48) has no real root from eps = {edge:.3g} on (x(0) = "
               f"{AMPLITUDE}), so its curve stops there.",
               "Averaging and energy treat only the 1/4 branch (as in the paper).",
               *transition_notes,
               load_note(load)])
