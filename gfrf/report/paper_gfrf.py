"""``paper-gfrf.md``: the GFRF stability paper (Cao & Cao, paper 001) number by number.

Sections: the table of every printed number against ours (the rows of
:func:`gfrf.papers.gfrf_paper.paper_checks`, rendered cell by cell with
:func:`gfrf.report._format.cell`, each with the command that reproduces it); the
paper's figures 3-6 regenerated; Theorems 1 and 2 with our certified margin r* and
the damping margin; and the simulations that confirm or refute the conclusions
(:mod:`gfrf.sim.validation`, through :func:`gfrf.report.analysis.analyse`).

The paper's values are quoted from the model files' ``[paper]`` tables and from
``paper_checks``; nothing else is typed in.

The page is computed, then rendered: :func:`compute` gathers every number in a
:class:`PaperGfrfFacts` (and draws the figures), :func:`render` fills the layout
:data:`PAGE` from it, and each sentence that compares or states a property of the
numbers (a verdict certified or not, a value inside a bracket, every row explained) is
chosen by the facts.  The figures section is in :mod:`gfrf.report.paper_gfrf_figures`,
the cart-pole section in :mod:`gfrf.report.paper_gfrf_cartpole`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gfrf._atomic import atomic_write_text
from gfrf._results import Result
from gfrf.papers.cartpole_trials import LoopDrive, has_physical_equation
from gfrf.papers.gfrf_paper import (
    AlphaRow,
    CheckRow,
    ThetaReading,
    alpha_variants,
    paper_checks,
    theta_readings,
)
from gfrf.report._format import code, header, num, table
from gfrf.report.analysis import MODELS_DIR, ModelAnalysis, analyse, settings
from gfrf.report.model_page import command_path
from gfrf.report.paper_gfrf_cartpole import CartpoleFacts, cartpole_facts, cartpole_text
from gfrf.report.paper_gfrf_figures import FigureFacts, figure_facts, figures_text
from gfrf.stability.criteria import Margin, parameter_margin

__all__ = ["write", "compute", "render", "PAGE", "PaperGfrfFacts", "FigureFacts",
           "check_table", "row_command", "simulation_table", "MODELS", "EQ2_MODELS",
           "CHECK_HEADERS", "SIMULATION_HEADERS"]

#: Section label of paper_checks -> bundled model file the row is about.
MODELS = {"3 (rho = 0.8)": "hanging_pendulum.toml",
          "3 (rho = 8)": "hanging_pendulum_damped.toml",
          "4 (cart-pole, eq (12))": "cartpole.toml",
          "5 (cart-pole, eq (16))": "cartpole_reduced.toml"}

#: Eq (2) with its input gain kept (rho = 0.8 and rho = 8), beside eq (6)'s files.
EQ2_MODELS = ("hanging_pendulum_eq2.toml", "hanging_pendulum_eq2_damped.toml")

#: Columns of the simulation table.
SIMULATION_HEADERS = ("model", "equation", "input", "amplitude r", "r / r*", "below r*",
                      "bounded", "peak |y|", "blow-up time (s)")

#: Columns of the reproduction table.
CHECK_HEADERS = ("section", "quantity", "paper (printed)", "ours", "match", "reason",
                 "check")

_ROWS = ("python -c \"from gfrf.papers.gfrf_paper import paper_checks as p; "
         "[print(r) for r in p('models')]\"")
_COEFFICIENTS = ("python -c \"from gfrf.papers.gfrf_paper import coefficient_rows as c; "
                 "[print(r) for r in c('models/cartpole.toml')]\"")


def row_command(row: CheckRow) -> str:
    """The shell command that reproduces ``row``'s value.

    Parameters
    ----------
    row : CheckRow
        One row of the reproduction table.

    Returns
    -------
    str
        The command.
    """
    path = f"models/{MODELS[row.section]}"
    q = row.quantity
    if "coefficient" in q and row.section.startswith("4"):
        return _COEFFICIENTS
    if any(k in q for k in ("||H1||", "beta_1", "peak frequency")):
        return f"gfrf norm {path} --order 1"
    if any(k in q for k in ("||H3||", "beta_3", "third-order")):
        return f"gfrf norm {path} --order 3"
    if q.startswith("h1("):
        return f"gfrf show {path}"
    if any(k in q for k in ("rho_3", "theta_")):
        return _ROWS
    return f"gfrf verdict {path} --order 3"


def check_table(rows: list[CheckRow]) -> str:
    """The reproduction table: one line per row, every value through :func:`cell`.

    Parameters
    ----------
    rows : list of CheckRow
        The rows.

    Returns
    -------
    str
        The Markdown table.
    """
    return table(CHECK_HEADERS, [[r.section, r.quantity, r.paper, r.ours,
                                  "**yes**" if r.match else "no", r.reason,
                                  code(row_command(r))] for r in rows])


def _theorem_rows(analyses: list[ModelAnalysis]) -> list[list[object]]:
    rows = []
    for a in analyses:
        v = a.verdict
        claim = a.model_file.paper.get("series", "stable (Theorem 2, section 5)")
        rows.append([f"[{a.model_file.name}](models/{a.stem}.md)", f"Theorem {v.theorem}",
                     claim, v.verdict, v.radius,
                     "certified" if v.radius_certified else "estimate", v.radius_estimate,
                     code(f"gfrf verdict {command_path(a.path)} --order {a.order}")])
    return rows


def _simulation_rows(analyses: list[ModelAnalysis], drives: dict[str, LoopDrive]
                     ) -> list[list[object]]:
    """Rows of the simulation table.  Open-loop pendulums: every trial of the analysis,
    with r/r* and "below r*" against the certified r*.  Cart-poles (r* = 0, no certified
    scale): the initial-angle runs and the cosine drives of :func:`loop_drive` at the
    loop's own corner frequency, "below r*" not applicable (``None``).  Each row names its
    equation; a "physical" run is kept only when the file's untruncated equation differs
    from the polynomial (eq (16)'s file has none: its runs would repeat the polynomial)."""
    rows: list[list[object]] = []
    for a in analyses:
        if a.validation is None:
            continue
        radius = a.verdict.radius if a.verdict.radius_certified else 0.0
        physical = has_physical_equation(a.model_file)
        for t in a.validation.trials:
            if a.closed and not t.kind.startswith("initial angle"):
                continue  # multiples of an uncertified plant estimate: replaced below
            if t.equation == "physical" and not physical:
                continue
            below = t.amplitude < radius if radius > 0 and t.amplitude > 0 else None
            rows.append([a.stem, t.equation, t.kind, t.amplitude,
                         t.amplitude / radius if below is not None else None, below,
                         t.bounded, t.peak, t.blowup_time])
        if a.stem in drives:
            d = drives[a.stem]
            for dt in d.trials:
                rows.append([a.stem, dt.equation,
                             f"cosine at {num(d.omega, 4)} rad/s (linear angle "
                             f"{num(dt.target_deg)} deg)", dt.amplitude, None, None,
                             dt.bounded, dt.peak, dt.blowup_time])
    return rows


def simulation_table(rows: list[list[object]]) -> str:
    """The simulation table, "below r*" shown as yes / no / n/a.

    Parameters
    ----------
    rows : list of list
        The rows; entry 5 (below r*) may be None.

    Returns
    -------
    str
        The Markdown table.
    """
    shown = [[*r[:5], "n/a" if r[5] is None else r[5], *r[6:]] for r in rows]
    return table(SIMULATION_HEADERS, shown)


def _certified(r: AlphaRow) -> bool:
    return r.verdict == "stable"


def _alpha_claim(r: AlphaRow) -> str:
    """rho = ... is (not) certified at r = 1, with r* and the simulation beside it."""
    if _certified(r):
        return f"rho = {num(r.rho)} is **certified stable at r = 1** (r* = {num(r.radius, 4)})"
    return (f"rho = {num(r.rho)} is not certified at r = 1 (r* = {num(r.radius, 4)}: the norm "
            "series diverges there, " + ("although the simulated pendulum stays bounded"
                                         if r.bounded else "and the simulated pendulum "
                                         "blows up") + f", peak {num(r.peak, 3)} rad)")


#: Sentences on the theta recursion by the number of sections (of two) that match.
_KEPT = ("neither section reproduces its theta_3", "one section reproduces its theta_3",
         "both sections reproduce their theta_3")
_DROPPED = ("neither does", "one does", "both do")


def _alpha_section(rows: Sequence[AlphaRow], readings: Sequence[ThetaReading] | None = None
                   ) -> tuple[list[str], str]:
    """Eq (2) (alpha = 1/(m L^2) kept) against eq (6) (alpha = 1): text and summary
    (``readings`` defaults to :func:`theta_readings` of the bundled models)."""
    if readings is None:
        readings = theta_readings(MODELS_DIR)
    by = {r.model: r for r in rows}
    eq2 = [by[Path(n).stem] for n in EQ2_MODELS]
    table_rows = [[f"[{r.model}](models/{r.model}.md)", r.alpha, r.rho, r.h1_norm, r.radius,
                   r.radius_proof, r.verdict, r.margin, r.bounded, r.peak] for r in rows]
    five = readings[-1]
    eq6, eq6_damped = by["hanging_pendulum"], by["hanging_pendulum_damped"]
    fold = eq6.alpha / eq2[0].alpha
    grows = eq2[1].radius / eq6_damped.radius
    same = abs(grows - fold) <= 1e-3 * fold
    text = [
        "## The hanging pendulum's input gain alpha", "",
        f"Eq (2) has the input gain alpha = 1/(m L^2) = {num(eq2[0].alpha)} on u; eq (6) "
        f"sets it to {num(eq6.alpha)} (the paper's rho_1 is the peak of H1 with unit gain: "
        f"||H1|| = {num(eq6.h1_norm, 4)}). Varying m or L with the gain frozen is physically "
        "inconsistent, so eq (2) is kept faithfully in "
        + " and ".join(f"[{Path(n).stem}](models/{Path(n).stem}.md)" for n in EQ2_MODELS)
        + "; eq (6)'s files stay as the paper's variant. Theorem 1 at the paper's r = 1 "
        "(`gfrf.papers.gfrf_paper.alpha_variants`; threshold from "
        "`gfrf verdict <file> --margin rho`; simulation: polynomial model, u = cos(w_r t) "
        f"at the resonance, {num(rows[0].t_end)} s):", "",
        table(["model", "alpha", "rho", "||H1||", "r*", "r* proof",
               "verdict at r = 1", "certified at r = 1 for rho >", "bounded at r = 1",
               "peak |theta| (rad)"], table_rows),
        f"With alpha kept, {_alpha_claim(eq2[0])}, and {_alpha_claim(eq2[1])}; "
        f"the threshold is rho > {num(eq2[1].margin, 5)} (eq (6): rho > "
        f"{num(eq6.margin, 5)}). The paper's conclusion for rho = {num(eq2[1].rho)} "
        + ("therefore holds" if _certified(eq2[1]) else "is not certified")
        + " for eq (2) - because the input gain "
        + ("shrinks" if fold > 1 else "grows") + f" ||H1|| {num(fold)}-fold "
        + ("(r* grows by the same factor)" if same else f"(r* grows {num(grows, 4)}-fold)")
        + ", a reason the paper does not give - and "
        + ("is certified" if _certified(eq6_damped) else "is not certified")
        + " for its own eq (6).", "",
        "**One reading of the theta recursion.** Theorem 2 prints theta_n = rho_1 sum "
        f"phi_m lambda_1^m ...; with that rho_1 prefactor "
        f"{_KEPT[min(2, sum(r.matches_kept for r in readings))]}, with it dropped "
        f"{_DROPPED[min(2, sum(r.matches_dropped for r in readings))]} (section 3 with "
        "phi_3 = its rho_3 and lambda_1 = 1, no controller; section 5 with the paper's "
        f"phi_3 = {num(five.phi3)}, lambda_1 = {num(five.lambda1)}). The paper's theta_3 = "
        f"{num(five.printed)} is " + ("" if five.matches_dropped else "not ")
        + f"{num(five.phi3)} x {num(five.lambda1)}^3 = {num(five.dropped, 4)}"
        + (": rho_1 dropped." if five.matches_dropped else "."), "",
        table(["section", "printed theta_3", "rho_1 (printed)", "phi_3", "lambda_1",
               "rho_1 phi_3 lambda_1^3 (as printed)", "phi_3 lambda_1^3 (rho_1 dropped)",
               "matches"],
              [[r.section, r.printed, r.rho1, r.phi3, r.lambda1, r.kept, r.dropped,
                "rho_1 dropped" if r.matches_dropped else
                ("as printed" if r.matches_kept else "neither")] for r in readings]),
    ]
    summary = (f"Theorem 1 (hanging pendulum): with eq (2)'s input gain alpha = "
               f"{num(eq2[0].alpha)} kept, rho = {num(eq2[1].rho)} is "
               + ("certified stable" if _certified(eq2[1]) else "not certified")
               + f" at r = 1 (r* = {num(eq2[1].radius, 4)}, threshold rho > "
               f"{num(eq2[1].margin, 4)}) and rho = {num(eq2[0].rho)} is "
               + ("also certified" if _certified(eq2[0]) else "not")
               + f" (r* = {num(eq2[0].radius, 3)}); eq (6) (alpha = {num(eq6.alpha)}) needs "
               f"rho > {num(eq6.margin, 4)}.")
    return text, summary


@dataclass(frozen=True, kw_only=True, repr=False)
class PaperGfrfFacts(Result):
    """Everything ``paper-gfrf.md`` states, computed before any sentence is written.

    :func:`render` fills :data:`PAGE` from these fields; each sentence that compares or
    states a property of the numbers is chosen by them (here, in :class:`FigureFacts`
    and in :class:`gfrf.report.paper_gfrf_cartpole.CartpoleFacts`).

    Attributes
    ----------
    rows : tuple of CheckRow
        Every printed number against ours.
    figures : FigureFacts
        Figures 3-6.
    cartpole : CartpoleFacts
        The cart-pole section.
    alpha : tuple of AlphaRow
        The hanging pendulum with and without eq (2)'s input gain.
    readings : tuple of ThetaReading
        The printed theta_3 against both readings of Theorem 2.
    stems : tuple of str
        The model pages linked, in table order.
    theorem_rows : list of list
        The Theorems 1 and 2 table.
    sim_rows : list of list
        The simulation table.
    margin : Margin
        The damping margin of eq (6) at r = 1.
    rho8 : float
        The damped pendulum's rho.
    radius8 : float
        Its r* (eq (6)).
    t_end : float
        The pendulums' simulation horizon (s).
    cart_radius : float
        The largest certified r* of the cart-poles (0 if none).
    out : str
        The report folder as written in the page's command.
    """

    rows: tuple[CheckRow, ...]
    figures: FigureFacts
    cartpole: CartpoleFacts
    alpha: tuple[AlphaRow, ...]
    readings: tuple[ThetaReading, ...]
    stems: tuple[str, ...]
    theorem_rows: list[list[object]]
    sim_rows: list[list[object]]
    margin: Margin
    rho8: float
    radius8: float
    t_end: float
    cart_radius: float
    out: str

    def unexplained(self) -> list[CheckRow]:
        """The rows that do not match and give no reason."""
        return [r for r in self.rows if not r.match and not r.reason]


def compute(out_dir: Path, quick: bool = False) -> PaperGfrfFacts:
    """Compute every number of the page and write its figures into ``out_dir``.

    Parameters
    ----------
    out_dir : Path
        The report folder (created if missing).
    quick : bool, optional
        Reduced setting (see :func:`gfrf.report.analysis.settings`).

    Returns
    -------
    PaperGfrfFacts
        The facts :func:`render` writes.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = paper_checks(MODELS_DIR)
    analyses = [analyse(str(MODELS_DIR / name), quick) for name in MODELS.values()]
    eq2 = [analyse(str(MODELS_DIR / name), quick) for name in EQ2_MODELS]
    pend, damped, cart12, cart16 = analyses
    cart = cartpole_facts(cart16.model_file, cart12.model_file, quick)
    cfg = settings(quick)
    ordered = [pend, eq2[0], damped, eq2[1], cart12, cart16]
    return PaperGfrfFacts(
        rows=tuple(rows), figures=figure_facts(out_dir, quick, rows), cartpole=cart,
        alpha=tuple(alpha_variants(MODELS_DIR, cfg["margin_tolerance"], cfg["t_end"])),
        readings=tuple(theta_readings(MODELS_DIR)), stems=tuple(a.stem for a in ordered),
        theorem_rows=_theorem_rows(ordered), sim_rows=_simulation_rows(ordered, cart.drives),
        margin=parameter_margin(pend.model_file, "rho", 1.0),
        rho8=damped.model_file.parameters["rho"], radius8=damped.verdict.radius,
        t_end=pend.t_end,
        cart_radius=max((a.verdict.radius for a in (cart12, cart16)
                         if a.verdict.radius_certified), default=0.0),
        out=out_dir.as_posix())


#: The page: one ``str.format`` layout; :func:`render` fills it from the facts.
PAGE = "\n".join([
    "{header}",
    "Paper: Cao Jianfu, Cao Fumin, *The robust stability analysis of a balance inverted "
    "pendulum* (`../shared/papers/001_2d500e4ecf148e2c.txt` beside this repository). "
    "Printed values are quoted from the model files' `[paper]` tables and from "
    "`gfrf.papers.gfrf_paper`; every other number is computed in this run. Certified: "
    "exact H1 norms, majorant upper bounds, r*; estimates: lower bounds found by search, "
    "radius estimates, simulations. Model pages: {model_pages}; timings: "
    "[speed-vs-error.md](speed-vs-error.md).",
    "",
    "## Every printed number",
    "",
    "A row matches when our value rounds to the printed one at the printed number of "
    "decimals. Section 3's theta_n are read as Theorem 2's recursion applied to the open "
    "loop (E = rho_1 r + rho_3 E^3).",
    "",
    "{check_table}",
    "{figures}",
    "{cartpole}",
    "{alpha}",
    "## Theorems 1 and 2: the paper's conclusions against the certified verdict",
    "",
    "The norm series is a power series in the input amplitude r (the paper tests r = 1); "
    "r* is its certified radius of convergence: the verdict is *stable* for every "
    "amplitude below r*.",
    "",
    "{theorem_table}",
    "Damping margin: Theorem 1 certifies the hanging pendulum of eq (6) at r = 1 for rho "
    "{direction} **{margin}** (file value {current}; bisection tolerance {tolerance}); "
    "`gfrf verdict models/hanging_pendulum.toml --margin rho`. The paper's claim for rho = "
    "{rho8} at r = 1 is certified only if r* > 1; for eq (6) r* = {radius8} ({claim8}); "
    "for eq (2) see the input-gain section above.",
    "",
    "## Simulations that confirm or refute the conclusions",
    "",
    "scipy RK45, fixed seed 0. Pendulums: the polynomial models (the object of the "
    "verdicts), horizon {t_end} s, inputs at r*/2, 2 r*, multiples of the radius estimate "
    "and the paper's r = 1; \"below r*\" compares the input size with the certified r*. "
    "Cart-poles: {cart_radius}, so \"below r*\" is n/a; each row names its equation - the "
    "truncated polynomial model or the untruncated physical equation (eqs (8)-(9), "
    "cartpole only; eq (16)'s file has no separate physical equation, so its runs are not "
    "repeated). Figures are on the model pages.",
    "",
    "{simulation_table}",
    "Trials below a certified r*: {below}; of these blew up (contradictions): "
    "{contradictions}. Cart-pole ideal loop: {angles_bounded}/{angles} initial-angle runs "
    "and {drives_bounded}/{drives} corner-frequency drives stay bounded - evidence about "
    "the idealised improper controller only (see the cart-pole section: any lag makes the "
    "loop diverge). Trials above r* that stay bounded do not refute the verdict: r* is a "
    "sufficient condition, not the true stability boundary.",
    "",
])


def render(f: PaperGfrfFacts) -> str:
    """The Markdown text of ``paper-gfrf.md`` from its facts.

    Parameters
    ----------
    f : PaperGfrfFacts
        The facts (:func:`compute`).

    Returns
    -------
    str
        The page.
    """
    cart_text, cart_summary = cartpole_text(f.cartpole)
    alpha_text, alpha_summary = _alpha_section(f.alpha, f.readings)
    below = [r for r in f.sim_rows if r[5] is True]
    angle_rows = [r for r in f.sim_rows if str(r[2]).startswith("initial angle")]
    drive_rows = [r for r in f.sim_rows if str(r[2]).startswith("cosine at") and
                  "linear angle" in str(r[2])]
    summary = [
        f"{sum(r.match for r in f.rows)} of {len(f.rows)} printed quantities are reproduced "
        "to the printed precision; " + ("every other row says why not" if not f.unexplained()
                                        else "not every other row says why not")
        + " (typo, sign slip, norm taken at the wrong point, series misjudged).",
        alpha_summary, cart_summary]
    m = f.margin
    return PAGE.format(
        header=header("The GFRF stability paper, reproduced", summary,
                      f"gfrf report --out {f.out}/"),
        model_pages=", ".join(f"[{s}](models/{s}.md)" for s in f.stems),
        check_table=check_table(list(f.rows)), figures="\n".join(figures_text(f.figures)),
        cartpole="\n".join(cart_text), alpha="\n".join(alpha_text),
        theorem_table=table(["model", "theorem", "paper's conclusion",
                             "our verdict at r = 1", "r*", "r* is",
                             "radius estimate (not certified)", "check"], f.theorem_rows),
        direction=m.direction, margin=num(m.value), current=num(m.current),
        tolerance=num(m.tolerance), rho8=num(f.rho8), radius8=num(f.radius8),
        claim8="certified" if f.radius8 > 1 else "not certified", t_end=num(f.t_end),
        cart_radius=("Theorem 2 gives no radius (r* = 0)" if f.cart_radius == 0 else
                     f"Theorem 2's largest certified r* is {num(f.cart_radius)}"),
        simulation_table=simulation_table(f.sim_rows), below=len(below),
        contradictions=sum(not r[6] for r in below),
        angles_bounded=sum(bool(r[6]) for r in angle_rows), angles=len(angle_rows),
        drives_bounded=sum(bool(r[6]) for r in drive_rows), drives=len(drive_rows))


def write(out_dir: Path, quick: bool = False) -> Path:
    """Write ``out_dir/paper-gfrf.md`` and its figures; return the Markdown path.

    Only this page (and its figures) is written; the model pages it links are written by
    :func:`gfrf.report.write_reports`.

    Parameters
    ----------
    out_dir : Path
        Report folder.
    quick : bool
        Reduced setting (see :func:`gfrf.report.analysis.settings`).

    Returns
    -------
    Path
        The path of ``paper-gfrf.md``.
    """
    facts = compute(out_dir, quick)
    return atomic_write_text(Path(out_dir) / "paper-gfrf.md", render(facts))
