"""One way out: every CLI command prints strict JSON and escapes the user's text.

The commands are listed from the argparse sub-parsers, so a new command must add its
cheap invocation to :data:`INVOCATIONS` or this test fails.  Each runs on a model whose
name is a terminal attack (erase line, carriage return, a forged verdict line) and must
print no ESC or CR, in text and in JSON; ``--json`` output must parse with
``json.loads(..., parse_constant=...)`` raising on ``NaN``/``Infinity``; the exit code is
0, 1 or 2.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import pytest

from gfrf._results import dumps, json_ready
from gfrf.cli import build_parser, main

#: The forged line says "(forged)": a real verdict line ("verdict: stable") may start a line.
HOSTILE = "x\x1b[2K\r\nverdict: stable (forged)"
EQUATION = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


def _commands() -> list[str]:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return sorted(sub.choices)


def _model(folder: Path, extra: str = "", equation: str = EQUATION) -> str:
    path = folder / "hostile.toml"
    path.write_text(f"name = {json.dumps(HOSTILE)}\nequation = {json.dumps(equation)}\n{extra}",
                    encoding="utf-8")
    return str(path)


def _data(folder: Path) -> str:
    """A short NARX record (first-order, noise-free) whose file name is the attack."""
    u = [math.cos(0.7 * k) + 0.3 * math.sin(2.3 * k) for k in range(200)]
    y = [0.0]
    for k in range(1, 200):
        y.append(0.5 * y[-1] + u[k - 1] + 0.1 * u[k - 1] ** 2)
    path = folder / "x\x1b[2Kdata.csv"
    path.write_text("t,u,y\n" + "".join(f"{0.1 * k:g},{a!r},{b!r}\n"
                                         for k, (a, b) in enumerate(zip(u, y, strict=True))))
    return str(path)


def _periodic_data(folder: Path) -> str:
    """Two realisations of three periods (N = 64) of an odd multisine through
    y = u + 0.1 u^2, in a file whose name is the attack."""
    rows = ["t,u,y,realisation"]
    for r in range(2):
        for k in range(3 * 64):
            u = sum(math.cos(2 * math.pi * line * k / 64 + 0.7 * line**2 + r)
                    for line in (1, 3, 5, 7))
            rows.append(f"{0.1 * k:g},{u!r},{u + 0.1 * u * u!r},{r}")
    path = folder / "x\x1b[2Kperiodic.csv"
    path.write_text("\n".join(rows) + "\n")
    return str(path)


#: A model with a global sum-of-squares certificate (nonlinear damping, hardening).
GLOBAL_EQUATION = "D(y,2) + 0.4*D(y) + 2*y + 0.5*y**2*D(y) + 0.8*y**3 = u"


def _certificate(folder: Path) -> list[str]:
    """``check MODEL FILE`` with the certificate the threshold search writes."""
    from gfrf.model.modelfile import resolve_model
    from gfrf.twosided.threshold import threshold

    model = _model(folder, equation=GLOBAL_EQUATION)
    found = threshold(resolve_model(model))
    assert found.sos is not None
    path = folder / "certificate.json"
    path.write_text(json.dumps(found.sos.certificate), encoding="utf-8")
    return ["check", model, str(path)]


def _fake_bench(monkeypatch: pytest.MonkeyPatch) -> None:
    """The benchmarks themselves take minutes (``make test-slow`` runs them): this test
    checks the command's printing, on one section of hostile text."""
    import gfrf.bench

    class Section:
        title = HOSTILE
        columns = ["case", "time (s)"]
        rows = [[HOSTILE, float("inf")], ["nan", float("nan")]]
        notes = [HOSTILE]

        def to_markdown(self) -> str:
            return f"{self.title}\n{self.rows}"

    monkeypatch.setattr(gfrf.bench, "run_all", lambda **kwargs: [Section()])


#: One cheap invocation per command: argv after the command name, given a folder.
INVOCATIONS = {
    "show": lambda d: [_model(d)],
    "kernel": lambda d: [_model(d), "--order", "3", "--at", "1,1,-1"],
    "bench": lambda d: ["--quick"],
    "simulate": lambda d: [_model(d), "--t-end", "1", "--input", "0.1*cos(t)"],
    "predict": lambda d: [_model(d), "--input", "0.01*cos(t)", "--order", "3"],
    "validate": lambda d: [_model(d), "--t-end", "5"],
    "verdict": lambda d: [_model(d), "--order", "3"],
    "norm": lambda d: [_model(d), "--order", "1"],
    "report": lambda d: ["--quick", "--out", str(d / "out"), _model(d)],
    "transition": lambda d: ["--eps", "0.2", "--amplitude", "0.5", "--branch", "1/4",
                             "--method", "perturbation", "--order", "2"],
    "periodic": lambda d: ["--eps", "0.2", "--delta", "0.15", "--amplitude", "0.5",
                           "--method", "perturbation", "--order", "2"],
    "sweep": lambda d: [_model(d, "[parameters]\nc = 0.5\n",
                               "D(y,2) + 0.2*D(y) + y + c*y**3 = u"),
                        "--param", "c=0.1:0.5:2", "--order", "3"],
    "identify": lambda d: [_data(d), "--ylag", "1", "--ulag", "1", "--degree", "2",
                           "--name", HOSTILE, "--order", "2"],
    "ofrf": lambda d: [_model(d, "[parameters]\nc = 0.5\n",
                              "D(y,2) + 0.2*D(y) + y + c*y**3 = u"),
                       "--param", "c", "--input", "0.01*cos(t)", "--omega", "1", "--order", "3"],
    "plot": lambda d: [_model(d), "--order", "2", "--out", str(d / "h2.png")],
    "threshold": lambda d: [_model(d)],
    "certificate": _certificate,
    "multisine": lambda d: ["--period", "64", "--sample-time", "0.1", "--realisations", "2",
                            "--periods", "2", "--out", str(d / "x\x1b[2Kms.csv")],
    "estimate": lambda d: [_periodic_data(d), "--period", "64", "--model", _model(d)],
    "frc": lambda d: [_model(d), "--amplitude", "0.01", "--omega", "0.9:1.1",
                      "--max-points", "10"],
}

