"""Figures of ``paper-periodic.md``: the paper's figures regenerated, and the chart.

Solid = exact orbit from Newton shooting, dots = analytical.  Each figure writer saves
one PNG next to the page (:mod:`gfrf.report.periodic`) and returns its path with the
rows of the table printed under it; grids are fixed, so the files are identical from
run to run.  The writers are private to the page.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from gfrf._results import subplots
from gfrf.periodic.compare import PeriodicComparison, compare_periodic, transition_curve
from gfrf.periodic.floquet import mathieu_transition, upper_quarter_transition
from gfrf.periodic.homotopy import ham
from gfrf.periodic.perturbation import perturbation_series
from gfrf.periodic.shooting import exact_transition_curve, transition_delta
from gfrf.report._format import save_figure
from gfrf.report.periodic_checks import UPPER_METHODS

__all__: list[str] = []


def _orbit_panel(ax: Axes, t: np.ndarray, x_exact: np.ndarray, x_method: np.ndarray,
                 title: str) -> None:
    ax.plot(t, x_exact, "-", color="k", lw=1.2, label="exact (shooting)")
    step = max(1, len(t) // 60)
    ax.plot(t[::step], x_method[::step], ".", color="C3", ms=4, label="analytical")
    if not np.isfinite(x_method).any():
        ax.text(0.5, 0.5, "method has no orbit", transform=ax.transAxes, ha="center",
                fontsize=8, color="C3")
    ax.set_title(title, fontsize=8)
    ax.tick_params(labelsize=7)
    ax.set_xticks(np.pi * np.arange(5), ["0", "π", "2π", "3π", "4π"])


def _label_orbit_axes(axes: list[list[Axes]]) -> None:
    """Axis labels on the outer panels of a grid of orbit panels (time t = omega t_phys)."""
    for row in axes:
        row[0].set_ylabel("x (rad)", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel("t = ω t_phys", fontsize=8)


def _fig2(out: Path, quick: bool) -> tuple[str, list[list[object]]]:
    """(16) at the paper's a, against the exact orbit through the same x(0)."""
    s = perturbation_series("1/4", 2, "kernel")
    eps_list = (0.1, 0.5) if quick else (0.1, 0.2, 0.5)
    a_list = (0.05, 1.0) if quick else (0.05, 0.5, 1.0)
    fig, axes = subplots(len(eps_list), len(a_list), figsize=(9, 2.2 * len(eps_list)),
                             squeeze=False)
    rows = []
    t = np.linspace(0, 4 * np.pi, 241)
    for i, e in enumerate(eps_list):
        for j, a in enumerate(a_list):
            x_an = s.evaluate(e, a, t)
            orbit = transition_delta(e, float(x_an[0]), "1/4")
            x_ex = orbit.evaluate(t)
            _orbit_panel(axes[i][j], t, x_ex, x_an, f"eps={e}, a={a}, x(0)={x_an[0]:.3g}")
            rows.append([e, a, float(x_an[0]), s.delta_at(e, a), orbit.delta,
                         float(np.max(np.abs(x_an - x_ex)))])
    axes[0][0].legend(fontsize=7)
    _label_orbit_axes(axes)
    fig.tight_layout()
    return save_figure(fig, out / "paper-periodic-fig2.png"), rows


def _transition_figure(out: Path, name: str, branches: tuple[str, ...],
                       amplitudes: tuple[float, ...], methods: tuple[tuple[str, str, int | None],
                                                                     ...],
                       eps: np.ndarray) -> tuple[str, list[list[object]]]:
    fig, ax = subplots(figsize=(7, 4.5))
    rows = []
    for b in branches:
        for a in amplitudes:
            exact = exact_transition_curve(eps, a, b)
            ax.plot(eps, exact, "-", color="k", lw=1)
            for k, (lab, m, order) in enumerate(methods):
                if b == "0" and m in ("energy", "averaging"):
                    continue
                vals = transition_curve(m, eps, a, b, order)
                ax.plot(eps, vals, ".", color=f"C{k}", ms=3,
                        label=lab if (b, a) == (branches[0], amplitudes[0]) else None)
                ok = np.isfinite(vals)
                rows.append([b, a, lab, float(np.max(np.abs(vals[ok] - exact[ok])))
                             if ok.any() else float("nan"), int((~ok).sum())])
    ax.set_xlabel("eps")
    ax.set_ylabel("delta")
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, out / name), rows


