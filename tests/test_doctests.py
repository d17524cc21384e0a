"""The Examples sections of every module of the package run as written.

One collector for the whole package: every module under ``gfrf`` (found by walking the
package, so a new module is picked up) that has examples is run by :mod:`doctest`,
from the repository root (examples name ``models/...``).
"""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil
from pathlib import Path

import pytest

import gfrf

ROOT = Path(__file__).resolve().parent.parent


def _module_names() -> list[str]:
    names = ["gfrf"] + [info.name for info in pkgutil.walk_packages(gfrf.__path__, "gfrf.")]
    return [n for n in names if not n.rsplit(".", 1)[-1].startswith("_dask")]


def _has_examples(name: str) -> bool:
    spec = importlib.util.find_spec(name)
    origin = spec.origin if spec is not None else None
    return origin is not None and ">>> " in Path(origin).read_text(encoding="utf-8")


@pytest.mark.parametrize("name", [n for n in _module_names() if _has_examples(n)])
def test_module_examples(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    result = doctest.testmod(importlib.import_module(name),
                             optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0


def test_the_collector_finds_the_package_modules() -> None:
    names = _module_names()
    assert {"gfrf", "gfrf.kernels.recursion", "gfrf.twosided.threshold"} <= set(names)
