"""Periodic measurements: a CSV of ``t,u,y[,realisation]`` cut into periods and their spectra.

Each realisation (the optional integer column ``realisation``; without it the file is
one realisation) starts its own time axis and holds consecutive periods of ``N``
samples.  :func:`read_periodic` reads and checks the file, :func:`spectra` turns the
samples into the DFT coefficients ``X[m, p, k]`` (realisation m, period p, line k),
scaled so that ``u(t) = sum_k X_k exp(j k w0 t)`` over positive and negative k.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gfrf.errors import ArgumentError

__all__ = ["Periodic", "read_periodic", "periodic", "spectra", "COLUMNS", "MAX_ROWS",
           "MAX_ABS_VALUE", "SAMPLE_TIME_LIMITS"]

#: The columns a measurement file may have (``realisation`` is optional).
COLUMNS = ("t", "u", "y", "realisation")
#: Most data rows read.
MAX_ROWS = 2_000_000
#: Most realisations.
MAX_REALISATIONS = 10_000
#: Largest data file in bytes (2,000,000 rows of four numbers in full precision fit).
MAX_BYTES = 400_000_000
#: Largest magnitude of a value of u or y (the spectra and their variances stay finite).
MAX_ABS_VALUE = 1e150
#: Sample times accepted, s (the step of the t column; beyond them the line
#: frequencies leave the float range).
SAMPLE_TIME_LIMITS = (1e-12, 1e12)


@dataclass(frozen=True, kw_only=True)
class Periodic:
    """Measured periods.

    Attributes
    ----------
    u, y : numpy.ndarray
        Shape (realisations, periods, N): the samples, transient periods removed.
    sample_time : float
        T in s (from the t column).
    notes : tuple of str
        What reading did (samples dropped at a realisation's end).
    """

    u: np.ndarray
    y: np.ndarray
    sample_time: float
    notes: tuple[str, ...]

    @property
    def period(self) -> int:
        """Samples per period N."""
        return int(self.u.shape[2])


def _header(path: Path) -> list[str]:
    try:
        with path.open(encoding="utf-8-sig", newline="") as fh:
            first = fh.readline(10_000)
    except UnicodeDecodeError as exc:
        raise ArgumentError(f"{path}: not a readable text file: {exc}") from None
    if not first.strip():
        raise ArgumentError(f"{path}: no header row (need t, u, y [, realisation])")
    header = [h.strip().strip('"').strip() for h in first.strip().split(",")]
    if len(header) == 1 and any(c in header[0] for c in ";\t "):
        raise ArgumentError(f"{path}: the header {header[0]!r} is not comma-separated")
    if "" in header:
        raise ArgumentError(f"{path}: an empty column name in the header "
                            f"{','.join(header)!r}")
    missing = [c for c in COLUMNS[:3] if c not in header]
    extra = [c for c in header if c not in COLUMNS]
    if extra:
        raise ArgumentError(
            f"{path}: columns {', '.join(map(repr, extra))} besides t, u, y, realisation: "
            f"multi-input or multi-output (MISO/MIMO) data are not supported; give one "
            f"input column u and one output column y (one file per input-output pair)")
    if missing:
        raise ArgumentError(f"{path}: no column {', '.join(map(repr, missing))}; the header "
                            f"has {', '.join(map(repr, header))}: need t, u, y "
                            f"[, realisation]")
    if len(set(header)) != len(header):
        raise ArgumentError(f"{path}: a column name appears twice in the header")
    return header


def read_periodic(path: str | Path, period: int, skip_periods: int = 0) -> Periodic:
    """Read a periodic measurement CSV (columns ``t,u,y`` and optionally ``realisation``).

    Parameters
    ----------
    path : str or Path
        The file.
    period : int
        N, the period in samples.
    skip_periods : int
        Periods dropped at the start of each realisation (transients).

    Returns
    -------
    Periodic

    Raises
    ------
    ArgumentError
        A missing file, other columns (MISO/MIMO data), a value that is not a finite
        number or above :data:`MAX_ABS_VALUE`, more than :data:`MAX_ROWS` rows or
        :data:`MAX_BYTES` bytes, a non-integer realisation, a time column not equally
        spaced or with a step outside :data:`SAMPLE_TIME_LIMITS`, fewer than one
        period per realisation.
    """
    p = Path(path)
    if not p.is_file():
        raise ArgumentError(f"data file {str(p)!r} does not exist or is not a regular file")
    size = p.stat().st_size
    if size > MAX_BYTES:
        raise ArgumentError(f"{p}: {size} bytes, above the limit {MAX_BYTES}")
    header = _header(p)
    try:
        with warnings.catch_warnings():  # "no data", blank lines: handled below
            warnings.simplefilter("ignore", UserWarning)
            values = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2,
                                max_rows=MAX_ROWS + 1, encoding="utf-8-sig")
    except ValueError as exc:
        raise ArgumentError(f"{p}: not a table of numbers: {str(exc).splitlines()[0]}"
                            ) from None
    if values.size == 0:
        raise ArgumentError(f"{p}: no data rows")
    if values.shape[0] > MAX_ROWS:
        raise ArgumentError(f"{p}: more than {MAX_ROWS} data rows")
    if values.shape[1] != len(header):
        raise ArgumentError(f"{p}: rows have {values.shape[1]} values, the header "
                            f"{len(header)} names")
    if not np.all(np.isfinite(values)):
        row, col = np.argwhere(~np.isfinite(values))[0]
        raise ArgumentError(f"{p}, data row {row + 1}, column {header[col]!r}: not a finite "
                            f"number")
    col = {name: values[:, header.index(name)] for name in header}
    for name in ("u", "y"):
        if np.any(np.abs(col[name]) > MAX_ABS_VALUE):
            row = int(np.argmax(np.abs(col[name]) > MAX_ABS_VALUE))
            raise ArgumentError(f"{p}, data row {row + 1}, column {name!r}: above "
                                f"MAX_ABS_VALUE = {MAX_ABS_VALUE:g} in magnitude (rescale it)")
    if "realisation" in col:
        r = col["realisation"]
        if np.any(r != np.round(r)):
            raise ArgumentError(f"{p}: column 'realisation' must hold integers")
        starts = np.flatnonzero(np.r_[True, r[1:] != r[:-1]])
        labels = r[starts]
        if np.unique(labels).size != labels.size:
            raise ArgumentError(f"{p}: the rows of each realisation must be consecutive")
    else:
        starts = np.array([0])
    if starts.size > MAX_REALISATIONS:
        raise ArgumentError(f"{p}: more than {MAX_REALISATIONS} realisations")
    return periodic(col["t"], col["u"], y=col["y"], starts=starts, period=period,
                    skip_periods=skip_periods, where=str(p))


def _step(t: np.ndarray, where: str) -> float:
    if t.size < 2:
        raise ArgumentError(f"{where}: a realisation with fewer than two samples")
    steps = np.diff(t)
    step = float(np.median(steps))
    if not step > 0 or np.max(np.abs(steps - step)) > 1e-6 * step + 1e-9 * np.max(np.abs(t)):
        bad = int(np.argmax(np.abs(steps - step)))
        raise ArgumentError(f"{where}: column 't' is not equally spaced (step "
                            f"{steps[bad]:.6g} after sample {bad + 1}, median {step:.6g})")
    if not SAMPLE_TIME_LIMITS[0] <= step <= SAMPLE_TIME_LIMITS[1]:
        raise ArgumentError(f"{where}: the step of column 't', {step:.6g} s, is outside "
                            f"[{SAMPLE_TIME_LIMITS[0]:g}, {SAMPLE_TIME_LIMITS[1]:g}] s "
                            f"(SAMPLE_TIME_LIMITS)")
    return step


def periodic(t: np.ndarray, u: np.ndarray, y: np.ndarray, starts: np.ndarray, period: int,
             skip_periods: int = 0, where: str = "data") -> Periodic:
    """Cut samples into realisations and periods.

    Parameters
    ----------
    t, u, y : numpy.ndarray
        Time (s), input and output samples, one-dimensional, equal lengths.
    starts : numpy.ndarray
        Index of the first sample of each realisation (the first is 0).
    period : int
        N, the period in samples (at least 4).
    skip_periods : int
        Periods dropped at the start of each realisation.
    where : str
        Name of the data in messages.

    Returns
    -------
    Periodic
        Realisations keep ``min`` over realisations of their whole periods.

    Raises
    ------
    ArgumentError
        As :func:`read_periodic`.
    """
    if isinstance(period, bool) or not isinstance(period, (int, np.integer)) or period < 4:
        raise ArgumentError(f"--period must be an integer of at least 4 samples, got "
                            f"{period!r}")
    if isinstance(skip_periods, bool) or not isinstance(skip_periods, (int, np.integer)) \
            or skip_periods < 0:
        raise ArgumentError(f"--skip-periods must be a non-negative integer, got "
                            f"{skip_periods!r}")
    bounds = list(zip(starts, [*starts[1:], t.size], strict=True))
    steps = [_step(t[a:b], f"{where}, realisation {i}") for i, (a, b) in enumerate(bounds)]
    step = steps[0]
    if max(abs(s - step) for s in steps) > 1e-6 * step:
        raise ArgumentError(f"{where}: realisations have different sample times "
                            f"({min(steps):.6g} to {max(steps):.6g} s)")
    counts = [(b - a) // period for a, b in bounds]
    whole = min(counts)
    if whole - skip_periods < 1:
        raise ArgumentError(f"{where}: a realisation has {min(b - a for a, b in bounds)} "
                            f"samples, {whole} whole period(s) of {period}: fewer than "
                            f"--skip-periods {skip_periods} + 1")
    notes = []
    if any(c != whole or (b - a) % period for c, (a, b) in zip(counts, bounds, strict=True)):
        notes.append(f"each realisation cut to its first {whole} whole period(s) of {period} "
                     f"samples")
    if skip_periods:
        notes.append(f"the first {skip_periods} period(s) of each realisation skipped")
    keep = whole - skip_periods
    uu = np.stack([u[a + skip_periods * period: a + whole * period] for a, _ in bounds])
    yy = np.stack([y[a + skip_periods * period: a + whole * period] for a, _ in bounds])
    shape = (len(bounds), keep, period)
    yy = yy.reshape(shape)
    if keep >= 3 and _transient(yy):
        notes.append("the first period differs from the others by more than their spread: "
                     "a transient? give --skip-periods 1")
    return Periodic(u=uu.reshape(shape), y=yy, sample_time=float(f"{step:.10g}"),
                    notes=tuple(notes))


def _transient(y: np.ndarray) -> bool:
    """True if the first period of the output lies farther from the mean of the later
    ones than 4 times the typical distance of a later period from that mean."""
    later = y[:, 1:, :]
    mean = later.mean(axis=1)
    spread = float(np.sqrt(np.mean((later - mean[:, None, :]) ** 2)))
    first = float(np.sqrt(np.mean((y[:, 0, :] - mean) ** 2)))
    return first > 4 * spread + 1e-9 * float(np.max(np.abs(y)))


def spectra(x: np.ndarray) -> np.ndarray:
    """DFT lines 0..N/2 of each period, scaled so that ``x(t) = sum_k X_k e^{j k w0 t}``
    (two-sided): shape (realisations, periods, N // 2 + 1).

    Parameters
    ----------
    x : numpy.ndarray
        Real samples of shape (realisations, periods, N), one period of N samples per row.

    Returns
    -------
    numpy.ndarray
        Complex, of shape (realisations, periods, N // 2 + 1).
    """
    return np.fft.rfft(x, axis=-1) / x.shape[-1]
