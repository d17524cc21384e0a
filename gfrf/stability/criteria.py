"""Theorems 1 and 2 of the GFRF stability paper, with a rigorous series decision.

Theorem 1 (open loop, eq (1) models).  The system is L2 stable if
  1) every H_n is a proper rational function,
  2) A_1(s) = sum_p a_{1,p} s^p is Hurwitz (all zeros in the open left half plane),
  3) the norm series sum_n ||H_n||_inf converges.

Theorem 2 (closed loop, plant kernels h_n, controller kernels s_n, reference r).
The tracking loop is internally L2 stable if
  1) all h_n and s_n are proper rational functions,
  2) the linear closed loop is L2 stable,
  3) with beta_n = ||h_n||, lambda_1 = ||s_1|| > 0, lambda_n = ||s_n|| <= alpha_n lambda_1^n,
     phi_1 = beta_1, phi_n = sum_{m=1}^n beta_m sum_{k_1+..+k_m=n} alpha_{k_1}..alpha_{k_m},
     rho_1 = ||g_1||, theta_1 = 1,
     theta_n = rho_1 sum_{m=2}^n phi_m lambda_1^m sum_{k_1+..+k_m=n} theta_{k_1}..theta_{k_m},
     the series sum phi_m lambda_1^m and sum theta_n rho_1^n converge,
  4) the reference spectrum is absolutely integrable.

How the ambiguous symbols are read
----------------------------------
* rho_1.  Theorem 2 prints ||g_1|| = sup|(1 + h_1) s_1|; section 5 computes
  rho_1 = sup|(1 + h_1 s_1)^{-1}|, the sensitivity peak.  Only the latter makes the
  theta recursion a bound: the loop error e solves (1 + h_1 s_1) e_1 = r at first
  order and e_n = -g_1 [sum_{m>=2} N_m(e, .., e)]_n with ||N_m|| <= phi_m lambda_1^m, so
  ||e_n|| <= theta_n rho_1^n by induction.  We use the sensitivity peak
  (:attr:`gfrf.stability.loops.ClosedLoop.sensitivity_peak`) and report the literal reading too.
* alpha_1.  Undefined in the paper; lambda_1 = alpha_1 lambda_1 forces alpha_1 = 1.  A
  linear controller has lambda_n = alpha_n = 0 for n >= 2 ("<" read as "<="), so
  phi_n = beta_n.
* beta_n for an unstable plant (the inverted pendulum) is the sup of |h_n| on the
  frequency axis (an L-infinity, not H-infinity, norm), as the paper's beta_1 = 0.58 is.
* Section 3 applies Theorem 2's theta recursion to the open-loop pendulum with
  rho_1 := ||H_1|| and rho_3 := |c_3| sup|1/A| (the cubic term's gain, not ||H_3||).
  That recursion is exactly the generating function of our majorant
  E = rho_1 r + rho_3 E^3 (see :mod:`gfrf.papers.gfrf_paper`); Theorem 1 is decided here
  with the certified majorant of every ||H_n|| instead.
* "converges".  Every series is a power series in the input amplitude r (the paper
  tests r = 1).  Its radius r* is computed from the certified majorant's generating
  function (:mod:`gfrf.bounds.majorant`): the verdict says the series converges for every
  amplitude below r*, and whether the requested amplitude is inside.  Beyond r* the
  majorant diverges, which decides nothing: the condition is then "not established"
  (``passed = None``).
* Three radii, never confused.  ``radius``: r*, the proven (certified) lower bound on
  the radius of the theorem's series.  ``radius_upper``: a proven upper bound on the
  true radius of the norm series sum ||H_n|| r^n (the plant's, for Theorem 2), from
  the static branch point of the zero-frequency kernels
  (:func:`gfrf.stability.static.radius_upper`),
  where one is proven.  ``radius_estimate``: a many-term estimate of that true radius
  (:func:`gfrf.stability.static.radius_estimate`), clamped into [lower bound, ``radius_upper``]: an
  estimate, never a proof and never the ground of a verdict.

Verdicts: ``stable`` when every condition holds (certified); ``unstable`` when the
linearisation has a pole in the open right half plane (Lyapunov's indirect method:
the equilibrium is unstable; the theorem is then inapplicable); ``inconclusive``
otherwise.  Angular frequencies are in rad/s throughout.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> v = theorem1(parse_model("D(y,2) + D(y) + 2*y + y**3 = u"), order=3, amplitude=0.1)
>>> v.verdict, round(v.radius, 4), [c.passed for c in v.conditions]
('stable', 0.5856, [True, True, True])
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf._results import markdown_table, plain, short_repr, verdict_figure, verdict_markdown
from gfrf.bounds.exact import format_roots
from gfrf.bounds.majorant import Majorant, Radius, certify, majorant, plant_radius, radius
from gfrf.bounds.norms import Bound, kernel_norm, linear_poles
from gfrf.bounds.rational import check_proof, rational_sup
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import MAX_KERNEL_ORDER
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile, model_from_dict

__all__ = ["Condition", "Verdict", "Margin", "theorem1", "theorem2", "verdict",
           "parameter_margin", "theta_series", "phi_series", "NORM_LEVELS", "DEFAULT_NORMS"]

#: Tightness of the ||H_n|| brackets a verdict prints.  ``"none"``: no brackets and no
#: radius estimate (the series rows carry the majorant only); ``"fast"``: the certified
#: majorant as upper end and one local search from the best resonance start as lower end
#: (no branch-and-bound); ``"tight"``: the full :func:`gfrf.bounds.norms.kernel_norm`
#: (branch-and-bound within its box budget, every local search).  ``radius_upper`` and
#: ``radius_estimate`` are computed at ``fast`` and ``tight``.  The conclusions
#: (conditions, verdict, r* and its proof label) never depend on the level.
#: ``with_norms=False`` (sweeps, margins) is ``norms="none"``.
NORM_LEVELS = ("none", "fast", "tight")
#: Level used when none is given (``gfrf verdict --norms``, ``norms=``).
DEFAULT_NORMS = "fast"


@dataclass(frozen=True)
class Condition:
    """One hypothesis of a theorem: ``passed`` True, False, or None (not established)."""

    name: str
    passed: bool | None
    value: Any
    detail: str

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {"name": self.name, "passed": self.passed, "value": plain(self.value),
                "detail": self.detail}


@dataclass(frozen=True)
class Verdict:
    """Outcome of Theorem 1 or 2 for one model and input amplitude.

    Attributes
    ----------
    verdict : str
        ``stable`` (every condition proven), ``inconclusive`` or ``unstable``.
    theorem : int
        1 (open loop) or 2 (closed loop).
    radius : float
        r*: the certified series converges for every amplitude r < r*.
    radius_certified : bool
        True when r* comes from certified sups (levels ``interval`` and ``float``).
    amplitude : float
        The input amplitude r tested (the paper's r = 1).
    conditions : tuple of Condition
    norms : tuple of Bound
        ||H_n|| brackets (plant) for n = 1..order.
    series : tuple of dict
        Per order n: the series terms (certified majorant and estimates).
    radius_estimate : float or None
        Estimate of the true radius of the norm series (the plant's for Theorem 2):
        a fit to many terms of a lower-bound series, clamped into [proven lower bound,
        ``radius_upper``].  An estimate only: no verdict rests on it.
    summary : str
        One sentence.
    radius_proof : str
        ``"interval"``: convergence at the certified end of r* re-checked in ball
        arithmetic on proven sups (Theorems 1 and 2); ``"float"``: certified in double
        precision; ``"none"``: an estimate.
    radius_upper : float or None
        Proven upper bound on the true radius of the norm series (the plant's for
        Theorem 2): the modulus of a static branch point (:mod:`gfrf.stability.static`).
    radius_upper_detail : str
        Where ``radius_upper`` comes from (the branch point and fold), or why absent.
    estimate_of : str
        Which series ``radius_upper`` and ``radius_estimate`` are about.
    estimate_lower : float or None
        The proven lower bound of that series the estimate was clamped to (r* for
        Theorem 1, the plant majorant's radius for Theorem 2).
    """

    verdict: str
    theorem: int
    radius: float
    radius_certified: bool
    amplitude: float
    conditions: tuple[Condition, ...]
    norms: tuple[Bound, ...] = field(default=())
    series: tuple[dict[str, Any], ...] = field(default=())
    radius_estimate: float | None = None
    summary: str = ""
    radius_proof: str = "float"
    radius_upper: float | None = None
    radius_upper_detail: str = ""
    estimate_of: str = ""
    estimate_lower: float | None = None

    def __repr__(self) -> str:
        return short_repr(self, "verdict", "theorem", "radius", "amplitude")

    def _repr_markdown_(self) -> str:
        return verdict_markdown(self)

    def plot(self) -> Any:
        """The norm series: ||H_n|| and the certified majorant c_n against n, and the
        root-test radii c_n^(-1/n) with r*, the amplitude r and the proven upper bound.

        Returns
        -------
        matplotlib.figure.Figure
            Made without pyplot (works with any backend; display it or ``savefig``).
        """
        return verdict_figure(self)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (the ``--json`` output of ``gfrf verdict``)."""
        return {"verdict": self.verdict, "theorem": self.theorem, "radius": self.radius,
                "radius_certified": self.radius_certified, "amplitude": self.amplitude,
                "conditions": [c.to_dict() for c in self.conditions],
                "norms": [b.to_dict() for b in self.norms], "series": list(self.series),
                "radius_estimate": self.radius_estimate, "summary": self.summary,
                "radius_proof": self.radius_proof, "proof": self.radius_proof,
                "radius_upper": self.radius_upper,
                "radius_upper_detail": self.radius_upper_detail,
                "estimate_of": self.estimate_of, "estimate_lower": self.estimate_lower,
                "radius_kinds": {
                    "radius": f"lower bound r* of the {_SERIES[self.theorem]}, "
                              + (_label(self.radius_proof) if self.radius_certified
                                 else "estimate (not certified)"),
                    "radius_upper": f"proven upper bound on the true radius of the "
                                    f"{self.estimate_of} (static branch point)",
                    "radius_estimate": f"estimate of the true radius of the {self.estimate_of}"
                                       " (not a proof; never decides a verdict)"}}


_SERIES = {1: "norm series sum ||H_n|| r^n", 2: "loop series sum theta_n rho_1^n r^n"}


def _check_amplitude(amplitude: float, order: int) -> None:
    if not (isinstance(amplitude, float | int) and math.isfinite(amplitude) and amplitude > 0):
        raise ArgumentError(f"amplitude must be a positive finite number, got {amplitude!r}")
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ArgumentError(f"order must be a positive integer, got {order!r}")
    if order > MAX_KERNEL_ORDER:  # before any norm is computed
        raise ArgumentError(f"order {order} exceeds MAX_KERNEL_ORDER = {MAX_KERNEL_ORDER}")


def _proper_condition(model: Model, maj: Majorant, what: str) -> Condition:
    """Condition 1: bounded kernels.  Improper H1 fails; an infinite majorant is undecided."""
    a, b = model.linear_output, model.linear_input
    if b and max(b) > max(a):
        return Condition(f"{what}: proper rational kernels", False, math.inf,
                         f"H1 improper: input derivative order {max(b)} > output order "
                         f"{max(a)}")
    if not maj.finite:
        return Condition(f"{what}: proper rational kernels", None, math.inf,
                         "not established: " + "; ".join(maj.reasons))
    return Condition(f"{what}: proper rational kernels", True, None,
                     "every H_n bounded by the finite certified majorant (hence proper on "
                     "the frequency axis)")


def _stability_condition(model: Model) -> tuple[Condition, str]:
    """Condition 2, decided exactly (Routh's test in rationals, exact boundary roots)."""
    report = linear_poles(model)
    kind = "|z| < 1" if model.is_discrete else "Re s < 0"
    values = [complex(p) for p in report.roots]
    if report.stable:
        return Condition("linear part A_1 stable", True, values,
                         f"all poles have {kind} (exact test on the given coefficients)"), ""
    if report.outside:
        detail = ("pole outside the stability region (exact test): the equilibrium is "
                  "unstable (Lyapunov's indirect method); Theorem 1 is inapplicable")
    else:
        detail = ("pole on the stability boundary at "
                  + format_roots(report.boundary, "z" if model.is_discrete else "s")
                  + " (exact test): Theorem 1 is inapplicable")
    return Condition("linear part A_1 stable", False, values, detail), \
        "unstable" if report.outside else "inconclusive"


#: Local searches of a ``fast`` bracket's lower end (from the best resonance start).
FAST_SEARCHES = 1


def _norm_level(with_norms: bool, norms: str | None) -> str:
    """The bracket level from ``with_norms`` (legacy switch) and ``norms``."""
    if norms is None:
        return DEFAULT_NORMS if with_norms else "none"
    if norms not in NORM_LEVELS:
        raise ArgumentError(f"norms must be one of {', '.join(NORM_LEVELS)}, got {norms!r}")
    if not with_norms and norms != "none":
        raise ArgumentError(f"with_norms=False contradicts norms={norms!r}; give norms alone")
    return norms


def _norms_and_series(model: Model, maj: Majorant, order: int, amplitude: float,
                      level: str) -> tuple[tuple[Bound, ...], tuple[dict[str, Any], ...]]:
    """The brackets at ``level`` (each computed once) and the majorant rows of the series."""
    coefficients = maj.coefficients(order)[:, 0]
    norms, rows = [], []
    for n in range(1, order + 1):
        bound = (None if level == "none" else
                 kernel_norm(model, n, proof=maj.proof, progress=None) if level == "tight" else
                 kernel_norm(model, n, proof=maj.proof, max_boxes=0, searches=FAST_SEARCHES))
        if bound is not None:
            norms.append(bound)
        upper = bound.upper if bound is not None else float(coefficients[n])
        rows.append({"order": n, "lower": bound.lower if bound else None, "upper": upper,
                     "majorant": float(coefficients[n]),
                     "majorant_term": _majorant_term(float(coefficients[n]), amplitude, n)})
    return tuple(norms), tuple(rows)


def _majorant_term(coefficient: float, amplitude: float, n: int) -> float:
    """coefficient * amplitude**n; inf when it overflows (not proven to converge), 0 for 0."""
    if coefficient == 0.0:
        return 0.0
    if not math.isfinite(coefficient):
        return math.inf
    try:
        return coefficient * amplitude ** n
    except OverflowError:
        return math.inf


@dataclass(frozen=True)
class _Radii:
    """Proven upper bound and estimate of a norm series' true radius."""

    upper: float | None
    detail: str
    estimate: float | None
    lower: float
    clamp: str = ""

    def text(self) -> str:
        """The clause appended to a series condition."""
        out = ""
        if self.upper is not None:
            out += f"; true radius proven <= {self.upper:.6g} ({self.detail})"
        if self.estimate is not None:
            out += f"; estimate of the true radius {self.estimate:.4g} (not a proof{self.clamp})"
        return out


def _radii(model: Model, maj: Majorant, lower: float, with_estimate: bool,
           proof: str) -> _Radii:
    """radius_upper and radius_estimate of ``model``'s norm series (both skipped for
    margins and sweeps, ``with_estimate`` False); ``maj`` is its majorant.  The upper
    bound is reported at the ``interval`` level only (it is proven in ball arithmetic);
    the estimate is clamped by it at every level."""
    if not with_estimate:
        return _Radii(None, "not computed (norms off)", None, lower)
    pole = next((r for r in maj.reasons
                 if r.startswith("sup|s^0 H1| infinite: pole on the") and "exact test" in r),
                None)
    if pole is not None:  # ||H1|| = inf: the series diverges for every r > 0
        return _Radii(0.0 if proof == "interval" else None,
                      f"||H1|| = inf, {pole.split(': ', 1)[1]}", None, lower)
    from gfrf.stability.static import radius_estimate, radius_upper

    bound = radius_upper(model)
    upper = None if bound is None else bound.value
    detail = ("no static branch point proven (no finite static gain, a polynomial static "
              "map, or the tracking budget ran out)" if bound is None else bound.detail)
    est = radius_estimate(model, lower, upper)
    if proof != "interval":
        upper, detail = None, f"not reported at proof level {proof!r} (use 'interval')"
    if est is None:
        return _Radii(upper, detail, None, lower)
    clamp = ("" if est.value == est.fitted else
             f"; the fit gave {est.fitted:.4g}, clamped to the "
             f"{'upper' if est.value < est.fitted else 'lower'} bound")
    return _Radii(upper, detail, est.value, lower, clamp)


def theorem1(model: Model, order: int = 5, amplitude: float = 1.0,
             with_norms: bool = True, proof: str = "interval", *,
             norms: str | None = None) -> Verdict:
    """Theorem 1 (open loop) for ``model`` at input amplitude ``amplitude``.

    Parameters
    ----------
    model : Model
    order : int
        Highest order whose norm bracket is reported (the decision uses all orders).
    amplitude : float
        Input amplitude r (the paper's test is r = 1).
    with_norms : bool
        False is ``norms="none"`` (margins, sweeps).
    proof : {"interval", "float", "none"}
        Level of proof (see :data:`gfrf.bounds.rational.PROOF_LEVELS`).  ``"interval"``
        (default): proven sups, majorant bounds and r* in ball arithmetic;
        ``"float"``: the same sound method in double precision; ``"none"``: estimates,
        which never give ``stable``.  Stability of A is decided exactly at every level.
    norms : {"none", "fast", "tight"}, optional
        Tightness of the printed ||H_n|| brackets (:data:`NORM_LEVELS`); default
        ``"fast"`` (:data:`DEFAULT_NORMS`): the certified majorant as upper end and one
        local search as lower end.  ``"tight"`` adds the branch-and-bound and every
        local search; ``"none"`` prints no bracket and no radius estimate.  The verdict,
        r* and the conditions are the same at every level.

    Returns
    -------
    Verdict
    """
    _check_amplitude(amplitude, order)
    check_proof(proof)
    level = _norm_level(with_norms, norms)
    maj = majorant(model, proof)
    proper = _proper_condition(model, maj, "H_n")
    stable, bad = _stability_condition(model)
    rad = plant_radius(maj)
    norms, rows = _norms_and_series(model, maj, order, amplitude, level)
    radii = _radii(model, maj, rad.value if maj.certified else 0.0, level != "none", proof)
    series = _series_condition("norm series sum ||H_n|| r^n converges", rad, amplitude,
                               maj.certified, radii.text())
    conditions = (proper, stable, series)
    result = bad or ("stable" if all(c.passed for c in conditions) else "inconclusive")
    summary = _summary(result, 1, rad, amplitude, conditions, maj.certified)
    if radii.upper is not None or radii.estimate is not None:
        summary += " The norm series:" + radii.text().lstrip(";") + "."
    return Verdict(result, 1, rad.value, maj.certified, float(amplitude), conditions, norms, rows,
                   radii.estimate, summary, rad.proof, radii.upper, radii.detail,
                   "norm series sum ||H_n|| r^n", radii.lower if level != "none" else None)


def _series_condition(name: str, rad: Radius, amplitude: float, exact: bool,
                      est: str = "") -> Condition:
    label = _label(rad.proof) if exact else "not certified"
    if amplitude < rad.certified_below:
        return Condition(name, True if exact else None, rad.value,
                         f"majorant converges for r < r* = {rad.value:.6g} ({label}); "
                         f"r = {amplitude:g} is inside{est}")
    return Condition(name, None, rad.value,
                     f"not established: the majorant diverges for r >= r* = {rad.value:.6g} "
                     f"({label}) and r = {amplitude:g} is outside{est}")


def _summary(result: str, theorem: int, rad: Radius, amplitude: float,
             conditions: tuple[Condition, ...], certified: bool) -> str:
    failed = [c.name for c in conditions if c.passed is False]
    open_ = [c.name for c in conditions if c.passed is None]
    kind = _label(rad.proof) if certified else "estimated (not certified)"
    text = (f"Theorem {theorem}: {result}. The {kind} norm series converges for every "
            f"input amplitude r < r* = {rad.value:.6g}; r = {amplitude:g} is "
            f"{'inside' if amplitude < rad.certified_below else 'outside'}.")
    if failed:
        text += " Failed: " + "; ".join(failed) + "."
    if open_:
        text += " Not established: " + "; ".join(open_) + "."
    return text


def _label(proof: str) -> str:
    """How a number at a level of proof is called in text."""
    return {"interval": "proven", "float": "certified (float)"}.get(proof, "estimate")


def theta_series(phi: list[float], lambda1: float, rho1: float, order: int) -> list[float]:
    """theta_1..theta_order of Theorem 2 from phi_1..phi_order (index 0 is phi_1).

    theta_1 = 1, theta_n = rho_1 sum_{m=2}^n phi_m lambda_1^m [x^n] Theta(x)^m, with
    Theta(x) = sum theta_k x^k (the sum over compositions k_1 + .. + k_m = n).
    An infinite rho_1 (a closed-loop pole on the axis) or phi_m bounds nothing:
    theta_n = inf for n >= 2.
    """
    if not (math.isfinite(rho1) and all(math.isfinite(p) for p in phi[:order])):
        return [1.0] + [math.inf] * (order - 1)
    theta = np.zeros(order + 1)
    theta[1] = 1.0
    for n in range(2, order + 1):
        total = 0.0
        power = theta.copy()  # Theta^1, truncated
        for m in range(2, n + 1):
            power = np.convolve(power, theta)[: order + 1]
            if phi[m - 1]:
                total += phi[m - 1] * lambda1 ** m * power[n]
        theta[n] = rho1 * total
    return theta[1:].tolist()


def phi_series(beta: list[float], alpha: list[float], order: int) -> list[float]:
    """phi_1..phi_order: phi_n = sum_m beta_m sum_{k_1+..+k_m=n} alpha_{k_1}..alpha_{k_m}.

    ``beta[0]`` is beta_1 and ``alpha[0]`` is alpha_1 (= 1); phi_1 = beta_1.
    """
    a = np.zeros(order + 1)
    a[1:len(alpha) + 1] = alpha[:order]
    phi = np.zeros(order + 1)
    power = np.zeros(order + 1)
    power[0] = 1.0
    for m in range(1, order + 1):
        power = np.convolve(power, a)[: order + 1]
        if beta[m - 1]:
            with np.errstate(invalid="ignore"):  # 0 * inf: an absent term adds nothing
                phi += np.where(power > 0, beta[m - 1] * power, 0.0)
    return phi[1:].tolist()


def theorem2(model_file: ModelFile, order: int = 5, amplitude: float = 1.0,
             with_norms: bool = True, proof: str = "interval", *,
             norms: str | None = None) -> Verdict:
    """Theorem 2 (closed loop) for a model file with a controller.

    A transfer-function controller has lambda_n = alpha_n = 0 (n >= 2).  A polynomial
    controller (``[controller] equation``) gets its own certified majorant M^c_n >=
    lambda_n, and alpha_n = M^c_n / lambda_1^n; then sum_n phi_n lambda_1^n is the plant
    majorant evaluated at the controller majorant C(1), and the theta series has the
    generating function E = rho_1 r + rho_1 [B(C(E)) - beta_1 lambda_1 E].

    Parameters
    ----------
    model_file : ModelFile
        Plant and controller.
    order, amplitude, with_norms, proof, norms
        As in :func:`theorem1` (default ``norms="fast"``); the amplitude scales the
        reference r.  At the interval level the loop radius is re-checked in ball
        arithmetic with the proven upper ends of rho_1 and lambda_1.

    Returns
    -------
    Verdict
    """
    _check_amplitude(amplitude, order)
    check_proof(proof)
    level = _norm_level(with_norms, norms)
    controller = model_file.controller
    if controller is None:
        raise ArgumentError("Theorem 2 needs a controller; use theorem1 for an open loop")
    plant = model_file.plant
    from gfrf.stability.loops import closed_loop  # imports python-control: Theorem 2 only

    loop = closed_loop(model_file, proof=proof)
    maj = majorant(plant, proof)
    cmaj = (None if controller.is_linear else
            majorant(controller.model, proof))  # type: ignore[arg-type]
    lam, rho1 = loop.controller_norm, loop.sensitivity_peak
    plant_proper = _proper_condition(plant, maj, "plant h_n")
    ctrl_ok = loop.controller_proper and math.isfinite(lam) and (cmaj is None or cmaj.finite)
    c1 = Condition("plant h_n and controller s_n proper rational",
                   False if not ctrl_ok or plant_proper.passed is False else plant_proper.passed,
                   {"lambda_1": lam}, ("controller improper or unbounded: lambda_1 = "
                                       f"{lam:g}; " if not ctrl_ok else "controller proper; ")
                   + plant_proper.detail)
    c2 = Condition("linear closed loop L2 stable", loop.stable,
                   [complex(p) for p in loop.poles],
                   "characteristic polynomial " + _poly_text(loop.characteristic)
                   + ("" if loop.stable else "; " + "; ".join(loop.notes)))
    alpha = ([1.0] + [0.0] * (order - 1) if cmaj is None or not ctrl_ok else
             [float(m) / lam ** n for n, m in
              enumerate(cmaj.coefficients(order)[1:, 0], start=1)])
    c3 = Condition("lambda_1 > 0 finite, lambda_n <= alpha_n lambda_1^n", ctrl_ok and lam > 0,
                   {"lambda_1": lam, "alpha": alpha},
                   "linear controller: lambda_n = alpha_n = 0 for n >= 2, phi_n = beta_n"
                   if cmaj is None else "alpha_n = M^c_n / lambda_1^n from the controller's "
                   "certified majorant M^c_n >= lambda_n")
    plant_rad = plant_radius(maj)
    norms, rows = _norms_and_series(plant, maj, order, amplitude, level)
    radii = _radii(plant, maj, plant_rad.value if maj.certified else 0.0, level != "none",
                   proof)
    exact = maj.certified and (cmaj is None or cmaj.certified)
    lam_up, rho1_up = loop.controller_norm_upper, loop.sensitivity_peak_upper
    if ctrl_ok:
        c_at_1 = lam_up if cmaj is None else _controller_output(cmaj)
        phi_ok = c_at_1 < plant_rad.certified_below
        c4 = Condition("sum phi_m lambda_1^m converges", phi_ok if exact else None,
                       {"controller_majorant_at_1": c_at_1, "plant_radius": plant_rad.value},
                       f"the series is the plant majorant at amplitude C(1) = {c_at_1:.6g} "
                       f"(C = controller majorant; lambda_1 for a linear controller), "
                       f"plant radius {plant_rad.value:.6g}")
        rad = _loop_radius(maj, lam_up, rho1_up, cmaj)
    else:
        c4 = Condition("sum phi_m lambda_1^m converges", False, {"lambda_1": lam},
                       "lambda_1 = inf: the series diverges from its second term")
        rad = Radius(0.0, 0.0, None, proof=proof)  # r* = 0: a trivially valid lower end
    c5 = _series_condition("sum theta_n rho_1^n r^n converges", rad, amplitude, exact)
    literal = _literal_rho(loop)
    c5 = Condition(c5.name, c5.passed if ctrl_ok else False,
                   {"rho_1": rho1, "rho_1_literal": literal, "radius": rad.value},
                   f"rho_1 = sup|(1 + h1 s1)^-1| = {rho1:.6g} at w = "
                   f"{loop.sensitivity_peak_omega:.4g} rad/s (the literal sup|(1 + h1) s1| "
                   f"= {literal:.4g}); " + c5.detail)
    c6 = Condition("reference spectrum absolutely integrable", True, None,
                   "hypothesis on the input, assumed; its size is the amplitude r")
    if ctrl_ok:
        phi = phi_series([row["majorant"] for row in rows], alpha, order)
        theta = theta_series(phi, lam, rho1, order)
        for row, ph, th in zip(rows, phi, theta, strict=True):
            row["phi"] = ph
            row["theta"] = th
            row["theta_term"] = th * (rho1 * amplitude) ** row["order"]
    conditions = (c1, c2, c3, c4, c5, c6)
    result = ("stable" if all(c.passed for c in conditions) else
              "unstable" if loop.outside else "inconclusive")
    summary = _summary(result, 2, rad, amplitude, conditions, exact)
    if radii.upper is not None or radii.estimate is not None:
        summary += (" The plant's own norm series sum ||h_n|| r^n (not the loop):"
                    + radii.text().lstrip(";") + ".")
    return Verdict(result, 2, rad.value, exact, float(amplitude), conditions, norms, rows,
                   radii.estimate, summary, rad.proof, radii.upper, radii.detail,
                   "plant norm series sum ||h_n|| r^n (not the loop series)",
                   radii.lower if level != "none" else None)


def _controller_output(cmaj: Majorant) -> float:
    """C(1) = sum_n M^c_n, the controller majorant at unit amplitude (inf if divergent,
    or, at the interval level, if the supersolution fails the ball-arithmetic check)."""
    x = certify(lambda z, r: cmaj.rhs(z, r), len(cmaj.powers), 1.0)
    if x is None or (cmaj.proof == "interval" and not cmaj.proves(x, 1.0)):
        return math.inf
    return float(x[0])


def _poly_text(coefficients: np.ndarray) -> str:
    """Monic polynomial in s as text, e.g. ``s^2 + 24.3538 s + 0.118901``."""
    monic = coefficients / coefficients[0]
    degree = monic.size - 1
    parts = []
    for i, c in enumerate(monic):
        power = degree - i
        var = "" if power == 0 else ("s" if power == 1 else f"s^{power}")
        coef = "" if (abs(c) == 1 and power) else f"{abs(c):.6g}"
        parts.append(("- " if c < 0 else "+ ") + (f"{coef} {var}".strip()))
    return " ".join(parts).lstrip("+ ")


def _literal_rho(loop: Any) -> float:
    """Theorem 2's printed sup|(1 + h1(jw)) s1(jw)| (reported, not used)."""
    num_p, den_p = loop.plant_poly  # the polynomials, not python-control objects
    num_c, den_c = loop.controller_poly
    return rational_sup(np.polymul(np.polyadd(den_p, num_p), num_c),
                        np.polymul(den_p, den_c)).value


def _loop_radius(maj: Majorant, lam: float, rho1: float,
                 cmaj: Majorant | None = None) -> Radius:
    """Radius in r of E = rho_1 r + rho_1 [B(C(E)) - beta_1 lambda_1 E] (certified).

    B is the plant majorant, C(E) the controller majorant (lambda_1 E for a linear
    controller); unknowns: plant majorant vector at amplitude C(E), controller majorant
    vector at amplitude E, and E.  ``proof`` of the result: ``"interval"`` when the
    majorants are proven and the supersolution at the certified end passes
    :func:`_loop_proves`; ``"none"`` for estimated majorants; else ``"float"``.
    """
    dim = len(maj.powers)
    cdim = 0 if cmaj is None else len(cmaj.powers)
    beta1 = maj.linear[0]

    def step(z: np.ndarray, r: float) -> np.ndarray:
        x, xc, e = z[:dim], z[dim:dim + cdim], z[-1]
        y = lam * e if cmaj is None else xc[0]
        x_new = maj.rhs(x, y)
        xc_new = np.zeros(0) if cmaj is None else cmaj.rhs(xc, e)
        e_new = rho1 * r + rho1 * (beta1 * (y - lam * e) + maj.gains[0] * maj.nonlinear(x, y))
        return np.concatenate([x_new, xc_new, [e_new]])

    rad = radius(step, dim + cdim + 1)
    levels = {maj.proof} | ({cmaj.proof} if cmaj is not None else set())
    if "none" in levels:
        return dataclasses.replace(rad, proof="none")
    if levels == {"interval"} and rad.solution is not None and rad.certified_below > 0:
        for z in _slack_candidates(step, rad.solution, rad.certified_below):
            if _loop_proves(maj, lam, rho1, cmaj, z, rad.certified_below):
                return dataclasses.replace(rad, proof="interval")
    return rad


def _slack_candidates(step: Any, z: np.ndarray, r: float) -> list[np.ndarray]:
    """Points near the supersolution z to try the ball check at.

    The majorant components of the loop solution are exact fixed points given E (their
    step does not involve r), so step(z, r) <= z is an equality there that balls cannot
    confirm; only E has the slack rho_1 (r' - r).  z + t d with (I - J) d = z (J the
    Jacobian of the step, by finite differences; (I - J)^-1 >= 0 below the radius)
    has step(z + t d) ~ z + t d - t z: slack in every component.  Any candidate that
    passes the ball check is a proof, whatever produced it.
    """
    n = z.size
    jac = np.empty((n, n))
    base = step(z, r)
    for i in range(n):
        h = 1e-7 * max(abs(z[i]), float(np.max(np.abs(z))), 1e-300)
        e = z.copy()
        e[i] += h
        jac[:, i] = (step(e, r) - base) / h
    candidates = [z]
    try:
        d = np.linalg.solve(np.eye(n) - jac, z)
    except np.linalg.LinAlgError:
        return candidates
    if np.all(np.isfinite(d)) and np.all(d >= 0):
        candidates += [z + t * d for t in (1e-13, 1e-12, 1e-11, 1e-10, 1e-9)]
    return candidates


def _loop_proves(maj: Majorant, lam: float, rho1: float, cmaj: Majorant | None,
                 z: np.ndarray, r: float) -> bool:
    """Whether step(z, r) <= z holds for the loop system in Arb ball arithmetic.

    The same step as :func:`_loop_radius` with every operation rounded outward
    (lam, rho1 the proven upper ends): it proves the monotone iteration from 0 stays
    below z, so the theta series converges at amplitude r.
    """
    if not (np.all(np.isfinite(z)) and np.all(z >= 0) and math.isfinite(lam)
            and math.isfinite(rho1) and maj.finite and (cmaj is None or cmaj.finite)):
        return False
    from flint import arb

    dim = len(maj.powers)
    cdim = 0 if cmaj is None else len(cmaj.powers)
    zs = [arb(float(v)) for v in z]
    x, xc, e = zs[:dim], zs[dim:dim + cdim], zs[-1]
    lam_b, rho_b = arb(lam), arb(rho1)
    y = lam_b * e if cmaj is None else xc[0]
    new = maj.rhs_ball(x, y, y)
    if cmaj is not None:
        new += cmaj.rhs_ball(xc, e, e)
    extra = arb(0) if cmaj is None else arb(maj.linear[0]) * (y - lam_b * e)
    new.append(rho_b * arb(r) + rho_b * (extra + arb(maj.gains[0]) * maj.nonlinear_ball(x, y)))
    return all(a <= b for a, b in zip(new, zs, strict=True))


def verdict(model: ModelFile | Model, order: int = 5, amplitude: float = 1.0,
            with_norms: bool = True, proof: str = "interval", *,
            norms: str | None = None) -> Verdict:
    """Theorem 2 when the model file has a controller, Theorem 1 otherwise.

    Parameters
    ----------
    model : ModelFile or Model
        A loaded model file (plant and optional controller) or a bare plant model.
    order : int
        Highest kernel order whose norms are computed and reported.
    amplitude : float
        Input amplitude r at which the series is tested (the paper's r = 1).
    with_norms : bool
        False is ``norms="none"`` (sweeps and margins).
    proof : {"interval", "float", "none"}
        Level of proof, default ``"interval"`` (see :func:`theorem1`).
    norms : {"none", "fast", "tight"}, optional
        Tightness of the ||H_n|| brackets, default ``"fast"`` (see :func:`theorem1`);
        the verdict and r* do not depend on it.

    Returns
    -------
    Verdict
    """
    if isinstance(model, Model):
        return theorem1(model, order, amplitude, with_norms, proof, norms=norms)
    if model.controller is not None:
        return theorem2(model, order, amplitude, with_norms, proof, norms=norms)
    return theorem1(model.plant, order, amplitude, with_norms, proof, norms=norms)


@dataclass(frozen=True)
class Margin:
    """Smallest (or largest) parameter value for which the certified verdict is ``stable``.

    Attributes
    ----------
    parameter : str
    value : float
        The boundary found by bisection (relative width ``tolerance``).
    direction : str
        ``"above"``: stable for parameter > value (e.g. damping); ``"below"`` otherwise.
    amplitude : float
    current : float
        The model file's own value.
    tolerance : float
    """

    parameter: str
    value: float
    direction: str
    amplitude: float
    current: float
    tolerance: float

    def __repr__(self) -> str:
        return short_repr(self, "parameter", "value", "direction", "amplitude")

    def _repr_markdown_(self) -> str:
        return markdown_table(("parameter", "boundary", "stable", "file value", "amplitude r"),
                              [(self.parameter, self.value, f"{self.direction} the boundary",
                                self.current, self.amplitude)])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {"parameter": self.parameter, "value": self.value, "direction": self.direction,
                "amplitude": self.amplitude, "current": self.current,
                "tolerance": self.tolerance}


def parameter_margin(model_file: ModelFile, parameter: str, amplitude: float = 1.0,
                     tolerance: float = 1e-6) -> Margin:
    """Boundary value of a model-file parameter for a certified ``stable`` verdict.

    The verdict is assumed monotone in the parameter near the boundary (true for the
    damping of the pendulum: r* increases with rho).  The nearest change of verdict is
    searched by scaling the file value up and down by powers of 2, then bisected, with
    the model rebuilt from the file each time; norms are not bracketed (majorant only).
    ``direction`` says whether the certified side lies above or below the boundary.

    Parameters
    ----------
    model_file : ModelFile
        Loaded from a TOML file (its ``path`` is re-read).
    parameter : str
        A key of the file's ``[parameters]`` table.
    amplitude : float
    tolerance : float
        Relative width of the final bracket.

    Returns
    -------
    Margin
    """
    if parameter not in model_file.parameters:
        raise ArgumentError(f"{parameter!r} is not a parameter of {model_file.name!r}; "
                            f"parameters: {', '.join(sorted(model_file.parameters))}")
    if not model_file.path:
        raise ArgumentError("parameter margins need a model file (its path is re-read)")
    from gfrf.model.modelfile import read_table

    data = read_table(model_file.path)
    current = model_file.parameters[parameter]

    def passes(value: float) -> bool:
        changed = {**data, "parameters": {**data.get("parameters", {}), parameter: value}}
        mf = model_from_dict(changed, path=model_file.path)
        return verdict(mf, 1, amplitude, with_norms=False).verdict == "stable"

    if current == 0:
        raise ArgumentError(f"{parameter!r} is 0 in the file: the margin search scales it by "
                            "powers of 2, give a nonzero value")
    ok_now = passes(current)
    bracket = None
    for k in range(1, 61):  # the nearest change of verdict, scaling up or down by 2^k
        for probe, previous in ((current * 2.0**k, current * 2.0 ** (k - 1)),
                                (current / 2.0**k, current / 2.0 ** (k - 1))):
            if passes(probe) != ok_now:
                bracket = sorted((previous, probe))
                break
        if bracket:
            break
    else:
        raise ArgumentError(f"no change of verdict found when scaling {parameter!r} by up "
                            "to 2^60 either way")
    lo, hi = bracket
    good_high = passes(hi)
    while abs(hi - lo) > tolerance * max(abs(lo), abs(hi)):
        mid = 0.5 * (lo + hi)
        if passes(mid) == good_high:
            hi = mid
        else:
            lo = mid
    return Margin(parameter, hi if good_high else lo, "above" if good_high else "below",
                  float(amplitude), current, tolerance)
