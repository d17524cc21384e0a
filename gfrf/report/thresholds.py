"""``thresholds.md``: the two-sided answer for every bundled model, and its figure.

For each bundled GFRF model: Theorem 1's (or 2's) r*, the second certificate (the
energy function of :mod:`gfrf.stability.energy` where it applies), the falsified
amplitude of :mod:`gfrf.twosided.falsify` with its witness, the static bound, and how
conservative r* is (r*/upper); the figure draws the three regions (proven stable,
unknown, a witness escapes) on a log amplitude axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from gfrf._atomic import atomic_write_text
from gfrf._results import Result, subplots
from gfrf.model.modelfile import load_model
from gfrf.report._format import header, save_figure, table
from gfrf.twosided.falsify import MARGINS
from gfrf.twosided.threshold import Threshold, threshold

__all__ = ["write", "compute", "render", "threshold_figure", "rows", "PendulumGap",
           "ThresholdsFacts", "PAGE", "GAP_LINE"]

#: The paper's pendulums, whose conservativeness r*/upper the report states in words.
PAPER_PENDULUMS = ("hanging_pendulum", "hanging_pendulum_damped")
#: The models of a quick build (tests): one global certificate, one witness.
QUICK_MODELS = ("duffing", "hanging_pendulum_damped")


def _kind(method: str, radius: float) -> str:
    """The certificate's family in a word, and ``global`` for an infinite radius."""
    family = ("sum of squares" if "sum-of-squares" in method else
              "energy" if "energy" in method or "E + eps" in method else "certificate")
    return f"{family}, global" if math.isinf(radius) else f"{family}, sublevel set"


def rows(results: dict[str, Threshold]) -> list[list[object]]:
    """One table row per model: r*, second certificate, falsified amplitude, static bound.

    Parameters
    ----------
    results : dict of str to Threshold
        The two-sided answers by model stem.

    Returns
    -------
    list of list
        One row per model.
    """
    out: list[list[object]] = []
    for stem, t in results.items():
        theorem = t.certificates[0]
        second = t.certificates[1:]
        tones = t.witness_tones
        f = t.falsification
        dw = t.d_witness
        witness = (f"d = {'+' if dw.first_sign > 0 else '-'}{t.upper:.4g} switching "
                   f"({len(dw.switch_times)} switches, to |D| <= 1e-6 |D(0)|, "
                   f"{t.upper_proof})" if dw is not None and t.upper is not None else
                   "-" if t.upper is None or f is None else
                   f"+-{t.upper:.4g} switching ({len(f.switch_times)} switches, "
                   f"{t.upper_proof})" if f.kind == "switching" else
                   " + ".join(f"{a:.4g} cos({w:.4g} t{'' if p == 0 else f' + {p:.3g}'})"
                              for a, w, p in tones) + f" ({t.upper_proof})")
        ratio = theorem.radius / t.upper if t.upper else None
        out.append([stem, f"Theorem {t.theorem}", theorem.radius,
                    "; ".join(f"{c.radius:.6g} ({_kind(c.method, c.radius)}, {c.proof})"
                              for c in second) or "-",
                    t.lower, t.upper, witness, t.static_bound, ratio])
    return out


def threshold_figure(results: dict[str, Threshold], path: Path) -> str:
    """Three regions per model on a log amplitude axis: proven, unknown, escapes.

    Parameters
    ----------
    results : dict of str to Threshold
        The two-sided answers by model stem.
    path : Path
        The PNG file.

    Returns
    -------
    str
        The file's name.
    """
    finite = [v for t in results.values() for v in (t.lower, t.upper or 0.0, t.static_bound or 0)
              if 0 < v < math.inf]
    lo, hi = min(finite) / 10, max(finite) * 10
    fig, ax = subplots(figsize=(8, 0.45 * len(results) + 1.6))
    for i, t in enumerate(results.values()):
        lower = min(max(t.lower, lo), hi)
        top = hi if t.upper is None else t.upper
        ax.barh(i, lower - lo, left=lo, color="tab:green", height=0.6)
        ax.barh(i, top - lower, left=lower, color="lightgray", height=0.6)
        if t.upper is not None:
            ax.barh(i, hi - t.upper, left=t.upper, color="tab:red", height=0.6)
        if t.static_bound:
            ax.plot([t.static_bound], [i], "k|", markersize=14)
    ax.set_xscale("log")
    ax.set_xlim(lo, hi)
    ax.set_yticks(range(len(results)), list(results))
    ax.invert_yaxis()
    ax.set_xlabel("input amplitude (sum of tone amplitudes; reference in a loop)")
    ax.set_title("green: stability proven;  gray: unknown;  |: static bound (of the series)\n"
                 "red: from upper on (a sum of tones of that amplitude escapes)", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path)


@dataclass(frozen=True, kw_only=True, repr=False)
class PendulumGap(Result):
    """How far the proofs reach toward the falsified amplitude on one paper pendulum.

    Attributes
    ----------
    stem : str
        The model's file stem.
    theorem : int
        The theorem behind ``radius`` (1 or 2).
    radius : float
        The theorem's r* (sums of tones).
    lower : float
        The best certificate's radius (every input with sup|u| below it).
    upper : float
        The smallest escaping amplitude found.
    switching : bool
        Whether the witness is a switching input (else a sum of tones).
    upper_proof_words : str
        How the witness's escape was shown.
    """

    stem: str
    theorem: int
    radius: float
    lower: float
    upper: float
    switching: bool
    upper_proof_words: str

    def best_proven(self) -> str:
        """Which proof reaches further: ``"lower"`` (the certificate) or ``"r*"``."""
        return "lower" if self.lower >= self.radius else "r*"


