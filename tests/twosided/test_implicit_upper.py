"""The cart-pole loop's two-sided answer in the class of bounded plant-input signals
d = C r: the witness replayed on a hand-written loop, and the CLI's JSON and file."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tests.conftest import MODELS

A, B, C = 15.6, 379.3, 0.1331
THETA_D = float(np.sqrt((A * 39.3185 - 1) / (0.1475 + A * 19.66)))  # D(theta) = 0


def _rhs(d: float):
    def rhs(_t: float, x: np.ndarray) -> list[float]:
        th, dth = x
        k = 39.3185 - 19.66 * th**2
        m = 1 + 0.1475 * th**2 - A * k
        return [dth, -(-67.578 * th + 11.2455 * th**3 + 0.1475 * th * dth**2
                       + k * (d - B * dth - C * th)) / m]
    return rhs


def _max_theta(d: float, t_end: float) -> float:
    sol = solve_ivp(_rhs(d), (0, t_end), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-13)
    return float(np.max(np.abs(sol.y[0])))


@pytest.mark.slow
def test_cartpole_threshold_in_the_plant_input_class(tmp_path, cli):
    out = tmp_path / "cert.json"
    code, stdout, _ = cli("threshold", str(MODELS / "cartpole.toml"), "--json",
                          "--certificate-out", str(out))
    data = json.loads(stdout)
    assert code == 0
    assert "sup|C(s) r| <= lower" in data["lower_class"]
    assert data["lower_proof"] == "interval" and data["lower"] > 100
    w = data["witness"]
    assert w["kind"] == "switching" and w["signal"] == "d"
    assert data["upper"] == w["amplitude"] > data["lower"]
    assert data["upper_proof"] == "interval" and data["enclosure"]["proven"] is True
    # replayed on the hand-written loop: the witness reaches D = 0, 0.5 x it stays clear
    assert not w["switch_times"]
    assert _max_theta(w["first_sign"] * w["amplitude"], 1.5 * w["t_escape"]) > THETA_D - 1e-5
    assert _max_theta(0.5 * w["amplitude"], 2 * w["t_escape"]) < THETA_D - 1e-3
    code, stdout, _ = cli("certificate", "check", str(MODELS / "cartpole.toml"), str(out),
                          "--json")
    assert code == 0 and json.loads(stdout)["valid"] is True
    cert = json.loads(out.read_text())
    cert["vertices"][10][1] = "-1"  # an upper-chain vertex moved below the lower chain
    out.write_text(json.dumps(cert))
    code, stdout, _ = cli("certificate", "check", str(MODELS / "cartpole.toml"), str(out),
                          "--json")
    assert code == 1 and json.loads(stdout)["valid"] is False


def _D(th: float) -> float:
    """The coefficient of theta'' in the loop, by hand (1 + 0.1475 th^2 - A k)."""
    return 1 + 0.1475 * th**2 - A * (39.3185 - 19.66 * th**2)


def _level_run(d, t_end: float, rtol: float, max_step: float = np.inf):
    """DOP853 from rest with the breakdown level |D| <= 1e-6 |D(0)| as a located event:
    (reached, time, smallest |D| / |D(0)|)."""
    def rhs(t: float, x: np.ndarray) -> list[float]:
        return _rhs(d(t, x))(t, x)

    def level(_t: float, x: np.ndarray) -> float:
        return abs(_D(x[0])) - 1e-6 * abs(_D(0.0))

    level.terminal = True
    sol = solve_ivp(rhs, (0, t_end), [0.0, 0.0], method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                    events=level, max_step=max_step)
    ratio = float(np.min(np.abs(_D(sol.y[0])))) / abs(_D(0.0))
    return sol.status == 1, float(sol.t[-1]), ratio


@pytest.fixture(scope="module")
def witness():
    from gfrf.model.modelfile import load_model
    from gfrf.stability.implicit import implicit_form
    from gfrf.twosided.implicit_upper import implicit_witness

    form = implicit_form(load_model(MODELS / "cartpole.toml"))
    w = implicit_witness(form, 300.0)
    assert w is not None
    return form, w


def test_the_witness_reaches_the_breakdown_level_in_a_replay_and_not_at_0_9(witness):
    _, w = witness
    signs = [w.first_sign * (-1) ** k for k in range(len(w.switch_times) + 1)]

    def d_of(scale: float):
        def d(t: float, _x: np.ndarray) -> float:
            k = int(np.searchsorted(w.switch_times, t, side="right"))
            return scale * w.amplitude * signs[k]
        return d

    runs = [_level_run(d_of(1.0), 3 * w.t_escape, rtol) for rtol in (1e-10, 1e-12)]
    assert all(r[0] for r in runs)
    assert runs[0][1] == pytest.approx(runs[1][1], rel=1e-4)
    assert runs[1][1] == pytest.approx(w.t_escape, rel=1e-3)
    below = _level_run(d_of(0.9), 20.0, 1e-11)
    assert not below[0] and below[2] > 2e-6


def test_bounded_inputs_below_the_proven_lower_stay_above_the_breakdown_level():
    from fractions import Fraction

    from gfrf.model.modelfile import load_model
    from gfrf.stability.implicit import implicit_form
    from gfrf.stability.implicit_region import certificate_at

    form = implicit_form(load_model(MODELS / "cartpole.toml"))
    cert = certificate_at(form, 340.0)
    assert cert is not None and cert["level"] == "1/1000000"
    U = 0.999 * float(Fraction(cert["U"]))
    ymax = max(abs(float(Fraction(v[0]))) for v in cert["vertices"])
    rng = np.random.default_rng(11)
    inputs = [lambda t, x: U, lambda t, x: -U,
              lambda t, x: -U if t < 3.0 else U,  # bang-bang: the widest swing
              lambda t, x: U * np.sign(np.sin(0.8 * t)), lambda t, x: U * np.sign(np.sin(6 * t))]
    for _ in range(3):
        a = rng.uniform(0, 1, 3)
        a = a / a.sum()
        w = rng.uniform(0.05, 30, 3)
        inputs.append(lambda t, x, a=a, w=w: U * float(np.sum(a * np.cos(w * t))))
    for d in inputs:
        sol = solve_ivp(lambda t, x, d=d: _rhs(d(t, x))(t, x), (0, 8), [0.0, 0.0],
                        method="DOP853", rtol=1e-9, atol=1e-12, max_step=0.02)
        assert sol.status == 0
        assert np.max(np.abs(sol.y[0])) <= ymax
        assert float(np.min(np.abs(_D(sol.y[0])))) > 1e-6 * abs(_D(0.0))


@pytest.mark.slow
def test_the_enclosure_proves_the_witness_and_not_the_witness_at_0_9(witness):
    from gfrf.twosided.implicit_enclose import enclose_implicit_witness

    form, w = witness
    e = enclose_implicit_witness(form, w.amplitude, w.first_sign, w.switch_times, w.t_escape)
    assert e is not None and e.proven
    reached, t_hit, _ = _level_run(lambda t, x: w.first_sign * w.amplitude, 3 * w.t_escape,
                                   1e-12)
    # the enclosure passes the level when the replay does (the enclosed time is an upper
    # end of the step's time ball)
    assert reached and t_hit <= e.t_proven <= t_hit + 0.05
    low = enclose_implicit_witness(form, 0.9 * w.amplitude, w.first_sign, w.switch_times,
                                   w.t_escape)
    assert low is not None and not low.proven
