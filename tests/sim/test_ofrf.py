"""OFRF and NOFRFs (gfrf.sim.ofrf, ``gfrf ofrf``) against independent references.

References: a scipy ``solve_ivp`` of the Duffing equation written here (not gfrf's
simulator), the kernel-based Volterra prediction ``gfrf.sim.volterra.predict`` (the
compiled recursion of gfrf.kernels, another code path) at several parameter values,
closed forms of the first orders.
"""

from __future__ import annotations

import functools
import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.cli import main
from gfrf.errors import ArgumentError
from gfrf.model.modelfile import model_from_dict
from gfrf.sim import ofrf as ofrf_module
from gfrf.sim.ofrf import ofrf
from gfrf.sim.volterra import predict

DUFFING = {"equation": "D(y,2) + 0.2*D(y) + y + k3*y**3 = u", "parameters": {"k3": 0.5}}


@functools.cache
def _harmonic(k3: float, amplitude: float, omega: float) -> complex:
    """Complex amplitude at omega of the steady state of y'' + 0.2 y' + y + k3 y^3 =
    A cos(omega t), from solve_ivp (300 periods, the last 20 averaged; computed once per
    process: two tests compare with the same runs)."""
    def rhs(t: float, x: np.ndarray) -> list[float]:
        return [x[1], amplitude * np.cos(omega * t) - 0.2 * x[1] - x[0] - k3 * x[0] ** 3]

    period = 2 * np.pi / omega
    t_end = 300 * period
    t = np.linspace(t_end - 20 * period, t_end, 20 * 256, endpoint=False)
    sol = solve_ivp(rhs, (0, t_end), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-13,
                    t_eval=t)
    return complex(2 * np.mean(sol.y[0] * np.exp(-1j * omega * t)))


def test_duffing_ofrf_matches_simulation_to_truncation_error() -> None:
    amplitude, omega = 0.015, 1.0   # below r* = 0.048 of the series at k3 = 0.5
    o = ofrf(DUFFING, "k3", [(amplitude, omega, 0.0)], omega, 5)
    # closed forms: P0 = A H1(j) = -0.075j; P1 = 2 * 3 H3(j, j, -j) / k3 * (A/2)^3
    # = -(3/4) A^3 H1(j)^3 H1(-j), H1(j) = 1/(0.2j)
    h1 = 1 / 0.2j
    assert o.coefficients[0] == pytest.approx(amplitude * h1, abs=1e-15)
    assert o.coefficients[1] == pytest.approx(-0.75 * amplitude ** 3 * h1 ** 3 * np.conj(h1),
                                              rel=1e-12)
    for k3 in (0.3, 1.0):
        simulated = _harmonic(k3, amplitude, omega)
        last = abs(sum(c * k3 ** k for k, c in enumerate(o.by_order[5])))
        error = abs(o(k3) - simulated)
        # the error is the truncation error: far below the last term kept (order 5) ...
        assert error < 0.1 * last
        # ... and the order-3 polynomial is worse by about that term
        order3 = sum(sum(c * k3 ** k for k, c in enumerate(o.by_order[n])) for n in (1, 3))
        assert abs(order3 - simulated) > 5 * error


@pytest.mark.parametrize("omega", [0.0, 1.0, 1.3, 3.0, 4.3])
def test_ofrf_equals_kernel_prediction(omega: float) -> None:
    """Two tones, a parameter in several terms (squared in one) and in B: the polynomial at
    two values equals predict() of the model at those values (kernels of gfrf.kernels)."""
    data = {"equation": "D(y,2) + 0.2*D(y) + y + c*y**3 + 0.3*c**2*y**2*D(y) + 0.1*y**2 "
                        "= (0.7 + 0.1*c)*u + 0.2*u**2", "parameters": {"c": 0.5}}
    tones = [(0.1, 1.0, 0.3), (0.05, 2.3, -0.2)]
    o = ofrf(data, "c", tones, omega, 5)
    for value in (0.5, 1.7):
        plant = model_from_dict({**data, "parameters": {"c": value}}).plant
        component = predict(plant, tones, 5, force=True).component(omega)
        expected = component.value * (1 if omega == 0 else 2)
        assert o(value) == pytest.approx(expected, rel=1e-10, abs=1e-15)


def test_narx_ofrf_equals_prediction() -> None:
    data = {"equation": "y[k] = 0.5*y[k-1] - c*y[k-1]**2*u[k-2] + u[k-1]",
            "sample_time": 0.1, "parameters": {"c": 0.2}}
    o = ofrf(data, "c", "0.3*cos(2.0*t)", 2.0, 5)
    for value in (0.2, 0.9):
        plant = model_from_dict({**data, "parameters": {"c": value}}).plant
        expected = 2 * predict(plant, [(0.3, 2.0, 0.0)], 5, force=True).component(2.0).value
        assert o(value) == pytest.approx(expected, rel=1e-10)


