"""CLI contract of ``gfrf verdict`` and ``gfrf norm``: JSON keys and exit codes 0/1/2."""

from __future__ import annotations

import json
import math

import pytest
from conftest import run

from gfrf.cli import main

STABLE = "D(y,2) + D(y) + 2*y + y**3 = u"



def test_verdict_json_inconclusive_exit_1(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "verdict", "models/hanging_pendulum_damped.toml", "--order", "3",
                       "--json")
    data = json.loads(out)
    assert code == 1
    assert {"verdict", "theorem", "radius", "conditions"} <= set(data)
    assert data["verdict"] == "inconclusive" and data["theorem"] == 1
    assert all({"name", "passed", "value", "detail"} <= set(c) for c in data["conditions"])
    assert len(data["norms"]) == 3


def test_verdict_stable_exit_0(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "verdict", STABLE, "--order", "3", "--amplitude", "0.1")
    assert code == 0
    assert "verdict: stable" in out and "[pass]" in out


def test_verdict_closed_loop_theorem_2(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "verdict", "models/cartpole_reduced.toml", "--order", "3",
                       "--json")
    data = json.loads(out)
    assert code == 1 and data["theorem"] == 2 and data["radius"] == 0.0


def test_verdict_unstable_exit_1(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "verdict", "D(y,2) - D(y) + 2*y + y**3 = u", "--order", "3",
                       "--json")
    assert code == 1 and json.loads(out)["verdict"] == "unstable"


def test_norm_order_1(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "norm", "D(y,2) + 0.05*D(y) + 2.45*y = u", "--order", "1",
                       "--json")
    data = json.loads(out)
    assert code == 0
    expected = 1 / (0.05 * math.sqrt(2.45 - 0.05**2 / 4))
    # a proven enclosure (outward-rounded), a few ulps wide
    assert data["lower"] <= expected * (1 + 1e-12) and data["upper"] >= expected * (1 - 1e-12)
    assert data["upper"] == pytest.approx(expected, rel=1e-9) and data["proof"] == "interval"


def test_norm_improper_is_inf(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "norm", "D(y,2) + D(y) + y = D(u,3)", "--order", "1", "--json")
    data = json.loads(out)
    assert code == 0 and data["lower"] == data["upper"] == "inf"


def test_norm_text_and_asymmetric(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "norm", "models/duffing.toml", "--order", "3", "--asymmetric")
    assert code == 0 and "asymmetric" in out and out.splitlines()[1].endswith("proven")


@pytest.mark.parametrize("argv", [
    ["norm", "models/duffing.toml", "--order", "0"],
    ["norm", "models/duffing.toml", "--order", "3", "--tol", "2"],
    ["verdict", "models/missing.toml"],
    ["verdict", "models/duffing.toml", "--amplitude", "-1"],
    ["verdict", "models/parametric_pendulum.toml"],
    ["verdict", "models/duffing.toml", "--margin", "nope"],
    ["verdict", "D(y,2) + = u"],
])
def test_bad_input_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str]) -> None:
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert err.startswith("gfrf: error:") and "Traceback" not in err


@pytest.mark.parametrize("command", ["verdict", "norm"])
def test_order_above_kernel_limit_refused_before_work(
        capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
        command: str) -> None:
    # verdict --order 13 used to compute ||H1||..||H12|| for a minute before refusing
    from gfrf.cli import stability
    from gfrf.kernels.recursion import MAX_KERNEL_ORDER

    def no_work(*args: object, **kwargs: object) -> None:
        pytest.fail("computed before checking the order")

    monkeypatch.setattr("gfrf.stability.criteria.verdict", no_work)  # imported where used
    monkeypatch.setattr("gfrf.bounds.norms.kernel_norm", no_work)
    monkeypatch.setattr(stability, "resolve_model", no_work)
    code, out, err = run(capsys, command, "models/duffing.toml", "--order",
                         str(MAX_KERNEL_ORDER + 1))
    assert code == 2 and out == ""
    assert f"MAX_KERNEL_ORDER = {MAX_KERNEL_ORDER}" in err


