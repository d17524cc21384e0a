"""The identification step: FROLS on input/output data, and the fit's quality.

:func:`identify` fits a polynomial NARMAX model to input/output data with FROLS as
sysidentpy runs it (:mod:`gfrf.identify.frols`; the number of terms, and the lags and
degree when not given, chosen by an information criterion; a constant term among the
candidates), re-estimates it with
noise terms by extended least squares when its residuals are coloured
(:mod:`gfrf.identify.noise`), rewrites it about its operating point so that the
deviations ``y = u = 0`` are an equilibrium (:mod:`gfrf.identify.operating`), rounds
the coefficients, and validates it on a held-out final part of the data (free run,
:func:`free_run`, and correlation tests, :mod:`gfrf.identify.validate`); the result is
an :class:`~gfrf.identify.result.Identification`.
:func:`same_terms` compares two identified models to a relative tolerance.

sysidentpy is not imported: :func:`sysidentpy_version` only reads the version of an
installed copy, for the record of which FROLS the fit reproduces.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, GfrfError
from gfrf.identify.data import (
    MAX_MATRIX,
    _check_data,
    _check_names,
    _check_sample_time,
    _check_settings,
    _check_signal,
    check_rank,
)
from gfrf.identify.floor import noise_floor
from gfrf.identify.frols import Selection, candidate_keys, frols, regressor_code
from gfrf.identify.grow import grow_output_error, held_out_rrse
from gfrf.identify.narx import _lead, narx_model
from gfrf.identify.noise import extended_least_squares, regressors, residuals
from gfrf.identify.operating import equilibrium, round_significant, shift
from gfrf.identify.output_error import WINDOW as OE_WINDOW
from gfrf.identify.output_error import (
    output_error_covariance,
    recurse,
    refine,
    warm_up,
    window_for,
)
from gfrf.identify.prune import WINDOW, Pruning, covariance, prune_and_refit
from gfrf.identify.result import Identification
from gfrf.identify.spread import DRAWS, RadiusSpread, radius, radius_spread
from gfrf.identify.structure import revise_lags
from gfrf.identify.swap import swap_lags
from gfrf.identify.threads import one_blas_thread
from gfrf.identify.validate import (
    FREE_RUN_LIMIT,
    PRECISE_FIT,
    correlation_tests,
    judge,
    model_error,
)
from gfrf.model.equation import Model, Term

Key = tuple[tuple[int, ...], tuple[int, ...]]

__all__ = ["Identification", "identify", "free_run", "same_terms", "SAME_TERMS_RTOL",
           "sysidentpy_version"]
#: A free run stops when |y| exceeds this multiple of the data's largest |y|.
_BLOWUP = 1e6


def free_run(model: Model, u: np.ndarray, y_initial: np.ndarray) -> tuple[np.ndarray, int | None]:
    """Free-run simulation of a NARX model from measured initial outputs.

    Parameters
    ----------
    model : Model
        A discrete-time model whose only term in ``y[k]`` is linear.
    u : numpy.ndarray
        The input sequence, one value per sample.
    y_initial : numpy.ndarray
        The first ``max lag`` outputs (measured); the rest are simulated.

    Returns
    -------
    y : numpy.ndarray
        The simulated output, ``len(u)`` samples (NaN after a blow-up).
    blowup : int or None
        The sample at which ``|y|`` exceeded ``1e6`` times the largest initial or
        input magnitude (at least 1), or None.
    """
    lead = _lead(model)
    terms = [(tuple(t.y_orders), tuple(t.u_orders), -t.coefficient / lead.coefficient)
             for t in model.terms if t is not lead]
    limit = _BLOWUP * max(1.0, float(np.max(np.abs(y_initial), initial=0.0)),
                          float(np.max(np.abs(u), initial=0.0)))
    return recurse(terms, np.asarray(u, dtype=float), np.asarray(y_initial, dtype=float), limit)


#: Relative tolerance of :func:`same_terms`: least squares on another CPU (another BLAS
#: summation order) moves a coefficient by a few ulps times the regressors' condition
#: number; a change of data or settings moves it by far more.
SAME_TERMS_RTOL = 1e-9


def same_terms(a: Sequence[Term], b: Sequence[Term], rtol: float = SAME_TERMS_RTOL) -> bool:
    """True if two identified models have the same monomials, in the same order, and
    coefficients equal to ``rtol`` relative (the scale is each pair's larger modulus).

    Exact equality would fail between machines: see :data:`SAME_TERMS_RTOL`.

    Parameters
    ----------
    a, b : sequence of Term
        The terms of the two models.
    rtol : float, optional
        The relative tolerance of the coefficients.

    Returns
    -------
    bool
        Whether they match.
    """
    return len(a) == len(b) and all(
        (s.y_orders, s.u_orders) == (t.y_orders, t.u_orders)
        and abs(s.coefficient - t.coefficient)
        <= rtol * max(abs(s.coefficient), abs(t.coefficient))
        for s, t in zip(a, b, strict=True))


def sysidentpy_version() -> str:
    """The installed sysidentpy's version, read without importing it ("" if absent).

    Returns
    -------
    str
        The version string.
    """
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("sysidentpy")
    except PackageNotFoundError:
        return ""


def _rrse(measured: np.ndarray, predicted: np.ndarray) -> float:
    """Root relative squared error sqrt(sum (y - yhat)^2 / sum (y - mean y)^2)."""
    spread = float(np.sum((measured - np.mean(measured)) ** 2))
    if spread == 0.0:
        return math.inf
    return math.sqrt(float(np.sum((measured - predicted) ** 2)) / spread)


#: A mean of u larger than this fraction of its standard deviation is an operating input.
OFFSET_FRACTION = 0.05
#: Residuals of root mean square below this fraction of the output's spread are the
#: rounding errors of an exact fit (noise-free data): not tested for whiteness.
ROUNDING_FLOOR = 1e-9
#: Structures compared when lags and degree are not given: (lag, degree), ylag = ulag.
STRUCTURES = tuple((lag, degree) for degree in (1, 2, 3) for lag in (1, 2, 3))


def _key_name(key: Key) -> str:
    ys, us = key
    return "*".join([f"y[k-{lag}]" for lag in ys] + [f"u[k-{lag}]" for lag in us]) or "1"


def _fit_structure(y: np.ndarray, u: np.ndarray, ylag: int, ulag: int, degree: int,
                   criterion: str, max_terms: int, forced: bool = False,
                   estimate: bool = True) -> Selection:
    """FROLS on the training window (the candidates' rank checked first)."""
    lag = max(ylag, ulag)
    keys = candidate_keys(ylag, ulag, degree)
    rows = min(y.size, 20000 + lag)
    check_rank(regressors(keys, y[:rows], u[:rows], lag), [_key_name(k) for k in keys])
    return frols(y, u, ylag=ylag, ulag=ulag, degree=degree, criterion=criterion,
                 max_terms=max_terms, forced=forced, estimate=estimate)


def _choose_structure(y: np.ndarray, u: np.ndarray, given: tuple[int | None, ...],
                      criterion: str, max_terms: int, holdout: float
                      ) -> tuple[tuple[int, int, int], tuple[dict[str, Any], ...]]:
    """Lags and degree of the smallest criterion among :data:`STRUCTURES` (the ``given``
    ylag, ulag, degree held fixed), each fitted on the same training samples."""
    valid = []
    first_error: ArgumentError | None = None
    for lag, degree in STRUCTURES:
        setting = (given[0] or lag, given[1] or lag, given[2] or degree)
        if any(v[:3] == setting for v in valid):
            continue
        try:
            valid.append((*setting, *_check_settings(y.size, *setting, criterion, max_terms,
                                                     holdout)))
        except ArgumentError as exc:
            first_error = first_error or exc
    window = min((v[5] for v in valid), default=0)
    table = []
    for ylag, ulag, degree, candidates, _, _ in valid:
        try:
            fit = _fit_structure(y[:window], u[:window], ylag=ylag, ulag=ulag, degree=degree,
                                 criterion=criterion, max_terms=min(max_terms, candidates),
                                 estimate=False)
        except ArgumentError as exc:  # dependent candidates: this degree is not excited
            first_error = first_error or exc
            continue
        table.append({"ylag": ylag, "ulag": ulag, "degree": degree, "terms": len(fit.keys),
                      criterion: round_significant(float(np.min(fit.criterion)))})
    if not table:
        assert first_error is not None
        raise first_error
    # a tie (to 1e-9 relative) goes to the simpler structure: STRUCTURES is in that order
    low = min(r[criterion] for r in table)
    best = next(r for r in table if r[criterion] <= low + 1e-9 * max(1.0, abs(low)))
    for r in table:
        r["chosen"] = r is best
    return (best["ylag"], best["ulag"], best["degree"]), tuple(table)


def _estimate(y: np.ndarray, u: np.ndarray, ylag: int, ulag: int, degree: int,
              criterion: str, max_terms: int, noise: bool | None, forced: bool = False,
              window: int = OE_WINDOW
              ) -> tuple[Selection, dict[Key, float], tuple[float, ...], list[str], str]:
    """FROLS, then a noise model when asked or when the residuals are coloured.

    Returns the fit, the process coefficients, the noise coefficients, notes and the
    kind of noise model: ``"none"``, ``"narmax"`` (extended least squares) or
    ``"output error"`` (when extended least squares cannot whiten the residuals:
    :mod:`gfrf.identify.output_error`, fitted on the first ``window`` samples).
    """
    lag = max(ylag, ulag)
    fit = _fit_structure(y, u, ylag=ylag, ulag=ulag, degree=degree, criterion=criterion,
                         max_terms=max_terms, forced=forced)
    theta = dict(zip(fit.keys, (float(v) for v in fit.theta), strict=True))
    notes: list[str] = []
    floor = ROUNDING_FLOOR * float(np.std(y))

    def white(th: dict[Key, float], c: tuple[float, ...]) -> bool:
        return correlation_tests(residuals(th, c, y, u, lag), u[lag:], floor=floor)[0].passed

    if noise is False or (noise is None and white(theta, ())):
        if noise is None:
            notes.append("the training residuals are white: no noise terms needed")
        return fit, theta, (), notes, "none"
    els, noise_terms = extended_least_squares(fit.keys, y, u, lag, ylag)
    if any(noise_terms) and (noise or white(els, noise_terms)):
        return fit, els, noise_terms, notes, "narmax"
    if noise:
        notes.append("extended least squares found no invertible noise model: no noise "
                     "terms")
        return fit, theta, (), notes, "none"
    notes.append("extended least squares could not whiten the coloured training residuals: "
                 "output-error estimate (free-run error minimised on the training part)")
    return fit, refine(theta, y, u, lag, window=window), (), notes, "output error"


def identify(y: Any, u: Any, sample_time: float, *, ylag: int | None = 2,
             ulag: int | None = 2, degree: int | None = 3, criterion: str = "bic",
             max_terms: int = 15, holdout: float = 0.25, output: str = "y",
             input: str = "u", noise: bool | None = None,
             prune: bool = True, radius_draws: int | None = DRAWS) -> Identification:
    """Identify a polynomial NARMAX model from input/output data with FROLS.

    The first ``1 - holdout`` of the samples train the model: FROLS ranks the
    candidate regressors (the constant and the monomials of degree 1..``degree`` in
    ``y(k-1..ylag)`` and ``u(k-1..ulag)``) by error reduction ratio, the information
    ``criterion`` picks the number of terms among 1..``max_terms``, least squares
    estimates theta.  When the training residuals are not white (``noise`` None) or
    when ``noise`` is True, extended least squares re-estimates the process terms with
    ``ylag`` moving-average noise terms.  A fitted constant, or an input mean, makes an
    operating point: the model is rewritten about its equilibrium there
    (:mod:`gfrf.identify.operating`).  Coefficients are rounded to
    :data:`SIGNIFICANT_DIGITS` digits.  The last ``holdout`` part validates the model
    (:func:`gfrf.identify.validate.judge`).

    Parameters
    ----------
    y, u : array_like
        Output and input samples, equally spaced by ``sample_time`` seconds.
    sample_time : float
        Sample time T in seconds.
    ylag, ulag, degree : int or None
        Largest output lag, largest input lag, polynomial degree; those None are chosen
        among :data:`STRUCTURES` (lag 1 to 3, ``ylag = ulag``, degree 1 to 3) by the
        smallest ``criterion``, the others held fixed; lags chosen so are checked on
        the held-out data (:func:`gfrf.identify.structure.revise_lags`: other lags
        when they fail validation, fewer when an output-error model needs fewer).
    criterion : {"bic", "aic", "aicc", "fpe", "lilc"}
        Information criterion for the number of terms (sysidentpy's names and
        formulas).
    max_terms : int
        Largest number of terms the criterion considers (at most the candidates).
    holdout : float
        Fraction (0.05 to 0.5) of the samples, at the end, held out for validation.
    output, input : str
        Signal names in the model.
    noise : bool or None
        Fit noise terms: None (default) when the training residuals are coloured.
    prune : bool
        Remove, after the criterion's choice, the terms whose removal keeps the
        held-out free run within its band (:mod:`gfrf.identify.prune`).
    radius_draws : int or None
        Coefficient vectors drawn for the spread of r* (:mod:`gfrf.identify.spread`);
        0 gives r* alone, None skips r*.

    Returns
    -------
    Identification

    Raises
    ------
    ArgumentError
        Bad data or settings (non-finite or constant samples, values beyond
        :data:`~gfrf.identify.data.MAX_MAGNITUDE`, linearly dependent candidates, too
        few samples for the candidates, a limit exceeded); checked before any fitting.
    """
    options = {"criterion": criterion, "max_terms": max_terms, "holdout": holdout,
               "output": output, "input": input, "noise": noise, "prune": prune,
               "radius_draws": radius_draws}
    with one_blas_thread():
        first = _identify(y, u, sample_time, ylag=ylag, ulag=ulag, degree=degree, **options)
        if ulag is not None or ylag is not None:
            return first
        return revise_lags(first, lambda lag, top: _identify(
            y, u, sample_time, ylag=lag, ulag=lag, degree=top, **options), criterion)


def _identify(y: Any, u: Any, sample_time: float, **options: Any) -> Identification:
    """:func:`identify` with the given lags, with BLAS as the caller set it.

    A model about an operating point that fails validation without a constant term is
    identified again with the constant kept (:func:`_with_constant`), and that model is
    taken when it passes: the first fit's equilibrium is the operating point, and on a
    nearly integrating system with an even nonlinearity (the mean output is not the
    equilibrium) it is off, and a term with a non-zero mean, ``u[k-1]**2``, then stands
    in for the missing constant as a structural error the correlation tests see.
    """
    first, without = _identify_once(y, u, sample_time, constant=False, **options)
    if not without or first.validation is None or first.validation.adequate:
        return first
    retry, _ = _identify_once(y, u, sample_time, constant=True, **options)
    if retry.validation is None or not retry.validation.adequate:
        return first
    return replace(retry, notes=(*retry.notes, "without a constant term about the first "
                                 "fit's operating point the model failed validation; with "
                                 "the constant kept (its operating point refitted) it "
                                 "passed"))


def _with_constant(theta: dict[Key, float], noise_terms: tuple[float, ...], kind: str,
                   y: np.ndarray, u: np.ndarray, lag: int, order: int,
                   window: int = OE_WINDOW
                   ) -> tuple[dict[Key, float], tuple[float, ...]]:
    """``theta`` with a constant term: refitted by the estimator of ``kind``; with noise
    terms (extended least squares) the constant is the mean equation error of the
    process terms, the others kept (estimated with them, the constant trades with the
    mean of the lagged residuals and is not determined)."""
    one: Key = ((), ())
    if one in theta:
        return theta, noise_terms
    keys = [*theta, one]
    if kind == "output error":
        return refine({**theta, one: 0.0}, y, u, lag, window=window), noise_terms
    if kind == "narmax":
        keys = list(theta)
        error = y[lag:] - regressors(keys, y, u, lag) @ np.array([theta[k] for k in keys])
        return {**theta, one: float(np.mean(error))}, noise_terms
    values = np.linalg.lstsq(regressors(keys, y, u, lag), y[lag:], rcond=None)[0]
    return {k: float(v) for k, v in zip(keys, values, strict=True)}, noise_terms


def _identify_once(y: Any, u: Any, sample_time: float, *, ylag: int | None,
                   ulag: int | None, degree: int | None, criterion: str, max_terms: int,
                   holdout: float, output: str, input: str, noise: bool | None,
                   prune: bool, radius_draws: int | None, constant: bool
                   ) -> tuple[Identification, bool]:
    """:func:`_identify` once; ``constant``: keep a constant term in the model about an
    operating point (refitted with it before pruning, which never removes it).  Also
    returns whether the model is about an operating point without a constant term."""
    y = _check_signal("y", y)
    u = _check_signal("u", u)
    if y.size != u.size:
        raise ArgumentError(f"y has {y.size} samples and u has {u.size}")
    sample_time = _check_sample_time(sample_time)
    _check_names(output, input)
    given = (ylag, ulag, degree)
    search = None in given
    probe = (ylag or 1, ulag or 1, degree or 1)
    candidates, n_train, n_fit = _check_settings(y.size, *probe, criterion, max_terms,
                                                 holdout)
    _check_data(y[:n_train], u[:n_train], degree or 3)
    mean_u, mean_y = float(np.mean(u[:n_train])), float(np.mean(y[:n_train]))
    u0 = mean_u if abs(mean_u) > OFFSET_FRACTION * float(np.std(u[:n_train])) else 0.0
    offset = u0 != 0.0 or abs(mean_y) > OFFSET_FRACTION * float(np.std(y[:n_train]))
    # the data about a centre: u0 first, then about the first fit's equilibrium, where
    # an output offset no longer expands y**3 into y**3, y**2, y and 1 (a second fit)
    cy, cu = 0.0, u0
    structure: tuple[dict[str, Any], ...] = ()
    if search:
        (ylag, ulag, degree), structure = _choose_structure(y - cy, u - cu, given, criterion,
                                                            max_terms, holdout)
        candidates, n_train, n_fit = _check_settings(y.size, ylag, ulag=ulag, degree=degree,
                                                     criterion=criterion, max_terms=max_terms,
                                                     holdout=holdout)
    assert ylag is not None and ulag is not None and degree is not None
    max_terms = min(max_terms, candidates)
    lag = max(ylag, ulag)
    oe_window = window_for(n_train)  # output-error fits: fewer samples on a long record
    fit, theta, noise_terms, notes, kind = _estimate(y[:n_fit], u[:n_fit] - cu, ylag=ylag,
                                                     ulag=ulag, degree=degree, criterion=criterion,
                                                     max_terms=max_terms, noise=noise,
                                                     window=oe_window)
    first_constant = constant = theta.get(((), ()))
    y0c = 0.0 if constant is None else equilibrium(theta, 0.0, mean_y)
    if offset and y0c != 0.0:  # the second fit, about the first one's equilibrium
        cy = y0c
        fit, theta, noise_terms, notes, kind = _estimate(y[:n_fit] - cy, u[:n_fit] - cu, ylag=ylag,
                                                         ulag=ulag, degree=degree,
                                                         criterion=criterion, max_terms=max_terms,
                                                         noise=noise, window=oe_window)
    yc, uc = y - cy, u - cu
    floor, floor_method = noise_floor(yc, uc, n_train, lag, candidate_keys(ylag, ulag, degree),
                                      fit.keys)
    if prune and len(fit.keys) < max_terms and not model_error(
            held_out_rrse(theta, yc, uc, n_train, lag), floor) < FREE_RUN_LIMIT:
        grown = _estimate(y[:n_fit] - cy, u[:n_fit] - cu, ylag=ylag, ulag=ulag, degree=degree,
                          criterion=criterion, max_terms=max_terms, noise=noise, forced=True,
                          window=oe_window)
        if kind == grown[4] == "output error":  # least squares on noisy data is biased
            grown = (grown[0], grow_output_error(theta, grown[1], y=y[:n_fit] - cy,
                                                 u=u[:n_fit] - cu, lag=lag,
                                                 candidates=candidate_keys(ylag, ulag, degree),
                                                 window=oe_window),
                     *grown[2:])
        if held_out_rrse(grown[1], yc, uc, n_train, lag) < held_out_rrse(
                theta, yc, uc, n_train, lag):
            chosen = len(fit.keys)
            fit, theta, noise_terms, notes, kind = grown
            notes.append(f"the criterion's {chosen} terms did not "
                         f"reproduce the held-out data: all {max_terms} terms fitted, "
                         f"then pruned")
    if constant and cy:
        theta, noise_terms = _with_constant(theta, noise_terms, kind=kind, y=y[:n_fit] - cy,
                                            u=u[:n_fit] - cu, lag=lag, order=ylag, window=oe_window)
    full_theta = theta
    pruning = None
    if prune:  # free runs from measured outputs before the held-out part (warm-up)
        w = warm_up(theta, lag, n_train - lag)
        theta, noise_terms, pruning = prune_and_refit(
            theta, noise_terms, kind=kind, y_train=y[:n_fit] - cy, u_train=u[:n_fit] - cu,
            y_test=yc[n_train - w:], u_test=uc[n_train - w:], lag=lag, order=ylag,
            noisy=floor >= PRECISE_FIT, warm=w,
            score=lambda th: _score(th, mean_y - cy, sample_time, output, input),
            window=oe_window)
        if floor >= PRECISE_FIT:  # FROLS ranked the lags on noisy outputs
            theta, noise_terms, swaps = swap_lags(theta, noise_terms, kind=kind, y=y[:n_fit] - cy,
                                                  u=u[:n_fit] - cu, lag=lag, order=ylag,
                                                  candidates=candidate_keys(ylag, ulag, degree),
                                                  window=oe_window)
            if swaps:
                end = n_train + lag + WINDOW  # the pruning's window
                pruning = replace(pruning, removed=pruning.removed + tuple(a for a, _ in swaps),
                                  added=tuple(b for _, b in swaps),
                                  pruned_error=held_out_rrse(theta, yc[:end], uc[:end],
                                                             n_train, lag))
    constant = theta.get(((), ()))
    y0c = 0.0 if constant is None else equilibrium(theta, 0.0, mean_y - cy)
    model, about = _about(theta, mean_y - cy, sample_time, output, input)
    y0 = cy + y0c
    if first_constant is None and u0 == 0.0:
        how = "no offset: no constant term selected, mean u is zero"
    else:
        how = ((f"constant term {first_constant:.6g} fitted" if first_constant is not None
                else "no constant term selected") + ("; u0 is the mean input" if u0 else
                                                     "; u0 = 0 (mean input is zero)")
               + "; y0 is the fitted model's equilibrium at u0" + (
                   ", the model refitted about it" if cy else ""))
    y0, u0 = round_significant(y0), round_significant(u0)
    noise_terms = tuple(round_significant(c) for c in noise_terms)
    y_test, u_test = y[n_train:] - y0, u[n_train:] - u0
    w = warm_up(about, lag, n_train - lag)
    simulated, blowup = free_run(model, u[n_train - w:] - u0, y[n_train - w:][:lag] - y0)
    simulated, blowup = simulated[w:], None if blowup is None else max(0, blowup - w)
    free = math.inf if blowup is not None else _rrse(y_test[lag:], simulated[lag:])
    if kind == "output error":  # its one-step predictor is the free run
        e = y_test[lag:] - simulated[lag:] if blowup is None else y_test[lag:]
    else:
        e = residuals(about, noise_terms, y_test, u_test, lag)
    one_step = _rrse(y_test[lag:], y_test[lag:] - e)
    validation = judge(free, one_step, e, u_test[lag:], blowup,
                       floor=ROUNDING_FLOOR * float(np.std(y_test)), noise_floor=floor,
                       noise_floor_method=floor_method)
    spread = None
    if radius_draws is not None and blowup is None:
        try:
            spread = _spread(
                model, theta, full_theta=full_theta, pruning=pruning, noise_terms=noise_terms,
                kind=kind, y=y[:n_fit] - cy, u=u[:n_fit] - cu, lag=lag,
                build=lambda th: _about(th, mean_y - cy, sample_time, output, input)[0],
                draws=radius_draws)
        except GfrfError as exc:  # e.g. a linear part that is not stable: no r*
            notes.append(f"no r* for the identified model: {exc}")
    if n_fit < n_train:
        notes.append(f"the candidate matrix is limited to {MAX_MATRIX} entries: the fit "
                     f"used the first {n_fit} of the {n_train} training samples")
    if len(fit.keys) == max_terms < candidates:
        notes.append(f"the criterion chose the largest size considered ({max_terms} terms): "
                     f"a larger max_terms may find a better model")
    if blowup is not None:
        notes.append(f"the identified model's free run blew up at held-out sample {blowup}: "
                     f"it does not reproduce the data")
    regressor_rows = tuple(
        {"codes": regressor_code(k, degree), "theta": round_significant(float(t)),
         "err": round_significant(float(e_))}
        for k, t, e_ in zip(fit.keys, fit.theta, fit.err, strict=True))
    settings = {"ylag": ylag, "ulag": ulag, "degree": degree, "criterion": criterion,
                "max_terms": max_terms, "holdout": float(holdout)}
    without = bool(cy) and ((), ()) not in theta
    return (Identification(
        model=model, settings=settings, n_samples=int(y.size), n_train=n_train,
        candidates=candidates, regressors=regressor_rows, free_run_error=free,
        one_step_error=one_step, blowup=blowup, notes=tuple(notes),
        sysidentpy_version=sysidentpy_version(),
        operating_point={"u0": u0, "y0": y0, "constant": first_constant, "how": how},
        noise=noise_terms, validation=validation, structure=structure, n_fit=n_fit,
        noise_model=kind, pruning=pruning, radius=spread,
        full_model=None if pruning is None or not pruning.removed else
        _about(full_theta, mean_y - cy, sample_time, output, input)[0]), without)


def _about(theta: dict[Key, float], near: float, sample_time: float, output: str,
           input_: str) -> tuple[Model, dict[Key, float]]:
    """The model of ``theta`` about its equilibrium at u = 0 (the one nearest ``near``),
    coefficients rounded to :data:`SIGNIFICANT_DIGITS` digits, and those coefficients."""
    if ((), ()) in theta:
        theta = shift(theta, equilibrium(theta, 0.0, near), 0.0)
    about = {k: round_significant(v) for k, v in theta.items()}
    return _model(about, sample_time, output, input_), about


def _score(theta: dict[Key, float], near: float, sample_time: float, output: str,
           input_: str) -> float:
    """r* of the model of ``theta`` (floating-point proof), 0 when it has none: the
    pruning's preference among removals the held-out data cannot tell apart."""
    try:
        return radius(_about(theta, near, sample_time, output, input_)[0], proof="float")
    except GfrfError:
        return 0.0


def _spread(model: Model, theta: dict[Key, float], full_theta: dict[Key, float],
            pruning: Pruning | None, noise_terms: tuple[float, ...], kind: str, y: np.ndarray,
            u: np.ndarray, lag: int, build: Any, draws: int) -> RadiusSpread:
    """r* of the model, of the full model, and the spread over the coefficients."""
    keys = list(theta)
    values = np.array([theta[k] for k in keys])
    if kind == "output error":
        cov = output_error_covariance(theta, y, u, lag)
    else:
        e = residuals(theta, noise_terms, y, u, lag)
        cov = covariance(keys, values, y, u, lag, float(np.mean(e**2)))
    full = None
    if pruning is not None and pruning.removed:
        try:
            full = radius(build(full_theta))
        except GfrfError:
            full = None
    return radius_spread(model, keys, theta=values, cov=cov, build=build, full=full, draws=draws)


def _model(theta: dict[Key, float], sample_time: float, output: str, input_: str) -> Model:
    """The gfrf model ``y[k] - sum theta*m = 0`` of a dict without constant."""
    terms = [Term((0,), (), 1.0, output, input_, True)]
    terms += [Term(ys, us, -v, output, input_, True) for (ys, us), v in theta.items()
              if v != 0.0]
    return narx_model(terms, sample_time, output, input_,
                      f"the identified model has no input term (a NAR model): its GFRFs "
                      f"are zero; the output does not respond to {input_!r} in the data")
