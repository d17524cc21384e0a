"""From measured data to a gfrf model: polynomial NARX models identified with sysidentpy.

:func:`from_sysidentpy` converts a fitted sysidentpy polynomial model into a gfrf
:class:`~gfrf.model.equation.Model` exactly: every regressor, lag and coefficient.  sysidentpy
encodes a regressor as a row of integer codes, one per factor, ``0`` for an unused
slot: ``1000 + n`` is the output ``y(k-n)``, ``2000 + n`` the (first) input ``u(k-n)``,
``3000 + n`` a second input; the row ``[2001, 1001, 0]`` is ``u(k-1)*y(k-1)`` and the
all-zero row is the constant.  The fitted model reads ``y[k] = sum_i theta_i *
regressor_i``; gfrf models are ``sum(terms) = 0``, so the gfrf terms are ``y[k]`` with
coefficient 1 and every regressor with coefficient ``-theta_i``.

:func:`identify` fits such a model to input/output data with sysidentpy's FROLS
(the number of terms chosen by an information criterion, the constant regressor left
out so that ``y = u = 0`` stays an equilibrium), converts it, and measures its
free-run error on a held-out final part of the data.  :func:`read_csv`,
:func:`model_file_text` and :func:`write_atomic` take the data from a CSV file to
a model file that ``gfrf verdict`` and ``gfrf report`` read like any other.

sysidentpy is the optional extra ``gfrf[identify]``; it is imported only inside
:func:`identify`.  The converter itself needs nothing but the model's ``final_model``
and ``theta`` arrays.  Sub-modules: :mod:`gfrf.identify.example` (the worked example's
data generator), :mod:`gfrf.report.identified` (its report page),
:mod:`gfrf.bench.identify` (identification timings).

Examples
--------
>>> import numpy as np
>>> from types import SimpleNamespace
>>> fitted = SimpleNamespace(final_model=np.array([[1001, 0], [2001, 1001], [2002, 0]]),
...                          theta=np.array([[0.5], [-0.2], [1.0]]))
>>> model = from_sysidentpy(fitted, sample_time=0.1)
>>> model.text
'y[k] = 0.5*y[k-1] + 1.0*u[k-2] - 0.2*y[k-1]*u[k-1]'
>>> model.equation()
'0.2*y[k-1]*u[k-1] + y[k] - 0.5*y[k-1] - u[k-2] = 0'
"""

from __future__ import annotations

import csv
import json
import math
import os
import tempfile
import tomllib
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from math import comb
from pathlib import Path
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, GfrfError, ModelError
from gfrf.model.equation import MAX_DEGREE, MAX_DERIVATIVE_ORDER, Model, Term
from gfrf.model.modelfile import ModelFile, model_from_dict

__all__ = ["Identification", "from_sysidentpy", "identify", "read_csv", "free_run",
           "model_file_text", "load_text", "narx_equation", "write_atomic", "candidate_count",
           "same_terms", "SAME_TERMS_RTOL",
           "INSTALL_HINT", "MAX_CANDIDATES", "MAX_SAMPLES", "MIN_SAMPLES"]

#: What to tell a user who lacks the optional dependency.
INSTALL_HINT = ("gfrf identify needs sysidentpy, the optional extra gfrf[identify]: "
                "pip install 'gfrf[identify]' (or: pip install sysidentpy)")
#: Largest number of candidate regressors (lags and degree) a fit may consider.
MAX_CANDIDATES = 2000
#: Largest number of samples read from a data file.
MAX_SAMPLES = 2_000_000
#: Fewest samples a fit accepts (training plus held-out part).
MIN_SAMPLES = 50
#: Largest number of floats in the candidate regressor matrix (8 bytes each).
_MAX_MATRIX = 300_000_000
#: A free run stops when |y| exceeds this multiple of the data's largest |y|.
_BLOWUP = 1e6
_CRITERIA = ("aic", "aicc", "bic", "fpe", "lilc")


