"""Verdict-vs-simulation trials and linear vs nonlinear closed loop."""

import math
import warnings

import numpy as np
import pytest

from gfrf.modelfile import load_model
from gfrf.validation import linear_vs_nonlinear, random_input, resonance, validate


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


def test_random_input_bounded_and_seeded():
    u1, u2 = random_input(0.3, 10.0, seed=4), random_input(0.3, 10.0, seed=4)
    t = np.linspace(0, 10, 501)
    assert np.array_equal(u1(t), u2(t)) and np.max(np.abs(u1(t))) <= 0.3


def test_validate_closed_loop_cartpole():
    mf = load_model("models/cartpole_reduced.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the closed loop is linearly stable: no warning
        result = validate(mf, 0.1, t_end=30.0)
    kinds = {t.kind for t in result.trials}
    assert {"initial angle 5 deg", "initial angle 15 deg", "bounded random"} <= kinds
    assert result.contradictions == []
    payload = result.to_dict()
    assert payload["radius"] == 0.1 and len(payload["trials"]) == 9


def test_validate_detects_unbounded_above_escape():
    # undamped-enough softening pendulum: a large resonant input escapes the well
    mf = load_model("models/hanging_pendulum.toml")
    result = validate(mf, 1.5, factors=(2.0,), t_end=60.0)  # A = 3 N m > max restoring 2.31
    assert any(not t.bounded for t in result.trials)
    assert result.contradictions == []  # nothing below the radius was tried
