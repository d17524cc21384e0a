"""CLI contract of `gfrf show` and `gfrf kernel` (JSON keys, exit codes)."""

import json
from pathlib import Path

import pytest

from gfrf.cli import main

MODELS = Path(__file__).resolve().parent.parent / "models"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


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
    (["kernel", "D(y,2) + y = u", "--order", "0", "--at", "1"], "positive integer"),
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
