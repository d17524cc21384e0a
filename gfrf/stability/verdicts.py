"""The verdict objects of Theorems 1 and 2: :class:`Condition` and :class:`Verdict`.

:func:`gfrf.stability.theorem1.theorem1` (open loop) and
:func:`gfrf.stability.theorem2.theorem2` (closed loop) return a :class:`Verdict`, one
:class:`Condition` per hypothesis of the theorem; :func:`gfrf.stability.criteria.verdict`
chooses the theorem.

Verdicts: ``stable`` when every condition holds (certified); ``unstable`` when the
linearisation has a pole in the open right half plane (Lyapunov's indirect method:
the equilibrium is unstable; the theorem is then inapplicable); ``inconclusive``
otherwise.  Angular frequencies are in rad/s throughout.

Three radii, never confused.  ``radius``: r*, the proven (certified) lower bound on
the radius of the theorem's series.  ``radius_upper``: a proven upper bound on the
true radius of the norm series sum ||H_n|| r^n (the plant's, for Theorem 2), from
the static branch point of the zero-frequency kernels
(:func:`gfrf.stability.static.radius_upper`),
where one is proven.  ``radius_estimate``: a many-term estimate of that true radius
(:func:`gfrf.stability.estimate.radius_estimate`), clamped into [lower bound,
``radius_upper``]: an estimate, never a proof and never the ground of a verdict.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from gfrf._results import Result, proof_word, short_repr, verdict_figure, verdict_markdown
from gfrf.bounds.norms import Bound

__all__ = ["Condition", "Verdict"]


@dataclass(frozen=True, kw_only=True)
class Condition(Result):
    """One hypothesis of a theorem: ``passed`` True, False, or None (not established)."""

    name: str
    passed: bool | None
    value: Any
    detail: str


@dataclass(frozen=True, kw_only=True)
class Verdict(Result):
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
    loop : str
        Theorem 2: the loop, where the reference enters (``u = C(r - y), C(s) = ...``);
        r, r* and ``loop_radius_upper`` are in units of the reference.  Empty for Theorem 1.
    loop_radius_upper : float or None
        Theorem 2: proven upper bound on the loop's true radius in units of r (static fold
        of the loop's static map, :func:`gfrf.stability.static.loop_radius_upper`).
    loop_radius_upper_detail : str
        Where ``loop_radius_upper`` comes from, or why absent.
    """

    _order = ("verdict", "theorem", "radius", "radius_certified", "amplitude", "conditions",
              "norms", "series", "radius_estimate", "summary", "radius_proof", "proof")

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
    loop: str = ""
    loop_radius_upper: float | None = None
    loop_radius_upper_detail: str = ""

    def __repr__(self) -> str:
        return short_repr(self, "verdict", "theorem", "radius", "amplitude")

    @property
    def linear_stable(self) -> bool | None:
        """Whether the linear part (Theorem 1) or the linear loop (Theorem 2) passed its
        stability condition; None when the verdict holds no such condition."""
        return next((c.passed for c in self.conditions
                     if c.name.startswith("linear") and "stable" in c.name), None)

    @property
    def radius_kind(self) -> str:
        """What r* is, in words: its proof level, and for an unstable linear part that it
        bounds the series of L-infinity norms on the frequency axis (not H-infinity
        norms: ``gfrf norm`` says the same), so it is no stability radius."""
        level = proof_word(self.radius_proof) if self.radius_certified else "estimate"
        if self.linear_stable is False:
            return (f"{level} for the series of L-infinity norms on the axis, not H-infinity: "
                    f"the linear part is unstable, so r* is no stability radius")
        return level

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

    def _computed(self) -> dict[str, Any]:
        return {
            "proof": self.radius_proof,
            "radius_kinds": {
                "radius": f"lower bound r* of the {_SERIES[self.theorem]}, "
                          + (self.radius_kind if self.radius_certified
                             else "estimate (not certified)"),
                "radius_upper": f"proven upper bound on the true radius of the "
                                f"{self.estimate_of} (static branch point)",
                "radius_estimate": f"estimate of the true radius of the {self.estimate_of}"
                                   " (not a proof; never decides a verdict)"}}


_SERIES = {1: "norm series sum ||H_n|| r^n", 2: "loop series sum theta_n rho_1^n r^n"}
