"""Odd random-phase multisines with a designed frequency grid, and the lines they isolate.

A multisine of period ``N`` samples (sample time ``T``) excites the harmonic lines
``k`` (angular frequency ``k * 2 pi / (N T)`` rad/s) with a flat amplitude and
independent uniformly random phases; each *realisation* draws new phases and is
repeated for several *periods*.  Two grids:

* ``"random-odd"`` (the Pintelon-Schoukens detection grid): odd lines up to
  ``max_line``, one of every three consecutive odd lines left out at random; the even
  lines show even-degree distortion, the odd lines left out odd-degree distortion;
* ``"isolating"``: a sparse set of odd lines chosen greedily so that every
  combination of one, two or three excited lines (signs included, the degenerate
  triples ``a + b - b`` excepted) falls on its own line below the Nyquist line:
  each sum or difference of two excited lines isolates one value of H2, each
  non-degenerate triple one value of H3 (:func:`combination_lines`).

>>> design = multisine(256, 0.1, grid="isolating", max_line=40, seed=1)
>>> design.lines
(1, 7, 25)
>>> [(c.line, c.factors) for c in design.isolated()[2][:3]]
[(2, (1, 1)), (6, (-1, 7)), (8, (1, 7))]
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from itertools import combinations_with_replacement
from typing import Any

import numpy as np

from gfrf._results import Result, markdown_table, short_repr
from gfrf.errors import ArgumentError

__all__ = ["Multisine", "multisine", "combination_lines", "Combination", "GRIDS",
           "MAX_PERIOD", "MAX_SIGNAL", "SAMPLE_TIME_LIMITS", "RMS_LIMITS",
           "MIN_LEVEL"]

#: The grids :func:`multisine` designs.
GRIDS = ("random-odd", "isolating")
#: Largest period in samples.
MAX_PERIOD = 1 << 20
#: Largest number of samples of a whole excitation (realisations x periods x period).
MAX_SIGNAL = 2_000_000
#: Most excited lines whose two- and three-line combinations are enumerated.
MAX_COMBINED_LINES = 40
#: Sample times accepted, s (beyond them the line frequencies or the time axis leave
#: the float range).
SAMPLE_TIME_LIMITS = (1e-12, 1e12)
#: RMS values accepted (beyond them the spectrum's powers leave the float range).
RMS_LIMITS = (1e-100, 1e100)
#: Smallest input level relative to the RMS value.
MIN_LEVEL = 1e-6


@dataclass(frozen=True, kw_only=True)
class Combination:
    """One output line reached by exactly one combination of excited lines.

    Attributes
    ----------
    line : int
        The output line (0 < line < N/2).
    factors : tuple of int
        The signed excited lines whose frequencies sum to ``line`` (negative: the
        conjugate component).
    count : int
        Number of distinct orderings of ``factors``: the output at ``line`` is
        ``count * H_n(factors) * prod X(factor)``.
    """

    line: int
    factors: tuple[int, ...]
    count: int


def _multisets(signed: list[int], order: int) -> list[tuple[int, ...]]:
    """Multisets of ``order`` signed lines, no pair x, -x, with a positive sum."""
    out = []
    for combo in combinations_with_replacement(signed, order):
        if any(-x in combo for x in combo) or sum(combo) <= 0:
            continue
        out.append(combo)
    return out


def _folded(s: int, n: int) -> int:
    s %= n
    return n - s if s > n // 2 else s


def combination_lines(lines: tuple[int, ...] | list[int], n: int, orders: tuple[int, ...] = (2, 3)
                      ) -> dict[int, list[Combination]]:
    """The output lines that exactly one combination of excited lines reaches, by order.

    A line counts as isolated for order ``m`` (2 or 3) when, of every combination of
    one, two and three excited lines (degenerate triples ``a + b - b`` excepted, they
    fall on excited lines), exactly one reaches it, of order ``m``, not through
    aliasing (its sum is below ``n / 2``), and it is not an excited line.

    Parameters
    ----------
    lines : sequence of int
        The excited lines (0 < line < n/2).
    n : int
        The period in samples.
    orders : tuple of int
        The orders wanted (subset of (2, 3)).

    Returns
    -------
    dict
        ``{order: [Combination, ...]}`` sorted by line; empty lists when more than
        :data:`MAX_COMBINED_LINES` lines are excited (a dense grid isolates nothing).
    """
    out: dict[int, list[Combination]] = {m: [] for m in orders}
    if len(lines) > MAX_COMBINED_LINES:
        return out
    signed = sorted({*lines, *(-k for k in lines)})
    reach: Counter[int] = Counter(_folded(k, n) for k in lines)
    found: dict[int, tuple[int, tuple[int, ...]]] = {}
    for m in (2, 3):
        for combo in _multisets(signed, m):
            s = sum(combo)
            line = _folded(s, n)
            reach[line] += 1
            if s < n / 2 and m in orders:
                found[line] = (m, combo)
    for line, (m, combo) in sorted(found.items()):
        if reach[line] == 1 and line != 0:
            count = math.factorial(m) // math.prod(math.factorial(c)
                                                   for c in Counter(combo).values())
            out[m].append(Combination(line=line, factors=combo, count=count))
    return out


def _isolating_lines(max_line: int, n: int) -> list[int]:
    """Odd lines, greedily from 1, each kept when the combinations of one to three lines
    it takes part in fall on new lines, each on its own, below the Nyquist line (at most
    :data:`MAX_COMBINED_LINES` lines)."""
    chosen: list[int] = []
    used = np.zeros(n // 2 + 1, dtype=bool)  # lines reached so far (below n / 2)
    signed = np.zeros(0, dtype=np.int64)  # +-chosen
    pairs = np.zeros(0, dtype=np.int64)  # sums of two of them, no x + (-x)
    for c in range(1, max_line + 1, 2):
        if 3 * c >= n / 2:
            break
        if used[c]:
            continue
        new = np.abs(np.concatenate([[c, 2 * c, 3 * c], c + signed, 2 * c + signed,
                                     c + pairs]))
        new = new[new != 0]
        if new.max() >= n / 2 or np.any(used[new]) or np.unique(new).size < new.size:
            continue
        chosen.append(c)
        used[new] = True
        signed = np.array(chosen + [-k for k in chosen], dtype=np.int64)
        i, j = np.triu_indices(signed.size)
        keep = signed[i] != -signed[j]
        pairs = signed[i][keep] + signed[j][keep]
        if len(chosen) == MAX_COMBINED_LINES:
            break
    return chosen


@dataclass(frozen=True, kw_only=True, repr=False)
class Multisine(Result):
    """A multisine excitation: its grid and its samples.

    ``to_dict`` is the grid (what ``gfrf estimate`` needs: period, sample time, lines),
    the lines' angular frequencies and those that isolate H2 and H3 as
    ``[output, [inputs]]`` in rad/s; it leaves out ``u`` (the sampled input: the data
    file's).

    Attributes
    ----------
    period : int
        Samples per period N.
    sample_time : float
        Sample time T in s.
    lines : tuple of int
        The excited lines k (angular frequency ``k * 2 pi / (N T)``).
    grid : str
        ``"random-odd"`` or ``"isolating"``.
    realisations, periods : int
        Phase realisations (of each level), and periods of each.
    rms : float
        RMS value of u (at level 1).
    levels : tuple of float
        Input levels relative to ``rms``; realisation ``r`` has level
        ``levels[r // realisations]``.
    seed : int
        Seed of the phases (and of the left-out lines).
    u : numpy.ndarray
        Samples, shape (realisations * len(levels), periods * period).
    """

    period: int
    sample_time: float
    lines: tuple[int, ...]
    grid: str
    realisations: int
    periods: int
    rms: float
    levels: tuple[float, ...]
    seed: int
    u: np.ndarray

    _exclude = ("u",)
    _order = ("period", "sample_time", "grid", "realisations", "periods", "rms", "levels",
              "seed", "lines")

    @property
    def omega(self) -> np.ndarray:
        """Angular frequencies of the excited lines (rad/s)."""
        return np.asarray(self.lines, dtype=float) * 2 * math.pi / (self.period * self.sample_time)

    def isolated(self) -> dict[int, list[Combination]]:
        """The lines that isolate H2 and H3 values (:func:`combination_lines`)."""
        return combination_lines(self.lines, self.period)

    def csv_text(self) -> str:
        """The excitation as CSV: columns ``t,u,realisation`` (t restarts per realisation)."""
        t = np.arange(self.u.shape[1]) * self.sample_time
        rows = ["t,u,realisation"]
        for r, row in enumerate(self.u):
            rows += [f"{a:.10g},{b:.10g},{r}" for a, b in zip(t, row, strict=True)]
        return "\n".join(rows) + "\n"

    def _computed(self) -> dict[str, Any]:
        """The lines' angular frequencies and those isolating H2 and H3 (rad/s)."""
        iso = self.isolated()
        w0 = 2 * math.pi / (self.period * self.sample_time)
        return {"omega": self.omega.tolist(),
                "h2_lines": [[c.line * w0, [f * w0 for f in c.factors]] for c in iso[2]],
                "h3_lines": [[c.line * w0, [f * w0 for f in c.factors]] for c in iso[3]]}

    def __repr__(self) -> str:
        return short_repr(self, "period", "sample_time", "grid", "realisations", "periods",
                          lines=len(self.lines))

    def _repr_markdown_(self) -> str:
        iso = self.isolated()
        return markdown_table(("period N", "T (s)", "grid", "excited lines", "realisations",
                               "periods", "H2 lines", "H3 lines"),
                              [(self.period, self.sample_time, self.grid, len(self.lines),
                                self.realisations, self.periods, len(iso[2]), len(iso[3]))])

    def plot(self, ax: Any = None) -> Any:
        """Amplitude spectrum of the first period (dB) against rad/s, excited lines marked.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw on; None makes a new figure.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.
        """
        from gfrf._results import new_figure

        if ax is None:
            figure, axes = new_figure(1, 1, (7.0, 3.5))
            ax = axes[0][0]
        figure = ax.figure
        spectrum = np.fft.rfft(self.u[0, :self.period]) / self.period
        w = np.arange(spectrum.size) * 2 * math.pi / (self.period * self.sample_time)
        level = 20 * np.log10(np.maximum(np.abs(spectrum), 1e-300))
        others = np.ones(w.size, dtype=bool)
        others[list(self.lines)] = False
        ax.plot(w[others], np.maximum(level[others], level.max() - 100), ".", color="0.6",
                markersize=2, label="other lines (drawn 100 dB below the top when lower)")
        ax.plot(self.omega, level[list(self.lines)], "o", label="excited lines")
        ax.set(xlabel="ω (rad/s)", ylabel="|U| (dB)", title=f"{self.grid} multisine")
        ax.legend(fontsize="small")
        return figure


def _check_positive_int(name: str, value: Any, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
            or not 1 <= value <= high:
        raise ArgumentError(f"{name} must be an integer from 1 to {high}, got {value!r}")
    return int(value)


def multisine(period: int, sample_time: float, *, grid: str = "random-odd",
              max_line: int | None = None, realisations: int = 4, periods: int = 3,
              rms: float = 1.0, levels: tuple[float, ...] = (1.0,), seed: int = 0
              ) -> Multisine:
    """Design an odd random-phase multisine and draw its realisations.

    Parameters
    ----------
    period : int
        Samples per period N (16 to :data:`MAX_PERIOD`).
    sample_time : float
        Sample time T in s (in :data:`SAMPLE_TIME_LIMITS`).
    grid : {"random-odd", "isolating"}
        The frequency grid (see the module's text).
    max_line : int, optional
        Highest excited line; default ``N // 8`` (random-odd) or ``N // 6 - 1``
        (isolating: three times it stays below the Nyquist line).
    realisations : int
        Phase realisations M (at each level).
    periods : int
        Periods P of each realisation (the first is often skipped as transient).
    rms : float
        RMS value of u (in :data:`RMS_LIMITS`).
    levels : tuple of float
        Input levels relative to ``rms`` (each in [:data:`MIN_LEVEL`, 1], distinct): with
        two or more, :func:`gfrf.identify.nonparametric.estimate_gfrf` extrapolates its
        estimates to zero amplitude.
    seed : int
        Seed of the phases, 0 to 2**63 - 1: the same arguments give the same samples.

    Returns
    -------
    Multisine

    Raises
    ------
    ArgumentError
        A value out of range, more than :data:`MAX_SIGNAL` samples, or a grid with
        no line to excite.
    """
    n = _check_positive_int("period", period, MAX_PERIOD)
    if n < 16:
        raise ArgumentError(f"period must be at least 16 samples, got {n}")
    if isinstance(sample_time, bool) or not isinstance(sample_time, (int, float)) \
            or not SAMPLE_TIME_LIMITS[0] <= sample_time <= SAMPLE_TIME_LIMITS[1]:
        raise ArgumentError(f"sample_time must be a number of seconds in "
                            f"[{SAMPLE_TIME_LIMITS[0]:g}, {SAMPLE_TIME_LIMITS[1]:g}] "
                            f"(SAMPLE_TIME_LIMITS), got {sample_time!r}")
    if grid not in GRIDS:
        raise ArgumentError(f"grid must be one of {', '.join(GRIDS)}, got {grid!r}")
    m = _check_positive_int("realisations", realisations, 1000)
    p = _check_positive_int("periods", periods, 1000)
    try:
        scale = tuple(float(v) for v in levels)
    except (TypeError, ValueError):
        raise ArgumentError(f"levels must be numbers in (0, 1], got {levels!r}") from None
    if not scale or len(scale) > 5 or not all(MIN_LEVEL <= v <= 1 for v in scale) \
            or len(set(scale)) != len(scale):
        raise ArgumentError(f"levels must be one to five distinct numbers in [MIN_LEVEL = "
                            f"{MIN_LEVEL:g}, 1], got {levels!r}")
    total = m * len(scale) * p * n
    if total > MAX_SIGNAL:
        raise ArgumentError(f"{m * len(scale)} realisations x {p} periods x {n} samples = "
                            f"{total} samples, above the limit {MAX_SIGNAL}")
    if isinstance(rms, bool) or not isinstance(rms, (int, float)) \
            or not RMS_LIMITS[0] <= rms <= RMS_LIMITS[1]:
        raise ArgumentError(f"rms must be a number in [{RMS_LIMITS[0]:g}, {RMS_LIMITS[1]:g}] "
                            f"(RMS_LIMITS), got {rms!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63:
        raise ArgumentError(f"seed must be an integer from 0 to 2**63 - 1, got {seed!r}")
    default = n // 8 if grid == "random-odd" else n // 6 - 1
    top = _check_positive_int("max_line", default if max_line is None else max_line,
                              n // 2 - 1)
    rng = np.random.default_rng(seed)
    if grid == "random-odd":
        odd = np.arange(1, top + 1, 2)
        keep = np.ones(odd.size, dtype=bool)
        for start in range(0, odd.size - 2, 3):
            keep[start + rng.integers(3)] = False
        lines = [int(k) for k in odd[keep]]
    else:
        lines = _isolating_lines(top, n)
    if not lines:
        raise ArgumentError(f"max_line {top}: no line to excite")
    amplitude = rms / math.sqrt(2 * len(lines))
    u = np.empty((m * len(scale), p * n))
    for r in range(u.shape[0]):
        spectrum = np.zeros(n // 2 + 1, dtype=complex)
        spectrum[lines] = amplitude * scale[r // m] * np.exp(2j * math.pi
                                                             * rng.random(len(lines)))
        one = np.fft.irfft(spectrum * n, n)
        u[r] = np.tile(one, p)
    return Multisine(period=n, sample_time=float(sample_time), lines=tuple(lines), grid=grid,
                     realisations=m, periods=p, rms=float(rms), levels=scale, seed=int(seed),
                     u=u)
