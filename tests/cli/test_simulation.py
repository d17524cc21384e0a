"""CLI contract of ``gfrf simulate`` and ``gfrf predict``."""

import json
import math

import numpy as np

from gfrf.cli import main


def test_simulate_json_and_csv(tmp_path, capsys):
    csv = tmp_path / "out.csv"
    png = tmp_path / "out.png"
    code = main(["simulate", "D(y) + y = u", "--input", "step(t)", "--t-end", "3",
                 "--rtol", "1e-10", "--atol", "1e-12", "--points", "31", "--csv", str(csv),
                 "--plot", str(png), "--json"])
    assert code == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["status"] == "ok" and payload["samples"] == 31
    assert payload["y_final"] == __import__("pytest").approx(1 - math.exp(-3), abs=1e-8)
    data = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert data.shape == (31, 3) and np.allclose(data[:, 2], 1.0)
    assert png.stat().st_size > 1000


def test_simulate_blowup_exit_1(capsys):
    code = main(["simulate", "D(y,2) + y - y**3 = u", "--initial", "1.5,0.5", "--t-end",
                 "20"])
    out = capsys.readouterr().out
    assert code == 1 and "BLOW-UP" in out


def test_closed_loop_cartpole_text(capsys):
    code = main(["simulate", "models/cartpole.toml", "--closed-loop", "--initial", "0.0873,0",
                 "--t-end", "2"])
    out = capsys.readouterr().out
    assert code == 0 and "improper" in out


def test_bad_input_exit_2(capsys):
    for argv in (["simulate", "models/duffing.toml", "--input", "0.5", "--t-end", "1"],
                 ["simulate", "models/duffing.toml", "--input", "sin(x)", "--t-end", "1"],
                 ["simulate", "models/duffing.toml", "--t-end", "-1"],
                 ["simulate", "models/duffing.toml", "--t-end", "1", "--rtol", "0"],
                 ["simulate", "models/duffing.toml", "--t-end", "1", "--closed-loop"],
                 ["predict", "models/duffing.toml", "--input", "step(t)"]):
        assert main(argv) == 2, argv
        assert "gfrf: error:" in capsys.readouterr().err


def test_predict_linear_json(capsys):
    # H1(j*2) of y'' + y' + 4y = u is -0.5j: amplitude 1.5 for 3*cos(2t)
    code = main(["predict", "D(y,2) + D(y) + 4*y = u", "--input", "3*cos(2*t)", "--order",
                 "3", "--json"])
    payload = json.loads(capsys.readouterr().out)
    assert code == 0
    (row,) = payload["components"]
    assert abs(row["amplitude"] - 1.5) < 1e-12 and abs(row["phase"] + math.pi / 2) < 1e-12


def test_predict_refuses_beyond_radius_exit_1(capsys):
    # a reported run printed an amplitude of 1020.9 with exit 0
    argv = ["predict", "models/hanging_pendulum.toml", "--input", "0.5*sin(1.565*t)",
            "--order", "3"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert "r* = 0.0131852" in line and "amplitude 0.5 " in line and "--force" in line
    assert main([*argv, "--force", "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert "r* = 0.0131852" in payload["warning"] and payload["amplitude"] == 0.5
    assert main([*argv, "--force"]) == 0
    assert "WARNING" in capsys.readouterr().out


def test_predict_never_prints_nan(capsys):
    argv = ["predict", "models/duffing.toml", "--input", "1e300*sin(t)", "--order", "3"]
    assert main(argv) == 1
    assert main([*argv, "--force", "--json"]) == 2
    captured = capsys.readouterr()
    assert "nan" not in captured.out.lower() and "not finite" in captured.err


def test_predict_multitone_amplitude_is_the_sum(capsys):
    # 0.03 + 0.03 = 0.06 > r* = 0.0483 of the Duffing model although each tone is inside
    argv = ["predict", "models/duffing.toml", "--input", "0.03*sin(t) + 0.03*cos(1.5*t)"]
    assert main(argv) == 1
    assert "amplitude 0.06 " in capsys.readouterr().err
    assert main(["predict", "models/duffing.toml", "--input", "0.02*sin(t) + 0.02*cos(1.5*t)",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["warning"] is None


def test_predict_too_many_products_exit_2(capsys):
    tones = " + ".join(f"0.0001*sin({1 + 0.1 * k:g}*t)" for k in range(40))
    assert main(["predict", "models/duffing.toml", "--input", tones, "--order", "5"]) == 2
    assert "MAX_PRODUCTS" in capsys.readouterr().err


def test_simulate_refuses_an_input_frequency_of_1e300_at_once(capsys):
    # sin(1e300*t) ran scipy's RK45 for many minutes
    import time

    start = time.perf_counter()
    code = main(["simulate", "models/duffing.toml", "--input", "sin(1e300*t)", "--t-end", "1"])
    assert time.perf_counter() - start < 5.0
    captured = capsys.readouterr()
    (line,) = captured.err.strip().splitlines()
    assert code == 2 and captured.out == ""
    assert "1e+300 rad/s" in line and "MAX_RHS_EVALUATIONS = 1000000" in line


def test_simulate_work_budget_failed_exit_1(capsys):
    import time

    start = time.perf_counter()
    code = main(["simulate", "models/duffing.toml", "--input", "exp(-t)*sin(t**2*1e6)",
                 "--t-end", "1", "--max-evaluations", "3000"])
    assert time.perf_counter() - start < 5.0
    captured = capsys.readouterr()
    assert code == 1 and "Traceback" not in captured.err
    (line,) = [x for x in captured.out.splitlines() if "FAILED" in x]
    assert "max_evaluations = 3000" in line and "stopped at t = " in line
    assert main(["simulate", "models/duffing.toml", "--t-end", "1",
                 "--max-evaluations", "0"]) == 2


def test_predict_unstable_plant_refused_unless_force(capsys):
    argv = ["predict", "models/cartpole_reduced.toml", "--input", "0.001*sin(t)"]
    assert main(argv) == 1
    captured = capsys.readouterr()
    (line,) = captured.err.strip().splitlines()
    assert captured.out == "" and "no steady state exists" in line and "--force" in line
    assert main([*argv, "--force", "--json"]) == 0
    assert "no steady state exists" in json.loads(capsys.readouterr().out)["warning"]
