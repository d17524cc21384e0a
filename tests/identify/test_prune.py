"""Merging nearly collinear terms before backward elimination: same-degree output
monomials that are nearly the same regressor on fast sampling."""

import numpy as np

from gfrf.identify.noise import regressors
from gfrf.identify.prune import _collinear_groups, carried, free_run_residual, prune, refitter

SLOW = {((1,), ()): 1.9, ((2,), ()): -0.905, ((), (1,)): 0.01, ((1, 1, 1), ()): -0.002}


def _simulate(u: np.ndarray) -> np.ndarray:
    """y[k] = 1.9 y[k-1] - 0.905 y[k-2] + 0.01 u[k-1] - 0.002 y[k-1]**3, written out."""
    y = np.zeros(u.size)
    for k in range(2, u.size):
        y[k] = 1.9 * y[k - 1] - 0.905 * y[k - 2] + 0.01 * u[k - 1] - 0.002 * y[k - 1] ** 3
    return y


def test_collinear_groups_share_input_factors_and_output_degree():
    theta = {((1,), ()): 1.0, ((2,), ()): 1.0, ((1, 1), ()): 1.0, ((1, 2), ()): 1.0,
             ((1,), (1,)): 1.0, ((2,), (1,)): 1.0, ((1,), (2,)): 1.0, ((), (1, 1)): 1.0,
             ((1, 1, 2), ()): 1.0}
    groups = sorted(sorted(g) for g in _collinear_groups(theta))
    assert groups == [[((1,), (1,)), ((2,), (1,))], [((1, 1), ()), ((1, 2), ())]]


def test_a_near_cancelling_pair_is_merged_into_one_term():
    """Least squares on noisy slow data splits the cube over y[k-1]**3, y[k-1]**2*y[k-2]
    and y[k-1]*y[k-2]**2 with large opposite coefficients; the merge keeps one of them,
    with about the true coefficient, and the smaller sum of magnitudes."""
    rng = np.random.default_rng(3)
    u = 3 * rng.uniform(-1, 1, 6000)
    y = _simulate(u) + 0.001 * rng.standard_normal(u.size)
    keys = list(SLOW) + [((1, 1, 2), ()), ((1, 2, 2), ())]
    train, lag = 4000, 2

    def refit(ks):
        theta = np.linalg.lstsq(regressors(ks, y[:train], u[:train], lag), y[lag:train],
                                rcond=None)[0]
        return dict(zip(ks, (float(v) for v in theta), strict=True))

    def score(theta):  # a stand-in for r*: the smaller the cubic magnitudes, the better
        return -sum(abs(v) for k, v in theta.items() if len(k[0]) == 3)

    full = refit(keys)
    assert score(full) < -0.01  # the split: magnitudes far above the true 0.002
    # significant=0: no term may be eliminated, only merged
    pruned, pruning = prune(full, refit, y[:train], u[:train], y[train:], u[train:], lag,
                            significant=0.0, score=score)
    cubes = {k: v for k, v in pruned.items() if len(k[0]) == 3}
    assert len(cubes) == 1 and len(pruning.removed) >= 2
    assert abs(next(iter(cubes.values())) + 0.002) < 0.0005


def test_carried_adds_a_left_out_term_to_its_group():
    start = {((1,), ()): 1.9, ((1, 1), ()): -0.0071, ((2, 2), ()): 0.0041,
             ((1,), (1,)): 0.2, ((2,), (2,)): 0.1}
    theta = carried(start, [((1,), ()), ((1, 1), ()), ((1,), (1,))])
    # y[k-2]**2 goes to y[k-1]**2 (same group); y[k-2]*u[k-2] has no member left
    assert theta == {((1,), ()): 1.9, ((1, 1), ()): -0.0071 + 0.0041, ((1,), (1,)): 0.2}


def test_an_output_error_trial_of_a_merged_pair_starts_from_their_sum():
    """A split cube (0.010 y[k-1]**3 - 0.012 y[k-2]**3, sum the true -0.002) merged into
    y[k-1]**3: from 0.010 alone the model softens and its free run blows up (no start for
    Levenberg-Marquardt); from the sum, the refit reaches the true coefficient and
    reproduces the noise-free output."""
    u = 3 * np.random.default_rng(5).uniform(-1, 1, 3000)
    y = _simulate(u)
    split = dict(SLOW) | {((1, 1, 1), ()): 0.010, ((2, 2, 2), ()): -0.012}
    refit = refitter("output error", y, u, 2, 2, split)
    merged = refit([k for k in split if k != ((2, 2, 2), ())])
    assert abs(merged[((1, 1, 1), ())] + 0.002) < 2e-4
    residual = free_run_residual(merged, y, u, 2)
    assert residual is not None and np.std(residual) < 0.05 * np.std(y)