POLE_AT_ZERO = """name = "loop with a closed-loop pole at s = 0"
output = "y"
equation = "D(y,2) + D(y) + y + 0.1*y**3 + 0.05*y**2*D(u) = u"

[controller]
num = [1]
den = [1]
feedback = 1
"""


def test_loop_pole_at_zero_never_prints_nan(capsys: pytest.CaptureFixture[str],
                                            tmp_path: pytest.TempPathFactory) -> None:
    # chi = s^2 + s + 1 - 1 = s^2 + s: python-control puts a closed-loop pole at 0, so the
    # sensitivity peak rho_1 is infinite; theta_n rho_1^n r^n printed nan (0 * inf).  The
    # D(u) factor also makes the plant majorant infinite (phi_n = 0 * inf before).
    import control
    import numpy as np

    poles = control.poles(control.feedback(control.tf([1], [1, 1, 1]), 1, sign=1))
    assert np.min(np.abs(poles)) < 1e-12
    path = tmp_path / "pole0.toml"  # type: ignore[operator]
    path.write_text(POLE_AT_ZERO)
    code, out, _ = run(capsys, "verdict", str(path), "--order", "5")
    assert code == 1 and "nan" not in out.lower()
    code, out, _ = run(capsys, "verdict", str(path), "--order", "5", "--json")
    data = json.loads(out)
    assert data["verdict"] != "stable"
    terms = [row["theta_term"] for row in data["series"]]
    assert terms == ["inf"] * 5  # rho_1 = inf bounds nothing; never NaN (JSON null)
    assert all(row["phi"] is not None for row in data["series"])


def test_library_verdict_checks_order_first(monkeypatch: pytest.MonkeyPatch) -> None:
    from gfrf.errors import ArgumentError
    from gfrf.kernels.recursion import MAX_KERNEL_ORDER
    from gfrf.model.equation import parse_model
    from gfrf.stability import criteria, theorem1

    monkeypatch.setattr(theorem1, "majorant", lambda *a: pytest.fail("computed first"))
    with pytest.raises(ArgumentError, match="MAX_KERNEL_ORDER"):
        criteria.verdict(parse_model(STABLE), MAX_KERNEL_ORDER + 1)


# -- levels of proof ---------------------------------------------------------------------
BETA = 1.0 / math.sqrt(2.0 - 0.25)  # ||H1|| of D(y,2) + D(y) + 2*y: 1/(b sqrt(c - b^2/4))


@pytest.mark.parametrize(("level", "label"), [("interval", "proven"),
                                              ("float", "certified (float)"),
                                              ("none", "estimate")])
def test_norm_proof_levels_text_and_json(capsys: pytest.CaptureFixture[str], level: str,
                                         label: str) -> None:
    code, out, _ = run(capsys, "norm", STABLE, "--order", "1", "--proof", level)
    # estimates are never a converged bracket: exit 1 at --proof none
    assert code == (1 if level == "none" else 0) and out.splitlines()[1].endswith(label)
    assert ("proven" in out) is (level == "interval")
    code, out, _ = run(capsys, "norm", STABLE, "--order", "1", "--proof", level, "--json")
    data = json.loads(out)
    assert data["proof"] == data["upper_proof"] == data["lower_proof"] == level
    assert data["proof_level"] == level
    assert data["upper"] == pytest.approx(BETA, rel=1e-13)
    if level == "interval":  # a proof: the enclosure contains the closed form
        from fractions import Fraction

        import mpmath as mp

        with mp.workdps(50):
            exact = 1 / (mp.mpf(1) * mp.sqrt(mp.mpf(2) - mp.mpf(1) / 4))
        assert Fraction(data["lower"]) <= Fraction(mp.nstr(exact, 45)) <= Fraction(data["upper"])


