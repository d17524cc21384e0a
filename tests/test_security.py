"""Hostile inputs: no user text is ever run as code, and every input is cheap to refuse.

Each case puts a payload into one text field (model equation, NARX equation,
``physical_equation``, a ``[parameters]`` value, ``sample_time``, the controller's
``num``/``den``/``equation``, a signal or parameter name, the ``--input`` of
``simulate``/``predict``, a sweep template) and asserts: a ``ModelError`` /
``ArgumentError`` (exit 2 with one ``gfrf: error:`` line from the CLI) whose message
names the problem, within a bounded time, and that the sentinel file the payload
would create does not exist.  A hypothesis fuzz of :mod:`gfrf.model.expr` closes the file.
"""

from __future__ import annotations

import ast
import time
from collections.abc import Callable
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gfrf.cli import main
from gfrf.errors import GfrfError, ModelError
from gfrf.model.equation import parse_model
from gfrf.model.expr import parse_expression
from gfrf.model.modelfile import load_model, model_from_dict
from gfrf.model.signals import parse_input
from gfrf.model.template import model_template

PACKAGE = Path(__file__).resolve().parent.parent / "gfrf"
#: Seconds any refusal may take (at most 5 s on a 2-core machine).
BOUND = 5.0
BASE = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


@pytest.fixture
def sentinel(tmp_path: Path) -> Path:
    return tmp_path / "pwned"


def _code_payloads(s: Path) -> list[tuple[str, str]]:
    """(payload, fragment of the refusal) for payloads that would run code."""
    return [
        (f"__import__('os').system('touch {s}')", "unexpected character"),
        (f"open('{s}', 'w')", "unexpected character"),
        ("exec('import os')", "unexpected character"),
        ("eval(1)", "unknown function 'eval'"),
        ("breakpoint()", "unknown function 'breakpoint'"),
        ("print(1)", "unknown function 'print'"),
        ("globals()", "unknown function 'globals'"),
        ("y.__class__", "unexpected character '.'"),
        ("().__class__.__bases__", "unexpected character '.'"),
        ("lambda: 0", "unexpected character ':'"),
        ("[x for x in (1,)]", "unknown function 'in'"),
        ("getattr(y, 1)", "unknown function 'getattr'"),
        ("Symbol(1)", "unknown function 'Symbol'"),
        ("sympify(1)", "unknown function 'sympify'"),
        ("y if y else u", "unknown symbol(s)"),
        ("y; u", "unexpected character ';'"),
        ("y @ u", "unexpected character '@'"),
        ("sin(y, x=1)", "'='"),
        ("{1: 2}", "unexpected character '{'"),
    ]


RESOURCE_PAYLOADS = [
    ("factorial(10**9)", "unknown function 'factorial'"),
    ("y**(10**9)", "exponent after '**' must be an integer literal"),
    ("9**9**9", "a tower a**b**c"),
    ("y**1000000000", "exceeds the limit MAX_EXPONENT"),
    ("9" * 1_000_000, "MAX_TEXT_LENGTH"),
    ("9" * 60, "MAX_NUMBER_LENGTH"),
    ("(" * 1000 + "y" + ")" * 1000, "MAX_NESTING"),
    ("+".join(["y"] * 6000), "MAX_TERMS"),
    ("(y + u + D(y) + D(u) + D(y,2) + D(u,2) + D(y,3))**15", "MAX_MONOMIALS"),
    ("*".join(["y"] * 40), "exceeds the limit MAX_DEGREE"),
    ("1e999*y", "not finite in double precision"),
    ("((((((7**15)**15)**15)**15)**15)**15)*y", "MAX_NUMBER_BITS"),
    ("exp(exp(exp(1000)))*y", "not finite"),
    ("D(y, 1000000000)", "exceeds the limit"),
    ("y^3", "write y**3"),
    ("1j*y", "malformed number"),
    ("nan*y", "is not finite"),
    ("a" * 100 + "*y", "MAX_NAME_LENGTH"),
]