def _stability_chart(out: Path, quick: bool) -> str:
    eps = np.linspace(0.0, 0.5, 201)
    fig, ax = subplots(figsize=(9.5, 5))
    d0, d1, du = (mathieu_transition(eps, "0"), mathieu_transition(eps, "1/4"),
                  upper_quarter_transition(eps))
    ax.fill_between(eps, d0, np.minimum(d1, 0.3), where=d1 > d0, color="0.9",
                    label="linearly stable (Mathieu)")
    ax.fill_between(eps, d1, du, color="#f3d9d9", label="1/4 instability tongue")
    for d, lab in ((d0, "exact linear: a_0(2 eps)/4"), (d1, "exact linear: b_1(2 eps)/4"),
                   (du, "exact linear: a_1(2 eps)/4")):
        ax.plot(eps, d, "-", color="k", lw=1.3, label=lab)
    coarse = np.linspace(0.01, 0.5, 8 if quick else 25)
    amp = 0.5
    styles = (("perturbation, order 2", "perturbation", 2, "C0"),
              ("perturbation, order 6", "perturbation", 6, "C1"),
              ("homotopy, order 4", "homotopy", 4, "C2"),
              ("energy (48)", "energy", None, "C3"), ("averaging (58)", "averaging", None, "C4"))
    for b in ("0", "1/4"):
        ax.plot(coarse, exact_transition_curve(coarse, amp, b), "--", color="0.4", lw=1.2,
                label=f"exact nonlinear, x(0) = {amp}" if b == "0" else None)
        for lab, m, order, col in styles:
            if b == "0" and m in ("energy", "averaging"):
                continue
            ax.plot(coarse, transition_curve(m, coarse, amp, b, order), "o", ms=3, color=col,
                    label=f"{lab}, x(0) = {amp}" if b == "1/4" else None)
    ax.plot(coarse, transition_curve("exact", coarse, amp, "1/4", side="upper"), ":",
            color="0.4", lw=1.2, label=f"exact nonlinear upper, x(0) = 0, x(pi) = {amp}")
    for (lab, m, _), col in zip(UPPER_METHODS, ("C3", "C4"), strict=True):
        ax.plot(coarse, transition_curve(m, coarse, amp, "1/4", side="upper"), "s", ms=3,
                mfc="none", color=col, label=f"{lab}, x(pi) = {amp}")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.set_xlabel("eps = A/L")
    ax.set_ylabel("delta = -g/(L omega^2)")
    ax.set_ylim(-0.15, 0.5)
    ax.legend(fontsize=6, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    return save_figure(fig, out / "paper-periodic-stability.png")


def _orbit_figure(out: Path, name: str, method: str, cases: list[list[tuple[float, float]]],
                  order: int | None = None) -> tuple[str, list[PeriodicComparison]]:
    """One panel per (eps, x(0)) on the 1/4 branch, one row of panels per list in ``cases``."""
    from gfrf.periodic.compare import method_orbit

    ncol = max(len(row) for row in cases)
    fig, axes = subplots(len(cases), ncol, figsize=(3 * ncol, 0.4 + 2.4 * len(cases)),
                             squeeze=False)
    rows = []
    t = np.linspace(0, 4 * np.pi, 401)
    for i, row in enumerate(cases):
        for j, (e, a) in enumerate(row):
            r = compare_periodic(method, e, a, "1/4", order)
            rows.append(r)
            x_ex = transition_delta(e, a, "1/4").evaluate(t)
            if np.isfinite(r.max_error):
                _, x_m = method_orbit(method, e, a, "1/4", t, order)
            else:
                x_m = np.full_like(t, np.nan)
            _orbit_panel(axes[i][j], t, x_ex, x_m, f"eps={e}, x(0)={a}, delta={r.delta_exact:.3g}")
    axes[0][0].legend(fontsize=6)
    _label_orbit_axes(axes)
    fig.tight_layout()
    return save_figure(fig, out / name), rows


def _fig10(out: Path, quick: bool) -> tuple[str, list[PeriodicComparison]]:
    from gfrf.periodic.compare import method_orbit

    eps_list = (0.1, 0.3)
    methods = (("perturbation", 2), ("homotopy", 2), ("energy", None), ("averaging", None))
    fig, axes = subplots(len(eps_list), 4, figsize=(11, 2.3 * len(eps_list)),
                             squeeze=False)
    t = np.linspace(0, 4 * np.pi, 401)
    rows = []
    for i, e in enumerate(eps_list):
        x_ex = transition_delta(e, 0.5, "1/4").evaluate(t)
        for j, (m, k) in enumerate(methods):
            r = compare_periodic(m, e, 0.5, "1/4", k)
            rows.append(r)
            x_m = method_orbit(m, e, 0.5, "1/4", t, k)[1] if np.isfinite(r.max_error) \
                else np.full_like(t, np.nan)
            _orbit_panel(axes[i][j], t, x_ex, x_m, f"{m}, eps={e}")
    axes[0][0].legend(fontsize=6)
    _label_orbit_axes(axes)
    fig.tight_layout()
    return save_figure(fig, out / "paper-periodic-fig10.png"), rows


def _ham_h_figure(out: Path) -> tuple[str, list[list[object]]]:
    """h-curves: delta and residual of the order-4 HAM against h (paper: h = -1/1000)."""
    hs = np.linspace(-1.6, -0.001, 60)
    fig, (ax1, ax2) = subplots(1, 2, figsize=(9, 3))
    rows = []
    for e in (0.01, 0.05, 0.08):
        res = [ham(e, 0.5, "1/4", 4, float(h)) for h in hs]
        ax1.plot(hs, [r.delta for r in res], label=f"eps={e}")
        ax2.semilogy(hs, [r.residual for r in res], label=f"eps={e}")
        exact = transition_delta(e, 0.5, "1/4").delta
        paper_h = ham(e, 0.5, "1/4", 4, -1 / 1000)
        best = min(res, key=lambda r: r.residual)
        rows.append([e, exact, paper_h.delta, paper_h.residual, best.h, best.delta,
                     best.residual])
    ax1.set_xlabel("h")
    ax1.set_ylabel("delta (HAM order 4)")
    ax2.set_xlabel("h")
    ax2.set_ylabel("RMS residual")
    ax1.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, out / "paper-periodic-ham-h.png"), rows
