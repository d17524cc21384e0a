"""Tests of gfrf.sim.system, gfrf.sim.simulation and gfrf.sim.fastsim against closed forms
and each other."""

import math
import re
import time
import warnings

import numpy as np
import pytest

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.sim.simulation import simulate
from gfrf.sim.system import build_system

MODELS = "models"


def test_first_order_step_closed_form():
    res = simulate(parse_model("2*D(y) + y = 3*u"), "step(t)", t_end=4.0, rtol=1e-10,
                   atol=1e-12)
    assert res.status == "ok"
    assert np.allclose(res.y, 3 * (1 - np.exp(-res.t / 2)), atol=1e-8)


def test_damped_oscillator_sine_closed_form():
    # y'' + 2 z w y' + w^2 y = cos(W t), zero state: steady state + homogeneous part
    w, z, W = 2.0, 0.3, 1.3
    res = simulate(parse_model(f"D(y,2) + {2*z*w}*D(y) + {w*w}*y = u"), f"cos({W}*t)",
                   t_end=30.0, method="dop853", rtol=1e-11, atol=1e-13)
    H = 1 / (w * w - W * W + 2j * z * w * W)
    wd = w * math.sqrt(1 - z * z)
    # homogeneous solution fixed by y(0) = y'(0) = 0
    A = -H.real
    B = (W * H.imag + z * w * A) / wd  # y'(0) = -W*Im(H)... derived: ss'(0) = -W*Im(H)
    ss = np.real(H * np.exp(1j * W * res.t))
    hom = np.exp(-z * w * res.t) * (A * np.cos(wd * res.t) + B * np.sin(wd * res.t))
    assert np.allclose(res.y, ss + hom, atol=1e-8)


def test_input_derivative_model():
    # y' + y = u' with u = sin(t): y = (cos t + sin t - e^{-t})/2... derived by hand:
    # Y = s/(s+1) U, steady state Re(j/(1+j) e^{jt}) = (cos t + sin t)/2, y(0)=0
    res = simulate(parse_model("D(y) + y = D(u)"), "sin(t)", t_end=5.0, rtol=1e-10,
                   atol=1e-12)
    expected = 0.5 * (np.cos(res.t) + np.sin(res.t) - np.exp(-res.t))
    assert np.allclose(res.y, expected, atol=1e-8)


def test_fast_path_matches_dop853():
    mf = load_model(f"{MODELS}/hanging_pendulum.toml")
    system = build_system(mf, equation="polynomial")
    ref = simulate(system, "0.05*sin(1.565*t)", t_end=40.0, method="dop853", rtol=1e-12,
                   atol=1e-14)
    fast = simulate(system, "0.05*sin(1.565*t)", t_end=40.0, method="fast", dt=0.005)
    assert fast.status == "ok"
    assert np.max(np.abs(fast.y - ref.y)) < 1e-8
    auto = simulate(system, "0.05*sin(1.565*t)", t_end=40.0, method="fast", rtol=1e-7)
    assert np.max(np.abs(auto.y - ref.y)) < 1e-7 * ref.peak * 2


def test_fast_rk4_is_fourth_order():
    system = build_system(parse_model("D(y,2) + 0.5*D(y) + y + 0.3*y**3 = u"))
    ref = simulate(system, "cos(t)", t_end=10.0, method="dop853", rtol=1e-13, atol=1e-15)
    errs = [np.max(np.abs(simulate(system, "cos(t)", t_end=10.0, method="fast", dt=dt).y
                          - ref.y)) for dt in (0.04, 0.02)]
    assert 12 < errs[0] / errs[1] < 20  # 2^4 = 16


