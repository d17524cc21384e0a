"""The data side of :mod:`gfrf.identify`: a CSV file's columns, and the checks of data and settings.

:func:`read_csv` reads the output and input columns of a CSV file with a header row.
The ``_check_*`` helpers refuse bad signal names, sample times, samples and fit
settings before any fitting, against the limits below; :func:`candidate_count` is the
number of candidate regressors that a fit's lags and degree give.
"""

from __future__ import annotations

import csv
import math
import sys
import warnings
from dataclasses import dataclass
from math import comb
from pathlib import Path
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import MAX_DEGREE, MAX_DERIVATIVE_ORDER

__all__ = ["read_csv", "read_data", "Data", "check_rank", "candidate_count", "MAX_CANDIDATES",
           "MAX_SELECTION_WORK",
           "MAX_SAMPLES", "MIN_SAMPLES", "MAX_MAGNITUDE", "MISSING"]

#: Largest number of candidate regressors (lags and degree) a fit may consider.
MAX_CANDIDATES = 2000
#: Largest number of samples read from a data file.
MAX_SAMPLES = 2_000_000
#: Fewest samples a fit accepts (training plus held-out part).
MIN_SAMPLES = 50
#: Largest number of floats in the candidate regressor matrix (8 bytes each, 32 MB): a
#: longer training part is fitted on its first ``MAX_MATRIX // (candidates + 1)`` samples.
MAX_MATRIX = 4_000_000
#: Largest work of the term selection, ``rows * candidates * max_terms`` (the error
#: reduction ratios of FROLS; about 5 s of CPU): refused before any fitting.
MAX_SELECTION_WORK = 500_000_000
_CRITERIA = ("aic", "aicc", "bic", "fpe", "lilc")


def _check_names(output: str, input_: str) -> None:
    for name in (output, input_):
        if not isinstance(name, str) or not name.isidentifier() or name in ("k", "D", "t"):
            raise ModelError(f"signal name {name!r} is not an identifier usable in an equation")
    if output == input_:
        raise ModelError(f"output and input have the same name {output!r}")


def _check_sample_time(sample_time: Any) -> float:
    if isinstance(sample_time, bool) or not isinstance(sample_time, (int, float)) \
            or not math.isfinite(sample_time) or sample_time < sys.float_info.min:
        raise ModelError(f"sample_time must be a positive normal number of seconds "
                         f"(>= {sys.float_info.min:.3g}), got {sample_time!r}")
    return float(sample_time)


