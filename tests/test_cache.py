"""Caches are code: only code this process generated runs.

Each case warms a cache in a fresh ``GFRF_CACHE_DIR``, plants something that would create a
canary file (a ``.pyc`` beside a cached module, numba index pickles in a folder that other
users could write, a symbolic link on a temporary file's name), runs again and checks the
canary does not exist, the answer is right, and the run says why the cache was not used.
"""

from __future__ import annotations

import importlib.util
import marshal
import os
import pickle
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("numba")

ROOT = Path(__file__).resolve().parent.parent
DUFFING = ROOT / "models" / "duffing.toml"
CLI = "import sys; from gfrf.cli import main; sys.exit(main(sys.argv[1:]))"
SIMULATE = ["-c", CLI, "simulate", str(DUFFING), "--input", "0.1*sin(t)", "--t-end",
            "5", "--method", "fast", "--json"]
KERNEL = """
import gfrf
import gfrf.kernels.native
gfrf.kernels.native.native_kernel = lambda *args: None  # numba's cache, whose trust is tested
from gfrf.kernels.recursion import kernel
k = kernel(gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), 3)
# the Duffing H3(w, w, w) in closed form: -0.5 H1(w)^3 H1(3w)
h1 = lambda w: 1 / (1 - w * w + 0.2j * w)
exact = -0.5 * h1(0.4) ** 3 * h1(1.2)
print(abs(complex(k.compiled()(0.4, 0.4, 0.4)) - exact) <= 1e-12 * abs(exact))
"""


def _run(argv: list[str], env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    """A child python (killed by ``timeout`` if it hangs: subprocess.run kills it)."""
    return subprocess.run([sys.executable, *argv], capture_output=True, text=True, cwd=ROOT,
                           env={**os.environ, **env}, timeout=300)


def _simulate(cache: Path, **env: str) -> subprocess.CompletedProcess[str]:
    return _run(SIMULATE, {"GFRF_CACHE_DIR": str(cache), **env})


#: The kernels' runs have no C compiler on the PATH and no native kernel (``KERNEL``): they
#: go through numba's cache, whose trust these tests check (native kernels:
#: tests/kernels/test_compiled_cache.py).
NO_CC = {"PATH": str(Path(sys.executable).parent)}


def _kernel(cache: Path) -> subprocess.CompletedProcess[str]:
    return _run(["-c", KERNEL], {"GFRF_CACHE_DIR": str(cache), **NO_CC})


class _Canary:
    """A pickle that creates a file when loaded."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def __reduce__(self) -> tuple:
        return (open, (str(self.path), "w"))


def _plant_indexes(cache: Path, canary: Path) -> list[Path]:
    """Every numba index under ``cache`` replaced by the canary pickle."""
    indexes = sorted(cache.rglob("*.nbi"))
    for path in indexes:
        path.write_bytes(pickle.dumps(_Canary(canary)))
    return indexes


def _ok(done: subprocess.CompletedProcess[str]) -> None:
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr


@pytest.fixture
def canary(tmp_path: Path) -> Path:
    return tmp_path / "canary"


@pytest.fixture(scope="module")
def warm(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A cache with the Duffing fast path and H3 compiled (copied by each test)."""
    cache = tmp_path_factory.mktemp("warm") / "cache"
    _ok(_simulate(cache))
    _ok(_kernel(cache))
    return cache


def _copy(warm: Path, tmp_path: Path) -> Path:
    cache = tmp_path / "cache"
    shutil.copytree(warm, cache, symlinks=True)
    return cache


def test_a_planted_pyc_beside_a_cached_module_never_runs(tmp_path: Path, canary: Path,
                                                          warm: Path) -> None:
    cache = _copy(warm, tmp_path)
    sources = sorted(cache.rglob("gfrf_rhs_*.py"))
    assert sources
    for source in sources:  # a .pyc Python would take for the source (same mtime, size)
        code = compile(f"open({str(canary)!r}, 'w').close()\n", str(source), "exec")
        st = source.stat()
        data = (importlib.util.MAGIC_NUMBER + (0).to_bytes(4, "little")
                + (int(st.st_mtime) & 0xFFFFFFFF).to_bytes(4, "little")
                + (st.st_size & 0xFFFFFFFF).to_bytes(4, "little") + marshal.dumps(code))
        pyc = Path(importlib.util.cache_from_source(str(source)))
        pyc.parent.mkdir(exist_ok=True)
        pyc.write_bytes(data)
    done = _simulate(cache)
    _ok(done)
    assert not canary.exists()


@pytest.mark.parametrize("how", ["folder 0777",
                                 pytest.param("file 0666", marks=pytest.mark.slow)])
def test_numba_pickles_others_could_write_are_not_read(tmp_path: Path, canary: Path,
                                                       how: str, warm: Path) -> None:
    cache = _copy(warm, tmp_path)
    indexes = _plant_indexes(cache, canary)
    assert indexes
    for path in indexes:
        if how == "folder 0777":
            path.parent.chmod(0o777)
        else:
            path.chmod(0o666)
    done = _simulate(cache)
    _ok(done)
    assert not canary.exists()
    assert "gfrf: warning: gfrf's cache is not used" in done.stderr
    assert "writable by group or others" in done.stderr
    done = _kernel(cache)
    _ok(done)
    assert done.stdout.strip() == "True"
    assert not canary.exists()


def test_a_world_writable_cache_folder_is_refused(tmp_path: Path, canary: Path) -> None:
    cache = tmp_path / "cache"
    cache.mkdir()
    cache.chmod(0o777)  # another user could swap the folders below it
    done = _kernel(cache)
    _ok(done)
    assert done.stdout.strip() == "True"
    assert f"{cache} is writable by group or others (mode 0777)" in done.stderr
    assert not list(cache.rglob("*.nb[ic]"))  # nothing written, nothing to read later


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="giving a file to another user needs root")
def test_numba_pickles_of_another_user_are_not_read(tmp_path: Path, canary: Path,
                                                    warm: Path) -> None:
    cache = _copy(warm, tmp_path)
    for path in _plant_indexes(cache, canary):
        os.chown(path, 65534, 65534)
    done = _simulate(cache)
    _ok(done)
    assert not canary.exists()
    assert "is owned by uid 65534" in done.stderr


