"""The MODEL argument of a command: a model file path or an equation text.

The rule itself is the library's (:func:`gfrf.model.modelfile.resolve_model`); this module
only adds the arguments.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from gfrf.model.modelfile import ModelFile

__all__ = ["add_model_argument", "resolve_model"]


def add_model_argument(parser: argparse.ArgumentParser) -> None:
    """Add the positional MODEL and the ``--sample-time`` option for inline NARX text.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand parser that gets the arguments.
    """
    parser.add_argument("model", metavar="MODEL",
                        help="a model file (models/*.toml; a bundled model by its file name, "
                             "e.g. duffing.toml) or an equation in quotes, "
                             "e.g. 'D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u'")
    parser.add_argument("--sample-time", type=float, default=None, metavar="T",
                        help="sample time in s when MODEL is an inline discrete (NARX) equation")


def resolve_model(args: argparse.Namespace) -> ModelFile:
    """The model of ``args.model`` (and ``args.sample_time``), by the library's one rule.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments with ``model`` (a model file path or an equation in quotes)
        and ``sample_time`` (s, or ``None``).

    Returns
    -------
    ModelFile
        The resolved model file.
    """
    from gfrf.model.modelfile import resolve_model as resolve

    return resolve(args.model, sample_time=args.sample_time)
