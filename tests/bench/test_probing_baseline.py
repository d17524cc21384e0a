"""The sympy harmonic-probing baseline of the bench agrees with gfrf's kernels."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import MODELS

from gfrf.bench.probing_baseline import ProbingBaseline, probing_work
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model


@pytest.mark.parametrize(("source", "top"), [
    ("duffing.toml", 5),
    ("narx_example.toml", 5),  # discrete: at q = exp(-j*w*T)
    ("cartpole.toml", 3),  # every term type: y*y'^2, y^2*y'', y^2*u
    ("D(y,2) + 0.3*D(y) + y + 0.4*D(y)**2*D(u) - 0.7*y*u**2 = u", 4),  # even orders, D(u)
])
def test_probing_baseline_agrees_with_the_kernels(source: str, top: int) -> None:
    model = (load_model(MODELS / source).plant if source.endswith(".toml")
             else parse_model(source))
    baseline = ProbingBaseline(model)
    w = np.random.default_rng(11).uniform(-20.0, 20.0, (top, 200))
    for n in range(1, top + 1):
        ours = kernel(model, n)(*w[:n])
        theirs = np.broadcast_to(baseline.function(n)(*w[:n]), ours.shape)
        if kernel(model, n).is_zero:
            assert np.all(theirs == 0), n
            continue
        assert np.max(np.abs(theirs - ours) / np.abs(ours)) <= 1e-12, n


def test_probing_work_counts_ordered_splittings() -> None:
    # y**3 (3!*S(4,3) = 36), y*u (2!*S(4,2) = 14) and u (1!*S(4,1) = 1); y, D(y) are linear
    model = parse_model("D(y) + y + y**3 + y*u = u")
    assert probing_work(model, 4) == 36 + 14 + 1