def _codes_and_theta(final_model: Any, theta: Any) -> tuple[np.ndarray, np.ndarray]:
    try:
        codes = np.asarray(final_model, dtype=float)
        values = np.asarray(theta, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"final_model and theta must be numeric arrays: {exc}") from None
    if codes.ndim == 1:
        codes = codes.reshape(-1, 1)
    if codes.ndim != 2 or codes.shape[0] == 0:
        raise ModelError(f"final_model must be a non-empty matrix of regressor codes, got "
                         f"shape {codes.shape}")
    if values.ndim == 2 and 1 in values.shape:
        values = values.ravel()
    if values.ndim != 1 or values.size != codes.shape[0]:
        raise ModelError(f"theta has {values.size} entries for {codes.shape[0]} regressors "
                         f"(rows of final_model)")
    if not np.all(np.isfinite(codes)) or np.any(codes != np.round(codes)) or np.any(codes < 0):
        raise ModelError("final_model must hold non-negative integer regressor codes")
    return codes.astype(np.int64), values


def _describe(row: Sequence[int]) -> str:
    return "[" + ", ".join(str(int(c)) for c in row) + "]"


def _decode(row: Sequence[int]) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Sorted output lags and input lags of one regressor row."""
    y_lags: list[int] = []
    u_lags: list[int] = []
    for code in row:
        if code == 0:
            continue
        signal, lag = divmod(int(code), 1000)
        if signal >= 3:
            raise ModelError(f"regressor {_describe(row)} uses input x{signal - 1} (code "
                             f"{code}): gfrf models have one input; a MISO model with more "
                             f"than one input has no single-input GFRFs")
        if signal != 1 and signal != 2:
            raise ModelError(f"regressor code {code} in {_describe(row)} is not an output "
                             f"(100n) or input (200n) code")
        if lag > MAX_DERIVATIVE_ORDER:
            raise ModelError(f"regressor code {code} has lag {lag}, above the limit "
                             f"{MAX_DERIVATIVE_ORDER}")
        if signal == 1 and lag == 0:
            raise ModelError(f"regressor code {code} is y(k) itself: an implicit model is "
                             f"not a NARX model")
        (y_lags if signal == 1 else u_lags).append(lag)
    return tuple(sorted(y_lags)), tuple(sorted(u_lags))


def _check_names(output: str, input_: str) -> None:
    for name in (output, input_):
        if not isinstance(name, str) or not name.isidentifier() or name in ("k", "D", "t"):
            raise ModelError(f"signal name {name!r} is not an identifier usable in an equation")
    if output == input_:
        raise ModelError(f"output and input have the same name {output!r}")


def _check_sample_time(sample_time: Any) -> float:
    if isinstance(sample_time, bool) or not isinstance(sample_time, (int, float)) \
            or not math.isfinite(sample_time) or sample_time <= 0:
        raise ModelError(f"sample_time must be a positive number of seconds, got "
                         f"{sample_time!r}")
    return float(sample_time)


def _lead(model: Model) -> Term:
    """The term ``a0*y[k]`` of a NARX model explicit in y[k] (no other term has lag 0)."""
    lead = [t for t in model.terms if 0 in t.y_orders]
    if not model.is_discrete or len(lead) != 1 or lead[0].y_orders != (0,) \
            or lead[0].u_orders:
        raise ArgumentError(f"{model.equation()} is not a NARX model explicit in "
                            f"{model.output}[k]")
    return lead[0]


def narx_equation(model: Model, digits: int | None = None) -> str:
    """The model as ``y[k] = theta_1*m_1 + ...``, linear terms first, output before input.

    Parameters
    ----------
    model : Model
        A discrete-time model whose only term in ``y[k]`` is linear.
    digits : int, optional
        Significant digits of the coefficients; None (default) writes the shortest
        text that reads back to the same float, so the equation is exact.
    """
    lead = _lead(model)
    a0 = lead.coefficient
    parts = []
    others = [t for t in model.terms if t is not lead]
    for t in sorted(others, key=lambda t: (t.degree, bool(t.u_orders), -len(t.y_orders),
                                           t.y_orders, t.u_orders)):
        c = -t.coefficient / a0
        number = repr(abs(c)) if digits is None else f"{abs(c):.{digits}g}"
        parts.append(("- " if c < 0 else "+ ") + f"{number}*{t.monomial()}")
    body = " ".join(parts)
    return f"{model.output}[k] = " + (body[2:] if body.startswith("+ ") else "-" + body[2:])


def _convert(final_model: Any, theta: Any, sample_time: Any, output: str, input_: str
             ) -> Model:
    sample_time = _check_sample_time(sample_time)
    _check_names(output, input_)
    codes, values = _codes_and_theta(final_model, theta)
    if codes.shape[1] > MAX_DEGREE:
        raise ModelError(f"regressors of degree {codes.shape[1]} exceed the limit {MAX_DEGREE}")
    terms = [Term((0,), (), 1.0, output, input_, True)]
    seen: dict[tuple[tuple[int, ...], tuple[int, ...]], str] = {}
    for row, value in zip(codes, values, strict=True):
        if not math.isfinite(value):
            raise ModelError(f"theta of regressor {_describe(row)} is {value}, not finite")
        y_lags, u_lags = _decode(row)
        if not y_lags and not u_lags:
            raise ModelError(f"the model has a constant term (regressor {_describe(row)}, "
                             f"theta = {value:.6g}): y = u = 0 is then not an equilibrium "
                             f"and the GFRFs about it are undefined; fit without the "
                             f"constant (gfrf identify does)")
        if (y_lags, u_lags) in seen:
            raise ModelError(f"regressors {seen[(y_lags, u_lags)]} and {_describe(row)} are "
                             f"the same monomial")
        seen[(y_lags, u_lags)] = _describe(row)
        if value != 0.0:
            terms.append(Term(y_lags, u_lags, -float(value), output, input_, True))
    if not any(t.u_orders for t in terms):
        raise ModelError(f"the model has no input term with a nonzero coefficient (a NAR "
                         f"model): its GFRFs are zero; fit it with the input {input_!r}")
    model = Model(terms=tuple(sorted(terms)), sample_time=sample_time, output=output,
                  input=input_)
    return replace(model, text=narx_equation(model))


def _noise_notes(fitted: Any) -> list[str]:
    estimator = getattr(fitted, "estimator", None)
    if getattr(estimator, "unbiased", False):
        return [f"the noise model of extended least squares (elag = "
                f"{getattr(fitted, 'elag', '?')}) is dropped: GFRFs are of the "
                f"deterministic part (sysidentpy keeps only process terms in theta)"]
    return []


def from_sysidentpy(model: Any, sample_time: float, output: str = "y",
                    input: str = "u") -> Model:  # noqa: A002 - the name a user expects
    """Convert a fitted sysidentpy polynomial NARX model into a gfrf Model, exactly.

    Parameters
    ----------
    model : sysidentpy model
        A fitted model with a polynomial basis: FROLS, AOLS, MetaMSS, ER, ... (any
        object with ``final_model``, the regressor code matrix, and ``theta``).
    sample_time : float
        Sample time T of the data in seconds (sysidentpy models are in samples).
    output, input : str
        Names of the output and input signals in the gfrf model.

    Returns
    -------
    Model
        The discrete-time model ``y[k] - sum_i theta_i * regressor_i = 0``; its
        ``text`` is the equation with shortest round-trip coefficients, which
        :func:`gfrf.model.equation.parse_model` reads back to the same terms.

    Raises
    ------
    ModelError
        A non-polynomial basis function (Fourier, Legendre, ...), more than one input,
        a constant term, an unfitted model, a code gfrf cannot read.

    Warns
    -----
    UserWarning
        When the model was fitted with a noise model (extended least squares): the
        noise (NARMAX) terms are dropped, since GFRFs are of the deterministic part.
    """
    basis = getattr(model, "basis_function", None)
    if basis is not None and type(basis).__name__ != "Polynomial":
        raise ModelError(f"the model uses the {type(basis).__name__} basis function: gfrf "
                         f"converts polynomial NARX models only (sysidentpy's Polynomial "
                         f"basis)")
    if getattr(model, "final_model", None) is None or getattr(model, "theta", None) is None:
        raise ModelError(f"{type(model).__name__} is not a fitted sysidentpy polynomial "
                         f"model (no final_model or theta): call fit first")
    n_inputs = getattr(model, "n_inputs", None)
    if isinstance(n_inputs, (int, np.integer)) and n_inputs > 1:
        raise ModelError(f"the model was fitted with {n_inputs} inputs: gfrf models have "
                         f"one input (MISO models have no single-input GFRFs)")
    result = _convert(model.final_model, model.theta, sample_time, output, input)
    for note in _noise_notes(model):
        warnings.warn(note, UserWarning, stacklevel=2)
    return result


def candidate_count(ylag: int, ulag: int, degree: int) -> int:
    """Number of candidate regressors of a polynomial NARX (constant excluded).

    Monomials of degree 1..``degree`` in ``ylag + ulag`` lagged signals.

    >>> candidate_count(2, 2, 3)
    34
    """
    return comb(ylag + ulag + degree, degree) - 1


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


def _check_int(name: str, value: Any, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not low <= value <= high:
        raise ArgumentError(f"{name} must be an integer from {low} to {high}, got {value!r}")
    return int(value)


def _check_settings(n: int, ylag: int, ulag: int, degree: int, criterion: str,
                    max_terms: int, holdout: float) -> tuple[int, int]:
    """Validate the fit settings against every limit; return (candidates, n_train)."""
    _check_int("ylag", ylag, 1, MAX_DERIVATIVE_ORDER)
    _check_int("ulag", ulag, 1, MAX_DERIVATIVE_ORDER)
    _check_int("degree", degree, 1, MAX_DEGREE)
    if criterion not in _CRITERIA:
        raise ArgumentError(f"criterion must be one of {', '.join(_CRITERIA)}, got "
                            f"{criterion!r}")
    candidates = candidate_count(ylag, ulag, degree)
    if candidates > MAX_CANDIDATES:
        raise ArgumentError(f"ylag {ylag}, ulag {ulag}, degree {degree} give {candidates} "
                            f"candidate terms, above the limit {MAX_CANDIDATES}")
    _check_int("max_terms", max_terms, 1, MAX_CANDIDATES)
    if isinstance(holdout, bool) or not isinstance(holdout, (int, float)) \
            or not 0.05 <= holdout <= 0.5:
        raise ArgumentError(f"holdout must be a fraction from 0.05 to 0.5, got {holdout!r}")
    if n < MIN_SAMPLES:
        raise ArgumentError(f"{n} samples: at least {MIN_SAMPLES} are needed")
    n_train = n - int(round(holdout * n))
    lag = max(ylag, ulag)
    if n_train - lag < 2 * candidates or n - n_train <= lag + 1:
        raise ArgumentError(f"{n} samples are too few for {candidates} candidate terms: the "
                            f"training part ({n_train} samples) needs at least "
                            f"{2 * candidates + lag}")
    if (n_train - lag) * (candidates + 1) > _MAX_MATRIX:
        raise ArgumentError(f"the candidate matrix ({n_train - lag} x {candidates + 1}) "
                            f"exceeds the limit of {_MAX_MATRIX} entries; use fewer samples, "
                            f"lags or a lower degree")
    return candidates, n_train


def _check_signal(name: str, values: Any) -> np.ndarray:
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"{name} must be a sequence of numbers: {exc}") from None
    if a.ndim != 1:
        raise ArgumentError(f"{name} must be one-dimensional, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ArgumentError(f"{name} has a non-finite value at sample "
                            f"{int(np.argmin(np.isfinite(a)))}")
    return a


def _frols(ylag: int, ulag: int, degree: int, criterion: str, max_terms: int) -> Any:
    """sysidentpy's FROLS with least squares, without the constant regressor."""
    try:
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


