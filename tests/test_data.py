"""The bundled models are package data: found through importlib.resources, declared in
pyproject.toml, and no module looks for them next to its own source file."""

from __future__ import annotations

import re
import tomllib

import pytest
from conftest import MODELS, ROOT

from gfrf._data import MODELS_DIR, bundled_model


def test_every_model_file_of_the_tree_is_found_as_package_data() -> None:
    shipped = {p.name for p in MODELS_DIR.iterdir()}
    assert {p.name for p in MODELS.glob("*.toml")} <= shipped
    assert bundled_model("duffing.toml").read_bytes() == (MODELS / "duffing.toml").read_bytes()


def test_pyproject_ships_the_models_with_the_package() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    data = config["tool"]["setuptools"]["package-data"]["gfrf"]
    assert {"models/*.toml", "models/*.csv"} <= set(data)
    assert (ROOT / "gfrf" / "models").resolve() == MODELS.resolve()


def test_a_missing_bundled_model_is_named() -> None:
    with pytest.raises(FileNotFoundError, match="no bundled model 'nope.toml'"):
        bundled_model("nope.toml")


def test_no_module_builds_the_models_path_from_its_own_location() -> None:
    pattern = re.compile(r"__file__.*\bmodels\b|parents?\b.*/ *\"models\"")
    offenders = [f"{p.relative_to(ROOT)}:{n}" for p in (ROOT / "gfrf").rglob("*.py")
                 for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
                 if pattern.search(line)]
    assert offenders == []
