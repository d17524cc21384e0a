"""Reports: the paper reproduced, its errors shown, every verdict explained.

:func:`write_reports` regenerates, deterministically (fixed seeds, Agg figures, no
dates), into one folder:

* ``paper-gfrf.md`` (:mod:`gfrf.report.paper_gfrf`): every number the GFRF paper
  prints against ours, the paper's figures 3-6, Theorems 1 and 2 with r*, simulations;
* ``paper-periodic.md`` through ``gfrf.report.periodic.write`` when that module exists;
* ``models/<stem>.md`` (:mod:`gfrf.report.model_page`): one verdict page per bundled
  GFRF model file;
* ``identified-example.md`` (:mod:`gfrf.report.identified`, with the ``identify`` extra):
  a NARX model identified from data against the true model;
* ``thresholds.md`` (:mod:`gfrf.report.thresholds`): the two-sided answer of every
  bundled model (r*, the energy certificate, the falsified amplitude, the static bound);
* ``README.md``: an index of the above.

``speed-vs-error.md`` is written by ``gfrf bench`` (minutes of timing) and only linked.

May import: every stage below the command line (papers, sweep, identify, periodic,
sim, ...); never :mod:`gfrf.cli` or :mod:`gfrf.bench`.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import tomllib
from collections.abc import Callable
from functools import partial
from pathlib import Path

from tqdm import tqdm

from gfrf._atomic import atomic_write_text
from gfrf._results import proof_word
from gfrf.model.safetext import markdown_text
from gfrf.report import model_page, paper_gfrf, thresholds
from gfrf.report._format import header, table
from gfrf.report.analysis import MODELS_DIR, analyse

__all__ = ["MODELS_DIR", "bundled_models", "write_reports", "write_index"]


def bundled_models(models_dir: Path = MODELS_DIR) -> list[str]:
    """Paths ``models/<stem>.toml`` of the bundled GFRF models (parametric ones excluded).

    Parameters
    ----------
    models_dir : Path, optional
        The folder of the model files.

    Returns
    -------
    list of str
        The paths, sorted.
    """
    out = []
    for path in sorted(models_dir.glob("*.toml")):
        kind = tomllib.loads(path.read_text(encoding="utf-8")).get("kind", "ode")
        if kind == "ode":
            out.append(str(path))
    return out


def write_index(out_dir: Path, models: list[str], quick: bool) -> Path:
    """``README.md`` listing every report with its one-line verdict.

    Parameters
    ----------
    out_dir : Path
        The report folder.
    models : list of str
        Paths of the model files.
    quick : bool
        The quick analysis setting (:func:`gfrf.report.analysis.settings`).

    Returns
    -------
    Path
        The path of ``README.md``.
    """
    rows = []
    for path in models:
        a = analyse(path, quick)
        v = a.verdict
        rows.append([f"[{markdown_text(a.model_file.name)}](models/{a.stem}.md)",
                     f"Theorem {v.theorem}",
                     v.verdict, v.radius,
                     "estimate (not a proof)" if not v.radius_certified
                     or v.radius_proof == "none" else f"{proof_word(v.radius_proof)} lower bound"])
    summary = ["Reports of gfrf: the GFRF paper reproduced, the periodic paper checked, and one "
               "verdict page per model.",
               f"{len(models)} model pages; the verdict is at input amplitude r = 1 and r* is "
               "the amplitude below which stability is proven.",
               "Timing tables are in speed-vs-error.md (written by `gfrf bench`)."]
    text = [header("gfrf reports", summary, f"gfrf report --out {out_dir.as_posix()}/"),
            "- [paper-gfrf.md](paper-gfrf.md): the GFRF stability paper, number by number.",
            "- [paper-periodic.md](paper-periodic.md): the parametrically excited pendulum.",
            "- [speed-vs-error.md](speed-vs-error.md): benchmarks (`make bench`).",
            "- [identified-example.md](identified-example.md): a NARX model identified from "
            "data (sysidentpy) against the true one.",
            "- [thresholds.md](thresholds.md): stable below (proven), unstable at (a "
            "witness), for every model.", "",
            table(["model", "theorem", "verdict at r = 1", "r*", "r* is"], rows)]
    path = out_dir / "README.md"
    return atomic_write_text(path, "\n".join(text))


def _steps(jobs: list[tuple[str, Callable[[], Path]]]) -> list[Path]:
    """Run the jobs: a tqdm bar on a terminal, else one line per step on stderr (a log
    that shows where a long build is, e.g. under ``make demo``)."""
    if sys.stderr.isatty():
        return [job() for _, job in tqdm(jobs, desc="report")]
    written = []
    for i, (label, job) in enumerate(jobs, 1):
        print(f"gfrf report: step {i}/{len(jobs)}: {label}", file=sys.stderr, flush=True)
        written.append(job())
    return written


def write_reports(out_dir: str | Path = "reports", models: list[str] | None = None,
                  quick: bool = False) -> list[Path]:
    """Regenerate reports into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Output folder (created).
    models : list of str, optional
        Model files whose pages to write; None writes everything (the paper reports,
        every bundled model's page and the index).
    quick : bool
        Reduced setting for tests (norm order 3, 20 s simulations).

    Returns
    -------
    list of Path
        The Markdown files written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if models:
        return _steps([(f"model page of {m}", partial(model_page.write, m, out, quick))
                       for m in models])
    paths = bundled_models()
    jobs: list[tuple[str, Callable[[], Path]]] = [
        (f"model page of models/{Path(m).name}", partial(model_page.write, m, out, quick))
        for m in paths]
    jobs.append(("paper-gfrf.md", partial(paper_gfrf.write, out, quick)))
    jobs.append(("thresholds.md", partial(thresholds.write, out, paths, quick)))
    if importlib.util.find_spec("gfrf.report.periodic") is not None:
        periodic = importlib.import_module("gfrf.report.periodic")
        jobs.append(("paper-periodic.md", partial(periodic.write, out, quick=quick)))
    if importlib.util.find_spec("sysidentpy") is not None:  # the `identify` extra
        from gfrf.report import identified as identify_report
        jobs.append(("identified-example.md", partial(identify_report.write, out, quick)))
    written = _steps(jobs)
    written.append(write_index(out, paths, quick))
    return written
