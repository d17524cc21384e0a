"""The noise floor of held-out data: the free-run error no model driven by the input can beat.

Measurement noise ``v`` on the output is in the held-out record but not in any free run
driven by the input, so even the true system's free run scores ``RRSE = sd(v) / sd(y)``
against the data.  A fixed limit on the free-run RRSE therefore refuses good models of
noisy data; :func:`gfrf.identify.validate.judge` compares the part of the free-run error
above this floor with the limit instead.  :func:`noise_floor` estimates the floor, as an
RRSE of the held-out part, in one of two ways:

* ``"periods"``: when the input repeats with a period ``P`` (at least
  :data:`MIN_PERIODS` whole periods after the first, which is skipped as transient),
  the output's spread about its mean period is the noise (``sd(v)^2`` is the sum of
  squared deviations over ``P (periods - 1)``);
* ``"rich model"``: otherwise, the held-out one-step prediction errors of a rich
  predictor: least squares on every candidate of the structure (up to
  :data:`RICH_CANDIDATES`; beyond, the selected terms) and the linear terms in
  ``y[k-1..RICH_LAGS]`` and ``u[k-1..RICH_LAGS]`` (with output noise the best
  predictor from measured outputs needs lags beyond the structure's: for a lightly
  damped oscillator sampled fast, lags up to 2 put the floor 1.6 times above the noise,
  lags up to 8 within 10 %), its residuals whitened by an
  autoregressive model of order up to :data:`AR_ORDER` fitted on the training part.
  No predictor from the past can beat ``sd(v)`` (``v[k]`` is independent of it), and
  for white output noise on a system whose linear part is stable the best one reaches
  it: the equation error ``A(q) v`` has innovations of exactly the noise's variance
  (Jensen's formula: ``A(q)`` is monic and minimum phase).  A rich predictor that
  misses part of the dynamics over-estimates the floor by that part only, and it does
  not depend on the identified model.

Work is bounded by counts: at most :data:`RICH_ROWS` training rows.
"""

from __future__ import annotations

import math

import numpy as np

from gfrf.identify.noise import regressors

__all__ = ["noise_floor", "input_period", "MIN_PERIODS", "RICH_CANDIDATES", "RICH_ROWS",
           "RICH_LAGS", "AR_ORDER"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Whole periods, after the first, that a periodic estimate needs.
MIN_PERIODS = 2
#: Largest number of candidates the rich model takes (beyond: the selected terms).
RICH_CANDIDATES = 300
#: Training rows of the rich model's fit (the last ones of the training part).
RICH_ROWS = 20000
#: Linear output and input lags the rich model adds to the structure's candidates.
RICH_LAGS = 8
#: Largest order of the autoregressive whitening filter (at most 1/20 of the rows).
AR_ORDER = 100
#: Start positions tried when looking for the input's period.
_PERIOD_TRIALS = 2000


def input_period(u: np.ndarray) -> int | None:
    """The shortest period ``P`` (at most ``u.size // (MIN_PERIODS + 1)``) with
    ``u[k + P] == u[k]`` for every ``k``, or None.

    Parameters
    ----------
    u : numpy.ndarray
        The input samples.
    """
    n = u.size
    longest = n // (MIN_PERIODS + 1)
    if longest < 2 or np.all(u == u[0]):
        return None
    candidates = np.flatnonzero(u[1:longest + 1] == u[0]) + 1
    for p in candidates[:_PERIOD_TRIALS]:
        if np.array_equal(u[p:], u[:n - p]):
            return int(p)
    return None


def _periodic(y: np.ndarray, period: int) -> float:
    """The noise variance from the spread of ``y`` about its mean period (first skipped)."""
    count = y.size // period - 1
    block = y[period:period * (count + 1)].reshape(count, period)
    deviation = block - block.mean(axis=0)
    return float(np.sum(deviation**2)) / (period * (count - 1))


def noise_floor(y: np.ndarray, u: np.ndarray, n_train: int, lag: int,
                candidates: list[Key], selected: list[Key]) -> tuple[float, str]:
    """The noise floor of the held-out part ``y[n_train:]`` as an RRSE, and its method.

    Parameters
    ----------
    y, u : numpy.ndarray
        The whole record (training part, then held-out part), about the operating point.
    n_train : int
        Samples of the training part.
    lag : int
        Largest lag of the candidates.
    candidates, selected : list
        Every candidate monomial of the structure (the constant included) and the
        selected ones.

    Returns
    -------
    floor : float
        ``sd(v) / sd(y_held_out)`` (0 for an exact fit, capped at 1).
    method : str
        ``"periods"`` or ``"rich model"``.
    """
    test = y[n_train + lag:]
    spread = float(np.var(test))
    if spread == 0.0:
        return 0.0, "rich model"
    period = input_period(u)
    if period is not None and y.size // period - 1 >= MIN_PERIODS:
        return min(1.0, math.sqrt(_periodic(y, period) / spread)), "periods"
    keys = candidates if len(candidates) <= RICH_CANDIDATES else selected
    extra = min(RICH_LAGS, (y.size - n_train) // 4, n_train // 4)  # short records: fewer
    keys = list(dict.fromkeys([*keys, *[((j,), ()) for j in range(1, extra + 1)],
                               *[((), (j,)) for j in range(1, extra + 1)]]))
    lag = max(lag, extra)
    start = max(0, n_train - RICH_ROWS)
    psi = regressors(keys, y[start:n_train], u[start:n_train], lag)
    theta = np.linalg.lstsq(psi, y[start + lag:n_train], rcond=None)[0]
    e_train = y[start + lag:n_train] - psi @ theta
    e_test = y[n_train + lag:] - regressors(keys, y[n_train:], u[n_train:], lag) @ theta
    order = min(AR_ORDER, e_train.size // 20)
    if order:
        a = np.linalg.lstsq(_lagged(e_train, order), e_train[order:], rcond=None)[0]
        e_test = e_test[order:] - _lagged(e_test, order) @ a
    return min(1.0, math.sqrt(float(np.mean(e_test**2)) / spread)), "rich model"


def _lagged(e: np.ndarray, order: int) -> np.ndarray:
    """Columns ``e[k-1] .. e[k-order]`` at rows ``k = order .. n-1``."""
    return np.column_stack([e[order - j:e.size - j] for j in range(1, order + 1)])
