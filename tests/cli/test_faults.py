"""Faults of the CLI: atomic outputs, Ctrl-C, closed pipes, bad schedulers, --plot."""

from __future__ import annotations

import csv
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import gfrf.sweep.run
import gfrf.sweep.schedulers
from gfrf._atomic import atomic_open, atomic_write_text
from gfrf.cli import main
from gfrf.cli._output import PLOT_SUFFIXES

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "models"
DUFFING = MODELS / "duffing.toml"
GFRF = [str(Path(sys.executable).parent / "gfrf")]


def _ctrl_c_reachable() -> None:
    """Child set-up: SIGINT at its default action, as under a terminal.

    A shell without job control starts background commands (CI's, say) with SIGINT
    ignored, and children inherit that; Python then installs no KeyboardInterrupt
    handler, so the child would rightly ignore the test's Ctrl-C and run on.
    """
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _finish(proc: subprocess.Popen, timeout: float) -> tuple[bytes, bytes]:
    """The child's output; its process group killed (nothing left running) if it outlives
    ``timeout`` or the wait fails (children are started with ``start_new_session``)."""
    try:
        return proc.communicate(timeout=timeout)
    except BaseException:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.communicate()
        raise
SWEEP_MODEL = """name = "damped"
equation = "D(y,2) + c*D(y) + y + 0.5*y**3 = u"
[parameters]
c = 0.2
"""


def run(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if ".tmp" in p.name)


# --- atomic outputs -----------------------------------------------------------------------

def test_atomic_open_keeps_the_old_file_when_the_writer_fails(tmp_path: Path) -> None:
    target = tmp_path / "map.csv"
    target.write_text("old,good\n", encoding="utf-8")
    for failure in (OSError("disk full"), KeyboardInterrupt()):
        with pytest.raises(type(failure)), atomic_open(target) as fh:
            fh.write("new,half")
            raise failure
        assert target.read_text(encoding="utf-8") == "old,good\n"
        assert leftovers(tmp_path) == []
    assert atomic_write_text(target, "new\n") == target
    assert target.read_text(encoding="utf-8") == "new\n"
    assert leftovers(tmp_path) == []


def test_atomic_writes_give_new_files_the_umask_mode(tmp_path: Path) -> None:
    mask = os.umask(0o027)
    try:
        atomic_write_text(tmp_path / "a.md", "x")
    finally:
        os.umask(mask)
    assert (tmp_path / "a.md").stat().st_mode & 0o777 == 0o640
    (tmp_path / "b.md").write_text("x")
    (tmp_path / "b.md").chmod(0o604)
    atomic_write_text(tmp_path / "b.md", "y")
    assert (tmp_path / "b.md").stat().st_mode & 0o777 == 0o604


