"""Lags swapped within collinear groups: the member the free run needs, not the one
FROLS ranked first on noisy outputs."""

import numpy as np

from gfrf.identify.frols import candidate_keys
from gfrf.identify.prune import free_run_residual
from gfrf.identify.swap import swap_lags

TRUE = {((1,), ()): 1.9, ((2,), ()): -0.905, ((), (1,)): 0.01, ((1, 1), ()): -0.004,
        ((1, 1, 1), ()): -0.002}


def _simulate(u: np.ndarray) -> np.ndarray:
    """y[k] = 1.9 y[k-1] - 0.905 y[k-2] + 0.01 u[k-1] - 0.004 y[k-1]**2
    - 0.002 y[k-1]**3, written out."""
    y = np.zeros(u.size)
    for k in range(2, u.size):
        y[k] = (1.9 * y[k - 1] - 0.905 * y[k - 2] + 0.01 * u[k - 1] - 0.004 * y[k - 1] ** 2
                - 0.002 * y[k - 1] ** 3)
    return y


def test_the_wrong_lag_of_a_square_is_swapped_for_the_right_one():
    """A model with y[k-2]**2 where the system has y[k-1]**2 (nearly the same regressor,
    not the same damping): the output-error refit with the swapped lag reproduces the
    noise-free output, and the swap is reported."""
    rng = np.random.default_rng(7)
    u = 3 * rng.uniform(-1, 1, 3000)
    x = _simulate(u)
    y = x + 0.01 * np.std(x) * rng.standard_normal(x.size)
    wrong = {((2, 2) if k[0] == (1, 1) else k[0], k[1]): v for k, v in TRUE.items()}
    theta, noise, swaps = swap_lags(wrong, (), "output error", y, u, 2, 2,
                                    candidate_keys(2, 2, 3))
    assert swaps == [("y[k-2]*y[k-2]", "y[k-1]*y[k-1]")] and noise == ()
    assert set(theta) == set(TRUE)
    assert abs(theta[((1, 1), ())] + 0.004) < 4e-4
    clean = free_run_residual(theta, x, u, 2)
    assert clean is not None and np.std(clean) < 0.02 * np.std(x)


def test_the_right_lags_are_kept():
    rng = np.random.default_rng(8)
    u = 3 * rng.uniform(-1, 1, 3000)
    x = _simulate(u)
    y = x + 0.01 * np.std(x) * rng.standard_normal(x.size)
    theta, _, swaps = swap_lags(dict(TRUE), (), "output error", y, u, 2, 2,
                                candidate_keys(2, 2, 3))
    assert swaps == [] and set(theta) == set(TRUE)
