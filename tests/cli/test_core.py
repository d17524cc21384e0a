"""CLI contract of `gfrf show` and `gfrf kernel` (JSON keys, exit codes)."""

import json

import pytest
from conftest import MODELS, run

from gfrf.cli import main


def test_kernel_json_contract(capsys):
    code, out, _ = run(capsys, "kernel", str(MODELS / "duffing.toml"), "--order", "3",
                       "--at", "1,1,-1", "--json")
    data = json.loads(out)
    assert code == 0
    assert data["order"] == 3 and data["omega"] == [1.0, 1.0, -1.0]
    # Duffing D(y,2)+0.2D(y)+y+0.5y^3=u: H1(+-1) = -+5j, H3 = -0.5 H1(1)^2 H1(-1) H1(1) = 312.5
    assert data["re"] == pytest.approx(312.5, rel=1e-12)
    assert data["im"] == pytest.approx(0.0, abs=1e-9)


def test_kernel_of_inline_equation_and_narx(capsys):
    code, out, _ = run(capsys, "kernel", "D(y,2) + 3*D(y) + 2*y = u", "--order", "1",
                       "--at", "0", "--json")
    assert code == 0 and json.loads(out)["re"] == pytest.approx(0.5)
    code, out, _ = run(capsys, "kernel", "y[k] = 0.5*y[k-1] + u[k-1]", "--sample-time", "1",
                       "--order", "1", "--at", "0", "--json")
    assert code == 0 and json.loads(out)["re"] == pytest.approx(2.0)


def test_show_prints_kernels_and_json(capsys):
    code, out, _ = run(capsys, "show", str(MODELS / "hanging_pendulum.toml"), "--order", "3")
    assert code == 0 and "H2 = 0 (structurally zero)" in out and "H3 =" in out
    code, out, _ = run(capsys, "show", str(MODELS / "cartpole.toml"), "--order", "2",
                       "--latex", "--json")
    data = json.loads(out)
    assert [k["order"] for k in data["kernels"]] == [1, 2]
    assert "\\" in data["kernels"][0]["recursive"]


@pytest.mark.parametrize("argv, fragment", [
    (["kernel", "D(y,2) + exp(y) = u", "--order", "1", "--at", "1"], "not polynomial"),
    (["kernel", "D(y,2) + y = u", "--order", "2", "--at", "1"], "needs 2"),
    (["kernel", "D(y,2) + y = u", "--order", "1", "--at", "abc"], "comma-separated"),
    (["kernel", "D(y,2) + y = u", "--order", "0", "--at", "1"],
     "--order must be an integer between 1 and MAX_KERNEL_ORDER = 12, got 0"),
    (["kernel", "D(y,2) + y = u", "--order", "1", "--at", "inf"], "finite"),
    (["show", "missing.toml"], "does not exist"),
    (["show", "y[k] = 0.5*y[k-1] + u[k-1]"], "--sample-time"),
    (["kernel", "D(y,2) + y = u", "--order", "x", "--at", "1"], "invalid int"),
])
def test_bad_input_exit_code_2_and_one_line(capsys, argv, fragment):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse usage errors
        code = exc.code
    _, err = capsys.readouterr()
    assert code == 2
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err


# --- cheap start, --version, negative values, one-line warnings ------------------------------

HEAVY = ("control", "matplotlib", "sympy", "numba", "dask", "distributed", "scipy", "numpy")


def _modules_after(argv: list[str]) -> set[str]:
    """Top-level packages of HEAVY imported by ``gfrf ARGV`` in a fresh interpreter."""
    import subprocess
    import sys

    script = ("import sys\nfrom gfrf.cli import main\ntry:\n    main(sys.argv[1:])\n"
              "except SystemExit:\n    pass\n"
              f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r})))")
    done = subprocess.run([sys.executable, "-c", script, *argv], capture_output=True,
                          text=True, check=True, cwd=MODELS.parent)
    return set(json.loads(done.stdout.strip().splitlines()[-1].replace("'", '"')))


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["kernel", "--help"],
                                  ["kernel", "m.toml", "--order", "three", "--at", "1"],
                                  ["no-such-command"]])
def test_help_version_and_usage_errors_import_nothing_heavy(argv):
    assert _modules_after(argv) == set()


def test_norm_path_imports_no_python_control_numba_or_matplotlib():
    loaded = _modules_after(["norm", str(MODELS / "duffing.toml"), "--order", "3"])
    assert "sympy" in loaded  # the path did run
    assert not loaded & {"control", "numba", "matplotlib", "dask", "distributed"}


def test_version_is_the_installed_distribution_version(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as exit_:
        main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out == f"gfrf {version('gfrf')}\n"


def test_negative_frequencies_as_option_value(capsys):
    code, out, err = run(capsys, "kernel", str(MODELS / "duffing.toml"), "--order", "3",
                         "--at", "-1.5,1.5,1.5", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["omega"] == [-1.5, 1.5, 1.5]

    # Duffing y'' + 0.2 y' + y + 0.5 y^3 = u: H3(w) = -0.5 H1(w1+w2+w3) prod H1(wi)
    def h1(w):
        return 1 / (1 - w * w + 0.2j * w)

    expected = -0.5 * h1(1.5) * h1(-1.5) * h1(1.5) * h1(1.5)
    assert complex(data["re"], data["im"]) == pytest.approx(expected, rel=1e-12)


def test_negative_initial_condition_as_option_value(capsys):
    from scipy.integrate import solve_ivp

    code, out, err = run(capsys, "simulate", str(MODELS / "duffing.toml"), "--t-end", "2",
                         "--initial", "-0.26,0", "--json")
    assert code == 0, err
    data = json.loads(out)
    exact = solve_ivp(lambda t, z: [z[1], -0.2 * z[1] - z[0] - 0.5 * z[0] ** 3], (0, 2),
                      [-0.26, 0.0], rtol=1e-12, atol=1e-14)
    assert data["peak_abs_y"] == pytest.approx(0.26, rel=1e-12)
    assert data["y_final"] == pytest.approx(exact.y[0, -1], rel=1e-6)


def test_warnings_are_one_clean_line():
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", "import sys; from gfrf.cli import main; "
                           "sys.exit(main(sys.argv[1:]))", "simulate", "D(y,2) - y + y**3 = u",
                           "--t-end", "1"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0
    lines = done.stderr.splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("gfrf: warning: the linearisation of the system is unstable")
    assert "UserWarning" not in done.stderr and ".py" not in done.stderr


def test_warnings_still_reach_a_recorder(capsys):
    with pytest.warns(UserWarning, match="linearisation"):
        code, _, err = run(capsys, "simulate", "D(y,2) - y + y**3 = u", "--t-end", "1")
    assert code == 0 and err == ""


def test_cli_method_list_matches_the_simulator():
    from gfrf.cli.simulation import METHODS
    from gfrf.sim.simulation import METHODS as SIMULATOR_METHODS

    assert METHODS == SIMULATOR_METHODS
