"""Model pages: rendered from their facts, every comparison sentence follows the numbers
(hand-made facts with swapped numbers), and the growth sentence follows its rows."""

from __future__ import annotations

from dataclasses import replace

import pytest

from gfrf.report.model_facts import (
    MarginFact,
    ModelPageFacts,
    NormFact,
    TrialFact,
    VerdictFacts,
)
from gfrf.report.model_page import growth_sentence, render


def _rows(power: int, relative_power: int) -> list[dict[str, float]]:
    """Rows of a difference c a^power and a relative difference c' a^relative_power."""
    return [{"angle_deg": a, "max_abs_error": 4e-8 * a**power,
             "relative_error": 2e-6 * a**relative_power} for a in (5.0, 10.0, 15.0)]


def test_a_cubic_difference_is_called_cubic() -> None:
    assert growth_sentence(_rows(3, 2)) == (
        "the difference grows like angle^3 (relative to the response: angle^2), the size "
        "of the neglected cubic terms.")


@pytest.mark.parametrize(("power", "relative", "size"), [(2, 1, "quadratic"),
                                                          (5, 4, "degree-5")])
def test_the_powers_follow_the_numbers(power: int, relative: int, size: str) -> None:
    text = growth_sentence(_rows(power, relative))
    assert f"like angle^{power} (relative to the response: angle^{relative})" in text
    assert f"the neglected {size} terms" in text


def test_the_cart_pole_rows_of_the_report_grow_like_the_cube() -> None:
    # the rows printed in reports/models/cartpole.md (5, 10, 15 degrees)
    rows = [{"angle_deg": 5.0, "max_abs_error": 4.7681e-06, "relative_error": 5.46384e-05},
            {"angle_deg": 10.0, "max_abs_error": 3.8567e-05, "relative_error": 0.000220973},
            {"angle_deg": 15.0, "max_abs_error": 0.000132609, "relative_error": 0.000506529}]
    assert "grows like angle^3 (relative to the response: angle^2)" in growth_sentence(rows)


# --- the page rendered from hand-made facts: every comparison follows its numbers -----------



def _verdict(**changes: object) -> VerdictFacts:
    base = VerdictFacts(theorem=1, verdict="stable", summary="A summary.", radius=0.5,
                        radius_certified=True, radius_proof="interval", radius_upper=None,
                        radius_upper_detail="", radius_estimate=None,
                        estimate_of="open-loop series",
                        conditions=(("H_n proper", True, "ok"), ("A stable", True, "ok")),
                        series=((1, 2.0, 1.0, None),))
    return replace(base, **changes)  # type: ignore[arg-type]


def _trial(amplitude: float, below: bool, bounded: bool) -> TrialFact:
    return TrialFact(kind="tone", amplitude=amplitude, below_radius=below, bounded=bounded,
                     peak=1.0, blowup_time=None if bounded else 3.0)


def _facts(**changes: object) -> ModelPageFacts:
    base = ModelPageFacts(
        name="Toy", stem="toy", path="models/toy.toml", regenerate="gfrf report x",
        source="", description="", equation_text="D(y) + y = u", polynomial="D(y) + y = u",
        truncation=0, sample_time=None, parameters=(), coefficients=(("y", 1, "linear"),),
        controller="", kernels=("H_{1} = 1", "H_{2} = 0", "H_{3} = 0"), discrete=False,
        closed=False, w3=None,
        norms=(NormFact(order=1, lower=1.0, upper=1.0, certified=True, argmax=(0.0,)),
               NormFact(order=2, lower=0.5, upper=0.75, certified=True, argmax=(1.0, 1.0))),
        norm_notes=(), order=2, verdict=_verdict(), margins=(), t_end=10.0, output="y",
        responses=(), trials=(_trial(0.25, True, True), _trial(1.0, False, False)),
        trial_scale=0.5, trial_scale_certified=True, contradictions=0,
        resonance="1 rad/s", growth=(), figures={"h1": "h1.png", "sim": "sim.png"})
    return replace(base, **changes)  # type: ignore[arg-type]


def test_headline_follows_the_proof_of_the_radius() -> None:
    assert "stable (L2) for every input amplitude r < r* = **0.5**" in render(_facts())
    estimate = render(_facts(verdict=_verdict(radius_proof="none", verdict="inconclusive")))
    assert "stable (L2)" not in estimate and "r* = 0.5 is an estimate" in estimate
    assert "r* is an estimate (not a proof)" in estimate
    failed = render(_facts(verdict=_verdict(
        radius=0.0, verdict="inconclusive",
        conditions=(("H_n proper", True, "ok"), ("A stable", False, "pole 1")))))
    assert "1 of 2 conditions fail: A stable)" in failed
    assert "the theorem's hypotheses fail" in failed


def test_trial_counts_follow_the_trials() -> None:
    text = render(_facts())
    assert "1/1 trials below r* stay bounded, 0/1 above; 0 contradiction(s)" in text
    swapped = render(_facts(trials=(_trial(0.25, True, False), _trial(0.3, True, True),
                                    _trial(1.0, False, True)), contradictions=1))
    assert "1/2 trials below r* stay bounded, 1/1 above; 1 contradiction(s)" in swapped
    assert "(a trial below r* that blew up): 1." in swapped
    none = render(_facts(trials=None))
    assert "No input trials (no positive radius to scale them)." in none
    uncertified = render(_facts(trial_scale_certified=False))
    assert "trials below the radius estimate" in uncertified
    assert "not applicable (no certified r*)" in uncertified


def test_exact_and_open_brackets_follow_the_norms() -> None:
    text = render(_facts())
    assert "||H1|| = 1, ||H2|| in [0.5, 0.75]" in text
    assert "orders [1]; open brackets: [2]" in text
    closed = NormFact(order=2, lower=0.75, upper=0.75, certified=True, argmax=(1.0, 1.0))
    swapped = render(_facts(norms=(_facts().norms[0], closed)))
    assert "||H2|| = 0.75" in swapped and "orders [1, 2]; open brackets: []" in swapped


def test_the_h3_slice_is_drawn_only_when_h3_is_not_zero() -> None:
    assert "H3 vanishes identically" in render(_facts())
    drawn = render(_facts(w3=2.0, figures={"h1": "a", "h3": "b.png", "sim": "c"}))
    assert "w3 = 2 rad/s fixed" in drawn and "![|H3| slice](b.png)" in drawn


def test_margins_follow_their_boundary() -> None:
    text = render(_facts(margins=(
        MarginFact(parameter="rho", current=8.0, direction="above", value=15.02391,
                   tolerance=1e-4),
        MarginFact(parameter="g", current=9.81, note="the verdict does not change"))))
    assert "certified stable for rho above **15.024**" in text
    assert "- g (file value 9.81): the verdict does not change." in text
    below = render(_facts(margins=(MarginFact(parameter="rho", current=8.0, direction="below",
                                              value=3.5, tolerance=1e-2),)))
    assert "certified stable for rho below **3.5**" in below
    assert "## Margins" not in render(_facts())


def test_the_closed_loop_growth_sentence_follows_its_rows() -> None:
    rows = tuple((a, 4e-8 * a**2, 2e-6 * a) for a in (5.0, 10.0, 15.0))
    text = render(_facts(closed=True, growth=rows))
    assert "grows like angle^2 (relative to the response: angle^1)" in text
    rows = tuple((a, 4e-8 * a**3, 2e-6 * a**2) for a in (5.0, 10.0, 15.0))
    assert "neglected cubic terms" in render(_facts(closed=True, growth=rows))
