"""The proven escape: Arb enclosures of the witness's trajectory from rest.

Independent references: mpmath's Taylor-series ODE solver at 50 digits (the enclosure
must contain it at every step), and the scaled witness (0.9 x) that must not be proven.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import mpmath as mp
import pytest
from enclosure_helpers import contains as _contains
from enclosure_helpers import witness as _witness

from gfrf import parse_model
from gfrf.cli import main
from gfrf.model.modelfile import load_model
from gfrf.twosided.enclose import enclose_witness
from gfrf.twosided.escape import escape_region
from gfrf.twosided.falsify import Falsification, falsify
from gfrf.twosided.witness import Chirp

MODELS = Path(__file__).resolve().parents[2] / "models"


@pytest.mark.slow
def test_enclosure_holds_the_50_digit_taylor_solution_under_a_switching_input() -> None:
    """y'' + 0.5 y' + 2.45 y - 0.4083 y^3 = u, u = +-0.94 switching at 2.1 and 4.3 s."""
    model = load_model(MODELS / "hanging_pendulum_damped.toml").plant
    f = _witness("switching", 0.94, 6.0, first_sign=1, switch_times=[2.1, 4.3])
    trace: list = []
    enclose_witness(model, f, trace=trace)
    assert trace and float(trace[-1][0].mid()) == pytest.approx(6.0)
    # the model as written: g/L theta - g/(6L) theta^3 with g = 9.8 = 49/5 and L = 4, so
    # 49/20 theta - 49/120 theta^3 (the input switches between the witness's doubles)
    with mp.workdps(50):
        cubic = mp.mpf(49) / 120
        edges, z, sign = [0, 2.1, 4.3, 6.0], [mp.mpf(0), mp.mpf(0)], 1
        checked = 0
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            u = sign * mp.mpf(0.94)
            sol = mp.odefun(lambda t, y, u=u: [y[1], -mp.mpf(0.5) * y[1] - mp.mpf("2.45") * y[0]
                                               + cubic * y[0] ** 3 + u], mp.mpf(a), z)
            for t, boxes in trace:
                tm = mp.mpf(t.mid().str(60, radius=False))
                if mp.mpf(a) < tm <= mp.mpf(b):
                    ref = sol(tm)
                    assert all(_contains(x, r) for x, r in zip(boxes, ref, strict=True)), tm
                    checked += 1
            z, sign = sol(mp.mpf(b)), -sign
        assert checked == len(trace)


@pytest.mark.slow
def test_enclosure_holds_the_50_digit_taylor_solution_under_a_tone_third_order() -> None:
    """y''' + 2y'' + 2y' + y - 0.5 y^3 = u, u = 0.3 cos(1.3 t + 0.4) (the tone's exact
    oscillator states ride along in the enclosure)."""
    model = parse_model("D(y,3) + 2*D(y,2) + 2*D(y) + y - 0.5*y**3 = u")
    f = _witness("tones", 0.3, 1.5, tones=[(0.3, 1.3, 0.4)])
    trace: list = []
    enclose_witness(model, f, trace=trace)
    assert len(trace) >= 6  # steps of at most 1/4 s
    with mp.workdps(50):
        a, w, p = mp.mpf(0.3), mp.mpf(1.3), mp.mpf(0.4)
        sol = mp.odefun(lambda t, y: [y[1], y[2], -2 * y[2] - 2 * y[1] - y[0]
                                      + mp.mpf(0.5) * y[0] ** 3 + a * mp.cos(w * t + p)],
                        0, [mp.mpf(0)] * 3)
        for t, boxes in trace:
            ref = sol(mp.mpf(t.mid().str(60, radius=False)))
            assert all(_contains(x, r) for x, r in zip(boxes[:3], ref, strict=True))


