"""paper-gfrf.md: the page is rendered from its facts; each comparing sentence follows
the numbers (facts built by hand, then numbers swapped so that a claim becomes false)."""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction

from gfrf.papers.cartpole import (
    ControllerTrial,
    InertiaReversal,
    LagRow,
    SignMargin,
    Theorem2Obstruction,
)
from gfrf.papers.cartpole_trials import DriveTrial, LagSimulation, LoopDrive
from gfrf.papers.gfrf_paper import AlphaRow, CheckRow, ThetaReading
from gfrf.report.paper_gfrf import PAGE, PaperGfrfFacts, render
from gfrf.report.paper_gfrf_cartpole import CartpoleFacts, cartpole_text
from gfrf.report.paper_gfrf_figures import FigureFacts, figures_text
from gfrf.stability.criteria import Margin

# the ideal loop: 1 - 2 x 1 = -1 < 0, chi(s) = -(s + 1)(s + 2)
_INERTIA = InertiaReversal(input_gain=2.0, a=1.0, feedback=-1, coefficient=-1.0,
                           characteristic=(-1.0, -3.0, -2.0), poles=(-1.0, -2.0),
                           plant_leading=1.0)


def _lag(tau: float, pole: float) -> LagRow:
    return LagRow(tau=tau, lags=1, poles=(-24.0, -0.005, pole), predicted=1 / tau)


def _sim(tau: float, growth: float | None, escape_time: float | None = 0.01
         ) -> tuple[LagSimulation, LagSimulation]:
    big = LagSimulation(tau=tau, theta0=0.0872665, escape=1.0, escape_time=escape_time,
                        t_end=1.0, growth_rate=None, feedback=-1, peak=1.0)
    return big, replace(big, theta0=1e-7, growth_rate=growth)


def _trial(radius: float, bound: float) -> ControllerTrial:
    return ControllerTrial(kp=30.0, kd=5.0, tau_f=0.01, stable=True, lambda1=2.0, rho1=1.0,
                           radius=radius, verdict="inconclusive", bound=bound)


def _cart(**change: object) -> CartpoleFacts:
    drive = LoopDrive(poles=(-24.0, -0.005), resonant=False, omega=24.0, gain=1.0, t_end=5.2,
                      periods=20, trials=(DriveTrial(equation="polynomial", target_deg=5.0,
                                                     amplitude=0.1, bounded=True, peak=0.09,
                                                     blowup_time=None),))
    values: dict[str, object] = dict(
        inertia=_INERTIA, lags=(_lag(0.001, 1001.0), _lag(0.01, 101.0)),
        sims=(_sim(0.001, 1000.0), _sim(0.01, 100.5)),
        sign=SignMargin(c_file=10.0, poles_file=(-3.0, 0.5), c_min=Fraction(49, 2),
                        poles_below=(-3.0, 0.01), poles_above=(-3.0, -0.01), step=0.01,
                        c_max={0.01: 400.0}, lag_poles_above={}),
        obstruction=Theorem2Obstruction(beta1_floor=Fraction(1, 49), c3=Fraction(-8, 3),
                                        kernel_h1_0=-0.02, kernel_h3_0=2.6, ceiling=0.002,
                                        holds=True, trials=(_trial(1e-4, 1e-3),
                                                            _trial(2e-4, 3e-3))),
        drive=drive, drives={"cartpole_reduced": drive}, w_plant=0.01, w2=49.0,
        plant_unstable=True)
    values.update(change)
    return CartpoleFacts(**values)  # type: ignore[arg-type]


def _text(facts: CartpoleFacts) -> str:
    lines, summary = cartpole_text(facts)
    return "\n".join(lines) + "\n" + summary


def test_cartpole_claims_hold_on_their_numbers() -> None:
    text = _text(_cart())
    assert "**The ideal loop is stable only by reversing the inertia.**" in text
    assert "= **-1** < 0. Its characteristic polynomial [-1, -3, -2] has every coefficient " \
           "negative, so its roots [-1, -2] lie in the left half plane - but only" in text
    assert "the unstable pole sits near (gain x a - 1)/tau" in text
    assert "from an initial angle diverges; " in text and "is the unstable pole:" in text
    assert "keeps a right-half-plane pole at s = [0.5]" in text
    assert "all poles in the left half plane [-3, -0.01]" in text
    assert "so at the paper's r = 1 the theta-series diverges for every such" in text
    assert "each below its own ceiling" in text and "The 2 best:" in text
    assert "**The loop has no resonance.** Both poles of the ideal loop are real" in text
    assert "has no resonant peak" in text and "*unstable plant's* |H1|" in text
    assert "that give linear steady angles of 5 deg, each run" in text
    assert text.endswith("Cart-pole: the paper's loop is stable only because the improper "
                         "a s^2 term makes the theta'' coefficient 1 - 2 x 1 = -1; any lag "
                         "tau = 0.001..0.01 s gives a pole at +101..1e+03 1/s and the lagged "
                         "nonlinear loop diverges; with u = +K theta, c must exceed 24.5 (the "
                         "paper's 10 leaves a pole at +0.5); Theorem 2 certifies no proper "
                         "stable linear controller (theta-series only for r < 0.002).")


