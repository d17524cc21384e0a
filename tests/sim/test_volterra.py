"""Volterra prediction vs closed forms and vs the simulated (shot) steady state."""

import itertools
import math
import re

import numpy as np
import pytest

from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.sim import volterra
from gfrf.sim.truncation import base_frequency, compare, error_vs_amplitude, select_order
from gfrf.sim.volterra import (
    MAX_PRODUCTS,
    BeyondRadiusError,
    NoSteadyStateError,
    input_amplitude,
    intermodulation_count,
    predict,
)

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
    A, w = 0.03, 0.7  # inside r* = 0.0483 (predict refuses beyond it)
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


@pytest.mark.slow
def test_select_order_verified_by_simulation():
    A, tol = 0.004, 2e-5
    choice = select_order(PENDULUM, A, tol, max_order=5)
    errors = compare(PENDULUM, [(A, W_PEAK, 0.0)], orders=(1, 3, 5))["errors"]
    assert errors[choice.order] < tol
    assert choice.bound >= errors[choice.order]
    lower = [n for n in (1, 3, 5) if n < choice.order]
    assert all(choice.terms.get(n + 2, 0) > 0 for n in lower)


# -- where the prediction is meaningful: the series radius, and bounded work ------------
ZETA = 0.1  # y'' + 2 zeta y' + y + 0.5 y^3 = u


def duffing_radius() -> float:
    """r* = 2 / (3 beta sqrt(3 g)) of X = beta r + g X^3 (closed form), beta = ||H1||,
    g = 0.5 sup|1/A|, with ||H1|| = sup|1/A| = 1 / (2 zeta sqrt(1 - zeta^2))."""
    beta = 1.0 / (2 * ZETA * math.sqrt(1 - ZETA**2))
    return 2.0 / (3.0 * beta * math.sqrt(3.0 * 0.5 * beta))


DUFFING = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")


def test_radius_is_the_closed_form_and_refusal_brackets_it():
    r_star = duffing_radius()
    with pytest.raises(BeyondRadiusError) as err:
        predict(DUFFING, [(1.001 * r_star, 1.0, 0.0)], 3)
    assert err.value.radius == pytest.approx(r_star, rel=1e-9)
    assert f"{r_star:.6g}" in str(err.value) and f"{1.001 * r_star:.6g}" in str(err.value)
    inside = predict(DUFFING, [(0.999 * r_star, 1.0, 0.0)], 3)
    assert inside.warning is None and inside.radius == pytest.approx(r_star, rel=1e-9)


def test_multitone_amplitude_is_the_sum_of_tone_amplitudes():
    r_star = duffing_radius()
    tones = [(0.6 * r_star, 1.0, 0.0), (-0.6 * r_star, 1.5, 0.3)]  # each alone is inside
    assert input_amplitude(tones) == pytest.approx(1.2 * r_star, rel=1e-15)
    with pytest.raises(BeyondRadiusError) as err:
        predict(DUFFING, tones, 3)
    assert err.value.amplitude == pytest.approx(1.2 * r_star, rel=1e-15)
    forced = predict(DUFFING, tones, 3, force=True)
    assert forced.warning and "r* =" in forced.warning and forced.to_dict()["warning"]


def test_pendulum_far_beyond_radius_refused():
    # a reported case: 0.5 N m at 1.565 rad/s predicted 1020.9 rad (simulated peak 1.75)
    with pytest.raises(BeyondRadiusError):
        predict(PENDULUM, [(0.5, 1.565, -math.pi / 2)], 3)


def test_overflow_never_returned():
    with pytest.raises(ArgumentError, match="not finite"):
        predict(DUFFING, [(1e300, 1.0, 0.0)], 3, force=True)


def test_intermodulation_closed_form_and_ordered_tuples():
    # Y(2 w1 - w2) at order 3 is 3 H3(w1, w1, -w2) c1^2 conj(c2) (3 orderings), with
    # H3(a, b, c) = -0.5 H1(a) H1(b) H1(c) H1(a + b + c) for this Duffing oscillator
    h1 = lambda x: 1 / (1 - x * x + 0.2j * x)  # noqa: E731
    (a1, w1, p1), (a2, w2, p2) = tones = [(0.01, 1.0, 0.2), (0.008, 1.7, -0.4)]
    c1, c2 = a1 / 2 * np.exp(1j * p1), a2 / 2 * np.exp(1j * p2)
    omega = 2 * w1 - w2
    expected = 3 * -0.5 * h1(w1) ** 2 * h1(-w2) * h1(omega) * c1**2 * np.conj(c2)
    p = predict(DUFFING, tones, 3)
    assert p.component(omega).value == pytest.approx(expected, rel=1e-12)
    # every component against the plain sum over all ordered n-tuples of signed tones
    om = np.array([w1, -w1, w2, -w2])
    ph = np.array([c1, np.conj(c1), c2, np.conj(c2)])
    brute: dict[float, complex] = {}
    for n in (1, 3):
        k = kernel(DUFFING, n)
        for combo in itertools.product(range(4), repeat=n):
            total = round(float(om[list(combo)].sum()), 9)
            value = complex(k(*om[list(combo)])) * np.prod(ph[list(combo)])
            brute[total] = brute.get(total, 0j) + value
    assert len(p.components) == len([t for t in brute if t >= 0])
    for total, value in brute.items():
        if total >= 0:
            assert p.component(total).value == pytest.approx(value, rel=1e-12, abs=1e-30)