@pytest.mark.parametrize("method", ["rk45", "fast"])
def test_blowup_reported(method):
    model = parse_model("D(y,2) + y - y**3 = u")
    # energy E = y'^2/2 + y^2/2 - y^4/4 above the barrier 1/4 with y' > 0: escapes
    res = simulate(model, None, t_end=20.0, initial=[1.5, 0.5], method=method, dt=0.001,
                   blowup=1e3)
    assert res.status == "blowup" and not res.bounded
    assert res.blowup_time is not None and 0.5 < res.blowup_time < 5.0
    assert np.all(np.isfinite(res.y)) and np.max(np.abs(res.y)) <= 1e3 * 1.01
    # escape time from the conserved energy: t = int dy / sqrt(2E - y^2 + y^4/2)
    from scipy.integrate import quad
    energy = 0.5**2 / 2 + 1.5**2 / 2 - 1.5**4 / 4
    t_exact = quad(lambda y: 1 / math.sqrt(2 * energy - y * y + y**4 / 2), 1.5, 1e3)[0]
    assert res.blowup_time == pytest.approx(t_exact, abs=2e-3)


def test_unstable_open_loop_warns():
    mf = load_model(f"{MODELS}/cartpole_reduced.toml")
    with pytest.warns(UserWarning, match="unstable"):
        res = simulate(mf, None, t_end=1.0, initial=[0.01, 0.0])
    assert any("unstable" in n for n in res.notes)


def test_closed_loop_improper_controller_linear_limit():
    # linear loop: (1 - 39.3185 a) th'' - 39.3185 b th' - (67.578 + 39.3185 c) th = 0
    mf = load_model(f"{MODELS}/cartpole_reduced.toml")
    a, b, c, k = 15.6, 379.3, 0.1331, 39.3185
    system = build_system(mf, closed_loop=True)
    assert any("improper" in n for n in system.notes)
    poles = np.roots([1 - k * a, -k * b, -(67.578 + k * c)])
    assert np.allclose(np.sort(system.linear_eigenvalues.real), np.sort(poles.real))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = simulate(system, None, t_end=3.0, initial=[1e-4, 0.0], rtol=1e-11, atol=1e-15)
    p1, p2 = poles
    # closed form with th(0) = 1e-4, th'(0) = 0
    expected = 1e-4 * (p2 * np.exp(p1 * res.t) - p1 * np.exp(p2 * res.t)) / (p2 - p1)
    assert np.allclose(res.y, expected, rtol=1e-5, atol=1e-12)
    # the plant input u = -(a th'' + b th' + c th) is reported, not the reference;
    # at t = 0: th' = 0, th'' = -1e-4 p1 p2 from the closed form
    assert res.u[0] == pytest.approx(-(a * (-1e-4 * p1 * p2) + c * 1e-4), rel=1e-6)


def test_narx_recursion_by_hand():
    mf = load_model(f"{MODELS}/narx_example.toml")
    res = simulate(mf, "step(t)", t_end=0.35)
    y = [0.0] * 4
    u = [1.0] * 4
    for k in range(4):
        y1 = y[k - 1] if k >= 1 else 0.0
        u1 = u[k - 1] if k >= 1 else 0.0
        u2 = u[k - 2] if k >= 2 else 0.0
        y[k] = 0.5 * y1 - 0.2 * y1**2 * u2 + u1
    assert np.allclose(res.y, y)


@pytest.mark.parametrize("kwargs, word", [({"t_end": 0.0}, "t_end"),
                                          ({"t_end": 1.0, "rtol": 0.0}, "rtol"),
                                          ({"t_end": 1.0, "method": "euler"}, "method"),
                                          ({"t_end": 1.0, "initial": [1, 2, 3]}, "initial")])
def test_bad_arguments(kwargs, word):
    with pytest.raises(ArgumentError, match=word):
        simulate(parse_model("D(y,2) + D(y) + y = u"), None, **kwargs)


def test_closed_loop_without_controller():
    with pytest.raises(ModelError, match="controller"):
        build_system(load_model(f"{MODELS}/duffing.toml"), closed_loop=True)


def _loop_file(equation, controller, **top):
    from gfrf.model.modelfile import model_from_dict
    return model_from_dict({"equation": equation, "controller": controller, **top})


PLANT = "D(y,2) + 0.5*D(y) + 2*y + y**3 = u"


@pytest.mark.parametrize("method", ["rk45", "dop853", "fast"])
@pytest.mark.parametrize("equation, num, den", [("u = 3*y", [3.0], [1.0]),
                                                ("D(u) + 2*u = 3*y", [3.0], [1.0, 2.0])])
