"""Forward regression orthogonal least squares (FROLS) with an information criterion.

:func:`frols` is the structure selection of the NARMAX school (Chen, Billings and Luo
1989; Billings 2013) as sysidentpy's ``FROLS`` runs it with its ``Polynomial`` basis
and ``LeastSquares`` estimator: the candidates are the constant and every monomial of
degree 1..``degree`` in ``y[k-1..ylag]`` and ``u[k-1..ulag]``, in sysidentpy's order
(:func:`candidate_keys`); the error reduction ratio ranks them
(:func:`gfrf.identify.ols.error_reduction_ratio`); the criterion (sysidentpy's
formulas, :data:`CRITERIA`) of the first n ranked terms, for n up to ``max_terms``,
comes from one QR factorisation of those terms; least squares (``numpy.linalg.lstsq``,
as sysidentpy's estimator) gives the coefficients of the size the criterion takes.  The
size is the criterion's global minimum (sysidentpy stops at its first local minimum,
one term for a lightly damped system).

The candidate matrix is built once, one candidate per contiguous row, and ranked in
place: one copy of it in memory, and no import of sysidentpy.
:func:`regressor_code` writes a term as sysidentpy's regressor code (``1000 + lag`` for
an output factor, ``2000 + lag`` for an input factor, largest first, zero-padded).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gfrf.identify.ols import error_reduction_ratio

__all__ = ["CRITERIA", "Selection", "candidate_keys", "frols", "regressor_code"]

Key = tuple[tuple[int, ...], tuple[int, ...]]


def _aic(n_theta: int, n_samples: int, e_var: float) -> float:
    return float(n_samples * np.log(e_var) + 2 * n_theta)


def _aicc(n_theta: int, n_samples: int, e_var: float) -> float:
    return _aic(n_theta, n_samples, e_var) + 2 * n_theta * (n_theta + 1) / (
        n_samples - n_theta - 1)


def _bic(n_theta: int, n_samples: int, e_var: float) -> float:
    return float(n_samples * np.log(e_var) + n_theta * np.log(n_samples))


def _fpe(n_theta: int, n_samples: int, e_var: float) -> float:
    return float(n_samples * np.log(e_var)
                 + n_samples * np.log((n_samples + n_theta) / (n_samples - n_theta)))


def _lilc(n_theta: int, n_samples: int, e_var: float) -> float:
    return float(n_samples * np.log(e_var) + 2 * n_theta * np.log(np.log(n_samples)))


#: The information criteria ``f(terms, samples, residual variance)``, sysidentpy's formulas.
CRITERIA: dict[str, Callable[[int, int, float], float]] = {
    "aic": _aic, "aicc": _aicc, "bic": _bic, "fpe": _fpe, "lilc": _lilc}


def candidate_keys(ylag: int, ulag: int, degree: int) -> list[Key]:
    """The constant and every monomial of degree 1..``degree``, in sysidentpy's order.

    Parameters
    ----------
    ylag, ulag : int
        Largest output and input lags.
    degree : int
        Largest degree.

    Returns
    -------
    list of Key
        ``(output lags, input lags)`` of each candidate, the constant ``((), ())`` first.
    """
    factors = [("y", lag) for lag in range(1, ylag + 1)] + \
        [("u", lag) for lag in range(1, ulag + 1)]
    keys: list[Key] = [((), ())]
    for d in range(1, degree + 1):
        for combo in itertools.combinations_with_replacement(factors, d):
            keys.append((tuple(sorted(lag for n, lag in combo if n == "y")),
                         tuple(sorted(lag for n, lag in combo if n == "u"))))
    return keys


def regressor_code(key: Key, degree: int) -> list[int]:
    """sysidentpy's regressor code of a monomial (a row of its ``final_model``).

    Parameters
    ----------
    key : Key
        ``(output lags, input lags)``.
    degree : int
        The length of the row.

    Returns
    -------
    list of int
        ``1000 + lag`` per output factor, ``2000 + lag`` per input factor, largest
        first, zeros after.
    """
    codes = sorted([1000 + lag for lag in key[0]] + [2000 + lag for lag in key[1]],
                   reverse=True)
    return codes + [0] * (degree - len(codes))


def _candidate_rows(keys: list[Key], y: np.ndarray, u: np.ndarray, lag: int) -> np.ndarray:
    """The candidates at samples ``lag..n-1``, one per contiguous row (``keys x rows``);
    each product in the order of :func:`gfrf.identify.noise.regressors` (same bits)."""
    n = y.size
    out = np.ones((len(keys), n - lag))
    for j, (ys, us) in enumerate(keys):
        for signal, lags in ((y, ys), (u, us)):
            for order in lags:
                out[j] *= signal[lag - order:n - order]
    return out


@dataclass(frozen=True)
class Selection:
    """The terms FROLS selected, their coefficients and the criterion.

    Attributes
    ----------
    keys : list of Key
        The selected monomials, in the order of selection.
    theta : numpy.ndarray
        Their least-squares coefficients (empty when not estimated).
    err : numpy.ndarray
        The error reduction ratio of each selected term.
    criterion : numpy.ndarray
        The criterion of the first 1..``max_terms`` ranked terms.
    """

    keys: list[Key]
    theta: np.ndarray
    err: np.ndarray
    criterion: np.ndarray


def frols(y: np.ndarray, u: np.ndarray, ylag: int, ulag: int, degree: int, criterion: str,
          max_terms: int, forced: bool = False, estimate: bool = True) -> Selection:
    """FROLS on the samples ``y, u``: the criterion's terms and their coefficients.

    Parameters
    ----------
    y, u : numpy.ndarray
        Output and input samples (the fit uses samples ``max(ylag, ulag)`` onwards).
    ylag, ulag, degree : int
        Largest output lag, input lag and degree of the candidates.
    criterion : str
        A key of :data:`CRITERIA`.
    max_terms : int
        Largest number of terms considered (at most the candidates).
    forced : bool, optional
        ``max_terms`` terms whatever the criterion says.
    estimate : bool, optional
        Estimate the coefficients (False: ``theta`` is empty).

    Returns
    -------
    Selection
    """
    lag = max(ylag, ulag)
    keys = candidate_keys(ylag, ulag, degree)
    count = min(max_terms, len(keys))
    target = np.asarray(y[lag:], dtype=float)
    rows = _candidate_rows(keys, y, u, lag)
    ratios, order = error_reduction_ratio(rows.T, target, count, overwrite=True)
    del rows  # ranked in place: the candidates are no longer whole
    chosen = [keys[int(i)] for i in order]
    columns = _candidate_rows(chosen, y, u, lag).T
    # least squares on each prefix from one QR factorisation: the residual of the first
    # i+1 columns is the target minus its projections on q_0..q_i
    q = np.linalg.qr(columns, mode="reduced")[0]
    residual = target.copy()
    coefficients = q.T @ residual
    values = np.full(count, np.nan)
    rule = CRITERIA[criterion]
    for i in range(count):
        residual = residual - q[:, i] * coefficients[i]
        values[i] = rule(i + 1, target.size, float(np.var(residual, ddof=1)))
    size = count if forced else int(np.argmin(values)) + 1
    theta = np.ravel(np.linalg.lstsq(columns[:, :size], target[:, None], rcond=None)[0]) \
        if estimate else np.zeros(0)
    return Selection(keys=chosen[:size], theta=theta, err=ratios[:size].copy(),
                     criterion=values)
