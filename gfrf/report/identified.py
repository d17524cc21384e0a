"""Report page of the identification example: identified against true H1, H2 and verdicts.

:func:`write` (entry point for :func:`gfrf.report.write_reports`, called as
``write(out_dir, quick)``) writes ``identified-example.md`` and two figures: the gain
of H1 and the gains of H2 on its diagonal and anti-diagonal, each with the true model
(``models/identified_example_true.toml``) and the identified one
(``models/identified_example.toml``) on the same axes; the coefficient table; the
held-out fit quality of a fresh identification from the CSV (and whether the
committed model file still matches it); the verdicts of both models.
:func:`compare` returns the numbers without writing anything.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gfrf._results import Result
from gfrf.identify import example as ex
from gfrf.identify.data import read_csv
from gfrf.identify.fit import Identification, identify, same_terms
from gfrf.identify.output import write_atomic
from gfrf.identify.trust import identified_verdict
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile, load_model
from gfrf.stability.criteria import verdict
from gfrf.stability.verdicts import Verdict

__all__ = ["Comparison", "compare", "render", "write", "PAGE", "LAYOUT"]

#: File name of the page.
PAGE = "identified-example.md"


@dataclass(frozen=True, kw_only=True, repr=False)
class Comparison(Result):
    """The identification example: both model files, a fresh fit, kernel errors, verdicts."""

    true: ModelFile
    identified: ModelFile
    fit: Identification
    file_matches_fit: bool
    errors: dict[str, float]
    verdict_true: Verdict
    verdict_identified: Verdict


def compare(models_dir: str | Path = ex.MODELS_DIR, quick: bool = False) -> Comparison:
    """Load the example's files, identify the CSV afresh, compare kernels and verdicts.

    Parameters
    ----------
    models_dir : str or Path, optional
        The folder with the example's CSV, true and identified model files.
    quick : bool, optional
        Verdicts of order 3 instead of 5.

    Returns
    -------
    Comparison
        The kernels' errors and the verdicts.
    """
    folder = Path(models_dir)
    true = load_model(folder / f"{ex.STEM}_true.toml")
    identified = load_model(folder / f"{ex.STEM}.toml")
    y, u = read_csv(folder / f"{ex.STEM}.csv", "y", "u")
    fit = identify(y, u, ex.SAMPLE_TIME)
    order = 3 if quick else 5
    return Comparison(true=true, identified=identified, fit=fit,
                      file_matches_fit=same_terms(fit.model.terms, identified.plant.terms),
                      errors=ex.kernel_errors(identified.plant, true.plant),
                      verdict_true=verdict(true, order),
                      verdict_identified=identified_verdict(fit, identified, order))


def _figures(c: Comparison, out_dir: Path) -> list[str]:
    from gfrf._results import subplots
    from gfrf.report._format import save_figure

    true, ident = c.true.plant, c.identified.plant
    nyquist = math.pi / float(true.sample_time)  # type: ignore[arg-type]
    w = np.linspace(0.0, nyquist, 600)
    fig, ax = subplots(figsize=(6, 3.6))
    for model, label, style in ((true, "true model", "-"), (ident, "identified", "--")):
        ax.plot(w, np.abs(kernel(model, 1)(w)), style, label=label)
    ax.set_xlabel("angular frequency w (rad/s), up to the Nyquist frequency pi/T")
    ax.set_ylabel("|H1(jw)|")
    ax.set_title("First-order GFRF: identified against true")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    names = [save_figure(fig, out_dir / "identified-example-h1.png")]
    fig, axes = subplots(1, 2, figsize=(9, 3.6), sharey=True)
    for ax, sign, title in ((axes[0], 1.0, "diagonal |H2(jw, jw)|"),
                            (axes[1], -1.0, "anti-diagonal |H2(jw, -jw)|")):
        for model, label, style in ((true, "true model", "-"), (ident, "identified", "--")):
            ax.plot(w, np.abs(kernel(model, 2)(w, sign * w)), style, label=label)
        ax.set_title(title)
        ax.set_xlabel("w (rad/s)")
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel("|H2|")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    names.append(save_figure(fig, out_dir / "identified-example-h2.png"))
    return names


def _coefficient_rows(c: Comparison) -> list[list[object]]:
    def thetas(m: Model) -> dict[str, float]:
        return {t.monomial(): -t.coefficient for t in m.terms
                if not (t.y_orders == (0,) and not t.u_orders)}

    true, ident = thetas(c.true.plant), thetas(c.identified.plant)
    rows = []
    for name in sorted(set(true) | set(ident), key=lambda n: (n.count("*"), n)):
        a, b = true.get(name, 0.0), ident.get(name, 0.0)
        rows.append([f"`{name}`", a, b, b - a])
    return rows


def _verdict_rows(c: Comparison) -> list[list[object]]:
    rows = []
    for label, v in (("true", c.verdict_true), ("identified", c.verdict_identified)):
        norms = {b.order: b for b in v.norms}
        h1 = norms.get(1)
        rows.append([label, v.verdict, v.radius,
                     "certified" if v.radius_certified else "estimate",
                     h1.upper if h1 else None, v.radius_estimate])
    return rows


#: The page: one ``str.format`` layout that :func:`render` fills from a :class:`Comparison`.
LAYOUT = "\n".join([
    "{header}",
    "## Data", "",
    "`python -m gfrf.identify.example` simulates the true model `{true_equation}` "
    "(T = {sample_time} s) driven by uniform white noise in [-1, 1] and adds white Gaussian "
    "measurement noise of standard deviation {noise} to the output (seed {seed}); it writes "
    "the CSV, the true model file and the identified model file into models/.", "",
    "## Identification", "",
    "{command}", "",
    "Fit: {quality}. sysidentpy {sysidentpy}.",
    "The committed model file matches this fresh identification: {matches}.",
    "", "Coefficients theta of y[k] = sum theta * monomial:", "",
    "{coefficients}",
    "## Kernels", "",
    "Gains on the same axes (rad/s, up to the Nyquist frequency pi/T). Relative "
    "error: largest |H_identified - H_true| over the grid divided by the largest "
    "|H_true|.", "",
    "{errors}",
    "{figures}", "",
    "## Verdicts", "",
    "{verdicts}",
    "True model: {summary_true}", "",
    "Identified model: {summary_identified}", "",
])


def render(c: Comparison, figures: list[str]) -> str:
    """The Markdown text of the page from the comparison and its figures' file names.

    Parameters
    ----------
    c : Comparison
        The facts (:func:`compare`).
    figures : list of str
        The figures' file names.

    Returns
    -------
    str
        The page.
    """
    from gfrf.report._format import code, header, table

    fit = c.fit
    summary = [
        f"A NARX model identified by `gfrf identify` from {fit.n_samples} noisy samples "
        f"(models/{ex.STEM}.csv) against the model that generated them.",
        f"Largest relative kernel errors: H1 {c.errors['H1']:.3g}, H2 {c.errors['H2']:.3g}; "
        f"held-out free-run RRSE {fit.free_run_error:.3g}.",
        f"Verdicts at r = 1: true model {c.verdict_true.verdict}, identified model "
        f"{c.verdict_identified.verdict}."]
    return LAYOUT.format(
        header=header("Identification example: from measured data to a verdict", summary,
                      "gfrf report --out reports/"),
        true_equation=ex.TRUE_EQUATION, sample_time=ex.SAMPLE_TIME, noise=ex.NOISE,
        seed=ex.SEED,
        command=code(f"gfrf identify models/{ex.STEM}.csv --output y --input u --sample-time "
                     f"{ex.SAMPLE_TIME} {fit.settings_text()} --out models/{ex.STEM}.toml"),
        quality=fit.quality_text(), sysidentpy=fit.sysidentpy_version,
        matches="yes" if c.file_matches_fit else "no (regenerate with the command above)",
        coefficients=table(["monomial", "true", "identified", "identified - true"],
                           _coefficient_rows(c)),
        errors=table(["kernel", "relative error"], [["H1", c.errors["H1"]],
                                                     ["H2", c.errors["H2"]]]),
        figures="\n".join(f"![{name}]({name})" for name in figures),
        verdicts=table(["model", "verdict at r = 1", "r*", "r* is", "||H1|| (upper)",
                        "radius estimate from lower bounds"], _verdict_rows(c)),
        summary_true=c.verdict_true.summary, summary_identified=c.verdict_identified.summary)


def write(out_dir: str | Path, quick: bool = False) -> Path:
    """Write ``identified-example.md`` and its figures into ``out_dir``; return the page.

    Parameters
    ----------
    out_dir : str or Path
        The report folder.
    quick : bool, optional
        Verdicts of order 3 instead of 5.

    Returns
    -------
    Path
        The path of the page.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    c = compare(quick=quick)
    return write_atomic(out / PAGE, render(c, _figures(c, out)))
