"""Adversarial cases of the default simulation path (generated fused rhs, stepped solvers).

References are independent: ``scipy.integrate.solve_ivp`` on hand-written right-hand
sides of the bundled models (same method and tolerances), closed forms, a hand-written
NARX recursion.  Security checks parse every generated source with :mod:`ast` and
allow only the validated state/input names, numbers and ``math`` functions.
"""

from __future__ import annotations

import ast
import builtins
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.cli import main
from gfrf.errors import ArgumentError
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.model.signals import parse_input
from gfrf.sim import integrate
from gfrf.sim.simulation import simulate
from gfrf.sim.system import build_system

MODELS = Path(__file__).resolve().parents[2] / "models"
METHODS = ("rk45", "dop853", "lsoda", "radau")
_MATH_OK = {"sin", "cos", "tan", "sinh", "cosh", "tanh", "atan", "exp", "log", "sqrt",
            "copysign", "pi", "e"}
#: Names the generator itself writes (function, arguments, fallback, exceptions).
_FIXED_NAMES = {"math", "abs", "_slow", "_t", "_z", "f", "ArithmeticError", "ValueError"}


def _quiet_simulate(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(*args, **kwargs)


# ----------------------------------------------------------------- (1) security

@pytest.fixture
def sources(monkeypatch):
    """Every source ``integrate`` compiles during the test (fused right-hand sides)."""
    seen: list[str] = []

    def spy(text, *args, **kwargs):
        if text.startswith("def f("):  # the fused function (the system's source is
            seen.append(text)  # sympy's print of the model, audited elsewhere)
        return builtins.compile(text, *args, **kwargs)

    monkeypatch.setattr(integrate, "compile", spy, raising=False)
    return seen


def _check_source(text: str, allowed: set[str]) -> None:
    tree = ast.parse(text)
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute):
            assert isinstance(node.value, ast.Name), text
            assert (node.value.id, node.attr in _MATH_OK) == ("math", True) \
                or (node.value.id, node.attr) == ("_z", "tolist"), text
        elif isinstance(node, ast.Name):
            assert node.id in allowed or node.id.startswith("_c") and node.id[2:].isdigit() \
                or node.id in _FIXED_NAMES, (node.id, text)
        elif isinstance(node, ast.Constant):
            assert isinstance(node.value, (int, float)) and not isinstance(node.value, bool), text
        elif isinstance(node, (ast.Import, ast.ImportFrom, ast.Lambda, ast.Subscript,
                               ast.Starred, ast.JoinedStr, ast.Global)):
            pytest.fail(f"unexpected {type(node).__name__} in generated source:\n{text}")


HOSTILE_INPUTS = ["__import__('os').system('true')", "t.__class__", "os.system", "exec(t)",
                  "t; import os", "sin(t)\nimport os", "ｔ", "1e400*t", "9" * 60 + "*t",
                  "(" * 40 + "t" + ")" * 40, "lambda: t", "[t]", "'t'", "getattr(t, 'x')",
                  "t.real", "sin(t)#", "__builtins__", "t if t else t", "e**t"]


@pytest.mark.parametrize("text", HOSTILE_INPUTS)
def test_hostile_input_text_is_refused(text):
    with pytest.raises(ArgumentError):
        parse_input(text)


@pytest.mark.parametrize("name", ["__import__", "os", "math", "_t", "_z", "f", "a__b", "lambda",
                                  "θ", "x.y", "exec"])
def test_hostile_signal_names(name, sources):
    """Names are refused or end up only as ``name__k`` identifiers of the source."""
    try:
        model = parse_model(f"D({name},2) + D({name}) + {name} = u", output=name)
    except Exception as exc:
        assert type(exc).__name__ in {"ModelError", "ArgumentError"}
        return
    system = build_system(model)
    res = _quiet_simulate(system, "0.1*sin(t) + step(t - 0.3)", t_end=0.5, n_out=5)
    assert res.status == "ok"
    assert sources, "the fused right-hand side was not generated"
    for text in sources:
        _check_source(text, set(system.state_names) | set(system.input_names))


