"""Volterra prediction vs closed forms and vs the simulated (shot) steady state."""

import math

import numpy as np
import pytest

from gfrf.errors import ArgumentError
from gfrf.model import parse_model
from gfrf.modelfile import load_model
from gfrf.volterra import base_frequency, compare, error_vs_amplitude, predict, select_order

PENDULUM = load_model("models/hanging_pendulum.toml").plant
W_PEAK = math.sqrt(2.45)  # rad/s, the 0.25 Hz peak of H1


def test_linear_prediction_closed_form():
    # y'' + y' + 4y = u, u = 3 cos(2t + 0.5): H1(2j) = 1/(4 - 4 + 2j) = -0.5j
    p = predict(parse_model("D(y,2) + D(y) + 4*y = u"), [(3.0, 2.0, 0.5)], order=3)
    (c,) = p.components
    assert c.omega == 2.0 and c.amplitude == pytest.approx(1.5)
    assert c.phase == pytest.approx(0.5 - math.pi / 2)


def test_duffing_third_harmonic_first_term_closed_form():
    # y'' + 0.2y' + y + 0.5y^3 = u: Y(3w) to order 3 is H3(w,w,w)(A/2)^3 with
    # H3(w,w,w) = -0.5 H1(w)^3 H1(3w), H1(w) = 1/(1 - w^2 + 0.2jw)
    A, w = 0.3, 0.7
    h1 = lambda x: 1 / (1 - x * x + 0.2j * x)  # noqa: E731
    expected = -0.5 * h1(w) ** 3 * h1(3 * w) * (A / 2) ** 3
    p = predict(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), [(A, w, 0.0)], 3)
    assert p.component(3 * w).value == pytest.approx(expected, rel=1e-12)
    assert p.component(2 * w) is None  # no even harmonics in an odd system


def test_error_slope_hanging_pendulum():
    data = error_vs_amplitude(PENDULUM, W_PEAK, np.geomspace(1e-3, 4e-3, 3))
    # odd system: H2 = H4 = 0, so the order-N error is led by H_{N+2}: slope N + 2
    for n, slope in data["slopes"].items():
        assert slope == pytest.approx(n + 2, abs=0.15)


def test_third_harmonic_predicted_vs_simulated():
    A = 0.005
    res = compare(PENDULUM, [(A, W_PEAK, 0.0)], orders=(5,))
    sim = res["steady_state"].harmonic(3)
    pred = predict(PENDULUM, [(A, W_PEAK, 0.0)], 5).component(3 * W_PEAK).value
    assert abs(sim) > 1e-7  # the third harmonic exists, as the paper says
    assert abs(pred - sim) < 1e-2 * abs(sim)


def test_multitone_intermodulation():
    duffing = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    tones = [(0.02, 1.0, 0.0), (0.015, 1.5, 0.3)]
    assert base_frequency(tones) == pytest.approx(0.5)
    res = compare(duffing, tones, orders=(1, 3))
    assert res["errors"][3] < 0.05 * res["errors"][1]
    ss = res["steady_state"]
    pred = predict(duffing, tones, 3)
    # intermodulation 2*1.0 - 1.5 = 0.5 rad/s is harmonic m = 1 of w0 = 0.5
    assert pred.component(0.5).value == pytest.approx(ss.harmonic(1), rel=0.05)


def test_incommensurate_rejected():
    with pytest.raises(ArgumentError, match="commensurate"):
        base_frequency([(1.0, 1.0, 0.0), (1.0, math.sqrt(2), 0.0)])


def test_select_order_verified_by_simulation():
    A, tol = 0.004, 2e-5
    choice = select_order(PENDULUM, A, tol, max_order=5)
    errors = compare(PENDULUM, [(A, W_PEAK, 0.0)], orders=(1, 3, 5))["errors"]
    assert errors[choice.order] < tol
    assert choice.bound >= errors[choice.order]
    lower = [n for n in (1, 3, 5) if n < choice.order]
    assert all(choice.terms.get(n + 2, 0) > 0 for n in lower)
