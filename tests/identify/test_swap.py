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


def test_a_long_record_swaps_on_the_trial_window_as_the_full_refits_do(monkeypatch):
    """On a long record (an output-error window below WINDOW) the trial refits fit the
    first TRIAL_OE_WINDOW samples and the swapped model the long-record window; the swap
    and its coefficients agree with those of full-window trials.  Records of at most
    27,000 samples (any holdout) keep the full window."""
    from gfrf.identify import output_error, swap
    from gfrf.identify.prune import TRIAL_OE_WINDOW

    assert output_error.window_for(27_000) == output_error.WINDOW
    assert output_error.window_for(output_error.LONG_RECORD + 1) == output_error.LONG_WINDOW
    rng = np.random.default_rng(7)
    u = 3 * rng.uniform(-1, 1, 6000)
    x = _simulate(u)
    y = x + 0.01 * np.std(x) * rng.standard_normal(x.size)
    wrong = {((2, 2) if k[0] == (1, 1) else k[0], k[1]): v for k, v in TRUE.items()}
    keys = [k for k in candidate_keys(2, 2, 3) if len(k[0]) == 2 and not k[1]]
    full, _, full_swaps = swap_lags(wrong, (), "output error", y, u, 2, 2, keys)
    windows: list[int] = []

    def recording(*args, window=output_error.WINDOW, **kw):
        windows.append(window)
        return output_error.refine(*args, window=window, **kw)

    monkeypatch.setattr(swap, "refine", recording)
    theta, _, swaps = swap_lags(wrong, (), "output error", y, u, 2, 2, keys,
                                output_error.LONG_WINDOW)
    assert windows[:-1] and set(windows[:-1]) == {TRIAL_OE_WINDOW}
    assert windows[-1] == output_error.LONG_WINDOW
    assert swaps == full_swaps == [("y[k-2]*y[k-2]", "y[k-1]*y[k-1]")]
    assert set(theta) == set(full) == set(TRUE)
    for k in TRUE:  # both near the system's coefficients, within their noise
        assert abs(theta[k] - full[k]) < 0.1 * abs(TRUE[k]), k
    assert abs(theta[((1, 1), ())] + 0.004) < 4e-4
