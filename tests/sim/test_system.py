"""The closed loop of the simulator is u = C(r + feedback*y), the loop Theorem 2, the
certificate engine's state form and python-control's ``feedback(C*G, 1)`` speak of.

Independent references: python-control's forced response of the linear loop, the
certificate engine's exact polynomial state form integrated by scipy, the linear loop's
y/r against the simulated first harmonic of a nonlinear loop at small amplitude."""

from __future__ import annotations

import math
import warnings

import control
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.errors import ArgumentError
from gfrf.model.modelfile import model_from_dict
from gfrf.sim.simulation import simulate
from gfrf.stability.loops import closed_loop
from gfrf.stability.polysys import peval, state_form

PLANT2 = "D(y,2) + 0.4*D(y) + 2*y = u"
PLANT3 = "D(y,3) + 1.2*D(y,2) + 3*D(y) + y = 2*u"
# r and its first two derivatives vanish at t = 0: the loop starts at rest with no
# impulse from an improper controller, as python-control's state-space loop does
REFERENCE = "0.7*sin(1.3*t)**3 + 0.2*sin(0.4*t)**3"


def _reference(t: np.ndarray) -> np.ndarray:
    return 0.7 * np.sin(1.3 * t) ** 3 + 0.2 * np.sin(0.4 * t) ** 3


def _loop(plant: str, num: list[float], den: list[float], feedback: int = -1):
    return model_from_dict({"equation": plant,
                            "controller": {"num": num, "den": den, "feedback": feedback}})


@pytest.mark.filterwarnings("ignore:the linearisation of the closed loop is unstable")
@pytest.mark.parametrize("plant, g, num, den, feedback", [
    (PLANT2, ([1.0], [1.0, 0.4, 2.0]), [0.5, 0.2], [1.0, 0.0], -1),   # PI
    (PLANT2, ([1.0], [1.0, 0.4, 2.0]), [0.5, 0.2], [1.0, 0.0], 1),
    (PLANT2, ([1.0], [1.0, 0.4, 2.0]), [0.3, 1.0, 2.0], [1.0], -1),   # improper: r', r''
    (PLANT3, ([2.0], [1.0, 1.2, 3.0, 1.0]), [0.3, 0.2], [1.0, 1.0], -1),  # lead-lag
    (PLANT3, ([2.0], [1.0, 1.2, 3.0, 1.0]), [0.3, 0.2], [1.0, 1.0], 1),
])
def test_linear_loop_is_python_controls_feedback_of_c_times_g(plant, g, num, den, feedback):
    t = np.linspace(0.0, 10.0, 50001)  # fine: forced_response holds r linear per step
    expected = control.forced_response(
        control.feedback(control.tf(num, den) * control.tf(*g), 1, sign=feedback), t,
        _reference(t)).outputs
    res = simulate(_loop(plant, num, den, feedback), REFERENCE, t_end=10.0, t_eval=t,
                   closed_loop=True, method="dop853", rtol=1e-12, atol=1e-14)
    assert res.status == "ok"
    assert np.max(np.abs(res.y - expected)) < 1e-8 * max(1.0, float(np.max(np.abs(expected))))


def test_plant_input_is_the_controller_acting_on_the_error():
    # u = 0.5 e + 0.2 int(e), e = r - y: the integral from the trapezoid rule on a fine grid
    t = np.linspace(0.0, 6.0, 60001)
    res = simulate(_loop(PLANT2, [0.5, 0.2], [1.0, 0.0]), REFERENCE, t_end=6.0, t_eval=t,
                   closed_loop=True, method="dop853", rtol=1e-12, atol=1e-14)
    e = _reference(t) - res.y
    integral = np.concatenate(([0.0], np.cumsum(0.5 * (e[1:] + e[:-1]) * np.diff(t))))
    assert np.max(np.abs(res.u - (0.5 * e + 0.2 * integral))) < 1e-7


def test_simulated_loop_is_the_certificate_engines_state_form():
    # the lower side (sum-of-squares certificates) works on polysys's exact state form of
    # the PI loop; the upper side (simulation, falsifier) on the simulator's: the same ODE
    mf = _loop("D(y,2) + 0.4*D(y) + 2*y + 0.5*y**3 = u", [0.5, 0.2], [1.0, 0.0])
    system = state_form(mf)
    assert system.input_name.startswith("r ") and "C(r - y)" in system.input_name

    def f(t: float, x: np.ndarray) -> list[float]:
        point = np.append(x, 0.8 * math.cos(1.7 * t))[None, :]
        return [float(peval(p, point)[0]) for p in system.f]

    t = np.linspace(0.0, 15.0, 301)
    ref = solve_ivp(f, (0.0, 15.0), np.zeros(system.n), method="DOP853", rtol=1e-12,
                    atol=1e-14, t_eval=t)
    res = simulate(mf, "0.8*cos(1.7*t)", t_end=15.0, t_eval=t, closed_loop=True,
                   method="dop853", rtol=1e-12, atol=1e-14)
    assert ref.success and res.status == "ok"
    assert np.max(np.abs(ref.y[0])) > 0.1
    assert np.max(np.abs(res.y - ref.y[0])) < 1e-8


