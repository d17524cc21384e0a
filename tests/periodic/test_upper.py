"""Upper side of the 1/4 tongue: energy (49), averaging case 3, exact (x(0) = 0 orbits)."""

import json

import numpy as np
import pytest
import sympy as sp

from gfrf.cli import main
from gfrf.errors import ArgumentError
from gfrf.periodic.averaging import averaging_equilibria, averaging_transition
from gfrf.periodic.compare import compare_periodic, method_orbit, method_transition
from gfrf.periodic.energy import energy_transition
from gfrf.periodic.floquet import upper_quarter_transition
from gfrf.periodic.shooting import transition_delta


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def _err(method: str, eps: float, amplitude: float) -> float:
    exact = method_transition("exact", eps, amplitude, "1/4", side="upper").delta
    return abs(method_transition(method, eps, amplitude, "1/4", side="upper").delta - exact)


def test_case3_regenerated():
    B, d, e = sp.symbols("B delta epsilon")
    printed = d - sp.Rational(1, 4) - d * B**2 / 8 - e / 2 + e * B**2 / 12
    assert sp.expand(averaging_equilibria()["case3"] - printed) == 0


def test_upper_is_lower_with_minus_eps():
    assert averaging_transition(0.1, 0.5, side="upper") == pytest.approx(
        averaging_transition(-0.1, 0.5))
    assert energy_transition(0.3, 0.5, side="upper") == pytest.approx(
        energy_transition(-0.3, 0.5))
    assert np.isfinite(energy_transition(0.3, 0.5, side="upper"))  # (49) always has a root


def test_exact_upper_is_mathieu_a1_and_odd():
    assert method_transition("exact", 0.3, 1e-3, "1/4", side="upper").delta == pytest.approx(
        float(upper_quarter_transition(0.3)), abs=1e-6)
    t = np.array([0.0, np.pi, 2 * np.pi])
    _, x = method_orbit("exact", 0.2, 0.5, "1/4", t, side="upper")
    assert x == pytest.approx([0.0, 0.5, 0.0], abs=1e-9)


def test_transition_error_second_order_in_eps():
    for m in ("averaging", "energy"):
        r = _err(m, 0.04, 1e-3) / _err(m, 0.02, 1e-3)
        assert 3 < r < 5, m


def test_transition_error_shrinks_with_amplitude():
    # eps = 1e-3: the amplitude error dominates; averaging O(B^4), energy at least as fast
    assert 8 < _err("averaging", 1e-3, 0.4) / _err("averaging", 1e-3, 0.2) < 32
    assert _err("energy", 1e-3, 0.4) / _err("energy", 1e-3, 0.2) > 8


def test_orbit_error_first_order_in_eps():
    for m, lo in (("averaging", 1.6), ("energy", 3.0)):
        r = (compare_periodic(m, 0.1, 0.25, side="upper").max_error
             / compare_periodic(m, 0.05, 0.25, side="upper").max_error)
        assert lo < r < 5, m


def test_averaging_eq3_beats_eq4_against_exact_eq3():
    exact = transition_delta(-0.01, 1.0, "1/4", None).delta
    err3 = abs(averaging_transition(0.01, 1.0, side="upper", equation=3) - exact)
    err4 = abs(averaging_transition(0.01, 1.0, side="upper") - exact)
    assert err3 < 0.3e-3 < 1e-3 < err4


def test_refusals():
    with pytest.raises(ArgumentError, match="only the lower"):
        method_transition("homotopy", 0.1, 0.5, "1/4", side="upper")
    with pytest.raises(ArgumentError, match="branch '1/4'"):
        method_transition("exact", 0.1, 0.5, "0", side="upper")
    with pytest.raises(ArgumentError, match="unknown side"):
        averaging_transition(0.1, 0.5, side="middle")


def test_cli_side(capsys):
    lower = _json(capsys, ["transition", "--eps", "0.1", "--amplitude", "0.5", "--method",
                           "averaging", "--json"])
    upper = _json(capsys, ["transition", "--eps", "0.1", "--amplitude", "0.5", "--method",
                           "averaging", "--side", "upper", "--json"])
    # closed form by hand, eps = 0.1, B = 0.5: delta = (1/4 -/+ eps/2 +/- eps B^2/12) / (1 - B^2/8)
    e, b2 = 0.1, 0.25
    assert lower["side"] == "lower" and lower["delta"] == pytest.approx(
        (0.25 - e / 2 + e * b2 / 12) / (1 - b2 / 8))  # = 97/465
    assert upper["side"] == "upper" and upper["delta"] == pytest.approx(
        (0.25 + e / 2 - e * b2 / 12) / (1 - b2 / 8))  # = 143/465
    eq3 = _json(capsys, ["transition", "--eps", "0.1", "--amplitude", "0.5", "--method",
                         "averaging", "--side", "upper", "--equation", "3", "--json"])
    assert eq3["equation"] == 3 and eq3["delta"] != upper["delta"]


def test_equation3_methods_beat_eq4_against_exact_eq3():
    ex = method_transition("exact", 0.1, 1.0, "1/4", equation=3).delta
    for m in ("perturbation", "averaging"):
        e3 = abs(method_transition(m, 0.1, 1.0, "1/4", equation=3).delta - ex)
        e4 = abs(method_transition(m, 0.1, 1.0, "1/4").delta - ex)
        assert e3 < 0.5 * e4, m
    r = compare_periodic("homotopy", 0.1, 1.0, "1/4", 2, equation=3)
    assert r.equation == 3 and r.delta_error < 1e-5 and r.max_error < 1e-3
    with pytest.raises(ArgumentError, match="eq \\(4\\) only"):
        method_transition("energy", 0.1, 0.5, "1/4", equation=3)
