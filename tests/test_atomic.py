"""Output files are opened once, links stay links, special input files are refused.

Every special file here (FIFO, symbolic link, a link to the process's own stdout) is
made in the test's own folder: the machine's /dev is never named.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from gfrf._atomic import atomic_open, atomic_write_text, check_output_path
from gfrf.cli import main
from gfrf.errors import ArgumentError

ROOT = Path(__file__).resolve().parent.parent
DUFFING = str(ROOT / "models" / "duffing.toml")
CLI = "import sys; from gfrf.cli import main; sys.exit(main())"
SIM = ["simulate", DUFFING, "--input", "0.1*sin(t)", "--t-end", "1", "--points", "20"]


def _read_all(fifo: Path, into: list[bytes]) -> threading.Thread:
    """A reader like ``cat fifo``: opens, reads to the first end of file, stops."""
    def read() -> None:
        with open(fifo, "rb") as fh:
            into.append(fh.read())

    thread = threading.Thread(target=read, daemon=True)
    thread.start()
    return thread


def test_a_fifo_reader_gets_the_whole_csv_from_one_open(tmp_path: Path,
                                                        capsys: pytest.CaptureFixture) -> None:
    fifo = tmp_path / "trace.csv"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = _read_all(fifo, got)
    assert main([*SIM, "--csv", str(fifo)]) == 0
    reader.join(10)
    capsys.readouterr()
    assert not reader.is_alive() and got
    assert got[0].startswith(b"t,y,u\n") and got[0].count(b"\n") == 21


@pytest.mark.parametrize("suffix", [".png", ".pdf", ".svg"])
def test_a_figure_reaches_a_fifo_in_one_piece(tmp_path: Path, capsys: pytest.CaptureFixture,
                                              suffix: str) -> None:
    fifo = tmp_path / f"figure{suffix}"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = _read_all(fifo, got)
    code = main([*SIM, "--plot", str(fifo)])
    reader.join(10)
    _, err = capsys.readouterr()
    assert code == 0, err
    assert got and len(got[0]) > 1000
    magic = {".png": b"\x89PNG", ".pdf": b"%PDF", ".svg": b"<?xml"}[suffix]
    assert got[0].startswith(magic)


def test_gfrf_plot_writes_a_fifo(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    fifo = tmp_path / "h1.pdf"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = _read_all(fifo, got)
    code = main(["plot", DUFFING, "--order", "1", "--no-mark", "--out", str(fifo)])
    reader.join(10)
    _, err = capsys.readouterr()
    assert code == 0, err
    assert got and got[0].startswith(b"%PDF")


def test_a_link_to_the_processes_stdout_is_written_through_not_replaced(tmp_path: Path) -> None:
    """``--csv DEV/stdout > out.txt``: DEV/stdout is the test's own link to /proc/self/fd/1."""
    if not Path("/proc/self/fd/1").exists():
        pytest.skip("no /proc/self/fd")
    dev = tmp_path / "dev"
    dev.mkdir()
    link = dev / "stdout"
    link.symlink_to("/proc/self/fd/1")
    out = tmp_path / "out.txt"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with open(out, "wb") as fh:
        proc = subprocess.run([sys.executable, "-c", CLI, *SIM, "--csv", str(link)], stdout=fh,
                              stderr=subprocess.PIPE, env=env, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert link.is_symlink() and os.readlink(link) == "/proc/self/fd/1"
    assert sorted(p.name for p in dev.iterdir()) == ["stdout"]
    text = out.read_text(encoding="utf-8")
    assert text.startswith("t,y,u\n")  # the CSV, then the summary after it
    assert text.count("\n") >= 22 and "evaluations" in text.splitlines()[21]


def test_a_link_to_a_fifo_stays_a_link(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    link = tmp_path / "elsewhere" / "out.csv"
    link.parent.mkdir()
    link.symlink_to(fifo)
    got: list[bytes] = []
    reader = _read_all(fifo, got)
    atomic_write_text(link, "a,b\n1,2\n")
    reader.join(10)
    assert got == [b"a,b\n1,2\n"]
    assert link.is_symlink() and os.path.realpath(link) == str(fifo)


def test_a_link_to_a_file_in_another_folder_is_written_through(tmp_path: Path) -> None:
    other = tmp_path / "other"
    other.mkdir()
    real = other / "data.csv"
    real.write_text("old\n", encoding="utf-8")
    named = tmp_path / "named"
    named.mkdir()
    link = named / "data.csv"
    link.symlink_to(real)
    atomic_write_text(link, "new\n")
    assert link.is_symlink() and real.read_text(encoding="utf-8") == "new\n"
    assert sorted(p.name for p in named.iterdir()) == ["data.csv"]
    assert sorted(p.name for p in other.iterdir()) == ["data.csv"]


def test_a_link_in_the_same_folder_keeps_the_link_and_replaces_its_file(tmp_path: Path) -> None:
    real = tmp_path / "v1.csv"
    real.write_text("old\n", encoding="utf-8")
    link = tmp_path / "latest.csv"
    link.symlink_to("v1.csv")
    atomic_write_text(link, "new\n")
    assert link.is_symlink() and real.read_text(encoding="utf-8") == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["latest.csv", "v1.csv"]


def test_a_dangling_link_is_refused_before_the_work(tmp_path: Path) -> None:
    link = tmp_path / "out.csv"
    link.symlink_to(tmp_path / "nowhere" / "x.csv")
    with pytest.raises(ArgumentError, match="symbolic link to nothing"):
        check_output_path("--csv", str(link))
    with pytest.raises(FileNotFoundError):
        atomic_write_text(link, "x\n")
    assert link.is_symlink()


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "t.csv"
    target.write_text("old\n", encoding="utf-8")
    with pytest.raises(RuntimeError), atomic_open(target) as fh:
        fh.write("partial")
        raise RuntimeError("stop")
    assert target.read_text(encoding="utf-8") == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["t.csv"]


def _char_device(folder: Path) -> Path:
    """A private /dev/zero (1, 5)."""
    node = folder / "zero"
    try:
        os.mknod(node, 0o20666, os.makedev(1, 5))
    except OSError:
        pytest.skip("cannot make a device node here")
    return node


@pytest.mark.parametrize("kind", ["fifo", "device", "directory"])
def test_a_special_input_csv_is_refused_by_what_it_is(tmp_path: Path, kind: str,
                                                      capsys: pytest.CaptureFixture) -> None:
    if kind == "fifo":
        path = tmp_path / "u.csv"
        os.mkfifo(path)  # nobody writes: opening it would block forever
    elif kind == "device":
        path = _char_device(tmp_path)  # reading it would never end
    else:
        path = tmp_path
    code = main(["simulate", DUFFING, "--input", f"csv:{path}", "--t-end", "1"])
    out, err = capsys.readouterr()
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "does not exist" not in err
    assert ("is a directory" if kind == "directory" else "not a regular file") in err
