"""Free-run scores on held-out data, and the larger output-error model when a small one fails.

:func:`held_out_rrse` is the free-run RRSE of a model on the held-out samples, the run
started from measured outputs its warm-up before them
(:func:`gfrf.identify.output_error.warm_up`).  :func:`grow_output_error` chooses the
larger output-error model the identification tries when the criterion's terms do not
reproduce the held-out data.  Least squares on noisy outputs is biased (the regressors
hold the noise), so both the terms FROLS ranks on the measured outputs and the
least-squares start of their refinement can be far off.  FROLS's terms are refined from
their least-squares coefficients (given) and from the smaller model's output-error
optimum (new terms at 0), and the one with the smaller training free-run error kept;
other terms, ranked by error reduction ratio on regressors built from the smaller
model's free run, which holds no measurement noise, instead of the measured outputs
(the instrumental idea: the ranking is no longer biased by the noise), replace them
only when they lower that error clearly (beyond twice the standard error of a mean
square): several near-equal terms fit no better than one and cancel in the majorant.
"""

from __future__ import annotations

import math

import numpy as np

from gfrf.identify.noise import regressors
from gfrf.identify.ols import error_reduction_ratio
from gfrf.identify.output_error import WINDOW, recurse, refine, warm_up
from gfrf.identify.prune import free_run_residual

__all__ = ["held_out_rrse", "grow_output_error"]

Key = tuple[tuple[int, ...], tuple[int, ...]]


def held_out_rrse(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, n_train: int,
                  lag: int) -> float:
    """Free-run RRSE of ``theta`` on the samples from ``n_train + lag`` on (inf on a
    blow-up), the run started its warm-up before them.

    Parameters
    ----------
    theta : dict
        The model ``{(output lags, input lags): coefficient}`` about its centre.
    y, u : numpy.ndarray
        The whole record (training part, then held-out part) about that centre.
    n_train : int
        Samples of the training part.
    lag : int
        Largest lag.
    """
    w = warm_up(theta, lag, n_train - lag)
    r = free_run_residual(theta, y[n_train - w:], u[n_train - w:], lag, w)
    spread = float(np.var(y[n_train + lag:])) * (y.size - n_train - lag)
    return math.inf if r is None or not spread else math.sqrt(float(r @ r) / spread)


def _training_error(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, lag: int) -> float:
    """Mean squared free-run error on the training samples after the warm-up."""
    r = free_run_residual(theta, y, u, lag, warm_up(theta, lag, (y.size - lag) // 4))
    return math.inf if r is None or not r.size else float(r @ r) / r.size


def _simulated_ranking(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, lag: int,
                       candidates: list[Key], terms: int) -> list[Key] | None:
    """The ``terms`` candidates ranked first by error reduction ratio on regressors built
    from the free run of ``theta`` (None when it blows up)."""
    limit = 1e3 * max(1.0, float(np.max(np.abs(y))))
    run, blowup = recurse([(ys, us, c) for (ys, us), c in theta.items()], u, y[:lag], limit)
    if blowup is not None:
        return None
    w = warm_up(theta, lag, (y.size - lag) // 4)
    psi = regressors(candidates, run, u, lag)[w:]
    order = error_reduction_ratio(psi, y[lag + w:], min(terms, len(candidates)))[1]
    return [candidates[int(i)] for i in order]


def grow_output_error(small: dict[Key, float], grown: dict[Key, float], y: np.ndarray,
                      u: np.ndarray, lag: int, candidates: list[Key],
                      window: int = WINDOW) -> dict[Key, float]:
    """The larger output-error model with the smallest training free-run error.

    Parameters
    ----------
    small : dict
        The output-error model of the criterion's terms.
    grown : dict
        FROLS's larger model, refined from its least-squares coefficients.
    y, u : numpy.ndarray
        Training samples about the models' centre.
    lag : int
        Largest lag.
    candidates : list
        The candidate monomials of the structure.
    window : int, optional
        Samples each refinement fits (:func:`gfrf.identify.output_error.window_for`).

    Returns
    -------
    dict
        The chosen model's coefficients.
    """
    options = [grown, refine({k: small.get(k, 0.0) for k in grown}, y, u, lag, window=window)]
    errors = [_training_error(theta, y, u, lag) for theta in options]
    best = int(np.argmin(errors))
    ranked = _simulated_ranking(small, y, u, lag, candidates, len(grown))
    if ranked is None or set(ranked) == set(grown):
        return options[best]
    other = refine({k: small.get(k, 0.0) for k in ranked}, y, u, lag, window=window)
    # other terms only for a clear gain: beyond twice the relative standard error
    # sqrt(2/N) of a mean square of N samples (noise alone moves it that much)
    margin = 2.0 * math.sqrt(2.0 / max(1, y.size - lag))
    return other if _training_error(other, y, u, lag) < (1 - margin) * errors[best] \
        else options[best]
