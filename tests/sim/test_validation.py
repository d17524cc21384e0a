"""Verdict-vs-simulation trials (radii from gfrf.stability.criteria) and linear vs
nonlinear loop."""

import json
import math
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from gfrf.cli import main
from gfrf.model.modelfile import load_model
from gfrf.sim.validation import (
    linear_vs_nonlinear,
    random_input,
    resonance,
    spectrum_size,
    validate,
)
from gfrf.stability.criteria import verdict

MODELS = sorted(p for p in Path("models").glob("*.toml")
                if tomllib.loads(p.read_text()).get("kind") != "parametric")


@pytest.fixture(scope="module")
def results():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return {p.stem: validate(load_model(str(p)), t_end=40.0, method="fast")
                for p in MODELS}


def test_bundled_models_are_all_validated(results):
    # models/ grows (e.g. identified_example*.toml): every non-parametric file is run
    assert {"cartpole", "cartpole_reduced", "duffing", "hanging_pendulum",
            "hanging_pendulum_damped", "narx_example"} <= set(results)
    assert all(r.trials and r.contradictions == [] for r in results.values())


@pytest.mark.parametrize("name", ["cartpole", "cartpole_reduced", "duffing",
                                  "hanging_pendulum", "hanging_pendulum_damped",
                                  "narx_example"])
def test_no_simulation_contradicts_the_verdict(results, name):
    result = results[name]
    v = verdict(load_model(f"models/{name}.toml"), 5)
    assert result.radius == v.radius  # the radius comes from the verdict, not by hand
    assert result.contradictions == []
    below = [t for t in result.trials if t.below_radius]
    if result.radius > 0:
        assert len(below) == 3 and all(t.amplitude == 0.5 * result.radius for t in below)
    for t in result.trials:
        assert t.input_peak <= t.amplitude * (1 + 1e-9)  # peak |u| never exceeds r


def test_theorem1_trials_reach_the_estimate_and_beyond(results):
    result = results["hanging_pendulum"]
    labels = {t.label for t in result.trials}
    assert {"0.5 r*", "2 r*", "1 r_est", "2 r_est", "10 r_est"} <= labels
    assert result.radius < result.radius_estimate
    # far above the radius the detector does see escapes (damped pendulum, NARX)
    for name in ("hanging_pendulum_damped", "narx_example"):
        assert any(not t.bounded for t in results[name].trials if t.label == "10 r_est")


@pytest.mark.parametrize("name", ["cartpole", "cartpole_reduced"])
def test_cartpole_has_no_radius_but_initial_angles_run(results, name):
    result = results[name]
    assert result.radius == 0 and result.theorem == 2
    assert any("gives no radius" in n for n in result.notes)
    angles = [t for t in result.trials if t.kind.startswith("initial angle")]
    assert {t.kind for t in angles} == {f"initial angle {a} deg" for a in (5, 10, 15)}
    assert {t.equation for t in angles} == {"polynomial", "physical"}
    assert all(t.bounded and t.below_radius is None for t in angles)
    assert len(angles) == len(result.trials)  # no input trials without a radius
    payload = json.loads(json.dumps(result.to_dict()))
    assert payload["radius"] == 0 and payload["contradictions"] == []


@pytest.mark.parametrize("name", ["cartpole_reduced", "cartpole"])
def test_linear_closed_loop_agrees_to_cubic_order(name):
    mf = load_model(f"models/{name}.toml")
    rel = [linear_vs_nonlinear(mf, a)["relative_error"] for a in (5.0, 10.0, 15.0)]
    assert rel[0] < 1e-4
    # neglected terms are cubic: relative error ~ angle^2 (ratios 4 and 9)
    assert rel[1] / rel[0] == pytest.approx(4.0, rel=0.1)
    assert rel[2] / rel[0] == pytest.approx(9.0, rel=0.1)


def test_resonance_of_hanging_pendulum():
    # |H1| peaks at sqrt(2.45 - 0.05^2/2) rad/s
    mf = load_model("models/hanging_pendulum.toml")
    assert resonance(mf.plant) == pytest.approx(math.sqrt(2.45 - 0.05**2 / 2), rel=2e-3)


def test_random_input_seeded_with_exact_spectrum_size():
    u1, u2 = random_input(0.3, seed=4, hold=0.5), random_input(0.3, seed=4, hold=0.5)
    t = np.arange(4096) * (8.0 / 4096)  # one period: 16 knots 0.5 s apart
    assert np.array_equal(u1(t), u2(t)) and np.max(np.abs(u1(t))) <= 0.3
    # sum of |Fourier coefficients| of the dense samples converges to the exact size
    assert np.sum(np.abs(np.fft.fft(u1(t)))) / t.size == pytest.approx(0.3, rel=1e-3)
    assert spectrum_size(np.array([1.0, -1.0])) == pytest.approx(1.0)


def test_cli_validate_exit_code_and_json(capsys):
    assert main(["validate", "models/cartpole_reduced.toml", "--t-end", "5", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["radius"] == 0 and len(payload["trials"]) == 6


def test_polynomial_controller_loop_is_validated():
    from gfrf.model.modelfile import model_from_dict
    mf = model_from_dict({"equation": "D(y,2) + 0.5*D(y) + 2*y + y**3 = u",
                          "controller": {"equation": "D(u) + 2*u = 3*y + 0.5*y**3"}})
    result = validate(mf, t_end=10.0)
    assert result.theorem == 2 and result.radius > 0
    assert {t.kind for t in result.trials if t.closed_loop} >= {"cosine at resonance",
                                                               "initial angle 5 deg"}
    assert all(t.bounded for t in result.trials) and result.contradictions == []
