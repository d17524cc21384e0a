"""A sweep on a local dask cluster stops at once on Ctrl-C, whether its worker processes
are starting or computing: exit 130 within 1 s, the one line ``gfrf: interrupted`` (no
worker's traceback), no live process left, no output file."""

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


def _starting(children: list) -> bool:
    """A worker process exists (dask's spawn), still importing: the start-up phase."""
    return any("spawn_main" in " ".join(c.cmdline()) for c in children)


def _computing(children: list) -> bool:
    """The workers have run points for 3 s of CPU between them."""
    return sum(c.cpu_times().user for c in children) > 3.0


@pytest.mark.slow
@pytest.mark.parametrize("phase", [_starting, _computing], ids=["starting", "computing"])
def test_ctrl_c_ends_a_processes_sweep_within_a_second(tmp_path: Path, phase: object) -> None:
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
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                if phase(parent.children(recursive=True)):  # type: ignore[operator]
                    break
            except psutil.Error:  # a child that ended meanwhile
                pass
            time.sleep(0.02)
        assert proc.poll() is None
        os.killpg(proc.pid, signal.SIGINT)
        start = time.monotonic()
        _, err = proc.communicate(timeout=60)
        elapsed = time.monotonic() - start
        time.sleep(0.3)
        alive = [p for p in psutil.process_iter(["pid", "status"])
                 if _group(p, proc.pid) and p.info["status"] != psutil.STATUS_ZOMBIE]
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 130
    assert err.decode() == "gfrf: interrupted\n"
    assert elapsed < 1.0, elapsed  # wall time on a shared machine (2 cores): 0.02-0.14 s
    assert alive == []
    assert not (tmp_path / "table.csv").exists()


def _group(process: object, group: int) -> bool:
    """Whether ``process`` is in the process group ``group`` (False once it is gone)."""
    try:
        return os.getpgid(process.pid) == group  # type: ignore[attr-defined]
    except OSError:
        return False
