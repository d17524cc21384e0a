"""The error grid of ``paper-periodic.md`` and the paper's conclusions tested on it.

:func:`error_grid` compares every method of Zhang, Zhen & Li (2019) with the exact
orbit (Newton shooting) on a grid of ``eps`` and ``x(0)``, one :class:`ErrorGrid` per
branch and side; :func:`conclusion_checks` tests the paper's conclusions 1 and 3 on
those numbers.  Everything is built from :mod:`gfrf.periodic` result objects, so the
report page (:mod:`gfrf.report.periodic`) and the tests read the same objects.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gfrf._results import Result
from gfrf.periodic.compare import PeriodicComparison, compare_periodic
from gfrf.periodic.homotopy import ham
from gfrf.periodic.shooting import transition_delta
from gfrf.report._format import num, table

__all__ = ["TABLE_METHODS", "UPPER_METHODS", "ConclusionCheck", "ErrorGrid",
           "conclusion_checks", "error_grid"]


#: Methods of the comparison table: (label, method, order); orders 2 are the paper's.
TABLE_METHODS: tuple[tuple[str, str, int | None], ...] = (
    ("perturbation, order 2 (paper)", "perturbation", 2),
    ("perturbation, order 4", "perturbation", 4),
    ("homotopy, order 2", "homotopy", 2),
    ("homotopy, order 4", "homotopy", 4),
    ("energy (48)", "energy", None),
    ("averaging (58)", "averaging", None),
)
#: Methods with an upper ``1/4`` curve (orbits with ``x(0) = 0``, amplitude ``x(pi)``).
UPPER_METHODS: tuple[tuple[str, str, int | None], ...] = (
    ("energy (49)", "energy", None),
    ("averaging case 3", "averaging", None),
)


@dataclass(frozen=True, kw_only=True, repr=False)
class ErrorGrid(Result):
    """Errors of every method on a grid of ``eps`` and ``x(0)`` for one branch.

    ``to_dict`` lists the rows, each comparison with its method ``label``; it leaves out
    ``eps_values`` and ``amplitudes`` (each row holds its eps and amplitude).

    Attributes
    ----------
    branch : str
    eps_values, amplitudes : tuple of float
    rows : dict
        ``(label, eps, amplitude) -> PeriodicComparison``.
    side : str
        ``"lower"`` or ``"upper"`` (``1/4`` tongue; amplitudes are then ``x(pi)``).
    """

    branch: str
    eps_values: tuple[float, ...]
    amplitudes: tuple[float, ...]
    rows: dict[tuple[str, float, float], PeriodicComparison]
    side: str = "lower"

    _exclude = ("eps_values", "amplitudes")
    _order = ("branch", "side", "rows")

    def labels(self) -> list[str]:
        """Method labels present in the grid, in table order."""
        return [lab for lab, _, _ in TABLE_METHODS + UPPER_METHODS
                if any(k[0] == lab for k in self.rows)]

    def _computed(self) -> dict[str, object]:
        """The rows, each comparison with its method label."""
        return {"rows": [{"label": k[0], **v.to_dict()} for k, v in self.rows.items()]}


def error_grid(branch: str, eps_values: tuple[float, ...], amplitudes: tuple[float, ...],
               side: str = "lower") -> ErrorGrid:
    """Compare each applicable method at every ``(eps, amplitude)`` of ``branch``/``side``.

    Parameters
    ----------
    branch : str
        The transition branch, ``"0"`` or ``"1/4"``.
    eps_values : tuple of float
        The values of eps.
    amplitudes : tuple of float
        The orbit amplitudes.
    side : str, optional
        ``"lower"`` or ``"upper"``: which transition curve of the branch.

    Returns
    -------
    ErrorGrid
        The errors of every method at every point.
    """
    rows = {}
    for lab, method, order in (TABLE_METHODS if side == "lower" else UPPER_METHODS):
        if branch == "0" and method in ("energy", "averaging"):
            continue
        for e in eps_values:
            for a in amplitudes:
                rows[(lab, e, a)] = compare_periodic(method, e, a, branch, order, side=side)
    return ErrorGrid(branch=branch, eps_values=eps_values, amplitudes=amplitudes, rows=rows,
                     side=side)


@dataclass(frozen=True, kw_only=True)
class ConclusionCheck(Result):
    """One conclusion of the paper tested on our numbers."""

    claim: str
    evidence: str
    holds: bool


def _err(grid: ErrorGrid, label: str, e: float, a: float) -> float:
    return grid.rows[(label, e, a)].max_error


def conclusion_checks(grid: ErrorGrid) -> list[ConclusionCheck]:
    """Test the paper's conclusions 1 and 3 on the 1/4-branch grid (paper orders).

    Parameters
    ----------
    grid : ErrorGrid
        The error grid of the 1/4 branch.

    Returns
    -------
    list of ConclusionCheck
        The checks.
    """
    out = []
    amin, amax = min(grid.amplitudes), max(grid.amplitudes)
    for lab in grid.labels():
        ok = [_err(grid, lab, e, amax) > _err(grid, lab, e, amin) for e in grid.eps_values
              if np.isfinite(_err(grid, lab, e, amax))]
        out.append(ConclusionCheck(
            claim=f"(1) accuracy drops as the initial angle grows: {lab}",
            evidence=f"max|dx| larger at x(0) = {amax} than at {amin} for {sum(ok)} of "
            f"{len(ok)} eps",
            holds=bool(ok) and all(ok)))
    paper = ["perturbation, order 2 (paper)", "homotopy, order 2", "energy (48)",
             "averaging (58)"]
    mid = sorted(grid.amplitudes)[len(grid.amplitudes) // 2]
    small = [e for e in grid.eps_values if e < 0.1]
    for e in small:
        errs = [_err(grid, lab, e, mid) for lab in paper]
        ratio = max(errs) / min(errs)
        out.append(ConclusionCheck(
            claim=f"(3) for eps < 0.1 the four methods are about equally accurate (eps = {e}, "
            f"x(0) = {mid})",
            evidence=", ".join(f"{lab}: {num(v, 3)}" for lab, v in zip(paper, errs, strict=True))
            + f"; largest/smallest = {num(ratio, 3)}", holds=ratio < 10))
    for e in [e for e in grid.eps_values if e > 0.1]:
        p, h_opt, en, av = (_err(grid, lab, e, mid) for lab in paper)
        h_paper = _paper_h_error(e, mid)
        for h, which in ((h_opt, "h minimising the residual"), (h_paper, "h = -1/1000")):
            finite_he = [v for v in (h, en) if np.isfinite(v)]
            holds = bool(finite_he) and max(p, av) < min(finite_he)
            out.append(ConclusionCheck(
                claim=f"(3) for eps > 0.1 perturbation and averaging beat homotopy and energy "
                f"(eps = {e}, x(0) = {mid}, paper orders, homotopy with {which})",
                evidence=f"perturbation {num(p, 3)}, averaging {num(av, 3)}, homotopy {num(h, 3)}, "
                f"energy {num(en, 3) if np.isfinite(en) else 'no orbit ((48) has no root)'}",
                holds=holds))
    return out


def _paper_h_error(eps: float, amplitude: float) -> float:
    """Max orbit error of the order-2 HAM at the paper's h = -1/1000 (1/4 branch)."""
    orbit = transition_delta(eps, amplitude, "1/4")
    t = np.linspace(0, 4 * np.pi, 401)
    approx = ham(eps, amplitude, "1/4", 2, -1 / 1000).solution(t)
    return float(np.max(np.abs(approx - orbit.evaluate(t))))


def _grid_table(grid: ErrorGrid) -> str:
    where = "x(0)" if grid.side == "lower" else "x(pi)"
    head = ["method", "eps"] + [f"{where} = {a}: |d delta| / max|dx|" for a in grid.amplitudes]
    rows = []
    for lab in grid.labels():
        for e in grid.eps_values:
            cells = []
            for a in grid.amplitudes:
                r = grid.rows[(lab, e, a)]
                cells.append("no orbit" if not np.isfinite(r.max_error)
                             else f"{num(r.delta_error, 2)} / {num(r.max_error, 2)}")
            rows.append([lab, e] + cells)
    return table(head, rows)