def test_nofrf_definition() -> None:
    """G_n = Y_n/U_n; U_3(1) of 0.015 cos t is 3 (A/2)^3; U_2(1) = 0 (undefined)."""
    o = ofrf(DUFFING, "k3", [(0.015, 1.0, 0.0)], 1.0, 3)
    g = o.nofrf()
    assert g[2] is None
    assert o.input_spectrum[3] == pytest.approx(3 * (0.015 / 2) ** 3)
    h1 = 1 / 0.2j
    # Y_3(1) = 3 H3(1,1,-1) (A/2)^3, so G_3 = H3(1,1,-1) = -k3 H1(1)^3 H1(-1)
    assert g[3] == pytest.approx(-0.5 * h1 ** 3 * np.conj(h1), rel=1e-12)
    assert g[1] == pytest.approx(h1, rel=1e-12)


@pytest.mark.parametrize(("data", "param", "message"), [
    ({"equation": "D(y,2) + c*D(y) + y + 0.5*y**3 = u", "parameters": {"c": 0.2}}, "c",
     "linear output part"),
    ({"equation": "D(y,2) + 0.2*D(y) + y + (1/c)*y**3 = u", "parameters": {"c": 2}}, "c",
     "not a polynomial"),
    (DUFFING, "nope", "not a key"),
    ({"equation": "D(y,2) - 0.2*D(y) + y + c*y**3 = u", "parameters": {"c": 0.2}}, "c",
     "unstable"),
])
def test_refusals(data: dict, param: str, message: str) -> None:
    with pytest.raises(ArgumentError, match=message):
        ofrf(data, param, [(0.01, 1.0, 0.0)], 1.0, 3)


def test_work_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(ofrf_module, "MAX_OFRF_WORK", 10)
    with pytest.raises(ArgumentError, match="MAX_OFRF_WORK"):
        ofrf(DUFFING, "k3", [(0.01, 1.0, 0.0)], 1.0, 5)


def test_cli_json_contract(tmp_path, capsys) -> None:
    path = tmp_path / "duffing.toml"
    path.write_text('equation = "D(y,2) + 0.2*D(y) + y + k3*y**3 = u"\n'
                    '[parameters]\nk3 = 0.5\n', encoding="utf-8")
    code = main(["ofrf", str(path), "--param", "k3", "--input", "0.015*cos(1.0*t)",
                 "--omega", "1", "--order", "5", "--json"])
    payload = json.loads(capsys.readouterr().out)
    assert code == 0
    coefficients = [complex(re, im) for re, im in payload["coefficients"]]
    value = complex(sum(c * 0.8 ** k for k, c in enumerate(coefficients)))
    plant = model_from_dict({**DUFFING, "parameters": {"k3": 0.8}}).plant
    component = predict(plant, [(0.015, 1.0, 0.0)], 5).component(1.0)
    # the same convention as gfrf predict: amplitude * exp(j phase)
    assert value == pytest.approx(component.amplitude * np.exp(1j * component.phase), rel=1e-12)
    assert payload["nofrf"][1]["value"] is None and payload["warning"] is None
    assert payload["truncation_proof"] == "interval"
    assert 0 < payload["truncation_bound"] < 1e-5


@pytest.mark.parametrize("k3", [0.3, 1.0, 2.0])
def test_truncation_bound_contains_the_simulated_error(k3: float) -> None:
    """|OFRF - simulated harmonic| <= the stated truncation bound, and the bound is
    within 100x of that error where the series converges fast (amplitude / r* <= 0.62)."""
    amplitude = 0.015
    simulated = _harmonic(k3, amplitude, 1.0)
    data = {**DUFFING, "parameters": {"k3": k3}}
    for order in (3, 5):
        o = ofrf(data, "k3", [(amplitude, 1.0, 0.0)], 1.0, order)
        error = abs(o(k3) - simulated)
        assert o.truncation_proof == "interval"
        assert error <= o.truncation_bound <= 100 * error


NARX = "y[k] = 0.5*y[k-1] - c*y[k-1]**2*u[k-2] + u[k-1]"


@functools.cache
def _narx_harmonic(c: float, amplitude: float) -> tuple[float, complex]:
    """(omega, complex amplitude at omega) of the NARX model's steady state: the recurrence
    iterated here (200 periods of 32 samples of 0.1 s), a DFT over the last 50."""
    sample_time, samples = 0.1, 32
    omega = 2 * np.pi / (sample_time * samples)
    k = np.arange(200 * samples)
    u = amplitude * np.cos(omega * sample_time * k)
    y = np.zeros(k.size)
    for i in range(2, k.size):
        y[i] = 0.5 * y[i - 1] - c * y[i - 1] ** 2 * u[i - 2] + u[i - 1]
    last = k[-50 * samples:]
    return omega, complex(2 * np.mean(y[last] * np.exp(-1j * omega * sample_time * last)))


