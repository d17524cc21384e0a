"""Speed-versus-error benchmarks: ``gfrf bench`` writes ``reports/speed-vs-error.md``.

Each computational kernel has a module here with ``run(quick: bool) -> BenchSection``;
:data:`SECTION_MODULES` lists them.  Every section times our method and the naive
baseline a user would write *in the same run*, and reports errors beside the
times, so ratios are measured, never asserted.

May import: every stage below the command line (it times them); never :mod:`gfrf.cli`
or :mod:`gfrf.report` (a section measures the library's functions, in-process or in a
new process through :func:`gfrf_command`).
"""

from __future__ import annotations

import datetime as _dt
import importlib
import math
import os
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from tqdm import tqdm

from gfrf import _data
from gfrf._atomic import atomic_write_text
from gfrf._data import MODELS_DIR

__all__ = ["BenchSection", "SECTION_MODULES", "MODELS_DIR", "best_of", "bundled_model",
           "figure_dir", "load_note", "machine_description", "run_all", "write_report",
           "gfrf_command"]

def bundled_model(name: str) -> str:
    """Absolute path of the bundled model file ``name`` (e.g. ``"cartpole.toml"``), as
    text for a command line (:func:`gfrf._data.bundled_model`: package data, so
    ``gfrf bench`` runs from any directory of an installed copy).

    Parameters
    ----------
    name : str
        File name in the bundled models folder.

    Returns
    -------
    str
        The absolute path.
    """
    return str(_data.bundled_model(name))

#: Modules that each define ``run(quick: bool) -> BenchSection``.
SECTION_MODULES: tuple[str, ...] = (
    "gfrf.bench.startup",
    "gfrf.bench.kernels",
    "gfrf.bench.cold",
    "gfrf.bench.simulation",
    "gfrf.bench.norms",
    "gfrf.bench.narx_norms",
    "gfrf.bench.brackets",
    "gfrf.bench.limits",
    "gfrf.bench.proof",
    "gfrf.bench.periodic",
    "gfrf.bench.sweep",
    "gfrf.bench.identify",
    "gfrf.bench.frc",
    "gfrf.bench.upper",
    "gfrf.bench.certificates",
)


def gfrf_command(args: list[str]) -> list[str]:
    """The console script a user runs (or the same entry point through ``-c``).

    Parameters
    ----------
    args : list of str
        The arguments after ``gfrf``.

    Returns
    -------
    list of str
        The command line, for :mod:`subprocess`.
    """
    import sys

    script = Path(sys.executable).with_name("gfrf")
    if script.exists():
        return [str(script), *args]
    return [sys.executable, "-c", "import sys; from gfrf.cli import main; sys.exit(main())",
            *args]


@dataclass
class BenchSection:
    """One table of the speed-vs-error report.

    Parameters
    ----------
    title : str
        Section heading.
    intro : str
        One paragraph: what is timed, what the error is measured against.
    columns : list of str
        Column headers.
    rows : list of list
        Table rows (already formatted strings or numbers).
    notes : list of str
        Bullet points under the table (targets, caveats).
    figures : list of str
        File names of figures written next to the report.
    """

    title: str
    intro: str
    columns: list[str]
    rows: list[list[object]]
    notes: list[str] = field(default_factory=list)
    figures: list[str] = field(default_factory=list)

    def to_markdown(self) -> str:
        """Render the section as Markdown."""
        lines = [f"## {self.title}", "", self.intro, ""]
        lines.append("| " + " | ".join(self.columns) + " |")
        lines.append("|" + "---|" * len(self.columns))
        for row in self.rows:
            lines.append("| " + " | ".join(str(c) for c in row) + " |")
        lines.append("")
        lines += [f"- {n}" for n in self.notes]
        lines += [f"![{f}]({f})" for f in self.figures]
        return "\n".join(lines).rstrip() + "\n"


