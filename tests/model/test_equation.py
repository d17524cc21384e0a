"""Tests of gfrf.model.equation: parsing, truncation and the bad-input catalogue."""

import math

import pytest

from gfrf.errors import ModelError
from gfrf.model.equation import parse_model


def _coefficients(model):
    return {(t.y_orders, t.u_orders): t.coefficient for t in model.terms}


def test_pendulum_text_of_the_paper():
    m = parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u")
    assert _coefficients(m) == {((2,), ()): 1.0, ((1,), ()): 0.05, ((0,), ()): 2.45,
                                ((0, 0, 0), ()): -0.41, ((), (0,)): -1.0}
    assert m.linear_output == {0: 2.45, 1: 0.05, 2: 1.0}
    assert m.linear_input == {0: -1.0}
    assert (m.degree, m.max_order, m.is_discrete) == (3, 2, False)


def test_cross_terms_and_products_of_derivatives():
    m = parse_model("D(y,2) - 67.578*y + 11.2455*y**3 + 0.1475*y*D(y)**2 "
                    "+ 0.1475*y**2*D(y,2) + 39.3185*u - 19.66*y**2*u = 0")
    c = _coefficients(m)
    assert c[((0, 1, 1), ())] == 0.1475
    assert c[((0, 0, 2), ())] == 0.1475
    assert c[((0, 0), (0,))] == -19.66


def test_sin_truncation_gives_minus_one_sixth():
    m = parse_model("D(y,2) + b*D(y) + c*sin(y) = u", truncation=3,
                    parameters={"b": 0.1, "c": 3.0})
    c = _coefficients(m)
    assert c[((0, 0, 0), ())] == pytest.approx(-0.5, rel=1e-15)
    assert c[((0,), ())] == pytest.approx(3.0)
    m5 = parse_model("D(y,2) + sin(y) = u", truncation=5)
    assert _coefficients(m5)[((0,) * 5, ())] == pytest.approx(1 / 120, rel=1e-14)
    # the untruncated equation is kept for simulation
    assert "sin" in str(m.physical)


def test_truncation_of_products_of_trig_and_derivatives():
    m = parse_model("(2 - cos(y)**2)*D(y,2) + sin(y) = cos(y)*u", truncation=3)
    c = _coefficients(m)
    # 2 - cos^2 = 1 + y^2 + O(y^4); cos(y)*u = u - y^2 u / 2
    assert c[((2,), ())] == pytest.approx(1.0)
    assert c[((0, 0, 2), ())] == pytest.approx(1.0)
    assert c[((0, 0), (0,))] == pytest.approx(0.5)


def test_narx_lags():
    m = parse_model("y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]", sample_time=0.1)
    assert m.is_discrete and m.sample_time == 0.1
    assert _coefficients(m) == {((0,), ()): 1.0, ((1,), ()): -0.5, ((), (1,)): -1.0,
                                ((1, 1), (2,)): 0.2}


def test_custom_signal_names_and_multiline_text():
    m = parse_model("D(theta,2)\n  + 2*theta = torque", output="theta", input="torque")
    assert m.equation() == "2*theta + D(theta,2) - torque = 0"


@pytest.mark.parametrize("text, kwargs, fragment", [
    ("D(y,2) + (y = u", {}, "cannot parse"),
    ("D(y,2) + 2*y", {}, "no input"),
    ("u = 3*u**2", {}, "no output"),
    ("D(y,2) + exp(y) = u", {}, "exp(y)"),
    ("y**2 + D(y)**3 = u", {}, "no linear term in the output"),
    ("D(y,2) + nan*y = u", {}, "NaN"),
    ("D(y,2) + oo*y = u", {}, "infinite"),
    ("D(y,-1) + y = u", {}, "negative derivative order"),
    ("D(y,400) + y = u", {}, "exceeds the limit"),
    ("D(y,2) + z*y = u", {}, "unknown symbol(s) z"),
    ("D(y,2) + y*t = u", {}, "depends explicitly on time"),
    ("D(y,2) + y = u = 0", {}, "more than one '='"),
    ("D(y,2) + y + 1 = u", {}, "constant term"),
    ("D(x,2) + y = u", {}, "first argument"),
    ("y[k] = y[k+1] + u[k-1]", {"sample_time": 1.0}, "future"),
    ("y[k] = 0.5*y[k-1] + u[k-1]", {"sample_time": -1.0}, "sample_time"),
    ("", {}, "empty equation"),
    ("D(y,2) + y = u", {"truncation": -2}, "truncation"),
    ("D(y,2) + y = u", {"parameters": {"a": float("inf")}}, "finite"),
])
def test_bad_input_is_a_model_error_naming_the_problem(text, kwargs, fragment):
    with pytest.raises(ModelError) as info:
        parse_model(text, **kwargs)
    assert fragment in str(info.value)
    assert isinstance(info.value, ValueError)


def test_coefficients_are_finite_floats():
    m = parse_model("D(y,2) + 1e-12*D(y) + 1e6*y + 3*y**2 = 1e3*u")
    assert all(math.isfinite(t.coefficient) for t in m.terms)
