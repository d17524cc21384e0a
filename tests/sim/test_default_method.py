"""The default simulation path: its accuracy against closed forms at every rtol, its
method rule as documented, and its stepping against plain ``solve_ivp``."""

import math
import re
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import gfrf.sim.simulation as simulation
from gfrf.errors import ArgumentError
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim.integrate import SCIPY_METHODS, _fused_rhs
from gfrf.sim.simulation import AUTO_RK45_RTOL, auto_method, simulate
from gfrf.sim.system import build_system

RTOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
# y'' + 2 z w y' + w^2 y = cos(W t), y(0) = y'(0) = 0
W0, ZETA, W = 2.0, 0.3, 1.3


def _oscillator_closed_form(t: np.ndarray) -> np.ndarray:
    h = 1 / (W0 * W0 - W * W + 2j * ZETA * W0 * W)
    wd = W0 * math.sqrt(1 - ZETA * ZETA)
    a = -h.real  # y(0) = 0
    b = (W * h.imag + ZETA * W0 * a) / wd  # y'(0) = 0
    return np.real(h * np.exp(1j * W * t)) + np.exp(-ZETA * W0 * t) * (
        a * np.cos(wd * t) + b * np.sin(wd * t))


@pytest.mark.parametrize("rtol", RTOLS)
def test_default_path_error_within_ten_rtol_of_closed_form(rtol):
    # The stated tolerance: over 30 s (~6 periods) the global error of the default
    # path stays within 10 rtol of the output's peak, at every rtol from 1e-3 to 1e-10.
    model = parse_model(f"D(y,2) + {2 * ZETA * W0}*D(y) + {W0 * W0}*y = u")
    res = simulate(model, f"cos({W}*t)", t_end=30.0, rtol=rtol, atol=rtol * 1e-3)
    exact = _oscillator_closed_form(res.t)
    assert res.status == "ok" and res.method == auto_method(rtol)
    assert np.max(np.abs(res.y - exact)) <= 10 * rtol * np.max(np.abs(exact))


def test_default_rtol_accuracy_first_order_step():
    # Defaults only (rtol 1e-8, atol 1e-10): 2 y' + y = 3 step(t), y = 3 (1 - exp(-t/2)),
    # within the same stated 10 rtol of the peak (3).
    res = simulate(parse_model("2*D(y) + y = 3*u"), "step(t)", t_end=10.0)
    assert res.method == "dop853"
    assert np.max(np.abs(res.y - 3 * (1 - np.exp(-res.t / 2)))) <= 10 * 1e-8 * 3


def _documented_threshold(doc: str) -> float:
    found = re.findall(r"rtol\s*>=\s*`{0,2}\s*([0-9.e+-]+)", doc)
    assert found, "the docstring states no rule 'rtol >= ...'"
    return float(found[0])


def test_auto_rule_is_the_documented_one():
    for doc in (auto_method.__doc__, simulate.__doc__):
        assert _documented_threshold(doc or "") == AUTO_RK45_RTOL
    assert "RK45" in (auto_method.__doc__ or "") and "DOP853" in (auto_method.__doc__ or "")
    for rtol, expected in ((1.0, "rk45"), (1e-3, "rk45"), (AUTO_RK45_RTOL, "rk45"),
                           (AUTO_RK45_RTOL * (1 - 1e-12), "dop853"), (1e-8, "dop853"),
                           (1e-13, "dop853")):
        assert auto_method(rtol) == expected
    assert simulation.METHODS[0] == "auto"
    assert simulate.__kwdefaults__["method"] == "auto"


