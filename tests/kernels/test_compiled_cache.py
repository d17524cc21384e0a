"""On-disk cache of the numba-compiled kernels: a second process pays no compile,
the code that runs is always the freshly generated source, an unwritable cache degrades to
an in-memory compile; with a C compiler the kernel is a shared library that a second
process loads without importing numba."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("numba")

MODEL = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 + 0.3*y**2 = u"
SCRIPT = f"""
import sys
import gfrf
from gfrf.kernels.recursion import kernel
k = kernel(gfrf.parse_model({MODEL!r}), 2)
h1 = lambda w: 1 / (1 - w * w + 0.2j * w)
# H2(w1, w2) = -0.3 H1(w1) H1(w2) H1(w1 + w2)
exact = -0.3 * h1(0.4) * h1(-1.3) * h1(0.4 - 1.3)
value = complex(k.compiled()(0.4, -1.3))
print(abs(value - exact) <= 1e-12 * abs(exact), "numba" in sys.modules)
"""


#: Prepended to the script to switch the native kernels off (numba's cache is used).
NO_NATIVE = "import gfrf.kernels.native as n\nn.native_kernel = lambda *args: None\n"


def run(cache: Path, native: bool = False, cc: bool = True) -> str:
    """The script's line; without ``native`` no native kernel (numba's cache is used),
    without ``cc`` no C compiler driver on the PATH."""
    env = {**os.environ, "GFRF_CACHE_DIR": str(cache)}
    if not cc:
        env["PATH"] = str(Path(sys.executable).parent)
    script = SCRIPT if native else NO_NATIVE + SCRIPT
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


def machine_code(cache: Path) -> dict[str, int]:
    return {p.name: p.stat().st_mtime_ns for p in (cache / "kernels").rglob("*.nb[ic]")}


def test_second_process_loads_the_compiled_kernel_from_disk(tmp_path: Path) -> None:
    assert run(tmp_path) .startswith("True")
    sources = list((tmp_path / "kernels").glob("gfrf_kernel_*.py"))
    assert len(sources) == 1
    first = machine_code(tmp_path)
    assert any(name.endswith(".nbc") for name in first)
    assert run(tmp_path) .startswith("True")
    assert machine_code(tmp_path) == first  # nothing recompiled, nothing rewritten


def test_a_tampered_cached_source_is_replaced_not_run(tmp_path: Path) -> None:
    assert run(tmp_path) .startswith("True")
    (source,) = (tmp_path / "kernels").glob("gfrf_kernel_*.py")
    good = source.read_text(encoding="utf-8")
    source.write_text(good.replace("return ", "return 1.0 + "), encoding="utf-8")
    assert run(tmp_path) .startswith("True")  # the generated code ran, not the file's
    assert source.read_text(encoding="utf-8") == good


def test_unwritable_cache_compiles_in_memory(tmp_path: Path) -> None:
    blocked = tmp_path / "not-a-directory"
    blocked.write_text("", encoding="utf-8")
    assert run(blocked) .startswith("True")


@pytest.mark.skipif(not sys.platform.startswith("linux") or shutil.which("cc") is None,
                    reason="shared-library kernels need Linux and a C compiler driver")
def test_a_second_process_loads_the_shared_library_without_numba(tmp_path: Path) -> None:
    assert run(tmp_path, native=True) == "True True"  # compiled by numba
    (library,) = (tmp_path / "kernels").glob("gfrf_native_*.so")
    built = library.stat().st_mtime_ns
    assert not list((tmp_path / "kernels").glob("gfrf_kernel_*.py"))
    assert run(tmp_path, native=True) == "True False"  # loaded: numba never imported
    assert library.stat().st_mtime_ns == built


@pytest.mark.skipif(not sys.platform.startswith("linux") or shutil.which("cc") is None,
                    reason="shared-library kernels need Linux and a C compiler driver")
def test_a_shared_library_in_a_folder_others_can_write_is_not_loaded(tmp_path: Path) -> None:
    assert run(tmp_path, native=True) == "True True"
    folder = tmp_path / "kernels"
    folder.chmod(0o777)
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          env={**os.environ, "GFRF_CACHE_DIR": str(tmp_path)}, timeout=300)
    folder.chmod(0o700)
    assert done.stdout.strip() == "True True"  # compiled in memory by numba
    assert "writable by group or others" in done.stderr


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="native kernels: Linux")
def test_without_cc_a_second_process_loads_the_object_without_numba(tmp_path: Path) -> None:
    assert run(tmp_path, native=True, cc=False) == "True True"  # compiled by numba
    (obj,) = (tmp_path / "kernels").glob("gfrf_native_*.o")
    built = obj.stat().st_mtime_ns
    assert run(tmp_path, native=True, cc=False) == "True False"  # linked in memory by LLVM
    assert obj.stat().st_mtime_ns == built