INPUTS = ["0.1*sin(1.2*t)", "0.3*step(t - 1)", "sign(t - 0.5)*abs(sin(t))", "sqrt(t)*exp(-t)",
          "log(1 + t)", "atan(t) + sinh(t)/cosh(t) + tanh(t)", "1e300*sin(t)*1e-300",
          "Heaviside(t - 0.25)", "pi*E*cos(t)", "1/(t + 1)"]


@pytest.mark.parametrize("model_file", ["duffing.toml", "hanging_pendulum.toml",
                                        "cartpole.toml"])
def test_generated_sources_hold_only_validated_tokens(model_file, sources):
    mf = load_model(MODELS / model_file)
    for closed in (False, True) if mf.controller is not None else (False,):
        system = build_system(mf, closed_loop=closed)
        allowed = set(system.state_names) | set(system.input_names)
        for text in INPUTS:
            try:
                _quiet_simulate(system, text, t_end=0.2, n_out=3, rtol=1e-4)
            except ArgumentError as err:  # the improper loop reads r', r'': no jump, no sqrt(t)
                assert closed and "u = C(r - y) with an improper controller" in str(err)
    assert sources
    for text in sources:
        _check_source(text, allowed | {"theta__0", "theta__1", "y__0", "y__1", "u__0",
                                       "_r__0", "_r__1", "_r__2"})


# ------------------------------------------------------- fused input == numpy input

@pytest.mark.parametrize("text", INPUTS + ["sqrt(t - 1)", "log(t - 1)", "1/(t - 1)"])
def test_fused_input_agrees_with_numpy_input(text):
    """The math-printed input gives numpy's value, or raises (then the numpy path runs)."""
    u = parse_input(text, max_derivative=1)
    for k in range(2):
        code = integrate._input_code(u.expr, k)
        if code is None:
            continue
        for t in (0.0, 0.25, 0.5, 1.0, 1.75, 3.0):
            with np.errstate(all="ignore"):
                ref = float(u.derivative(k)(t))
            try:
                got = eval(code, {"math": math, "_t": t})
            except (ArithmeticError, ValueError):
                continue
            assert isinstance(got, (int, float))
            assert got == pytest.approx(ref, rel=1e-14, abs=1e-300), (text, k, t)


# -------------------------------------------- (1b) complex powers, domain, NaN hangs

def _write(tmp_path, physical: str) -> Path:
    path = tmp_path / "m.toml"
    path.write_text(f'name = "generated"\noutput = "y"\nequation = "D(y,2) + D(y) + y = u"\n'
                    f'physical_equation = "{physical}"\n')
    return path


@pytest.mark.parametrize("physical", ["D(y,2) + D(y) + sqrt(sqrt(1 + y)) - 1 = u",
                                      "D(y,2) + D(y) + sqrt(1 + y)**3 - 1 = u"])
@pytest.mark.parametrize("method", METHODS)
def test_fractional_power_outside_domain_stops_not_crashes(tmp_path, physical, method):
    """(1+y)**(1/4) at y < -1: Python floats give a complex (was: TypeError traceback);
    a non-finite f(0, z0) made scipy retry a NaN step forever (was: hang)."""
    mf = load_model(_write(tmp_path, physical))
    assert build_system(mf).rhs_body == ()  # left to the numpy-scalar rhs
    res = _quiet_simulate(mf, t_end=1.0, initial=[-1.5], method=method)
    assert res.status == "blowup" and res.blowup_time == 0.0 and res.t.size == 0
    # driven out of the domain during the run: stops, never a NaN sample
    res = _quiet_simulate(mf, "-20*step(t)", t_end=2.0, initial=[-0.5], method=method,
                          rtol=1e-6, atol=1e-9)
    assert res.status in {"blowup", "failed"}
    assert np.all(np.isfinite(res.y)) and np.all(np.isfinite(res.u))
    assert np.all(1 + res.y >= -1e-6)