def _timed(call: Callable[[], object]) -> BaseException:
    start = time.perf_counter()
    with pytest.raises(GfrfError) as info:
        call()
    assert time.perf_counter() - start < BOUND
    return info.value


def _fields(payload: str) -> dict[str, Callable[[], object]]:
    """The same payload in every field that takes text."""
    return {
        "equation": lambda: parse_model(f"D(y,2) + y + {payload} = u"),
        "narx": lambda: parse_model(f"y[k] = 0.5*y[k-1] + {payload} + u[k-1]", sample_time=0.1),
        "physical": lambda: model_from_dict({"equation": BASE, "truncation": 3,
                                             "physical_equation": f"D(y,2) + {payload} = u"}),
        "parameter": lambda: model_from_dict({"equation": "D(y,2) + a*y = u",
                                              "parameters": {"a": payload}}),
        "sample_time": lambda: model_from_dict({"equation": "y[k] = 0.5*y[k-1] + u[k-1]",
                                                "sample_time": payload}),
        "controller num": lambda: model_from_dict({"equation": BASE,
                                                   "controller": {"num": [payload]}}),
        "controller den": lambda: model_from_dict({"equation": BASE,
                                                   "controller": {"num": [1],
                                                                  "den": [1, payload]}}),
        "controller equation": lambda: model_from_dict(
            {"equation": BASE, "controller": {"equation": f"u = {payload}"}}),
        "input": lambda: parse_input(f"0.1*sin(t) + {payload}"),
        "template": lambda: model_template({"equation": "D(y,2) + c*D(y) + b*y = u",
                                            "parameters": {"c": 0.2, "b": payload}}, ["c"]),
    }


FIELDS = list(_fields("y"))


@pytest.mark.parametrize("field", FIELDS)
@pytest.mark.parametrize("index", range(len(_code_payloads(Path("s")))))
def test_code_payloads_are_refused_in_every_field(field: str, index: int,
                                                  sentinel: Path) -> None:
    payload, fragment = _code_payloads(sentinel)[index]
    error = _timed(_fields(payload)[field])
    assert not sentinel.exists()
    message = str(error)
    assert fragment in message or "unknown symbol(s)" in message, message


@pytest.mark.parametrize(("payload", "fragment"), RESOURCE_PAYLOADS,
                         ids=[p[:30] for p, _ in RESOURCE_PAYLOADS])
def test_resource_payloads_are_refused_quickly(payload: str, fragment: str) -> None:
    error = _timed(lambda: parse_model(f"D(y,2) + y + {payload} = u"))
    assert fragment in str(error)


@pytest.mark.parametrize(("payload", "fragment"), [
    ("sin(10**300*t)", "MAX_EXPONENT"),
    ("0.1*I*t", "unknown symbol(s) I"),
    ("sqrt(-1)*t", "not a real number"),
    ("t**(10**9)", "integer literal"),
    ("factorial(10**9)*t", "unknown function 'factorial'"),
])
def test_input_payloads(payload: str, fragment: str) -> None:
    assert fragment in str(_timed(lambda: parse_input(payload)))


@pytest.mark.parametrize("name", ["__class__", "lambda", "a.b", "x" * 100, "_y__0"])
def test_names_are_plain_identifiers(name: str) -> None:
    _timed(lambda: parse_model("D(y) + y = u", parameters={name: 1.0}))
    _timed(lambda: parse_model("D(v) + v = u", output=name))


