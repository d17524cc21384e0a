"""``gfrf frc``: the JSON contract, the figure, and one-line refusals with exit 2."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gfrf.cli import main

HARDENING = "D(y,2) + 0.1*D(y) + y + 0.3*y**3 = u"


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["frc", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_json_contract(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, HARDENING, "--amplitude", "0.3", "--omega", "0.5:2",
                        "--harmonics", "7", "--json")
    assert code == 0
    data = json.loads(out, parse_constant=lambda c: pytest.fail(f"non-JSON token {c}"))
    assert data["harmonics"] == 7
    points = data["points"]
    assert points[0]["omega"] == pytest.approx(0.5) and points[-1]["omega"] == pytest.approx(2)
    for p in points:
        assert set(p) == {"omega", "amplitude", "stable", "coefficients"}
        assert isinstance(p["stable"], bool)
        c = p["coefficients"]
        assert len(c) == 8 and c[0][1] == 0 and all(len(pair) == 2 for pair in c)
        assert p["amplitude"] == pytest.approx(math.hypot(*c[1]), rel=1e-12)
    # continuation order: consecutive points are close along the branch
    steps = [math.hypot(b["omega"] - a["omega"], b["amplitude"] - a["amplitude"])
             for a, b in zip(points, points[1:], strict=False)]
    assert max(steps) < 0.2
    assert [set(f) for f in data["folds"]] == [{"omega", "amplitude"}] * 2
    assert 1.40 < data["folds"][0]["omega"] < 1.44 and 1.2 < data["folds"][1]["omega"] < 1.24
    assert any(not p["stable"] for p in points)


def test_coefficients_are_the_periodic_solution(capsys: pytest.CaptureFixture[str]) -> None:
    """y(t) = a0 + sum a_k cos(k w t) + b_k sin(k w t) satisfies the ODE under
    u = A cos(w t): the residual on a fine grid is at the truncation level."""
    _, out, _ = _run(capsys, HARDENING, "--amplitude", "0.3", "--omega", "0.5:2", "--json")
    data = json.loads(out)
    for p in data["points"][::25]:
        w = p["omega"]
        c = np.array(p["coefficients"])
        k = np.arange(c.shape[0])
        t = np.linspace(0, 2 * math.pi / w, 200)
        cos, sin = np.cos(np.outer(t, k) * w), np.sin(np.outer(t, k) * w)
        y = cos @ c[:, 0] + sin @ c[:, 1]
        dy = (-sin * k * w) @ c[:, 0] + (cos * k * w) @ c[:, 1]
        ddy = (-cos * (k * w) ** 2) @ c[:, 0] + (-sin * (k * w) ** 2) @ c[:, 1]
        residual = ddy + 0.1 * dy + y + 0.3 * y ** 3 - 0.3 * np.cos(w * t)
        assert np.max(np.abs(residual)) < 1e-5


def test_vary_amplitude_and_text_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, HARDENING, "--vary", "amplitude", "--amplitude", "0.01:0.3",
                        "--omega", "1.3", "--json")
    data = json.loads(out)
    assert code == 0 and data["vary"] == "amplitude"
    assert data["forcing"][0] == pytest.approx(0.01) and data["forcing"][-1] == pytest.approx(0.3)
    assert all(p["omega"] == pytest.approx(1.3) for p in data["points"])
    code, out, _ = _run(capsys, HARDENING, "--amplitude", "0.3", "--omega", "0.5:2")
    assert code == 0 and "fold 1 (up-sweep jump): omega = 1.42" in out


def test_plot_file(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "frc.png"
    code, _, _ = _run(capsys, HARDENING, "--amplitude", "0.3", "--omega", "0.5:2",
                      "--plot", str(path))
    assert code == 0 and path.read_bytes()[:4] == b"\x89PNG"


def test_narx_up_to_nyquist(capsys: pytest.CaptureFixture[str]) -> None:
    narx = "y[k] = 0.5*y[k-1] - 0.1*y[k-1]**3 + u[k-1]"
    code, out, _ = _run(capsys, narx, "--sample-time", "0.1", "--amplitude", "0.5",
                        "--omega", f"1:{math.pi / 0.1}", "--json")
    assert code == 0 and json.loads(out)["points"][-1]["omega"] == pytest.approx(math.pi / 0.1)
    code, _, err = _run(capsys, narx, "--sample-time", "0.1", "--amplitude", "0.5",
                        "--omega", "1:40")
    assert code == 2 and "Nyquist" in err


@pytest.mark.parametrize("args", [
    ["--amplitude", "x", "--omega", "1:2"],
    ["--amplitude", "0.3", "--omega", "2:1"],
    ["--amplitude", "0.3", "--omega", "1"],
    ["--amplitude", "0.3", "--omega", "1:2:3"],
    ["--amplitude", "nan", "--omega", "1:2"],
    ["--amplitude", "0", "--omega", "1:2"],
    ["--amplitude", "0.3", "--omega", "0:2"],
    ["--amplitude", "0.3", "--omega", "1:inf"],
    ["--amplitude", "0.3", "--omega", "1:2", "--harmonics", "0"],
    ["--amplitude", "0.3", "--omega", "1:2", "--harmonics", "1000"],
    ["--amplitude", "0.3", "--omega", "1:2", "--step", "-1"],
    ["--amplitude", "0.3", "--omega", "1:2", "--max-points", "1"],
    ["--amplitude", "0.3", "--omega", "1:2", "--plot", "out.xyz"],
    ["--vary", "amplitude", "--amplitude", "0.3", "--omega", "1"],
])
def test_bad_input_is_one_line_and_exit_2(args: list[str],
                                          capsys: pytest.CaptureFixture[str]) -> None:
    try:
        code = main(["frc", HARDENING, *args])
    except SystemExit as exc:  # argparse's own refusals
        code = exc.code
    out = capsys.readouterr()
    assert code == 2, out.err
    assert out.err.count("\n") == 1 and out.err.startswith("gfrf: error: ")
    assert out.out == ""


def test_a_branch_that_does_not_end_exits_1_with_its_points(
        capsys: pytest.CaptureFixture[str]) -> None:
    """An undamped resonance sends the response to infinity: the points found so far,
    complete false, a note, exit 1 (no traceback at the singular internal resonance)."""
    code, out, _ = _run(capsys, "D(y,2) + y = u", "--amplitude", "0.5", "--omega", "0.5:2",
                        "--max-points", "60", "--json")
    data = json.loads(out)
    assert code == 1 and data["complete"] is False and len(data["points"]) == 60
    assert data["points"][0]["amplitude"] == pytest.approx(0.5 / (1 - 0.25))
    assert any("stopped" in note for note in data["notes"])


def test_no_periodic_solution_exits_1_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    """u**2 drives 2 w = 1 rad/s, an undamped mode, at w = 0.5: harmonic balance finds
    no periodic solution and says so (a valid input, not converged: exit 1)."""
    code, out, err = _run(capsys, "D(y,3) + D(y,2) + D(y) + y + y**2 = u**2 + u",
                          "--amplitude", "0.5", "--omega", "0.5:2")
    assert code == 1 and out == "" and "no periodic solution" in err