@pytest.mark.slow
def test_a_witness_scaled_by_0_9_is_not_proven() -> None:
    model = load_model(MODELS / "hanging_pendulum_damped.toml").plant
    f = falsify(model, 23.1)
    assert f.kind == "switching" and f.upper is not None
    proof = enclose_witness(model, f)
    assert proof is not None and proof.proven
    assert proof.t_proven == pytest.approx(f.t_escape, rel=0.02)
    weaker = Falsification(0.9 * f.upper, [], f.t_escape, f.edge, cap=f.cap, t_end=f.t_end,
                           runs=0, escape="", kind="switching", first_sign=f.first_sign,
                           switch_times=f.switch_times, levels=f.levels,
                           region=escape_region(model, 0.9 * f.upper))
    scaled = enclose_witness(model, weaker)
    assert scaled is not None and not scaled.proven


@pytest.mark.slow
def test_narx_witness_is_proven_by_the_ball_recursion(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    code = main(["threshold", str(MODELS / "narx_example.toml")])
    text = capsys.readouterr().out
    assert code == 0 and "DOP853" not in text and "proven" in text
    main(["threshold", str(MODELS / "narx_example.toml"), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert data["upper_proof"] == "interval" and data["upper"] >= data["lower"]
    assert data["witness"]["kind"] in ("tones", "switching", "chirp")


@pytest.mark.slow
@pytest.mark.parametrize("source, cap", [
    ("D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u", 2.0),
    ("third-order plant", 6.0)])
def test_slow_escapes_are_proven_and_the_weaker_witness_is_not(source: str, cap: float
                                                                ) -> None:
    """The softening oscillator escapes after about 80 s and the third-order plant after
    about 70 s of switching: the Lohner enclosure stays narrow that long."""
    if source == "third-order plant":
        import control

        from gfrf.model.from_control import from_tf

        model = from_tf(control.tf([2], [1, 1.2, 3, 1]), {2: 0.3, 3: 0.5})
    else:
        model = parse_model(source)
    f = falsify(model, cap)
    assert f.kind == "switching" and f.upper is not None and f.t_escape is not None
    proof = enclose_witness(model, f)
    assert proof is not None and proof.proven, proof
    assert proof.t_proven == pytest.approx(f.t_escape, rel=0.02)
    region = escape_region(model, 0.9 * f.upper) if f.region is not None else None
    weaker = Falsification(0.9 * f.upper, [], f.t_escape, f.edge, cap=f.cap, t_end=f.t_end,
                           runs=0, escape="", kind="switching", first_sign=f.first_sign,
                           switch_times=f.switch_times, levels=f.levels, region=region)
    scaled = enclose_witness(model, weaker)
    assert scaled is not None and not scaled.proven


@pytest.mark.slow
def test_ctrl_c_during_the_proof_exits_130_quietly() -> None:
    """SIGINT to the process group once the enclosure has started: exit 130, the one
    line ``gfrf: interrupted`` on stderr, nothing on stdout."""
    import os
    import signal
    import subprocess
    import sys
    import time

    root = MODELS.parent
    script = """
import signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)  # as under a terminal
from gfrf.twosided import enclose
advance = enclose._advance
said = []
def spying(*args):
    if not said:
        said.append(1)
        print("proof", file=sys.stderr, flush=True)
    return advance(*args)
enclose._advance = spying
from gfrf.cli import main
sys.exit(main(["threshold", "D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u"]))
"""
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=root, start_new_session=True)
    try:
        assert proc.stderr is not None
        while True:  # warnings of the lower side may come first
            line = proc.stderr.readline()
            assert line, "the proof never started"
            if line == b"proof\n":
                break
        time.sleep(0.2)
        os.killpg(proc.pid, signal.SIGINT)
        start = time.perf_counter()
        out, err = proc.communicate(timeout=60)
        assert proc.returncode == 130
        assert err.decode() == "gfrf: interrupted\n" and out == b""
        assert time.perf_counter() - start < 5.0
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


@pytest.mark.slow
def test_enclosure_holds_the_50_digit_taylor_solution_under_a_chirp() -> None:
    """y'' + 0.2y' + 2y - 0.3y^3 = u, u = 0.5 cos(1.4 t + k t^2), k = (0.7 - 1.4)/(2*3):
    the chirp's phase states (c, s, tau) ride along; the input is the exact chirp of the
    witness's doubles."""
    model = parse_model("D(y,2) + 0.2*D(y) + 2*y - 0.3*y**3 = u")
    chirp = Chirp(amplitude=0.5, omega_start=1.4, omega_end=0.7, duration=3.0)
    f = _witness("chirp", 0.5, 2.0, chirp=chirp)
    trace: list = []
    enclose_witness(model, f, trace=trace)
    assert len(trace) >= 8 and float(trace[-1][0].mid()) == pytest.approx(2.0)  # 1.5 t_escape
    with mp.workdps(50):
        a, w0 = mp.mpf(0.5), mp.mpf(1.4)
        k = (mp.mpf(0.7) - w0) / (2 * mp.mpf(3.0))
        sol = mp.odefun(lambda t, y: [y[1], -mp.mpf("0.2") * y[1] - 2 * y[0] + mp.mpf("0.3")
                                      * y[0] ** 3 + a * mp.cos(w0 * t + k * t * t)],
                        0, [mp.mpf(0)] * 2)
        for t, boxes in trace:
            tm = mp.mpf(t.mid().str(60, radius=False))
            ref = sol(tm)
            assert all(_contains(x, r) for x, r in zip(boxes[:2], ref, strict=True)), tm
            assert _contains(boxes[4], tm)  # tau is the time


@pytest.mark.slow
def test_chirp_witness_escape_is_proven_and_not_at_090() -> None:
    """A down-sweep that escapes y'' + 0.2y' + 2y - 0.3y^3 = u: the enclosure enters the
    certified escape region; the same chirp at 0.9 x the amplitude is not proven."""
    from gfrf.sim.system import build_system
    from gfrf.twosided.runner import EscapeRunner

    model = parse_model("D(y,2) + 0.2*D(y) + 2*y - 0.3*y**3 = u")
    runner = EscapeRunner(build_system(model, equation="polynomial"), model, 10.0)
    chirp = Chirp(amplitude=0.551337890625, omega_start=2 ** 0.5, omega_end=0.5 * 2 ** 0.5,
                  duration=200.0)
    t_escape = runner.confirm_chirp(chirp)
    assert t_escape is not None

    def witness(c: Chirp) -> Falsification:
        return Falsification(c.amplitude, [], t_escape, c.amplitude, cap=2.0,
                             t_end=runner.t_end, runs=0, escape="", kind="chirp", chirp=c,
                             region=runner.region(c.amplitude), levels=list(runner.levels))

    proof = enclose_witness(model, witness(chirp))
    assert proof is not None and proof.proven and proof.t_proven <= 1.01 * t_escape
    weaker = enclose_witness(model, witness(replace(chirp, amplitude=0.9 * chirp.amplitude)))
    assert weaker is not None and not weaker.proven


def test_an_irrational_coefficient_is_enclosed_by_its_widened_double() -> None:
    """y'' + (pi/10) y' + y - 0.3 y^3 = u, u = 0.6: pi has no rational value; the
    enclosure, built on the double of pi/10 widened by a relative 2^-50, holds the
    50-digit solution with pi itself."""
    model = parse_model("D(y,2) + pi/10*D(y) + y - 0.3*y**3 = u")
    f = _witness("switching", 0.6, 1.0, first_sign=1, switch_times=[])
    trace: list = []
    enclose_witness(model, f, trace=trace)
    assert len(trace) >= 3
    with mp.workdps(50):
        sol = mp.odefun(lambda t, y: [y[1], -mp.pi / 10 * y[1] - y[0]
                                      + mp.mpf("0.3") * y[0] ** 3 + mp.mpf(0.6)],
                        0, [mp.mpf(0)] * 2)
        for t, boxes in trace:
            ref = sol(mp.mpf(t.mid().str(60, radius=False)))
            assert all(_contains(x, r) for x, r in zip(boxes[:2], ref, strict=True))
