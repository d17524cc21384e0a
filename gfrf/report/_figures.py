"""Figures of the reports: gain/phase of H1, slices of H3, time responses.

All figures use matplotlib's Agg backend (set in :mod:`gfrf.report._format`) and
evaluate the kernels of :mod:`gfrf.kernels.recursion` on fixed grids, so they are identical
from run to run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from matplotlib.colors import LogNorm

from gfrf._results import subplots
from gfrf.kernels.poles import linear_poles
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model
from gfrf.report._format import save_figure
from gfrf.report.analysis import Response

__all__ = ["frequency_scale", "h1_figure", "h3_slice_figure", "response_figure"]


def frequency_scale(model: Model) -> float:
    """A characteristic angular frequency (rad/s): largest |pole| of H1, or 1.

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    float
        The frequency in rad/s (pi / T for a NARX model).
    """
    if model.is_discrete:
        return math.pi / float(model.sample_time)  # type: ignore[arg-type]
    return float(max(np.abs(linear_poles(model)), default=1.0)) or 1.0


def _phase_deg(h: np.ndarray) -> np.ndarray:
    """Phase in degrees, with -0.0 imaginary parts read as +0.0: a real negative value is
    +180 deg whichever evaluation path (numpy or compiled) produced its signed zero."""
    h = np.asarray(h, dtype=complex)
    return np.degrees(np.arctan2(h.imag + 0.0, h.real))


def h1_figure(model: Model, path: Path, *, hz: bool = False,
              extra: Sequence[tuple[str, Callable[[np.ndarray], np.ndarray]]] = (),
              title: str = "") -> str:
    """Gain (log) and phase (deg) of H1 against frequency; ``extra`` curves dashed.

    Parameters
    ----------
    model : Model
        The plant model.
    path : Path
        The PNG file.
    hz : bool, optional
        Frequency axis in Hz instead of rad/s.
    extra : sequence of (str, callable), optional
        Further curves: a label and a function of the angular frequency (rad/s) giving
        complex values.
    title : str, optional
        The figure's title.

    Returns
    -------
    str
        The file's name.
    """
    scale = frequency_scale(model)
    if model.is_discrete:
        w = np.linspace(1e-3 * scale, scale, 2000)
    else:
        w = np.geomspace(1e-2 * scale, 1e2 * scale, 2000)
    h = kernel(model, 1)(w)
    x = w / (2 * math.pi) if hz else w
    fig, (ax_g, ax_p) = subplots(2, 1, figsize=(6, 5), sharex=True)
    ax_g.loglog(x, np.abs(h), label="H1 (this model)")
    ax_p.semilogx(x, _phase_deg(h))
    for label, f in extra:
        values = f(w)
        ax_g.loglog(x, np.abs(values), "--", label=label)
        ax_p.semilogx(x, _phase_deg(values), "--")
    ax_g.set_ylabel("|H1|")
    ax_p.set_ylabel("phase of H1 (deg)")
    ax_p.set_xlabel("frequency (Hz)" if hz else "angular frequency w (rad/s)")
    ax_p.set_yticks([-180, -90, 0, 90, 180])
    for ax in (ax_g, ax_p):
        ax.grid(True, which="both", alpha=0.3)
    ax_g.legend(fontsize=8)
    ax_g.set_title(title or "First-order GFRF H1(jw)", parse_math=False)
    fig.tight_layout()
    return save_figure(fig, path)


def h3_slice_figure(model: Model, path: Path, w3: float, half_width: float, *,
                    points: int = 301, hz: bool = False, phase: bool = False,
                    title: str = "") -> str:
    """|H3| (log colour) or its phase over (w1, w2) in [-W, W]^2 at fixed w3 (rad/s).

    Parameters
    ----------
    model : Model
        The plant model.
    path : Path
        The PNG file.
    w3 : float
        The fixed third frequency in rad/s.
    half_width : float
        W in rad/s.
    points : int, optional
        Grid points per axis.
    hz : bool, optional
        Axes in Hz instead of rad/s.
    phase : bool, optional
        Draw the phase instead of |H3|.
    title : str, optional
        The figure's title.

    Returns
    -------
    str
        The file's name.
    """
    w = np.linspace(-half_width, half_width, points)
    w1, w2 = np.meshgrid(w, w)
    h = kernel(model, 3)(w1, w2, w3)
    x = w / (2 * math.pi) if hz else w
    unit = "Hz" if hz else "rad/s"
    fig, ax = subplots(figsize=(5.5, 4.5))
    if phase:
        image = ax.pcolormesh(x, x, _phase_deg(h), cmap="twilight", vmin=-180,
                              vmax=180, shading="auto")
        fig.colorbar(image, ax=ax, label="phase of H3 (deg)")
    else:
        mag = np.abs(h)
        positive = mag[mag > 0]
        low = max(float(positive.min()), float(positive.max()) * 1e-6) if positive.size else 1.0
        image = ax.pcolormesh(x, x, np.maximum(mag, low), norm=LogNorm(vmin=low),
                              cmap="viridis", shading="auto")
        fig.colorbar(image, ax=ax, label="|H3|")
    third = w3 / (2 * math.pi) if hz else w3
    ax.set_xlabel(f"{'f1' if hz else 'w1'} ({unit})")
    ax.set_ylabel(f"{'f2' if hz else 'w2'} ({unit})")
    ax.set_title(title or f"{'phase' if phase else '|H3|'} at {'f3' if hz else 'w3'} = "
                 f"{third:.4g} {unit}", parse_math=False)
    fig.tight_layout()
    return save_figure(fig, path)


def response_figure(responses: Sequence[Response], path: Path, title: str,
                    ylabel: str) -> str:
    """Output y(t) of each response; a blow-up is marked where the run stopped.

    Parameters
    ----------
    responses : sequence of Response
        The runs, each with a label and a simulation result.
    path : Path
        The PNG file.
    title : str
        The figure's title.
    ylabel : str
        The label of the y axis.

    Returns
    -------
    str
        The file's name.
    """
    fig, ax = subplots(figsize=(6.5, 3.8))
    for r in responses:
        res = r.result
        line = ax.plot(res.t, res.y, lw=0.9, label=r.label
                       + ("" if res.bounded else f" - blew up at t = {res.blowup_time:.3g} s"))
        if not res.bounded and res.t.size:
            ax.plot(res.t[-1], res.y[-1], "x", color=line[0].get_color(), ms=8)
    ax.set_xlabel("time t (s)")
    ax.set_ylabel(ylabel)
    peak = max((float(np.max(np.abs(r.result.y))) for r in responses if r.result.bounded),
               default=1.0)
    ax.set_ylim(-1.5 * peak, 1.5 * peak)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title, fontsize=9, parse_math=False)
    fig.tight_layout()
    return save_figure(fig, path)
