"""Backward elimination of identified terms, judged on the held-out free run.

An information criterion on one-step residuals keeps terms that lower the residual a
little (noise fitted, or small terms that nearly cancel); their magnitudes all enter
the majorant of Theorem 1 and lower the radius r*.  :func:`prune` removes them again:
in each round the terms are tried in the order of their least-squares t-statistic
(smallest ``|theta| / sd`` first; on noisy data only those below :data:`SIGNIFICANT`),
each removal refitted with the same estimator and
simulated on the held-out part; the first removal whose free run stays within the
confidence band of the full model's is kept, and the next round starts.  Given a
``score`` (r* of a model), the elimination starts with merges of nearly collinear terms:
on fast sampling ``y[k-1]**3``, ``y[k-1]**2*y[k-2]``, ``y[k-2]**3`` are nearly the same
regressor, the band cannot tell them apart, and a pair that nearly cancels adds both
magnitudes to the majorant of r*.  Each group of terms with the same input factors and
the same degree in the output is replaced by the one of its members whose refitted
model stays within the band with the largest score, when that beats the model's.
An output-error trial starts from the group's coefficients summed on the member kept
(:func:`carried`): from that member's own coefficient alone, the model can be far off
or blow up, and a trial's few steps do not recover.
Merges are tried on noisy data only (:func:`prune_and_refit`): a noise-free record
identifies the true terms, and a merge would only trade accuracy for r*.  The band is
paired: the squared free-run errors of the candidate and of the full model are
compared sample by sample, averaged over :data:`BLOCKS` consecutive blocks, and the
mean difference must be at most :data:`Z` standard errors of the block means plus
``TOLERANCE**2`` of the output's variance (the slack a noise-free record needs, whose
band is empty).

Work is bounded by counts: at most :data:`MAX_REFITS` refits, free runs of at most
:data:`WINDOW` held-out samples each, and at most :data:`MAX_WORK` term-samples
simulated in all (a free run of ``m`` terms over ``n`` samples counts ``m n``; an
output-error refit counts its evaluations); a model of more than :data:`MAX_TERMS` terms
is not pruned.

Models are dicts ``{(output lags, input lags): theta}`` of ``y[k] = sum theta*m`` (the
key ``((), ())`` is a constant, never removed).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gfrf._results import Result, short_repr
from gfrf.identify.noise import regressors
from gfrf.identify.output_error import recurse

__all__ = ["Pruning", "prune", "free_run_residual", "t_statistics", "covariance",
           "refitter", "carried", "prune_and_refit", "WINDOW", "MAX_REFITS", "MAX_WORK",
           "MAX_TERMS", "SIGNIFICANT", "BLOCKS", "Z", "TOLERANCE", "CAP", "TRIAL_ROWS"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Held-out samples each trial free run simulates (the first ones).
WINDOW = 5000
#: Most refits (trial removals) of one elimination.
MAX_REFITS = 200
#: Most term-samples simulated by one elimination (about 5 s of CPU).
MAX_WORK = 30_000_000
#: Largest model that is pruned.
MAX_TERMS = 40
#: On noisy data, terms with a least-squares t-statistic at least this are never removed.
SIGNIFICANT = 3.0
#: Blocks of the held-out window whose means give the band's standard error.
BLOCKS = 10
#: Width of the band in standard errors.
Z = 2.0
#: Free-run RRSE (in quadrature) a removal may add even when the band is empty.
TOLERANCE = 0.01
#: Free-run RRSE (in quadrature) a removal may never exceed, whatever the band.
CAP = 0.02
#: A trial free run stops when |y| exceeds this multiple of the data's largest |y|.
_BLOWUP = 1e3


def free_run_residual(theta: dict[Key, float], y: np.ndarray, u: np.ndarray, lag: int,
                      warm: int = 0) -> np.ndarray | None:
    """``y - y_sim`` at samples ``lag + warm ..`` of the model's free run from the measured
    first outputs, or None on a blow-up.

    Parameters
    ----------
    theta : dict
        The model ``{(output lags, input lags): coefficient}``.
    y, u : numpy.ndarray
        Output and input samples.
    lag : int
        Measured outputs the free run starts from.
    warm : int, optional
        Samples simulated after those but not scored (the start's transient:
        :func:`gfrf.identify.output_error.warm_up`).
    """
    terms = [(ys, us, c) for (ys, us), c in theta.items()]
    limit = _BLOWUP * max(1.0, float(np.max(np.abs(y))))
    values, blowup = recurse(terms, u, y[:lag], limit)
    first = lag + warm
    return None if blowup is not None else y[first:] - values[first:]


def covariance(keys: list[Key], theta: np.ndarray, y: np.ndarray, u: np.ndarray, lag: int,
               variance: float | None = None) -> np.ndarray:
    """Least-squares covariance ``s^2 (Psi^T Psi)^-1`` of the coefficients of ``keys``.

    ``s^2`` is ``variance`` when given (the innovations' of a noise model), else the
    variance of the equation error ``y - Psi theta`` (``len(keys)`` degrees of freedom).

    Parameters
    ----------
    keys : list
        The monomials ``(output lags, input lags)``.
    theta : numpy.ndarray
        Their coefficients.
    y, u : numpy.ndarray
        Output and input samples of the fit.
    lag : int
        Largest lag (the rows start there).
    variance : float, optional
        The residual variance ``s^2``.
    """
    psi = regressors(keys, y, u, lag)
    if variance is None:
        e = y[lag:] - psi @ theta
        variance = float(e @ e) / max(1, e.size - len(keys))
    return variance * np.linalg.pinv(psi.T @ psi)


def t_statistics(keys: list[Key], theta: np.ndarray, y: np.ndarray, u: np.ndarray,
                 lag: int) -> np.ndarray:
    """``|theta| / sd`` of each coefficient (inf where its sd is 0).

    Parameters
    ----------
    keys, theta, y, u, lag
        As in :func:`covariance`.
    """
    sd = np.sqrt(np.maximum(np.diag(covariance(keys, theta, y, u, lag)), 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(sd > 0, np.abs(theta) / np.where(sd > 0, sd, 1.0), math.inf)


@dataclass(frozen=True, kw_only=True)
class Pruning(Result):
    """What :func:`prune` removed, and the free runs it compared.

    Attributes
    ----------
    removed : tuple of str
        The monomials removed, in order.
    added : tuple of str
        Candidates swapped in for a term of their collinear group
        (:func:`gfrf.identify.swap.swap_lags`; the terms they replaced are in ``removed``).
    full_error, pruned_error : float
        Held-out free-run RRSE of the full and the pruned model on the window.
    refits : int
        Trial removals refitted and simulated.
    complete : bool
        False when :data:`MAX_REFITS` or :data:`MAX_WORK` stopped the elimination before
        its end, or the model has more than :data:`MAX_TERMS` terms.
    window : int
        Held-out samples simulated.
    """

    removed: tuple[str, ...]
    added: tuple[str, ...] = ()
    full_error: float
    pruned_error: float
    refits: int
    complete: bool
    window: int



    def __repr__(self) -> str:
        return short_repr(self, "removed", "pruned_error")

    def text(self) -> str:
        """One line for the text output."""
        what = (f"removed {len(self.removed)} term(s) ({', '.join(self.removed)})"
                if self.removed else "removed no term")
        if self.added:
            what += f", swapped in {', '.join(self.added)}"
        stop = "" if self.complete else (f" (stopped at a work limit: {MAX_REFITS} refits, "
                                         f"{MAX_WORK:.3g} term-samples, {MAX_TERMS} terms)")
        return (f"pruning: {what}: held-out free-run RRSE {self.pruned_error:.4g} against "
                f"{self.full_error:.4g} with every term, within the band ({Z:g} standard errors "
                f"of {BLOCKS} block means or {TOLERANCE:g}^2, at most {CAP:g}^2){stop}")


def _name(key: Key) -> str:
    ys, us = key
    return "*".join([f"y[k-{lag}]" for lag in ys] + [f"u[k-{lag}]" for lag in us]) or "1"


def _merge(current: dict[Key, float], best: np.ndarray,
           score: Callable[[dict[Key, float]], float], budget: list[int],
           trial: Callable[[list[Key]], tuple[dict[Key, float], np.ndarray | None]],
           removed: list[str], unit: int) -> tuple[dict[Key, float], np.ndarray]:
    """Each collinear group replaced by its best-scoring member within the band (when it
    beats the model's score); ``budget`` = [refits, work] is counted on, ``removed``
    gets the names of the terms merged away; a trial costs ``unit`` per term."""
    for group in _collinear_groups(current):
        value = score(current)
        choice = None
        for keep in group:
            if budget[0] >= MAX_REFITS or budget[1] + unit * len(current) > MAX_WORK:
                break
            budget[0] += 1
            budget[1] += unit * len(current)
            model, r = trial([k for k in current if k == keep or k not in group])
            if r is not None and (s := score(model)) > value:
                choice, value = (model, r, keep), s
        if choice is not None:
            removed += [_name(k) for k in group if k != choice[2]]
            current, best = choice[0], choice[1]
    return current, best


def _collinear_groups(theta: dict[Key, float]) -> list[list[Key]]:
    """Groups of two or more terms with the same input factors and the same degree in
    the output (nearly the same regressor when the output changes little per sample)."""
    groups: dict[tuple[int, tuple[int, ...]], list[Key]] = {}
    for key in theta:
        if (group := _group(key)) is not None:
            groups.setdefault(group, []).append(key)
    return [g for g in groups.values() if len(g) > 1]


def _group(key: Key) -> tuple[int, tuple[int, ...]] | None:
    """The collinear group of a nonlinear term with output factors: (output degree, input
    lags); None for the others."""
    return (len(key[0]), key[1]) if key[0] and len(key[0]) + len(key[1]) > 1 else None


def _within(trial: np.ndarray, full: np.ndarray, scale: float) -> bool:
    """True when the mean of ``trial**2 - full**2`` is within the paired band."""
    d = trial**2 - full**2
    blocks = np.array([b.mean() for b in np.array_split(d, BLOCKS)])
    error = float(np.std(blocks, ddof=1)) / math.sqrt(BLOCKS)
    mean = float(np.mean(d))
    return mean <= max(Z * error, TOLERANCE**2 * scale) and mean <= CAP**2 * scale


def prune(theta: dict[Key, float], refit: Callable[[list[Key]], dict[Key, float]],
          y_train: np.ndarray, u_train: np.ndarray, y_test: np.ndarray, u_test: np.ndarray,
          lag: int, refit_work: int = 0, significant: float = math.inf, warm: int = 0,
          score: Callable[[dict[Key, float]], float] | None = None
          ) -> tuple[dict[Key, float], Pruning]:
    """Backward elimination of the terms of ``theta`` on the held-out free run.

    Parameters
    ----------
    theta : dict
        The full model ``{key: coefficient}`` (a constant key is kept).
    refit : callable
        ``refit(keys)`` returns the coefficients of a model with only ``keys``, fitted
        with the estimator that gave ``theta``.
    y_train, u_train : numpy.ndarray
        The training samples (for the t-statistics that order the trials).
    y_test, u_test : numpy.ndarray
        The held-out samples (about the same operating point as ``theta``), after
        ``warm`` samples that precede them.
    lag : int
        The largest lag of the candidates (the free runs start from ``lag`` measured
        outputs).
    refit_work : int
        Term-samples one refit simulates per term of the model (0: least squares).
    significant : float
        Terms whose least-squares t-statistic is at least this are kept (inf: every term
        may go; noise-free data, whose residuals are the fit's structural error, give
        t-statistics that mean nothing).
    warm : int, optional
        Samples at the start of ``y_test`` the free runs go through before they are
        scored.
    score : callable, optional
        ``score(theta)``, larger is better (r* of the model): merges of collinear terms
        before the elimination (None: none).

    Returns
    -------
    theta : dict
        The pruned model (``theta`` itself when nothing was removed).
    Pruning
    """
    first = lag + warm
    n = min(y_test.size, WINDOW + first)
    y_w, u_w = y_test[:n], u_test[:n]
    scale = float(np.var(y_w[first:]))
    full = free_run_residual(theta, y_w, u_w, lag, warm)
    spread = math.sqrt(scale * (y_w.size - first)) if scale else math.inf

    def rrse(r: np.ndarray | None) -> float:
        return math.inf if r is None else float(np.linalg.norm(r)) / spread

    current, refits, complete = dict(theta), 0, True
    removed: list[str] = []
    if full is None or scale == 0.0 or len(theta) > MAX_TERMS:
        return current, Pruning(removed=(), full_error=rrse(full), pruned_error=rrse(full),
                                refits=0, complete=len(theta) <= MAX_TERMS, window=n - first)
    best = full
    work = 0

    def merge_trial(keys: list[Key]) -> tuple[dict[Key, float], np.ndarray | None]:
        trial = refit(keys)
        r = free_run_residual(trial, y_w, u_w, lag, warm)
        return trial, r if r is not None and _within(r, full, scale) else None

    budget = [refits, work]
    if score is not None:
        current, best = _merge(current, best, score=score, budget=budget, trial=merge_trial,
                               removed=removed, unit=n + refit_work)
    refits, work = budget
    while True:
        keys = [k for k in current if k != ((), ())]
        if len(keys) <= 1:
            break
        stats = t_statistics(list(current), np.array(list(current.values())), y_train,
                             u_train, lag)
        order = sorted((s, i) for i, (k, s) in enumerate(zip(current, stats, strict=True))
                       if k != ((), ()) and s < significant)
        accepted = None
        for _, i in order:
            cost = (n + refit_work) * len(current)
            if refits >= MAX_REFITS or work + cost > MAX_WORK:
                complete = False
                break
            work += cost
            key = list(current)[i]
            trial_keys = [k for k in current if k != key]
            if not any(us for _, us in trial_keys):
                continue  # a model without input terms has no GFRFs
            refits += 1
            trial = refit(trial_keys)
            r = free_run_residual(trial, y_w, u_w, lag, warm)
            if r is not None and _within(r, full, scale):
                accepted = (key, trial, r)
                break
        if accepted is None or not complete:
            break
        removed.append(_name(accepted[0]))
        current, best = accepted[1], accepted[2]
    return current, Pruning(removed=tuple(removed), full_error=rrse(full),
                            pruned_error=rrse(best), refits=refits, complete=complete,
                            window=n - first)


#: Iterations of extended least squares in a trial refit.
TRIAL_ELS_ITERATIONS = 30
#: Training rows of a trial refit (the first ones); the pruned model is refitted on all.
TRIAL_ROWS = 20_000
#: Training samples of an output-error trial refit, and its evaluations per coefficient.
TRIAL_OE_WINDOW = 2000
TRIAL_OE_EVALUATIONS = 2


def refitter(kind: str, y: np.ndarray, u: np.ndarray, lag: int, order: int,
             start: dict[Key, float]) -> Callable[[list[Key]], dict[Key, float]]:
    """``refit(keys)`` with the estimator of ``kind`` on the training samples ``y, u``.

    ``"none"``: least squares; ``"narmax"``: extended least squares with ``order`` noise
    terms (at most :data:`TRIAL_ELS_ITERATIONS` iterations); ``"output error"``:
    Levenberg-Marquardt from the coefficients of ``start`` (:data:`TRIAL_OE_EVALUATIONS`
    evaluations per coefficient on :data:`TRIAL_OE_WINDOW` samples).

    Parameters
    ----------
    kind : {"none", "narmax", "output error"}
        The estimator of the identified model.
    y, u : numpy.ndarray
        Training samples.
    lag : int
        Largest lag.
    order : int
        Noise terms of extended least squares.
    start : dict
        Coefficients an output-error refit starts from.
    """
    from gfrf.identify.noise import extended_least_squares
    from gfrf.identify.output_error import refine

    def least_squares(keys: list[Key]) -> dict[Key, float]:
        theta = np.linalg.lstsq(regressors(keys, y, u, lag), y[lag:], rcond=None)[0]
        return {k: float(v) for k, v in zip(keys, theta, strict=True)}

    if kind == "narmax":
        return lambda keys: extended_least_squares(keys, y, u, lag, order,
                                                   TRIAL_ELS_ITERATIONS)[0]
    if kind == "output error":
        return lambda keys: refine(carried(start, keys), y, u, lag,
                                   TRIAL_OE_EVALUATIONS * (len(keys) + 1), TRIAL_OE_WINDOW)
    return least_squares


def carried(start: dict[Key, float], keys: list[Key]) -> dict[Key, float]:
    """The coefficients of ``start`` on ``keys``, each term of ``start`` left out added to
    the first of ``keys`` in its collinear group (:func:`_group`), if any.

    Nearly collinear regressors act as one: a pair that nearly cancels (``-0.0071
    y[k-1]**2 + 0.0041 y[k-2]**2``) is one term of their sum's size, and a few
    Levenberg-Marquardt steps from the kept member's own coefficient alone end far from
    the optimum they would reach from the sum.

    Parameters
    ----------
    start : dict
        The coefficients of the larger model.
    keys : list
        The terms kept (those not in ``start`` start at 0).
    """
    theta = {k: start.get(k, 0.0) for k in keys}
    for key, value in start.items():
        if key not in theta:
            group = _group(key)
            home = next((k for k in keys if group is not None and _group(k) == group), None)
            if home is not None:
                theta[home] += value
    return theta


def prune_and_refit(theta: dict[Key, float], noise: tuple[float, ...], kind: str,
                    y_train: np.ndarray, u_train: np.ndarray, y_test: np.ndarray,
                    u_test: np.ndarray, lag: int, order: int, noisy: bool, warm: int = 0,
                    score: Callable[[dict[Key, float]], float] | None = None,
                    window: int | None = None
                    ) -> tuple[dict[Key, float], tuple[float, ...], Pruning]:
    """:func:`prune` with the estimator of ``kind`` (:func:`refitter`), then the pruned
    terms refitted with that estimator's full work (extended least squares to
    convergence, or the output-error refinement); returns the coefficients, the noise
    terms and the :class:`Pruning`.  On ``noisy`` data a term whose t-statistic is at
    least :data:`SIGNIFICANT` is kept whatever the free run says.

    Parameters
    ----------
    theta : dict
        The full model's coefficients.
    noise : tuple of float
        Its noise terms.
    kind : str
        Its estimator (:func:`refitter`).
    y_train, u_train, y_test, u_test : numpy.ndarray
        Training and held-out samples about the model's centre.
    lag : int
        Largest lag.
    order : int
        Noise terms of extended least squares.
    noisy : bool
        True when the noise floor is at least
        :data:`~gfrf.identify.validate.PRECISE_FIT`.
    warm : int, optional
        Samples at the start of ``y_test`` the free runs go through unscored.
    score : callable, optional
        ``score(theta)`` of :func:`prune` (r* of the model); used on ``noisy`` data only.
    window : int, optional
        Samples the output-error refit of the pruned terms fits (default
        :data:`gfrf.identify.output_error.WINDOW`).
    """
    from gfrf.identify.noise import extended_least_squares
    from gfrf.identify.output_error import WINDOW as OE_WINDOW
    from gfrf.identify.output_error import refine

    size = len(theta) + 1
    refit_work = (TRIAL_OE_EVALUATIONS * size * min(TRIAL_OE_WINDOW, y_train.size)
                  if kind == "output error" else 0)
    rows = TRIAL_ROWS + lag  # trial refits on the first rows; the pruned model on all
    pruned, pruning = prune(theta, refitter(kind, y_train[:rows], u_train[:rows], lag, order,
                                            theta),
                            y_train=y_train, u_train=u_train, y_test=y_test, u_test=u_test,
                            lag=lag, refit_work=refit_work,
                            significant=SIGNIFICANT if noisy else math.inf, warm=warm,
                            score=score if noisy else None)
    if not pruning.removed:
        return theta, noise, pruning
    keys = list(pruned)
    if kind == "narmax":
        pruned, noise = extended_least_squares(keys, y_train, u_train, lag, order)
    elif kind == "output error":
        pruned = refine(pruned, y_train, u_train, lag, window=window or OE_WINDOW)
    return pruned, noise if kind == "narmax" else (), pruning
