"""Pictures of a kernel H_n: Bode plot of H1, the |H2(jw1, jw2)| map, slices of H_n >= 3.

All angular frequencies are in rad/s (python-control's ``bode_plot`` conventions:
magnitude in dB, phase in degrees).  Figures are made without pyplot
(:func:`gfrf._results.new_figure`), so nothing opens a window and any backend works.

The grid adapts to the resonances: the poles p of the linear part A give the
resonances |Im p| and their half-widths |Re p|; around each one (and around the
frequencies where the sums w1 + w2 or the diagonal n*w reach it) points are packed on
a scale of the half-width (an arctan spacing: half the points within 3 half-widths of
the peak), so a resonance 1e-3 of the plotted range wide is resolved.  The uniform
part of an H2 map has a spacing that divides the main resonance w0, so the ridges
w1 + w2 = +-w0 of A(j(w1 + w2)) pass through grid points.  A discrete (NARX) model is
plotted up to the Nyquist frequency pi/T.

``mark`` is where the sup of |H_n| found by ``gfrf norm`` (``Bound.argmax``) sits; it
is drawn on the figure (a star, with its value in the legend).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from gfrf._results import new_figure
from gfrf.errors import ArgumentError
from gfrf.kernels.poles import linear_poles
from gfrf.model.safetext import plot_text

#: A :class:`gfrf.kernels.recursion.Kernel` (not imported: recursion imports this module).
Kernel = Any

__all__ = ["plot_kernel", "resonances", "frequency_grid", "WHAT", "MAX_AXIS_POINTS"]

#: What a map shows.
WHAT = ("magnitude", "phase")
#: Points of a uniform axis, and per resonance cluster.
_UNIFORM = 401
_CLUSTER = 121
#: Most points on one axis of a plot (an H2 map holds its square: a million values,
#: under 0.5 GB with the temporaries of the evaluation, drawn in a fraction of a second).
#: A finer grid is thinned to this many points with a warning, before any evaluation.
MAX_AXIS_POINTS = 1001


def resonances(kernel: Kernel) -> list[tuple[float, float]]:
    """(w_r, half-width) = (|Im s|, |Re s|) in rad/s of the poles s of the linear part
    (:func:`gfrf.kernels.poles.linear_poles`), one per conjugate pair.

    Parameters
    ----------
    kernel : Kernel
        The kernel; its model's linear part is used.

    Returns
    -------
    list of tuple of float
        One ``(w_r, half-width)`` per pole.
    """
    out = []
    for s in linear_poles(kernel.model):
        if s.imag <= 0 and math.isfinite(s.real):  # one of each conjugate pair
            out.append((float(abs(s.imag)), float(max(abs(s.real), 1e-12))))
    return sorted(out)


def _top(kernel: Kernel, omega_range: float | None) -> float:
    if omega_range is not None:
        if not math.isfinite(omega_range) or omega_range <= 0:
            raise ArgumentError(f"range must be a positive frequency in rad/s, got "
                                f"{omega_range!r}")
        return float(omega_range)
    if kernel.model.is_discrete:
        return math.pi / kernel.model.sample_time
    peaks = [w + 3 * h for w, h in resonances(kernel)] or [1.0]
    return max(2.0 * max(peaks), 1.0) if max(peaks) > 0 else 2.0


def frequency_grid(kernel: Kernel, top: float, centres: Sequence[float] = (),
                   symmetric: bool = True) -> np.ndarray:
    """Sorted grid on [-top, top] (or [0, top]): uniform, plus clusters on the resonances
    and on ``centres`` (rad/s), with the uniform spacing dividing the main resonance
    (when that takes at most twice the uniform points: else the clusters alone resolve
    it).  At most :data:`MAX_AXIS_POINTS` points: a finer grid is thinned evenly (in
    index, so the clusters stay denser than the rest) and a warning says so.

    Parameters
    ----------
    kernel : Kernel
        The kernel.
    top : float
        The end of the range in rad/s, > 0.
    centres : sequence of float, optional
        Further frequencies (rad/s) that get a cluster.
    symmetric : bool, optional
        The grid is on [-top, top]; False: on [0, top].

    Returns
    -------
    numpy.ndarray
        The sorted grid.
    """
    res = resonances(kernel)
    low = -top if symmetric else 0.0
    n = _UNIFORM
    parts = [np.linspace(low, top, n)]
    if res:
        main = max(res, key=lambda wh: wh[0] / wh[1])[0]
        if 0 < main < top:
            step = main / math.ceil(main / ((top - low) / (n - 1)))
            if (top - low) / step <= 2 * n:
                parts.append(np.arange(math.ceil(low / step), math.floor(top / step) + 1)
                             * step)
    u = np.tan(np.linspace(-1.45, 1.45, _CLUSTER))  # arctan spacing, +-8 half-widths
    for w, h in res:
        for c in [w, *centres]:
            for sign in ((1, -1) if symmetric else (1,)):
                parts.append(sign * c + h * u)
    grid = np.unique(np.concatenate(parts))
    grid = grid[(grid >= low) & (grid <= top)]
    if grid.size > MAX_AXIS_POINTS:
        warnings.warn(f"the plot grid is thinned from {grid.size} to MAX_AXIS_POINTS = "
                      f"{MAX_AXIS_POINTS} points per axis (narrow resonances may be drawn "
                      f"coarsely; plot a smaller range to see them)", stacklevel=2)
        keep = np.unique(np.round(np.linspace(0, grid.size - 1, MAX_AXIS_POINTS)).astype(int))
        grid = grid[keep]
    return grid


def _value(h: np.ndarray, what: str) -> tuple[np.ndarray, str]:
    if what == "phase":
        return np.degrees(np.angle(h)), "phase (deg)"
    return np.abs(h), "magnitude"


def plot_kernel(kernel: Kernel, *, omega_range: float | None = None, what: str = "magnitude",
                mark: Sequence[float] | None = None, fixed: Sequence[float] | None = None
                ) -> Any:
    """Figure of H_n: Bode (n = 1), |H2| map (n = 2), diagonal and 2-D slices (n >= 3).

    Parameters
    ----------
    kernel : Kernel
        The kernel to draw.
    omega_range : float, optional
        Largest angular frequency W in rad/s (axes span [-W, W] or, for H1, up to W);
        default from the resonances (the Nyquist frequency for NARX).
    what : {"magnitude", "phase"}
        What the maps and slices show (H1 always shows both, as a Bode plot).
    mark : sequence of float, optional
        Where the sup of |H_n| sits (``Bound.argmax`` of ``gfrf norm``), rad/s.
    fixed : sequence of float, optional
        For n >= 3, the n - 2 frequencies held fixed in the 2-D slice (default: the
        last n - 2 of ``mark``, else the main resonance); stated on the figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if what not in WHAT:
        raise ArgumentError(f"what must be one of {', '.join(WHAT)}, got {what!r}")
    n = kernel.order
    if mark is not None and len(mark) != n:
        raise ArgumentError(f"mark needs {n} frequencies, got {len(mark)}")
    top = _top(kernel, omega_range)
    if kernel.is_zero:
        fig, axes = new_figure(1, 1, (6.0, 2.0))
        axes[0][0].axis("off")
        axes[0][0].text(0.5, 0.5, f"H{n} = 0 identically (no term of the model reaches "
                                  f"order {n})\n{_name(kernel)}", ha="center", va="center",
                        parse_math=False)
        return fig
    if n == 1:
        if omega_range is None and not kernel.model.is_discrete:
            top *= 5  # a Bode plot shows the roll-off beyond the resonances
        return _bode(kernel, top, mark)
    if n == 2:
        fig, axes = new_figure(1, 1, (6.0, 5.0))
        _map(fig, axes[0][0], kernel, top, what, (), mark)
        return fig
    res = resonances(kernel)
    main = max(res, key=lambda wh: wh[0] / wh[1])[0] if res else top / 2
    if fixed is None:
        fixed = tuple(mark[2:]) if mark is not None else (main,) * (n - 2)
    if len(fixed) != n - 2:
        raise ArgumentError(f"fixed needs {n - 2} frequencies, got {len(fixed)}")
    fig, axes = new_figure(1, 2, (11.0, 4.6))
    _diagonal(axes[0][0], kernel, top, what, mark)
    _map(fig, axes[0][1], kernel, top, what, tuple(float(f) for f in fixed), mark)
    return fig