def test_linear_polynomial_controller_matches_transfer_function(method, equation, num, den):
    poly = _loop_file(PLANT, {"equation": equation})
    tf = _loop_file(PLANT, {"num": num, "den": den})
    kw = dict(t_end=8.0, closed_loop=True, method=method, rtol=1e-11, atol=1e-13, dt=1e-3)
    a = simulate(poly, "0.3*sin(1.3*t)", initial=[0.2, 0.0], **kw)
    b = simulate(tf, "0.3*sin(1.3*t)", initial=[0.2, 0.0], **kw)
    assert a.status == b.status == "ok"
    assert np.max(np.abs(a.y - b.y)) < 1e-8
    assert np.max(np.abs(a.u - b.u)) < 1e-8


def test_nonlinear_polynomial_controller_matches_substituted_plant():
    # u = C(r - y) = 3 e + 0.5 e^3, e = r - y, substituted into the plant by hand
    loop = _loop_file(PLANT, {"equation": "u = 3*y + 0.5*y**3"})
    equivalent = parse_model("D(y,2) + 0.5*D(y) + 2*y + y**3 = 3*(u - y) + 0.5*(u - y)**3")
    kw = dict(t_end=10.0, method="dop853", rtol=1e-12, atol=1e-14, initial=[0.4, -0.1])
    a = simulate(loop, "0.5*sin(0.9*t)", closed_loop=True, **kw)
    b = simulate(equivalent, "0.5*sin(0.9*t)", **kw)
    assert np.max(np.abs(a.y - b.y)) < 1e-8
    e = 0.5 * np.sin(0.9 * a.t) - a.y
    assert np.allclose(a.u, 3 * e + 0.5 * e**3, atol=1e-12)


def test_polynomial_controller_with_plant_input_derivative():
    # (s^2+s+1) Y = (s+1) U, U = W, (s+2) W = 3 (R - Y)  =>
    # y''' + 3y'' + 6y' + 5y = 3r' + 3r, with y''(0) = w'(0) + w(0) = 3 r(0) = 0 for r = sin t
    loop = _loop_file("D(y,2) + D(y) + y = D(u) + u", {"equation": "D(u) + 2*u = 3*y"})
    equivalent = parse_model("D(y,3) + 3*D(y,2) + 6*D(y) + 5*y = 3*D(u) + 3*u")
    kw = dict(t_end=6.0, method="dop853", rtol=1e-12, atol=1e-14)
    a = simulate(loop, "sin(t)", closed_loop=True, **kw)
    b = simulate(equivalent, "sin(t)", **kw)
    assert np.max(np.abs(a.y - b.y)) < 1e-8


def test_implicit_polynomial_controller_matches_improper_transfer_function():
    # the controller uses D(y,2): plant and controller are solved jointly
    poly = _loop_file("D(y,2) - y + 0.3*y**3 = u", {"equation": "u = 0.1*D(y,2) + 4*D(y) + 6*y"})
    tf = _loop_file("D(y,2) - y + 0.3*y**3 = u", {"num": [0.1, 4.0, 6.0], "den": [1.0]})
    kw = dict(t_end=5.0, closed_loop=True, method="dop853", rtol=1e-12, atol=1e-14,
              initial=[0.3, 0.0])
    a, b = simulate(poly, None, **kw), simulate(tf, None, **kw)
    assert a.status == "ok" and np.max(np.abs(a.y - b.y)) < 1e-8


def test_polynomial_controller_refusals():
    too_improper = _loop_file("D(y) + y = u", {"equation": "u = D(y,2)"})
    with pytest.raises(ModelError, match="above the plant order"):
        build_system(too_improper, closed_loop=True)
    too_slow = _loop_file("D(y,2) + y = D(u,2)", {"equation": "D(u) + u = y"})
    with pytest.raises(ModelError, match="controller's output order"):
        build_system(too_slow, closed_loop=True)


NARX = "y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]"


