"""Proven escapes of closed loops u = C(r - y) with a proper controller: the Arb
enclosure of the loop's state (plant and controller) under the witness's reference.

Independent references: mpmath's Taylor-series ODE solver at 50 digits on the loop
written by hand (the controller realised by hand, not by the code's state form), and the
witness scaled by 0.9, which must not be proven.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import mpmath as mp
import pytest
from enclosure_helpers import contains as _contains
from enclosure_helpers import witness as _witness

from gfrf.cli import main
from gfrf.model.modelfile import load_model, model_from_dict
from gfrf.twosided.enclose import enclose_witness, loop_flow
from gfrf.twosided.falsify import Falsification, falsify

MODELS = Path(__file__).resolve().parents[2] / "models"
PLANT = "D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u"
#: C = 0.5 + 0.2/s (PI) and C = (2s + 1)/(s + 2) = 2 - 3/(s + 2) (lead-lag).
PI = {"equation": PLANT, "controller": {"num": [0.5, 0.2], "den": [1.0, 0.0]}}
LEAD = {"equation": PLANT, "controller": {"num": [2.0, 1.0], "den": [1.0, 2.0]}}


def _plant(y: mp.mpf, v: mp.mpf, u: mp.mpf) -> mp.mpf:
    """y'' of the plant as written (0.2 is 1/5 and 0.3 is 3/10, not the doubles)."""
    return -mp.mpf("0.2") * v - y + mp.mpf("0.3") * y ** 3 + u


def test_pi_loop_enclosure_holds_the_50_digit_taylor_solution_under_a_switching_reference(
        ) -> None:
    """r = +-0.3 switching at 1 s; the PI state z' = e = r - y, u = 0.5 e + 0.2 z (the
    controller's 0.2 as written, 1/5; the reference the witness's double 0.3)."""
    f = _witness("switching", 0.3, 2.4, first_sign=1, switch_times=[1.0])
    trace: list = []
    proof = enclose_witness(model_from_dict(PI), f, trace=trace)
    assert proof is not None and not proof.proven
    assert len(trace) >= 10 and float(trace[-1][0].mid()) == pytest.approx(2.4)
    with mp.workdps(50):
        edges, z, sign, checked = [0, 1.0, 2.4], [mp.mpf(0)] * 3, 1, 0
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            r = sign * mp.mpf(0.3)

            def rhs(t: mp.mpf, x: list, r: mp.mpf = r) -> list:
                e = r - x[0]
                return [x[1], _plant(x[0], x[1], mp.mpf(0.5) * e + mp.mpf("0.2") * x[2]), e]

            sol = mp.odefun(rhs, mp.mpf(a), z)
            for t, boxes in trace:
                tm = mp.mpf(t.mid().str(60, radius=False))
                if mp.mpf(a) < tm <= mp.mpf(b):
                    ref = sol(tm)
                    assert all(_contains(x, v) for x, v in zip(boxes[:2], ref, strict=False)), tm
                    checked += 1
            z, sign = sol(mp.mpf(b)), -sign
        assert checked == len(trace)


def _pi_loop(c1: mp.mpf, c3: mp.mpf, ki: mp.mpf, r: mp.mpf) -> Callable[..., list]:
    """The PI loop y'' = -c1 y' - y + c3 y^3 + u, u = 0.5 e + ki z, z' = e = r - y."""
    def rhs(t: mp.mpf, x: list) -> list:
        e = r - x[0]
        return [x[1], -c1 * x[1] - x[0] + c3 * x[0] ** 3 + mp.mpf(0.5) * e + ki * x[2], e]
    return rhs


def test_pi_loop_enclosure_is_of_the_written_model_not_of_its_doubles() -> None:
    """The boxes are tight enough to tell 1/5 from the double 0.2: over the first second
    of r = 0.3 every box holds the 50-digit solution of the loop as written, and some box
    misses the solution of the loop whose coefficients are the doubles."""
    f = _witness("switching", 0.3, 2.4, first_sign=1, switch_times=[1.0])
    trace: list = []
    enclose_witness(model_from_dict(PI), f, trace=trace)
    times = [(t, boxes) for t, boxes in trace if float(t.mid()) <= 1.0]
    assert len(times) >= 3
    with mp.workdps(50):
        solutions = []
        for c1, c3, ki in (("0.2", "0.3", "0.2"), (0.2, 0.3, 0.2)):
            sol = mp.odefun(_pi_loop(mp.mpf(c1), mp.mpf(c3), mp.mpf(ki), mp.mpf(0.3)), 0,
                            [mp.mpf(0)] * 3)
            solutions.append([all(_contains(x, v) for x, v in
                                  zip(boxes[:3], sol(mp.mpf(t.mid().str(60, radius=False))),
                                      strict=True)) for t, boxes in times])
    written, doubles = solutions
    assert all(written)
    assert not all(doubles)


@pytest.mark.slow
def test_lead_lag_loop_enclosure_holds_the_50_digit_taylor_solution_under_a_tone() -> None:
    """r = 1.2 cos(0.9 t + 0.3); the lead-lag state z' = -2 z + e, u = 2 e - 3 z (the
    tone's oscillator states ride along after the loop's three states)."""
    f = _witness("tones", 1.2, 1.5, tones=[(1.2, 0.9, 0.3)])
    trace: list = []
    enclose_witness(model_from_dict(LEAD), f, trace=trace)
    assert len(trace) >= 6
    with mp.workdps(50):
        a, w, p = mp.mpf(1.2), mp.mpf(0.9), mp.mpf(0.3)

        def rhs(t: mp.mpf, x: list) -> list:
            e = a * mp.cos(w * t + p) - x[0]
            return [x[1], _plant(x[0], x[1], 2 * e - 3 * x[2]), -2 * x[2] + e]

        sol = mp.odefun(rhs, 0, [mp.mpf(0)] * 3)
        for t, boxes in trace:
            ref = sol(mp.mpf(t.mid().str(60, radius=False)))
            assert all(_contains(x, v) for x, v in zip(boxes[:2], ref, strict=False))


def test_lead_lag_loop_witness_is_proven_and_not_at_0_9() -> None:
    mf = model_from_dict(LEAD)
    f = falsify(mf, 7.0, closed_loop=True)
    assert f.kind == "switching" and f.upper is not None and f.t_escape is not None
    proof = enclose_witness(mf, f)
    assert proof is not None and proof.proven, proof
    assert proof.t_proven == pytest.approx(f.t_escape, rel=0.02)
    weaker = Falsification(0.9 * f.upper, [], f.t_escape, f.edge, cap=f.cap, t_end=f.t_end,
                           runs=0, escape="", kind="switching", first_sign=f.first_sign,
                           switch_times=f.switch_times, levels=f.levels)
    scaled = enclose_witness(mf, weaker)
    assert scaled is not None and not scaled.proven


def test_an_improper_controller_has_no_loop_enclosure() -> None:
    mf = load_model(MODELS / "cartpole_reduced.toml")
    assert loop_flow(mf) is None
    assert enclose_witness(mf, _witness("switching", 1.0, 3.0, switch_times=[1.0])) is None


@pytest.mark.slow
def test_threshold_of_a_lead_lag_loop_proves_its_witness(tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]
                                                         ) -> None:
    path = tmp_path / "loop.toml"
    path.write_text(f'output = "y"\nequation = "{PLANT}"\n\n[controller]\nnum = [2, 1]\n'
                    "den = [1, 2]\nfeedback = -1\n")
    assert main(["threshold", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["upper_proof"] == "interval" and data["witness"]["kind"] == "switching"
    assert data["lower"] <= data["upper"] <= 1.3 * data["lower"]