def test_product_limit_checked_before_any_kernel(monkeypatch):
    tones = [(1e-4, 1.0 + 0.1 * i, 0.0) for i in range(40)]
    expected = sum(math.comb(80 + n - 1, n) for n in (1, 3, 5))  # odd orders only
    assert intermodulation_count(DUFFING, 40, 5) == expected > MAX_PRODUCTS
    monkeypatch.setattr(volterra, "kernel", lambda *a, **k: pytest.fail("kernel built"))
    with pytest.raises(ArgumentError, match="MAX_PRODUCTS"):
        predict(DUFFING, tones, 5)
    with pytest.raises(ArgumentError, match="MAX_KERNEL_ORDER"):
        predict(DUFFING, tones[:1], 13)


def test_select_order_refuses_beyond_radius():
    with pytest.raises(BeyondRadiusError):
        select_order(DUFFING, 1.01 * duffing_radius(), 1e-3)


def test_unstable_linear_part_has_no_steady_state():
    # open-loop reduced cart-pole: theta'' - 67.578 theta = -39.3185 u, pole +sqrt(67.578)
    cartpole = load_model("models/cartpole_reduced.toml").plant
    pole = f"s = {math.sqrt(67.578):.6g}"
    with pytest.raises(NoSteadyStateError, match=f"unstable \\(pole {pole}.*no steady state"):
        predict(cartpole, [(1e-3, 1.0, 0.0)], 3)
    with pytest.raises(NoSteadyStateError):
        select_order(cartpole, 1e-3, 1e-6)
    forced = predict(cartpole, [(1e-3, 1.0, 0.0)], 1, force=True)
    assert "no steady state exists" in forced.warning
    # H1(j) = -39.3185 / (-1 - 67.578): the forced value is still the formal kernel sum
    assert forced.component(1.0).amplitude == pytest.approx(1e-3 * 39.3185 / 68.578, rel=1e-12)


@pytest.mark.parametrize("text, sample_time, where", [
    ("D(y,2) + y + y**3 = u", None, "boundary at s = +-1j"),
    ("y[k] = 1.2*y[k-1] + u[k-1]", 0.1, "unstable (pole z = 1.2"),
])
def test_marginal_or_unstable_linear_part_refused(text, sample_time, where):
    model = parse_model(text, sample_time=sample_time)
    with pytest.raises(NoSteadyStateError, match=re.escape(where)):
        predict(model, [(1e-3, 2.0, 0.0)], 3)


def test_shooting_stops_on_its_work_budget():
    # 999 rad/s beside 1 rad/s: a common period of 2 pi s holds 999 fast periods
    import time

    from gfrf.errors import ConvergenceError
    from gfrf.sim.system import build_system
    from gfrf.sim.truncation import steady_state

    system = build_system(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    start = time.perf_counter()
    with pytest.raises(ConvergenceError, match="max_evaluations = 5000 "):
        steady_state(system, [(0.01, 1.0, 0.0), (0.01, 999.0, 0.0)], max_evaluations=5000)
    assert time.perf_counter() - start < 5.0


def test_predict_and_verdict_report_the_same_radius_and_proof() -> None:
    """One r* for the norm series: the prediction's is the verdict's, with its proof level."""
    from gfrf.sim.volterra import predict
    from gfrf.stability.criteria import verdict

    model = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    v = verdict(model, 3, 0.01)
    p = predict(model, [(0.01, 1.2, 0.0)], 3)
    assert p.radius == v.radius and p.radius_proof == v.radius_proof == "interval"
    # Duffing's majorant radius in closed form: 2 / (3 beta sqrt(3 * 0.5 beta)), beta = ||H1||
    beta = 1.0 / (0.2 * (1.0 - 0.01) ** 0.5)
    assert p.radius == pytest.approx(2.0 / (3.0 * beta * (3.0 * 0.5 * beta) ** 0.5), rel=1e-9)