def _narx_reference(r, controller, feedback=-1):
    """Hand recursion of NARX under u = w = C[e], e = r + feedback*y,
    w[k] = controller(e, w, k)."""
    n = r.size
    y, w, e = np.zeros(n), np.zeros(n), np.zeros(n)
    for k in range(n):
        y1 = y[k - 1] if k >= 1 else 0.0
        u1 = w[k - 1] if k >= 1 else 0.0
        u2 = w[k - 2] if k >= 2 else 0.0
        y[k] = 0.5 * y1 - 0.2 * y1**2 * u2 + u1
        e[k] = r[k] + feedback * y[k]
        w[k] = controller(e, w, k)
    return y, w


def test_narx_closed_loop_discrete_transfer_function():
    # C(z) = 0.3/(z - 0.2) (control.tf order, dt = plant sample time):
    # w[k] = 0.2 w[k-1] + 0.3 e[k-1], e = r - y
    mf = _loop_file(NARX, {"num": [0.3], "den": [1.0, -0.2]}, sample_time=0.1)
    res = simulate(mf, "0.5*sin(2*t)", t_end=5.0, closed_loop=True)
    r = 0.5 * np.sin(2 * res.t)
    y, u = _narx_reference(r, lambda e, w, k: (0.2 * w[k - 1] + 0.3 * e[k - 1]) if k else 0.0)
    assert res.t.size == 51 and np.max(np.abs(res.y - y)) < 1e-12
    assert np.max(np.abs(res.u - u)) < 1e-12


def test_narx_closed_loop_polynomial_controller():
    mf = _loop_file(NARX, {"equation": "u[k] = 0.4*y[k] + 0.1*y[k]**3 - 0.3*u[k-1]",
                           "feedback": 1}, sample_time=0.1)
    res = simulate(mf, "0.5*sin(2*t)", t_end=5.0, closed_loop=True)
    r = 0.5 * np.sin(2 * res.t)
    y, u = _narx_reference(r, lambda e, w, k: 0.4 * e[k] + 0.1 * e[k]**3
                           - 0.3 * (w[k - 1] if k else 0.0), feedback=1)
    assert np.max(np.abs(res.y - y)) < 1e-12 and np.max(np.abs(res.u - u)) < 1e-12


def test_narx_closed_loop_with_feedthrough_both_ways():
    # y[k] = 0.5 y[k-1] + 0.5 u[k], u = 0.8 (r[k] - y[k]): y[k] = (0.5 y[k-1] + 0.4 r[k]) / 1.4
    mf = _loop_file("y[k] = 0.5*y[k-1] + 0.5*u[k]", {"num": [0.8], "den": [1.0]},
                    sample_time=0.5)
    res = simulate(mf, "step(t)", t_end=3.0, closed_loop=True)
    y = np.zeros(7)
    for k in range(7):
        y[k] = (0.5 * (y[k - 1] if k else 0.0) + 0.4) / 1.4
    assert np.max(np.abs(res.y - y)) < 1e-14
    with pytest.raises(ModelError, match="not causal"):
        build_system(_loop_file(NARX, {"num": [1.0, 0.0], "den": [1.0]}, sample_time=0.1),
                     closed_loop=True)


