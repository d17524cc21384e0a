"""The verdict page of one model: ``reports/models/<stem>.md`` with its figures.

For a control engineer who has not read the code: the equation and its coefficients,
the kernels H1..H3 (symbolic, gain/phase of H1, a slice of |H3|), the norms with their
brackets, the verdict with every condition of Theorem 1 or 2, the margin r*, the
parameter margins (for a file with ``[parameters]``), and simulations below and above
r*.  :func:`gfrf.report.model_facts.compute` computes every number in one run (each is
printed with the ``gfrf`` command that reproduces it); :func:`render` writes the page
from those facts only, one section per function of :data:`SECTIONS`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from gfrf._atomic import atomic_write_text
from gfrf._results import proof_word
from gfrf.model.safetext import markdown_text
from gfrf.report._format import bracket_cells, cell, code, header, mark, num, table
from gfrf.report.analysis import MARGIN_OCTAVES
from gfrf.report.model_facts import ModelPageFacts, VerdictFacts, command_path, compute

__all__ = ["write", "render", "headline", "summary_lines", "command_path", "growth_sentence",
           "SECTIONS"]


def headline(v: VerdictFacts) -> str:
    """The first summary line: r* proven, estimated, or zero (never 'stable' on an estimate).

    Parameters
    ----------
    v : VerdictFacts
        The verdict's facts.

    Returns
    -------
    str
        The line.
    """
    if v.proven_radius:
        return (f"Theorem {v.theorem}: stable (L2) for every input amplitude r < r* = "
                f"**{num(v.radius)}** ({proof_word(v.radius_proof)} lower bound); verdict at "
                f"r = 1: **{v.verdict}**.")
    if v.radius > 0:  # an estimated r* never headlines 'stable'
        return (f"Theorem {v.theorem}: verdict **{v.verdict}**; no input amplitude is proven "
                f"stable (r* = {num(v.radius)} is an estimate, not a proof).")
    failed = [name for name, passed, _ in v.conditions if passed is False]
    return (f"Theorem {v.theorem}: verdict **{v.verdict}**; r* = 0, no input amplitude "
            f"is certified ({len(failed)} of {len(v.conditions)} conditions fail: "
            + "; ".join(failed) + ").")


def summary_lines(f: ModelPageFacts) -> list[str]:
    """The three-line summary of a model page.

    Parameters
    ----------
    f : ModelPageFacts
        The page's facts.

    Returns
    -------
    list of str
        Three lines.
    """
    norms = ", ".join(f"||H{b.order}|| {_bracket(b.lower, b.upper)}" for b in f.norms[:3])
    if f.trials is None:
        sims = "No input trials (no positive radius to scale them)."
    else:
        below = [t for t in f.trials if t.below_radius]
        above = [t for t in f.trials if not t.below_radius]
        scale = "r*" if f.trial_scale_certified else "the radius estimate"
        sims = (f"Simulations: {sum(t.bounded for t in below)}/{len(below)} trials below "
                f"{scale} stay bounded, {sum(t.bounded for t in above)}/{len(above)} above; "
                f"{f.contradictions} contradiction(s) of the verdict.")
    return [headline(f.verdict), f"Norms: {norms}.", sims]


def _bracket(lower: float, upper: float) -> str:
    if lower == upper:
        return f"= {num(upper)}"
    low, high, _ = bracket_cells(lower, upper)  # outward, to the digits it proves
    return f"in [{low}, {high}]"


def _model_section(f: ModelPageFacts) -> list[str]:
    out = ["## The model", ""]
    if f.source:
        out += [f"Source: {markdown_text(f.source)}.", ""]
    if f.description:
        out += [markdown_text(f.description), ""]
    out += ["Equation as written in the model file:", "", "```", f.equation_text, "```", ""]
    if f.truncation:
        out += [f"Polynomial model after Taylor truncation at order {f.truncation} "
                "(the object the GFRFs and the verdict describe):", ""]
    else:
        out += ["Polynomial model (the object the GFRFs and the verdict describe):", ""]
    out += ["```", f.polynomial, "```", ""]
    if f.sample_time is not None:
        out += [f"Discrete time, sample time T = {num(f.sample_time)} s; `y[k-l]` is "
                "the output l samples back.", ""]
    if f.parameters:
        out += [table(["parameter", "value"], [[k, v] for k, v in f.parameters])]
    out += ["Coefficients (`D(y,l)` is the l-th derivative):", "",
            table(["monomial", "coefficient", "kind"], [list(r) for r in f.coefficients])]
    if f.controller:
        out += [f.controller, ""]
    return out


def _kernel_section(f: ModelPageFacts) -> list[str]:
    var = "q_i = exp(-j w_i T)" if f.discrete else "s_i = j w_i"
    cmd = f"gfrf kernel {f.path} --order 3 --at 1,1,-1"
    out = ["## Kernels (GFRFs)", "",
           f"Symbolic kernels in {var}, symmetric (the unique symmetric GFRF); a long H3 is "
           "shown in its recursive form, with H_1(.) the first-order kernel. Evaluate one "
           f"at any point with {code(cmd)}.", ""]
    for latex in f.kernels:
        out += ["```math", latex, "```", ""]
    out += [f"![gain and phase of H1]({f.figures['h1']})", ""]
    if f.w3 is None:
        return out + ["H3 vanishes identically: no slice to draw.", ""]
    return out + [f"Slice of |H3| through the point where its largest value was found "
                  f"(w3 = {num(f.w3)} rad/s fixed; log colour scale):", "",
                  f"![|H3| slice]({f.figures['h3']})", ""]


def _norm_section(f: ModelPageFacts) -> list[str]:
    rows = [[b.order, *bracket_cells(b.lower, b.upper),
             "certified" if b.certified else "estimate", list(b.argmax),
             code(f"gfrf norm {f.path} --order {b.order}")] for b in f.norms]
    out = ["## Norms", "",
           "||H_n|| = sup over all frequencies of |H_n(jw_1, ..., jw_n)|. The lower bound is a "
           "value of |H_n| actually attained (at the listed frequencies); the upper bound is "
           "a proven majorant. Equal bounds mean the norm is known exactly.", "",
           table(["n", "lower", "upper", "relative gap", "upper bound", "attained at (rad/s)",
                  "check"], rows)]
    return out + [f"- {note}" for note in f.norm_notes] + [""]


def _verdict_section(f: ModelPageFacts) -> list[str]:
    v = f.verdict
    theorem = ("Theorem 1 (open loop): L2 stable if every H_n is proper, the linear part is "
               "stable and the norm series sum ||H_n|| r^n converges" if v.theorem == 1 else
               "Theorem 2 (closed loop): internally L2 stable if plant and controller kernels "
               "are proper, the linear closed loop is stable and the series sum phi_m "
               "lambda_1^m and sum theta_n rho_1^n r^n converge")
    out = ["## Verdict", "", f"{theorem}. Check with "
           f"{code(f'gfrf verdict {f.path} --order {f.order}')}.", "",
           table(["condition", "result", "detail"],
                 [[name, mark(passed), detail] for name, passed, detail in v.conditions])]
    out += ["Series at r = 1 (M_n is the certified majorant, M_n >= ||H_n||):", "",
            table(["n", "M_n", "M_n r^n", "theta_n rho_1^n r^n"], [list(r) for r in v.series])]
    cert = "certified" if v.radius_certified else "estimate (grid sups)"
    est = (f" Proven upper bound on the true radius of the {v.estimate_of}: "
           f"{num(v.radius_upper, 6)} ({v.radius_upper_detail})." if v.radius_upper else "")
    est += (f" Estimate of that true radius: {num(v.radius_estimate, 4)} (an estimate, not a "
            "proof; no verdict rests on it)." if v.radius_estimate else "")
    margin = (f"the certified series converges for every input amplitude r < r*, so the "
              f"verdict is *stable* there.{est}" if v.proven_radius else
              f"r* is an estimate (not a proof): no input amplitude is proven stable.{est}"
              if v.radius > 0 else
              f"no input amplitude is certified: the theorem's hypotheses fail.{est}")
    return out + [f"**Margin r\\* = {num(v.radius)}** ({cert}): {margin}", "",
                  f"Verdict at r = 1: **{v.verdict}**. {v.summary}", ""]


def _margin_section(f: ModelPageFacts) -> list[str]:
    if not f.margins:
        return []
    octaves = f"file value x 2^-{MARGIN_OCTAVES} .. 2^{MARGIN_OCTAVES}"
    out = ["## Margins", "",
           f"Verdict at r = 1 (Theorem {f.verdict.theorem}, majorant only) along each "
           f"parameter over the bracket {octaves}, the others at their file values; where "
           "the verdict changes once, that boundary is bisected by "
           "`gfrf.stability.criteria.parameter_margin` (certified).", ""]
    for m in f.margins:
        if m.value is None:
            out.append(f"- {m.parameter} (file value {num(m.current)}): {m.note}.")
            continue
        digits = max(3, round(-math.log10(m.tolerance)) + 1)
        out.append(f"- {m.parameter} (file value {num(m.current)}): certified stable for "
                   f"{m.parameter} {m.direction} **{num(m.value, digits)}** (bisection tolerance "
                   f"{num(m.tolerance)}); {code(f'gfrf verdict {f.path} --margin {m.parameter}')}.")
    return out + [""]


def _simulation_section(f: ModelPageFacts) -> list[str]:
    kind = ("closed loop from initial angles, zero reference" if f.closed else
            "sinusoidal input at the H1 peak, below and above r*")
    out = ["## Simulations", "",
           f"Polynomial model simulated with scipy (RK45, rtol 1e-8), horizon {num(f.t_end)} s; "
           "a run stops when |y| reaches 1e3 (blow-up). Figure: "
           f"{kind}.", "", f"![simulation]({f.figures['sim']})", "",
           "Reproduce the curves with:", ""]
    for r in f.responses:
        cmd = f"gfrf simulate {f.path} --polynomial --t-end {f.t_end:g} " \
              "--rtol 1e-8 --atol 1e-11 --blowup 1000"
        if f.closed:
            cmd += f" --closed-loop --initial {math.radians(r.initial_angle_deg)!r},0"
        else:
            cmd += f" --input '{r.signal}'"
        out.append(f"- {r.label}: {code(cmd)}")
    out.append("")
    if f.trials is None:
        return out + ["No input trials: there is no positive radius to scale them.", ""]
    scale = ("r*" if f.trial_scale_certified else
             "the uncertified radius estimate (r* = 0)")
    out += [f"Trials of `gfrf.sim.validation.validate` at multiples of {scale} = "
            f"{num(f.trial_scale)} (and at the paper's r = 1); fixed seed 0, drive "
            f"frequency w_r = {f.resonance}.", "",
            table(["input", "amplitude", "below scale", "bounded", "peak |y|", "blow-up time (s)"],
                  [[t.kind, t.amplitude, t.below_radius, t.bounded, t.peak, t.blowup_time]
                   for t in f.trials])]
    count = (f.contradictions if f.trial_scale_certified
             else "not applicable (no certified r*)")
    out += [f"Contradictions of the verdict (a trial below r* that blew up): {count}.", ""]
    if f.closed:
        rows = [{"angle_deg": a, "max_abs_error": e, "relative_error": r} for a, e, r in f.growth]
        out += ["Nonlinear versus linear closed loop from an initial angle (5 s, zero "
                f"reference): {growth_sentence(rows)}", "",
                table(["initial angle (deg)", "max |difference| (rad)", "relative"],
                      [list(row) for row in f.growth])]
    return out


def growth_sentence(rows: list[dict[str, float]]) -> str:
    """How the nonlinear-minus-linear difference grows with the initial angle, from the
    rows: the powers are the least-squares slopes of log(difference) and log(relative
    difference) against log(angle), rounded to integers.

    Parameters
    ----------
    rows : list of dict
        :func:`gfrf.sim.validation.linear_vs_nonlinear` results (``angle_deg``,
        ``max_abs_error``, ``relative_error``), at least two angles.

    Returns
    -------
    str
        The sentence.
    """
    x = np.log([r["angle_deg"] for r in rows])
    p_abs, p_rel = (round(float(np.polyfit(x, np.log([r[key] for r in rows]), 1)[0]))
                    for key in ("max_abs_error", "relative_error"))
    size = {2: "quadratic", 3: "cubic"}.get(p_abs, f"degree-{p_abs}")
    return (f"the difference grows like angle^{p_abs} (relative to the response: "
            f"angle^{p_rel}), the size of the neglected {size} terms.")


def _certification(f: ModelPageFacts) -> list[str]:
    v = f.verdict
    exact = [b.order for b in f.norms if b.certified and b.gap == 0]
    open_ = [b.order for b in f.norms if b.gap > 0]
    return ["## What is proven and what is estimated", "",
            f"- Certified: the upper bounds of ||H_n|| (majorant), r* = {num(v.radius)}"
            f"{'' if v.radius_certified else ' (here only an estimate: grid sups)'}, the "
            "pass/FAIL of each condition.",
            f"- Exact norms (bracket closed): orders {cell(exact)}; open brackets: "
            f"{cell(open_)}.",
            "- Estimates: the lower bounds (best values found by search), the radius estimate "
            "from lower bounds, and every simulation (finite horizon, one input each).", ""]


#: The page's sections in order, each a function of the facts (an empty list: left out).
SECTIONS = (_model_section, _kernel_section, _norm_section, _verdict_section,
            _margin_section, _simulation_section, _certification)


def render(f: ModelPageFacts) -> str:
    """The Markdown text of a model page from its facts.

    Parameters
    ----------
    f : ModelPageFacts
        The facts (:func:`gfrf.report.model_facts.compute`).

    Returns
    -------
    str
        The page.
    """
    parts = [header(markdown_text(f.name), summary_lines(f), f.regenerate)]
    parts += ["\n".join(lines) for lines in (section(f) for section in SECTIONS) if lines]
    parts.append("Related: [paper reproduction](../paper-gfrf.md), "
                 "[speed vs error](../speed-vs-error.md).\n")
    return "\n".join(parts)


def write(path: str, out_dir: Path, quick: bool = False) -> Path:
    """Write ``out_dir/models/<stem>.md`` and its PNGs for the model file at ``path``.

    Parameters
    ----------
    path : str
        A GFRF model file.
    out_dir : Path
        Report root (the page goes to its ``models/`` folder).
    quick : bool
        Reduced setting (see :func:`gfrf.report.analysis.settings`).

    Returns
    -------
    Path
        The Markdown page.
    """
    facts = compute(path, out_dir, quick)
    return atomic_write_text(Path(out_dir) / "models" / f"{facts.stem}.md", render(facts))