def test_sweep_table_interrupted_midway_keeps_the_previous_table(
        tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> None:
    model = tmp_path / "m.toml"
    model.write_text(SWEEP_MODEL, encoding="utf-8")
    out = tmp_path / "map.csv"
    code, _, _ = run(capsys, "sweep", str(model), "--param", "c=0.1:0.4:3", "--what", "radius",
                     "--out", str(out))
    assert code == 0
    good = out.read_text(encoding="utf-8")
    assert len(list(csv.DictReader(good.splitlines()))) == 3

    def half_then_interrupt(self: csv.DictWriter, rows: list) -> None:
        self.writerow(rows[0])
        raise KeyboardInterrupt

    monkeypatch.setattr(csv.DictWriter, "writerows", half_then_interrupt)
    code, _, err = run(capsys, "sweep", str(model), "--param", "c=0.1:0.4:5", "--what",
                       "radius", "--out", str(out))
    assert code == 130
    assert err == "gfrf: interrupted\n"
    assert out.read_text(encoding="utf-8") == good
    assert leftovers(tmp_path) == []


# --- Ctrl-C and closed pipes ---------------------------------------------------------------

def test_keyboard_interrupt_in_any_command_is_exit_130_one_line(
        capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> None:
    import gfrf.cli.core

    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(gfrf.cli.core, "_show", interrupted)  # registered per main()
    code, out, err = run(capsys, "show", str(DUFFING))
    assert (code, out, err) == (130, "", "gfrf: interrupted\n")


def test_sigint_during_a_simulation(tmp_path: Path) -> None:
    # a run far longer than the wait (1e8 evaluations take minutes), so the signal lands
    proc = subprocess.Popen([*GFRF, "simulate", str(DUFFING), "--t-end", "1e8", "--input",
                             "0.1*sin(t)", "--max-evaluations", "100000000", "--csv",
                             str(tmp_path / "trace.csv")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT,
                            start_new_session=True, preexec_fn=_ctrl_c_reachable)
    time.sleep(4.0)
    proc.send_signal(signal.SIGINT)
    out, err = _finish(proc, timeout=30)
    assert proc.returncode == 130
    assert err.decode() == "gfrf: interrupted\n"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv", [["--help"], ["show", str(DUFFING), "--order", "3"],
                                  ["kernel", str(DUFFING), "--order", "1", "--at", "1"]])
def test_closed_stdout_exits_quietly(argv: list[str]) -> None:
    proc = subprocess.Popen([*GFRF, *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            cwd=ROOT, start_new_session=True)
    proc.stdout.close()  # the reader is gone before the first line: `gfrf ... | head -0`
    err = proc.stderr.read()
    _finish(proc, timeout=60)
    assert proc.returncode in (0, 141)
    assert err == b""


# --- dask scheduler addresses ----------------------------------------------------------------

@pytest.mark.parametrize(("address", "words"), [
    ("tcp://host:notaport", "port"), ("tcp://127.0.0.1:99999", "port"), ("tcp://:8786", "HOST"),
    ("inproc://x", "in-process"), ("tls://127.0.0.1:8786", "security context"),
    ("ucx://127.0.0.1:8786", "ucx"), ("ws://127.0.0.1:8786", "scheme"), ("nonsense", "tcp://"),
])
def test_malformed_scheduler_is_exit_2_one_line(
        tmp_path: Path, capsys: pytest.CaptureFixture, address: str, words: str) -> None:
    model = tmp_path / "m.toml"
    model.write_text(SWEEP_MODEL, encoding="utf-8")
    start = time.perf_counter()
    code, out, err = run(capsys, "sweep", str(model), "--param", "c=0.1:0.4:2",
                         "--scheduler", address)
    assert time.perf_counter() - start < 5
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("gfrf: error: scheduler")
    assert words.lower() in err.lower() and address in err


def test_scheduler_host_port_without_scheme_is_tcp() -> None:
    assert gfrf.sweep.run.check_scheduler("127.0.0.1:8786") == "tcp://127.0.0.1:8786"
    assert gfrf.sweep.run.check_scheduler("tcp://[::1]:8786") == "tcp://[::1]:8786"


def test_listener_that_is_not_a_scheduler_times_out(
        tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("distributed")
    model = tmp_path / "m.toml"
    model.write_text(SWEEP_MODEL, encoding="utf-8")
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    accepted: list[socket.socket] = []

    def accept() -> None:  # accept and never say a word
        try:
            while True:
                accepted.append(server.accept()[0])
        except OSError:
            pass

    threading.Thread(target=accept, daemon=True).start()
    monkeypatch.setattr(gfrf.sweep.schedulers, "SCHEDULER_TIMEOUT", 1.5)
    port = server.getsockname()[1]
    try:
        start = time.perf_counter()
        code, _, err = run(capsys, "sweep", str(model), "--param", "c=0.1:0.4:2",
                           "--scheduler", f"tcp://127.0.0.1:{port}")
        elapsed = time.perf_counter() - start
    finally:
        server.close()
        for conn in accepted:
            conn.close()
    assert accepted, "the sweep never connected"
    assert code == 2 and err.count("\n") == 1
    assert "within 1.5 s" in err and "not a dask scheduler" in err
    assert elapsed < 6


def test_documented_scheduler_timeout_is_ten_seconds() -> None:
    assert gfrf.sweep.schedulers.SCHEDULER_TIMEOUT == 10.0
    assert "SCHEDULER_TIMEOUT" in (gfrf.sweep.run.executor.__doc__ or "")


# --- --plot suffix ---------------------------------------------------------------------------

def test_plot_suffixes_are_what_matplotlib_writes() -> None:
    from matplotlib.backend_bases import FigureCanvasBase

    supported = FigureCanvasBase.get_supported_filetypes()
    assert {s.lstrip(".") for s in PLOT_SUFFIXES} <= set(supported)


@pytest.mark.parametrize("command", [
    ["sweep", "no-such-model.toml", "--param", "c=0.1:0.4:2"],
    ["simulate", "no-such-model.toml", "--t-end", "1"],
])
def test_unsupported_plot_suffix_is_exit_2_before_any_work(
        tmp_path: Path, capsys: pytest.CaptureFixture, command: list[str]) -> None:
    # the model does not exist: an error about the plot shows it was checked first
    code, out, err = run(capsys, *command, "--plot", str(tmp_path / "map.xyz"))
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "'.xyz'" in err and ".png" in err and ".pdf" in err and ".svg" in err
    assert list(tmp_path.iterdir()) == []


# --- sweep points whose model is not real-valued ------------------------------------------------

def test_non_real_value_at_a_grid_point_is_that_rows_error(
        tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> None:
    import json

    import gfrf.stability.criteria

    real_verdict = gfrf.stability.criteria.verdict

    def complex_below_zero(mf, *args, **kwargs):  # what a complex coefficient does downstream
        if mf.parameters["c"] < 0:
            raise TypeError("must be real number, not complex")
        return real_verdict(mf, *args, **kwargs)

    monkeypatch.setattr(gfrf.stability.criteria, "verdict", complex_below_zero)
    model = tmp_path / "m.toml"
    model.write_text(SWEEP_MODEL, encoding="utf-8")
    code, out, err = run(capsys, "sweep", str(model), "--param", "c=-0.2:0.2:3", "--what",
                         "radius", "--json")
    assert code == 0 and err == ""
    rows = json.loads(out)["rows"]
    assert [bool(r["error"]) for r in rows] == [True, False, False]
    assert "c = -0.2" in rows[0]["error"] and "not real-valued" in rows[0]["error"]
    assert rows[2]["radius"] > 0


@pytest.mark.slow
def test_ctrl_c_of_a_dask_process_sweep_is_one_line() -> None:
    pytest.importorskip("distributed")
    proc = subprocess.Popen([*GFRF, "sweep", str(MODELS / "hanging_pendulum.toml"), "--param",
                             "rho=0.5:8:400", "--what", "bounded", "--t-end", "500",
                             "--scheduler", "processes", "--workers", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT,
                            start_new_session=True, preexec_fn=_ctrl_c_reachable)
    time.sleep(10.0)
    os.killpg(proc.pid, signal.SIGINT)  # as a terminal does: the whole process group
    _, err = _finish(proc, timeout=60)
    assert proc.returncode == 130
    assert err.decode() == "gfrf: interrupted\n"


def test_every_output_file_is_written_through_a_temporary_path() -> None:
    """A regression guard: file writes in the package go through gfrf._atomic (a ``tmp``
    path, an ``atomic_open`` handle ``fh`` or a memory ``buffer`` then written by it) or are
    listed here with the reason they need not."""
    import re

    allowed = {
        "gfrf/_atomic.py",  # the helper itself
        "gfrf/bench/identify.py",  # benchmark input data in a temporary folder
        "gfrf/bench/cold.py",  # the CSV-reading benchmark's data in a temporary folder
        "gfrf/_cache.py",  # numba cache anchors: mkstemp file + rename
        "gfrf/model/modelfile.py",  # fdopen of a model file for reading ("rb")
    }
    pattern = re.compile(r"\.write_text\(|\.savefig\(|savetxt\(|write_table\(|"
                         r"open\([^)]*[\"']w|fdopen\(")
    offenders = []
    for path in sorted((ROOT / "gfrf").rglob("*.py")):
        name = path.relative_to(ROOT).as_posix()
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            through = re.search(r"tmp|atomic_open\(|\bfh\b|\bbuffer\b", line)
            if pattern.search(line) and not through and name not in allowed:
                offenders.append(f"{name}:{number}: {line.strip()}")
    assert offenders == []
