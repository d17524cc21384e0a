"""The best linear approximation (BLA) from periodic data, with its noise and distortion levels.

The robust method of Pintelon and Schoukens: each realisation m (a random-phase
multisine) measured over P periods gives ``G_m = mean_p Y / mean_p U`` on the excited
lines, with a noise variance from the period-to-period variation of
``Y - G_m U``; the BLA is the mean of the ``G_m``; the variance of that mean is
estimated twice, from the realisation-to-realisation spread (noise plus the stochastic
nonlinear distortion, which changes with the phases) and from the periods (noise
only); their difference is the distortion's share.

``bla_std`` and ``noise_std`` are standard deviations of the BLA *estimate* (the mean
over M realisations): total and noise.  ``distortion_std`` is the standard deviation of
the stochastic nonlinear distortion ``G_S`` of *one* realisation's FRF (the level of the
distortion the system makes at this input, whatever M), ``var G_S = M (bla_std**2 -
noise_std**2)`` as in Pintelon and Schoukens' robust method, so
``bla_std**2 = noise_std**2 + distortion_std**2 / M``; where the realisation spread (an
estimate with ``2 (M - 1)`` degrees of freedom) is below the noise, the distortion is 0
and ``bla_std`` the noise level.  With one realisation the distortion is taken from the
non-excited lines next to each excited line (the fast method); with one period the
noise is not separated (None).

The excited lines are those where the input is significantly non-zero: in every
realisation above 1e-3 of the largest line and, with two periods or more, 10 times
above the input's own period-to-period spread.  The detection lines are the
non-excited lines below the Nyquist line, even and odd.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf._results import Result, markdown_table, new_figure, short_repr
from gfrf.errors import ArgumentError

__all__ = ["BLA", "best_linear_approximation", "excited_lines", "significant_lines",
           "RELATIVE_FLOOR"]

#: An excited line's input amplitude exceeds this fraction of the largest line's.
RELATIVE_FLOOR = 1e-3
#: ... and its power exceeds this multiple of its period-to-period variance.
SNR_FLOOR = 100.0
#: Distortion is detected only above this fraction of the excited lines' output power
#: (-100 dB: rounding errors of noise-free data are not distortion).
ROUNDOFF = 1e-10


def _between(x: np.ndarray) -> np.ndarray:
    """Variance of the mean over axis 1 (periods): sum |x - mean|^2 / (P (P - 1))."""
    p = x.shape[1]
    return np.sum(np.abs(x - x.mean(axis=1, keepdims=True)) ** 2, axis=1) / (p * (p - 1))


def excited_lines(u_spectra: np.ndarray, period: int) -> np.ndarray:
    """Indices of the lines (1 .. below N/2) where the input is significantly non-zero.

    Parameters
    ----------
    u_spectra : numpy.ndarray
        Input DFT lines, shape (realisations, periods, N // 2 + 1).
    period : int
        N (for even N the Nyquist line, a real coefficient, is never used).

    Returns
    -------
    numpy.ndarray
        Line indices in increasing order.
    """
    return np.flatnonzero(np.all(significant_lines(u_spectra, period), axis=0))


def significant_lines(u_spectra: np.ndarray, period: int) -> np.ndarray:
    """Where the input is significantly non-zero, realisation by realisation.

    Parameters
    ----------
    u_spectra : numpy.ndarray
        Input DFT lines, shape (realisations, periods, N // 2 + 1).
    period : int
        N.

    Returns
    -------
    numpy.ndarray
        Booleans, shape (realisations, N // 2 + 1): above :data:`RELATIVE_FLOOR` of the
        realisation's largest line and (two periods or more) :data:`SNR_FLOOR` times the
        line's period-to-period variance; DC and the Nyquist line never.
    """
    power = np.abs(u_spectra.mean(axis=1)) ** 2
    power[:, 0] = 0.0
    if period % 2 == 0:
        power[:, -1] = 0.0
    significant = power > RELATIVE_FLOOR ** 2 * np.max(power, axis=1, keepdims=True)
    if u_spectra.shape[1] >= 2:
        significant &= power > SNR_FLOOR * _between(u_spectra)
    return significant


@dataclass(frozen=True, kw_only=True, repr=False)
class BLA(Result):
    """The best linear approximation on the excited lines, and the detection levels.

    ``to_dict`` is the contract (omega, bla as ``[re, im]`` pairs, the three standard
    deviations) and the rest, ``partial`` as ``partial_lines``; it leaves out
    ``output_level`` and ``output_noise`` (the output spectrum and its noise on every
    line: the plot's data).

    Attributes
    ----------
    omega : numpy.ndarray
        Excited lines' angular frequencies (rad/s).
    lines : numpy.ndarray
        Excited line indices k (omega = k w0, w0 = 2 pi / (N T)).
    bla : numpy.ndarray
        The BLA (complex).
    bla_std, noise_std : numpy.ndarray or None
        Standard deviations of the BLA estimate: total, and its noise share (None
        where the data cannot separate them).
    distortion_std : numpy.ndarray or None
        Standard deviation of the stochastic nonlinear distortion of one realisation's
        FRF (its share in ``bla_std`` is ``distortion_std / sqrt(M)``).
    realisations, periods, period : int
        M, P (after skipping) and N.
    sample_time : float
        T in s.
    partial : numpy.ndarray
        Lines excited in some realisations only (a grid drawn anew per realisation):
        neither in the BLA nor detection lines.
    output_level, output_noise : numpy.ndarray
        RMS over realisations of the period-averaged output on every line 0..N/2, and
        the noise standard deviation of that average (None with one period).
    detection : dict
        Mean output power over noise power on the even and odd non-excited lines
        (``even_ratio``, ``odd_ratio``; None without such lines or noise estimate),
        and whether each exceeds the noise by 4 standard deviations of that mean and
        :data:`ROUNDOFF` times the output power on the excited lines.
    """

    omega: np.ndarray
    lines: np.ndarray
    bla: np.ndarray
    bla_std: np.ndarray | None
    noise_std: np.ndarray | None
    distortion_std: np.ndarray | None
    realisations: int
    periods: int
    period: int
    sample_time: float
    partial: np.ndarray
    output_level: np.ndarray
    output_noise: np.ndarray | None
    detection: dict[str, Any]

    _exclude = ("output_level", "output_noise")
    _keys = {"partial": "partial_lines"}
    _order = ("omega", "bla", "bla_std", "noise_std", "distortion_std", "lines",
              "partial_lines")

    def _computed(self) -> dict[str, Any]:
        """The BLA as ``[re, im]`` pairs, the line indices as ints."""
        return {"bla": [[float(v.real), float(v.imag)] for v in self.bla],
                "lines": [int(k) for k in self.lines],
                "partial_lines": [int(k) for k in self.partial]}

    def __repr__(self) -> str:
        return short_repr(self, "realisations", "periods", "period", lines=len(self.lines))

    def _repr_markdown_(self) -> str:
        def db(a: np.ndarray | None, i: int) -> float | None:
            return None if a is None else float(20 * np.log10(max(a[i], 1e-300)))

        rows = [(float(self.omega[i]), float(20 * np.log10(abs(self.bla[i]))),
                 float(np.angle(self.bla[i])), db(self.bla_std, i), db(self.noise_std, i),
                 db(self.distortion_std, i)) for i in range(min(len(self.lines), 20))]
        return markdown_table(("ω (rad/s)", "|BLA| (dB)", "phase (rad)", "total std (dB)",
                               "noise std (dB)", "distortion std, one realisation (dB)"), rows)

    def plot(self, ax: Any = None) -> Any:
        """The BLA (dB) with its total, noise and distortion standard deviations against
        rad/s, and (when ``ax`` is None) beside it the detection plot: the output on the
        excited, odd and even non-excited lines with the noise level.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw the BLA on (without the detection plot); None makes a new figure
            with both.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.
        """
        if ax is None:
            figure, axes = new_figure(1, 2, (12.0, 4.0))
            self.draw(axes[0][0])
            self.draw_detection(axes[0][1])
            return figure
        self.draw(ax)
        return ax.figure

    def draw(self, ax: Any) -> None:
        """Draw the BLA and its standard deviations (dB against rad/s) on ``ax``.

        Parameters
        ----------
        ax : matplotlib.axes.Axes
            The axes to draw on.
        """
        ax.plot(self.omega, _db(self.bla), "-", color="black", label="BLA")
        for values, style, label in (
                (self.bla_std, {"marker": "o", "markerfacecolor": "none", "color": "#1971c2"},
                 "total std (noise + distortion)"),
                (self.noise_std, {"marker": "x", "color": "#e8590c"}, "noise std"),
                (self.distortion_std, {"marker": "+", "color": "#2b8a3e"},
                 "distortion std (one realisation)")):
            if values is not None:
                ax.plot(self.omega, _db(values), linestyle="none", markersize=5, label=label,
                        **style)
        ax.set(xlabel="ω (rad/s)", ylabel="dB",
               title=f"best linear approximation (M = {self.realisations}, "
                     f"P = {self.periods})")
        ax.legend(fontsize="small", loc="best")

    def draw_detection(self, ax: Any) -> None:
        """Draw the output on the excited, odd and even non-excited lines and the noise
        level (dB against rad/s) on ``ax``.

        Parameters
        ----------
        ax : matplotlib.axes.Axes
            The axes to draw on.
        """
        w0 = 2 * math.pi / (self.period * self.sample_time)
        k = np.arange(1, (self.period + 1) // 2)
        excited = np.isin(k, self.lines)
        free = ~excited & ~np.isin(k, self.partial)
        odd = free & (k % 2 == 1)
        even = free & (k % 2 == 0)
        for mask, style, label in ((excited, "o", "excited lines"),
                                   (odd, "^", "odd non-excited lines"),
                                   (even, "s", "even non-excited lines")):
            if np.any(mask):
                ax.plot(k[mask] * w0, _db(self.output_level[k[mask]]), style, markersize=3,
                        label=label)
        if self.output_noise is not None:
            ax.plot(k * w0, _db(self.output_noise[k]), "-", color="0.5", linewidth=0.8,
                    label="noise level (std of the period mean)")
        ax.set(xlabel="ω (rad/s)", ylabel="|Y| (dB)",
               title="output spectrum: distortion detection")
        ax.legend(fontsize="small", loc="best")


def _db(a: np.ndarray) -> np.ndarray:
    """20 log10 |a|, NaN (not drawn) where a is zero."""
    magnitude = np.abs(a)
    return np.where(magnitude > 0, 20 * np.log10(np.where(magnitude > 0, magnitude, 1.0)),
                    np.nan)


def _fast_distortion(y_mean: np.ndarray, y_var: np.ndarray | None, lines: np.ndarray,
                     u_mean: np.ndarray, n: int, partial: np.ndarray) -> np.ndarray | None:
    """Distortion variance at each excited line from the two nearest non-excited lines on
    each side of the same parity (odd lines for an odd design, any otherwise)."""
    k = np.arange(1, (n + 1) // 2)
    odd_design = bool(np.all(lines % 2 == 1))
    free = k[~np.isin(k, lines) & ~np.isin(k, partial)
             & ((k % 2 == 1) if odd_design else True)]
    if free.size == 0:
        return None
    power = np.abs(y_mean[free]) ** 2 - (0.0 if y_var is None else y_var[free])
    out = np.empty(lines.size)
    for i, line in enumerate(lines):
        near = np.argsort(np.abs(free - line), kind="stable")[:4]
        out[i] = max(float(np.mean(power[near])), 0.0) / abs(u_mean[line]) ** 2
    return out


def best_linear_approximation(u_spectra: np.ndarray, y_spectra: np.ndarray,
                              period: int, sample_time: float,
                              lines: np.ndarray | None = None) -> BLA:
    """The BLA by the robust method (several realisations and periods).

    Parameters
    ----------
    u_spectra, y_spectra : numpy.ndarray
        DFT lines of input and output, shape (realisations M, periods P, N // 2 + 1),
        as :func:`gfrf.identify.measured.spectra` gives them.
    period : int
        N, samples per period.
    sample_time : float
        T in s.
    lines : numpy.ndarray, optional
        The excited lines (default: :func:`excited_lines`).

    Returns
    -------
    BLA

    Raises
    ------
    ArgumentError
        No excited line (the input has no periodic content with this period).
    """
    m, p, _ = u_spectra.shape
    n = period
    significant = significant_lines(u_spectra, n)
    lines = np.flatnonzero(np.all(significant, axis=0)) if lines is None else lines
    partial = np.setdiff1d(np.flatnonzero(np.any(significant, axis=0)), lines)
    if lines.size == 0:
        raise ArgumentError("the input has no significantly excited line at this period")
    u_mean, y_mean = u_spectra.mean(axis=1), y_spectra.mean(axis=1)
    g = y_mean[:, lines] / u_mean[:, lines]
    bla = g.mean(axis=0)
    noise_var = None
    y_var = None
    if p >= 2:
        residual = y_spectra[:, :, lines] - g[:, None, :] * u_spectra[:, :, lines]
        g_var = _between(residual) / np.abs(u_mean[:, lines]) ** 2
        noise_var = g_var.sum(axis=0) / m ** 2
        y_var = _between(y_spectra)
    if m >= 2:
        total = np.sum(np.abs(g - bla) ** 2, axis=0) / (m * (m - 1))
        distortion = None
        if noise_var is not None:
            total = np.maximum(total, noise_var)  # never below the noise variance
            distortion = m * (total - noise_var)
    else:
        fast = _fast_distortion(y_mean[0], None if y_var is None else y_var[0], lines,
                                u_mean[0], n, partial)
        distortion = fast
        total = None if noise_var is None else noise_var + (0.0 if fast is None else fast)
    level = np.sqrt(np.mean(np.abs(y_mean) ** 2, axis=0))
    noise = None if y_var is None else np.sqrt(np.mean(y_var, axis=0))
    w0 = 2 * math.pi / (n * sample_time)
    return BLA(omega=lines * w0, lines=lines, bla=bla,
               bla_std=None if total is None else np.sqrt(total),
               noise_std=None if noise_var is None else np.sqrt(noise_var),
               distortion_std=None if distortion is None else np.sqrt(distortion),
               realisations=m, periods=p, period=n, sample_time=sample_time,
               output_level=level, output_noise=noise,
               partial=partial, detection=_detection(level, y_var, lines, m, n, partial))


def _detection(level: np.ndarray, y_var: np.ndarray | None, lines: np.ndarray, m: int,
               n: int, partial: np.ndarray) -> dict[str, Any]:
    k = np.arange(1, (n + 1) // 2)
    out: dict[str, Any] = {}
    for name, parity in (("even", 0), ("odd", 1)):
        free = k[~np.isin(k, lines) & ~np.isin(k, partial) & (k % 2 == parity)]
        out[f"{name}_lines"] = int(free.size)
        if free.size == 0 or y_var is None:
            out[f"{name}_ratio"], out[f"{name}_detected"] = None, None
            continue
        noise = float(np.mean(np.mean(y_var, axis=0)[free]))
        power = float(np.mean(level[free] ** 2))
        ratio = power / noise if noise > 0 else math.inf
        out[f"{name}_ratio"] = ratio
        out[f"{name}_detected"] = bool(ratio > 1 + 4 / math.sqrt(free.size * m)
                                       and power > ROUNDOFF * float(np.mean(level[lines] ** 2)))
    return out
