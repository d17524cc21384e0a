"""Input breakpoints on the fast path's RK4 grid, and step doubling that misses its tolerance.

References are closed forms: the step response of y'' + 0.4 y' + 2 y = u (zeta*omega =
0.2, damped frequency 1.4 rad/s, DC gain 1/2), first-order responses solved piece by
piece, and the exact zeros of the breakpoint arguments.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim.simulation import simulate

pytest.importorskip("numba")

MODELS = Path(__file__).resolve().parents[2] / "models"
OSCILLATOR = "D(y,2) + 0.4*D(y) + 2*y = u"
RTOL, ATOL = 1e-8, 1e-10


def _step_response(t: np.ndarray, t0: float) -> np.ndarray:
    """Response of y'' + 0.4 y' + 2 y = step(t - t0) from rest."""
    tau = np.maximum(t - t0, 0.0)
    return 0.5 * (1 - np.exp(-0.2 * tau) * (np.cos(1.4 * tau) + np.sin(1.4 * tau) / 7))


def _tolerance(exact: np.ndarray) -> float:
    return RTOL * float(np.max(np.abs(exact))) + ATOL


@pytest.mark.parametrize(("model", "text", "exact"), [
    (OSCILLATOR, "step(t-1)", lambda t: _step_response(t, 1.0)),
    (OSCILLATOR, "step(2*t-3)", lambda t: _step_response(t, 1.5)),
    (OSCILLATOR, "step(t-1) - step(t-5)",
     lambda t: _step_response(t, 1.0) - _step_response(t, 5.0)),
    # u' = step(t - 1): the breakpoint of a derivative the model uses
    ("D(y,2) + 0.4*D(y) + 2*y = D(u)", "(t-1)*step(t-1)", lambda t: _step_response(t, 1.0)),
])
def test_steps_converge_to_the_closed_form_in_few_steps(model, text, exact):
    # before: the jump inside an RK4 step made step doubling run to 16,777,216 steps
    # (67,108,864 evaluations) and stop there without meeting rtol
    res = simulate(parse_model(model), text, t_end=10.0, method="fast", rtol=RTOL, atol=ATOL)
    assert res.status == "ok", res.message
    assert res.nfev < 100_000
    ref = exact(res.t)
    assert np.max(np.abs(res.y - ref)) <= _tolerance(ref)


def test_user_dt_puts_the_jump_on_a_step_boundary():
    # dt = 0.01 s with the step at 1.005 s, mid-step on a uniform grid (there the
    # quadrature sees u = 1 on 5/6 of the step: an O(dt) error of about 1e-3)
    res = simulate(parse_model(OSCILLATOR), "step(t - 1.005)", t_end=10.0, method="fast",
                   dt=0.01)
    assert res.status == "ok"
    assert np.max(np.abs(res.y - _step_response(res.t, 1.005))) < 1e-7


def test_jump_at_t_end_is_taken_from_the_left():
    # y' + y = step(t - 10) stays 0 up to t = 10 (a last stage taken at u(10) = 1 gave
    # y(10) = h/6)
    res = simulate(parse_model("D(y) + y = u"), "step(t - 10)", t_end=10.0, method="fast")
    assert res.status == "ok" and res.peak == 0.0


def test_square_wave_first_order():
    # y' + y = sign(sin(pi t)): on [k, k+1) u = (-1)^k and y relaxes towards it
    res = simulate(parse_model("D(y) + y = u"), "sign(sin(pi*t))", t_end=4.5, method="fast",
                   rtol=RTOL, atol=ATOL)
    assert res.status == "ok" and res.nfev < 100_000
    k = np.minimum(np.floor(res.t), 4).astype(int)
    start = [0.0]
    for j in range(4):
        s = (-1.0) ** j
        start.append(s + (start[-1] - s) * math.exp(-1.0))
    s = (-1.0) ** k
    ref = s + (np.array(start)[k] - s) * np.exp(-(res.t - k))
    assert np.max(np.abs(res.y - ref)) <= _tolerance(ref)


