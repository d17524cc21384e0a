"""The free run is scored after its start is forgotten: a lightly damped system sampled
fast, with white output noise, scores its noise level, not the transient that two noisy
starting outputs excite."""

import math

import numpy as np
import pytest

from gfrf.identify.output_error import warm_up

pytest.importorskip("sysidentpy")


def test_warm_up_is_the_decay_time_of_the_slowest_mode():
    # y[k] = 0.5 y[k-1]: 0.5^10 < 1e-3 <= 0.5^9
    assert warm_up({((1,), ()): 0.5, ((), (1,)): 1.0}, 1, 1000) == 10
    # complex pair of modulus sqrt(0.9): (0.9)^(k/2) < 1e-3 from k = 132
    theta = {((1,), ()): 1.8, ((2,), ()): -0.9}
    assert warm_up(theta, 2, 1000) == math.ceil(2 * math.log(1e-3) / math.log(0.9))
    assert warm_up(theta, 2, 50) == 50
    assert warm_up({((), (1,)): 1.0}, 1, 1000) == 0  # no output terms: nothing to forget


def _oscillator_samples(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x'' + 0.3 x' + x = u sampled at T = 0.1 with a zero-order hold (exact, scipy)."""
    from scipy.signal import cont2discrete, dlsim

    a = np.array([[0.0, 1.0], [-1.0, -0.3]])
    b = np.array([[0.0], [1.0]])
    c = np.array([[1.0, 0.0]])
    ad, bd, cd, dd, _ = cont2discrete((a, b, c, np.zeros((1, 1))), 0.1, method="zoh")
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1, 1, n)
    x = np.ravel(dlsim((ad, bd, cd, dd, 0.1), u)[1])
    return u, x, rng.standard_normal(n)


def test_a_lightly_damped_system_with_output_noise_scores_its_noise():
    from gfrf.identify.fit import identify

    u, x, white = _oscillator_samples(4000, 3)
    y = x + 0.05 * np.std(x) * white
    result = identify(y, u, 0.1, ylag=2, ulag=2, degree=1, radius_draws=None)
    noise = 0.05 * np.std(x) / np.std(y[3000 + 2:])
    # the true model scores the noise; the start's transient alone doubled it
    assert result.free_run_error < 1.2 * noise
    assert result.validation.adequate, result.validation.reason


def test_the_noise_floor_of_a_lightly_damped_system_is_near_its_output_noise():
    """The rich predictor's longer lags reach the noise (lags up to 2 gave 1.6 times it)."""
    from gfrf.identify.floor import noise_floor
    from gfrf.identify.frols import candidate_keys

    u, x, white = _oscillator_samples(4000, 3)
    y = x + 0.05 * np.std(x) * white
    keys = candidate_keys(2, 2, 3)
    floor, method = noise_floor(y, u, 3000, 2, keys, keys)
    truth = 0.05 * np.std(x) / np.std(y[3002:])
    assert method == "rich model" and 0.9 * truth < floor < 1.15 * truth
