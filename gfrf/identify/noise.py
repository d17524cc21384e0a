"""NARMAX noise terms: extended least squares, and the residuals of a process + noise model.

Noise on a measured output makes the equation error of a NARX model coloured
(``v[k] - a1*v[k-1] - ...``), and least squares on such errors biases the process
terms.  :func:`extended_least_squares` re-estimates the selected process terms
together with moving-average noise terms ``c_j * e[k-j]`` (the classic NARMAX
extended least squares: the unmeasured ``e`` is replaced by the residuals of the
previous iteration); :func:`residuals` runs the process + noise model one step
ahead and returns ``e``, the residuals the correlation tests judge.

Models are dicts ``{(output lags, input lags): theta}`` of ``y[k] = sum theta*m``; the
noise model is a tuple ``(c_1, ..., c_q)``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["regressors", "extended_least_squares", "residuals", "ELS_ITERATIONS"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Most iterations of extended least squares (it stops earlier when no process
#: coefficient moves by more than 1e-14 of the largest, or when a step below
#: :data:`_ROUNDING_LEVEL` of the largest is no smaller than the one before: the
#: iteration has reached the level of its rounding errors, and the digits written are
#: those of the limit; work, never time, decides).
ELS_ITERATIONS = 200
#: Steps below this fraction of the largest coefficient that stop shrinking are rounding.
_ROUNDING_LEVEL = 1e-9


def regressors(keys: list[Key], y: np.ndarray, u: np.ndarray, lag: int) -> np.ndarray:
    """The columns ``m(y, u)`` at samples ``lag .. n-1`` (rows), one per key.

    Parameters
    ----------
    keys : list of Key
        ``(output lags, input lags)`` of each monomial.
    y, u : numpy.ndarray
        Output and input samples.
    lag : int
        The first sample used, at least the largest lag.

    Returns
    -------
    numpy.ndarray
        Shape ``(n - lag, len(keys))``.
    """
    n = y.size
    out = np.ones((n - lag, len(keys)))
    for j, (ys, us) in enumerate(keys):
        for signal, lags in ((y, ys), (u, us)):
            for order in lags:
                out[:, j] *= signal[lag - order:n - order]
    return out


def _ma_filter(r: np.ndarray, noise: tuple[float, ...]) -> np.ndarray:
    """e with e[k] = r[k] - sum_j c_j e[k-j] (zero before the first sample)."""
    from scipy.signal import lfilter

    if not noise:
        return r
    return lfilter([1.0], [1.0, *noise], r)


def residuals(theta: dict[Key, float], noise: tuple[float, ...], y: np.ndarray,
              u: np.ndarray, lag: int) -> np.ndarray:
    """One-step residuals ``e[k]`` of the process + noise model at samples ``lag..n-1``.

    Parameters
    ----------
    theta : dict of Key to float
        The process coefficients.
    noise : tuple of float
        The moving-average noise coefficients ``(c_1, ..., c_order)``.
    y, u : numpy.ndarray
        Output and input samples.
    lag : int
        The first sample used, at least the largest lag.

    Returns
    -------
    numpy.ndarray
        The ``n - lag`` residuals.
    """
    keys = list(theta)
    values = np.array([theta[k] for k in keys])
    r = y[lag:] - regressors(keys, y, u, lag) @ values
    return _ma_filter(r, noise)


def extended_least_squares(keys: list[Key], y: np.ndarray, u: np.ndarray, lag: int,
                           order: int, iterations: int = ELS_ITERATIONS
                           ) -> tuple[dict[Key, float], tuple[float, ...]]:
    """Process coefficients and ``order`` moving-average noise coefficients by ELS
    (at most ``iterations`` iterations).

    Parameters
    ----------
    keys : list of Key
        ``(output lags, input lags)`` of each process monomial.
    y, u : numpy.ndarray
        Output and input samples.
    lag : int
        The first sample used, at least the largest lag.
    order : int
        The order of the moving-average noise model.
    iterations : int, optional
        Most iterations.

    Returns
    -------
    theta : dict
        The process terms ``{key: theta}``.
    noise : tuple of float
        ``(c_1, ..., c_order)``: ``y[k] = sum theta*m + sum_j c_j*e[k-j] + e[k]`` with
        ``e`` white; the noise model is kept invertible (its iteration stops before a
        step that would make it not).
    """
    psi = regressors(keys, y, u, lag)
    target = y[lag:]
    q, r = np.linalg.qr(psi)
    q = np.asfortranarray(q)  # q.T @ extra in every iteration: contiguous columns
    qt = q.T @ target
    theta = _triangular(r, qt) if _well_conditioned(r) else \
        np.linalg.lstsq(psi, target, rcond=None)[0]
    e = target - psi @ theta
    noise = np.zeros(order)
    previous = np.inf
    for _iteration in range(iterations):
        lagged = np.column_stack([np.r_[np.zeros(j), e[:e.size - j]]
                                  for j in range(1, order + 1)])
        full = _augmented_least_squares(psi, q, r, qt, lagged, target)
        if np.any(np.abs(np.roots(np.r_[1.0, full[len(keys):]])) >= 1.0):
            break  # a noise model that is not invertible: keep the last invertible one
        step = float(np.max(np.abs(full[:len(keys)] - theta)))
        scale = float(np.max(np.abs(theta)))
        # converged, or at the rounding level: a small step that no longer shrinks
        done = step <= 1e-14 * scale or previous <= step <= _ROUNDING_LEVEL * scale
        previous = step
        theta, noise = full[:len(keys)], full[len(keys):]
        if done:
            break
        # the residuals of the process + noise model, run one step ahead
        e = _ma_filter(target - psi @ theta, tuple(noise))
    return ({k: float(v) for k, v in zip(keys, theta, strict=True)},
            tuple(float(c) for c in noise))


#: A triangular factor whose smallest diagonal entry is below this fraction of its
#: largest is treated as rank deficient (least squares by the SVD instead).
_RANK_TOLERANCE = 1e-10


def _well_conditioned(r: np.ndarray) -> bool:
    """True when the triangular factor ``r`` of a QR factorisation is safely invertible."""
    diag = np.abs(np.diag(r))
    return bool(diag.size) and float(np.min(diag)) > _RANK_TOLERANCE * float(np.max(diag))


def _triangular(r: np.ndarray, rhs: np.ndarray, lower: bool = False) -> np.ndarray:
    """The solution of the triangular system ``r x = rhs`` (upper unless ``lower``)."""
    from scipy.linalg import solve_triangular

    return np.asarray(solve_triangular(r, rhs, lower=lower))


def _augmented_least_squares(psi: np.ndarray, q: np.ndarray, r: np.ndarray, qt: np.ndarray,
                             extra: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least squares on the columns ``[psi, extra]`` from the QR factors of ``psi``.

    ``psi = q r`` and ``qt = q.T target`` are computed once; each call orthogonalises
    the few ``extra`` columns against ``q`` (classical Gram-Schmidt, repeated when a
    column kept less than :data:`_REORTHOGONALISE` of its squared norm: one pass leaves
    an orthogonality error of about the unit roundoff over that fraction) and factors
    what is left, ``rest``: the QR factorisation of the whole matrix by blocks,
    ``O(rows * columns * extra)`` work instead of a new factorisation.  The triangular
    factor of ``rest`` is the Cholesky factor of ``rest.T rest`` when that is well
    conditioned (lagged residuals are nearly orthogonal to each other), else that of a
    QR factorisation.  A rank-deficient matrix goes to ``numpy.linalg.lstsq``
    (minimum-norm solution).
    """
    c = q.T @ extra
    rest = extra - q @ c
    if np.any(np.einsum("ij,ij->j", rest, rest)
              < _REORTHOGONALISE * np.einsum("ij,ij->j", extra, extra)):
        c2 = q.T @ rest  # much cancelled: once more
        rest -= q @ c2
        c += c2
    k = rest.shape[1]
    r22, top2 = _cholesky_factor(rest, target)
    if r22 is None:  # the triangular factor of [rest, target]: r22 and q2.T @ target
        r2 = np.asarray(np.linalg.qr(np.column_stack([rest, target]), mode="r"))
        r22, top2 = r2[:k, :k], r2[:k, k]
    whole = np.vstack([np.hstack([r, c]), np.hstack([np.zeros((k, r.shape[1])), r22])])
    if not _well_conditioned(whole):
        return np.asarray(np.linalg.lstsq(np.hstack([psi, extra]), target, rcond=None)[0])
    return _triangular(whole, np.r_[qt, top2])


#: An extra column that keeps less than this fraction of its squared norm after one
#: Gram-Schmidt pass is orthogonalised again.
_REORTHOGONALISE = 0.01
#: A Cholesky factor of ``rest.T rest`` whose smallest diagonal entry is below this
#: fraction of its largest squares too large a condition number: QR instead.
_CHOLESKY_TOLERANCE = 1e-4


def _cholesky_factor(rest: np.ndarray, target: np.ndarray
                     ) -> tuple[np.ndarray | None, np.ndarray]:
    """``(r22, q2.T target)`` of ``rest = q2 r22`` from the Cholesky factor of
    ``rest.T rest``; ``(None, ...)`` when that is not well conditioned."""
    try:
        lower = np.linalg.cholesky(rest.T @ rest)
    except np.linalg.LinAlgError:
        return None, target[:0]
    diag = np.abs(np.diag(lower))
    if not float(np.min(diag)) > _CHOLESKY_TOLERANCE * float(np.max(diag)):
        return None, target[:0]
    return lower.T, _triangular(lower, rest.T @ target, lower=True)
