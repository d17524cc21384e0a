"""A cached library or object file is loaded only when its size and SHA-256 match its
record: a truncated file, a flipped byte or a missing record is rebuilt, never loaded
(loading a truncated library crashes the process, so each load runs in a subprocess)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="native kernels: Linux")

MODEL = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 + 0.3*y**2 = u"
#: The compiled H3 against the numpy path (the recursion's generated code, no numba)
#: at a grid of points: the largest relative difference, and the kernel's type.
SCRIPT = f"""
import numpy as np
import gfrf
from gfrf.kernels.recursion import kernel
k = kernel(gfrf.parse_model({MODEL!r}), 3)
w = np.linspace(-2.5, 2.5, 11)
w1, w2, w3 = w[:, None, None], 0.7 * w[None, :, None], -0.4 * w[None, None, :]
compiled, numpy_path = k.compiled()(w1, w2, w3), k(w1, w2, w3)
print(float(np.max(abs(compiled - numpy_path) / abs(numpy_path))), type(k.compiled()).__name__)
"""


def load(cache: Path, cc: bool) -> float:
    """Run the script in a fresh process: the relative difference (asserts a clean exit
    and the shared-library or object-file kernel)."""
    env = {**os.environ, "GFRF_CACHE_DIR": str(cache)}
    if not cc:
        env["PATH"] = str(Path(sys.executable).parent)  # no C compiler driver
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          env=env, timeout=300)
    assert done.returncode == 0, (done.returncode, done.stderr)  # -7 bus error, -11 segfault
    assert done.stderr == ""
    difference, kind = done.stdout.split()
    assert kind == "NativeKernel"
    return float(difference)


def truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def flip_a_byte(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x10
    path.write_bytes(bytes(data))


def delete_the_record(path: Path) -> None:
    path.with_name(path.name + ".json").unlink()


@pytest.mark.parametrize(("suffix", "damages"), [
    (".so", (truncate, flip_a_byte, delete_the_record)),
    pytest.param(".o", (truncate,), marks=pytest.mark.slow)])
def test_a_damaged_cached_kernel_is_rebuilt_not_loaded(
        tmp_path: Path, suffix: str, damages: tuple[Callable[[Path], None], ...]) -> None:
    cc = suffix == ".so"
    if cc and shutil.which("cc") is None:
        pytest.skip("shared libraries need a C compiler driver")
    assert load(tmp_path, cc) < 1e-12  # built
    (artifact,) = (tmp_path / "kernels").glob(f"gfrf_native_*{suffix}")
    good = artifact.read_bytes()
    record = json.loads(artifact.with_name(artifact.name + ".json").read_text())
    assert record["size"] == len(good)
    for damage in damages:
        damage(artifact)
        assert load(tmp_path, cc) < 1e-12, damage  # discarded and built again
        assert artifact.stat().st_size == len(good)
        assert json.loads(artifact.with_name(artifact.name + ".json").read_text()) == record
