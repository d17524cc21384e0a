"""Data the package ships: the bundled model files.

They live in ``models/`` at the top of the source tree and are installed inside the
package as ``gfrf/models`` (``gfrf/models`` is a link to ``../models`` in the source tree;
pyproject.toml declares the files as package data), so :mod:`importlib.resources` finds
them from any directory, in a checkout and in a wheel alike.

>>> bundled_model("duffing.toml").name
'duffing.toml'
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

__all__ = ["MODELS_DIR", "bundled_model"]

#: The folder of the bundled model files (``*.toml``, and the identification example's CSV).
MODELS_DIR: Path = Path(str(files("gfrf") / "models")).resolve()


def bundled_model(name: str) -> Path:
    """The path of the bundled model file ``name`` (e.g. ``"duffing.toml"``).

    Parameters
    ----------
    name : str
        A file name in :data:`MODELS_DIR`.

    Raises
    ------
    FileNotFoundError
        No bundled file of that name.
    """
    path = MODELS_DIR / name
    if not path.is_file():
        raise FileNotFoundError(f"no bundled model {name!r} in {MODELS_DIR}")
    return path