def test_csv_input_knots_and_hold(tmp_path):
    # samples of u = t on [0, 2] (the cubic spline reproduces a line exactly), held at 2
    # after: u' = 1 then 0, a jump at t = 2 s in y' + y = u'
    times = [0.0, 0.5, 0.7, 1.3, 2.0]
    path = tmp_path / "ramp.csv"
    path.write_text("t,u\n" + "".join(f"{x},{x}\n" for x in times))
    signal = parse_input(f"csv:{path}", max_derivative=1)
    assert signal.breakpoints(5.0).tolist() == times[1:]
    assert signal.breakpoints(1.0).tolist() == [0.5, 0.7]
    res = simulate(parse_model("D(y) + y = D(u)"), signal, t_end=5.0, method="fast",
                   rtol=RTOL, atol=ATOL)
    assert res.status == "ok", res.message
    assert res.nfev < 100_000  # before: 67,108,864
    y2 = 1 - math.exp(-2.0)
    ref = np.where(res.t <= 2.0, 1 - np.exp(-res.t), y2 * np.exp(-(res.t - 2.0)))
    assert np.max(np.abs(res.y - ref)) <= _tolerance(ref)


@pytest.mark.parametrize(("text", "expected"), [
    ("step(t - 1) - 0.5*step(2*t - 10)", [1.0, 5.0]),
    ("Heaviside(t**2 - 2)", [math.sqrt(2)]),
    ("abs(t - pi)*exp(-t)", [math.pi]),
    ("sqrt(t**2 - 2*t + 1)", [1.0]),  # |t - 1|: a kink in a fractional power
    ("sign(cos(2*t + 1))", [(math.pi / 2 + k * math.pi - 1) / 2 for k in range(7)]),
    ("step(0.1*t - 0.3) + step(t - 20) + step(t + 1)", [3.0]),  # outside (0, 10): dropped
    ("0.1*sin(1.2*t) + exp(-t)", []),
])
def test_breakpoints_of_text_inputs(text, expected):
    got = parse_input(text).breakpoints(10.0)
    assert got is not None
    assert got == pytest.approx(expected, rel=1e-14, abs=1e-14)


@pytest.mark.parametrize("text", ["step(t - sin(t) - 1)", "step(sin(t) + 0.5)",
                                  "step(sin(1e9*t))"])
def test_breakpoints_unknown_are_none(text):
    # an argument of another form, or more than MAX_BREAKPOINTS zeros: not guessed
    assert parse_input(text).breakpoints(10.0) is None


def test_tolerance_not_met_is_failed(monkeypatch, capsys):
    # rtol = 1e-14 is out of reach of 4096 RK4 steps over 10 s: the run must say so
    from gfrf.cli import main
    from gfrf.sim import fastsim

    monkeypatch.setattr(fastsim, "MAX_STEPS", 4096)
    res = simulate(parse_model(OSCILLATOR), "0.1*sin(t)", t_end=10.0, method="fast",
                   rtol=1e-14, atol=1e-16)
    assert res.status == "failed" and not res.bounded and res.blowup_time is None
    assert "rtol=1e-14" in res.message and "not met" in res.message
    assert "stopped at 4096 steps" in res.message
    code = main(["simulate", OSCILLATOR, "--input", "0.1*sin(t)", "--t-end", "10",
                 "--method", "fast", "--rtol", "1e-14", "--atol", "1e-16"])
    out = capsys.readouterr().out
    assert code == 1 and "FAILED: tolerance" in out


@pytest.mark.slow
def test_pole_in_the_input_is_not_ok():
    # u = 1/(t - 1) is infinite at 1 s: step doubling runs to MAX_STEPS (about 5 s)
    res = simulate(load_model(MODELS / "duffing.toml"), "1/(t-1)", t_end=3.0, method="fast")
    assert res.status == "failed" and "not met" in res.message


