"""Output-error refinement: the process coefficients that best reproduce the output in free run.

White noise added to a measured output makes a NARX model's equation error coloured,
with a moving-average part whose roots come close to the unit circle for lightly
damped systems, where extended least squares (:mod:`gfrf.identify.noise`) cannot keep
its noise model invertible.  The output-error estimate of the same terms minimises
instead the free-run (simulation) error ``sum (y - y_sim(theta))**2`` over the training
samples, which white output noise does not bias.  :func:`refine` starts from the
least-squares coefficients and runs scipy's Levenberg-Marquardt for a bounded number
of evaluations, on at most :data:`WINDOW` samples (:data:`LONG_WINDOW` on a record of
more than :data:`LONG_RECORD` training samples, :func:`window_for`: a bound on the work of
a pure-Python free run); :func:`simulate` is the free run.

Models are dicts ``{(output lags, input lags): theta}`` of ``y[k] = sum theta*m`` (the
key ``((), ())`` is a constant).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["refine", "simulate", "recurse", "output_error_covariance", "warm_up", "WINDOW",
           "MAX_EVALUATIONS", "SETTLE", "LONG_RECORD", "LONG_WINDOW", "window_for"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Training samples the refinement simulates (the first ones): bounds its work.
WINDOW = 20000
#: Training samples beyond which a record is long: its refinements fit fewer samples.
LONG_RECORD = 40_000
#: Training samples the refinement simulates on a long record.
LONG_WINDOW = 5000
#: Most residual evaluations of the refinement (work, never time, bounds it).
MAX_EVALUATIONS = 400
#: A simulation stops when |y| exceeds this multiple of the data's largest |y|.
_BLOWUP = 1e3
#: A free run is scored once its linear part's slowest mode has decayed to this fraction.
SETTLE = 1e-3


def window_for(n_train: int) -> int:
    """Samples an output-error refinement fits on a record of ``n_train`` training samples:
    :data:`WINDOW`, or :data:`LONG_WINDOW` beyond :data:`LONG_RECORD` (the many
    refinements of an identification stay within a bounded work on a long record).

    Parameters
    ----------
    n_train : int
        Training samples of the record.
    """
    return WINDOW if n_train <= LONG_RECORD else LONG_WINDOW


def warm_up(theta: dict[Key, float], lag: int, most: int) -> int:
    """Samples a free run needs before it is scored: its start is forgotten by then.

    A free run starts from ``lag`` measured outputs, noise included; for a lightly
    damped system sampled fast the difference of two noisy outputs is a large velocity
    error, and the transient it starts (about ``noise / (omega T)``) can dominate the
    free-run error of a perfect model for hundreds of samples.  The warm-up is the
    number of samples in which the slowest mode of the linear part (spectral radius
    ``rho`` of ``y[k] = sum a_j y[k-j]``) decays to :data:`SETTLE`:
    ``ceil(log(SETTLE) / log(rho))``, at most ``most``; 0 when the linear part has no
    output terms, ``most`` when it does not decay (``rho >= 1``).

    Parameters
    ----------
    theta : dict of Key to float
        The model's coefficients.
    lag : int
        Its largest lag.
    most : int
        The largest warm-up allowed (the samples available before the scored part).

    Returns
    -------
    int
        The number of samples.
    """
    a = [theta.get(((j,), ()), 0.0) for j in range(1, lag + 1)]
    roots = np.roots(np.r_[1.0, -np.asarray(a, dtype=float)]) if any(a) else np.zeros(0)
    rho = float(np.max(np.abs(roots), initial=0.0))
    if rho == 0.0:
        return 0
    if rho >= 1.0:
        return max(0, most)
    return max(0, min(most, math.ceil(math.log(SETTLE) / math.log(rho))))


def simulate(keys: list[Key], theta: np.ndarray, u: np.ndarray, y_initial: np.ndarray,
             limit: float) -> np.ndarray | None:
    """Free run of ``y[k] = sum theta_i m_i`` from the measured first outputs; None when
    ``|y|`` exceeds ``limit``.

    Parameters
    ----------
    keys : list of Key
        ``(output lags, input lags)`` of each monomial.
    theta : numpy.ndarray
        The coefficients, one per key.
    u : numpy.ndarray
        Input samples.
    y_initial : numpy.ndarray
        The measured outputs before the first simulated sample.
    limit : float
        The bound on |y| beyond which the run stops.

    Returns
    -------
    numpy.ndarray or None
        The outputs (``u.size`` samples), or None after a blow-up.
    """
    values, blowup = recurse([(ys, us, float(c)) for (ys, us), c in
                              zip(keys, theta, strict=True)], u, y_initial, limit)
    return None if blowup is not None else values


def recurse(terms: list[tuple[tuple[int, ...], tuple[int, ...], float]], u: np.ndarray,
            y_initial: np.ndarray, limit: float) -> tuple[np.ndarray, int | None]:
    """Free run of ``y[k] = sum c * prod y[k - ys] * prod u[k - us]`` over ``terms``
    ``(ys, us, c)``, from the measured first outputs ``y_initial``.

    Returns the outputs (NaN from a blow-up on) and the first sample whose ``|y|``
    exceeds ``limit``, or None.

    Parameters
    ----------
    terms : list of tuple
        ``(output lags, input lags, coefficient)`` per monomial.
    u : numpy.ndarray
        Input samples.
    y_initial : numpy.ndarray
        The measured outputs before the first simulated sample.
    limit : float
        The bound on |y| beyond which the run stops.
    """
    n = u.size
    start = y_initial.size
    forced = np.zeros(n)
    dynamic = []
    for ys, us, c in terms:
        factor = np.full(n, c)
        for lag in us:
            factor[lag:] *= u[:n - lag]
            factor[:lag] = 0.0
        if ys:
            dynamic.append((ys, factor.tolist()))
        else:
            forced += factor
    values = np.full(n, np.nan).tolist()
    values[:start] = y_initial.tolist()
    forced_list = forced.tolist()
    for k in range(start, n):
        total = forced_list[k]
        for lags, factor in dynamic:
            term = factor[k]
            for lag in lags:
                term *= values[k - lag]
            total += term
        if not abs(total) <= limit:
            return np.asarray(values), k
        values[k] = total
    return np.asarray(values), None


def refine(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, lag: int,
           evaluations: int = MAX_EVALUATIONS, window: int = WINDOW) -> dict[Key, float]:
    """The output-error coefficients of the same terms, from ``theta`` (Levenberg-Marquardt
    with at most ``evaluations`` residual evaluations on the first ``window`` samples;
    the free run's first samples, its :func:`warm_up` for ``theta``, at most a quarter
    of them, are simulated but not fitted).

    Parameters
    ----------
    theta : dict of Key to float
        The starting coefficients (e.g. the least-squares ones).
    y, u : numpy.ndarray
        Output and input samples.
    lag : int
        The number of measured outputs the simulation starts from.
    evaluations : int, optional
        Most residual evaluations.
    window : int, optional
        Number of samples fitted, from the first.

    Returns
    -------
    dict of Key to float
        The refined coefficients (``theta`` unchanged when its free run blows up).
    """
    from scipy.optimize import least_squares

    keys = list(theta)
    n = min(y.size, window)
    y, u = y[:n], u[:n]
    limit = _BLOWUP * max(1.0, float(np.max(np.abs(y))))
    first = lag + warm_up(theta, lag, (n - lag) // 4)  # the start's transient not fitted
    penalty = np.full(n - first, limit)

    def residual(values: np.ndarray) -> np.ndarray:
        sim = simulate(keys, values, u, y[:lag], limit)
        return penalty if sim is None else sim[first:] - y[first:]

    start = np.array([theta[k] for k in keys])
    if simulate(keys, start, u, y[:lag], limit) is None:
        return dict(theta)  # no finite starting point: nothing to refine
    result = least_squares(residual, start, method="lm", xtol=1e-12, ftol=1e-12,
                           max_nfev=evaluations)
    return {k: float(v) for k, v in zip(keys, result.x, strict=True)}


def output_error_covariance(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, lag: int,
                            window: int = WINDOW) -> np.ndarray:
    """Covariance ``s^2 (J^T J)^-1`` of output-error coefficients: ``J`` the forward-difference
    Jacobian of the free run (first ``window`` samples, after the warm-up :func:`refine`
    leaves out) by the coefficients, ``s^2`` the free-run residual's variance (inf
    entries when a free run blows up).

    Parameters
    ----------
    theta : dict
        The output-error coefficients.
    y, u : numpy.ndarray
        Training samples.
    lag : int
        Largest lag.
    window : int
        Samples simulated (the first ones).
    """
    keys = list(theta)
    n = min(y.size, window)
    y, u = y[:n], u[:n]
    limit = _BLOWUP * max(1.0, float(np.max(np.abs(y))))
    first = lag + warm_up(theta, lag, (n - lag) // 4)  # as refine fitted them
    values = np.array([theta[k] for k in keys])
    base = simulate(keys, values, u, y[:lag], limit)
    if base is None:
        return np.full((len(keys), len(keys)), math.inf)
    columns = []
    for i in range(len(keys)):
        step = 1e-6 * max(abs(values[i]), 1e-8)
        moved = values.copy()
        moved[i] += step
        sim = simulate(keys, moved, u, y[:lag], limit)
        if sim is None:
            return np.full((len(keys), len(keys)), math.inf)
        columns.append((sim[first:] - base[first:]) / step)
    jac = np.column_stack(columns)
    r = y[first:] - base[first:]
    variance = float(r @ r) / max(1, r.size - len(keys))
    return variance * np.linalg.pinv(jac.T @ jac)
