"""Exact linear decisions are about the model as written: a damping that cancels to 0 in
decimals (0.1 + 0.2 - 0.3, by Fraction arithmetic on the decimal strings) but to
5.55e-17 in doubles leaves a pole pair on the imaginary axis, s = +-j (closed form)."""

from __future__ import annotations

from fractions import Fraction

from gfrf.bounds.majorant import written_polynomials
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import model_from_dict
from gfrf.stability.criteria import verdict
from gfrf.stability.loops import closed_loop

CANCELS = "0.1 + 0.2 - 0.3"


def test_the_linear_part_as_written_is_read_exactly() -> None:
    num, den = written_polynomials(parse_model("D(y,2) + 0.2*D(y) + 2.45/6*y = 0.3*u"),
                                   normalize=False)
    assert den == [1, Fraction(1, 5), Fraction(49, 120)] and num == [Fraction(3, 10)]


def test_an_undamped_plant_as_written_is_not_linearly_stable() -> None:
    assert Fraction("0.1") + Fraction("0.2") - Fraction("0.3") == 0 < 0.1 + 0.2 - 0.3
    v = verdict(parse_model(f"D(y,2) + ({CANCELS})*D(y) + y + 0.5*y**3 = u"), order=1,
                with_norms=False)
    condition = next(c for c in v.conditions if c.name == "linear part A_1 stable")
    assert condition.passed is False and "boundary" in condition.detail
    assert v.verdict != "stable"


def test_a_loop_undamped_as_written_is_not_stable() -> None:
    """y'' + y = u under u = -(c s + 1) y, c = 0.1 + 0.2 - 0.3: chi = s^2 + c s + 2."""
    loop = closed_loop(model_from_dict({"equation": "D(y,2) + y = u", "controller": {
        "num": [CANCELS, 1], "den": [1]}}))
    assert not loop.stable and not loop.outside