def read_csv(path: str | Path, output: str, input: str  # noqa: A002
             ) -> tuple[np.ndarray, np.ndarray]:
    """Read the output and input columns of a CSV file with a header row.

    Parameters
    ----------
    path : str or Path
        The CSV file: a header naming the columns, then one row per sample.
    output, input : str
        Header names of the output and input columns.

    Returns
    -------
    y, u : numpy.ndarray

    Raises
    ------
    ArgumentError
        Missing file or column, a value that is not a finite number (the message
        names the line and column), fewer than two rows, more than :data:`MAX_SAMPLES`.
    """
    p = Path(path)
    if not p.is_file():
        raise ArgumentError(f"data file {str(p)!r} does not exist")
    y: list[float] = []
    u: list[float] = []
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(fh)
            header = [h.strip() for h in next(reader, [])]
            columns = []
            for name in (output, input):
                if name not in header:
                    raise ArgumentError(f"{p}: no column {name!r}; the header has "
                                        f"{', '.join(map(repr, header)) or 'nothing'}")
                columns.append(header.index(name))
            for row in reader:
                if not row or all(not c.strip() for c in row):
                    continue
                if reader.line_num > MAX_SAMPLES + 1:
                    raise ArgumentError(f"{p}: more than {MAX_SAMPLES} samples")
                for target, col, name in ((y, columns[0], output), (u, columns[1], input)):
                    text = row[col].strip() if col < len(row) else ""
                    try:
                        value = float(text)
                    except ValueError:
                        value = math.nan
                    if not math.isfinite(value):
                        raise ArgumentError(f"{p}, line {reader.line_num}, column {name!r}: "
                                            f"{text!r} is not a finite number")
                    target.append(value)
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ArgumentError(f"{p}: not a readable CSV file: {exc}") from None
    if len(y) < 2:
        raise ArgumentError(f"{p}: fewer than two data rows")
    return np.asarray(y), np.asarray(u)


