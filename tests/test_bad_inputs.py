"""A catalogue of bad inputs: each must raise its documented error naming the problem.

Python API cases assert the exact exception type and a fragment of the message that
names the offending term, key or value.  CLI cases assert exit code 2 and a single
``gfrf: error: ...`` line on stderr (no traceback).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from gfrf.bounds.norms import kernel_norm
from gfrf.cli import main
from gfrf.errors import ArgumentError, ModelError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model, model_from_dict
from gfrf.stability.criteria import parameter_margin
from gfrf.stability.theorem1 import theorem1
from gfrf.stability.theorem2 import theorem2

MODELS = Path(__file__).resolve().parent.parent / "models"
PENDULUM = str(MODELS / "hanging_pendulum.toml")
CARTPOLE = str(MODELS / "cartpole.toml")
FIRST_ORDER = "D(y) + y = u"


def _parse(text: str, **kwargs: object) -> Callable[[], object]:
    return lambda: parse_model(text, **kwargs)


def _file(data: dict) -> Callable[[], object]:
    return lambda: model_from_dict(data)


PARSER_CASES = [
    ("empty", _parse("   "), "empty equation"),
    ("double equals", _parse("D(y,2) + y == u"), "not '=='"),
    ("two equals", _parse("y = u = 0"), "more than one '='"),
    ("empty side", _parse("D(y,2) + y = "), "side of the equation is empty"),
    ("unbalanced paren", _parse("D(y,2) + (y = u"), "cannot parse the equation"),
    ("sin without truncation", _parse("D(y,2) + sin(y) = u"), "'sin(y)' is not polynomial"),
    ("constant term", _parse("D(y,2) + y + 1 = u"), "constant term 1"),
    ("explicit time", _parse("D(y,2) + t*y = u"), "depends explicitly on time t"),
    ("unknown symbol", _parse("D(y,2) + y + a*y**3 = u"), "unknown symbol(s) a"),
    ("negative order", _parse("D(y,-1) + y = u"), "negative derivative order -1"),
    ("huge order", _parse("D(y,25) + y = u"), "order 25 exceeds the limit"),
    ("fractional order", _parse("D(y,1.5) + y = u"), "must be a non-negative integer"),
    ("D of a non-signal", _parse("D(z) + y = u"), "'D(z)': the first argument"),
    ("unknown function", _parse("D(y,2) + y + foo(y) = u"), "unknown function 'foo'"),
    ("no input", _parse("D(y,2) + D(y) + y = 0"), "has no input 'u'"),
    ("no output", _parse("D(u) + u = 0"), "has no output 'y'"),
    ("no linear output", _parse("D(y)**2 + y**3 = u"), "no linear term in the output"),
    ("division by zero", _parse("D(y,2) + y/0 = u"), "NaN or infinite coefficient"),
    ("identically zero", _parse("y - y = 0"), "identically zero"),
    ("zero truncation", _parse(FIRST_ORDER, truncation=0), "truncation must be a positive"),
    ("negative sample time", _parse("y[k] = u[k-1]", sample_time=-1.0),
     "sample_time must be a positive"),
    ("future lag", _parse("y[k] = 0.5*y[k+1] + u[k-1]", sample_time=0.1), "looks into the future"),
    ("unknown lagged signal", _parse("y[k] = 0.5*z[k-1] + u[k-1]", sample_time=0.1),
     "unknown signal 'z'"),
    ("D in a NARX model", _parse("y[k] = D(y) + u[k-1]", sample_time=0.1),
     "discrete models use y[k-n]"),
    ("NaN parameter", _parse(FIRST_ORDER, parameters={"a": float("nan")}),
     "parameter 'a' must be a finite number"),
    ("parameter named like the output", _parse(FIRST_ORDER, parameters={"y": 1.0}),
     "parameter name 'y' clashes"),
    ("output named like input", _parse(FIRST_ORDER, output="u"), "the same name 'u'"),
]

MODEL_FILE_CASES = [
    ("unknown key", _file({"equation": FIRST_ORDER, "bogus": 1}),
     "unknown model file key(s) 'bogus'"),
    ("missing equation", _file({"name": "x"}), "missing key 'equation'"),
    ("parametric kind", _file({"equation": FIRST_ORDER, "kind": "parametric"}),
     "parametrically excited"),
    ("unknown kind", _file({"equation": FIRST_ORDER, "kind": "pde"}), "kind must be"),
    ("zero controller den", _file({"equation": FIRST_ORDER,
                                    "controller": {"num": [1], "den": [0]}}),
     "controller.den is zero"),
    ("unknown controller symbol", _file({"equation": FIRST_ORDER,
                                          "controller": {"num": ["zz"], "den": [1]}}),
     "controller.num: 'zz' uses unknown symbol(s) zz"),
    ("bad feedback sign", _file({"equation": FIRST_ORDER,
                                 "controller": {"num": [1], "feedback": 2}}),
     "controller.feedback must be -1 or +1"),
    ("boolean parameter", _file({"equation": FIRST_ORDER, "parameters": {"a": True}}),
     "parameters.a: expected a number"),
    ("infinite parameter", _file({"equation": FIRST_ORDER, "parameters": {"a": "oo"}}),
     "parameters.a: 'oo' is not finite"),
    ("controller both forms", _file({"equation": FIRST_ORDER,
                                      "controller": {"num": [1], "equation": "u = y"}}),
     "either num/den"),
    ("missing file", lambda: load_model("/nonexistent/model.toml"), "does not exist"),
]

NUMERIC_CASES = [
    ("kernel order 0", lambda: kernel(parse_model(FIRST_ORDER), 0),
     "kernel order must be an integer between 1 and MAX_KERNEL_ORDER = 12, got 0"),
    ("kernel order 13", lambda: kernel(parse_model(FIRST_ORDER), 13),
     "kernel order must be an integer between 1 and MAX_KERNEL_ORDER = 12, got 13"),
    ("wrong number of frequencies", lambda: kernel(parse_model(FIRST_ORDER), 2)(1.0),
     "H2 takes 2 angular frequencies, got 1"),
    ("NaN frequency", lambda: kernel(parse_model(FIRST_ORDER), 1)(float("nan")),
     "must be finite"),
    ("negative amplitude", lambda: theorem1(parse_model(FIRST_ORDER), amplitude=-1.0),
     "amplitude must be a positive finite number"),
    ("zero order", lambda: theorem1(parse_model(FIRST_ORDER), order=0),
     "order must be an integer between 1 and MAX_KERNEL_ORDER"),
    ("norm order 0", lambda: kernel_norm(parse_model(FIRST_ORDER), 0),
     "order must be an integer between 1 and MAX_KERNEL_ORDER"),
    ("theorem 2 without controller",
     lambda: theorem2(model_from_dict({"equation": FIRST_ORDER})), "needs a controller"),
    ("margin of unknown parameter", lambda: parameter_margin(load_model(PENDULUM), "zz"),
     "'zz' is not a parameter"),
]


def _ids(cases: list) -> list[str]:
    return [c[0] for c in cases]


@pytest.mark.parametrize(("name", "call", "fragment"), PARSER_CASES + MODEL_FILE_CASES,
                         ids=_ids(PARSER_CASES + MODEL_FILE_CASES))
def test_model_errors(name: str, call: Callable[[], object], fragment: str) -> None:
    with pytest.raises(ModelError) as info:
        call()
    assert type(info.value) is ModelError
    assert fragment in str(info.value)


@pytest.mark.parametrize(("name", "call", "fragment"), NUMERIC_CASES, ids=_ids(NUMERIC_CASES))
def test_argument_errors(name: str, call: Callable[[], object], fragment: str) -> None:
    with pytest.raises(ArgumentError) as info:
        call()
    assert type(info.value) is ArgumentError
    assert fragment in str(info.value)


CLI_CASES = [
    ("missing file", ["verdict", "nonexistent.toml"], "does not exist"),
    ("unknown command", ["frobnicate"], "invalid choice: 'frobnicate'"),
    ("non-integer order", ["norm", PENDULUM, "--order", "x"], "invalid int value: 'x'"),
    ("order 0", ["verdict", PENDULUM, "--order", "0"],
     "--order must be an integer between 1 and MAX_KERNEL_ORDER = 12, got 0"),
    ("NaN amplitude", ["verdict", PENDULUM, "--amplitude", "nan"], "amplitude must be"),
    ("order beyond limit", ["norm", PENDULUM, "--order", "13"], "MAX_KERNEL_ORDER = 12, got 13"),
    ("unknown margin parameter", ["verdict", PENDULUM, "--margin", "zz"],
     "'zz' is not a parameter"),
    ("frequency count", ["kernel", PENDULUM, "--order", "2", "--at", "1"],
     "--at needs 2 angular frequencies"),
    ("infinite frequency", ["kernel", PENDULUM, "--order", "1", "--at", "inf"],
     "must be finite"),
    ("NARX without sample time", ["verdict", "y[k] = 0.5*y[k-1] + u[k-1]"],
     "needs --sample-time"),
    ("inline equation without input", ["verdict", "D(y) + y"], "has no input 'u'"),
    ("negative end time", ["simulate", PENDULUM, "--t-end", "-1"], "t_end must be a positive"),
    ("unknown input function", ["simulate", PENDULUM, "--input", "foo(t)", "--t-end", "1"],
     "unknown function 'foo'"),
    ("sweep unknown parameter", ["sweep", PENDULUM, "--param", "zz=0:1:3"],
     "unknown parameter 'zz'"),
    ("sweep bad range", ["sweep", PENDULUM, "--param", "rho=0:1"], "'rho=0:1'"),
    ("sweep N < 1", ["sweep", PENDULUM, "--param", "rho=0.1:1:0"], "N = 0"),
    ("sweep non-number", ["sweep", PENDULUM, "--param", "rho=a:1:3"], "'a'"),
    ("sweep repeated parameter", ["sweep", PENDULUM, "--param", "rho=1:2:2",
                                  "--param", "rho=1:3:2"], "'rho' is swept twice"),
    ("sweep bad output suffix", ["sweep", PENDULUM, "--param", "rho=1:2:2", "--out", "x.xlsx"],
     "'.xlsx'"),
    ("sweep controller gain of an open loop", ["sweep", PENDULUM, "--param", "a=1:2:2"],
     "unknown parameter 'a'"),
    ("sweep bad scheduler", ["sweep", CARTPOLE, "--param", "a=1:2:2", "--scheduler", "bogus"],
     "scheduler 'bogus'"),
    ("sweep zero chunk", ["sweep", PENDULUM, "--param", "rho=1:2:2", "--chunk", "0"],
     "chunk size must be a positive integer, got 0"),
    ("sweep negative horizon", ["sweep", PENDULUM, "--param", "rho=1:2:2", "--what", "bounded",
                                "--t-end", "-5"], "t_end must be a positive number"),
    ("sweep unknown quantity", ["sweep", PENDULUM, "--param", "rho=1:2:2", "--what", "gain"],
     "invalid choice: 'gain'"),
]


@pytest.mark.parametrize(("name", "argv", "fragment"), CLI_CASES, ids=_ids(CLI_CASES))
def test_cli_bad_input_exits_2_with_one_line(name: str, argv: list[str], fragment: str,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse usage errors exit through the parser
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("gfrf: error:")
    assert fragment in lines[0]
    assert "Traceback" not in err + out