@pytest.mark.parametrize("rtol", [1e-3, 1e-4, 1e-6])
def test_auto_is_the_chosen_method_exactly(rtol):
    system = build_system(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    auto = simulate(system, "0.5*sin(1.3*t)", t_end=20.0, rtol=rtol, atol=rtol * 1e-3)
    chosen = simulate(system, "0.5*sin(1.3*t)", t_end=20.0, rtol=rtol, atol=rtol * 1e-3,
                      method="rk45" if rtol >= 1e-4 else "dop853")
    assert auto.method == chosen.method and auto.nfev == chosen.nfev
    assert np.array_equal(auto.y, chosen.y)


@pytest.mark.parametrize("method", ["rk45", "dop853", "lsoda", "radau"])
def test_stepping_matches_solve_ivp(method):
    # The solver stepped by integrate_scipy gives solve_ivp's samples and evaluation count
    # on the same right-hand side (here written with numpy: rhs of the source + u(t)).
    system = build_system(load_model("models/hanging_pendulum.toml"), equation="polynomial")
    signal = parse_input("0.05*sin(1.565*t)")
    t_eval = np.linspace(0.0, 60.0, 601)
    res = simulate(system, signal, t_end=60.0, t_eval=t_eval, method=method, rtol=1e-6,
                   atol=1e-9)
    rhs = system.function("rhs")

    def f(t, y):
        out = np.empty(2)
        rhs(y, [float(signal(t))], out)
        return out

    sol = solve_ivp(f, (0.0, 60.0), [0.0, 0.0], method=SCIPY_METHODS[method], rtol=1e-6,
                    atol=1e-9, t_eval=t_eval)
    assert np.max(np.abs(res.states - sol.y)) < 1e-12
    if method == "radau":  # gfrf also counts the finite-difference Jacobian's evaluations
        assert res.nfev >= sol.nfev
    else:
        assert res.nfev == sol.nfev


@pytest.mark.parametrize("text", ["0.3*step(t - 1)", "0.1*sign(t - 2)", "abs(t - 2)",
                                  "sqrt(t)", "exp(-t)*sin(3*t)", "tanh(t - 1)",
                                  "log(1 + t)", "0.2*cos(t)**3", "tan(0.1*t)",
                                  "1/(1 + t**2)", "step(t - 1)*sin(t)", "sinh(0.1*t)",
                                  "cosh(0.1*t)", "atan(t - 2)"])
def test_fused_right_hand_side_matches_numpy(text):
    # The generated f(t, z) (input printed for math) against the source's rhs with the
    # input's numpy callables, at ordinary times and exactly at jumps (t = 1, 2).
    # With D(u) in the model where u' has no Dirac term, else without.
    jumps = "step" in text or "sign" in text
    system = build_system(parse_model("D(y,2) + 0.3*D(y) + y - 0.2*y**3 = "
                                      + ("u" if jumps else "D(u) + u")))
    signal = parse_input(text, max_derivative=system.n_inputs - 1)
    rhs = system.function("rhs")

    def numpy_path(t, z):
        out = np.empty(2)
        with np.errstate(all="ignore"):
            rhs(z, [float(signal.derivative(k)(t)) for k in range(system.n_inputs)], out)
        return out

    fused = _fused_rhs(system, signal, numpy_path)
    assert fused is not None
    z = np.array([0.3, -0.7])
    for t in (0.0, 0.5, 1.0, 1.5, 2.0, 3.25, 10.0):
        assert np.allclose(fused(t, z), numpy_path(t, z), rtol=1e-14, atol=1e-15), t


def test_dirac_input_derivative_is_refused_and_smooth_inputs_are_exact():
    # D(u) of a step is a Dirac term, which has no math printing (no fused rhs); no
    # integrator represents the impulse (numpy maps it to 0, which once dropped the jump
    # silently), so the run is refused, naming the time.  y' + y = u' + u has transfer 1:
    # with a smooth step, y = u.
    system = build_system(parse_model("D(y) + y = D(u) + u"))
    signal = parse_input("step(t - 1)", max_derivative=1)
    assert _fused_rhs(system, signal, lambda t, z: z) is None
    with pytest.raises(ArgumentError, match=r"impulse.*|t = 1 s"):
        simulate(system, signal, t_end=3.0, rtol=1e-10, atol=1e-12)
    smooth = "0.5*(1 + tanh((t - 1)/0.05))"
    res = simulate(system, smooth, t_end=3.0, rtol=1e-10, atol=1e-12)
    u = 0.5 * (1 + np.tanh((res.t - 1) / 0.05))  # y(0) = 0 = u(0) to 4e-18
    assert res.status == "ok" and np.allclose(res.y, u, atol=1e-7)


def test_fused_right_hand_side_not_used_for_csv(tmp_path):
    path = tmp_path / "u.csv"
    path.write_text("0,0\n1,1\n2,0\n")
    system = build_system(parse_model("D(y) + y = u"))
    assert _fused_rhs(system, parse_input(f"csv:{path}"), lambda t, z: z) is None
    res = simulate(system, f"csv:{path}", t_end=2.0)
    assert res.status == "ok" and np.all(np.isfinite(res.y))


def test_domain_error_stops_the_run_without_nan():
    # sqrt(3 - t) has no real value after 3 s: math raises, numpy gives nan; the run
    # stops there (never NaN samples), as before the fused path.
    res = simulate(parse_model("D(y) + y = u"), "sqrt(3 - t)", t_end=5.0)
    assert res.status != "ok" and np.all(np.isfinite(res.y))
    assert 2.9 < res.t[-1] <= 3.0


def test_closed_loop_plant_input_by_hand():
    # Cart-pole with its improper controller: u = C(r - th) = a e'' + b e' + c e, e = r - th,
    # th'' from eqs (8)-(9) typed by hand; gfrf's u is evaluated on whole trajectories.
    mf = load_model("models/cartpole.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = simulate(mf, "0.02*sin(t)", t_end=5.0, closed_loop=True, initial=[0.2618, 0.0],
                       rtol=1e-10, atol=1e-12)
    big_m, m, length, g = 0.145, 0.03, 0.125, 9.8
    a, b, c = 15.6, 379.3, 0.1331
    th, om = res.states
    r, dr, ddr = 0.02 * np.sin(res.t), 0.02 * np.cos(res.t), -0.02 * np.sin(res.t)
    co, si = np.cos(th), np.sin(th)
    acc = ((big_m + m) * g / length * si - m * om ** 2 * si * co
           - co * (a * ddr + b * (dr - om) + c * (r - th)) / length) \
        / ((big_m + m) * 4 / 3 - m * co ** 2 - a * co / length)
    assert res.status == "ok"
    assert np.allclose(res.u, a * (ddr - acc) + b * (dr - om) + c * (r - th), rtol=1e-9,
                       atol=1e-9)


@pytest.mark.parametrize("method", ["rk45", "dop853"])
def test_dense_output_batches_join_exactly(method, monkeypatch):
    # The samples do not depend on how many steps' interpolants are evaluated together.
    import gfrf.sim.integrate as integrate

    system = build_system(load_model("models/duffing.toml"))
    whole = simulate(system, "0.5*sin(1.3*t)", t_end=50.0, method=method, rtol=1e-7)
    monkeypatch.setattr(integrate, "_DENSE_BATCH", 5)
    batched = simulate(system, "0.5*sin(1.3*t)", t_end=50.0, method=method, rtol=1e-7)
    assert whole.t.size == batched.t.size == 2001
    assert np.array_equal(whole.states, batched.states)
