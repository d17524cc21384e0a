"""The data side of :mod:`gfrf.identify`: a CSV file's columns, and the checks of data and settings.

:func:`read_csv` reads the output and input columns of a CSV file with a header row.
The ``_check_*`` helpers refuse bad signal names, sample times, samples and fit
settings before any fitting, against the limits below; :func:`candidate_count` is the
number of candidate regressors that a fit's lags and degree give.
"""

from __future__ import annotations

import csv
import math
from math import comb
from pathlib import Path
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import MAX_DEGREE, MAX_DERIVATIVE_ORDER

__all__ = ["read_csv", "candidate_count", "MAX_CANDIDATES", "MAX_SAMPLES", "MIN_SAMPLES"]

#: Largest number of candidate regressors (lags and degree) a fit may consider.
MAX_CANDIDATES = 2000
#: Largest number of samples read from a data file.
MAX_SAMPLES = 2_000_000
#: Fewest samples a fit accepts (training plus held-out part).
MIN_SAMPLES = 50
#: Largest number of floats in the candidate regressor matrix (8 bytes each).
_MAX_MATRIX = 300_000_000
_CRITERIA = ("aic", "aicc", "bic", "fpe", "lilc")


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


def candidate_count(ylag: int, ulag: int, degree: int) -> int:
    """Number of candidate regressors of a polynomial NARX (constant excluded).

    Monomials of degree 1..``degree`` in ``ylag + ulag`` lagged signals.

    >>> candidate_count(2, 2, 3)
    34
    """
    return comb(ylag + ulag + degree, degree) - 1


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
