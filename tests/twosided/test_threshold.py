"""The two-sided answer of ``gfrf threshold`` (lower proven, upper a witness).

The checks are independent of the code under test: the energy certificate's dV/dt is
recomputed with sympy from V and the ODE; the witness is re-simulated with a
hand-written right-hand side and scipy's solve_ivp (escape = |theta| > 10 from
rest); the measured tone threshold A = 1.34 of the damped pendulum comes from an
independent scan.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from gfrf.cli import main
from gfrf.model.equation import parse_model
from gfrf.stability.energy import energy_certificate
from gfrf.twosided.lower import IMPROPER_LOWER_CLASS

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "models"
#: An independent scan: smallest escaping tone of hanging_pendulum_damped.
TONE_THRESHOLD = 1.34
CONTRACT = {"lower", "lower_method", "lower_proof", "upper", "upper_method", "witness",
            "certificates"}


def _json(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict]:
    code = main(["threshold", *argv, "--json"])
    out = capsys.readouterr().out
    return code, _strict(out)


def _strict(text: str) -> dict:
    """Strict JSON (a NaN/Infinity token raises); ``lower`` "inf" read back as math.inf."""
    data = json.loads(text, parse_constant=lambda token: pytest.fail(f"JSON token {token}"))
    if data.get("lower") == "inf":
        data["lower"] = math.inf
    return data


def _check_contract(data: dict) -> None:
    assert CONTRACT <= set(data)
    assert isinstance(data["lower"], float) and isinstance(data["lower_method"], str)
    assert data["lower_proof"] in ("interval", "float", "none")
    assert data["upper"] is None or isinstance(data["upper"], float)
    assert (data["upper"] is None) == (data["witness"] is None) == (data["upper_method"] is None)
    if data["witness"] is not None:
        w = data["witness"]
        if w["kind"] == "unstable-pole":
            assert data["upper"] == 0.0 and data["lower"] == 0.0
        elif w["kind"] == "tones":
            assert set(w) == {"kind", "tones", "t_escape"}
            assert all(len(t) == 3 for t in w["tones"])
            assert math.isclose(sum(t[0] for t in w["tones"]), data["upper"])
        else:
            # a loop with an improper controller names the signal switched (d = C r) and
            # the stated breakdown level its escape reaches
            extra = ({"signal", "escape"} if data["lower_class"] == IMPROPER_LOWER_CLASS
                     else set())
            assert set(w) == {"kind", "amplitude", "first_sign", "switch_times", "t_escape",
                              *extra}
            assert w["amplitude"] == data["upper"] and w["first_sign"] in (1, -1)
            assert w["switch_times"] == sorted(w["switch_times"])
    for c in data["certificates"]:
        assert {"method", "radius", "proof", "input_class"} <= set(c)


# --- the energy certificate -------------------------------------------------------------

def test_energy_certificate_applies_to_damped_hardening_only() -> None:
    assert energy_certificate(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")).radius \
        == math.inf
    assert energy_certificate(parse_model("2*D(y,2) + D(y) + y + y**2 + y**5 = 3*u")) \
        is not None
    for text in ("D(y,2) + 0.2*D(y) + y - 0.5*y**3 = u",  # softening
                 "D(y,2) - 0.2*D(y) + y + 0.5*y**3 = u",  # negative damping
                 "D(y,2) + y + 0.5*y**3 = u",  # undamped
                 "D(y,2) + D(y) - y + y**3 = u",  # unstable origin (bounded, not stable)
                 "D(y,2) + 0.2*D(y) + y + 0.5*y**4 = u",  # even degree
                 "D(y,2) + 0.2*D(y) + y + 0.5*y**3 + y**2*D(y) = u",  # outside the class
                 "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u + u**2",  # nonlinear input
                 "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = 0*u + D(u)"):  # derivative of u
        assert energy_certificate(parse_model(text)) is None, text


def test_energy_derivative_recomputed_with_sympy() -> None:
    """dV/dt + alpha |x|^2 - (y' + eps y) w equals P(y) minus a square: P's top coefficient
    is negative, so the certificate's inequality holds (recomputed from V and the ODE)."""
    y, p, w = sp.symbols("y p w", real=True)
    k, lead, lin = sp.Rational(1, 5), sp.Rational(1, 2), sp.Integer(1)  # the Duffing model
    f = lin * y + lead * y**3
    eps, alpha = k / 2, k / 4
    V = p**2 / 2 + sp.integrate(f, (y, 0, y)) + eps * y * p
    dV = sp.diff(V, y) * p + sp.diff(V, p) * (-k * p - f + w)
    rest = sp.expand(dV + alpha * (y**2 + p**2) - (p + eps * y) * w)
    P = eps**2 * k**2 * y**2 / (4 * (k - eps - alpha)) + alpha * y**2 - eps * y * f
    square = (k - eps - alpha) * (p + eps * k * y / (2 * (k - eps - alpha)))**2
    assert sp.simplify(rest - (P - square)) == 0
    assert sp.Poly(P, y).LC() < 0 and sp.degree(P, y) == 4


def test_duffing_is_bounded_under_large_bounded_inputs() -> None:
    """The certificate says every bounded input gives a bounded state: large inputs far
    beyond Theorem 1's r* = 0.048 stay bounded in an independent solve_ivp run."""
    for a, w in ((50.0, 1.3), (200.0, 0.4), (20.0, 5.0)):
        sol = solve_ivp(lambda t, z, a=a, w=w: [z[1], -0.2 * z[1] - z[0] - 0.5 * z[0]**3
                                                + a * math.cos(w * t)],
                        (0, 60), [0.0, 0.0], method="DOP853", rtol=1e-8, atol=1e-10)
        assert sol.status == 0 and np.max(np.abs(sol.y[0])) < 4 * a ** (1 / 3)


# --- gfrf threshold ---------------------------------------------------------------------

def test_duffing_lower_is_proven_infinite_upper_null(capsys) -> None:
    code = main(["threshold", str(MODELS / "duffing.toml"), "--json"])
    out = capsys.readouterr().out
    assert '"lower": "inf"' in out  # JSON has no infinity: the CLI's string "inf"
    data = _strict(out)
    _check_contract(data)
    assert code == 0
    assert data["lower"] == math.inf and data["lower_proof"] == "interval"
    assert "energy" in data["lower_method"] and "theorem" not in data["lower_method"]
    assert data["upper"] is None and data["witness"] is None
    theorem = next(c for c in data["certificates"] if c["method"].startswith("theorem 1"))
    assert 0 < theorem["radius"] < 0.1  # r* = 0.048: the second certificate is not Theorem 1


@pytest.mark.slow
def test_pendulum_upper_and_an_independent_witness_run(capsys) -> None:
    code, data = _json(capsys, str(MODELS / "hanging_pendulum_damped.toml"))
    _check_contract(data)
    assert code == 0
    assert data["upper"] <= 1.05 * TONE_THRESHOLD
    assert 0.409 <= data["lower"] <= data["upper"] and data["lower_proof"] == "interval"
    w = data["witness"]
    assert w["kind"] == "switching"  # u = +-U beats every sum of tones on an oscillator
    U, times = w["amplitude"], w["switch_times"]

    def rhs(t: float, z: list[float], u: float) -> list[float]:
        return [z[1], -0.5 * z[1] - 2.45 * z[0] + (9.8 / 4 / 6) * z[0]**3 + u]

    def escaped(t: float, z: list[float], u: float) -> float:
        return abs(z[0]) - 10.0

    escaped.terminal = True  # type: ignore[attr-defined]
    for rtol in (1e-9, 1e-11):  # each switch an integration boundary, u constant between
        z, sign, t_hit = [0.0, 0.0], w["first_sign"], None
        for a, b in zip([0.0, *times], [*times, times[-1] + 200.0], strict=True):
            sol = solve_ivp(rhs, (a, b), z, method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                            events=escaped, args=(sign * U,))
            if sol.status == 1:
                t_hit = sol.t_events[0][0]
                break
            z, sign = list(sol.y[:, -1]), -sign
        assert t_hit is not None, rtol  # the witness escapes: |theta| > 10 (then blows up)
        assert t_hit >= w["t_escape"] - 1e-6  # the escape region is entered before


@pytest.mark.slow
def test_same_command_same_bytes(capsys) -> None:
    outs = []
    for _ in range(2):
        main(["threshold", str(MODELS / "hanging_pendulum_damped.toml"), "--json"])
        outs.append(capsys.readouterr().out)
    assert outs[0] == outs[1]


def test_text_output_says_the_three_regions(capsys) -> None:
    code = main(["threshold", "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"])
    out = capsys.readouterr().out
    # the property proven is boundedness, not a return to rest
    assert code == 0 and "bounded for every bounded input" in out
    assert len(out.splitlines()) <= 8


@pytest.mark.parametrize("argv", [["models/nonexistent.toml"], ["D(y,2) + y = u", "--order", "0"],
                                  ["D(y,2) + y^3 = u"]])
def test_bad_input_exit_2(capsys, argv: list[str]) -> None:
    assert main(["threshold", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("gfrf: error:") and "Traceback" not in err


def test_api_threshold_is_exported() -> None:
    import gfrf

    t = gfrf.threshold(gfrf.load_model(MODELS / "duffing.toml"))
    assert t.lower == math.inf and t.upper is None and t.witness is None


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(p.stem for p in MODELS.glob("*.toml")
                                        if "kind = \"parametric\"" not in p.read_text()))
def test_every_bundled_model_lower_at_least_r_star_and_below_upper(capsys, name: str) -> None:
    import gfrf

    code, data = _json(capsys, str(MODELS / f"{name}.toml"))
    _check_contract(data)
    r_star = gfrf.verdict(gfrf.load_model(MODELS / f"{name}.toml"), with_norms=False).radius
    # lower covers every input with sup|u| <= lower; r* (sums of tones) is listed beside it
    assert data["certificates"][0]["radius"] <= max(r_star, 0.0) + 1e-12
    assert data["lower_class"].startswith("every")
    if data["upper"] is not None:
        assert data["lower"] <= data["upper"]
    # exit 0 exactly when both sides are closed: a proven lower > 0 met by a witness or
    # global, or an unstable equilibrium
    proven = data["lower"] > 0 and data["lower_proof"] != "none"
    closed = data["unstable"] is not None or (
        proven and (data["lower"] == math.inf or data["upper"] is not None))
    assert data["answered"] is closed and code == (0 if closed else 1)


def test_verdict_threshold_block_closes_the_gap(capsys) -> None:
    """Theorem 1 alone says inconclusive for the damped Duffing at r = 1; with the
    threshold block the energy certificate proves it stable (exit 0)."""
    duffing = str(MODELS / "duffing.toml")
    assert main(["verdict", duffing, "--order", "3"]) == 1
    capsys.readouterr()
    assert main(["verdict", duffing, "--order", "3", "--threshold", "--json"]) == 0
    block = json.loads(capsys.readouterr().out)["threshold"]
    assert block["verdict_at_amplitude"] == "stable" and block["upper"] is None


def test_local_certificate_of_the_damped_pendulum_survives_energy_pumping() -> None:
    """The sublevel-set radius U lies between Theorem 1's r* = 0.409 and the escaping
    tone 1.34, and the worst input for the energy, u = U sign(theta'), keeps an
    independent solve_ivp run inside the well (|theta| < sqrt(6), the barrier)."""
    from gfrf.model.modelfile import load_model
    from gfrf.stability.energy_local import local_energy_certificate

    cert = local_energy_certificate(load_model(MODELS / "hanging_pendulum_damped.toml").plant)
    assert cert is not None and cert.proof == "interval"
    U = cert.radius
    assert 0.409 < U < TONE_THRESHOLD
    b = 9.8 / 4 / 6
    for u in (lambda t, z: U * math.copysign(1.0, z[1]),
              lambda t, z: U * math.cos(1.05 * t), lambda t, z: U * math.cos(1.45 * t)):
        sol = solve_ivp(lambda t, z, u=u: [z[1], -0.5 * z[1] - 2.45 * z[0] + b * z[0]**3
                                           + u(t, z)],
                        (0, 200), [0.0, 0.0], method="DOP853", rtol=1e-9, atol=1e-12,
                        max_step=0.05)
        assert sol.status == 0 and np.max(np.abs(sol.y[0])) < math.sqrt(6)
    assert local_energy_certificate(parse_model("D(y,2) + 0.5*D(y) + 2.45*y + 0.4*y**3 = u")) \
        is None  # hardening: the global certificate's case, not this one


def test_r_star_of_an_unstable_linear_part_proves_nothing() -> None:
    """Theorem 1 computes r* = 0.3849 for y'' + y' - y + y^3 = u, but its linear part is
    unstable (pole at (-1 + sqrt 5)/2 > 0): no amplitude is proven stable."""
    import gfrf

    t = gfrf.threshold(parse_model("D(y,2) + D(y) - y + y**3 = u"))
    assert t.certificates[0].radius == 0.0 and t.lower == 0.0
    assert "linear part" in t.certificates[0].detail
    # the unstable pole answers both sides: lower = upper = 0, the pole as the reason
    assert t.upper == 0.0 and "0.618034" in (t.unstable or "")
    assert t.answer.startswith("unstable at every input amplitude")


def test_a_linear_model_with_an_unstable_pole_is_unstable_at_every_amplitude(capsys) -> None:
    """y' = y + u: the pole s = 1 is decided exactly; lower = upper = 0, exit 0.  The closed
    form y = int e^(t-s) u(s) ds grows for an input as small as 1e-6 (a DOP853 run)."""
    code, data = _json(capsys, "D(y) - y = u")
    assert code == 0
    _check_contract(data)
    assert data["lower"] == 0 and data["lower_proof"] == "none"
    assert data["upper"] == 0 and data["upper_proof"] == "interval"
    assert "s = 1" in data["unstable"] and data["witness"]["kind"] == "unstable-pole"
    assert all(c["proof"] in ("interval", "float", "none") for c in data["certificates"])
    sol = solve_ivp(lambda t, y: [y[0] + 1e-6 * math.cos(t)], (0, 30), [0.0],
                    method="DOP853", rtol=1e-10, atol=1e-14)
    assert abs(sol.y[0, -1]) > 1e3


@pytest.mark.parametrize(("lower", "lower_proof", "upper", "unstable", "answered"), [
    (0.0, "none", 0.79, None, False),        # a witness, nothing proven below
    (0.0, "none", None, None, False),        # nothing on either side
    (0.4, "interval", 1.3, None, True),      # proven below, a witness above
    (0.4, "float", 1.3, None, True),
    (0.4, "interval", None, None, False),    # no escape found up to the cap
    (math.inf, "interval", None, None, True),  # a global certificate
    (0.0, "none", 0.0, "pole s = 1", True),  # an exactly decided unstable equilibrium
])
def test_threshold_is_answered_only_with_a_proven_lower_side(
        lower: float, lower_proof: str, upper: float | None, unstable: str | None,
        answered: bool) -> None:
    """The rule behind the exit code of ``gfrf threshold`` (0 exactly when answered)."""
    from gfrf.twosided.threshold import Threshold

    t = Threshold(name="m", lower=lower, lower_method="m", lower_proof=lower_proof,
                  upper=upper, upper_method=None if upper is None else "w", certificates=(),
                  unstable=unstable)
    assert t.answered is answered and t.to_dict()["answered"] is answered


def test_a_loop_witness_method_names_the_reference_an_open_loop_the_input() -> None:
    """The falsifier switches the input u of an open loop and the reference r of a loop
    u = C(r - y): every witness kind has both texts, the same but for that signal."""
    from gfrf.twosided.threshold import LOOP_UPPER_METHOD, UPPER_METHOD

    assert set(UPPER_METHOD) <= set(LOOP_UPPER_METHOD)
    for kind, text in UPPER_METHOD.items():
        loop = LOOP_UPPER_METHOD[kind]
        assert "input u" not in loop and "sup|u|" not in loop
        assert loop.replace("reference r", "input u").replace("sup|r|", "sup|u|") == text
