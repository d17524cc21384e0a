"""Stability maps of a parameter sweep (matplotlib, Agg backend).

One swept parameter: the certified radius r* (log scale) against the parameter, each
point coloured by its class, the amplitude r as a dashed line (the verdict is
``stable`` where r* lies above it), and the parameter ranges where the linear part is
unstable shaded.  Two swept parameters: the plane coloured by class, with contours of
log10 r*.  Classes: Theorem 1/2 proves stability; not proven (inconclusive); linear
part unstable; the point failed (its error column says why).  ``norm`` sweeps plot ||H1|| and the
majorants; ``bounded`` sweeps colour points by bounded / blown-up simulations.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from gfrf._atomic import atomic_write_figure
from gfrf.errors import ArgumentError
from gfrf.model.safetext import plot_text
from gfrf.sweep.run import SweepResult

__all__ = ["plot_stability_map", "point_class", "map_title", "CLASSES"]

#: Class label and colour of each point kind, in legend order.
CLASSES = {
    "stable": ("stability proven (Theorem {theorem})", "#2b8a3e"),
    "inconclusive": ("not proven", "#f2c94c"),
    "linear unstable": ("linear part unstable", "#c92a2a"),
    "bounded": ("simulation bounded", "#2b8a3e"),
    "blowup": ("simulation blew up", "#c92a2a"),
    "error": ("failed (see the error column)", "#868e96"),
}


def point_class(row: dict) -> str:
    """The map class of one table row.

    Parameters
    ----------
    row : dict
        One row of :attr:`SweepResult.rows`.

    Returns
    -------
    str
        A key of :data:`CLASSES`.
    """
    if row["error"]:
        return "error"
    if "bounded" in row:
        return "bounded" if row["bounded"] else "blowup"
    if not row["linear_stable"]:
        return "linear unstable"
    return row.get("verdict", "inconclusive") if row.get("verdict") != "unstable" \
        else "linear unstable"


def _label(kind: str, result: SweepResult) -> str:
    theorem = next((r["theorem"] for r in result.rows if "theorem" in r), "1/2")
    return CLASSES[kind][0].format(theorem=theorem)


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def map_title(result: SweepResult, title: str = "") -> str:
    """Title of the map: ``title`` without the file values of the swept parameters.

    A model name such as ``"Hanging pendulum, rho = 0.8"`` states the file value of
    ``rho``; on a map sweeping ``rho`` that value is not fixed, so each
    ``NAME = NUMBER`` of a swept parameter is removed (with a leading comma) and a
    second line states the swept range of every axis.

    Parameters
    ----------
    result : SweepResult
        The sweep.
    title : str, optional
        The title asked for (user text, made safe for matplotlib); empty: the command.

    Returns
    -------
    str
        Two lines.
    """
    base = plot_text(title, limit=80) if title else f"gfrf sweep --what {result.what}"
    for axis in result.axes:
        base = re.sub(rf"(?:,\s*)?(?<![\w.]){re.escape(axis.name)}\s*=\s*{_NUMBER}", "",
                      base)
    base = re.sub(r"\s{2,}", " ", base).strip(" ,")
    swept = "; ".join(f"{a.name} from {a.values[0]:g} to {a.values[-1]:g} "
                      f"({len(a.values)} values)" for a in result.axes)
    return f"{base}\nswept: {swept}"


def plot_stability_map(result: SweepResult, path: str | Path, title: str = "") -> Path:
    """Write the stability map of ``result`` to ``path`` (PNG, PDF, SVG by suffix).

    The title is :func:`map_title` of ``title``: the file values of swept parameters
    are dropped from it and the swept ranges are stated.

    Parameters
    ----------
    result : SweepResult
        The sweep, with one or two swept parameters.
    path : str or Path
        The figure file; its suffix chooses the format.
    title : str, optional
        The title asked for; empty: the command.

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    ArgumentError
        More than two swept parameters (a map is one- or two-dimensional).
    """
    if len(result.axes) > 2:
        raise ArgumentError(f"--plot draws one or two swept parameters, got "
                            f"{len(result.axes)}: sweep fewer or drop --plot")
    from gfrf._results import subplots

    fig, ax = subplots(figsize=(6.4, 4.8))
    if len(result.axes) == 1:
        _one(ax, result)
    else:
        _two(ax, result)
    ax.set_title(map_title(result, title), fontsize=10, parse_math=False)
    fig.tight_layout()
    out = Path(path)
    atomic_write_figure(fig, out, dpi=120)
    return out


def _one(ax: object, result: SweepResult) -> None:
    name = result.axes[0].name
    x = np.array([r[name] for r in result.rows])
    kinds = [point_class(r) for r in result.rows]
    if result.what == "norm":
        ax.semilogy(x, [r["h1"] for r in result.rows], "k.-", label="||H1||")
        for column in [c for c in result.columns if c.startswith("M")]:
            values = np.array([r[column] for r in result.rows], dtype=float)
            if np.any(values > 0):
                ax.semilogy(x, values, ".-", label=f"majorant of ||H{column[1:]}||")
        ax.set_ylabel("norm bound")
    else:
        key = "peak" if result.what == "bounded" else "radius"
        y = np.array([r.get(key) or np.nan for r in result.rows], dtype=float)
        positive = y[y > 0]
        floor = positive.min() / 10 if positive.size else result.amplitude / 100
        if np.any(~(y > 0)):  # r* = 0 (or no value) cannot sit on a log axis
            ax.axhline(floor, color="0.6", lw=0.8, ls=":")
            ax.annotate(f"{key} = 0 or undefined", (x.min(), floor), fontsize=7,
                        xytext=(2, 3), textcoords="offset points")
        y = np.where(y > 0, y, floor)
        ax.semilogy(x, y, "-", color="0.6", lw=1)
        for kind in dict.fromkeys(kinds):
            mask = np.array([k == kind for k in kinds])
            ax.semilogy(x[mask], y[mask], "o", color=CLASSES[kind][1],
                        label=_label(kind, result))
        if result.what != "bounded":
            ax.axhline(result.amplitude, ls="--", color="k", lw=1,
                       label=f"amplitude r = {result.amplitude:g}")
            unstable = any(r.get("linear_stable") is False for r in result.rows)
            ax.set_ylabel("series radius r* (no stability radius where the linear part is "
                          "unstable)" if unstable else "certified radius r*", fontsize=8)
        else:
            ax.set_ylabel("peak |y|")
        for xi, kind in zip(x, kinds, strict=True):
            if kind == "linear unstable":
                step = np.diff(x).min() / 2 if x.size > 1 else 0.5
                ax.axvspan(xi - step, xi + step, color=CLASSES[kind][1], alpha=0.12, lw=0)
    ax.set_xlabel(name)
    ax.legend(fontsize=8)


def _two(ax: object, result: SweepResult) -> None:
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    (a, b) = result.axes
    kinds = [point_class(r) for r in result.rows]
    present = list(dict.fromkeys(k for k in CLASSES if k in kinds))
    index = np.array([present.index(k) for k in kinds]).reshape(len(a.values), len(b.values))
    cmap = ListedColormap([CLASSES[k][1] for k in present])
    ax.pcolormesh(b.values, a.values, index, cmap=cmap, vmin=-0.5,
                  vmax=len(present) - 0.5, shading="nearest")
    if result.what in ("verdict", "radius") and min(len(a.values), len(b.values)) > 1:
        radius = np.array([r.get("radius") or np.nan for r in result.rows], dtype=float)
        with np.errstate(divide="ignore"):
            level = np.log10(np.where(radius > 0, radius, np.nan)).reshape(index.shape)
        if np.isfinite(level).sum() > 3:
            contours = ax.contour(b.values, a.values, level, colors="k", linewidths=0.7)
            ax.clabel(contours, fmt="log10 r* = %.1f", fontsize=7)
    ax.set_xlabel(b.name)
    ax.set_ylabel(a.name)
    ax.legend(handles=[Patch(color=CLASSES[k][1], label=_label(k, result)) for k in present],
              fontsize=8, loc="best")