@pytest.mark.parametrize("c", [0.1, 0.2])
def test_narx_truncation_bound_contains_the_simulated_error(c: float) -> None:
    """The error of the order-3 and -5 OFRF against the iterated recurrence is below the
    stated bound, which is within 20x of it."""
    omega, simulated = _narx_harmonic(c, 0.3)
    data = {"equation": NARX, "sample_time": 0.1, "parameters": {"c": c}}
    for order in (3, 5):
        o = ofrf(data, "c", [(0.3, omega, 0.0)], omega, order)
        error = abs(o(c) - simulated)
        assert error <= o.truncation_bound <= 20 * error


@pytest.mark.parametrize(("model", "amplitude"), [
    ("duffing", 0.015), ("duffing", 0.025), ("narx", 0.2), ("narx", 0.3), ("narx", 0.4)])
def test_orders_beyond_the_kernels_limit_keep_the_bound_and_lower_the_error(
        model: str, amplitude: float) -> None:
    """Orders 5, 13 and 21 (the GFRF kernels stop at 12) against simulation at amplitudes
    up to 0.73 r*: the stated bound contains the error at each order, and order 21 has a
    smaller bound and error than order 5 (down to simulation's own accuracy)."""
    if model == "duffing":
        value, omega, simulated = 1.0, 1.0, _harmonic(1.0, amplitude, 1.0)
        data, name = {**DUFFING, "parameters": {"k3": 1.0}}, "k3"
    else:
        value, (omega, simulated) = 0.2, _narx_harmonic(0.2, amplitude)
        data, name = {"equation": NARX, "sample_time": 0.1, "parameters": {"c": 0.2}}, "c"
    bounds, errors = [], []
    for order in (5, 13, 21):
        o = ofrf(data, name, [(amplitude, omega, 0.0)], omega, order)
        assert o.truncation_proof == "interval" and amplitude < 0.75 * o.radius
        bounds.append(o.truncation_bound)
        errors.append(abs(o(value) - simulated))
        assert errors[-1] <= bounds[-1]
    assert bounds[2] < 0.01 * bounds[0]
    assert errors[2] < max(0.01 * errors[0], 1e-11)


def test_the_order_is_checked_against_its_own_limit() -> None:
    with pytest.raises(ArgumentError, match="MAX_OFRF_ORDER = 64"):
        ofrf(DUFFING, "k3", [(0.01, 1.0, 0.0)], 1.0, ofrf_module.MAX_OFRF_ORDER + 1)
    with pytest.raises(ArgumentError, match="MAX_OFRF_WORK"):  # eight tones: the work
        ofrf(DUFFING, "k3", [(0.01, float(k), 0.0) for k in range(1, 9)], 1.0, 30)


def test_truncation_bound_is_inf_beyond_the_radius(capsys) -> None:
    argv = ["ofrf", DUFFING["equation"], "--param", "k3=8", "--input", "0.05*cos(1.0*t)",
            "--omega", "1", "--order", "5", "--json"]
    assert main(argv) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["truncation_bound"] == "inf" and payload["truncation_proof"] == "none"


def test_cli_inline_equation_with_value(tmp_path, capsys) -> None:
    argv = ["--input", "0.015*cos(1.0*t)", "--omega", "1", "--order", "3", "--json"]
    assert main(["ofrf", DUFFING["equation"], "--param", "k3=0.5", *argv]) == 0
    inline = json.loads(capsys.readouterr().out)
    path = tmp_path / "duffing.toml"
    path.write_text('equation = "D(y,2) + 0.2*D(y) + y + k3*y**3 = u"\n'
                    '[parameters]\nk3 = 0.1\n', encoding="utf-8")
    assert main(["ofrf", str(path), "--param", "k3=0.5", *argv]) == 0   # overrides 0.1
    from_file = json.loads(capsys.readouterr().out)
    assert inline["coefficients"] == from_file["coefficients"]
    assert inline["value"] == from_file["value"] == 0.5


@pytest.mark.parametrize("argv", [
    ["ofrf", "D(y)+y=u", "--param", "c", "--input", "cos(t)", "--omega", "1"],
    ["ofrf", "D(y)+y+c*y**3=u", "--param", "c=x", "--input", "cos(t)", "--omega", "1"],
    ["ofrf", "models/duffing.toml", "--param", "c", "--input", "cos(t)", "--omega", "1"],
    ["ofrf", "models/duffing.toml", "--param", "c", "--input", "step(t)", "--omega", "1"],
])
def test_cli_bad_input_exit_2(argv: list[str], capsys) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("gfrf: error:") and "Traceback" not in err


def test_frequency_not_reached_is_said() -> None:
    o = ofrf(DUFFING, "k3", "0.01*cos(1.0*t)", 1.5, 5)   # one tone at 1: nothing at 1.5
    assert o.coefficients == (0j,) and not o.reached and "not a sum" in o.warning
    assert all(g is None for g in o.nofrf().values())
