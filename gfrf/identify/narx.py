"""sysidentpy's polynomial NARX models as gfrf models, exactly, and a NARX model as text.

:func:`from_sysidentpy` converts a fitted sysidentpy polynomial model into a gfrf
:class:`~gfrf.model.equation.Model` exactly: every regressor, lag and coefficient.  sysidentpy
encodes a regressor as a row of integer codes, one per factor, ``0`` for an unused
slot: ``1000 + n`` is the output ``y(k-n)``, ``2000 + n`` the (first) input ``u(k-n)``,
``3000 + n`` a second input; the row ``[2001, 1001, 0]`` is ``u(k-1)*y(k-1)`` and the
all-zero row is the constant.  The fitted model reads ``y[k] = sum_i theta_i *
regressor_i``; gfrf models are ``sum(terms) = 0``, so the gfrf terms are ``y[k]`` with
coefficient 1 and every regressor with coefficient ``-theta_i``.  :func:`narx_equation`
writes such a model back as ``y[k] = theta_1*m_1 + ...``.

The converter needs nothing but the model's ``final_model`` and ``theta`` arrays: this
module does not import sysidentpy.

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

import math
import warnings
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, ModelError
from gfrf.identify.data import _check_names, _check_sample_time
from gfrf.model.equation import MAX_DEGREE, MAX_DERIVATIVE_ORDER, Model, Term

__all__ = ["from_sysidentpy", "narx_equation", "narx_model"]


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
    return narx_model(terms, sample_time, output, input_,
                      f"the model has no input term with a nonzero coefficient (a NAR "
                      f"model): its GFRFs are zero; fit it with the input {input_!r}")


def narx_model(terms: list[Term], sample_time: float, output: str, input_: str,
               no_input: str) -> Model:
    """The NARX :class:`Model` of ``terms`` (sorted, its text written by :func:`narx_equation`).

    Parameters
    ----------
    terms : list of Term
        The terms of the equation.
    sample_time : float
        T in s.
    output, input_ : str
        Names of the output and of the input.
    no_input : str
        The error message for a model without input term.

    Returns
    -------
    Model
        The model.

    Raises
    ------
    ModelError
        With the message ``no_input`` when no term has an input factor (a NAR model,
        whose GFRFs are all zero).
    """
    if not any(t.u_orders for t in terms):
        raise ModelError(no_input)
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
                    input: str = "u") -> Model:
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
