"""NARX kernel norms: the certified bracket of ||Hn|| against a dense grid on the torus.

For each bundled NARX model, :func:`gfrf.bounds.norms.kernel_norm` with its default
settings (work caps, tol 1e-3) against what a user would write: |H_n| on a uniform
N^n grid of the torus [-pi/T, pi/T)^n (H_n is periodic in every frequency), evaluated
with gfrf's own vectorised kernel (the symbolic kernel is built before either is timed,
so neither time includes it).  Times are CPU seconds of this process.  The grid gives a
value and no bound; its shortfall is measured against gfrf's lower end (an attained
value), and every grid value must lie below gfrf's certified upper end (to the 1e-12
relative rounding of a float evaluation).
"""

from __future__ import annotations

import math
import os
import time
from typing import Any

import numpy as np

from gfrf.bench import BenchSection, bundled_model, load_note
from gfrf.bounds.norms import kernel_norm
from gfrf.kernels.recursion import kernel
from gfrf.model.modelfile import load_model

__all__ = ["run"]

#: The bundled NARX models.
MODELS = ("narx_example.toml", "identified_example.toml", "identified_example_true.toml")
#: The model whose order-5 row the quick run keeps (the open gap the branch-and-bound
#: works on).
QUICK_ORDER5 = "identified_example.toml"
#: Grid points per axis, by kernel order (about 0.3 and 1 million points).
GRID = {3: 64, 5: 16}
#: Points evaluated per vectorised call of the grid.
_CHUNK = 200_000


def _grid_max(k: Any, n: int, half: float, points: int) -> float:
    """Max of |H_n| on the uniform ``points``^n grid of [-half, half)^n (chunked)."""
    axis = -half + 2.0 * half * np.arange(points) / points
    best, total = 0.0, points ** n
    for start in range(0, total, _CHUNK):
        index = np.arange(start, min(total, start + _CHUNK))
        w = [axis[(index // points ** i) % points] for i in range(n)]
        with np.errstate(all="ignore"):
            values = np.abs(k(*w))
        finite = values[np.isfinite(values)]
        best = max(best, float(finite.max(initial=0.0)))
    return best


def _cpu(call: Any) -> tuple[float, Any]:
    start = time.process_time()
    value = call()
    return time.process_time() - start, value


def run(quick: bool) -> BenchSection:
    """Time the NARX norm brackets and the dense grids; return the report section.

    Parameters
    ----------
    quick : bool
        Order 3 of every model and order 5 of the identified example only (all order-5
        rows take about a minute).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``.
    """
    load = os.getloadavg()
    rows: list[list[object]] = []
    for name in MODELS:
        model = load_model(bundled_model(name)).plant
        half = math.pi / model.sample_time  # type: ignore[operator]
        for n in (3, 5) if not quick or name == QUICK_ORDER5 else (3,):
            k = kernel(model, n)  # built once, outside both timings
            t_ours, bound = _cpu(lambda m=model, order=n: kernel_norm(m, order))
            t_grid, grid = _cpu(lambda f=k, order=n, w=half: _grid_max(f, order, w, GRID[order]))
            shortfall = (bound.lower - grid) / bound.lower if bound.lower > 0 else 0.0
            rows.append([name.removesuffix(".toml"), n, f"{t_ours:.2f}",
                         f"{bound.lower:.6g} .. {bound.upper:.6g}", f"{bound.gap:.1e}",
                         str(bound.boxes),
                         f"{GRID[n]}^{n}", f"{t_grid:.2f}", f"{t_grid / t_ours:.2g}",
                         f"{shortfall:.1e}", "yes" if grid <= bound.upper * (1 + 1e-12) else "NO"])
    notes = ["'grid / gfrf' is the grid's CPU time over gfrf's, measured in this run; the "
             "grid's shortfall is (gfrf lower - grid max) / gfrf lower (positive: the grid "
             "missed the peak by that much).",
             "gfrf's gap is (upper - lower) / upper with the default settings: tol 1e-3 and "
             "the default work cap of the branch-and-bound; 'boxes' is the work it spent "
             "(0: the majorant is attained, no search).",
             load_note(load)]
    return BenchSection(
        title="NARX norms: certified ||Hn|| brackets against a dense grid on the torus",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["model", "n", "gfrf CPU s", "gfrf bracket", "gap", "boxes", "grid",
                 "grid CPU s", "grid / gfrf", "grid shortfall", "grid <= upper"],
        rows=rows, notes=notes)