def _duffing_system() -> object:
    from gfrf.model.modelfile import load_model
    from gfrf.sim.system import build_system

    return build_system(load_model(DUFFING))


def test_a_planted_link_on_a_temporary_name_is_not_followed(tmp_path: Path, warm: Path,
                                                            monkeypatch: pytest.MonkeyPatch
                                                            ) -> None:
    from gfrf.sim import fastsim

    monkeypatch.setenv("GFRF_CACHE_DIR", str(_copy(warm, tmp_path)))
    monkeypatch.setattr(fastsim, "_MODULES", {})
    system = _duffing_system()
    fastsim.compile_system(system)
    (source,) = (tmp_path / "cache").rglob("gfrf_rhs_*.py")
    victim = tmp_path / "victim.txt"
    victim.write_text("precious\n", encoding="utf-8")
    source.unlink()  # so that it is written again, next to the planted links
    for name in (f"{source.stem}.{os.getpid()}.tmp", f"{source.stem}.tmp"):
        (source.parent / name).symlink_to(victim)
    monkeypatch.setattr(fastsim, "_MODULES", {})
    monkeypatch.delitem(sys.modules, source.stem, raising=False)
    fastsim.compile_system(system)
    assert victim.read_text(encoding="utf-8") == "precious\n"


@pytest.mark.parametrize("kind", ["a file", pytest.param("below a file",
                                                          marks=pytest.mark.slow)])
def test_an_unusable_cache_folder_falls_back_to_memory(tmp_path: Path, kind: str) -> None:
    blocked = tmp_path / "file"
    blocked.write_text("", encoding="utf-8")
    done = _simulate(blocked if kind == "a file" else blocked / "sub")
    _ok(done)
    assert "compiling in memory, uncached" in done.stderr
    assert '"status": "ok"' in done.stdout


def test_the_layout_honours_xdg_cache_home(tmp_path: Path, warm: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    from gfrf.sim import fastsim

    shutil.copytree(warm, tmp_path / "xdg" / "gfrf", symlinks=True)
    monkeypatch.delenv("GFRF_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(fastsim, "_MODULES", {})
    folder = tmp_path / "xdg" / "gfrf" / "fastsim"
    before = {p: p.stat().st_mtime_ns for p in folder.rglob("*")}
    fastsim.compile_system(_duffing_system())  # loaded from there: nothing rewritten
    assert {p: p.stat().st_mtime_ns for p in folder.rglob("*")} == before
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert stat.S_IMODE((folder / "__pycache__").stat().st_mode) == 0o700
    # numba's pickles are in the checked folders, nowhere else
    pickles = {p.parent for p in (tmp_path / "xdg").rglob("*.nb[ic]")}
    assert pickles == {folder / "__pycache__", folder.parent / "kernels" / "__pycache__"}


def _kernel_numba_dir(cache: Path, numba_dir: Path) -> subprocess.CompletedProcess[str]:
    return _run(["-c", KERNEL], {"GFRF_CACHE_DIR": str(cache),
                                  "NUMBA_CACHE_DIR": str(numba_dir), **NO_CC})


def test_numba_cache_dir_is_honoured_when_private(tmp_path: Path, canary: Path) -> None:
    numba_dir = tmp_path / "numba"
    first = _kernel_numba_dir(tmp_path / "cache", numba_dir)
    _ok(first)
    assert first.stdout.strip() == "True" and "cache is not used" not in first.stderr
    indexes = sorted(numba_dir.rglob("*.nbi"))  # the machine code went there, 0700
    assert indexes and not list((tmp_path / "cache").rglob("*.nb[ic]"))
    assert all(stat.S_IMODE(p.parent.stat().st_mode) == 0o700 for p in indexes)
    before = {p: p.stat().st_mtime_ns for p in numba_dir.rglob("*")}
    second = _kernel_numba_dir(tmp_path / "cache", numba_dir)  # loaded, nothing rewritten
    _ok(second)
    assert second.stdout.strip() == "True"
    assert {p: p.stat().st_mtime_ns for p in numba_dir.rglob("*")} == before
    # the same checks as gfrf's own folder: pickles others could write are not read
    _plant_indexes(numba_dir, canary)
    numba_dir.chmod(0o777)
    third = _kernel_numba_dir(tmp_path / "cache", numba_dir)
    _ok(third)
    assert third.stdout.strip() == "True" and not canary.exists()
    assert "writable by group or others" in third.stderr and "NUMBA_CACHE_DIR" in third.stderr


@pytest.mark.parametrize("kind", ["nbc", "nbi"])
def test_a_truncated_numba_cache_file_is_compiled_again(tmp_path: Path, warm: Path,
                                                         kind: str) -> None:
    """A truncated machine-code (``.nbc``) or index (``.nbi``) pickle of a kernel: numba
    raises on it; the kernel's cache files are deleted and it is compiled afresh."""
    cache = _copy(warm, tmp_path)
    files = sorted((cache / "kernels").rglob(f"gfrf_kernel_*.{kind}"))
    assert files
    for path in files:
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    done = _kernel(cache)
    _ok(done)
    assert done.stdout.strip() == "True"
    assert all(p.stat().st_size > 0 for p in (cache / "kernels").rglob("gfrf_kernel_*.nb?"))
