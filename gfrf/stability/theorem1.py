"""Theorem 1 of the GFRF stability paper (open loop), with a rigorous series decision.

Theorem 1 (open loop, eq (1) models).  The system is L2 stable if
  1) every H_n is a proper rational function,
  2) A_1(s) = sum_p a_{1,p} s^p is Hurwitz (all zeros in the open left half plane),
  3) the norm series sum_n ||H_n||_inf converges.

Also here: the norm-series rows, brackets and radii (``radius_upper``,
``radius_estimate``, see :mod:`gfrf.stability.verdicts`) and the conditions and summary
text that Theorem 2 (:mod:`gfrf.stability.theorem2`) shares.

How the ambiguous symbols are read
----------------------------------
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

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> v = theorem1(parse_model("D(y,2) + D(y) + 2*y + y**3 = u"), order=3, amplitude=0.1)
>>> v.verdict, round(v.radius, 4), [c.passed for c in v.conditions]
('stable', 0.5856, [True, True, True])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gfrf._results import proof_word
from gfrf.bounds.branch_bound import DEFAULT_WORK, MAX_ORDER, box_work
from gfrf.bounds.exact import format_roots, poles
from gfrf.bounds.majorant import Majorant, Radius, majorant, plant_radius
from gfrf.bounds.norms import Bound, kernel_norm, linear_poles
from gfrf.bounds.rational import check_proof
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import check_order
from gfrf.model.equation import Model
from gfrf.stability.verdicts import Condition, Verdict

__all__ = ["theorem1", "NORM_LEVELS", "DEFAULT_NORMS"]

#: Tightness of the ||H_n|| brackets a verdict prints.  ``"none"``: no brackets and no
#: radius estimate (the series rows carry the majorant only); ``"fast"``: the certified
#: majorant as upper end and one local search from the best resonance start as lower end
#: (no branch-and-bound); ``"tight"``: the full :func:`gfrf.bounds.norms.kernel_norm`
#: to its default tol 1e-3 (branch-and-bound, every local search), the orders sharing
#: one default work cap (:data:`gfrf.bounds.branch_bound.DEFAULT_WORK`, about 8 s of
#: enclosures: the boxes an order spends are not available to the next).  ``radius_upper`` and
#: ``radius_estimate`` are computed at ``fast`` and ``tight``.  The conclusions
#: (conditions, verdict, r* and its proof label) never depend on the level.
#: ``with_norms=False`` (sweeps, margins) is ``norms="none"``.
NORM_LEVELS = ("none", "fast", "tight")
#: Level used when none is given (``gfrf verdict --norms``, ``norms=``).
DEFAULT_NORMS = "fast"


def _check_amplitude(amplitude: float, order: int) -> None:
    if not (isinstance(amplitude, float | int) and math.isfinite(amplitude) and amplitude > 0):
        raise ArgumentError(f"amplitude must be a positive finite number, got {amplitude!r}")
    check_order(order)  # before any norm is computed


def _proper_condition(model: Model, maj: Majorant, what: str) -> Condition:
    """Condition 1: bounded kernels.  Improper H1 fails; an infinite majorant is undecided."""
    a, b = model.linear_output, model.linear_input
    if b and max(b) > max(a):
        return Condition(name=f"{what}: proper rational kernels", passed=False, value=math.inf,
                         detail=f"H1 improper: input derivative order {max(b)} > output order "
                         f"{max(a)}")
    if not maj.finite:
        return Condition(name=f"{what}: proper rational kernels", passed=None, value=math.inf,
                         detail="not established: " + "; ".join(maj.reasons))
    return Condition(name=f"{what}: proper rational kernels", passed=True, value=None,
                     detail="every H_n bounded by the finite certified majorant (hence proper on "
                     "the frequency axis)")


def _stability_condition(model: Model) -> tuple[Condition, str]:
    """Condition 2, decided exactly (Routh's test in rationals, exact boundary roots) on
    A's coefficients as written (``0.2`` is 1/5; its doubles when one is irrational)."""
    from gfrf.bounds.majorant import written_polynomials

    written = written_polynomials(model, normalize=False)
    report = linear_poles(model) if written is None else poles(written[1], model.is_discrete)
    kind = "|z| < 1" if model.is_discrete else "Re s < 0"
    values = [complex(p) for p in report.roots]
    if report.stable:
        return Condition(name="linear part A_1 stable", passed=True, value=values,
                         detail=f"all poles have {kind} (exact test on the coefficients as "
                                f"written)"), ""
    if report.outside:
        detail = ("pole outside the stability region (exact test): the equilibrium is "
                  "unstable (Lyapunov's indirect method); Theorem 1 is inapplicable")
    else:
        detail = ("pole on the stability boundary at "
                  + format_roots(report.boundary, "z" if model.is_discrete else "s")
                  + " (exact test): Theorem 1 is inapplicable")
    return Condition(name="linear part A_1 stable", passed=False, value=values, detail=detail), \
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
    work = DEFAULT_WORK  # the tight brackets of all orders share one default work cap
    for n in range(1, order + 1):
        budget = None
        if level == "tight" and 2 <= n <= MAX_ORDER and not model.is_discrete:
            budget = max(0, work // box_work(model, n))
        bound = (None if level == "none" else
                 kernel_norm(model, n, proof=maj.proof, max_boxes=budget, progress=None)
                 if level == "tight" else
                 kernel_norm(model, n, proof=maj.proof, max_boxes=0, searches=FAST_SEARCHES))
        if budget is not None and bound is not None:
            work -= bound.boxes * box_work(model, n)
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
    from gfrf.bounds.radius_scaling import amplitude_shift
    from gfrf.stability.static import radius_upper

    shift = amplitude_shift(maj)  # both on the O(1) problem, scaled back exactly
    bound = radius_upper(model, shift)
    upper = None if bound is None else bound.value
    detail = ("no static branch point proven (no finite static gain, a polynomial static "
              "map, or the tracking budget ran out)" if bound is None else bound.detail)
    est = _scaled_estimate(model, lower, upper, shift)
    if proof != "interval":
        upper, detail = None, f"not reported at proof level {proof!r} (use 'interval')"
    if est is None:
        return _Radii(upper, detail, None, lower)
    clamp = ("" if est.value == est.fitted else
             f"; the fit gave {est.fitted:.4g}, clamped to the "
             f"{'upper' if est.value < est.fitted else 'lower'} bound")
    return _Radii(upper, detail, est.value, lower, clamp)


def _scaled_estimate(model: Model, lower: float, upper: float | None, shift: int) -> Any:
    """:func:`gfrf.stability.estimate.radius_estimate` computed in the amplitude units
    2^shift (:func:`gfrf.model.scaling.amplitude_scaled`) and scaled back exactly."""
    import dataclasses

    from gfrf.model.scaling import amplitude_scaled
    from gfrf.stability.estimate import radius_estimate

    scaled = amplitude_scaled(model, shift)
    if scaled is None:
        scaled, shift = model, 0
    est = radius_estimate(scaled, math.ldexp(lower, -shift),
                          None if upper is None else math.ldexp(upper, -shift))
    if est is None or shift == 0:
        return est
    return dataclasses.replace(est, value=math.ldexp(est.value, shift),
                               fitted=math.ldexp(est.fitted, shift), lower=lower, upper=upper)


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
    return Verdict(verdict=result,
                   theorem=1,
                   radius=rad.value,
                   radius_certified=maj.certified,
                   amplitude=float(amplitude),
                   conditions=conditions,
                   norms=norms,
                   series=rows,
                   radius_estimate=radii.estimate,
                   summary=summary,
                   radius_proof=rad.proof,
                   radius_upper=radii.upper,
                   radius_upper_detail=radii.detail,
                   estimate_of="norm series sum ||H_n|| r^n",
                   estimate_lower=radii.lower if level != "none" else None)


def _series_condition(name: str, rad: Radius, amplitude: float, exact: bool,
                      est: str = "") -> Condition:
    label = proof_word(rad.proof) if exact else "not certified"
    if amplitude < rad.certified_below:
        return Condition(name=name, passed=True if exact else None, value=rad.value,
                         detail=f"majorant converges for r < r* = {rad.value:.6g} ({label}); "
                         f"r = {amplitude:g} is inside{est}")
    if rad.value == 0.0:  # an infinite majorant entry: nothing certified, nothing refuted
        return Condition(name=name, passed=None, value=rad.value,
                         detail=f"not established: the majorant certifies no amplitude r > 0 "
                         f"(r* = 0: it has an infinite entry, see the H_n condition){est}")
    return Condition(name=name, passed=None, value=rad.value,
                     detail=f"not established: the majorant diverges for r >= r* = {rad.value:.6g} "
                     f"({label}) and r = {amplitude:g} is outside{est}")


def _summary(result: str, theorem: int, rad: Radius, amplitude: float,
             conditions: tuple[Condition, ...], certified: bool) -> str:
    failed = [c.name for c in conditions if c.passed is False]
    open_ = [c.name for c in conditions if c.passed is None]
    kind = proof_word(rad.proof) if certified else "estimated (not certified)"
    text = (f"Theorem {theorem}: {result}. The {kind} norm series converges for every "
            f"input amplitude r < r* = {rad.value:.6g}; r = {amplitude:g} is "
            f"{'inside' if amplitude < rad.certified_below else 'outside'}.")
    if rad.value == 0.0:
        text = (f"Theorem {theorem}: {result}. The {kind} majorant certifies no input "
                f"amplitude r > 0 (r* = 0).")
    if failed:
        text += " Failed: " + "; ".join(failed) + "."
    if open_:
        text += " Not established: " + "; ".join(open_) + "."
    return text