def test_domain_errors_in_fused_rhs_fall_back(tmp_path):
    """math raising (sqrt of a negative, 1/0) sends the evaluation to the numpy path; a
    model with 1/(1+y) matches solve_ivp."""
    mf = load_model(_write(tmp_path, "D(y,2) + D(y) + 1 - 1/(1 + y) = u"))
    system = build_system(mf)
    fused = integrate._fused_rhs(system, parse_input("sqrt(t - 1)"), lambda t, z: "slow")
    assert fused is not None and fused(0.5, np.array([0.0, 0.0])) == "slow"  # ValueError
    assert fused(0.5, np.array([-1.0, 0.0])) == "slow"  # ZeroDivisionError
    assert fused(2.0, np.array([0.0, 0.0])) == pytest.approx([0.0, 1.0], abs=1e-15)
    res = _quiet_simulate(mf, "0.5*sin(t)", t_end=3.0, initial=[0.2], rtol=1e-9,
                          atol=1e-12)
    assert res.status == "ok"

    def f(t, z):
        return [z[1], 0.5 * np.sin(t) - z[1] - 1 + 1 / (1 + z[0])]

    ref = solve_ivp(f, (0, 3), [0.2, 0], method="DOP853", rtol=1e-9, atol=1e-12,
                    t_eval=res.t)
    assert np.max(np.abs(res.y - ref.y[0])) < 1e-9


@pytest.mark.parametrize("method", METHODS)
def test_initial_state_above_blowup_is_a_blowup_at_zero(method):
    """|y(0)| >= blowup: was reported as a blow-up at t = ln 2 (where y = 2e6 e^-t came
    back below 1e6)."""
    res = _quiet_simulate(parse_model("D(y) + y = u"), t_end=2.0, initial=[2e6],
                          method=method)
    assert res.status == "blowup" and res.blowup_time == 0.0


# ----------------------------------------------- (2) correctness vs plain solve_ivp

def _pendulum(k_damp, k_stiff, gain, u):
    return lambda t, z: [z[1], gain * u(t) - k_damp * z[1] - k_stiff * np.sin(z[0])]


def _step(t):
    return 0.3 if t >= 1.3 else 0.0


def _cartpole_loop(t, z):  # eqs (8)-(9), u = C(r - th) = a (r - th)'' + b (r - th)' + c (r - th),
    # r = 0.01*step(t): r' = r'' = 0 after the start
    big_m, m, length, g = 0.145, 0.03, 0.125, 9.8
    a, b, c = 15.6, 379.3, 0.1331
    th, dth = z
    r = 0.01 if t >= 0 else 0.0
    coeff = (big_m + m) * 4 / 3 - m * np.cos(th) ** 2 - a * np.cos(th) / length
    rest = (-(big_m + m) * g / length * np.sin(th) + m * dth ** 2 * np.sin(th) * np.cos(th)
            + np.cos(th) * (c * r - b * dth - c * th) / length)
    return [dth, -rest / coeff]


CASES = {  # model file, closed loop, input text, hand-written rhs, initial state
    "duffing": ("duffing.toml", False, "0.3*step(t - 1.3)",
                lambda t, z: [z[1], _step(t) - 0.2 * z[1] - z[0] - 0.5 * z[0] ** 3], [0.5, 0]),
    "pendulum": ("hanging_pendulum.toml", False, "0.4*sin(1.1*t)",
                 _pendulum(0.05, 2.45, 1.0, lambda t: 0.4 * np.sin(1.1 * t)), [1.0, 0]),
    "pendulum_damped": ("hanging_pendulum_damped.toml", False, "sign(t - 2)",
                        _pendulum(0.5, 2.45, 1.0, lambda t: float(np.sign(t - 2))), [0, 1]),
    "pendulum_eq2": ("hanging_pendulum_eq2.toml", False, "2*cos(t)",
                     _pendulum(0.05, 2.45, 1 / 16, lambda t: 2 * np.cos(t)), [0.3, 0]),
    "cartpole_loop": ("cartpole.toml", True, "0.01*step(t)", _cartpole_loop, [0.05, 0]),
}


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("rtol", [1e-3, 1e-9])
def test_bundled_models_match_solve_ivp(case, method, rtol):
    file, closed, text, f, z0 = CASES[case]
    atol = rtol * 1e-3
    t_end = 4.0
    t_eval = np.sort(np.r_[0.0, np.random.default_rng(7).uniform(0, t_end, 37), t_end])
    res = _quiet_simulate(load_model(MODELS / file), text, t_end=t_end, closed_loop=closed,
                          initial=z0, method=method, rtol=rtol, atol=atol, t_eval=t_eval)
    ref = solve_ivp(f, (0, t_end), z0, method=integrate.SCIPY_METHODS[method], rtol=rtol,
                    atol=atol, t_eval=t_eval)
    assert res.status == "ok" and ref.success
    assert np.all(np.isfinite(res.y))
    scale = max(1.0, float(np.max(np.abs(ref.y[0]))))
    # both integrate the same ODE to rtol: they agree to a few times the tolerance
    assert np.max(np.abs(res.y - ref.y[0])) <= 50 * rtol * scale, case


