"""Kernel pictures: the grid is bounded before any evaluation, and Ctrl-C acts at once."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from gfrf.cli import main
from gfrf.kernels.plot import MAX_AXIS_POINTS, frequency_grid
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model

ROOT = Path(__file__).resolve().parents[2]
#: Poles near -1000 and +-1j with half-width 5e-6: a uniform step dividing the resonance
#: would need millions of points per axis on [-1e5, 1e5].
STIFF = "D(y,3) + 1000.01*D(y,2) + 10.001*D(y) + 1000*y + 0.3*y**2 = u"
CLI = "import sys; from gfrf.cli import main; sys.exit(main())"


@pytest.mark.parametrize("top", [None, 1e5, 1e12])
def test_the_grid_of_a_map_is_bounded_and_thinning_is_announced(top: float | None) -> None:
    k = kernel(parse_model(STIFF), 2)
    w = 12_000.0 if top is None else top
    with pytest.warns(UserWarning, match="MAX_AXIS_POINTS"):
        grid = frequency_grid(k, w, [0.5, 0.0])
    assert grid.size <= MAX_AXIS_POINTS
    assert grid[0] >= -w and grid[-1] <= w and (grid[1:] > grid[:-1]).all()
    near = grid[abs(abs(grid) - 1.0) < 1e-3]  # the narrow resonance keeps points
    assert near.size >= 10


def test_plot_of_a_stiff_model_over_a_huge_range_is_drawn_bounded(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "h2.png"
    with pytest.warns(UserWarning, match="the plot grid is thinned"):
        code = main(["plot", STIFF, "--order", "2", "--range", "1e12", "--no-mark",
                     "--out", str(out)])
    _, err = capsys.readouterr()
    assert code == 0, err
    assert out.read_bytes().startswith(b"\x89PNG")


def _cpu_seconds(pid: int) -> float:
    """User + system CPU of a running process (from /proc; independent of the load)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@pytest.fixture
def child() -> Iterator[list[subprocess.Popen]]:
    started: list[subprocess.Popen] = []
    yield started
    for proc in started:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def interrupt_after(started: list[subprocess.Popen], argv: list[str], cpu: float,
                    tmp_path: Path) -> tuple[float, int, str]:
    """Run ``gfrf argv`` in its own session, send SIGINT to its group once it used
    ``cpu`` seconds of CPU; return (CPU seconds it spent after the signal, exit code,
    stderr)."""
    if not Path("/proc/self/stat").exists():
        pytest.skip("no /proc")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-c", CLI, *argv], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            cwd=tmp_path)
    started.append(proc)
    while proc.poll() is None and _cpu_seconds(proc.pid) < cpu:
        time.sleep(0.05)
    assert proc.poll() is None, "the command ended before the interrupt"
    before = _cpu_seconds(proc.pid)
    os.killpg(proc.pid, signal.SIGINT)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    err = proc.stderr.read().decode() if proc.stderr else ""
    return usage.ru_utime + usage.ru_stime - before, proc.returncode, err


@pytest.mark.parametrize("cpu", [1.0, 2.2])
def test_ctrl_c_stops_gfrf_plot_within_a_second_of_cpu(child: list[subprocess.Popen],
                                                       tmp_path: Path, cpu: float) -> None:
    after, code, err = interrupt_after(child, ["plot", STIFF, "--order", "2", "--out",
                                               "h2.png"], cpu, tmp_path)
    # the grid-thinning warning may come first; the interrupt is the last and only other line
    assert code == 130 and err.endswith("gfrf: interrupted\n") and "Traceback" not in err
    assert all(line.startswith("gfrf: ") for line in err.splitlines())
    assert after < 1.0
    assert list(tmp_path.iterdir()) == []
