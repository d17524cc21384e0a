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
