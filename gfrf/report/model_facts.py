"""The facts of one model page, computed before :mod:`gfrf.report.model_page` renders them.

:func:`compute` runs :func:`gfrf.report.analysis.analyse`, draws the figures and keeps
every number and word the page states in a :class:`ModelPageFacts`; the page's
sentences (which amplitudes are proven, how many trials stay bounded, which brackets
are closed, how fast the nonlinear difference grows) are derived from these fields
only, so a test can render hand-made facts and see each sentence follow its numbers.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import sympy as sp

from gfrf._results import Result
from gfrf.bounds.norms import linear_poles
from gfrf.kernels.recursion import kernel
from gfrf.model.safetext import plot_text
from gfrf.report._figures import frequency_scale, h1_figure, h3_slice_figure, response_figure
from gfrf.report.analysis import ModelAnalysis, analyse
from gfrf.sim.validation import linear_vs_nonlinear, resonance_label
from gfrf.stability.verdicts import Verdict

__all__ = ["ModelPageFacts", "VerdictFacts", "NormFact", "MarginFact", "TrialFact",
           "ResponseFact", "compute", "command_path", "MAX_EXPLICIT"]

#: Longest explicit symbolic kernel shown in full; longer ones are shown recursively.
MAX_EXPLICIT = 700

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


@dataclass(frozen=True, kw_only=True, repr=False)
class NormFact(Result):
    """One bracket of ||H_n|| as the page prints it.

    Attributes
    ----------
    order : int
    lower, upper : float
        The bracket.
    certified : bool
        Whether the upper end is certified.
    argmax : tuple of float
        Where ``lower`` is attained (rad/s).
    """

    order: int
    lower: float
    upper: float
    certified: bool
    argmax: tuple[float, ...]

    @property
    def gap(self) -> float:
        """Relative gap (upper - lower) / upper (0 when the ends are equal)."""
        if self.upper == self.lower:
            return 0.0
        return math.inf if math.isinf(self.upper) else (self.upper - self.lower) / self.upper


@dataclass(frozen=True, kw_only=True, repr=False)
class VerdictFacts(Result):
    """What the page states of the verdict at r = 1.

    Attributes
    ----------
    theorem : int
        1 (open loop) or 2 (closed loop).
    verdict, summary : str
        The verdict and its sentence.
    radius : float
        r*.
    radius_certified : bool
    radius_proof : str
        ``"interval"``, ``"float"`` or ``"none"``.
    radius_upper : float or None
    radius_upper_detail : str
    radius_estimate : float or None
    estimate_of : str
        What the radius bounds (the series of the plant or of the loop).
    conditions : tuple of tuple
        ``(name, passed, detail)`` per condition.
    series : tuple of tuple
        ``(order, majorant, majorant_term, theta_term)`` per row.
    """

    theorem: int
    verdict: str
    summary: str
    radius: float
    radius_certified: bool
    radius_proof: str
    radius_upper: float | None
    radius_upper_detail: str
    radius_estimate: float | None
    estimate_of: str
    conditions: tuple[tuple[str, bool | None, str], ...]
    series: tuple[tuple[int, float, float, float | None], ...]

    @property
    def proven_radius(self) -> bool:
        """Whether r* > 0 is proven (certified, not an estimate): only then 'stable'."""
        return self.radius > 0 and self.radius_certified and self.radius_proof != "none"

    @classmethod
    def of(cls, v: Verdict) -> VerdictFacts:
        """The facts of a :class:`~gfrf.stability.verdicts.Verdict`.

        Parameters
        ----------
        v : Verdict
            The verdict.

        Returns
        -------
        VerdictFacts
        """
        return cls(theorem=v.theorem, verdict=v.verdict, summary=v.summary, radius=v.radius,
                   radius_certified=v.radius_certified, radius_proof=v.radius_proof,
                   radius_upper=v.radius_upper, radius_upper_detail=v.radius_upper_detail,
                   radius_estimate=v.radius_estimate, estimate_of=v.estimate_of,
                   conditions=tuple((c.name, c.passed, c.detail) for c in v.conditions),
                   series=tuple((r["order"], r["majorant"], r["majorant_term"],
                                 r.get("theta_term")) for r in v.series))


@dataclass(frozen=True, kw_only=True, repr=False)
class MarginFact(Result):
    """One ``[parameters]`` entry: its certified boundary, or why there is none.

    Attributes
    ----------
    parameter : str
    current : float
        The file value.
    note : str
        Why there is no margin (used when ``value`` is None).
    direction : str
        ``"above"`` or ``"below"``.
    value : float or None
        The certified boundary.
    tolerance : float
        The bisection tolerance.
    """

    parameter: str
    current: float
    note: str = ""
    direction: str = ""
    value: float | None = None
    tolerance: float = 0.0


@dataclass(frozen=True, kw_only=True, repr=False)
class TrialFact(Result):
    """One validation trial (a row of the trials table).

    Attributes
    ----------
    kind : str
    amplitude : float
    below_radius : bool or None
    bounded : bool
    peak : float
    blowup_time : float or None
    """

    kind: str
    amplitude: float
    below_radius: bool | None
    bounded: bool
    peak: float
    blowup_time: float | None


@dataclass(frozen=True, kw_only=True, repr=False)
class ResponseFact(Result):
    """One drawn time response.

    Attributes
    ----------
    label : str
    signal : str
        The input expression (open loop).
    initial_angle_deg : float
        The initial angle (closed loop).
    """

    label: str
    signal: str
    initial_angle_deg: float


@dataclass(frozen=True, kw_only=True, repr=False)
class ModelPageFacts(Result):
    """Everything ``reports/models/<stem>.md`` states, computed before it is written.

    ``to_dict`` leaves out the figure file names (``figures``), which are not results.

    Attributes
    ----------
    name, stem, path : str
        The model's name, file stem and path as printed in commands.
    regenerate : str
        The command that regenerates the page.
    source, description : str
        From the model file (user text: escaped when rendered).
    equation_text, polynomial : str
        The equation as written and the polynomial model.
    truncation : int
        Taylor truncation order (0: none).
    sample_time : float or None
        NARX sample time (None: continuous time).
    parameters : tuple of tuple
        ``(name, value)`` of ``[parameters]``.
    coefficients : tuple of tuple
        ``(monomial, coefficient, kind)`` rows.
    controller : str
        The controller sentence (empty without one).
    kernels : tuple of str
        LaTeX of H1, H2, H3.
    discrete, closed : bool
        NARX model; model with a controller.
    w3 : float or None
        w3 of the |H3| slice (None: H3 vanishes).
    norms : tuple of NormFact
    norm_notes : tuple of str
        The brackets' notes without CPU-dependent numbers.
    order : int
        Highest norm order of the verdict.
    verdict : VerdictFacts
    margins : tuple of MarginFact
    t_end : float
        Simulation horizon (s).
    output : str
        The output variable.
    responses : tuple of ResponseFact
    trials : tuple of TrialFact or None
        None: no input trials (no positive radius to scale them).
    trial_scale : float
    trial_scale_certified : bool
    contradictions : int
        Trials below r* that blew up.
    resonance : str
        The drive frequency in words.
    growth : tuple of tuple
        ``(angle_deg, max_abs_error, relative_error)`` of the closed loop's
        nonlinear-minus-linear difference (empty for an open loop).
    figures : dict of str to str
        ``h1``, ``h3`` (absent when H3 vanishes) and ``sim`` PNG file names.
    """

    name: str
    stem: str
    path: str
    regenerate: str
    source: str
    description: str
    equation_text: str
    polynomial: str
    truncation: int
    sample_time: float | None
    parameters: tuple[tuple[str, float], ...]
    coefficients: tuple[tuple[str, object, str], ...]
    controller: str
    kernels: tuple[str, ...]
    discrete: bool
    closed: bool
    w3: float | None
    norms: tuple[NormFact, ...]
    norm_notes: tuple[str, ...]
    order: int
    verdict: VerdictFacts
    margins: tuple[MarginFact, ...]
    t_end: float
    output: str
    responses: tuple[ResponseFact, ...]
    trials: tuple[TrialFact, ...] | None
    trial_scale: float
    trial_scale_certified: bool
    contradictions: int
    resonance: str
    growth: tuple[tuple[float, float, float], ...]
    figures: dict[str, str]

    _exclude = ("figures",)


def _latex(a: ModelAnalysis, n: int) -> str:
    k = kernel(a.model_file.plant, n)
    if k.is_zero:
        return f"H_{{{n}}} = 0"
    expr = k.expr
    if len(str(expr)) > MAX_EXPLICIT:
        expr = k.recursive_expr
    return f"H_{{{n}}} = {sp.latex(expr)}"


def _controller(a: ModelAnalysis) -> str:
    from gfrf.model.safetext import markdown_text
    from gfrf.report._format import cell

    ctrl = a.model_file.controller
    if ctrl is None:
        return ""
    loop_text = "u = C(r - y)" if ctrl.feedback == -1 else "u = C(r + y)"
    return (f"Controller: {markdown_text(ctrl.name or 'linear')} "
            f"({markdown_text(ctrl.source)}). C(s) = num/den with "
            f"num = {cell(list(ctrl.num or ()))}, den = {cell(list(ctrl.den or ()))} "
            f"(highest power first), loop {loop_text}.")


def _figures(a: ModelAnalysis, folder: Path) -> tuple[dict[str, str], float | None]:
    """Draw H1, the |H3| slice (when H3 does not vanish) and the responses."""
    plant = a.model_file.plant
    poles = linear_poles(plant)
    kind = ("" if poles.stable else "\nL∞ gain of an unstable plant" if poles.outside
            else "\nL∞ gain of a plant with poles on the stability boundary")
    name = plot_text(a.model_file.name, limit=80)
    figures = {"h1": h1_figure(plant, folder / f"{a.stem}-h1.png", title=f"H1 of {name}{kind}")}
    norm3 = a.verdict.norms[2] if len(a.verdict.norms) >= 3 else None
    w3 = None
    if norm3 is not None and norm3.upper > 0:
        w3 = norm3.argmax[2]
        half = 2.5 * max(frequency_scale(plant) if not plant.is_discrete else 0.0,
                         max(abs(x) for x in norm3.argmax), 1e-3)
        if plant.is_discrete:
            half = frequency_scale(plant)
        figures["h3"] = h3_slice_figure(plant, folder / f"{a.stem}-h3.png", w3, half,
                                        title=f"|H3(jw1, jw2, jw3)| at w3 = {w3:.4g} rad/s")
    kind = ("closed loop from initial angles, zero reference" if a.closed else
            "sinusoidal input at the H1 peak, below and above r*")
    figures["sim"] = response_figure(a.responses, folder / f"{a.stem}-sim.png",
                                     f"{name}:\n{kind}", f"{plant.output}(t)")
    return figures, w3


def compute(path: str, out_dir: Path, quick: bool = False) -> ModelPageFacts:
    """Analyse the model file at ``path`` and draw its figures into ``out_dir/models``.

    Parameters
    ----------
    path : str
        A GFRF model file.
    out_dir : Path
        Report root (the figures go to its ``models/`` folder).
    quick : bool, optional
        Reduced setting (see :func:`gfrf.report.analysis.settings`).

    Returns
    -------
    ModelPageFacts
        The facts :func:`gfrf.report.model_page.render` writes.
    """
    a = analyse(str(path), quick)
    mf, plant, v = a.model_file, a.model_file.plant, a.verdict
    folder = Path(out_dir) / "models"
    folder.mkdir(parents=True, exist_ok=True)
    figures, w3 = _figures(a, folder)
    val = a.validation
    growth = (tuple((r["angle_deg"], r["max_abs_error"], r["relative_error"])
                    for r in (linear_vs_nonlinear(mf, angle) for angle in (5.0, 10.0, 15.0)))
              if a.closed and val is not None else ())
    margins = tuple(
        MarginFact(parameter=s.parameter, current=s.current, note=s.note) if s.margin is None
        else MarginFact(parameter=s.parameter, current=s.current, direction=s.margin.direction,
                        value=s.margin.value, tolerance=s.margin.tolerance)
        for s in a.margins)
    return ModelPageFacts(
        name=mf.name, stem=a.stem, path=command_path(a.path),
        regenerate=f"gfrf report {command_path(a.path)} --out {Path(out_dir).as_posix()}/",
        source=mf.source or "", description=mf.description or "",
        equation_text=plant.text.strip(), polynomial=plant.equation(),
        truncation=plant.truncation or 0,
        sample_time=plant.sample_time if plant.is_discrete else None,
        parameters=tuple(mf.parameters.items()) if mf.parameters else (),
        coefficients=tuple((r["monomial"], r["coefficient"], r["kind"])
                           for r in plant.coefficient_table()),
        controller=_controller(a), kernels=tuple(_latex(a, n) for n in (1, 2, 3)),
        discrete=plant.is_discrete, closed=a.closed, w3=w3,
        norms=tuple(NormFact(order=b.order, lower=b.lower, upper=b.upper,
                             certified=b.certified, argmax=tuple(b.argmax)) for b in v.norms),
        norm_notes=tuple(sorted({_stable_note(note) for b in v.norms for note in b.notes})),
        order=a.order, verdict=VerdictFacts.of(v), margins=margins, t_end=a.t_end,
        output=plant.output,
        responses=tuple(ResponseFact(label=r.label, signal=r.signal,
                                     initial_angle_deg=r.initial_angle_deg)
                        for r in a.responses),
        trials=None if val is None else tuple(
            TrialFact(kind=t.kind, amplitude=t.amplitude, below_radius=t.below_radius,
                      bounded=t.bounded, peak=t.peak, blowup_time=t.blowup_time)
            for t in val.trials),
        trial_scale=a.trial_scale, trial_scale_certified=a.trial_scale_certified,
        contradictions=0 if val is None else len(val.contradictions),
        resonance=resonance_label(plant), growth=growth, figures=figures)