def _run_cli(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    start = time.perf_counter()
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    assert time.perf_counter() - start < BOUND
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("gfrf: error:"), err
    return err[0]


@pytest.mark.parametrize("key", ["equation", "physical_equation", "parameters",
                                 "controller", "sample_time"])
def test_cli_model_file_payloads_exit_2(key: str, tmp_path: Path, sentinel: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    payload = f"__import__('os').system('touch {sentinel}')".replace("'", "\\'")
    lines = {"equation": f'equation = "D(y,2) + y + {payload} = u"',
             "physical_equation": f'equation = "{BASE}"\ntruncation = 3\n'
                                  f'physical_equation = "D(y,2) + {payload} = u"',
             "parameters": f'equation = "D(y,2) + a*y = u"\nparameters = {{ a = "{payload}" }}',
             "controller": f'equation = "{BASE}"\n[controller]\nnum = ["{payload}"]',
             "sample_time": f'equation = "y[k] = 0.5*y[k-1] + u[k-1]"\n'
                            f'sample_time = "{payload}"'}
    path = tmp_path / "hostile.toml"
    path.write_text(lines[key] + "\n")
    _run_cli(["verdict", str(path)], capsys)
    assert not sentinel.exists()


@pytest.mark.parametrize("command", ["simulate", "predict"])
def test_cli_input_payload_exit_2(command: str, sentinel: Path,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    argv = [command, "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u", "--input",
            f"__import__('os').system('touch {sentinel}')"]
    if command == "simulate":
        argv += ["--t-end", "1"]
    _run_cli(argv, capsys)
    assert not sentinel.exists()


def test_cli_inline_equation_payload_exit_2(sentinel: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    line = _run_cli(["verdict", f"D(y,2) + y + __import__('os').system('touch {sentinel}') = u"],
                    capsys)
    assert "unexpected character" in line
    assert not sentinel.exists()


def test_power_caret_gets_a_hint(capsys: pytest.CaptureFixture[str]) -> None:
    assert "write y**3" in _run_cli(["verdict", "D(y,2) + y + y^3 = u"], capsys)


def test_one_megabyte_file_is_refused_fast(tmp_path: Path) -> None:
    path = tmp_path / "big.toml"
    path.write_text('equation = "' + "+".join(["y"] * 500_000) + ' = u"\n')
    assert "MAX_FILE_BYTES" in str(_timed(lambda: load_model(path)))


def test_deep_but_legitimate_models_parse() -> None:
    terms = " + ".join(f"{0.001 * (i + 1)!r}*y**{1 + i % 3}*D(y)**{i % 2}" for i in range(500))
    start = time.perf_counter()
    model = parse_model(f"D(y,2) + y + {terms} = u")
    assert time.perf_counter() - start < BOUND
    # y, y**2, y**3 with and without D(y): 6 distinct monomials; sums checked exactly.
    coefficients = {(t.y_orders, t.u_orders): t.coefficient for t in model.terms}
    expected_y3 = sum(0.001 * (i + 1) for i in range(500) if i % 3 == 2 and i % 2 == 0)
    assert coefficients[((0, 0, 0), ())] == pytest.approx(expected_y3, rel=1e-12)
    # 99,000 unary minus signs are read iteratively (no recursion): an even count is +y.
    assert parse_model("-" * 99_000 + "y + D(y) = u").linear_output == {0: 1.0, 1: 1.0}
    narx = " + ".join(f"0.0001*y[k-{1 + i % 20}]*u[k-{1 + i % 7}]" for i in range(500))
    assert parse_model(f"y[k] = 0.5*y[k-1] + {narx} + u[k-1]", sample_time=0.1).degree == 2


def test_no_eval_of_user_text_in_the_package() -> None:
    """sympify/parse_expr are used nowhere; eval/exec only run code gfrf generated itself."""
    generated = {("_cache.py", "exec"), ("integrate.py", "exec"), ("budget.py", "exec"),
                 ("template.py", "eval"), ("native.py", "exec"),
                 ("numeric.py", "exec")}  # the kernel code gfrf wrote
    forbidden = {"sympify", "parse_expr", "S", "eval", "exec", "__import__"}
    found = set()
    for path in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Attribute) and node.attr in forbidden - {"S"}:
                found.add((path.name, node.attr))
            elif isinstance(node, ast.Name) and node.id in forbidden - {"S"}:
                found.add((path.name, node.id))
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                    and node.func.attr == "S":
                found.add((path.name, "S"))  # sp.S("text") is sympify
            elif isinstance(node, ast.ImportFrom) and "parsing" in (node.module or ""):
                found.add((path.name, node.module))
    assert found <= generated, found - generated


# -- fuzzing the expression language --------------------------------------------------

_LEAVES = st.sampled_from(["y", "u", "1", "2.5", "1e300", "0", "rho", "pi", "t", "k", "x",
                           "D(y)", "D(u,2)", "y[k-1]", "'s'", "None", "__import__",
                           "9" * 45, "1j", "nan", "()", "[]"])
_UNARY = st.sampled_from(["-", "+", "~", "not ", "*", "**", "lambda: "])
_BINARY = st.sampled_from(["+", "-", "*", "/", "**", "//", "%", "@", "^", ".", ",", "==",
                           " if ", " for ", "[", "("])
_CALLS = st.sampled_from(["sin", "exp", "sqrt", "D", "eval", "open", "factorial", "print", ""])


def _extend(children: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    return st.one_of(
        st.tuples(_UNARY, children).map("".join),
        st.tuples(children, _BINARY, children).map("".join),
        st.tuples(_CALLS, children).map(lambda p: f"{p[0]}({p[1]})"),
        st.tuples(children, st.integers(0, 40)).map(lambda p: f"({p[0]})**{p[1]}"),
    )


random_trees = st.recursive(_LEAVES, _extend, max_leaves=30)
SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


def _only_model_error(text: str, **kwargs: object) -> None:
    start = time.perf_counter()
    try:
        parse_model(text, **kwargs)
    except ModelError:
        pass
    assert time.perf_counter() - start < BOUND


@SETTINGS
@given(random_trees)
def test_fuzz_random_trees_continuous(tree: str) -> None:
    _only_model_error(f"D(y,2) + y + {tree} = u", parameters={"rho": 0.8}, truncation=3)


@SETTINGS
@given(random_trees)
def test_fuzz_random_trees_discrete(tree: str) -> None:
    _only_model_error(f"y[k] = 0.5*y[k-1] + {tree} + u[k-1]", sample_time=0.1)


@SETTINGS
@given(st.text(max_size=200))
def test_fuzz_random_strings(text: str) -> None:
    start = time.perf_counter()
    try:
        parse_expression(text, names={"y": parse_model("D(y)+y=u").atom("y", 0)})
    except ModelError:
        pass
    assert time.perf_counter() - start < BOUND


# -- hostile inputs to the parser --------------------------------------------------------

def test_sweep_template_never_puts_user_names_in_code(sentinel: Path) -> None:
    evil = f"x=__import__('os').system('touch {sentinel}')"
    data = {"equation": BASE, "controller": {"num": [1], "den": [1, 1],
                                             "parameters": {evil: 1.0}}}
    _timed(lambda: model_template(data, [evil]))
    assert not sentinel.exists()
    # Names that are keywords or modules of the generated code are refused or harmless.
    _timed(lambda: model_from_dict({"equation": BASE, "controller": {
        "num": ["lambda"], "den": [1, 1], "parameters": {"lambda": 1.0}}}))
    template = model_template({"equation": "D(y,2) + math*D(y) + y = u",
                               "parameters": {"math": 0.2}}, ["math"])
    assert "math" not in template.source.split(":")[0]
    assert template.instantiate({"math": 0.4}).plant.linear_output[1] == 0.4


def test_sweep_template_of_parameter_chains_stays_cheap() -> None:
    data = {"equation": "D(y,2) + 0.2*D(y) + y + p3*y**3 = u",
            "parameters": {"a": 1.0, "b": 0.0, "p1": "(a+b)**15", "p2": "p1**15",
                           "p3": "p2**15"}}
    from gfrf.model.template import TemplateUnsupported

    start = time.perf_counter()
    with pytest.raises(TemplateUnsupported, match="MAX_DEGREE"):
        model_template(data, ["a", "b"])
    assert time.perf_counter() - start < BOUND


@pytest.mark.parametrize(("payload", "fragment"), [
    ("((y+u+D(y)+D(u)+D(y,2)+D(u,2)+D(y,3)+D(u,3))**-1)**-15", "MAX_MONOMIALS"),
    ("(y**-1)**-15*(y**-1)**-15*(u**-1)**-15", "MAX_DEGREE"),
    ("exp(log(y + u))", "log() of a signal"),
    ("tan(tan(tan(y)))", "MAX_FUNCTION_NESTING"),
    ("+".join(f"sin({i}*y)" for i in range(1, 41)), "MAX_FUNCTION_CALLS"),
    ("D(", "D( is not closed"),
    ("\u0663*y", "unexpected character"),
    ("D(y,\u0663)", "unexpected character"),
])
def test_laundered_sizes_are_refused(payload: str, fragment: str) -> None:
    error = _timed(lambda: parse_model(f"D(y,2) + y + {payload} = u", truncation=3))
    assert fragment in str(error)


def test_numeric_function_towers_are_evaluated_once() -> None:
    inner = "+".join(f"sin({k})" for k in range(1, 2000))
    start = time.process_time()  # CPU, not wall: a loaded machine must not fail it
    model = parse_model("D(y) + y + " + "sin(" * 30 + inner + ")" * 30 + "*y**3 = u")
    assert time.process_time() - start < BOUND
    assert model.degree == 3


def test_file_and_number_edge_cases_are_clean_errors(tmp_path: Path) -> None:
    deep = tmp_path / "deep.toml"
    deep.write_text(f'equation = "{BASE}"\npaper = {{ x = {"[" * 5000}{"]" * 5000} }}\n')
    assert "nested too deep" in str(_timed(lambda: load_model(deep)))
    big = tmp_path / "big.toml"
    big.write_text(f'equation = "D(y,2) + a*y = u"\n[parameters]\na = {10 ** 400}\n')
    assert "too large" in str(_timed(lambda: load_model(big)))
    assert "finite number" in str(_timed(lambda: parse_model("D(y)+a*y=u",
                                                             parameters={"a": 10 ** 400})))


def test_long_inline_equation_on_the_cli(capsys: pytest.CaptureFixture[str]) -> None:
    terms = "+".join(["0.001*y**3"] * 300)
    assert main(["norm", f"D(y,2) + 0.2*D(y) + y + {terms} = u", "--order", "1",
                 "--json"]) == 0
    assert '"upper"' in capsys.readouterr().out


def test_input_not_finite_at_start_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    line = _run_cli(["simulate", BASE, "--input", "1/t", "--t-end", "1"], capsys)
    assert "not finite at t = 0" in line


@pytest.mark.filterwarnings("ignore:the linearisation of the closed loop is unstable")
def test_closed_loop_with_an_output_named_r(capsys: pytest.CaptureFixture[str],
                                            tmp_path: Path) -> None:
    """The reference's internal symbols must not clash with a signal called r."""
    import json

    peaks = []
    for name in ("y", "r"):
        path = tmp_path / f"{name}.toml"
        path.write_text(f'equation = "D({name},2) + 0.2*D({name}) + {name} + '
                        f'0.5*{name}**3 = u"\noutput = "{name}"\n[controller]\n'
                        f'equation = "D(u) + u = 0.5*{name}"\n')
        assert main(["simulate", str(path), "--closed-loop", "--input", "0.3*sin(t)",
                     "--t-end", "20", "--json"]) == 0
        peaks.append(json.loads(capsys.readouterr().out)["peak_abs_y"])
    assert peaks[0] == pytest.approx(peaks[1], rel=1e-12)


def test_taylor_truncation_work_is_bounded_before_sympy_runs() -> None:
    atoms = "y+u+D(y)+D(u)+D(y,2)+D(u,2)+D(y,3)+D(u,3)"
    error = _timed(lambda: parse_model(f"D(y)+y+exp({atoms}) - 1 = u", truncation=7))
    assert "MAX_TRUNCATION_WORK" in str(error)  # 6435 monomials: minutes of sympy series