def _toml_string(text: str) -> str:
    return json.dumps(text, ensure_ascii=True)


def model_file_text(result: Identification, data: str, name: str = "",
                    description: str = "") -> str:
    """The model file (TOML) of an identification; ``source`` names the data and settings.

    The text is read back before it is returned: its model must have exactly the
    identified terms (same lags, same coefficients), else :class:`ModelError`.
    """
    m = result.model
    source = (f"gfrf identify {data} --output {m.output} --input {m.input} --sample-time "
              f"{m.sample_time!r} {result.settings_text()} (sysidentpy "
              f"{result.sysidentpy_version} FROLS): {result.quality_text()}")
    lines = ["# Identified from measured data by `gfrf identify` (sysidentpy FROLS).",
             f"name = {_toml_string(name or 'NARX identified from ' + Path(data).name)}",
             f"equation = {_toml_string(m.text)}",
             f"sample_time = {m.sample_time!r}"]
    if m.output != "y" or m.input != "u":
        lines += [f"output = {_toml_string(m.output)}", f"input = {_toml_string(m.input)}"]
    lines.append(f"source = {_toml_string(source)}")
    if description or result.notes:
        about = " ".join([description, *result.notes]).strip()
        lines.append(f"description = {_toml_string(about)}")
    text = "\n".join(lines) + "\n"
    reread = model_from_dict(tomllib.loads(text)).plant
    if reread.terms != m.terms:  # Term equality includes the coefficient
        raise ModelError(f"the model file does not reproduce the identified model: "
                         f"{reread.equation()} != {m.equation()}")
    return text


def load_text(text: str, path: str) -> ModelFile:
    """The ModelFile of a model file text (as ``load_model`` would read it from ``path``)."""
    return model_from_dict(tomllib.loads(text), path=path)


def write_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (temporary file in the same folder, then rename).

    A reader sees the old file or the new one, never a partial file; the temporary
    file is removed when writing fails.
    """
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=folder)
    mask = os.umask(0)
    os.umask(mask)
    try:
        os.chmod(tmp, 0o666 & ~mask)  # mkstemp's 0600 would make a private file
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target