def candidate_count(ylag: int, ulag: int, degree: int) -> int:
    """Number of candidate regressors of a polynomial NARX (constant excluded).

    Monomials of degree 1..``degree`` in ``ylag + ulag`` lagged signals.

    Parameters
    ----------
    ylag, ulag : int
        Largest lags of the output and of the input.
    degree : int
        Largest total degree.

    Returns
    -------
    int
        The count.

    Examples
    --------
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
                    max_terms: int, holdout: float) -> tuple[int, int, int]:
    """Validate the fit settings against every limit; return (candidates, n_train, n_fit).

    ``n_fit`` is the number of training samples the candidate matrix holds (all of the
    training part, or its first part when the matrix would exceed :data:`MAX_MATRIX`).
    """
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
    n_fit = min(n_train, MAX_MATRIX // (candidates + 1) + lag)
    work = (n_fit - lag) * (candidates + 1) * min(max_terms, candidates)
    if work > MAX_SELECTION_WORK:
        raise ArgumentError(f"ylag {ylag}, ulag {ulag}, degree {degree} ({candidates} "
                            f"candidate terms) with max_terms {max_terms} on {n_fit} "
                            f"training rows need {work:.3g} regressor operations, above the "
                            f"limit {MAX_SELECTION_WORK:.3g}: lower max_terms, the lags or "
                            f"the degree")
    return candidates, n_train, n_fit


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


#: Largest |value| in the data: powers up to the degree of larger values overflow or lose
#: every digit of the smaller terms; rescale the data (SI units) first.
MAX_MAGNITUDE = 1e50
#: Smallest largest |value| of a signal: powers up to the degree of smaller values
#: underflow; rescale the data first.
MIN_MAGNITUDE = 1e-50
#: Smallest spread (standard deviation) of a signal, relative to its largest |value|,
#: that is not constant (rounding of a constant leaves about 1e-16).
_MIN_SPREAD = 1e-12
#: What ``missing`` may be in :func:`read_data`.
MISSING = ("refuse", "drop", "interpolate")


def _check_data(y: np.ndarray, u: np.ndarray, degree: int) -> None:
    """Refuse data no fit can use: too large, constant, or no excitation."""
    for name, a in (("y", y), ("u", u)):
        big = float(np.max(np.abs(a)))
        if big > MAX_MAGNITUDE:
            raise ArgumentError(f"{name} has values up to {big:.3g}, above the limit "
                                f"{MAX_MAGNITUDE:g}: regressors of degree {degree} would "
                                f"overflow; rescale the data (e.g. to SI units)")
        spread = big * float(np.std(a / big)) if big > 0 else 0.0  # no underflow at 1e-300
        if 0 < big < MIN_MAGNITUDE and spread > _MIN_SPREAD * big:
            raise ArgumentError(f"{name} has values only up to {big:.3g}, below the limit "
                                f"{MIN_MAGNITUDE:g}: regressors of degree {degree} would "
                                f"underflow; rescale the data (e.g. to SI units)")
        if not spread > _MIN_SPREAD * big:
            raise ArgumentError(f"{name} is constant ({a[0]:.6g} in every sample of the "
                                f"training part): no dynamics can be identified from it")


def check_rank(columns: np.ndarray, names: list[str]) -> None:
    """Refuse linearly dependent candidate regressors (columns).

    Parameters
    ----------
    columns : numpy.ndarray
        Candidate regressors, one per column (samples in rows).
    names : list of str
        The regressors' names, one per column.

    Raises
    ------
    ArgumentError
        The columns, each scaled to unit norm, have a singular value below 1e-9 of the
        largest; the message names a dependent regressor.
    """
    norms = np.linalg.norm(columns, axis=0)
    if np.any(norms == 0.0):
        raise ArgumentError(f"the candidate regressor {names[int(np.argmin(norms))]} is "
                            f"zero in the training data")
    scaled = columns / norms
    s = np.linalg.svd(scaled, compute_uv=False)
    if s[-1] <= 1e-9 * s[0]:
        r = np.linalg.qr(scaled, mode="r")
        diag = np.abs(np.diag(r))
        worst = names[int(np.argmin(diag))]
        raise ArgumentError(f"the candidate regressors are linearly dependent (e.g. "
                            f"{worst} is a combination of the others): the input does not "
                            f"excite every term of this model; use a lower --degree or an "
                            f"input with more levels")


@dataclass(frozen=True)
class Data:
    """Columns of a data file, with what reading them did.

    Attributes
    ----------
    y, u : numpy.ndarray
        Output and input samples.
    sample_time : float or None
        The step of the time column, when the file has one.
    notes : tuple of str
        Rows dropped or interpolated.
    """

    y: np.ndarray
    u: np.ndarray
    sample_time: float | None
    notes: tuple[str, ...]


def _time_step(t: np.ndarray, path: Path, name: str) -> float:
    steps = np.diff(t)
    step = float(np.median(steps))
    if not step > 0 or np.max(np.abs(steps - step)) > 1e-6 * step + 1e-9 * np.max(np.abs(t)):
        bad = int(np.argmax(np.abs(steps - step)))
        raise ArgumentError(f"{path}: column {name!r} is not equally spaced (step "
                            f"{steps[bad]:.6g} after row {bad + 1}, median {step:.6g})")
    return float(f"{step:.10g}")  # 0.1, not the 0.09999999999999432 of printed times


def _fill(values: np.ndarray, missing: str, path: Path, columns: str, first_line: int
          ) -> tuple[np.ndarray, list[str]]:
    """Rows of ``values`` (samples x signals, NaN missing) with the gaps handled."""
    bad = ~np.all(np.isfinite(values), axis=1)
    if not np.any(bad):
        return values, []
    count = int(np.sum(bad))
    if missing == "refuse":
        raise ArgumentError(f"{path}: {count} row(s) with missing or non-numeric values in "
                            f"{columns} (the first on line {first_line}); give --missing "
                            f"interpolate (linear, in the sample index) or --missing drop "
                            f"(keep the longest run of complete rows)")
    if missing == "drop":
        edges = np.flatnonzero(np.diff(np.r_[1, bad.astype(int), 1]))
        runs = list(zip(edges[::2], edges[1::2], strict=True))  # [start, end) of good runs
        start, end = max(runs, key=lambda r: (r[1] - r[0], -r[0]))
        return values[start:end], [f"{count} row(s) with missing values: kept the longest run "
                                   f"of complete rows, data rows {start + 1} to {end}"]
    good = np.flatnonzero(~bad)
    if good.size < 2:
        raise ArgumentError(f"{path}: fewer than two complete rows to interpolate from")
    out = values[good[0]:good[-1] + 1].copy()
    index = np.arange(good[0], good[-1] + 1)
    for j in range(out.shape[1]):
        ok = np.isfinite(out[:, j])
        out[:, j] = np.interp(index, index[ok], out[ok, j])
    dropped = good[0] + values.shape[0] - 1 - good[-1]
    return out, [f"{count} row(s) with missing values: interpolated linearly in the sample "
                 f"index" + (f" ({dropped} at the ends dropped)" if dropped else "")]


def _plain_numeric(path: Path, columns: list[int]) -> np.ndarray | None:
    """The ``columns`` of the rows after the header, read by :func:`numpy.loadtxt` when
    every row holds plain finite numbers there (the common file: one fast parse), else
    None (the row-by-row reader then finds and names what is wrong)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an empty rest: None below
            values = np.loadtxt(path, delimiter=",", comments=None, usecols=columns,
                                ndmin=2, skiprows=1, max_rows=MAX_SAMPLES + 1,
                                quotechar='"', dtype=float, encoding="utf-8-sig")
    except (ValueError, IndexError):
        values = None
    if values is None or values.shape[0] > MAX_SAMPLES or not np.all(np.isfinite(values)) \
            or values.shape[0] == 0:
        return None
    return values


