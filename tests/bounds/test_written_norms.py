"""Interval-grade norms, majorants, witnesses and r* are about the model as written.

The parser keeps the exact value of every written coefficient (``0.2`` is 1/5); a proven
(``interval``) bracket must contain the value of that model, not of its doubles.  The
references are closed forms evaluated by mpmath at 50 digits from the written rationals.
"""

from __future__ import annotations

import math
from fractions import Fraction

import flint
import mpmath
import pytest

from gfrf.bounds.majorant import linear_polynomials, majorant, plant_radius
from gfrf.bounds.norms import h1_norm, kernel_norm
from gfrf.bounds.rational import enclosed_sup, rational_sup
from gfrf.bounds.witness import kernel_ball
from gfrf.model.equation import parse_model

#: The damping 0.1 + 0.2 - 0.3 is 0 as written and 5.55e-17 in doubles.
ZERO_DAMPING = "D(y,2) + (0.1+0.2-0.3)*D(y) + y + 0.5*y**3 = u"
#: As written the damping is 1e-20; its double is 5.55e-17.
TINY_DAMPING = "D(y,2) + (0.1+0.2-0.3+1e-20)*D(y) + y + 0.5*y**3 = u"


def _oscillator_peak(damping: mpmath.mpf, stiffness: mpmath.mpf | int = 1) -> mpmath.mpf:
    """sup over w of 1/|k - w^2 + j c w| for c^2 < 2k (closed form)."""
    return 1 / (damping * mpmath.sqrt(stiffness - damping ** 2 / 4))


def test_zero_damping_as_written_has_no_proven_finite_norm_or_radius() -> None:
    model = parse_model(ZERO_DAMPING)
    doubles = rational_sup(*linear_polynomials(model))  # what the doubles would claim
    assert math.isfinite(doubles.upper) and doubles.upper > 1e15
    bound = h1_norm(model)
    assert bound.upper == math.inf and not bound.stable
    rad = plant_radius(majorant(model))
    assert rad.value == 0.0 or rad.proof != "interval"


def test_h1_bracket_contains_the_written_value_the_doubles_bracket_excludes() -> None:
    model = parse_model(TINY_DAMPING)
    with mpmath.workdps(50):
        written = _oscillator_peak(mpmath.mpf(10) ** -20)
        doubles = rational_sup(*linear_polynomials(model))
        assert not doubles.lower <= written <= doubles.upper  # the old claim is false
        bound = h1_norm(model)
        assert bound.proof == "interval"
        assert bound.lower <= written <= bound.upper
        assert bound.upper <= written * (1 + 1e-12)


@pytest.mark.parametrize("text, damping, stiffness", [
    ("D(y,2) + 0.05*D(y) + 2.45*y = u", "0.05", "2.45"),
    ("D(y,2) + 0.1*D(y) + 2.45/6*y - 0.41*y**3 = u", "0.1", "49/120"),
])
def test_h1_bracket_contains_the_mpmath_value_of_the_written_rationals(
        text: str, damping: str, stiffness: str) -> None:
    c, k = Fraction(damping), Fraction(stiffness)
    with mpmath.workdps(50):
        value = _oscillator_peak(mpmath.mpf(c.numerator) / c.denominator,
                                 mpmath.mpf(k.numerator) / k.denominator)
        bound = h1_norm(parse_model(text))
        assert bound.proof == "interval" and bound.lower <= value <= bound.upper


def test_irrational_coefficient_enclosed_around_pi() -> None:
    bound = h1_norm(parse_model("D(y,2) + pi/10*D(y) + y = u"))
    with mpmath.workdps(50):
        value = _oscillator_peak(mpmath.pi / 10)
        assert bound.lower <= value <= bound.upper
        assert bound.upper - bound.lower <= 1e-12 * value


def test_enclosed_sup_refuses_when_the_interval_may_reach_the_axis() -> None:
    one = (Fraction(1), Fraction(1))
    res = enclosed_sup([one], [one, (Fraction(-1, 10**30), Fraction(1, 10**30)), one])
    assert res.upper == math.inf and res.lower == 0.0 and res.reason


def test_witness_ball_is_the_written_kernel() -> None:
    # H2(0, 0) = -c for D(y) + y + c y^2 = u; as written c = 1/10, not the double 0.1
    ball = kernel_ball(parse_model("D(y) + y + 0.1*y**2 = u"), 2, (0.0, 0.0))
    saved = flint.ctx.prec
    flint.ctx.prec = 256
    try:
        assert ball.real.contains(flint.arb(flint.fmpq(-1, 10)))
        assert not ball.real.contains(flint.arb(-0.1))
    finally:
        flint.ctx.prec = saved


def test_majorant_weight_is_above_the_written_coefficient() -> None:
    # 0.41 as a double is below 41/100: the proven weight rounds up
    maj = majorant(parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u"))
    assert Fraction(maj.terms[0].weight) >= Fraction(41, 100)
    assert Fraction(majorant(parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u"),
                             "float").terms[0].weight) == Fraction(0.41)


def test_radius_of_the_written_cubic_below_its_closed_form() -> None:
    # X = beta1 r + g X^3 has r* = 2 / (3 beta1 sqrt(3 g)), g = 0.5 sup|1/A| = 0.5 beta1
    model = parse_model(TINY_DAMPING)
    rad = plant_radius(majorant(model))
    with mpmath.workdps(50):
        beta1 = _oscillator_peak(mpmath.mpf(10) ** -20)
        closed = 2 / (3 * beta1 * mpmath.sqrt(3 * beta1 / 2))
        doubles = rational_sup(*linear_polynomials(model)).upper
        assert rad.certified_below <= closed
        assert closed < 2 / (3 * doubles * math.sqrt(3 * doubles / 2))  # the doubles' r*


def test_kernel_norm_upper_is_the_written_majorant() -> None:
    bound = kernel_norm(parse_model(TINY_DAMPING), 3, max_boxes=0, searches=1)
    with mpmath.workdps(50):
        beta1 = _oscillator_peak(mpmath.mpf(10) ** -20)
        # M_3 = 0.5 K_0 beta1^3 = 0.5 beta1^4 here (sup|1/A| = sup|H1|)
        assert bound.upper >= 0.5 * beta1 ** 4 * (1 - 1e-12)
