"""Work caps of the norm searches: every search ends on a count of evaluations, never a clock.

A 13-term NARX model of degree 3 (7,060 operations per box of its H5) once kept the
default order-5 bracket running for minutes; its searches are counted here, and a
function that improves at every step (the pattern search's worst case) must stop on
the cap.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gfrf.bounds import local_search
from gfrf.bounds.branch_bound import (
    DEFAULT_WORK,
    box_work,
    branch_and_bound,
    default_budget,
)
from gfrf.bounds.budget import kernel_operations
from gfrf.bounds.starts import start_points
from gfrf.kernels.recursion import kernel
from gfrf.model.modelfile import load_model, resolve_model

MODELS = Path(__file__).resolve().parents[2] / "models"
THIRTEEN = ("y[k] = 0.5*y[k-1] - 0.2*y[k-2] + 0.05*y[k-3] + 0.6*u[k-1] + 0.3*u[k-2] "
            "- 0.1*u[k-3] + 0.15*y[k-1]*u[k-1] - 0.1*u[k-1]**2 + 0.05*y[k-2]*u[k-2] "
            "- 0.05*y[k-1]**3 + 0.03*y[k-1]**2*u[k-2] - 0.02*u[k-1]*u[k-2]*y[k-3] "
            "+ 0.04*y[k-2]**2*y[k-1]")


def _thirteen():
    return resolve_model(THIRTEEN, sample_time=0.1).plant


def test_default_budget_of_a_large_narx_kernel_stays_within_the_default_work() -> None:
    model = _thirteen()
    work = box_work(model, 5)
    assert work > DEFAULT_WORK // 20_000  # a fixed floor of 20,000 boxes would exceed it
    assert default_budget(model, 5) * work <= DEFAULT_WORK


def test_local_search_of_a_13_term_narx_h5_counts_its_evaluations() -> None:
    model = _thirteen()
    k = kernel(model, 5)
    points = [0]

    def counted(*w: np.ndarray) -> np.ndarray:
        points[0] += int(np.size(w[0]))
        return k(*w)

    operations = kernel_operations(model, 5)
    found = local_search.local_search(counted, model, 5, True, np.inf, 1e-3, "float",
                                      operations)
    assert found.evaluations == points[0]
    # the start points, then at most two searches, each within the cap
    starts = start_points(local_search.frequencies(model, "float")[0], 5).shape[0]
    assert points[0] <= starts + 2 * (local_search.SEARCH_WORK // operations)
    assert np.isclose(found.value, abs(complex(k(*found.argmax))), rtol=1e-12)


def test_pattern_search_stops_on_the_cap_when_every_step_improves() -> None:
    def rising(*w: np.ndarray) -> np.ndarray:  # |sum w| grows without end along (1, .., 1)
        return np.sum(np.array(w, dtype=float), axis=0) + 0j

    x, value, evaluations, capped = local_search._pattern_search(rising, np.zeros(5), 0.1,
                                                                 1_000)
    assert capped and evaluations <= 1_000
    assert value == float(np.sum(x)) > 0


def test_branch_and_bound_evaluates_at_most_its_budget() -> None:
    model = load_model(MODELS / "identified_example.toml").plant  # H3: about 6,000 boxes
    for budget in (1, 7, 300):
        result = branch_and_bound(model, 3, tol=1e-12, max_boxes=budget)
        assert result.boxes <= budget and result.stop == "budget"


@pytest.mark.slow
def test_order_5_norm_of_a_13_term_narx_ends_on_its_work_caps() -> None:
    from gfrf.bounds.norms import kernel_norm

    model = _thirteen()
    b = kernel_norm(model, 5)
    assert b.boxes <= default_budget(model, 5)
    assert b.boxes * box_work(model, 5) <= DEFAULT_WORK
    assert any(f"{b.boxes} boxes of {box_work(model, 5)} operations" in note
               for note in b.notes)  # the work spent is stated
    assert 0 < b.lower <= b.upper
