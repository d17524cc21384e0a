"""FROLS (structure selection by error reduction ratio and an information criterion)
against sysidentpy's own FROLS, an independent implementation (Householder ERR, one
selection run and least squares per size)."""

import numpy as np
import pytest

from gfrf.identify.frols import CRITERIA, candidate_keys, frols, regressor_code
from gfrf.identify.noise import regressors


def _data(seed: int, n: int = 1500, noise: float = 0.02) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1, 1, n)
    y = np.zeros(n)
    for k in range(2, n):
        y[k] = (0.6 * y[k - 1] - 0.2 * y[k - 2] + 0.5 * u[k - 1] + 0.3 * u[k - 2]
                + 0.15 * y[k - 1] * u[k - 1] - 0.1 * u[k - 1] ** 2 - 0.05 * y[k - 1] ** 3)
    return y + noise * rng.standard_normal(n) + 0.3, u


@pytest.mark.parametrize("seed, ylag, ulag, degree, criterion",
                         [(1, 2, 2, 3, "bic"), (2, 3, 1, 2, "aic"), (3, 1, 2, 3, "aicc"),
                          (4, 2, 2, 2, "fpe"), (5, 2, 3, 2, "lilc")])
def test_selection_matches_sysidentpy(seed, ylag, ulag, degree, criterion):
    """Same candidates (codes and columns), same criterion values for every size, same
    terms, coefficients and error reduction ratios as sysidentpy at the chosen size."""
    mss = pytest.importorskip("sysidentpy.model_structure_selection")
    from sysidentpy.basis_function import Polynomial
    from sysidentpy.parameter_estimation import LeastSquares

    y, u = _data(seed)
    keys = candidate_keys(ylag, ulag, degree)
    count = min(12, len(keys))
    ours = frols(y, u, ylag, ulag, degree, criterion, count)

    reference = mss.FROLS(ylag=ylag, xlag=ulag, order_selection=True, info_criteria=criterion,
                          n_info_values=count, estimator=LeastSquares(),
                          basis_function=Polynomial(degree=degree), model_type="NARMAX")
    reference.fit(X=u[:, None], y=y[:, None])
    codes = reference.regressor_space(1)
    assert [list(map(int, c)) for c in codes] == [regressor_code(k, degree) for k in keys]
    np.testing.assert_allclose(ours.criterion, reference.info_values, rtol=1e-10)

    size = len(ours.keys)
    assert size == int(np.argmin(reference.info_values)) + 1  # the global minimum
    fixed = mss.FROLS(ylag=ylag, xlag=ulag, order_selection=False, n_terms=size,
                      estimator=LeastSquares(), basis_function=Polynomial(degree=degree),
                      model_type="NARMAX")
    fixed.fit(X=u[:, None], y=y[:, None])
    assert [regressor_code(k, degree) for k in ours.keys] == \
        [list(map(int, c)) for c in fixed.final_model]
    np.testing.assert_allclose(ours.theta, np.ravel(fixed.theta), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ours.err, np.ravel(fixed.err)[:size], rtol=1e-9, atol=1e-15)


def test_forced_size_and_no_estimate():
    y, u = _data(7, n=800)
    forced = frols(y, u, 2, 2, 2, "bic", 9, forced=True)
    assert len(forced.keys) == 9 and forced.theta.size == 9
    bare = frols(y, u, 2, 2, 2, "bic", 9, estimate=False)
    assert bare.theta.size == 0 and bare.keys == forced.keys[:len(bare.keys)]
    # the coefficients are least squares on the chosen columns
    want = np.linalg.lstsq(regressors(forced.keys, y, u, 2), y[2:], rcond=None)[0]
    np.testing.assert_allclose(forced.theta, want, rtol=1e-10)


def test_criteria_formulas():
    """sysidentpy's formulas (Billings 2013, ch. 3), written out."""
    n, k, v = 1000, 5, 0.01
    base = n * np.log(v)
    assert CRITERIA["aic"](k, n, v) == pytest.approx(base + 2 * k)
    assert CRITERIA["bic"](k, n, v) == pytest.approx(base + k * np.log(n))
    assert CRITERIA["aicc"](k, n, v) == pytest.approx(base + 2 * k + 2 * k * (k + 1) / (n - k - 1))
    assert CRITERIA["fpe"](k, n, v) == pytest.approx(base + n * np.log((n + k) / (n - k)))
    assert CRITERIA["lilc"](k, n, v) == pytest.approx(base + 2 * k * np.log(np.log(n)))
