"""The evaluation path chosen by the work, and the per-order step functions of the ufunc."""

from __future__ import annotations

import numpy as np
import pytest

from gfrf.kernels import compiled
from gfrf.kernels.recursion import generator, kernel
from gfrf.model.equation import parse_model

DUFFING = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


def _closed_form(w1: np.ndarray, w2: np.ndarray, w3: np.ndarray) -> np.ndarray:
    """Symmetric Duffing H3 = -0.5 H1(w1) H1(w2) H1(w3) H1(w1 + w2 + w3)."""
    h1 = lambda w: 1 / (1 - w * w + 0.2j * w)  # noqa: E731
    return -0.5 * h1(w1) * h1(w2) * h1(w3) * h1(w1 + w2 + w3)


def test_few_points_never_compile() -> None:
    gen = generator(parse_model(DUFFING))
    kernel(parse_model(DUFFING), 3)
    assert not compiled.compile_pays(gen, 3, True, 10)
    assert not compiled.compile_pays(gen, 3, True, compiled.MIN_POINTS - 1)
    # the saving grows with the points, the compile does not: a threshold exists
    assert compiled.compile_pays(gen, 3, True, 10**12)


def test_a_call_that_pays_runs_the_ufunc_with_the_same_values(
        monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("numba")
    k = kernel(parse_model(DUFFING), 3)
    rng = np.random.default_rng(2)
    w = rng.uniform(-3.0, 3.0, (3, 2000))
    numpy_values = k(*w)
    calls = []
    real = k._gen.ufunc

    def spy(n: int, symmetric: bool) -> object:
        calls.append(n)
        return real(n, symmetric)

    monkeypatch.setattr("gfrf.kernels.recursion.MIN_POINTS", 1)
    monkeypatch.setattr(compiled, "MIN_POINTS", 1)
    monkeypatch.setattr(compiled, "COMPILE_SECONDS", 0.0)
    monkeypatch.setattr(compiled, "COMPILE_SECONDS_PER_OP", 0.0)
    monkeypatch.setattr(k._gen, "ufunc", spy)
    fast = k(*w)
    assert calls == [3]
    exact = _closed_form(*w)
    assert np.max(np.abs(fast - exact) / np.abs(exact)) < 1e-13
    assert np.max(np.abs(fast - numpy_values) / np.abs(exact)) < 1e-13


def test_step_functions_call_each_order_once_per_block() -> None:
    gen = generator(parse_model("D(y,2) + 0.2*D(y) + y + 0.3*y**2 + 0.5*y**3 = u"))
    kernel(gen.model, 4)
    functions, body = compiled._step_functions(gen, 4, True)
    assert {f"def step_{m}(" in functions for m in range(1, 5)} == {True}
    assert body.count("step_1(") == 4 and body.count("step_2(") == 6
    assert body.count("step_3(") == 4 and body.count("step_4(") == 1
