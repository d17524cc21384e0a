"""Shared-library kernels: the closed form of H2 at broadcast points, a pole raises."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux") or shutil.which("cc") is None,
    reason="shared-library kernels need Linux and a C compiler driver")


def _native(equation: str, n: int, cache: Path, monkeypatch: pytest.MonkeyPatch):
    from gfrf.kernels.compiled import _step_functions
    from gfrf.kernels.native import NativeKernel, native_kernel
    from gfrf.kernels.recursion import generator
    from gfrf.model.equation import parse_model

    monkeypatch.setenv("GFRF_CACHE_DIR", str(cache))
    f = native_kernel(_step_functions(generator(parse_model(equation)), n, True), n)
    assert isinstance(f, NativeKernel)
    return f


def test_h2_matches_its_closed_form_at_broadcast_points(tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    f = _native("D(y,2) + 0.2*D(y) + y + 0.3*y**2 = u", 2, tmp_path, monkeypatch)
    h1 = lambda w: 1 / (1 - w * w + 0.2j * w)  # noqa: E731
    w1, w2 = np.linspace(-3, 3, 7)[:, None], np.linspace(-2, 2, 5)[None, :]
    value = f(w1, w2)
    assert value.shape == (7, 5)
    np.testing.assert_allclose(value, -0.3 * h1(w1) * h1(w2) * h1(w1 + w2), rtol=1e-13)
    assert isinstance(f(0.4, -1.3), complex)  # a scalar for scalars, like a ufunc


def test_without_cc_the_object_file_is_linked_in_memory(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    import gfrf.kernels.native as native

    monkeypatch.setattr(native.shutil, "which", lambda name: None)  # no C compiler driver
    f = _native("D(y,2) + 0.2*D(y) + y + 0.3*y**2 = u", 2, tmp_path, monkeypatch)
    files = sorted(p.name for p in (tmp_path / "kernels").glob("gfrf_native_*"))
    assert [name.split(".", 1)[1] for name in files] == ["o", "o.json"]  # object, record
    h1 = lambda w: 1 / (1 - w * w + 0.2j * w)  # noqa: E731
    w1, w2 = np.linspace(-3, 3, 7)[:, None], np.linspace(-2, 2, 5)[None, :]
    np.testing.assert_allclose(f(w1, w2), -0.3 * h1(w1) * h1(w2) * h1(w1 + w2), rtol=1e-13)
    again = _native("D(y,2) + 0.2*D(y) + y + 0.3*y**2 = u", 2, tmp_path, monkeypatch)
    assert np.array_equal(again(w1, w2), f(w1, w2))  # loaded from the cached object


def test_a_point_on_a_pole_raises_zero_division(tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    f = _native("D(y,2) + y + y**2 = u", 2, tmp_path, monkeypatch)
    with pytest.raises(ZeroDivisionError):
        f(np.array([0.5, 1.0]), np.array([0.0, 0.0]))  # H1(1) = 1 / (1 - 1)