def test_cartpole_sentences_follow_swapped_numbers() -> None:
    # a positive theta'' coefficient and a right-half-plane root: no inertia reversal
    flipped = replace(_INERTIA, coefficient=1.0, characteristic=(1.0, -1.0, 2.0),
                      poles=(0.5, 0.5))
    text = _text(_cart(inertia=flipped))
    assert "only by reversing" not in text and "= **1** > 0." in text
    assert "has coefficients of both signs, so its roots [0.5, 0.5] do not all lie" in text
    assert "loop is not stabilised although" in text
    # a controller whose r* exceeds its ceiling, an obstruction that does not hold
    obst = replace(_cart().obstruction, holds=False, trials=(_trial(5e-3, 1e-3),))
    text = _text(_cart(obstruction=obst))
    assert "not each below its own ceiling" in text and "The 1 best:" in text
    assert "is not excluded by this ceiling" in text
    assert "certifies proper stable linear controllers" in text
    # lag poles far from the prediction, growth rates off the pole, no escape
    text = _text(_cart(lags=(_lag(0.001, 2000.0), _lag(0.01, 101.0)),
                       sims=(_sim(0.001, 500.0, None), _sim(0.01, 100.5))))
    assert "the unstable pole is not near (gain x a - 1)/tau" in text
    assert "from an initial angle does not always reach 1 rad" in text
    assert "is not the unstable pole:" in text
    # a complex pole pair: the loop can resonate; a stable plant; c_file stabilises
    runs = tuple(replace(_cart().drive.trials[0], target_deg=a) for a in (15.0, 5.0, 10.0))
    drive = replace(_cart().drive, poles=(-1 + 3j, -1 - 3j), resonant=True, omega=3.1623,
                    trials=runs)
    sign = replace(_cart().sign, poles_file=(-3.0, -0.5), poles_above=(-3.0, 0.01))
    text = _text(_cart(drive=drive, plant_unstable=False, sign=sign))
    assert "no resonant peak" not in text and "**The loop can resonate.**" in text
    assert "least damped pair's |p| = 3.162 rad/s" in text and "slow corner" not in text
    assert "steady angles of 5, 10 and 15 deg" in text
    assert "*plant's* |H1|" in text and "unstable plant" not in text
    assert "the ideal loop has no right-half-plane pole." in text
    assert "leaves no unstable pole" in text and "all poles in the left half" not in text


def _figures(**change: object) -> FigureFacts:
    values: dict[str, object] = dict(
        names=("a.png", "b.png", "c.png"), stiff=49.0, unstable=True, real=True,
        sign="negative", points=151, d0=-49.0, b3=(0.25, 0.26), argmax=(0.0, 0.0),
        beta3_paper=2.56)
    values.update(change)
    return FigureFacts(**values)  # type: ignore[arg-type]


def test_figure_sentences_follow_the_bracket_and_the_plant() -> None:
    text = "\n".join(figures_text(_figures()))
    assert "the paper's beta_3 = 2.56 is not in this bracket" in text
    assert "The plant is unstable" in text and "and negative at every one of the 151^2" in text
    text = "\n".join(figures_text(_figures(b3=(2.5, 2.6), unstable=False, real=False)))
    assert "the paper's beta_3 = 2.56 is in this bracket" in text
    assert "The plant is unstable" not in text and "flat colour" not in text


def _alpha(model: str, alpha: float, rho: float, radius: float, verdict: str,
           bounded: bool = True) -> AlphaRow:
    return AlphaRow(model=model, alpha=alpha, rho=rho, h1_norm=alpha / rho, radius=radius,
                    radius_proof="interval", verdict=verdict, margin=15.0 * alpha,
                    margin_tolerance=1e-6, resonance=1.0, bounded=bounded, peak=0.3,
                    t_end=100.0)