def _bode(kernel: Kernel, top: float, mark: Sequence[float] | None) -> Any:
    res = resonances(kernel)
    bottom = min([w - 3 * h for w, h in res if w - 3 * h > 0] + [top]) / 100
    w = np.unique(np.concatenate([np.geomspace(bottom, top, _UNIFORM),
                                  frequency_grid(kernel, top, symmetric=False)]))
    w = w[w >= bottom]
    h = kernel(w)
    fig, axes = new_figure(2, 1, (6.4, 5.6))
    mag, phase = axes[0][0], axes[1][0]
    with np.errstate(divide="ignore"):
        mag.semilogx(w, 20 * np.log10(np.abs(h)))
    phase.semilogx(w, np.degrees(np.unwrap(np.angle(h))))
    if mark is not None:
        value = abs(complex(kernel(abs(mark[0]))))
        label = f"sup |H1| = {value:.6g} at {abs(mark[0]):.6g} rad/s (norm)"
        if mark[0] != 0:
            mag.plot([abs(mark[0])], [20 * math.log10(value)], "r*", ms=11, label=label)
        else:  # at omega = 0, left of a log axis
            mag.axhline(20 * math.log10(value), color="r", ls="--", lw=1, label=label)
        mag.legend(fontsize=8)
    mag.set_ylabel("magnitude (dB)")
    phase.set_ylabel("phase (deg)")
    phase.set_xlabel("omega (rad/s)")
    mag.set_title(f"H1 of {_name(kernel)}", fontsize=9, parse_math=False)
    for ax in (mag, phase):
        ax.grid(True, which="both", alpha=0.3)
    return fig


