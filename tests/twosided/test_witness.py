"""Chirp witnesses: the input is what its text says, and a witness escapes when replayed
by an independent DOP853 run of the hand-written loop equation."""

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


@pytest.fixture(scope="module")
def loop_witness():
    # u = C(r - y) = r - y around y'' + 0.2 y' + y - 0.3 y^3 = u: no switching inputs
    # are searched in a loop, and a down-sweep beats every tone
    mf = model_from_dict({"equation": "D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u",
                          "controller": {"num": [1.0], "den": [1.0]}})
    return falsify(mf, 2.0, closed_loop=True)


def test_chirp_witness_of_a_loop_is_replayable(loop_witness) -> None:
    f = loop_witness
    w = f.witness()
    assert w is not None and w["kind"] == "chirp"
    assert set(w) == {"kind", "amplitude", "omega_start", "omega_end", "duration", "t_escape"}
    assert f.upper == w["amplitude"] and w["t_escape"] <= w["duration"]
    tones = [c["edge"] for c in f.candidates if c["kind"] == "tones"]
    assert tones and f.upper < min(tones)  # it beats the best tone edge found
    a, w0, w1, dur = (w[k] for k in ("amplitude", "omega_start", "omega_end", "duration"))
    rate = (w1 - w0) / (2 * dur)

    def rhs(t: float, z: np.ndarray) -> list[float]:  # y'' = r - y - 0.2 y' - y + 0.3 y^3
        r = a * math.cos(w0 * t + rate * t * t)
        return [z[1], r - 2.0 * z[0] - 0.2 * z[1] + 0.3 * z[0] ** 3]

    level = f.levels[0]

    def out(_t: float, z: np.ndarray) -> float:
        return abs(z[0]) - level

    out.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(rhs, (0.0, dur), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-14,
                    events=out)
    assert sol.t_events[0].size == 1
    assert sol.t_events[0][0] == pytest.approx(w["t_escape"], rel=0.01)
    assert "a chirp from" in f.input_text() and parse_input(
        f.input_text().split("u = ")[1].split(" on [")[0]).text