@pytest.mark.parametrize(("text", "order", "refused"), [
    ("step(t - 1)", 1, True), ("step(t - 1)", 2, True), ("(t - 1)*step(t - 1)", 1, False),
    ("(t - 1)*step(t - 1)", 2, True), ("abs(t - 1)", 1, False), ("abs(t - 1)", 2, True),
    ("step(t)", 2, False), ("step(t - 9)", 1, False), ("sign(sin(3*t))", 1, True)])
def test_impulses_of_needed_input_derivatives_are_refused(text: str, order: int,
                                                          refused: bool) -> None:
    """A jump of u^(k-1) inside (0, t_end] makes u^(k) a Dirac delta, which the
    integrators would drop silently (y = 0 for D(y) + y = D(u) under step(t - 1), where
    the truth is exp(-(t - 1))); the simulation refuses it.  (t - 1)*step(t - 1) has a
    continuous u, a jump at t = 0 precedes the run, one at 9 s lies beyond t_end = 3 s."""
    from gfrf.errors import ArgumentError

    equation = "D(y,2) + 0.4*D(y) + 2*y = " + ("D(u)" if order == 1 else "D(u,2)")
    if refused:
        with pytest.raises(ArgumentError, match="impulse"):
            simulate(parse_model(equation), text, t_end=3.0, method="fast")
    else:
        assert simulate(parse_model(equation), text, t_end=3.0, method="fast").status == "ok"


@pytest.mark.parametrize(("t_end", "dt"), [(1e19, None), (1e300, None), (1e10, 1e-9),
                                           (2e10, 1e-9)])
def test_astronomical_step_counts_are_refused(t_end: float, dt: float | None) -> None:
    """A segment of more than 9.2e18 steps used to wrap int64 and crash (ValueError or
    IndexError); now every such grid exceeds MAX_STEPS and is refused."""
    from gfrf.errors import ArgumentError

    with pytest.raises(ArgumentError, match="MAX_STEPS"):
        simulate(parse_model("D(y,2) + 0.4*D(y) + 2*y = u"), "step(t - 1e10)" if t_end == 2e10
                 else "step(t - 1)", t_end=t_end, method="fast", dt=dt)


def test_non_finite_input_is_a_failure_not_a_blow_up() -> None:
    """sqrt(1 - t) is NaN after 1 s while |y| < 0.3 before: the state turns NaN because
    the input does, which used to be reported as a blow-up of the model at 1.0007 s."""
    res = simulate(parse_model("D(y,2) + 0.4*D(y) + 2*y = u"), "sqrt(1 - t)", t_end=3.0,
                   method="fast")
    assert res.status == "failed" and res.blowup_time is None
    assert "input" in res.message and np.all(np.abs(res.y) < 1.0)
    grows = simulate(parse_model("D(y,2) + 0.4*D(y) + 2*y - y**3 = u"), "3*sin(t)",
                     t_end=30.0, method="fast")
    assert grows.status == "blowup" and grows.blowup_time is not None


def test_prepared_system_runs_again_as_a_fresh_one():
    from gfrf.sim.system import build_system

    mf = load_model(MODELS / "duffing.toml")
    system, signal = build_system(mf), parse_input("0.1*sin(t)")

    def run(system, signal, x0, dt):
        res = simulate(system, signal, t_end=2.0, method="fast", initial=x0, dt=dt, n_out=21)
        return res.y, [n for n in res.notes if "stability limit" in n]

    for dt in (None, 0.1):  # 0.1 s is beyond RK4's limit at x = 30 (rate 37/s), not at 0
        runs = [run(system, signal, x0, dt) for x0 in ([0.0, 0.0], [30.0, 0.0], [0.0, 0.0])]
        fresh = run(build_system(mf), parse_input("0.1*sin(t)"), [30.0, 0.0], dt)
        np.testing.assert_array_equal(runs[0][0], runs[2][0])
        np.testing.assert_array_equal(runs[1][0], fresh[0])
        assert runs[1][1] == fresh[1] and runs[0][1] == runs[2][1] == []
    assert fresh[1]
