"""The NARX-norm bench section: registered, and its dense-grid baseline is a true grid max."""

from __future__ import annotations

import numpy as np

from gfrf.bench import SECTION_MODULES
from gfrf.bench.narx_norms import _grid_max


def test_the_narx_norm_section_is_run_by_gfrf_bench() -> None:
    assert "gfrf.bench.narx_norms" in SECTION_MODULES


def test_grid_max_visits_every_point_of_the_periodic_grid() -> None:
    # |1 + e^{j w1} + e^{j w2} + e^{j w3}| is 4 at w = 0 only; a shifted copy peaks at a
    # grid point off the first chunk, so a missed chunk or axis shows
    points, half = 64, np.pi
    axis = -half + 2 * half * np.arange(points) / points
    peak = (axis[5], axis[40], axis[63])

    def k(*w: np.ndarray) -> np.ndarray:
        return 1 + sum(np.exp(1j * (x - p)) for x, p in zip(w, peak, strict=True))

    assert np.isclose(_grid_max(k, 3, half, points), 4.0, rtol=1e-14)
    shifted = _grid_max(lambda *w: k(*(x + 2 * half / (2 * points) for x in w)), 3, half,
                        points)
    assert shifted < 4.0 - 1e-4  # half a grid step off the peak: the grid misses it
