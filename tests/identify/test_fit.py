"""A constant term added to an identified model about a mis-set operating point: each
estimator recovers the offset the data have (a closed form: the level a linear recursion
needs to sit at the true equilibrium)."""

from __future__ import annotations

import numpy as np
import pytest

from gfrf.identify.fit import _with_constant


def _data(offset_error: float, noise: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """y[k] = 0.9 y[k-1] + 0.5 u[k-1] about its equilibrium, measured about a centre
    ``offset_error`` below it: y - c = 0.9 (y - c) + ... + 0.1 * offset_error."""
    rng = np.random.default_rng(4)
    u = rng.uniform(-1, 1, 3000)
    x = np.zeros(u.size)
    for k in range(1, u.size):
        x[k] = 0.9 * x[k - 1] + 0.5 * u[k - 1]
    return x + offset_error + noise * rng.standard_normal(u.size), u


@pytest.mark.parametrize("kind", ["none", "output error"])
def test_the_constant_is_the_offset_error_times_one_minus_the_ar_sum(kind):
    y, u = _data(0.05)
    theta = {((1,), ()): 0.9, ((), (1,)): 0.5}
    fitted, noise_terms = _with_constant(theta, (), kind, y, u, 1, 1)
    assert noise_terms == ()
    assert fitted[((), ())] == pytest.approx(0.1 * 0.05, rel=1e-3, abs=1e-7)
    assert fitted[((1,), ())] == pytest.approx(0.9, abs=1e-4)


def test_with_noise_terms_the_constant_is_the_mean_equation_error():
    """Extended least squares with a constant leaves it undetermined (it trades with the
    mean of the lagged residuals): the constant is the process terms' mean error."""
    y, u = _data(0.05, noise=0.01)
    theta = {((1,), ()): 0.9, ((), (1,)): 0.5}
    fitted, noise_terms = _with_constant(theta, (-0.5,), "narmax", y, u, 1, 1)
    assert noise_terms == (-0.5,)
    assert fitted[((), ())] == pytest.approx(0.005, abs=0.001)
    assert fitted[((1,), ())] == 0.9


def test_a_model_with_a_constant_is_returned_unchanged():
    theta = {((), ()): 0.1, ((1,), ()): 0.5}
    assert _with_constant(theta, (0.2,), "none", np.zeros(10), np.zeros(10), 1, 1) == \
        (theta, (0.2,))
