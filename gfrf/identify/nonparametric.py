"""Nonparametric GFRF estimates from multisine data: H1 (the BLA), and H2, H3 on isolated lines.

An output line that exactly one combination of excited lines reaches
(:func:`gfrf.identify.multisine.combination_lines`) carries
``Y = c * H_n(w_1, ..., w_n) * X_1 ... X_n`` plus higher-order terms (``c`` the number
of orderings of the combination, ``X_i`` the input lines, conjugated for a negative
frequency), so ``H_n`` there is ``Y / (c X_1 ... X_n)``, estimated per realisation and
averaged, with the same three standard deviations as the BLA
(:mod:`gfrf.identify.bla`): total (realisations), noise (periods), distortion (the
difference: terms of order n + 2 whose phases change between realisations).  The
terms of order n + 2 that keep the phase of ``X_1 ... X_n`` (``H_{n+2}(..., w, -w)``)
are a bias that no standard deviation shows, like the BLA's difference from H1: it
grows with the square of the amplitude, and a smaller amplitude removes it.

:func:`estimate_gfrf` reads the data, estimates the BLA and the kernels, and with a
model compares them with its GFRFs on the same lines.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._results import Result, markdown_table, new_figure, short_repr
from gfrf.identify.bla import BLA, best_linear_approximation, excited_lines, significant_lines
from gfrf.identify.measured import Periodic, read_periodic, spectra
from gfrf.identify.multisine import MAX_COMBINED_LINES, Combination, combination_lines

__all__ = ["KernelLines", "Estimate", "estimate_gfrf", "kernel_lines", "bla_bias", "SIGMAS",
           "ONE_LEVEL_CAVEAT"]

#: An estimate agrees with a model within this many of its standard deviations.
SIGMAS = 3.0


@dataclass(frozen=True, kw_only=True, repr=False)
class KernelLines(Result):
    """Estimates of H_n on the lines that isolate it.

    ``to_dict`` has the BLA's keys (``bla`` holds H_n's estimate as ``[re, im]`` pairs,
    ``bla_std`` its standard deviation) and the frequencies; it leaves out ``order``, the
    key of its entry (``h1``, ``h2``, ``h3``) in the estimate.

    Attributes
    ----------
    order : int
        n (2 or 3).
    omega : numpy.ndarray
        The output lines' angular frequencies (rad/s): the sums of ``frequencies``.
    frequencies : numpy.ndarray
        Shape (lines, n): the signed frequencies (rad/s) at which H_n is estimated.
    value : numpy.ndarray
        The estimates of the symmetric H_n (complex).
    value_std, noise_std, distortion_std : numpy.ndarray or None
        Standard deviations of the estimates, as the BLA's.
    """

    order: int
    omega: np.ndarray
    frequencies: np.ndarray
    value: np.ndarray
    value_std: np.ndarray | None
    noise_std: np.ndarray | None
    distortion_std: np.ndarray | None

    _exclude = ("order",)
    _keys = {"value": "bla", "value_std": "bla_std"}

    def __repr__(self) -> str:
        return short_repr(self, "order", lines=int(self.omega.size))

    def _computed(self) -> dict[str, Any]:
        """The estimates as ``[re, im]`` pairs, the frequencies as floats."""
        return {"frequencies": [[float(w) for w in row] for row in self.frequencies],
                "bla": [[float(v.real), float(v.imag)] for v in self.value]}

    def draw(self, ax: Any, model: np.ndarray | None = None) -> None:
        """|H_n| estimates (dB) with 3-sigma bars against the output line (rad/s); a bar
        reaching below a tenth of its estimate (0 within 3 sigma) is cut at -20 dB.

        Parameters
        ----------
        ax : matplotlib.axes.Axes
            The axes to draw on.
        model : numpy.ndarray, optional
            The model's H_n (complex) on the same lines, marked with crosses.
        """
        level = 20 * np.log10(np.maximum(np.abs(self.value), 1e-300))
        if self.value_std is not None:
            top = 20 * np.log10(np.abs(self.value) + SIGMAS * self.value_std)
            low = 20 * np.log10(np.maximum(np.abs(self.value) - SIGMAS * self.value_std,
                                           0.1 * np.abs(self.value)))
            ax.errorbar(self.omega, level, yerr=[level - low, top - level], fmt="o",
                        markersize=3, label=f"estimate ± {SIGMAS:g}σ")
        else:
            ax.plot(self.omega, level, "o", markersize=3, label="estimate")
        if model is not None:
            ax.plot(self.omega, 20 * np.log10(np.maximum(np.abs(model), 1e-300)), "x",
                    color="#c92a2a", label="model")
        ax.set(xlabel="ω of the output line (rad/s)", ylabel=f"|H{self.order}| (dB)",
               title=f"H{self.order} on the {self.omega.size} lines that isolate it")
        ax.legend(fontsize="small", loc="best")


def kernel_lines(u_spectra: np.ndarray, y_spectra: np.ndarray, combos: list[Combination],
                 order: int, w0: float) -> KernelLines:
    """H_n estimates on the combination lines ``combos``.

    Parameters
    ----------
    u_spectra, y_spectra : numpy.ndarray
        DFT lines, shape (realisations M, periods P, N // 2 + 1).
    combos : list of Combination
        The isolated lines of this order.
    order : int
        n.
    w0 : float
        Line spacing in rad/s.

    Returns
    -------
    KernelLines
    """
    m, p, _ = u_spectra.shape
    count = len(combos)
    factors = np.array([c.factors for c in combos], dtype=int).reshape(count, order)
    counts = np.array([c.count for c in combos], dtype=float)
    out_lines = np.array([c.line for c in combos], dtype=int)
    x = u_spectra[:, :, np.abs(factors)]  # (M, P, lines, n)
    x = np.where(factors < 0, np.conj(x), x)
    x_mean = x.mean(axis=1)
    product_mean = counts * np.prod(x_mean, axis=-1)  # (M, lines)
    y = y_spectra[:, :, out_lines]
    h = y.mean(axis=1) / product_mean
    value = h.mean(axis=0)
    noise_var = None
    if p >= 2:
        residual = y - h[:, None, :] * counts * np.prod(x, axis=-1)
        mean = residual.mean(axis=1, keepdims=True)
        spread = np.sum(np.abs(residual - mean) ** 2, axis=1) / (p * (p - 1))
        noise_var = np.sum(spread / np.abs(product_mean) ** 2, axis=0) / m ** 2
    if m >= 2:
        total = np.sum(np.abs(h - value) ** 2, axis=0) / (m * (m - 1))
        distortion = None
        if noise_var is not None:
            total = np.maximum(total, noise_var)
            distortion = m * (total - noise_var)
    else:
        total, distortion = noise_var, None
    return KernelLines(order=order, omega=out_lines * w0, frequencies=factors * w0,
                       value=value, value_std=None if total is None else np.sqrt(total),
                       noise_std=None if noise_var is None else np.sqrt(noise_var),
                       distortion_std=None if distortion is None else np.sqrt(distortion))


@dataclass(frozen=True, kw_only=True)
class Estimate:
    """Nonparametric estimates from multisine data.

    ``to_dict`` stays written out: the contract puts the BLA's keys at the top level, has
    ``h1``, ``h2``, ``h3`` and ``model`` only where they exist (never null) and names
    ``comparison`` ``model``.

    Attributes
    ----------
    bla : BLA
        The best linear approximation (of the highest input level) and its levels.
    h1 : KernelLines or None
        H1 extrapolated to zero amplitude (None: one input level, where the BLA is the
        estimate of H1, biased by the amplitude-dependent terms).
    h2, h3 : KernelLines or None
        H2 and H3 on the lines the excitation isolates (None: no such line),
        extrapolated to zero amplitude when there are several input levels.
    levels : tuple of float
        The input levels (RMS over the excited lines), lowest first.
    notes : tuple of str
        What reading and estimating did.
    comparison : dict or None
        With a model: its GFRFs on the same lines and how many estimates lie within
        :data:`SIGMAS` standard deviations of them.
    model_values : dict
        The model's H1, H2, H3 on the lines (complex arrays; empty without a model).
    bla_bias : dict
        The BLA's systematic difference from H1 (:func:`bla_bias`): measured with two
        levels or more, a caveat with one.
    """

    bla: BLA
    h1: KernelLines | None
    h2: KernelLines | None
    h3: KernelLines | None
    levels: tuple[float, ...]
    notes: tuple[str, ...]
    comparison: dict[str, Any] | None = None
    model_values: dict[str, np.ndarray] = field(default_factory=dict)
    bla_bias: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """The BLA's fields at the top, ``h2``/``h3`` where isolated, notes, comparison."""
        out = self.bla.to_dict()
        out["levels"] = list(self.levels)
        for name in ("h1", "h2", "h3"):
            kernel = getattr(self, name)
            if kernel is not None:
                out[name] = kernel.to_dict()
        out["notes"] = list(self.notes)
        out["bla_bias"] = self.bla_bias
        if self.comparison is not None:
            out["model"] = self.comparison
        return out

    def __repr__(self) -> str:
        return short_repr(self, h1_lines=len(self.bla.lines),
                          h2_lines=0 if self.h2 is None else self.h2.omega.size,
                          h3_lines=0 if self.h3 is None else self.h3.omega.size)

    def _repr_markdown_(self) -> str:
        rows = [("H1 (BLA)", len(self.bla.lines)),
                ("H2", 0 if self.h2 is None else self.h2.omega.size),
                ("H3", 0 if self.h3 is None else self.h3.omega.size)]
        return self.bla._repr_markdown_() + "\n\n" + markdown_table(("kernel", "lines"), rows)

    def plot(self, ax: Any = None) -> Any:
        """The BLA (with the model's H1 when compared) and the detection plot; below them
        |H2| and |H3| on their lines when the excitation isolates any.  With ``ax``: the
        BLA only, on it.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw the BLA on; None makes a new figure with every panel.

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.
        """
        if ax is not None:
            self._draw_bla(ax)
            return ax.figure
        kernels = [k for k in (self.h2, self.h3) if k is not None]
        figure, axes = new_figure(2 if kernels else 1, 2, (12.0, 8.0 if kernels else 4.0))
        self._draw_bla(axes[0][0])
        self.bla.draw_detection(axes[0][1])
        for i, k in enumerate(kernels):
            k.draw(axes[1][i], self.model_values.get(f"h{k.order}"))
        if len(kernels) == 1:
            axes[1][1].set_axis_off()
        return figure

    def _draw_bla(self, ax: Any) -> None:
        self.bla.draw(ax)
        if self.h1 is not None:
            ax.plot(self.h1.omega, 20 * np.log10(np.abs(self.h1.value)), "s", markersize=3,
                    color="#862e9c", label="H1 extrapolated to zero amplitude")
        if "h1" in self.model_values:
            ax.plot(self.bla.omega, 20 * np.log10(np.abs(self.model_values["h1"])), "--",
                    color="#c92a2a", label="model H1")
        ax.legend(fontsize="small", loc="best")


def _agreement(estimate: np.ndarray, std: np.ndarray | None, model: np.ndarray
               ) -> dict[str, Any]:
    error = np.abs(estimate - model)
    out: dict[str, Any] = {"model": [[float(v.real), float(v.imag)] for v in model],
                           "relative_error": [float(e) for e in np.divide(
                               error, np.abs(model), out=np.full(error.size, math.inf),
                               where=np.abs(model) > 0)]}
    if std is not None:
        z = np.divide(error, std, out=np.full(error.size, math.inf), where=std > 0)
        out["sigmas"] = [float(v) for v in z]
        out["within"] = float(np.mean(z <= SIGMAS)) if z.size else None
    return out


def _compare(estimate: Estimate, model: Any, sample_time: float
             ) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    from gfrf.kernels.recursion import kernel

    values = {"h1": np.asarray(kernel(model, 1)(estimate.bla.omega), dtype=complex)}
    h1 = estimate.h1 or _as_lines(estimate.bla)
    out: dict[str, Any] = {"sigmas": SIGMAS,
                           "h1": _agreement(h1.value, h1.value_std, values["h1"])}
    out["h1"]["estimate"] = "h1 (extrapolated)" if estimate.h1 else "bla"
    model_t = getattr(model, "sample_time", None)
    if model_t is not None and abs(float(model_t) - sample_time) > 1e-6 * sample_time:
        out["note"] = (f"the model's sample time {float(model_t):g} s differs from the "
                       f"data's {sample_time:g} s")
    for name in ("h2", "h3"):
        lines = getattr(estimate, name)
        if lines is None:
            continue
        h = kernel(model, lines.order)
        values[name] = np.asarray(h(*lines.frequencies.T), dtype=complex)
        out[name] = _agreement(lines.value, lines.value_std, values[name])
    return out, values


#: Realisations whose input RMS values differ by less than this fraction share a level.
LEVEL_TOLERANCE = 0.02
#: Levels are told apart only when each is at least this factor above the one below.
LEVEL_GAP = 1.2


def _rms(u_spectra: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """RMS over the excited lines of each realisation's period-averaged input."""
    return np.sqrt(2 * np.sum(np.abs(u_spectra.mean(axis=1)[:, lines]) ** 2, axis=1))


def amplitude_levels(u_spectra: np.ndarray, lines: np.ndarray) -> list[np.ndarray]:
    """Realisations grouped by input level (RMS over the excited lines), lowest first.

    Levels are told apart only in a designed experiment: every realisation within
    :data:`LEVEL_TOLERANCE` of its level's lowest, at least two realisations a level,
    and each level :data:`LEVEL_GAP` times the one below.  Anything else (realisations
    scaled to a peak value, say, whose RMS values scatter) is one level.

    Parameters
    ----------
    u_spectra : numpy.ndarray
        Input DFT lines, shape (realisations, periods, N // 2 + 1).
    lines : numpy.ndarray
        The excited lines.

    Returns
    -------
    list of numpy.ndarray
        Realisation indices of each level.
    """
    rms = _rms(u_spectra, lines)
    order = np.argsort(rms, kind="stable")
    groups = [[int(order[0])]]
    for i in order[1:]:
        if rms[i] > (1 + LEVEL_TOLERANCE) * rms[groups[-1][0]]:
            groups.append([])
        groups[-1].append(int(i))
    designed = all(len(g) >= 2 for g in groups) and all(
        rms[b[0]] >= LEVEL_GAP * rms[a[-1]] for a, b in zip(groups, groups[1:], strict=False))
    if not designed:
        return [np.arange(rms.size)]
    return [np.sort(np.array(g)) for g in groups]


def _as_lines(bla: BLA) -> KernelLines:
    return KernelLines(order=1, omega=bla.omega, frequencies=bla.omega[:, None],
                       value=bla.bla, value_std=bla.bla_std, noise_std=bla.noise_std,
                       distortion_std=bla.distortion_std)


def _extrapolate(estimates: list[KernelLines], x: list[float]) -> KernelLines:
    """The value at zero amplitude of the polynomial in ``x`` (squared input level)
    through the levels' estimates (Lagrange weights), with the variances weighted alike."""
    weights = [math.prod(-xj / (xi - xj) for j, xj in enumerate(x) if j != i)
               for i, xi in enumerate(x)]

    def combined(name: str) -> np.ndarray | None:
        parts = [getattr(e, name) for e in estimates]
        if any(p is None for p in parts):
            return None
        return np.sqrt(sum(w ** 2 * p ** 2 for w, p in zip(weights, parts, strict=True)))

    first = estimates[0]
    return KernelLines(order=first.order, omega=first.omega, frequencies=first.frequencies,
                       value=np.sum([w * e.value for w, e in zip(weights, estimates, strict=True)],
                                    axis=0),
                       value_std=combined("value_std"), noise_std=combined("noise_std"),
                       distortion_std=combined("distortion_std"))


def estimate_gfrf(data: str | Path | Periodic, period: int | None = None, *,
                  skip_periods: int = 0, model: Any = None) -> Estimate:
    """Nonparametric H1 (the BLA), H2 and H3 from periodic multisine data.

    With realisations at two or more input levels (:func:`amplitude_levels`,
    ``gfrf.multisine(levels=...)``), each estimate is
    made per level and extrapolated to zero amplitude (a polynomial in the squared
    level through the levels' values): that removes the amplitude-dependent bias
    (H1 + 3 H3(w, w', -w') |U'|^2 + ... for the BLA), at the price of a larger
    standard deviation; the top-level BLA is then the highest level's and ``h1`` is
    the extrapolated H1.

    Parameters
    ----------
    data : str, Path or Periodic
        A CSV file with columns ``t,u,y`` and optionally ``realisation`` (read by
        :func:`gfrf.identify.measured.read_periodic`), or periods already cut.
    period : int, optional
        N, the period in samples (needed with a file).
    skip_periods : int
        Periods dropped at the start of each realisation of a file.
    model : Model or ModelFile, optional
        Compare the estimates with its GFRFs on the same lines (a ModelFile's plant).

    Returns
    -------
    Estimate

    Raises
    ------
    ArgumentError
        Bad data (see :func:`~gfrf.identify.measured.read_periodic`), no excited line.
    """
    from gfrf.errors import ArgumentError

    if isinstance(data, Periodic):
        measured = data
    else:
        if period is None:
            raise ArgumentError("give the period N in samples")
        measured = read_periodic(data, period, skip_periods)
    n, t = measured.period, measured.sample_time
    u_spectra, y_spectra = spectra(measured.u), spectra(measured.y)
    lines = excited_lines(u_spectra, n)
    if lines.size == 0:
        raise ArgumentError("the input has no significantly excited line at this period "
                            f"({n} samples): is --period right?")
    notes = list(measured.notes)
    isolated = combination_lines([int(k) for k in lines], n)
    partial = np.setdiff1d(np.flatnonzero(np.any(significant_lines(u_spectra, n), axis=0)), lines)
    if partial.size:
        notes.append(f"{partial.size} lines are excited in some realisations only: left out "
                     f"of the BLA and of the detection lines; no H2, H3 (their combinations "
                     f"are not known to be isolated)")
        isolated = {2: [], 3: []}
    if lines.size > MAX_COMBINED_LINES:
        notes.append(f"{lines.size} excited lines: H2 and H3 are estimated only from "
                     f"sparse excitations (gfrf multisine --grid isolating)")
    w0 = 2 * math.pi / (n * t)
    groups = amplitude_levels(u_spectra, lines)
    per_level = []
    for g in groups:
        bla = best_linear_approximation(u_spectra[g], y_spectra[g], n, t, lines)
        per_level.append((bla, {m: kernel_lines(u_spectra[g], y_spectra[g], isolated[m], m, w0)
                                if isolated[m] else None for m in (2, 3)}))
    bla, kernels = per_level[-1]
    h1 = None
    rms = _rms(u_spectra, lines)
    levels = [float(np.sqrt(np.mean(rms[g] ** 2))) for g in groups]
    if len(groups) == 1 and rms.max() > (1 + LEVEL_TOLERANCE) * rms.min():
        notes.append(f"the input RMS varies between realisations ({rms.min():.4g} to "
                     f"{rms.max():.4g}) without distinct levels: one level, the BLA of them all")
    if len(groups) >= 2:
        x = [(v / levels[-1]) ** 2 for v in levels]
        h1 = _extrapolate([_as_lines(b) for b, _ in per_level], x)
        kernels = {m: None if kernels[m] is None else
                   _extrapolate([k for _, level in per_level if (k := level[m]) is not None], x)
                   for m in (2, 3)}
        notes.append(f"{len(groups)} input levels (RMS {', '.join(f'{v:.4g}' for v in levels)}): "
                     f"H1, H2, H3 extrapolated to zero amplitude; the BLA is the highest "
                     f"level's")
    bias = bla_bias(bla, h1, len(groups))
    if h1 is None:
        notes.append(bias["note"])
    result = Estimate(bla=bla, h1=h1, h2=kernels[2], h3=kernels[3], levels=tuple(levels),
                      notes=tuple(notes), bla_bias=bias)
    if model is None:
        return result
    comparison, values = _compare(result, getattr(model, "plant", model), t)
    return replace(result, comparison=comparison, model_values=values)


#: Wording of the caveat for a BLA from one input level.
ONE_LEVEL_CAVEAT = ("one input level: the BLA is not H1 but H1 plus the systematic part of "
                    "the nonlinear distortion (3 H3(w, w', -w') |U'|^2 + ..., growing with "
                    "the square of the amplitude), which no standard deviation shows; "
                    "measure at two levels (gfrf multisine --levels 1,0.5) to see it")


def bla_bias(bla: BLA, h1: KernelLines | None, levels: int) -> dict[str, Any]:
    """The BLA's bias: its difference from H1 extrapolated to zero amplitude, per line.

    With one input level the bias cannot be seen in the data (it does not change with the
    phases): the result says so.  With two or more, ``bias`` is ``BLA - H1`` on each
    excited line with its standard deviation ``sqrt(bla_std^2 + h1_std^2)`` (an upper
    value: the two estimates share the highest level's data), ``relative_median`` the
    median of ``|bias| / |H1|`` and ``significant_lines`` the lines where ``|bias|``
    exceeds :data:`SIGMAS` standard deviations.

    Parameters
    ----------
    bla : BLA
        The highest level's best linear approximation.
    h1 : KernelLines or None
        H1 extrapolated to zero amplitude on the same lines (None with one level).
    levels : int
        The number of input levels.

    Returns
    -------
    dict
        ``levels``, ``measured``, ``bias`` (``[re, im]`` pairs or None), ``bias_std``,
        ``relative_median``, ``significant_lines``, ``lines`` and ``note``.
    """
    empty: dict[str, Any] = {"levels": levels, "measured": False, "bias": None,
                             "bias_std": None, "relative_median": None,
                             "significant_lines": None, "lines": int(bla.bla.size)}
    if h1 is None or h1.value.size != bla.bla.size:
        return {**empty, "note": ONE_LEVEL_CAVEAT if levels < 2 else
                "the levels' lines differ: no bias measured"}
    bias = bla.bla - h1.value
    std = None
    significant = None
    if bla.bla_std is not None and h1.value_std is not None:
        std = np.sqrt(np.asarray(bla.bla_std) ** 2 + np.asarray(h1.value_std) ** 2)
        significant = int(np.sum(np.abs(bias) > SIGMAS * std))
    relative = float(np.median(np.abs(bias) / np.maximum(np.abs(h1.value), 1e-300)))
    note = (f"BLA bias from {levels} levels: median |BLA - H1| is {100 * relative:.3g} % of "
            f"|H1|" + ("" if significant is None else
                       f", beyond {SIGMAS:g} standard deviations on {significant} of "
                       f"{bias.size} lines"))
    return {**empty, "measured": True, "bias": [[float(z.real), float(z.imag)] for z in bias],
            "bias_std": None if std is None else [float(v) for v in std],
            "relative_median": relative, "significant_lines": significant, "note": note}