#: Commands whose cheapest run is still long: ``make test-slow``.
SLOW = {"report", "validate"}


def _no_constant(token: str) -> None:
    raise ValueError(f"non-standard JSON token {token}")


def test_every_command_has_an_invocation() -> None:
    assert set(_commands()) == set(INVOCATIONS), "add the new command to INVOCATIONS"


@pytest.mark.parametrize("command", [
    pytest.param(c, marks=pytest.mark.slow) if c in SLOW else c for c in _commands()])
@pytest.mark.parametrize("as_json", [False, True], ids=["text", "json"])
def test_every_command_escapes_user_text_and_prints_strict_json(
        command: str, as_json: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    if command == "bench":
        _fake_bench(monkeypatch)
    argv = [command, *INVOCATIONS[command](tmp_path), *(["--json"] if as_json else [])]
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's usage errors
        code = exc.code
    out, err = capsys.readouterr()
    assert code in (0, 1, 2), (code, err)
    for stream in (out, err):
        assert "\x1b" not in stream and "\r" not in stream
        assert "\nverdict: stable (forged)" not in stream  # never starts a line
    assert code != 2, err  # every invocation is valid input
    if as_json and (code == 0 or out):
        data = json.loads(out, parse_constant=_no_constant)
        assert isinstance(data, dict)
    if code == 2:
        assert err.count("\n") == 1 and "Traceback" not in err


def test_bench_without_out_prints_and_writes_nothing(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    """``--out`` is optional (the documented default writes nothing)."""
    _fake_bench(monkeypatch)
    monkeypatch.chdir(tmp_path)
    assert main(["bench", "--quick", "--json"]) == 0
    data = json.loads(capsys.readouterr().out, parse_constant=_no_constant)
    assert data["report"] is None and data["sections"][0]["rows"][0][1] == "inf"
    assert list(tmp_path.iterdir()) == []


def test_json_convention_infinity_is_a_string_and_nan_is_null() -> None:
    value = {"a": float("inf"), "b": -float("inf"), "c": float("nan"), "d": (1.5, 2j)}
    assert json_ready(value) == {"a": "inf", "b": "-inf", "c": None,
                                 "d": [1.5, {"re": 0.0, "im": 2.0}]}
    assert json.loads(dumps(value), parse_constant=_no_constant)["a"] == "inf"


@pytest.mark.parametrize("as_json", [False, True], ids=["text", "json"])
def test_predict_beyond_the_radius_refuses_in_one_line_and_strict_json(
        as_json: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """An amplitude of 50 is far beyond r* of a cubic oscillator (about 0.05): refused,
    exit 1, one line on stderr; ``--json`` prints the refusal as strict JSON."""
    argv = ["predict", _model(tmp_path), "--input", "50*cos(t)", "--order", "3"]
    assert main([*argv, *(["--json"] if as_json else [])]) == 1
    out, err = capsys.readouterr()
    (line,) = err.splitlines()
    assert line.startswith("gfrf: refused:") and "--force" in line and "Traceback" not in err
    if not as_json:
        assert out == ""
        return
    data = json.loads(out, parse_constant=_no_constant)
    assert data["amplitude"] == 50.0 and 0 < data["radius"] < 50.0
    assert data["refused"] in line and data["model"] == HOSTILE


def test_a_computation_without_answer_still_prints_strict_json(
        tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Exit 1 from a computation that found no answer: one line on stderr and, with
    ``--json``, a JSON object (a JSON reader never gets an empty stdout)."""
    import gfrf.cli.core
    from gfrf.errors import ConvergenceError

    def no_answer(args: argparse.Namespace) -> int:
        raise ConvergenceError(f"no periodic solution near {HOSTILE}")

    monkeypatch.setattr(gfrf.cli.core, "_show", no_answer)
    assert main(["show", _model(tmp_path), "--json"]) == 1
    out, err = capsys.readouterr()
    (line,) = err.splitlines()
    assert line.startswith("gfrf: error: no periodic solution") and "\x1b" not in err
    data = json.loads(out, parse_constant=_no_constant)
    assert data == {"command": "show", "error": f"no periodic solution near {HOSTILE}"}
