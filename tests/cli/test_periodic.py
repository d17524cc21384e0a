"""CLI contract of ``gfrf transition`` and ``gfrf periodic``."""

import json

import pytest

from gfrf.cli import main
from gfrf.cli.periodic import METHODS as CLI_METHODS
from gfrf.periodic.compare import METHODS
from gfrf.periodic.floquet import mathieu_transition


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_methods_listed_once():
    assert CLI_METHODS == METHODS


def test_transition_json_delta(capsys):
    out = _json(capsys, ["transition", "--eps", "0.1", "--amplitude", "1e-4", "--branch", "0",
                         "--method", "exact", "--json"])
    assert out["delta"] == pytest.approx(float(mathieu_transition(0.1, "0")), abs=1e-9)
    out = _json(capsys, ["transition", "--eps", "0.1", "--amplitude", "0.5", "--branch", "1/4",
                         "--method", "perturbation", "--order", "6", "--json"])
    assert out["order"] == 6 and out["method"] == "perturbation"
    assert 0.19 < out["delta"] < 0.22


def test_periodic_json_max_error(capsys):
    out = _json(capsys, ["periodic", "--eps", "0.1", "--amplitude", "0.3", "--method",
                         "averaging", "--json"])
    assert 0 < out["max_error"] < 0.05


@pytest.mark.parametrize("argv", [
    ["transition", "--eps", "0.1", "--amplitude", "0.5", "--method", "galerkin"],
    ["periodic", "--eps", "0.1", "--amplitude", "0.5", "--branch", "0", "--method", "energy"],
    ["transition", "--eps", "0.4", "--amplitude", "0.5", "--method", "energy"],
])
def test_bad_input_exit_2(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse usage error
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("gfrf: error:") and len(err.strip().splitlines()) == 1


def test_no_convergence_is_exit_1(capsys):
    """Valid input whose shooting finds no orbit: exit 1 (2 is bad input only)."""
    argv = ["periodic", "--eps", "0.2", "--amplitude", "0.1", "--delta", "0.1", "--method",
            "perturbation"]
    with pytest.warns(UserWarning):
        code = main(argv)
    assert code == 1
    err = capsys.readouterr().err
    assert err.startswith("gfrf: error:") and "did not converge" in err


def test_eps_out_of_range_warns_but_computes(capsys):
    with pytest.warns(UserWarning, match="eps"):
        out = _json(capsys, ["transition", "--eps", "1.2", "--amplitude", "0.5",
                             "--method", "averaging", "--json"])
    assert out["delta"] < 0

