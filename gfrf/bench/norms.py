"""Speed versus error of the GFRF norms: ||H3||, ||H5|| and ||H1|| of the rho = 0.8 pendulum.

||Hn||: the certified bracket of :func:`gfrf.bounds.norms.kernel_norm` (first call including
the symbolic recursion) against what a user would write for a global maximum of
|Hn(j w)| over [-3, 3]^n rad/s on ``sympy.lambdify(..., cse=True)`` of the same
explicit kernel: ``scipy.optimize.differential_evolution`` (seed 0, default tol,
polish=True) and a coarse grid whose best point is polished by Nelder-Mead (xatol
1e-10, fatol 1e-12 relative).  Their times include the lambdify but not the symbolic
kernel, which they take from gfrf.  ||H3|| is known in closed form, |c3| ||H1||^4
with ||H1|| = 1/(b sqrt(c - b^2/4)) (attained at (w_r, w_r, -w_r)); for ||H5|| the
error is against the best value any method found.  Dense grids are kept for scale.

||H1||: :func:`gfrf.bounds.norms.h1_norm` (proven enclosure of the stationary points) against
python-control's ``control.norm(sys, p='inf')`` and a 10^5-point grid on [0, 3] rad/s.
"""

from __future__ import annotations

import importlib.util
import math
import os
import time
import warnings
from collections.abc import Callable
from typing import Any

import control
import numpy as np
import sympy as sp

from gfrf.bench import BenchSection, best_of, load_note
from gfrf.bounds.norms import h1_norm, kernel_norm
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model, parse_model

__all__ = ["run"]

_B, _C = 0.05, 2.45
_C3 = 9.8 / 24.0
_EQUATION = f"D(y,2) + {_B}*D(y) + {_C}*y - {_C3!r}*y**3 = u"
_SEED = 0
#: Coarse grid points per axis before the Nelder-Mead polish, by kernel order.
_POLISH_GRID = {3: 41, 5: 13}