def read_data(path: str | Path, output: str, input: str,
              time: str = "t", missing: str = "refuse") -> Data:
    """Read the output, input and (if present) time columns of a CSV file with a header row.

    Parameters
    ----------
    path : str or Path
        The CSV file: a header naming the columns, then one row per sample.
    output, input : str
        Header names of the output and input columns.
    time : str
        Header name of the time column (used when present: its step is the sample
        time, and it must be equally spaced).
    missing : {"refuse", "drop", "interpolate"}
        Rows with an empty or non-numeric value: refused (the default), the longest
        run of complete rows kept, or filled by linear interpolation.

    Returns
    -------
    Data

    Raises
    ------
    ArgumentError
        Missing file or column, a missing value (with ``missing="refuse"``), a value
        that is not a finite number (the message names the line and column), fewer
        than two rows, more than :data:`MAX_SAMPLES`, a time column not equally spaced.
    """
    if missing not in MISSING:
        raise ArgumentError(f"missing must be one of {', '.join(MISSING)}, got {missing!r}")
    p = Path(path)
    if not p.is_file():
        raise ArgumentError(f"data file {str(p)!r} does not exist")
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            header = [h.strip() for h in next(csv.reader([fh.readline()]), [])]
            names = [output, input]
            for name in names:
                if name not in header:
                    raise ArgumentError(f"{p}: no column {name!r}; the header has "
                                        f"{', '.join(map(repr, header)) or 'nothing'}")
            if time in header and time not in names:
                names.append(time)
            columns = [header.index(name) for name in names]
            fast = _plain_numeric(p, columns)
            fh.seek(0)
            reader = csv.reader(fh)
            next(reader, [])
            values = np.empty((1024, len(names))) if fast is None else fast
            count = 0 if fast is None else fast.shape[0]
            first_missing = 0
            for row in reader if fast is None else ():
                if not row or all(not c.strip() for c in row):
                    continue
                if count >= MAX_SAMPLES:
                    raise ArgumentError(f"{p}: more than {MAX_SAMPLES} samples")
                if count == values.shape[0]:
                    values = np.resize(values, (2 * count, len(names)))
                for j, (col, name) in enumerate(zip(columns, names, strict=True)):
                    text = row[col].strip() if col < len(row) else ""
                    if not text or text.lower() in ("nan", "na", "null", "none"):
                        values[count, j] = math.nan
                        first_missing = first_missing or reader.line_num
                        continue
                    try:
                        value = float(text)
                    except ValueError:
                        value = math.nan
                    if not math.isfinite(value):
                        raise ArgumentError(f"{p}, line {reader.line_num}, column {name!r}: "
                                            f"{text!r} is not a finite number")
                    values[count, j] = value
                count += 1
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ArgumentError(f"{p}: not a readable CSV file: {exc}") from None
    values, notes = (values, []) if fast is not None else _fill(  # fast: all finite
        values[:count], missing, p, " or ".join(map(repr, names)), first_missing)
    if values.shape[0] < 2:
        raise ArgumentError(f"{p}: fewer than two data rows")
    step = _time_step(values[:, 2], p, time) if len(names) == 3 else None
    return Data(np.ascontiguousarray(values[:, 0]), np.ascontiguousarray(values[:, 1]),
                step, tuple(notes))


def read_csv(path: str | Path, output: str, input: str
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
        As :func:`read_data` with ``missing="refuse"``.
    """
    data = read_data(path, output, input, time="\0")
    return data.y, data.u