def _name(kernel: Kernel) -> str:
    """The model's text as one line of a figure (drawn with ``parse_math=False``)."""
    return plot_text(kernel.model.text or kernel.model.equation(), limit=60)


def _map(fig: Any, ax: Any, kernel: Kernel, top: float, what: str,
         fixed: tuple[float, ...], mark: Sequence[float] | None) -> None:
    from matplotlib.colors import LogNorm
    from matplotlib.image import NonUniformImage

    res = resonances(kernel)
    centres = [w / 2 for w, _ in res] + [0.0]
    if fixed:
        centres += [abs(w - f) for w, _ in res for f in fixed]
    grid = frequency_grid(kernel, top, centres)
    w1, w2 = np.meshgrid(grid, grid, indexing="xy")
    args = [w1, w2] + [np.full_like(w1, f) for f in fixed]
    with np.errstate(all="ignore"):
        values, label = _value(kernel(*args), what)
    if what == "magnitude":
        finite = values[np.isfinite(values) & (values > 0)]
        vmax = float(finite.max()) if finite.size else 1.0
        values = np.clip(values, vmax * 1e-6, None)
        style: dict[str, Any] = {"norm": LogNorm(vmin=vmax * 1e-6, vmax=vmax),
                                 "cmap": "viridis"}
        label = f"|H{kernel.order}| (log scale)"
    else:
        from matplotlib.colors import Normalize

        style = {"cmap": "twilight", "norm": Normalize(vmin=-180, vmax=180)}
    # An image on the non-uniform grid (each value fills the cell of its nearest grid
    # point): drawn several times faster than a mesh of a million quadrilaterals.
    mesh = NonUniformImage(ax, interpolation="nearest", extent=(grid[0], grid[-1],
                                                                 grid[0], grid[-1]), **style)
    mesh.set_data(grid, grid, values)
    ax.add_image(mesh)
    ax.set_xlim(grid[0], grid[-1])
    ax.set_ylim(grid[0], grid[-1])
    fig.colorbar(mesh, ax=ax, label=label)
    if mark is not None and np.allclose(mark[2:], fixed):
        value = abs(complex(kernel(*mark)))
        ax.plot([mark[0]], [mark[1]], "r*", ms=12,
                label=f"sup |H{kernel.order}| = {value:.6g} (norm)")
        ax.legend(fontsize=8, loc="upper left")
    ax.set_xlabel("omega1 (rad/s)")
    ax.set_ylabel("omega2 (rad/s)")
    ax.set_aspect("equal")
    if fixed:
        others = ", ".join(f"omega{i + 3} = {f:.4g}" for i, f in enumerate(fixed))
        ax.set_title(f"H{kernel.order}(j omega1, j omega2, ...)\nwith {others} rad/s fixed",
                     fontsize=9)
    else:
        ax.set_title(f"H2 of {_name(kernel)}", fontsize=9, parse_math=False)


def _diagonal(ax: Any, kernel: Kernel, top: float, what: str,
              mark: Sequence[float] | None) -> None:
    n = kernel.order
    res = resonances(kernel)
    centres = [w / k for w, _ in res for k in range(1, n + 1)]
    w = frequency_grid(kernel, top, centres)
    with np.errstate(all="ignore"):
        values, label = _value(kernel(*([w] * n)), what)
    if what == "magnitude":
        ax.semilogy(w, values)
        if mark is not None:
            value = abs(complex(kernel(*mark)))
            ax.axhline(value, color="r", ls="--", lw=1,
                       label=f"sup |H{n}| = {value:.6g} (norm) at "
                             f"({', '.join(f'{m:.3g}' for m in mark)})")
            ax.legend(fontsize=8)
    else:
        ax.plot(w, values)
    ax.set_xlabel("omega (rad/s)")
    ax.set_ylabel(f"H{n}(j omega, ..., j omega) {label}")
    ax.set_title(f"diagonal slice of H{n}\n{_name(kernel)}", fontsize=9, parse_math=False)
    ax.grid(True, alpha=0.3)