def _grid_max(model: Model, n_axis: int) -> float:
    """Max of |H3| on an n_axis^3 uniform grid over [-3, 3]^3 (chunked)."""
    h3 = kernel(model, 3)
    w = np.linspace(-3.0, 3.0, n_axis)
    best = 0.0
    chunk = max(1, 2_000_000 // (n_axis * n_axis))
    for i in range(0, n_axis, chunk):
        values = np.abs(h3(w[i:i + chunk, None, None], w[None, :, None], w[None, None, :]))
        best = max(best, float(values.max()))
    return best


def _time(f: Callable[[], Any]) -> tuple[float, Any]:
    start = time.perf_counter()
    value = f()
    return time.perf_counter() - start, value


def _objective(model: Model, n: int) -> Callable[..., Any]:
    """What a user writes: lambdify the explicit H_n (from gfrf) and evaluate at s = j w."""
    k = kernel(model, n)
    return sp.lambdify(k.variables, k.expr, "numpy", cse=True)


def _differential_evolution(model: Model, n: int) -> tuple[float, int]:
    from scipy.optimize import differential_evolution

    f = _objective(model, n)
    result = differential_evolution(lambda x: -abs(f(*(1j * x))), [(-3.0, 3.0)] * n,
                                    seed=_SEED, polish=True)
    return float(-result.fun), int(result.nfev)


def _grid_nelder_mead(model: Model, n: int) -> tuple[float, int]:
    from scipy.optimize import minimize

    f = _objective(model, n)
    g = np.linspace(-3.0, 3.0, _POLISH_GRID[n])
    mesh = np.meshgrid(*([g] * n), indexing="ij", sparse=True)
    values = np.abs(f(*(1j * x for x in mesh)))
    start = np.array([g[i] for i in np.unravel_index(int(np.argmax(values)), values.shape)])
    result = minimize(lambda x: -abs(f(*(1j * x))), start, method="Nelder-Mead",
                      options={"xatol": 1e-10, "fatol": 1e-12 * float(values.max()),
                               "maxiter": 20_000, "maxfev": 40_000})
    return float(-result.fun), int(result.nfev) + values.size


def _search_rows(model: Model, n: int, exact: float | None) -> tuple[list[list[object]], float]:
    """gfrf's bracket, DE and grid + Nelder-Mead for ||H_n||; rows and gfrf's time."""
    t_ours, bound = _time(lambda: kernel_norm(model, n))
    t_de, (de, de_evals) = _time(lambda: _differential_evolution(model, n))
    t_nm, (nm, nm_evals) = _time(lambda: _grid_nelder_mead(model, n))
    best = exact if exact is not None else max(bound.lower, de, nm)
    label = "closed form" if exact is not None else "best found"

    def err(value: float) -> str:
        return f"{abs(value - best) / best:.1e}"

    rows: list[list[object]] = [
        [f"‖H{n}‖ gfrf kernel_norm (first call, incl. symbolic recursion)",
         f"{t_ours:.3f}", "1", f"{err(bound.lower)} (lower end, vs {label})",
         f"yes: upper {bound.upper:.10g}, gap {bound.gap:.1e}"],
        [f"‖H{n}‖ differential_evolution (seed {_SEED}, polish)", f"{t_de:.3f}",
         f"{t_de / t_ours:.2g}", err(de), f"no ({de_evals} evaluations)"],
        [f"‖H{n}‖ grid {_POLISH_GRID[n]}^{n} + Nelder-Mead", f"{t_nm:.3f}",
         f"{t_nm / t_ours:.2g}", err(nm), f"no ({nm_evals} evaluations)"]]
    return rows, t_ours


def run(quick: bool) -> BenchSection:
    """Time the norm brackets and the baselines; return the report section.

    Parameters
    ----------
    quick : bool
        Grid resolutions 25 and 50 instead of 50, 100 and 200, and no order-5 search.

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    beta1 = 1.0 / (_B * math.sqrt(_C - _B * _B / 4.0))
    exact3 = _C3 * beta1**4
    model = parse_model(_EQUATION)
    rows, t_ours = _search_rows(model, 3, exact3)
    resolutions = (25, 50) if quick else (50, 100, 200)
    last = (0.0, 1.0, 1)
    for n_axis in resolutions:
        t_grid, value = _time(lambda n=n_axis: _grid_max(model, n))
        err = abs(value - exact3) / exact3
        rows.append([f"‖H3‖ dense grid {n_axis}^3 on [-3, 3]^3", f"{t_grid:.3f}",
                     f"{t_grid / t_ours:.2g}", f"{err:.1e}", f"no ({n_axis**3:.2e} points)"])
        last = (t_grid, err, n_axis)
    t_grid, err, n_axis = last
    need = n_axis * math.sqrt(max(err, 1e-300) / 1e-6) if err > 1e-6 else n_axis
    t_need = t_grid * (need / n_axis) ** 3
    rows.append([f"‖H3‖ dense grid for 1e-6 (extrapolated, N ~ {need:.3g})", f"~{t_need:.3g}",
                 f"~{t_need / t_ours:.2g}", "1e-06", "no; error ~ h^2, time ~ N^3"])
    if not quick:
        rows += _search_rows(model, 5, None)[0]
    h1_rows, h1_notes = _h1_rows(model, beta1)
    rows += h1_rows
    notes = [f"exact ||H3|| = |c3| ||H1||^4 = {exact3:.10g}; exact ||H1|| = {beta1:.12g} "
             "(closed forms, rad/s).",
             "'x gfrf' is each method's time over gfrf's for the same norm, measured in this "
             "run; 'certified' means a proven upper bound comes with the value.",
             "The baselines find a value (or a local maximum: their error column shows which) "
             "without any bound on how far the true sup may lie above it.",
             *h1_notes,
             load_note(load)]
    return BenchSection(
        title="GFRF norms: ||Hn|| and ||H1|| of the hanging pendulum (rho = 0.8)",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["method", "time (s)", "x gfrf", "relative error", "certified"],
        rows=rows, notes=notes)


def _h1_rows(model: Model, beta1: float) -> tuple[list[list[object]], list[str]]:
    repeat = 5
    t_ours, ours = best_of(lambda: h1_norm(model), repeat)
    t_float, ours_float = best_of(lambda: h1_norm(model, proof="float"), repeat)
    system = control.tf([1.0], [1.0, _B, _C])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t_pc, pc = best_of(lambda: float(control.norm(system, p="inf")), repeat)
    w = np.linspace(0.0, 3.0, 100_000)
    t_grid, grid = best_of(lambda: float(np.max(1.0 / np.abs(_C - w * w + 1j * _B * w))),
                            repeat)

    def err(value: float) -> str:
        return f"{abs(value - beta1) / beta1:.1e}"

    rows: list[list[object]] = [
        ["‖H1‖ gfrf h1_norm (proof='interval', default)", f"{t_ours:.4f}", "1",
         err(ours.upper), "yes (proven enclosure)"],
        ["‖H1‖ gfrf h1_norm (proof='float')", f"{t_float:.4f}", f"{t_float / t_ours:.2g}",
         err(ours_float.upper), "no (float stationary points)"],
        ["‖H1‖ control.norm(sys, p='inf')", f"{t_pc:.4f}", f"{t_pc / t_ours:.2g}", err(pc),
         "no"],
        ["‖H1‖ grid 1e5 points on [0, 3]", f"{t_grid:.4f}", f"{t_grid / t_ours:.2g}",
         err(grid), "no"]]
    slycot = importlib.util.find_spec("slycot") is not None
    notes = [f"python-control {control.__version__}; slycot "
             + ("installed: control.norm uses its AB13DD routine."
                if slycot else "NOT installed on this machine, so control.norm uses its "
                "own bisection (tolerance 1e-6); the slycot timing is not measured here."),
             (f"gfrf's h1_norm calls control.norm itself on every call, as a cross-check "
              f"(gfrf/bounds/norms.py, kept in Bound.reference): about {t_pc * 1e3:.2g} ms (the "
              f"control.norm row) of its {t_ours * 1e3:.2g} ms is that cross-check."
              if ours.reference is not None else
              "gfrf's h1_norm runs no python-control cross-check on its hot path "
              "(Bound.reference is empty).")]
    return rows, notes
