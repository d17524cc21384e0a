"""Witnesses of a loop: a chirp's input is what its text says, and switching and chirp
witnesses escape when replayed by an independent DOP853 run of the hand-written loop
equation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.model.modelfile import model_from_dict
from gfrf.model.signals import parse_input
from gfrf.twosided.falsify import falsify
from gfrf.twosided.witness import Chirp


def test_chirp_values_are_the_text_and_its_derivatives() -> None:
    chirp = Chirp(amplitude=0.7, omega_start=1.3, omega_end=0.4, duration=25.0)
    t = np.linspace(0.0, 25.0, 101)
    signal = parse_input(chirp.text(), max_derivative=2)  # sympy differentiates the text
    table = chirp.values(t, [0, 1, 2])
    for k in range(3):
        assert np.allclose(table[:, k], signal.derivative(k)(t), rtol=1e-12, atol=1e-12)
    # the instantaneous frequency runs from omega_start to omega_end
    assert 2 * chirp.rate * chirp.duration + chirp.omega_start == pytest.approx(0.4)


#: The loop u = C(r - y) = r - y around y'' + 0.2 y' + y - 0.3 y^3 = u.
LOOP = {"equation": "D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u",
        "controller": {"num": [1.0], "den": [1.0]}}


def _loop_rhs(r: float) -> object:
    def rhs(t: float, z: np.ndarray) -> list[float]:  # y'' = r - y - 0.2 y' - y + 0.3 y^3
        return [z[1], r - 2.0 * z[0] - 0.2 * z[1] + 0.3 * z[0] ** 3]
    return rhs


def _out(level: float) -> object:
    def out(_t: float, z: np.ndarray) -> float:
        return abs(z[0]) - level

    out.terminal = True  # type: ignore[attr-defined]
    return out


def test_switching_witness_of_a_loop_escapes_in_a_hand_written_replay() -> None:
    """Switching references are searched in a loop: the witness (r = +-U at its switch
    times) escapes in DOP853 runs of the hand-written loop, segment by segment."""
    f = falsify(model_from_dict(LOOP), 2.0, closed_loop=True)
    w = f.witness()
    assert w is not None and w["kind"] == "switching" and "r = " in f.input_text("r")
    edges = [0.0, *w["switch_times"], 1.5 * w["t_escape"]]
    z, sign, hit = np.zeros(2), w["first_sign"], None
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        sol = solve_ivp(_loop_rhs(sign * w["amplitude"]), (a, b), z, method="DOP853",
                        rtol=1e-11, atol=1e-14, events=_out(f.levels[0]))
        if sol.t_events[0].size:
            hit = float(sol.t_events[0][0])
            break
        z, sign = sol.y[:, -1], -sign
    assert hit is not None and hit == pytest.approx(w["t_escape"], rel=0.01)


def test_chirp_of_a_loop_is_replayable() -> None:
    """A down-sweep of the reference escapes the loop: the falsifier's check and an
    independent DOP853 run of the hand-written loop agree on the escape time."""
    from gfrf.sim.system import build_system
    from gfrf.twosided.runner import EscapeRunner

    mf = model_from_dict(LOOP)
    runner = EscapeRunner(build_system(mf, closed_loop=True, equation="polynomial"),
                          mf.plant, 10.0)
    chirp = Chirp(amplitude=0.551337890625, omega_start=2 ** 0.5, omega_end=0.5 * 2 ** 0.5,
                  duration=200.0)
    t_escape = runner.confirm_chirp(chirp)
    assert t_escape is not None
    a, w0, dur, rate = chirp.amplitude, chirp.omega_start, chirp.duration, chirp.rate

    def rhs(t: float, z: np.ndarray) -> list[float]:
        return _loop_rhs(a * math.cos(w0 * t + rate * t * t))(t, z)  # type: ignore[operator]

    sol = solve_ivp(rhs, (0.0, dur), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14,
                    events=_out(runner.levels[0]))
    assert sol.t_events[0].size == 1
    assert sol.t_events[0][0] == pytest.approx(t_escape, rel=0.01)
    assert parse_input(chirp.text()).text