@pytest.mark.parametrize("method", ["auto", "rk45", "dop853"])
def test_t_eval_edge_cases(method):
    model = load_model(MODELS / "duffing.toml")
    f = CASES["duffing"][3]
    for t_end, t_eval in [(1e-9, None), (1e-9, [1e-9]), (3.0, [0.0]), (3.0, [3.0]),
                          (3.0, [1.2999999, 1.3, 1.3000001]), (3.0, [0.0, 3.0])]:
        res = _quiet_simulate(model, "0.3*step(t - 1.3)", t_end=t_end, t_eval=t_eval,
                              method=method, rtol=1e-10, atol=1e-13, initial=[0.5])
        expected = np.linspace(0, t_end, 2001) if t_eval is None else np.asarray(t_eval)
        assert res.status == "ok" and np.array_equal(res.t, expected)
        ref = solve_ivp(f, (0, t_end), [0.5, 0], method="DOP853", rtol=1e-12, atol=1e-14,
                        t_eval=expected)
        assert np.max(np.abs(res.y - ref.y[0])) < 1e-8


@pytest.mark.parametrize("method", METHODS)
def test_blowup_time_closed_form(method):
    """y' = y^2, y(0) = 1: y = 1/(1 - t) reaches 1e6 at t = 1 - 1e-6."""
    res = _quiet_simulate(parse_model("D(y) - y**2 = u"), t_end=2.0, initial=[1.0],
                          method=method, rtol=1e-10, atol=1e-12)
    assert res.status == "blowup"
    assert res.blowup_time == pytest.approx(1 - 1e-6, abs=1e-8)
    assert np.all(np.isfinite(res.y)) and res.t[-1] <= res.blowup_time
    assert np.all(np.abs(res.y) < 1e6)


@pytest.mark.parametrize("method", METHODS)
def test_budget_stops_with_finite_samples(method):
    res = _quiet_simulate(load_model(MODELS / "duffing.toml"), "0.4*sin(t)", t_end=100.0,
                          method=method, max_evaluations=200)
    assert res.status == "failed" and "max_evaluations = 200" in res.message
    step_cost = {"rk45": 6, "dop853": 12, "lsoda": 2, "radau": 20}[method]
    assert 200 <= res.nfev <= 200 + step_cost
    assert 0 < res.t[-1] < 100.0 and np.all(np.isfinite(res.y))
    d = json.dumps(res.to_dict(), allow_nan=False)  # no NaN printed
    assert '"failed"' in d


def test_narx_matches_hand_recursion():
    mf = load_model(MODELS / "narx_example.toml")
    res = _quiet_simulate(mf, "sin(t)", t_end=5.0, initial=[0.3])
    k = np.arange(51)
    u = np.sin(0.1 * k)
    y = np.zeros(51)
    prev = 0.3
    for i in range(51):
        u1 = u[i - 1] if i >= 1 else 0.0
        u2 = u[i - 2] if i >= 2 else 0.0
        y[i] = 0.5 * prev - 0.2 * prev ** 2 * u2 + u1
        prev = y[i]
    assert np.allclose(res.t, 0.1 * k) and np.max(np.abs(res.y - y)) < 1e-12