@dataclass(frozen=True, kw_only=True, repr=False)
class ThresholdsFacts(Result):
    """Everything ``thresholds.md`` states, computed before it is written.

    ``to_dict`` leaves out ``figure`` (the PNG's file name, not a result).

    Attributes
    ----------
    rows : list of list
        The table, one row per model (:func:`rows`).
    gaps : tuple of PendulumGap
        The paper's pendulums with a falsified amplitude.
    figure : str
        The figure's file name.
    """

    rows: list[list[object]]
    gaps: tuple[PendulumGap, ...]
    figure: str

    _exclude = ("figure",)


#: The page: one ``str.format`` layout filled by :func:`render`.
PAGE = "\n".join([
    "{header}",
    "{table}",
    "",
    "![three regions]({figure})",
    "",
    "{gaps}",
    "Units: r* bounds inputs of Theorem 1's class (amplitude = L1 norm of the "
    "spectrum); lower, and every energy or sum-of-squares certificate, every input "
    "with sup|u| below it. A witness is switched on at t = 0 from rest: a switching "
    "input is measured by sup|u| (the same class as lower), a sum of tones by the "
    "sum of its amplitudes (its spectrum's L1 norm is infinite, so it is reported "
    "beside r*, in its own units). The witness column says how its escape was "
    "shown: interval (an Arb enclosure, or the NARX recursion in Arb, enters the "
    "certified escape region) or estimate (simulation: the fast path, then DOP853 "
    "at two tolerances). The static bound bounds the norm series' radius, not "
    "stability.",
    "",
])

#: One line per paper pendulum; ``best`` says which proof reaches further.
GAP_LINE = ("- `{stem}`: Theorem {theorem} proves {radius:.4g} (sums of tones), the best "
            "certificate {lower:.4g} (every input with sup|u| below it), {what} {upper:.4g} "
            "escapes ({words}): r*/upper = {r_ratio:.1%} (Theorem {theorem}), lower/upper = "
            "{l_ratio:.1%} ({best}).")


def compute(out_dir: Path, models: list[str], quick: bool = False) -> ThresholdsFacts:
    """The two-sided answer of every model in ``models``; writes ``thresholds.png``.

    Parameters
    ----------
    out_dir : Path
        The report folder.
    models : list of str
        Paths of the model files.
    quick : bool, optional
        Only :data:`QUICK_MODELS`.

    Returns
    -------
    ThresholdsFacts
        The facts :func:`render` writes.
    """
    if quick:
        models = [m for m in models if Path(m).stem in QUICK_MODELS]
    results = {Path(m).stem: threshold(load_model(m)) for m in models}
    figure = threshold_figure(results, out_dir / "thresholds.png")
    gaps = tuple(
        PendulumGap(stem=stem, theorem=t.theorem, radius=t.certificates[0].radius,
                    lower=t.lower, upper=t.upper,
                    switching=t.falsification is not None
                    and t.falsification.kind == "switching",
                    upper_proof_words=t.upper_proof_words)
        for stem, t in results.items() if stem in PAPER_PENDULUMS and t.upper)
    return ThresholdsFacts(rows=rows(results), gaps=gaps, figure=figure)


def render(facts: ThresholdsFacts) -> str:
    """The Markdown text of ``thresholds.md`` from its facts.

    Parameters
    ----------
    facts : ThresholdsFacts
        The facts (:func:`compute`).

    Returns
    -------
    str
        The page.
    """
    summary = ["Stable below lower (proven), unstable at upper (a simulation witness), "
               "unknown between: every bundled model.",
               "lower is the largest radius proven for every input with sup|u| <= lower "
               "(energy or exactly re-checked sum-of-squares certificates); Theorem 1/2's "
               "r* covers sums of tones only and is listed beside it.",
               "upper is the smallest escaping bounded input found from rest (a switching "
               "input u = +-U: sup|u|; a sum of tones: the sum of amplitudes), with a "
               f"{MARGINS[0]:g}x margin; escape = entering a certified escape region or "
               "passing a level from the model's scale (interval: enclosed in Arb)."]
    gaps = "".join(GAP_LINE.format(
        stem=g.stem, theorem=g.theorem, radius=g.radius, lower=g.lower, upper=g.upper,
        what=("a switching input u = +-U of sup|u|" if g.switching
              else "a sum of tones of amplitude"),
        words=g.upper_proof_words, r_ratio=g.radius / g.upper, l_ratio=g.lower / g.upper,
        best=("the best proven" if g.best_proven() == "lower"
              else "below r*, which covers sums of tones only")) + "\n" for g in facts.gaps)
    return PAGE.format(
        header=header("Thresholds: proven below, broken above", summary,
                      "gfrf report --out reports/"),
        table=table(["model", "theorem", "r* (proven)", "second certificate", "lower",
                     "upper (falsified)", "witness u(t), rad/s", "static bound",
                     "r*/upper"], facts.rows),
        figure=facts.figure, gaps=gaps)


def write(out_dir: Path, models: list[str], quick: bool = False) -> Path:
    """Write ``thresholds.md`` and ``thresholds.png`` for ``models`` (paths) into ``out_dir``.

    ``quick`` (tests) keeps only :data:`QUICK_MODELS` (about 5 s instead of about 60 s).

    Parameters
    ----------
    out_dir : Path
        The report folder.
    models : list of str
        Paths of the model files.
    quick : bool, optional
        Only :data:`QUICK_MODELS`.

    Returns
    -------
    Path
        The path of ``thresholds.md``.
    """
    facts = compute(out_dir, models, quick)
    return atomic_write_text(out_dir / "thresholds.md", render(facts))