def best_of(call: Callable[[], Any], repeat: int,
            before: Callable[[], None] | None = None) -> tuple[float, Any]:
    """Best wall time in seconds of ``repeat`` calls (``before`` runs untimed before each,
    e.g. to clear a cache) and the last call's result.

    Parameters
    ----------
    call : callable
        The timed call, without arguments.
    repeat : int
        Number of timed calls, >= 1.
    before : callable, optional
        Untimed call before each timed one.

    Returns
    -------
    float
        The best wall time in s.
    object
        The last call's result.
    """
    best, out = math.inf, None
    for _ in range(repeat):
        if before is not None:
            before()
        start = time.perf_counter()
        out = call()
        best = min(best, time.perf_counter() - start)
    return best, out


def load_note(load: tuple[float, float, float]) -> str:
    """The report line stating the load average ``load`` at the start of a section.

    Parameters
    ----------
    load : tuple of float
        The 1, 5 and 15 minute load averages (:func:`os.getloadavg`).

    Returns
    -------
    str
        One sentence for the section's notes.
    """
    return (f"Load average (1, 5, 15 min) at the start of this section: "
            f"{load[0]:.2f}, {load[1]:.2f}, {load[2]:.2f} on {os.cpu_count()} cores.")


def machine_description() -> str:
    """Cores, CPU model, Python, date and load average, for the report header."""
    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return (f"{os.cpu_count()} cores, {cpu}, Python {platform.python_version()}, "
            f"{platform.system()} {platform.machine()}, run on {_dt.date.today().isoformat()}; "
            "load average (1, 5, 15 min) when the report was written: "
            + ", ".join(f"{x:.2f}" for x in os.getloadavg())
            + " (a section's own load note gives the load at its start)")


def figure_dir() -> Path:
    """The folder where sections write their figures (set by :func:`run_all`)."""
    return Path(os.environ.get("GFRF_REPORT_DIR", "reports"))


def run_all(quick: bool = False, only: list[str] | None = None,
            out_dir: str | Path | None = "reports") -> list[BenchSection]:
    """Run every benchmark section (or those whose module name contains an ``only`` entry).

    Figures go to ``out_dir`` (sections read it through :func:`figure_dir`); None writes
    them to a temporary folder that is removed afterwards (nothing is left behind).

    Parameters
    ----------
    quick : bool, optional
        Passed to every section's ``run``: smaller, faster settings.
    only : list of str, optional
        Substrings of the section module names to run; None or empty runs all.
    out_dir : str, Path or None, optional
        Folder of the figures; None: a temporary folder.

    Returns
    -------
    list of BenchSection
        The sections, in :data:`SECTION_MODULES` order.
    """
    import tempfile

    names = [n for n in SECTION_MODULES if not only or any(o in n for o in only)]
    with tempfile.TemporaryDirectory(prefix="gfrf-bench-") as scratch:
        folder = Path(scratch if out_dir is None else out_dir)
        folder.mkdir(parents=True, exist_ok=True)
        previous = os.environ.get("GFRF_REPORT_DIR")
        os.environ["GFRF_REPORT_DIR"] = str(folder)
        try:
            return [importlib.import_module(name).run(quick)
                    for name in tqdm(names, desc="bench", disable=None)]
        finally:
            if previous is None:
                os.environ.pop("GFRF_REPORT_DIR", None)
            else:
                os.environ["GFRF_REPORT_DIR"] = previous


def write_report(sections: list[BenchSection], out_dir: str | Path) -> Path:
    """Write ``speed-vs-error.md`` into ``out_dir`` and return its path.

    Parameters
    ----------
    sections : list of BenchSection
        The sections, in order.
    out_dir : str or Path
        The folder (created if missing); the file is replaced atomically.

    Returns
    -------
    Path
        The path of ``speed-vs-error.md``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    text = ["# Speed versus error", "",
            "Every row times a gfrf kernel and the naive baseline in the same run; "
            "errors are measured against an independent reference named in each section.",
            "", f"Machine: {machine_description()}.", "",
            "Regenerate with `make bench` (or `gfrf bench --out reports/`).", ""]
    text += [s.to_markdown() for s in sections]
    path = out / "speed-vs-error.md"
    return atomic_write_text(path, "\n".join(text))
