"""Shared test helpers: the bundled models, the in-process CLI runner, the markers.

Markers (registered in pyproject.toml): ``slow`` (``make test-slow`` only), and, set here
on every test of a module whose source uses them, ``subprocess`` (starts Python
processes), ``numba`` (skipped without numba) and ``dask`` (skipped without dask), so
``pytest -m "not subprocess"`` or a machine without the extras selects what it can run.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import pytest

# One BLAS thread per test process, set before numpy loads (the workers of ``-n auto``
# inherit it): the suite runs a process per core, and OpenBLAS's own threads on top of
# them wait for each other, spinning (an eigenvalue loop cost 8x the CPU time).
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

ROOT = Path(__file__).resolve().parent.parent
#: The bundled models of the source tree (the installed copy: ``gfrf.model.bundled``).
MODELS = ROOT / "models"

_SOURCE_MARKERS = {"subprocess": "subprocess", "numba": "numba", "dask": "dask"}
_OPTIONAL = {"numba": "numba", "dask": "distributed"}


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """``gfrf ARGV`` in this process: ``(exit code, stdout, stderr)`` (argparse's usage
    errors give their exit code too)."""
    from gfrf.cli import main

    try:
        code = main(list(argv))
    except SystemExit as exc:
        code = int(exc.code or 0)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]):
    """The CLI runner bound to this test's captured output: ``cli("show", path)``."""
    return lambda *argv: run(capsys, *argv)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    sources: dict[Path, str] = {}
    for item in items:
        path = Path(str(item.fspath))
        if path not in sources:
            sources[path] = path.read_text(encoding="utf-8") if path.suffix == ".py" else ""
        for word, marker in _SOURCE_MARKERS.items():
            if f"import {word}" in sources[path] or f"from {word}" in sources[path] \
                    or f'"{word}"' in sources[path]:
                item.add_marker(marker)
                module = _OPTIONAL.get(word)
                if module and importlib.util.find_spec(module) is None:
                    item.add_marker(pytest.mark.skip(reason=f"needs {module}"))