# ----------------------------------------------------- (3) determinism, (4) CLI

def _run(capsys, argv):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("method", ["auto", "rk45", "dop853", "lsoda", "radau"])
def test_cli_methods_json_deterministic(capsys, method):
    argv = ["simulate", str(MODELS / "duffing.toml"), "--t-end", "2", "--input",
            "0.3*step(t - 1)", "--method", method, "--json"]
    runs = []
    for _ in range(2):
        code, out, _ = _run(capsys, argv)
        assert code == 0
        data = json.loads(out)
        assert data["status"] == "ok"
        assert data["method"] == ("dop853" if method == "auto" else method)
        for key in ("wall_time_s", "compile_time_s"):  # timings, not results
            data.pop(key)
        runs.append(json.dumps(data, sort_keys=True))
    assert runs[0] == runs[1]


def test_cli_text_output_is_byte_identical(capsys):
    argv = ["simulate", str(MODELS / "cartpole.toml"), "--closed-loop", "--t-end", "1",
            "--input", "0.01*step(t)"]
    first = _run(capsys, argv)
    assert first == _run(capsys, argv) and first[0] == 0


@pytest.mark.parametrize("extra", [["--method", "bogus"], ["--method", "RK45"],
                                   ["--rtol", "nan"], ["--rtol", "-1"], ["--atol", "0"],
                                   ["--max-evaluations", "0"], ["--t-end", "inf"],
                                   ["--input", "__import__('os')"], ["--input", "t.real"],
                                   ["--input", "csv:/nonexistent.csv"],
                                   ["--initial", "nan"],
                                   ["--input", "99999999999999999999999999999999999999**15*t"]])
def test_cli_bad_values_exit_2_one_line(capsys, extra):
    argv = ["simulate", str(MODELS / "duffing.toml"), "--t-end", "1", *extra]
    try:
        code, out, err = _run(capsys, argv)
    except SystemExit as exc:  # argparse
        code, err = exc.code, capsys.readouterr().err
    assert code == 2
    message = [line for line in err.splitlines() if line.startswith("gfrf")]
    assert len(message) == 1 and "Traceback" not in err


def test_cli_csv_input_matches_expression(capsys, tmp_path):
    """A CSV input (numpy path, no fused rhs) of a smooth signal agrees with its formula."""
    t = np.linspace(0, 3, 3001)
    path = tmp_path / "u.csv"
    np.savetxt(path, np.c_[t, 0.2 * np.sin(t)], delimiter=",", header="t,u", comments="")
    mf = load_model(MODELS / "duffing.toml")
    a = _quiet_simulate(mf, f"csv:{path}", t_end=3.0, n_out=31)
    b = _quiet_simulate(mf, "0.2*sin(t)", t_end=3.0, n_out=31)
    assert np.max(np.abs(a.y - b.y)) < 1e-8


def test_dense_values_fall_back_when_scipy_attributes_change():
    """An interpolant of the batched classes without the private attributes read (another
    scipy) is called per step instead of raising AttributeError."""
    from scipy.integrate import RK45

    solver = RK45(lambda t, y: [y[1], -y[0]], 0.0, np.array([1.0, 0.0]), 2.0, rtol=1e-8,
                 atol=1e-12)
    pieces, t_eval, i = [], np.linspace(0, 2, 41), 0
    while solver.status == "running":
        solver.step()
        j = int(np.searchsorted(t_eval, solver.t, side="right"))
        pieces.append((i, j, solver.dense_output()))
        i = j

    class RkDenseOutput:  # same name, public call only
        def __init__(self, inner):
            self._inner = inner

        def __call__(self, t):
            return self._inner(t)

    bare = [(i, j, RkDenseOutput(d)) for i, j, d in pieces]
    got = integrate._dense_values(bare, t_eval)
    assert np.max(np.abs(got - integrate._dense_values(pieces, t_eval))) < 1e-14
    assert np.max(np.abs(got[0] - np.cos(t_eval))) < 1e-7