@pytest.mark.parametrize("tol", ["0.001", "0.9"])
def test_norm_exit_code_says_whether_the_bracket_closed_to_tol(
        capsys: pytest.CaptureFixture[str], tol: str) -> None:
    """The pendulum's ||H5|| left at the majorant (no branch-and-bound) is open: exit 1 at
    the default tol, 0 at a tol above its gap; the gap is recomputed from the two ends."""
    code, out, _ = run(capsys, "norm", "models/hanging_pendulum.toml", "--order", "5",
                       "--max-boxes", "0", "--tol", tol, "--json")
    data = json.loads(out)
    gap = (data["upper"] - data["lower"]) / data["upper"]
    assert 0.1 < gap < 0.9 and data["tol"] == float(tol) and data["stable"] is True
    assert data["converged"] is (gap <= float(tol)) and code == (0 if gap <= float(tol) else 1)
    code, out, _ = run(capsys, "norm", "models/hanging_pendulum.toml", "--order", "5",
                       "--max-boxes", "0", "--tol", tol)
    verdict = "  converged: gap" if gap <= float(tol) else "  not converged: gap"
    assert out.splitlines()[2].startswith(verdict) and f"tol {float(tol):g}" in out


def test_norm_header_names_the_level_asked_and_reached(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    code, out, _ = run(capsys, "norm", STABLE, "--order", "1", "--proof", "float")
    assert out.splitlines()[0].endswith("proof level asked float, reached float")
    from gfrf.bounds.norms import Bound
    from gfrf.cli.stability import _reached

    # an upper end lowered by the float branch-and-bound, a witness proven in balls
    mixed = Bound(lower=1.0, upper=1.0005, argmax=(0.0, 0.0), certified=True, method="m",
                  order=2, proof="float", upper_proof="float", lower_proof="interval")
    assert _reached(mixed) == "float (upper end float, lower end interval)"


def test_norm_order3_proof_per_end(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = run(capsys, "norm", STABLE, "--order", "3", "--json")
    data = json.loads(out)
    assert (data["upper_proof"], data["lower_proof"], data["proof"]) == \
        ("interval", "interval", "interval")


def test_verdict_proof_levels(capsys: pytest.CaptureFixture[str]) -> None:
    """Only certified levels may give 'stable'; the radius carries its level."""
    outcomes = {}
    for level in ("interval", "float", "none"):
        code, out, _ = run(capsys, "verdict", STABLE, "--order", "1", "--amplitude", "0.1",
                           "--proof", level, "--json")
        data = json.loads(out)
        outcomes[level] = (code, data["verdict"], data["radius_proof"])
        assert all(b["proof"] == level for b in data["norms"])
    assert outcomes == {"interval": (0, "stable", "interval"),
                        "float": (0, "stable", "float"),
                        "none": (1, "inconclusive", "none")}
    code, out, _ = run(capsys, "verdict", STABLE, "--order", "1", "--amplitude", "0.1",
                       "--proof", "float")
    assert "proven" not in out and "r* = " in out and "(certified (float))" in out


def test_proof_default_stated_and_bad_level_refused(capsys: pytest.CaptureFixture[str]) -> None:
    for command in ("norm", "verdict"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        out = " ".join(capsys.readouterr().out.split())
        assert "--proof {none,float,interval}" in out and "'interval' (default" in out
    with pytest.raises(SystemExit) as info:
        main(["norm", STABLE, "--order", "1", "--proof", "exact"])
    assert info.value.code == 2


def test_verdict_norms_levels_same_conclusions(capsys: pytest.CaptureFixture[str]) -> None:
    got = {}
    for level in ("none", "fast", "tight"):
        code, out, _ = run(capsys, "verdict", "models/duffing.toml", "--order", "3",
                           "--norms", level, "--json")
        data = json.loads(out)
        assert data["norms_level"] == level
        got[level] = (code, data["verdict"], data["radius"], data["radius_proof"],
                      [c["passed"] for c in data["conditions"]], len(data["norms"]))
    assert got["none"][:5] == got["fast"][:5] == got["tight"][:5]
    assert (got["none"][5], got["fast"][5], got["tight"][5]) == (0, 3, 3)


def test_verdict_help_states_the_norms_default(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["verdict", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "--norms {none,fast,tight}" in out and "'fast' (default;" in out
    with pytest.raises(SystemExit) as bad:
        main(["verdict", "models/duffing.toml", "--norms", "exact"])
    assert bad.value.code == 2