def _facts(**change: object) -> PaperGfrfFacts:
    alpha = (_alpha("hanging_pendulum", 1.0, 0.8, 0.01, "inconclusive"),
             _alpha("hanging_pendulum_eq2", 0.0625, 0.8, 0.16, "inconclusive"),
             _alpha("hanging_pendulum_damped", 1.0, 8.0, 0.4, "inconclusive"),
             _alpha("hanging_pendulum_eq2_damped", 0.0625, 8.0, 6.4, "stable"))
    readings = (ThetaReading(section="3", printed=0.5, rho1=2.0, phi3=0.5, lambda1=1.0,
                             kept=1.0, dropped=0.5),
                ThetaReading(section="5", printed=0.006, rho1=1.5, phi3=2.56, lambda1=0.1331,
                             kept=0.009, dropped=0.006036))
    values: dict[str, object] = dict(
        rows=(CheckRow(section="3 (rho = 0.8)", quantity="||H1||", paper=12.78, ours=12.7792,
                       match=True, reason=""),
              CheckRow(section="3 (rho = 0.8)", quantity="rho_3", paper=1.0, ours=2.0,
                       match=False, reason="typo")),
        figures=_figures(), cartpole=_cart(), alpha=alpha, readings=readings,
        stems=("hanging_pendulum",), theorem_rows=[["m", "Theorem 1", "stable", "x", 0.1,
                                                    "certified", 0.2, "c"]],
        sim_rows=[["m", "polynomial", "cosine", 0.05, 0.5, True, True, 0.1, None],
                  ["m", "polynomial", "cosine", 0.2, 2.0, False, False, 9.0, 3.0]],
        margin=Margin(parameter="rho", value=15.1, direction="above", amplitude=1.0,
                      current=0.8, tolerance=1e-6),
        rho8=8.0, radius8=0.4, t_end=100.0, cart_radius=0.0, out="reports")
    values.update(change)
    return PaperGfrfFacts(**values)  # type: ignore[arg-type]


def test_alpha_sentences_follow_the_verdicts() -> None:
    page = render(_facts())
    assert ("With alpha kept, rho = 0.8 is not certified at r = 1 (r* = 0.16: the norm "
            "series diverges there, although the simulated pendulum stays bounded, peak "
            "0.3 rad), and rho = 8 is **certified stable at r = 1** (r* = 6.4)") in page
    assert ("therefore holds for eq (2) - because the input gain shrinks ||H1|| 16-fold (r* "
            "grows by the same factor), a reason the paper does not give - and is not "
            "certified for its own eq (6).") in page
    assert "prefactor neither section reproduces its theta_3, with it dropped both do" in page
    assert "= 0.006036: rho_1 dropped." in page
    assert "rho = 8 is certified stable at r = 1" in page and "rho = 0.8 is not (r*" in page
    # swap the verdicts and the radii: every claim turns
    alpha = _facts().alpha
    swapped = (alpha[0], replace(alpha[1], verdict="stable", radius=2.0),
               replace(alpha[2], verdict="stable"),
               replace(alpha[3], verdict="inconclusive", radius=0.5, bounded=False))
    page = render(_facts(alpha=swapped,
                         readings=(replace(_facts().readings[0], kept=0.5, dropped=1.0),)))
    assert "rho = 0.8 is **certified stable at r = 1** (r* = 2)" in page
    assert "rho = 8 is not certified at r = 1 (r* = 0.5: the norm series diverges there, " \
           "and the simulated pendulum blows up" in page
    assert "rho = 8 is not certified for eq (2)" in page and "(r* grows 1.25-fold)" in page
    assert "and is certified for its own eq (6)." in page
    assert "rho = 0.8 is also certified (r*" in page
    assert "prefactor one section reproduces its theta_3, with it dropped neither does" in page
    assert "The paper's theta_3 = 0.5 is not 0.5 x 1^3 = 1." in page


def test_page_summary_and_counts_follow_the_rows() -> None:
    page = render(_facts())
    assert "> 1 of 2 printed quantities are reproduced to the printed precision; every " \
           "other row says why not" in page
    assert "for eq (6) r* = 0.4 (not certified)" in page and "for rho above **15.1**" in page
    assert "Cart-poles: Theorem 2 gives no radius (r* = 0)" in page
    assert "Trials below a certified r*: 1; of these blew up (contradictions): 0." in page
    rows = (*_facts().rows, CheckRow(section="3 (rho = 8)", quantity="x", paper=1.0, ours=3.0,
                                     match=False, reason=""))
    sims = [["m", "polynomial", "cosine", 0.05, 0.5, True, False, 9.0, 2.0]]
    page = render(_facts(rows=rows, radius8=1.5, cart_radius=0.3, sim_rows=sims))
    assert "1 of 3 printed quantities" in page and "not every other row says why" in page
    assert "for eq (6) r* = 1.5 (certified)" in page
    assert "Cart-poles: Theorem 2's largest certified r* is 0.3" in page
    assert "(contradictions): 1." in page


def test_layout_is_filled() -> None:
    page = render(_facts())
    # the template's two headings and one from each section: figures, cart-pole, alpha
    assert page.count("\n## ") == PAGE.count("\n## ") + 3 == 6
    assert "{" not in page and page.endswith("the true stability boundary.\n")
