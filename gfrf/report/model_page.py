"""The verdict page of one model: ``reports/models/<stem>.md`` with its figures.

For a control engineer who has not read the code: the equation and its coefficients,
the kernels H1..H3 (symbolic, gain/phase of H1, a slice of |H3|), the norms with their
brackets, the verdict with every condition of Theorem 1 or 2, the margin r*, the
parameter margins (for a file with ``[parameters]``), and simulations below and above
r*.  Every number comes from :func:`gfrf.report.analysis.analyse` in the same run;
each is printed with the ``gfrf`` command that reproduces it.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import sympy as sp

from gfrf._atomic import atomic_write_text
from gfrf._results import proof_word
from gfrf.bounds.norms import linear_poles
from gfrf.kernels.recursion import kernel
from gfrf.model.safetext import markdown_text, plot_text
from gfrf.report._figures import frequency_scale, h1_figure, h3_slice_figure, response_figure
from gfrf.report._format import bracket_cells, cell, code, header, mark, num, table
from gfrf.report.analysis import MARGIN_OCTAVES, ModelAnalysis, analyse
from gfrf.sim.validation import linear_vs_nonlinear, resonance_label

__all__ = ["write", "summary_lines", "command_path", "growth_sentence"]

#: Parts of a norm's notes computed in floating point whose last bits may differ between
#: CPUs (box counts, the float gap): the pages leave the numbers out.
_FLOAT_PARTS = ((re.compile(r"branch-and-bound: \d+ boxes; "), "branch-and-bound: "),
                (re.compile(r"stopped at \d+ boxes"), "stopped"),
                (re.compile(r"relative gap \S+ > tol"), "relative gap > tol"))


def _stable_note(note: str) -> str:
    """``note`` without the CPU-dependent numbers of :data:`_FLOAT_PARTS`."""
    for pattern, text in _FLOAT_PARTS:
        note = pattern.sub(text, note)
    return note


#: Longest explicit symbolic kernel shown in full; longer ones are shown recursively.
MAX_EXPLICIT = 700


def command_path(path: str) -> str:
    """The model path as printed in commands: ``models/<file>`` for bundled models.

    Parameters
    ----------
    path : str
        The model file's path.

    Returns
    -------
    str
        The path as printed.
    """
    p = Path(path)
    return f"models/{p.name}" if p.parent.name == "models" else str(path)


def summary_lines(a: ModelAnalysis) -> list[str]:
    """The three-line summary of a model page (also used in the index).

    Parameters
    ----------
    a : ModelAnalysis
        The model's analysis.

    Returns
    -------
    list of str
        Three lines.
    """
    v = a.verdict
    if v.radius > 0 and v.radius_certified and v.radius_proof != "none":
        level = proof_word(v.radius_proof)
        first = (f"Theorem {v.theorem}: stable (L2) for every input amplitude r < r* = "
                 f"**{num(v.radius)}** ({level} lower bound); verdict at r = 1: "
                 f"**{v.verdict}**.")
    elif v.radius > 0:  # an estimated r* never headlines 'stable'
        first = (f"Theorem {v.theorem}: verdict **{v.verdict}**; no input amplitude is proven "
                 f"stable (r* = {num(v.radius)} is an estimate, not a proof).")
    else:
        failed = [c.name for c in v.conditions if c.passed is False]
        first = (f"Theorem {v.theorem}: verdict **{v.verdict}**; r* = 0, no input amplitude "
                 f"is certified ({len(failed)} of {len(v.conditions)} conditions fail: "
                 + "; ".join(failed) + ").")
    norms = ", ".join(f"||H{b.order}|| {_bracket(b.lower, b.upper)}" for b in v.norms[:3])
    val = a.validation
    if val is None:
        sims = "No input trials (no positive radius to scale them)."
    else:
        below = [t for t in val.trials if t.below_radius]
        above = [t for t in val.trials if not t.below_radius]
        scale = "r*" if a.trial_scale_certified else "the radius estimate"
        sims = (f"Simulations: {sum(t.bounded for t in below)}/{len(below)} trials below "
                f"{scale} stay bounded, {sum(t.bounded for t in above)}/{len(above)} above; "
                f"{len(val.contradictions)} contradiction(s) of the verdict.")
    return [first, f"Norms: {norms}.", sims]


def _bracket(lower: float, upper: float) -> str:
    if lower == upper:
        return f"= {num(upper)}"
    low, high, _ = bracket_cells(lower, upper)  # outward, to the digits it proves
    return f"in [{low}, {high}]"


def _latex(a: ModelAnalysis, n: int) -> str:
    k = kernel(a.model_file.plant, n)
    if k.is_zero:
        return f"H_{{{n}}} = 0"
    expr = k.expr
    if len(str(expr)) > MAX_EXPLICIT:
        expr = k.recursive_expr
    return f"H_{{{n}}} = {sp.latex(expr)}"


def _model_section(a: ModelAnalysis) -> list[str]:
    mf, plant = a.model_file, a.model_file.plant
    out = ["## The model", ""]
    if mf.source:
        out += [f"Source: {markdown_text(mf.source)}.", ""]
    if mf.description:
        out += [markdown_text(mf.description), ""]
    out += ["Equation as written in the model file:", "", "```", plant.text.strip(), "```", ""]
    if plant.truncation:
        out += [f"Polynomial model after Taylor truncation at order {plant.truncation} "
                "(the object the GFRFs and the verdict describe):", ""]
    else:
        out += ["Polynomial model (the object the GFRFs and the verdict describe):", ""]
    out += ["```", plant.equation(), "```", ""]
    if plant.is_discrete:
        out += [f"Discrete time, sample time T = {num(plant.sample_time)} s; `y[k-l]` is "
                "the output l samples back.", ""]
    if mf.parameters:
        out += [table(["parameter", "value"], [[k, v] for k, v in mf.parameters.items()])]
    out += ["Coefficients (`D(y,l)` is the l-th derivative):", "",
            table(["monomial", "coefficient", "kind"],
                  [[r["monomial"], r["coefficient"], r["kind"]]
                   for r in plant.coefficient_table()])]
    ctrl = mf.controller
    if ctrl is not None:
        loop_text = "u = C(r - y)" if ctrl.feedback == -1 else "u = C(r + y)"
        out += [f"Controller: {markdown_text(ctrl.name or 'linear')} "
                f"({markdown_text(ctrl.source)}). C(s) = num/den with "
                f"num = {cell(list(ctrl.num or ()))}, den = {cell(list(ctrl.den or ()))} "
                f"(highest power first), loop {loop_text}.", ""]
    return out


def _kernel_section(a: ModelAnalysis, out_dir: Path) -> list[str]:
    plant = a.model_file.plant
    var = "q_i = exp(-j w_i T)" if plant.is_discrete else "s_i = j w_i"
    cmd = f"gfrf kernel {command_path(a.path)} --order 3 --at 1,1,-1"
    out = ["## Kernels (GFRFs)", "",
           f"Symbolic kernels in {var}, symmetric (the unique symmetric GFRF); a long H3 is "
           "shown in its recursive form, with H_1(.) the first-order kernel. Evaluate one "
           f"at any point with {code(cmd)}.", ""]
    for n in (1, 2, 3):
        out += ["```math", _latex(a, n), "```", ""]
    poles = linear_poles(plant)
    kind = ("" if poles.stable else "\nL∞ gain of an unstable plant" if poles.outside
            else "\nL∞ gain of a plant with poles on the stability boundary")
    h1_png = h1_figure(plant, out_dir / f"{a.stem}-h1.png",
                       title=f"H1 of {plot_text(a.model_file.name, limit=80)}{kind}")
    out += [f"![gain and phase of H1]({h1_png})", ""]
    norm3 = a.verdict.norms[2] if len(a.verdict.norms) >= 3 else None
    if norm3 is not None and norm3.upper > 0:
        w3 = norm3.argmax[2]
        half = 2.5 * max(frequency_scale(plant) if not plant.is_discrete else 0.0,
                         max(abs(x) for x in norm3.argmax), 1e-3)
        if plant.is_discrete:
            half = frequency_scale(plant)
        png = h3_slice_figure(plant, out_dir / f"{a.stem}-h3.png", w3, half,
                              title=f"|H3(jw1, jw2, jw3)| at w3 = {w3:.4g} rad/s")
        out += [f"Slice of |H3| through the point where its largest value was found "
                f"(w3 = {num(w3)} rad/s fixed; log colour scale):", "",
                f"![|H3| slice]({png})", ""]
    else:
        out += ["H3 vanishes identically: no slice to draw.", ""]
    return out


def _norm_section(a: ModelAnalysis) -> list[str]:
    p = command_path(a.path)
    rows = []
    for b in a.verdict.norms:
        rows.append([b.order, *bracket_cells(b.lower, b.upper), "certified" if b.certified
                     else "estimate", list(b.argmax), code(f"gfrf norm {p} --order {b.order}")])
    out = ["## Norms", "",
           "||H_n|| = sup over all frequencies of |H_n(jw_1, ..., jw_n)|. The lower bound is a "
           "value of |H_n| actually attained (at the listed frequencies); the upper bound is "
           "a proven majorant. Equal bounds mean the norm is known exactly.", "",
           table(["n", "lower", "upper", "relative gap", "upper bound", "attained at (rad/s)",
                  "check"], rows)]
    # box counts and the tail bound's digits come from floating point whose last bits
    # may differ between CPUs: the page names the method, not the count
    notes = sorted({_stable_note(note) for b in a.verdict.norms for note in b.notes})
    out += [f"- {note}" for note in notes]
    return out + [""]


def _verdict_section(a: ModelAnalysis) -> list[str]:
    v, p = a.verdict, command_path(a.path)
    theorem = ("Theorem 1 (open loop): L2 stable if every H_n is proper, the linear part is "
               "stable and the norm series sum ||H_n|| r^n converges" if v.theorem == 1 else
               "Theorem 2 (closed loop): internally L2 stable if plant and controller kernels "
               "are proper, the linear closed loop is stable and the series sum phi_m "
               "lambda_1^m and sum theta_n rho_1^n r^n converge")
    out = ["## Verdict", "", f"{theorem}. Check with "
           f"{code(f'gfrf verdict {p} --order {a.order}')}.", "",
           table(["condition", "result", "detail"],
                 [[c.name, mark(c.passed), c.detail] for c in v.conditions])]
    series_rows = []
    for row in v.series:
        series_rows.append([row["order"], row["majorant"], row["majorant_term"],
                            row.get("theta_term")])
    out += ["Series at r = 1 (M_n is the certified majorant, M_n >= ||H_n||):", "",
            table(["n", "M_n", "M_n r^n", "theta_n rho_1^n r^n"], series_rows)]
    cert = "certified" if v.radius_certified else "estimate (grid sups)"
    est = (f" Proven upper bound on the true radius of the {v.estimate_of}: "
           f"{num(v.radius_upper, 6)} ({v.radius_upper_detail})." if v.radius_upper else "")
    est += (f" Estimate of that true radius: {num(v.radius_estimate, 4)} (an estimate, not a "
            "proof; no verdict rests on it)." if v.radius_estimate else "")
    margin = (f"the certified series converges for every input amplitude r < r*, so the "
              f"verdict is *stable* there.{est}" if v.radius > 0 and v.radius_certified
              and v.radius_proof != "none" else
              f"r* is an estimate (not a proof): no input amplitude is proven stable.{est}"
              if v.radius > 0 else
              f"no input amplitude is certified: the theorem's hypotheses fail.{est}")
    out += [f"**Margin r\\* = {num(v.radius)}** ({cert}): {margin}", "",
            f"Verdict at r = 1: **{v.verdict}**. {v.summary}", ""]
    return out


def _margin_section(a: ModelAnalysis) -> list[str]:
    if not a.margins:
        return []
    p = command_path(a.path)
    octaves = f"file value x 2^-{MARGIN_OCTAVES} .. 2^{MARGIN_OCTAVES}"
    out = ["## Margins", "",
           f"Verdict at r = 1 (Theorem {a.verdict.theorem}, majorant only) along each "
           f"parameter over the bracket {octaves}, the others at their file values; where "
           "the verdict changes once, that boundary is bisected by "
           "`gfrf.stability.criteria.parameter_margin` (certified).", ""]
    for s in a.margins:
        m = s.margin
        if m is None:
            out.append(f"- {s.parameter} (file value {num(s.current)}): {s.note}.")
            continue
        digits = max(3, round(-math.log10(m.tolerance)) + 1)
        out.append(f"- {s.parameter} (file value {num(s.current)}): certified stable for "
                   f"{s.parameter} {m.direction} **{num(m.value, digits)}** (bisection tolerance "
                   f"{num(m.tolerance)}); {code(f'gfrf verdict {p} --margin {s.parameter}')}.")
    return out + [""]


def _simulation_section(a: ModelAnalysis, out_dir: Path) -> list[str]:
    ylabel = f"{a.model_file.plant.output}(t)"
    kind = ("closed loop from initial angles, zero reference" if a.closed else
            "sinusoidal input at the H1 peak, below and above r*")
    png = response_figure(a.responses, out_dir / f"{a.stem}-sim.png",
                          f"{plot_text(a.model_file.name, limit=80)}:\n{kind}", ylabel)
    out = ["## Simulations", "",
           f"Polynomial model simulated with scipy (RK45, rtol 1e-8), horizon {num(a.t_end)} s; "
           "a run stops when |y| reaches 1e3 (blow-up). Figure: "
           f"{kind}.", "", f"![simulation]({png})", "", "Reproduce the curves with:", ""]
    for r in a.responses:
        cmd = f"gfrf simulate {command_path(a.path)} --polynomial --t-end {a.t_end:g} " \
              "--rtol 1e-8 --atol 1e-11 --blowup 1000"
        if a.closed:
            cmd += f" --closed-loop --initial {math.radians(r.initial_angle_deg)!r},0"
        else:
            cmd += f" --input '{r.signal}'"
        out.append(f"- {r.label}: {code(cmd)}")
    out.append("")
    val = a.validation
    if val is None:
        return out + ["No input trials: there is no positive radius to scale them.", ""]
    scale = ("r*" if a.trial_scale_certified else
             "the uncertified radius estimate (r* = 0)")
    out += [f"Trials of `gfrf.sim.validation.validate` at multiples of {scale} = "
            f"{num(a.trial_scale)} (and at the paper's r = 1); fixed seed 0, drive "
            f"frequency w_r = {resonance_label(a.model_file.plant)}.", "",
            table(["input", "amplitude", "below scale", "bounded", "peak |y|", "blow-up time (s)"],
                  [[t.kind, t.amplitude, t.below_radius, t.bounded, t.peak, t.blowup_time]
                   for t in val.trials])]
    bad = val.contradictions
    out += [f"Contradictions of the verdict (a trial below r* that blew up): "
            f"{len(bad) if a.trial_scale_certified else 'not applicable (no certified r*)'}.",
            ""]
    if a.closed:
        rows = [linear_vs_nonlinear(a.model_file, angle) for angle in (5.0, 10.0, 15.0)]
        out += ["Nonlinear versus linear closed loop from an initial angle (5 s, zero "
                f"reference): {growth_sentence(rows)}", "",
                table(["initial angle (deg)", "max |difference| (rad)", "relative"],
                      [[r["angle_deg"], r["max_abs_error"], r["relative_error"]] for r in rows])]
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


def _certification(a: ModelAnalysis) -> list[str]:
    v = a.verdict
    exact = [b.order for b in v.norms if b.certified and b.gap == 0]
    open_ = [b.order for b in v.norms if b.gap > 0]
    return ["## What is proven and what is estimated", "",
            f"- Certified: the upper bounds of ||H_n|| (majorant), r* = {num(v.radius)}"
            f"{'' if v.radius_certified else ' (here only an estimate: grid sups)'}, the "
            "pass/FAIL of each condition.",
            f"- Exact norms (bracket closed): orders {cell(exact)}; open brackets: "
            f"{cell(open_)}.",
            "- Estimates: the lower bounds (best values found by search), the radius estimate "
            "from lower bounds, and every simulation (finite horizon, one input each).", ""]


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
    a = analyse(str(path), quick)
    folder = Path(out_dir) / "models"
    folder.mkdir(parents=True, exist_ok=True)
    regen = f"gfrf report {command_path(a.path)} --out {Path(out_dir).as_posix()}/"
    parts = [header(markdown_text(a.model_file.name), summary_lines(a), regen)]
    for section in (_model_section(a), _kernel_section(a, folder), _norm_section(a),
                    _verdict_section(a), _margin_section(a), _simulation_section(a, folder),
                    _certification(a)):
        if section:
            parts.append("\n".join(section))
    parts.append("Related: [paper reproduction](../paper-gfrf.md), "
                 "[speed vs error](../speed-vs-error.md).\n")
    page = folder / f"{a.stem}.md"
    return atomic_write_text(page, "\n".join(parts))