@pytest.mark.parametrize("omega", [0.6, 1.4])
def test_first_harmonic_at_small_amplitude_is_the_loops_h1(omega):
    # the nonlinear PI loop driven by r = eps cos(w t): y's first harmonic is
    # T(jw) eps + O(eps^3), T = PC/(1 + PC) the linear loop Theorem 2 analyses, and the
    # error's is g1(jw) eps, g1 = 1/(1 + PC) (the sensitivity of rho_1)
    mf = _loop("D(y,2) + 0.4*D(y) + 2*y + 0.5*y**3 = u", [0.5, 0.2], [1.0, 0.0])
    loop = closed_loop(mf)
    eps, periods, skip = 1e-3, 40, 200  # skip: transient periods (slowest pole ~ -0.2)
    period = 2 * math.pi / omega
    t = np.linspace(skip * period, (skip + periods) * period, 40 * 64 + 1)
    res = simulate(mf, f"{eps!r}*cos({omega!r}*t)", t_end=float(t[-1]), t_eval=t,
                   closed_loop=True, method="dop853", rtol=1e-12, atol=1e-16)
    w = np.exp(-1j * omega * t[:-1])
    harmonic = 2 * np.mean(res.y[:-1] * w)
    h1 = complex(loop.reference_to_output(1j * omega))
    assert abs(harmonic - h1 * eps) < 1e-4 * abs(h1) * eps
    error = 2 * np.mean((eps * np.cos(omega * t[:-1]) - res.y[:-1]) * w)
    g1 = complex(loop.sensitivity(1j * omega))
    assert abs(error - g1 * eps) < 1e-4 * abs(g1) * eps


def test_improper_loop_refuses_a_reference_whose_derivative_is_an_impulse():
    mf = _loop(PLANT2, [0.3, 1.0, 2.0], [1.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ArgumentError, match=r"u = C\(r - y\) with an improper controller"
                                                r".*order 2.*impulse"):
            simulate(mf, "0.3*step(t - 1)", t_end=2.0, closed_loop=True)
        with pytest.raises(ArgumentError, match=r"derivative 1 is not finite.*improper"):
            simulate(mf, "sqrt(t)", t_end=2.0, closed_loop=True)
    # a proper controller with a direct term reads r only: a jump is fine
    res = simulate(_loop(PLANT2, [0.5, 0.2], [1.0, 0.0]), "0.3*step(t - 1)", t_end=2.0,
                   closed_loop=True)
    assert res.status == "ok"


def test_improper_loop_says_when_the_reference_does_not_start_at_rest():
    # cos(1.3 t) jumps from 0 to 1 at t = 0: python-control's loop gets the impulse of
    # C's s^2 and s terms, the run from rest at t = 0+ does not, and says so
    num, den = [0.3, 1.0, 2.0], [1.0]
    mf = _loop(PLANT2, num, den)
    t = np.linspace(0.0, 10.0, 50001)
    expected = control.forced_response(
        control.feedback(control.tf(num, den) * control.tf([1.0], [1.0, 0.4, 2.0]), 1), t,
        np.cos(1.3 * t)).outputs
    res = simulate(mf, "cos(1.3*t)", t_end=10.0, t_eval=t, closed_loop=True,
                   method="dop853", rtol=1e-12, atol=1e-14)
    assert np.max(np.abs(res.y - expected)) > 1e-3
    assert any(n.startswith("r(0) = 1, not 0") and "impulse" in n for n in res.notes)
    slope = simulate(mf, "sin(1.3*t)", t_end=1.0, closed_loop=True)
    assert any(n.startswith("r'(0) = 1.3, not 0") for n in slope.notes)
    quiet = simulate(mf, REFERENCE, t_end=1.0, closed_loop=True)
    assert not any("not 0" in n for n in quiet.notes)
    # a given initial state is the state at t = 0+: nothing is left out
    given = simulate(mf, "cos(1.3*t)", t_end=1.0, closed_loop=True, initial=[0.0, 0.0])
    assert not any("not 0" in n for n in given.notes)


def test_improper_loop_refuses_a_reference_too_steep_to_integrate_and_runs_a_smooth_one():
    num, den = [0.3, 1.0, 2.0], [1.0]
    mf = _loop(PLANT2, num, den)
    with pytest.raises(ArgumentError, match=r"improper controller.*time scale of 1e-09 s"):
        simulate(mf, "0.3*(1 + tanh((t - 1)/1e-9))", t_end=3.0, closed_loop=True)
    # a smoothed jump wide against the loop's time scale: python-control's linear loop
    t = np.linspace(0.0, 6.0, 6001)
    reference = 0.3 * (1 + np.tanh((t - 1) / 0.05))
    expected = control.forced_response(
        control.feedback(control.tf(num, den) * control.tf([1.0], [1.0, 0.4, 2.0]), 1), t,
        reference).outputs
    res = simulate(mf, "0.3*(1 + tanh((t - 1)/0.05))", t_end=6.0, t_eval=t,
                   closed_loop=True, method="dop853", rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(res.y - expected)) < 1e-5


def test_improper_loop_refuses_a_reference_whose_jump_hides_in_a_pole():
    # atan(1/(t - 1)) jumps by -pi at t = 1: the impulse of r' there would be lost
    mf = _loop(PLANT2, [0.3, 1.0, 2.0], [1.0])
    for text in ("0.02*atan(1/(t - 1))", "0.02*tanh(tan(t))"):
        with pytest.raises(ArgumentError, match=r"improper controller.*cannot be judged"):
            simulate(mf, text, t_end=3.0, closed_loop=True)
    assert simulate(mf, "0.02*sin(2*t)**3/(1 + t)", t_end=3.0, closed_loop=True).status == "ok"
