"""The exact value of every coefficient as written (decimals are exact rationals) rides
beside its double, and the proofs use it: a proven statement is about the model the
user wrote, not about its rounding to doubles.

Independent references: Fraction arithmetic on the decimal strings, mpmath at 50 digits,
and the closed form of a cubic's static fold.
"""

from __future__ import annotations

import dataclasses
import math
from fractions import Fraction

import mpmath as mp
import pytest

from gfrf.model.equation import parse_model
from gfrf.model.modelfile import Controller, model_from_dict
from gfrf.model.scaling import amplitude_scaled, normalized
from gfrf.stability.energy import energy_certificate
from gfrf.stability.polysys import StateFormError, state_form
from gfrf.stability.static import radius_upper


def _exact(model, y_orders, u_orders=()):  # type: ignore[no-untyped-def]
    return next(t.exact for t in model.terms
                if t.y_orders == y_orders and t.u_orders == u_orders)


def test_constant_arithmetic_on_decimals_stays_rational() -> None:
    m = parse_model("D(y,2) + 0.2*D(y) + 2.45/6*y - 1.5e-3*y**3 + 0.3**2*y**2 = u")
    assert _exact(m, (1,)) == Fraction("0.2") == Fraction(1, 5)
    assert _exact(m, (0,)) == Fraction("2.45") / 6 == Fraction(49, 120)
    assert _exact(m, (0, 0, 0)) == -Fraction(3, 2000)
    assert _exact(m, (0, 0)) == Fraction(9, 100)
    # the double path is untouched: the float the parser always computed
    assert next(t.coefficient for t in m.terms if t.y_orders == (0,)) == 2.45 / 6


def test_model_file_parameters_and_controller_keep_the_written_values() -> None:
    mf = model_from_dict({
        "equation": "D(y,2) + c*D(y) + w*y = u",
        "parameters": {"c": 0.145, "w": "2.45/6"},
        "controller": {"num": [0.2, "w"], "den": [1.0, 0.0]}})
    assert _exact(mf.plant, (1,)) == Fraction(29, 200)
    assert _exact(mf.plant, (0,)) == Fraction(49, 120)
    assert mf.controller is not None
    assert mf.controller.exact_tf() == ((Fraction(1, 5), Fraction(49, 120)),
                                        (Fraction(1), Fraction(0)))
    # a python-control style controller holds doubles: they are its model
    doubles = Controller(num=(0.2,), den=(1.0,))
    assert doubles.exact_tf() == ((Fraction(0.2),), (Fraction(1),))
    assert Fraction(0.2) != Fraction(1, 5)


def test_the_state_form_of_a_decimal_model_is_the_written_one() -> None:
    system = state_form(parse_model("D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u"))
    last = system.f[-1]
    assert last[(0, 1, 0)] == Fraction(-1, 5)
    assert last[(3, 0, 0)] == Fraction(3, 10)
    loop = state_form(model_from_dict({"equation": "D(y,2) + 0.2*D(y) + y = u",
                                       "controller": {"num": [0.5, 0.2], "den": [1, 0]}}))
    assert Fraction(1, 5) in loop.f[1].values()  # u = 0.5 e + 0.2 z, z the PI state


def test_an_irrational_coefficient_is_bounded_and_refused_by_the_exact_engine() -> None:
    m = parse_model("D(y,2) + pi*D(y) + sqrt(2)*y = u")
    with mp.workdps(50):
        for term, value in ((next(t for t in m.terms if t.y_orders == (1,)), mp.pi),
                            (next(t for t in m.terms if t.y_orders == (0,)), mp.sqrt(2))):
            assert term.exact is None
            lo, hi = term.bounds()
            assert mp.mpf(lo.numerator) / lo.denominator < value \
                < mp.mpf(hi.numerator) / hi.denominator
            assert hi - lo < Fraction(1, 10**13)
    with pytest.raises(StateFormError, match="not rational"):
        state_form(m)


def test_a_changed_double_falls_back_to_itself_and_a_power_of_two_scaling_is_exact() -> None:
    m = parse_model("4*D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u")
    damping = next(t for t in m.terms if t.y_orders == (1,))
    moved = dataclasses.replace(damping, coefficient=0.25)
    assert moved.exact == Fraction(1, 4)  # the written 1/5 belongs to another double
    assert _exact(normalized(m), (1,)) == Fraction(1, 20)  # divided by 4 exactly
    assert _exact(amplitude_scaled(m, 3), (0, 0, 0)) == Fraction(-3, 10) * 2 ** 6
    # the same doubles without written values (equal as models) keep their own values
    doubles = dataclasses.replace(m, terms=tuple(dataclasses.replace(t, written=None)
                                                 for t in m.terms))
    assert doubles == m
    assert _exact(normalized(doubles), (1,)) == Fraction(0.2) / 4


def test_a_monomial_that_cancels_in_doubles_but_not_as_written_is_kept() -> None:
    # as written the damping is 0.1 + 0.2 - 0.3 = 0; in doubles it is 5.55e-17
    m = parse_model("D(y,2) + (0.1 + 0.2 - 0.3)*D(y) + y = u")
    assert _exact(m, (1,)) == 0
    assert next(t.coefficient for t in m.terms if t.y_orders == (1,)) == 0.1 + 0.2 - 0.3


def test_proofs_follow_the_written_sign_where_the_double_has_the_other() -> None:
    """y'' + 0.2y' + y + c y^3 = u with c = 0.1 + 0.2 - 0.3 - 1e-17: as written c =
    -1e-17 (softening: a static fold at |u| = 2 / (3 sqrt(3 |c|)), escape beyond), in
    doubles c = +4.55e-17 (hardening, globally bounded).  A proof about the doubles
    would certify boundedness for every input size, false for the model as written."""
    c = Fraction("0.1") + Fraction("0.2") - Fraction("0.3") - Fraction("1e-17")
    assert c == Fraction(-1, 10**17) and 0.1 + 0.2 - 0.3 - 1e-17 > 0
    m = parse_model("D(y,2) + 0.2*D(y) + y + (0.1 + 0.2 - 0.3 - 1e-17)*y**3 = u")
    assert energy_certificate(m) is None
    bound = radius_upper(m)
    assert bound is not None
    assert bound.value == pytest.approx(2 / (3 * math.sqrt(3 * 1e-17)), rel=1e-9)
