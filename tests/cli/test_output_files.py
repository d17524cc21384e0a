"""Outputs: write what the user named, nothing else.

A device or FIFO named as an output is written in place (a device stays a device,
``/dev/full`` is an error), and every output path is checked before any work, with the
user's path (never a temporary file's) in the message.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

import gfrf.sim.simulation
from gfrf._atomic import atomic_write_text
from gfrf.cli import main

ROOT = Path(__file__).resolve().parents[2]
DUFFING = str(ROOT / "models" / "duffing.toml")
SIM = ["simulate", DUFFING, "--input", "0.1*sin(t)", "--t-end", "1", "--points", "20"]


def run(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fail the test if a simulation starts (the paths must be refused before)."""
    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the simulation ran before the output path was checked")

    monkeypatch.setattr(gfrf.sim.simulation, "simulate", refuse)


def _device(folder: Path, name: str, minor: int) -> Path:
    """A private copy of /dev/null (minor 3) or /dev/full (minor 7): a test must never
    risk the real ones (the old writer replaced its target with a regular file)."""
    node = folder / name
    try:
        os.mknod(node, stat.S_IFCHR | 0o666, os.makedev(1, minor))
    except (PermissionError, AttributeError, OSError):
        pytest.skip("cannot make a device node here")
    return node


def test_a_full_device_is_a_write_error_naming_it(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture) -> None:
    full = _device(tmp_path, "full", 7)
    code, _, err = run(capsys, *SIM, "--csv", str(full))
    assert code == 2
    assert err == f"gfrf: error: No space left on device: {full}\n"
    assert stat.S_ISCHR(os.lstat(full).st_mode)


def test_a_fifo_stays_a_fifo_and_gets_the_data(tmp_path: Path,
                                               capsys: pytest.CaptureFixture) -> None:
    fifo = tmp_path / "out.csv"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # so that the writer's open returns
    try:
        code, _, err = run(capsys, *SIM, "--csv", str(fifo))
        data = os.read(reader, 1 << 16)
    finally:
        os.close(reader)
    assert code == 0, err
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert data.startswith(b"t,y,u\n") and data.count(b"\n") == 21


def test_a_device_node_is_written_not_replaced(tmp_path: Path) -> None:
    from gfrf.identify.output import write_atomic

    node = _device(tmp_path, "null", 3)
    atomic_write_text(node, "data\n")
    assert stat.S_ISCHR(os.lstat(node).st_mode)
    write_atomic(node, "data\n")  # identify's writer (model files, data) too
    assert stat.S_ISCHR(os.lstat(node).st_mode)
    assert list(tmp_path.iterdir()) == [node]


@pytest.mark.parametrize(("option", "make", "words"), [
    ("--csv", lambda d: "", "--csv: empty file name"),
    ("--csv", lambda d: str(d), "is a directory"),
    ("--csv", lambda d: str(d / "missing" / "x.csv"), "does not exist"),
    ("--plot", lambda d: "", "--plot: empty file name"),
    ("--plot", lambda d: str(d / "missing" / "x.png"), "does not exist"),
])
def test_output_paths_are_checked_before_any_work(tmp_path: Path, capsys: pytest.CaptureFixture,
                                                  no_work: None, option: str, make: object,
                                                  words: str) -> None:
    path = make(tmp_path)  # type: ignore[operator]
    code, out, err = run(capsys, *SIM, option, path)
    assert code == 2 and out == ""
    assert err.startswith("gfrf: error: ") and err.count("\n") == 1
    assert words in err and ".tmp" not in err
    if path:
        assert repr(path) in err


def test_the_atomic_writer_names_the_users_path(tmp_path: Path) -> None:
    target = tmp_path / "missing" / "x.csv"
    with pytest.raises(FileNotFoundError) as info:
        atomic_write_text(target, "a\n")
    assert info.value.filename == str(target)
    with pytest.raises(IsADirectoryError) as info:
        atomic_write_text(tmp_path, "a\n")
    assert info.value.filename == str(tmp_path)


@pytest.mark.parametrize("command", ["report", "bench"])
def test_an_output_folder_that_is_a_file_is_refused_first(tmp_path: Path, command: str,
                                                         capsys: pytest.CaptureFixture) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("", encoding="utf-8")
    code, out, err = run(capsys, command, "--out", str(blocked), "--quick")
    assert code == 2 and out == ""
    assert err == f"gfrf: error: --out {str(blocked)!r} is not a folder\n"
