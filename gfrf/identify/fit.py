"""The identification step: sysidentpy's FROLS on input/output data, and the fit's quality.

:func:`identify` fits a polynomial NARX model to input/output data with sysidentpy's
FROLS (the number of terms chosen by an information criterion, the constant regressor
left out so that ``y = u = 0`` stays an equilibrium), converts it exactly
(:mod:`gfrf.identify.narx`), and measures its free-run error (:func:`free_run`) on a
held-out final part of the data; the result is an :class:`Identification`.
:func:`same_terms` compares two identified models to a relative tolerance.

sysidentpy is the optional extra ``gfrf[identify]``; it is imported only inside
:func:`identify` (:data:`INSTALL_HINT` says how to install it).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, GfrfError
from gfrf.identify.data import _check_names, _check_sample_time, _check_settings, _check_signal
from gfrf.identify.narx import _convert, _lead
from gfrf.model.equation import Model, Term

__all__ = ["Identification", "identify", "free_run", "same_terms", "SAME_TERMS_RTOL",
           "INSTALL_HINT"]

#: What to tell a user who lacks the optional dependency.
INSTALL_HINT = ("gfrf identify needs sysidentpy, the optional extra gfrf[identify]: "
                "pip install 'gfrf[identify]' (or: pip install sysidentpy)")
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
    a0 = lead.coefficient
    n = len(u)
    start = len(y_initial)
    y = np.full(n, np.nan)
    y[:start] = y_initial
    forced = np.zeros(n)
    dynamic = []
    for t in model.terms:
        if t is lead:
            continue
        factor = np.full(n, -t.coefficient / a0)
        for lag in t.u_orders:
            factor[lag:] *= u[:n - lag]
            factor[:lag] = 0.0
        if t.y_orders:
            dynamic.append((list(t.y_orders), factor.tolist()))
        else:
            forced += factor
    limit = _BLOWUP * max(1.0, float(np.max(np.abs(y_initial), initial=0.0)),
                          float(np.max(np.abs(u), initial=0.0)))
    values = y.tolist()
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


#: Relative tolerance of :func:`same_terms`: least squares on another CPU (another BLAS
#: summation order) moves a coefficient by a few ulps times the regressors' condition
#: number; a change of data or settings moves it by far more.
SAME_TERMS_RTOL = 1e-9


def same_terms(a: Sequence[Term], b: Sequence[Term], rtol: float = SAME_TERMS_RTOL) -> bool:
    """True if two identified models have the same monomials, in the same order, and
    coefficients equal to ``rtol`` relative (the scale is each pair's larger modulus).

    Exact equality would fail between machines: see :data:`SAME_TERMS_RTOL`.
    """
    return len(a) == len(b) and all(
        (s.y_orders, s.u_orders) == (t.y_orders, t.u_orders)
        and abs(s.coefficient - t.coefficient)
        <= rtol * max(abs(s.coefficient), abs(t.coefficient))
        for s, t in zip(a, b, strict=True))


def _rrse(measured: np.ndarray, predicted: np.ndarray) -> float:
    """Root relative squared error sqrt(sum (y - yhat)^2 / sum (y - mean y)^2)."""
    spread = float(np.sum((measured - np.mean(measured)) ** 2))
    if spread == 0.0:
        return math.inf
    return math.sqrt(float(np.sum((measured - predicted) ** 2)) / spread)


@dataclass(frozen=True)
class Identification:
    """A NARX model identified from data, with its fit settings and quality.

    Attributes
    ----------
    model : Model
        The identified discrete-time model (converted exactly from sysidentpy).
    settings : dict
        ``ylag``, ``ulag``, ``degree``, ``criterion``, ``max_terms``, ``holdout``.
    n_samples, n_train : int
        Samples in the data and in the training part (the rest is held out).
    candidates : int
        Candidate regressors considered (constant excluded).
    regressors : tuple of dict
        Per selected regressor in FROLS order: ``codes``, ``theta``, ``err`` (the
        error reduction ratio).
    free_run_error : float
        Root relative squared error of the free-run simulation on the held-out part
        (``inf`` when the simulation blew up).
    one_step_error : float
        Root relative squared error of one-step-ahead prediction on the held-out part.
    blowup : int or None
        Held-out sample at which the free run blew up, or None.
    notes : tuple of str
        Remarks (dropped noise terms, ...).
    sysidentpy_version : str
    """

    model: Model
    settings: dict[str, Any]
    n_samples: int
    n_train: int
    candidates: int
    regressors: tuple[dict[str, Any], ...]
    free_run_error: float
    one_step_error: float
    blowup: int | None = None
    notes: tuple[str, ...] = field(default=())
    sysidentpy_version: str = ""

    def settings_text(self) -> str:
        """The fit settings as command-line options."""
        s = self.settings
        return (f"--ylag {s['ylag']} --ulag {s['ulag']} --degree {s['degree']} "
                f"--criterion {s['criterion']} --max-terms {s['max_terms']} "
                f"--holdout {s['holdout']:g}")

    def quality_text(self) -> str:
        """One line: terms chosen and the held-out errors."""
        held = self.n_samples - self.n_train
        run = (f"free run blew up at held-out sample {self.blowup}" if self.blowup is not None
               else f"free-run RRSE {self.free_run_error:.4g}")
        return (f"{len(self.regressors)} of {self.candidates} candidate terms "
                f"({self.settings['criterion'].upper()}); on the held-out last {held} of "
                f"{self.n_samples} samples: {run}, one-step RRSE {self.one_step_error:.4g}")

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {"model": self.model.to_dict(), "settings": dict(self.settings),
                "n_samples": self.n_samples, "n_train": self.n_train,
                "candidates": self.candidates,
                "regressors": [dict(r) for r in self.regressors],
                "free_run_error": self.free_run_error, "one_step_error": self.one_step_error,
                "blowup": self.blowup, "notes": list(self.notes),
                "sysidentpy_version": self.sysidentpy_version}


def _frols(ylag: int, ulag: int, degree: int, criterion: str, max_terms: int) -> Any:
    """sysidentpy's FROLS with least squares, without the constant regressor."""
    try:
        import matplotlib  # sysidentpy imports it anyway

        # sysidentpy's first import restyles matplotlib globally (top and right spines
        # off): the caller's plots, and gfrf's reports, are not its to change.
        with matplotlib.rc_context():
            from sysidentpy.basis_function import Polynomial
            from sysidentpy.model_structure_selection import FROLS
            from sysidentpy.parameter_estimation import LeastSquares
    except ImportError:
        raise GfrfError(INSTALL_HINT) from None

    class _FrolsWithoutConstant(FROLS):  # type: ignore[misc, valid-type]
        """FROLS over the candidate regressors minus the constant (column 0)."""

        def run_mss_algorithm(self, psi: np.ndarray, y: np.ndarray,
                              process_term_number: int) -> tuple[Any, ...]:
            err, piv, selected = self.error_reduction_ratio(psi[:, 1:], y,
                                                             process_term_number)
            return err, np.asarray(piv) + 1, selected

        def information_criterion(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
            """sysidentpy's criterion for 1..n_info_values terms from one greedy ERR run.

            The ERR selection is sequential, so the first n regressors of a run for
            n_info_values terms are those of a run for n terms: least squares on each
            prefix gives sysidentpy's values without one selection run per size.
            """
            count = self.n_info_values
            selected = self.run_mss_algorithm(x, y, count)[2]
            target = self._default_estimation_target(y)
            n_samples = y.shape[0] - self.max_lag
            values = np.full(count, np.nan)
            for i in range(count):
                theta = self.estimator.optimize(selected[:, :i + 1], target)
                residual = target - selected[:, :i + 1] @ theta
                values[i] = self.info_criteria_function(i + 1, n_samples,
                                                        float(np.var(residual, ddof=1)))
            return values

    return _FrolsWithoutConstant(
        ylag=ylag, xlag=ulag, order_selection=True, info_criteria=criterion,
        n_info_values=max_terms, estimator=LeastSquares(),
        basis_function=Polynomial(degree=degree), model_type="NARMAX")


def identify(y: Any, u: Any, sample_time: float, *, ylag: int = 2, ulag: int = 2,
             degree: int = 3, criterion: str = "bic", max_terms: int = 15,
             holdout: float = 0.25, output: str = "y", input: str = "u",  # noqa: A002
             ) -> Identification:
    """Identify a polynomial NARX model from input/output data with sysidentpy's FROLS.

    The first ``1 - holdout`` of the samples train the model: FROLS ranks the
    candidate regressors (monomials of degree 1..``degree`` in ``y(k-1..ylag)`` and
    ``u(k-1..ulag)``, no constant) by error reduction ratio, the information
    ``criterion`` picks the number of terms among 1..``max_terms``, least squares
    estimates theta.  The last ``holdout`` part measures the free-run error.

    Parameters
    ----------
    y, u : array_like
        Output and input samples, equally spaced by ``sample_time`` seconds.
    sample_time : float
        Sample time T in seconds.
    ylag, ulag, degree : int
        Largest output lag, largest input lag, polynomial degree.
    criterion : {"bic", "aic", "aicc", "fpe", "lilc"}
        Information criterion for the number of terms (sysidentpy's names).
    max_terms : int
        Largest number of terms the criterion considers (at most the candidates).
    holdout : float
        Fraction (0.05 to 0.5) of the samples, at the end, held out for validation.
    output, input : str
        Signal names in the model.

    Returns
    -------
    Identification

    Raises
    ------
    ArgumentError
        Bad data or settings (non-finite samples, too few samples for the
        candidates, a limit exceeded); checked before any fitting.
    GfrfError
        sysidentpy is not installed (the message says how to install it).
    """
    y = _check_signal("y", y)
    u = _check_signal("u", u)
    if y.size != u.size:
        raise ArgumentError(f"y has {y.size} samples and u has {u.size}")
    sample_time = _check_sample_time(sample_time)
    _check_names(output, input)
    candidates, n_train = _check_settings(y.size, ylag, ulag, degree, criterion, max_terms,
                                          holdout)
    max_terms = min(max_terms, candidates)
    frols = _frols(ylag, ulag, degree, criterion, max_terms)
    import sysidentpy

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        frols.fit(X=u[:n_train, None], y=y[:n_train, None])
    model = _convert(frols.final_model, frols.theta, sample_time, output, input)
    theta = np.ravel(frols.theta)
    regressors = tuple({"codes": [int(c) for c in row], "theta": float(t), "err": float(e)}
                       for row, t, e in zip(frols.final_model, theta,
                                            np.ravel(frols.err)[:theta.size], strict=True))
    lag = max(ylag, ulag)
    y_test, u_test = y[n_train:], u[n_train:]
    simulated, blowup = free_run(model, u_test, y_test[:lag])
    free = math.inf if blowup is not None else _rrse(y_test[lag:], simulated[lag:])
    one_step = _one_step(model, y_test, u_test, lag)
    notes = []
    if len(regressors) == max_terms < candidates:
        notes.append(f"the criterion chose the largest size considered ({max_terms} terms): "
                     f"a larger max_terms may find a better model")
    if blowup is not None:
        notes.append(f"the identified model's free run blew up at held-out sample {blowup}: "
                     f"it does not reproduce the data")
    settings = {"ylag": ylag, "ulag": ulag, "degree": degree, "criterion": criterion,
                "max_terms": max_terms, "holdout": float(holdout)}
    return Identification(model=model, settings=settings, n_samples=int(y.size),
                          n_train=n_train, candidates=candidates, regressors=regressors,
                          free_run_error=free, one_step_error=one_step,
                          blowup=blowup, notes=tuple(notes),
                          sysidentpy_version=str(sysidentpy.__version__))


def _one_step(model: Model, y: np.ndarray, u: np.ndarray, lag: int) -> float:
    """RRSE of one-step-ahead prediction (measured past outputs) on samples lag..end."""
    n = y.size
    prediction = np.zeros(n - lag)
    lead = _lead(model)
    for t in model.terms:
        if t is lead:
            continue
        value = np.full(n - lag, -t.coefficient / lead.coefficient)
        for name, orders in ((y, t.y_orders), (u, t.u_orders)):
            for order in orders:
                value *= name[lag - order:n - order]
        prediction += value
    return _rrse(y[lag:], prediction)