def test_fast_auto_step_dissipative_duffing_stays_bounded():
    # From t_end/256 = 7.8 s steps both step-doubling runs blew up in
    # their first step and were taken as agreeing: a false blow-up at t = 7.8 s.
    # Energy E = y'^2/2 + y^2/2 + y^4/8 decreases (damping 0.2), so |y| <= 1 for ever.
    from scipy.integrate import solve_ivp

    t_end = 2000.0
    t_eval = np.linspace(0.0, t_end, 401)
    res = simulate(load_model(f"{MODELS}/duffing.toml"), None, t_end=t_end,
                   initial=[1.0, 0.0], method="fast", t_eval=t_eval, equation="polynomial")
    assert res.status == "ok" and res.t[-1] == t_end
    assert np.max(np.abs(res.y)) <= 1.0 + 1e-12
    ref = solve_ivp(lambda t, z: [z[1], -0.2 * z[1] - z[0] - 0.5 * z[0] ** 3], (0, t_end),
                    [1.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-13, t_eval=t_eval)
    assert np.max(np.abs(res.y - ref.y[0])) < 1e-7


def test_fast_auto_step_confirms_a_true_blowup():
    # the escape of test_blowup_reported with the automatic step: still a blow-up, at the
    # time the conserved energy gives (the two runs' blow-up times agree to 1 %)
    from scipy.integrate import quad

    res = simulate(parse_model("D(y,2) + y - y**3 = u"), None, t_end=20.0,
                   initial=[1.5, 0.5], method="fast", blowup=1e3)
    energy = 0.5**2 / 2 + 1.5**2 / 2 - 1.5**4 / 4
    t_exact = quad(lambda y: 1 / math.sqrt(2 * energy - y * y + y**4 / 2), 1.5, 1e3)[0]
    assert res.status == "blowup"
    assert res.blowup_time == pytest.approx(t_exact, rel=0.02)


def test_fast_agreement_rejects_runs_that_both_blew_up_at_once():
    from gfrf.sim.fastsim import _agree, _Run

    y = np.ones((2, 1))
    # coarse run: 256 steps of 7.8125 s, blew up at step 1; fine run at its step 1
    coarse, fine = _Run(y, 1, 7.8125, True), _Run(y, 1, 3.90625, True)
    assert not _agree(coarse, fine, False, 1e-8, 1e-10, 2000.0)
    # blow-up times 1.000 s and 0.999 s agree to 1 %
    assert _agree(_Run(y, 100, 0.01, True), _Run(y, 200, 0.004995, True), False, 1e-8, 1e-10,
                  2000.0)
    # one run finished, the other blew up: never
    assert not _agree(_Run(y, 256, 1.0, False), _Run(y, 3, 0.5, True), False, 1e-8, 1e-10,
                      256.0)


def test_fast_immediate_blowup_is_resolved_cheaply():
    # u = 1e300 sin(t): |y| passes 1e6 within ~1e-98 s; HEAD reported t = h (any h) and
    # the first fix doubled to MAX_STEPS (9 s, 1 GB).  Now each finer run stops just past
    # the blow-up and the time is resolved to BLOWUP_RESOLUTION * t_end.
    from gfrf.sim.fastsim import BLOWUP_RESOLUTION

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = simulate(load_model(f"{MODELS}/duffing.toml"), "1e300*sin(t)", t_end=10.0,
                       method="fast")
    assert res.status == "blowup" and res.blowup_time <= 2 * BLOWUP_RESOLUTION * 10.0
    assert np.all(np.isfinite(res.y)) and res.t.size >= 1


@pytest.mark.parametrize("method", ["rk45", "dop853", "radau", "lsoda"])
def test_work_budget_stops_scipy_run_with_its_time(method):
    # y' + y = step(t): y = 1 - exp(-t).  50 evaluations cannot reach t = 10 at rtol 1e-10;
    # the samples before the stop are still the solution, the message names the budget.
    budget = 50
    t_eval = np.linspace(0.0, 10.0, 1001)
    start = time.perf_counter()
    res = simulate(parse_model("D(y) + y = u"), "step(t)", t_end=10.0, method=method,
                   rtol=1e-10, atol=1e-12, t_eval=t_eval, max_evaluations=budget)
    assert time.perf_counter() - start < 5.0
    assert res.status == "failed" and not res.bounded and res.blowup_time is None
    match = re.search(r"stopped at t = (\S+) s of 10 s: (\d+) right-hand-side evaluations "
                      r"reached the work budget max_evaluations = 50", res.message)
    assert match, res.message
    t_stop, used = float(match.group(1)), int(match.group(2))
    assert budget <= used == res.nfev <= budget + 40  # overrun: at most one step's work
    assert 0.0 < res.t[-1] <= t_stop < res.t[-1] + 0.01 + 1e-6 and t_stop < 10.0
    assert np.allclose(res.y, 1.0 - np.exp(-res.t), atol=1e-6)


def test_default_budget_fits_a_long_accurate_run():
    # the largest bundled use (speed report): hanging pendulum, 200 s, RK45 at rtol 1e-10
    from gfrf.sim.integrate import MAX_RHS_EVALUATIONS

    res = simulate(load_model(f"{MODELS}/hanging_pendulum.toml"), "0.05*sin(1.565*t)",
                   t_end=200.0, rtol=1e-10, atol=1e-13)
    assert res.status == "ok" and res.nfev < MAX_RHS_EVALUATIONS / 10


@pytest.mark.parametrize("text", ["sin(1e300*t)", "0.1*exp(-t)*cos(4e6*t + 1)",
                                  "step(t - 0.5)*tan(1e7*t)"])
def test_input_tone_too_fast_for_the_budget_refused_up_front(text):
    start = time.perf_counter()
    with pytest.raises(ArgumentError, match=r"angular frequency .* periods over t_end = 1 s, "
                                            r"more than 500000 .*MAX_RHS_EVALUATIONS"):
        simulate(load_model(f"{MODELS}/duffing.toml"), text, t_end=1.0)
    assert time.perf_counter() - start < 5.0


def test_tone_refusal_follows_the_budget():
    # 1e4 rad/s over 1 s: 1591.5 periods; refused with 3000 evaluations, not with 4000
    model = parse_model("D(y) + y = u")
    with pytest.raises(ArgumentError, match="1592 periods.*max_evaluations = 3000"):
        simulate(model, "sin(1e4*t)", t_end=1.0, max_evaluations=3000)
    res = simulate(model, "sin(1e4*t)", t_end=1.0, max_evaluations=4000)
    assert res.status == "failed" and "max_evaluations = 4000" in res.message


def test_narx_longer_than_budget_refused():
    model = parse_model("y[k] = 0.5*y[k-1] + u[k]", sample_time=0.1)
    with pytest.raises(ArgumentError, match="10001 samples .* max_evaluations = 10000"):
        simulate(model, "sin(t)", t_end=1000.0, max_evaluations=10_000)
    assert simulate(model, "sin(t)", t_end=999.95, max_evaluations=10_000).t.size == 10_000
    with pytest.raises(ArgumentError, match="max_evaluations"):
        simulate(model, "sin(t)", t_end=1.0, max_evaluations=0)


def test_fast_plant_input_of_an_improper_loop_from_the_states():
    # u = C(r - y) = 2 e'' + 3 e' + 5 e, e = r - y, around y'' + 0.5 y' + 2 y + y^3 = u:
    # the compiled plant-input loop (it solves for y'') against u rebuilt by hand.
    mf = _loop_file(PLANT, {"num": [2.0, 3.0, 5.0], "den": [1.0]})
    res = simulate(mf, "0.3*sin(1.3*t)", t_end=4.0, closed_loop=True, method="fast",
                   dt=1e-3, initial=[0.2, 0.0])
    y, dy = res.states
    r = 0.3 * np.sin(1.3 * res.t)
    dr, ddr = 0.3 * 1.3 * np.cos(1.3 * res.t), -0.3 * 1.3**2 * np.sin(1.3 * res.t)
    # y'' from the loop equation: 3 y'' = 2 r'' + 3 r' + 5 r - 3.5 y' - 7 y - y^3
    ddy = (2.0 * ddr + 3.0 * dr + 5.0 * r - 3.5 * dy - 7.0 * y - y**3) / 3.0
    assert res.status == "ok" and res.u.shape == res.t.shape
    assert np.allclose(res.u, 2.0 * (ddr - ddy) + 3.0 * (dr - dy) + 5.0 * (r - y),
                       rtol=0, atol=1e-12)


def test_fast_cache_file_that_differs_is_rewritten_not_run(tmp_path, monkeypatch):
    from gfrf.sim import fastsim

    monkeypatch.setenv("GFRF_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(fastsim, "_MODULES", {})
    system = build_system(parse_model("D(y) + 2*y = u"))
    fastsim.compile_system(system)
    (path,) = (tmp_path / "fastsim").glob("gfrf_rhs_*.py")
    good = path.read_text(encoding="utf-8")
    sentinel = tmp_path / "planted-ran"
    path.write_text(f"open({str(sentinel)!r}, 'w').close()\n", encoding="utf-8")
    monkeypatch.setattr(fastsim, "_MODULES", {})
    res = simulate(system, "step(t)", t_end=1.0, method="fast", dt=1e-3)
    assert not sentinel.exists() and path.read_text(encoding="utf-8") == good
    assert abs(res.y[-1] - (1 - math.exp(-2.0)) / 2) < 1e-10
