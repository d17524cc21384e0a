"""Resolve the MODEL argument of a command: a model file path or an equation text."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from gfrf.errors import ModelError

if TYPE_CHECKING:
    from gfrf.model.modelfile import ModelFile

__all__ = ["add_model_argument", "resolve_model"]


def add_model_argument(parser: argparse.ArgumentParser) -> None:
    """Add the positional MODEL and the ``--sample-time`` option for inline NARX text."""
    parser.add_argument("model", metavar="MODEL",
                        help="a model file (models/*.toml) or an equation in quotes, "
                             "e.g. 'D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u'")
    parser.add_argument("--sample-time", type=float, default=None, metavar="T",
                        help="sample time in s when MODEL is an inline discrete (NARX) equation")


def _is_file(text: str) -> bool:
    try:
        return Path(text).is_file()
    except (OSError, ValueError):  # too long for a file name, or a NUL character
        return False


def resolve_model(args: argparse.Namespace) -> ModelFile:
    """Load ``args.model`` as a file if it names one (or ends in .toml), else parse it."""
    from gfrf.model.modelfile import load_model, model_from_dict

    text = args.model
    if text.endswith(".toml") or ("=" not in text and _is_file(text)):
        if args.sample_time is not None:
            raise ModelError("--sample-time is for inline equations; a model file sets "
                             "sample_time itself")
        return load_model(text)
    data: dict[str, object] = {"equation": text, "name": "inline model"}
    if args.sample_time is not None:
        data["sample_time"] = args.sample_time
    elif "[k" in text:
        raise ModelError("a discrete (NARX) equation needs --sample-time")
    return model_from_dict(data)
