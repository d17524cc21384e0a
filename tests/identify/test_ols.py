"""The error reduction ratio ranking and the block least squares of extended least squares
against independent algorithms: sysidentpy's Householder FROLS and numpy's SVD lstsq."""

import numpy as np
import pytest

from gfrf.identify.noise import _augmented_least_squares
from gfrf.identify.ols import error_reduction_ratio


def _candidates(seed: int, rows: int = 3000) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1, 1, rows + 3)
    y = np.zeros(rows + 3)
    for k in range(2, rows + 3):
        y[k] = 0.6 * y[k - 1] - 0.2 * y[k - 2] + 0.5 * u[k - 1] + 0.1 * y[k - 1] * u[k - 1]
    y += 0.01 * rng.standard_normal(y.size)
    lagged = [y[2:-1], y[1:-2], u[2:-1], u[1:-2]]
    columns = [a * b for i, a in enumerate(lagged) for b in lagged[i:]] + lagged
    return np.column_stack(columns), y[3:]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_ranking_matches_sysidentpy_householder(seed: int) -> None:
    ofr = pytest.importorskip("sysidentpy.model_structure_selection")
    psi, target = _candidates(seed)
    frols = ofr.FROLS(ylag=1, xlag=1, n_terms=8)
    frols.max_lag = 0
    err_ref, piv_ref, _ = frols.error_reduction_ratio(psi, target[:, None], 8)
    err, order = error_reduction_ratio(psi, target, 8)
    assert list(order) == [int(p) for p in piv_ref]
    np.testing.assert_allclose(err[:9], np.asarray(err_ref)[:9], rtol=1e-9, atol=1e-15)


def test_block_least_squares_matches_svd_least_squares() -> None:
    rng = np.random.default_rng(4)
    psi = rng.standard_normal((2000, 6)) @ np.triu(rng.uniform(0.5, 2, (6, 6)))
    extra = rng.standard_normal((2000, 3)) + psi[:, :3] * 0.9  # partly in psi's span
    target = rng.standard_normal(2000)
    q, r = np.linalg.qr(psi)
    got = _augmented_least_squares(psi, q, r, q.T @ target, extra, target)
    want = np.linalg.lstsq(np.hstack([psi, extra]), target, rcond=None)[0]
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-12)
