"""The cart-pole section of ``paper-gfrf.md``: its facts, then its text.

:func:`cartpole_facts` computes every number of the section into a
:class:`CartpoleFacts`; :func:`cartpole_text` writes the section and its summary line
from them, and each sentence that states a sign, a comparison or a property of the
numbers (every coefficient negative, each r* below its own ceiling, no resonant peak,
...) is chosen by the facts, so it follows the numbers.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gfrf._results import Result
from gfrf.bounds.majorant import linear_polynomials
from gfrf.model.modelfile import ModelFile
from gfrf.papers.cartpole import (
    LAG_TIME_CONSTANTS,
    InertiaReversal,
    LagRow,
    SignMargin,
    Theorem2Obstruction,
    inertia_reversal,
    lagged_loops,
    sign_margin,
    theorem2_obstruction,
)
from gfrf.papers.cartpole_trials import LagSimulation, LoopDrive, lagged_simulation, loop_drive
from gfrf.report._format import cell, num, table
from gfrf.sim.validation import resonance

__all__ = ["CartpoleFacts", "cartpole_facts", "cartpole_text", "NEAR"]

#: Relative distance within which two rates are called the same ("sits near", "is").
NEAR = 0.05


@dataclass(frozen=True, kw_only=True, repr=False)
class CartpoleFacts(Result):
    """Every number of the cart-pole section.

    Attributes
    ----------
    inertia : InertiaReversal
        The ideal loop's theta'' coefficient and characteristic polynomial.
    lags : tuple of LagRow
        Closed-loop poles with 1 and 3 lags.
    sims : tuple of (LagSimulation, LagSimulation)
        Lagged nonlinear loop from a large and from a 1e-7 rad start, per tau.
    sign : SignMargin
        The feedback sign u = +K theta: c*, poles below and above, c_max(tau).
    obstruction : Theorem2Obstruction
        The ceiling on Theorem 2's r* and the PD-with-filter search.
    drive : LoopDrive
        Eq (16)'s ideal loop: poles, drive frequency and runs.
    drives : dict of str to LoopDrive
        The drives of both cart-pole files by stem (the simulation table's rows).
    w_plant : float
        The peak of the plant's |H1| on the grid (rad/s).
    w2 : float
        Minus the plant's constant denominator coefficient.
    plant_unstable : bool
        Whether the plant has a right-half-plane pole.
    """

    inertia: InertiaReversal
    lags: tuple[LagRow, ...]
    sims: tuple[tuple[LagSimulation, LagSimulation], ...]
    sign: SignMargin
    obstruction: Theorem2Obstruction
    drive: LoopDrive
    drives: dict[str, LoopDrive]
    w_plant: float
    w2: float
    plant_unstable: bool

    def one_lag(self) -> list[LagRow]:
        """The rows with one lag."""
        return [r for r in self.lags if r.lags == 1]

    def reversal_stabilises(self) -> bool:
        """The loop's theta'' coefficient is negative and its poles are stable."""
        return self.inertia.coefficient < 0 and all(p.real < 0 for p in self.inertia.poles)

    def lag_pole_near_prediction(self) -> bool:
        """Each one-lag unstable pole within :data:`NEAR` of (gain a - 1)/tau."""
        return all(r.predicted is not None and r.unstable
                   and _near(r.unstable[0].real, r.predicted) for r in self.one_lag())

    def lagged_diverges(self) -> bool:
        """Every lagged nonlinear run from an initial angle reaches |theta| = 1 rad."""
        return all(big.escape_time is not None for big, _ in self.sims)

    def growth_is_pole(self) -> bool:
        """Each growth rate from 1e-7 rad within :data:`NEAR` of its unstable pole."""
        poles = {r.tau: r.unstable[0].real for r in self.one_lag() if r.unstable}
        return all(small.growth_rate is not None and small.tau in poles
                   and _near(small.growth_rate, poles[small.tau]) for _, small in self.sims)

    def each_below_ceiling(self) -> bool:
        """Every stabilising controller's certified r* is below its own ceiling."""
        return all(t.radius < t.bound for t in self.obstruction.stabilising)


def _near(value: float, reference: float) -> bool:
    return abs(value - reference) <= NEAR * abs(reference)


def cartpole_facts(reduced: ModelFile, full: ModelFile, quick: bool) -> CartpoleFacts:
    """The cart-pole numbers of eq (16) (``reduced``) and eq (12) (``full``).

    Parameters
    ----------
    reduced : ModelFile
        Eq (16)'s file.
    full : ModelFile
        Eq (12)'s file.
    quick : bool
        Fewer drive periods (20 instead of 100).

    Returns
    -------
    CartpoleFacts
        The facts :func:`cartpole_text` writes.
    """
    periods = 20 if quick else 100
    drives = {Path(mf.path).stem: loop_drive(mf, periods=periods) for mf in (full, reduced)}
    den = linear_polynomials(reduced.plant)[1]
    return CartpoleFacts(
        inertia=inertia_reversal(reduced), lags=tuple(lagged_loops(reduced)),
        sims=tuple((lagged_simulation(full, tau), lagged_simulation(full, tau, theta0=1e-7))
                   for tau in (LAG_TIME_CONSTANTS[0], LAG_TIME_CONSTANTS[-1])),
        sign=sign_margin(reduced), obstruction=theorem2_obstruction(reduced),
        drive=drives[Path(reduced.path).stem], drives=drives,
        w_plant=resonance(reduced.plant), w2=-float(den[-1]),
        plant_unstable=bool(np.any(np.roots(den).real > 0)))


def _signs(values: list[Any]) -> str:
    real = [float(np.real(v)) for v in values]
    return ("every coefficient negative" if all(v < 0 for v in real) else
            "every coefficient positive" if all(v > 0 for v in real) else
            "coefficients of both signs")


def _inertia(c: CartpoleFacts) -> str:
    i = c.inertia
    lhp = all(p.real < 0 for p in i.poles)
    rel = "<" if i.coefficient < 0 else ">" if i.coefficient > 0 else "="
    return (("**The ideal loop is stable only by reversing the inertia.**"
             if c.reversal_stabilises() else "**The ideal loop and the inertia.**")
            + " With the model's own "
            f"signs (eq (16): theta'' - ... + {num(i.input_gain)} u = 0, negative feedback "
            f"u = -(a s^2 + b s + c) theta) the closed loop's theta'' coefficient is 1 - "
            f"{num(i.input_gain)} x {num(i.a)} = **{num(i.coefficient)}** {rel} 0. "
            f"Its characteristic polynomial {cell(list(i.characteristic))} has "
            f"{_signs(list(i.characteristic))}, so its roots {cell(list(i.poles))} "
            + ("lie in the left half plane" if lhp else "do not all lie in the left half plane")
            + (" - but only because the controller's a s^2 term, an ideal differentiator of "
               "theta', cancels and reverses the plant's own inertia. No realisable "
               "controller can do that." if c.reversal_stabilises() else "."))


def _and(values: list[float]) -> str:
    words = [num(v) for v in values]
    return ", ".join(words[:-1]) + " and " + words[-1] if len(words) > 1 else "".join(words)


def _resonance(c: CartpoleFacts) -> str:
    d = c.drive
    slow = min(abs(p) for p in d.poles)
    every = "Both poles" if len(d.poles) == 2 else f"All {len(d.poles)} poles"
    head = ("**The loop has no resonance.** " + every + " of the ideal loop are real "
            f"({cell(list(d.poles))}): it is overdamped, |y/r(jw)| has no resonant peak. "
            "The cosine drives in the simulation table below therefore run at the loop's "
            f"fast corner |p| = {num(d.omega, 4)} rad/s" if not d.resonant else
            "**The loop can resonate.** The ideal loop has a complex pole pair "
            f"({cell(list(d.poles))}). The cosine drives in the simulation table below run "
            f"at the least damped pair's |p| = {num(d.omega, 4)} rad/s")
    return (head + f" for {d.periods} periods ({num(d.t_end, 4)} s), with reference "
            "amplitudes (r of u = C(r - y)) that give linear steady angles of "
            f"{_and(sorted({t.target_deg for t in d.trials}))} deg, each run started on "
            "that linear steady state"
            + ("" if d.resonant else
               f" (the slow corner, {num(slow, 3)} rad/s, has a period of "
               f"{num(2 * np.pi / slow, 3)} s)")
            + ". The old 'resonance' drive used the peak of the *"
            + ("unstable plant's" if c.plant_unstable else "plant's") + "* |H1| (w -> 0; "
            f"{num(c.w_plant, 3)} rad/s on the grid, a period of "
            f"{num(2 * np.pi / c.w_plant, 3)} s against a 100 s horizon) and is dropped.")


def _obstruction(c: CartpoleFacts) -> str:
    o, stab = c.obstruction, c.obstruction.stabilising
    best = o.best
    shown = min(5, len(stab))
    return (
        f"holds ({o.holds}), so at the paper's r = 1 the theta-series "
        + ("diverges for every such controller (and under either reading of rho_1)"
           if o.holds else "is not excluded by this ceiling")
        + f". A search over {len(o.trials)} PD-with-filter controllers u = +(K_d s + K_p)/"
        f"(tau_f s + 1) theta agrees: {len(stab)} stabilise the linear loop, "
        f"{sum(t.verdict == 'stable' for t in o.trials)} are certified at r = 1, and the "
        f"largest certified r* is {num(best.radius if best else 0.0)}, "
        + ("each below its own" if c.each_below_ceiling() else "not each below its own")
        + " ceiling (2/(3 sqrt 3)) (lambda_1 rho_1)^(-3/2) |c3|^(-1/2). The "
        + ("five" if shown == 5 else str(shown)) + " best:")


def cartpole_text(c: CartpoleFacts) -> tuple[list[str], str]:
    """The cart-pole section's lines and its summary line, from its facts.

    Parameters
    ----------
    c : CartpoleFacts
        The facts (:func:`cartpole_facts`).

    Returns
    -------
    tuple of (list of str, str)
        The section's lines and the summary line.
    """
    inertia, sign, obst = c.inertia, c.sign, c.obstruction
    one = c.one_lag()
    rhp_file = [p for p in sign.poles_file if p.real > 0]
    c_min, gain = float(sign.c_min), inertia.input_gain
    above = [p.real for p in sign.poles_above]
    lag_rows = [[r.tau, r.lags, list(r.unstable), r.predicted, list(r.poles)] for r in c.lags]
    sim_rows = [[big.tau, num(big.theta0 * 180 / np.pi, 3) + " deg", big.escape_time,
                 small.growth_rate,
                 next(r.unstable[0].real for r in one if r.tau == big.tau)]
                for big, small in c.sims]
    pd_rows = [[t.kp, t.kd, t.tau_f, t.lambda1, t.rho1, t.radius, t.bound, t.verdict]
               for t in sorted(obst.stabilising, key=lambda t: -t.radius)[:5]]
    diverges = "diverges" if c.lagged_diverges() else "does not always reach 1 rad"
    text = [
        "## The cart-pole loop, told straight", "",
        "Computed by `gfrf.papers.cartpole` (tests: `tests/papers/test_cartpole.py`, "
        "against exact Routh-Hurwitz arrays in rationals, the static series, python-control "
        "and direct integrations).", "",
        _inertia(c), "",
        "**Any lag destroys it.** The controller times 1/(tau s + 1)^k (k = 1, and k = 3 "
        "for the paper's eq (15) with T1 = T2 = T3 = tau); closed-loop poles by "
        "`control.feedback` / `control.poles`. For one lag the unstable pole "
        + ("sits near" if c.lag_pole_near_prediction() else "is not near")
        + " (gain x a - 1)/tau:", "",
        table(["tau (s)", "lags", "right-half-plane poles", "(gain a - 1)/tau",
               "all poles"], lag_rows),
        "The lagged *nonlinear* loop (eq (12) with the lag state, `scipy.integrate."
        f"solve_ivp` DOP853) from an initial angle {diverges}; from 1e-7 rad the growth "
        "rate of ln|theta| (between 1e-5 and 1e-3 rad) "
        + ("is" if c.growth_is_pole() else "is not") + " the unstable pole:", "",
        table(["tau (s)", "start", "|theta| = 1 rad at t (s)", "growth rate from 1e-7 rad "
               "(1/s)", "unstable pole (1/s)"], sim_rows),
        "**The physically right sign.** For this plant u = +K theta stabilises (feedback "
        f"+1). With the paper's c = {num(sign.c_file)} the ideal loop "
        + (f"keeps a right-half-plane pole at s = {cell([p.real for p in rhp_file])}"
           if rhp_file else "has no right-half-plane pole")
        + f". Routh-Hurwitz on chi(s) = (s^2 - {num(c.w2)}) + {num(gain)} (a s^2 + b s + c) "
        "(all three coefficients positive) gives stability exactly for **c > c* = "
        f"{num(c.w2)}/{num(gain)} = {sign.c_min.numerator}/{sign.c_min.denominator} = "
        f"{num(c_min)}**; python-control: at c* (1 - {num(sign.step)}) a pole at "
        f"{cell(max(p.real for p in sign.poles_below))}, at c* (1 + {num(sign.step)}) "
        + ("all poles in the left half plane" if all(p < 0 for p in above) else "poles at")
        + f" {cell(above)}. With one lag tau the same c* holds "
        "and the cubic Hurwitz condition adds an upper limit c < c_max(tau): "
        + ", ".join(f"c_max({num(t)} s) = {num(v)}" for t, v in sign.c_max.items()) + ".",
        "",
        "**Theorem 2 cannot certify this plant with any proper, stable linear "
        "controller.** Proof (docstring of `theorem2_obstruction`): (i) a stabilising "
        "controller needs |s1(0)| > 1/beta with beta = |h1(0)| = "
        f"{num(float(obst.beta1_floor))} (chi(0) > 0), so lambda_1 = ||s1|| > "
        f"{num(1 / float(obst.beta1_floor))}; (ii) rho_1 >= 1 (sensitivity -> 1 as w -> "
        "inf; the literal sup|(1 + h1) s1| > 1 too); (iii) phi_3 >= beta_3 >= |h3(0,0,0)| "
        f"= |c3| = {num(abs(float(obst.c3)))} (static branch, exact; gfrf's kernel gives "
        f"{num(obst.kernel_h3_0)}); (iv) if sum theta_n (rho_1 r)^n converges, its sum T "
        "solves T = rho_1 r + rho_1 Psi(lambda_1 T), and y = lambda_1 T gives r = "
        "y/(lambda_1 rho_1) - Psi(y) < beta y - |c3| y^3 <= (2/(3 sqrt 3)) beta^(3/2) "
        f"|c3|^(-1/2) = **{num(obst.ceiling, 4)}**. The exact test 4 beta^3 < 27 |c3| "
        + _obstruction(c), "",
        table(["K_p", "K_d", "tau_f (s)", "lambda_1", "rho_1", "r* (certified)",
               "ceiling", "verdict at r = 1"], pd_rows),
        _resonance(c), ""]
    lag_lo, lag_hi = one[0], one[-1]
    summary = ("Cart-pole: the paper's loop is "
               + ("stable only because" if c.reversal_stabilises() else "not stabilised although")
               + " the improper a s^2 term "
               f"makes the theta'' coefficient 1 - {num(inertia.input_gain)} x "
               f"{num(inertia.a)} = {num(inertia.coefficient, 4)}; any lag tau = "
               f"{num(lag_lo.tau)}..{num(lag_hi.tau)} s gives a pole at +"
               f"{num(lag_hi.unstable[0].real, 3)}..{num(lag_lo.unstable[0].real, 3)} 1/s "
               f"and the lagged nonlinear loop {diverges}; with u = +K theta, c must exceed "
               f"{num(c_min, 5)} (the paper's {num(sign.c_file)} "
               + (f"leaves a pole at +{num(rhp_file[0].real, 3)})" if rhp_file
                  else "leaves no unstable pole)")
               + "; Theorem 2 certifies "
               + ("no proper stable linear controller" if obst.holds
                  else "proper stable linear controllers")
               + f" (theta-series only for r < {num(obst.ceiling, 3)}).")
    return text, summary
