"""Markdown building blocks shared by the reports: numbers, tables, headers, figures.

Every number that reaches a report goes through :func:`cell`, so a test can render a
result object's value and find exactly that text in the report.  Figures are written
with matplotlib's Agg backend at a fixed dpi without a creation date, so two runs give
byte-identical PNG files.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from decimal import ROUND_CEILING, Decimal
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from gfrf._atomic import atomic_write_figure
from gfrf._results import outward_bracket

__all__ = ["num", "bracket_cells", "cell", "table", "header", "save_figure", "mark", "code",
           "DPI"]

#: Resolution of every report figure (small PNGs that still read well on a code host).
DPI = 100


def num(x: float | None, digits: int = 6) -> str:
    """A float with ``digits`` significant digits; ``inf``, ``-inf``, ``-`` for None.

    Parameters
    ----------
    x : float or None
        The number.
    digits : int, optional
        Significant digits.

    Returns
    -------
    str
        The text.
    """
    if x is None:
        return "-"
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def bracket_cells(lower: float, upper: float, most: int = 6) -> tuple[str, str, str]:
    """(lower, upper, relative gap) of a bracket as printed: rounded outward to the
    digits the bracket proves (:func:`gfrf._results.outward_bracket`), so the text does
    not depend on the last bits of a float.

    A bracket of relative gap g keeps ``2 + ceil(-log10 g)`` significant digits:
    lower rounded down, upper rounded up, the gap that of the printed numbers rounded up
    to two digits.  A bracket closed to rounding (more than ``most`` digits: the proven
    exact-algebra and ball-arithmetic values, deterministic), a point value, zero, a
    negative or an infinite end prints as :func:`num` does.

    Parameters
    ----------
    lower, upper : float
        The ends of the bracket.
    most : int, optional
        Most significant digits printed.

    Returns
    -------
    tuple of str
        The three cells.

    Examples
    --------
    >>> bracket_cells(0.0111398, 0.0209773)
    ('0.0111', '0.021', '0.48')
    """
    rounded = outward_bracket(lower, upper, most)
    if rounded is None:
        gap = 0.0 if upper == lower else (math.inf if math.isinf(upper) else
                                           (upper - lower) / upper if upper else math.nan)
        return num(lower, most), num(upper, most), num(gap, most)
    low, high, digits = rounded
    gap = Decimal((high - low) / high)  # of the printed numbers: deterministic
    gap = gap.quantize(Decimal(1).scaleb(gap.adjusted() - 1), rounding=ROUND_CEILING)
    return num(low, digits), num(high, digits), num(float(gap), 2)


def cell(value: Any) -> str:
    """Render one table cell: numbers via :func:`num`, lists element-wise, text escaped.

    Parameters
    ----------
    value : object
        A bool, None, number, complex, list, tuple, numpy scalar or other value (as str).

    Returns
    -------
    str
        The cell's text.
    """
    if isinstance(value, bool):
        return "yes" if value else "no"
    if value is None:
        return "-"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return num(value)
    if isinstance(value, complex):
        if value.imag == 0:
            return num(value.real)
        sign = "+" if value.imag > 0 else "-"
        return f"{num(value.real)} {sign} {num(abs(value.imag))}j"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(cell(v) for v in value) + "]"
    if hasattr(value, "item"):  # numpy scalar
        return cell(value.item())
    return str(value).replace("|", "\\|").replace("\n", " ")


def mark(passed: bool | None) -> str:
    """pass / FAIL / open for a theorem condition.

    Parameters
    ----------
    passed : bool or None
        The condition's outcome; None: not established.

    Returns
    -------
    str
        ``"pass"``, ``"**FAIL**"`` or ``"open"``.
    """
    return {True: "pass", False: "**FAIL**", None: "open"}[passed]


def code(text: str) -> str:
    """Inline code span (for commands beside numbers).

    Parameters
    ----------
    text : str
        The text, without backticks.

    Returns
    -------
    str
        The text in backticks.
    """
    return f"`{text}`"


def table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A GitHub Markdown table; every header and entry is rendered by :func:`cell`.

    Parameters
    ----------
    headers : sequence
        The column headings.
    rows : sequence of sequence
        The rows.

    Returns
    -------
    str
        The table, with a final newline.
    """
    lines = ["| " + " | ".join(cell(h) for h in headers) + " |", "|" + "---|" * len(headers)]
    for row in rows:
        lines.append("| " + " | ".join(cell(c) for c in row) + " |")
    return "\n".join(lines) + "\n"


def header(title: str, summary: Sequence[str], regenerate: str) -> str:
    """Title, a three-line summary and the command that regenerates the report.

    Parameters
    ----------
    title : str
        The report's title.
    summary : sequence of str
        Exactly three lines.
    regenerate : str
        The command.

    Returns
    -------
    str
        The Markdown text.
    """
    if len(summary) != 3:
        raise ValueError(f"a report summary has three lines, got {len(summary)}")
    lines = [f"# {title}", "", *(f"> {s}  " for s in summary), "",
             f"Regenerate: `{regenerate}` (deterministic: same numbers and figures on every "
             "run). Angular frequencies are in rad/s unless a column says Hz.", ""]
    return "\n".join(lines)


def save_figure(fig: Figure, path: Path) -> str:
    """Write ``fig`` as PNG (Agg, :data:`DPI`, no date metadata), return the name.

    Report figures are made with :func:`gfrf._results.subplots` (no pyplot, so nothing to
    close and no backend switched).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : Path
        The PNG file; its folder is created if missing.

    Returns
    -------
    str
        The file's name.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_figure(fig, path, dpi=DPI, metadata={"Software": None})
    return path.name
