"""Lags swapped within collinear groups after pruning, on the training free run.

FROLS ranks candidates on the measured outputs; with noise on them it can pick
``y[k-2]**2`` where the system has ``y[k-1]**2``.  On fast sampling the two are nearly
the same regressor, but not in a free run: their difference ``(y[k-1] - y[k-2])(y[k-1] +
y[k-2])`` is an output-dependent damping, and on a lightly damped oscillator sampled at
T = 0.1 s a coefficient of 0.003 on it is about a tenth of the linear damping.  The
output-error optimum with the wrong lag then leaves a model error the correlation tests
see (held-out free run 0.027 against noise 0.021), and the right lag does not (0.022).
:func:`swap_lags` tries, for each term of the pruned model with output factors, the
other candidates of its group (:func:`gfrf.identify.prune._group`: same input factors,
same degree in the output) in its place, each refitted with the model's estimator to
convergence, and keeps the one with the smallest training free-run error when it is
clearly smaller (beyond twice the standard error of a mean square, the margin of
:mod:`gfrf.identify.grow`).  At most :data:`MAX_SWAPS` refits, each on the first
:data:`~gfrf.identify.prune.TRIAL_ROWS` training rows; a swapped model is refitted on
all of them.  On a long record (an output-error ``window`` below
:data:`~gfrf.identify.output_error.WINDOW`, :func:`~gfrf.identify.output_error.window_for`)
an output-error trial fits the first :data:`~gfrf.identify.prune.TRIAL_OE_WINDOW` of them
(its training free-run error is still scored on all of them), and the swapped model the
first ``window``.
"""

from __future__ import annotations

import math

import numpy as np

from gfrf.identify.grow import _training_error
from gfrf.identify.noise import extended_least_squares, regressors
from gfrf.identify.output_error import WINDOW, refine
from gfrf.identify.prune import TRIAL_OE_WINDOW, TRIAL_ROWS, _group, _name, carried

__all__ = ["swap_lags", "MAX_SWAPS"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Most trial refits of one pass.
MAX_SWAPS = 24


def swap_lags(theta: dict[Key, float], noise: tuple[float, ...], kind: str, y: np.ndarray,
              u: np.ndarray, lag: int, order: int, candidates: list[Key],
              window: int = WINDOW
              ) -> tuple[dict[Key, float], tuple[float, ...], list[tuple[str, str]]]:
    """One pass of swaps within collinear groups; returns the coefficients, the noise
    terms and the swaps made as ``(removed, added)`` names.

    Parameters
    ----------
    theta : dict
        The pruned model ``{(output lags, input lags): coefficient}``.
    noise : tuple of float
        Its noise terms (extended least squares).
    kind : {"none", "narmax", "output error"}
        Its estimator (:func:`gfrf.identify.prune.refitter`).
    y, u : numpy.ndarray
        Training samples about the model's centre.
    lag : int
        Largest lag.
    order : int
        Noise terms of extended least squares.
    candidates : list
        The candidate monomials of the structure.
    window : int, optional
        Samples an output-error refit of the swapped model fits
        (:func:`gfrf.identify.output_error.window_for`).
    """
    trial_window = window if window >= WINDOW else TRIAL_OE_WINDOW

    def refit(keys: list[Key], start: dict[Key, float], fitted: int = trial_window
              ) -> tuple[dict[Key, float], tuple[float, ...]]:
        if kind == "output error":
            return refine(carried(start, keys), y, u, lag, window=fitted), ()
        if kind == "narmax":
            return extended_least_squares(keys, y, u, lag, order)
        values = np.linalg.lstsq(regressors(keys, y, u, lag), y[lag:], rcond=None)[0]
        return {k: float(v) for k, v in zip(keys, values, strict=True)}, ()

    every = (y, u)
    y, u = y[:TRIAL_ROWS + lag], u[:TRIAL_ROWS + lag]
    margin = 2.0 * math.sqrt(2.0 / max(1, y.size - lag))
    error = _training_error(theta, y, u, lag)
    swaps: list[tuple[str, str]] = []
    trials = 0
    for term in list(theta):
        if term not in theta or _group(term) is None:
            continue
        best = None
        for other in candidates:
            if other in theta or _group(other) != _group(term) or trials >= MAX_SWAPS:
                continue
            trials += 1
            keys = [other if k == term else k for k in theta]
            start = {other if k == term else k: v for k, v in theta.items()}
            model, terms = refit(keys, start)
            e = _training_error(model, y, u, lag)
            if e < (1 - margin) * error and (best is None or e < best[0]):
                best = (e, model, terms, other)
        if best is not None:
            error, theta, noise = best[0], best[1], best[2]
            swaps.append((_name(term), _name(best[3])))
    if swaps and (every[0].size > y.size or trial_window < window):
        y, u = every
        theta, noise = refit(list(theta), theta, window)
    return theta, noise, swaps
