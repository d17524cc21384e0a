"""A sweep on a local dask cluster stops at once on Ctrl-C: the workers are killed, not
retired one by one."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CLI = "import sys; from gfrf.cli import main; sys.exit(main())"


@pytest.mark.slow
def test_ctrl_c_ends_a_processes_sweep_promptly(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    psutil = pytest.importorskip("psutil")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    argv = ["sweep", str(ROOT / "models" / "hanging_pendulum_damped.toml"), "--param",
            "rho=1:20:400", "--what", "bounded", "--scheduler", "processes", "--workers", "2",
            "--out", "table.csv"]
    proc = subprocess.Popen([sys.executable, "-c", CLI, *argv], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                            cwd=tmp_path)
    try:
        parent = psutil.Process(proc.pid)
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline and proc.poll() is None:  # workers computing
            workers = parent.children(recursive=True)
            if sum(c.cpu_times().user for c in workers if c.is_running()) > 3.0:
                break
            time.sleep(0.2)
        assert proc.poll() is None
        os.killpg(proc.pid, signal.SIGINT)
        start = time.monotonic()
        _, err = proc.communicate(timeout=60)
        elapsed = time.monotonic() - start
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 130
    assert err.decode().endswith("gfrf: interrupted\n")
    assert elapsed < 3.0, elapsed  # wall time on a shared machine (2 cores, load 14): about 2 s
    assert not (tmp_path / "table.csv").exists()
