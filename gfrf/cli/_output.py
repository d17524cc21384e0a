"""Shared printing helpers for the CLI: JSON or short human text, nothing else."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

from gfrf._results import dumps
from gfrf.errors import ArgumentError
from gfrf.model.safetext import printable

__all__ = ["add_json_flag", "emit", "emit_refusal", "check_plot_path",
           "check_output_file", "check_output_folder", "terminal_text", "PLOT_SUFFIXES"]

#: Figure formats of ``--plot`` (chosen by the file suffix; all written by matplotlib's
#: Agg backend, checked before any computation so a typo costs nothing).
PLOT_SUFFIXES: tuple[str, ...] = (".png", ".pdf", ".svg", ".svgz", ".eps", ".ps", ".jpg",
                                  ".jpeg", ".tif", ".tiff", ".webp")


def check_plot_path(path: str | None) -> None:
    """Refuse a ``--plot`` file whose suffix matplotlib cannot write, naming the good ones.

    Parameters
    ----------
    path : str or None
        The ``--plot`` file name; ``None`` (no plot asked for) passes.

    Raises
    ------
    ArgumentError
        The suffix is not one of :data:`PLOT_SUFFIXES`.
    """
    if path is None:
        return
    check_output_file("--plot", path)
    suffix = Path(path).suffix.lower()
    if suffix not in PLOT_SUFFIXES:
        raise ArgumentError(f"--plot {path!r}: unsupported figure format {suffix or '(none)'!r}; "
                            f"use one of {', '.join(PLOT_SUFFIXES)}")


def check_output_file(option: str, path: str | None) -> None:
    """Refuse, before any work, an output file that cannot be written
    (:func:`gfrf._atomic.check_output_path`, the one check of every output file).

    Parameters
    ----------
    option : str
        The option's name as the user wrote it, e.g. ``"--out"``, quoted in the message.
    path : str or None
        The output file name; ``None`` (no file asked for) passes.

    Raises
    ------
    ArgumentError
        Naming ``option`` and the user's ``path``.
    """
    from gfrf._atomic import check_output_path

    check_output_path(option, path)


def check_output_folder(option: str, path: str) -> None:
    """Refuse, before any work, an output folder that cannot be made or written.

    Parameters
    ----------
    option : str
        The option's name as the user wrote it, quoted in the message.
    path : str
        The output folder; it may not exist yet if its nearest existing parent is a
        writable folder.

    Raises
    ------
    ArgumentError
        Empty, an existing non-folder, or a missing folder whose parent is not writable.
    """
    if not path.strip():
        raise ArgumentError(f"{option}: empty folder name")
    folder = Path(path)
    if folder.exists():
        if not folder.is_dir():
            raise ArgumentError(f"{option} {path!r} is not a folder")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise ArgumentError(f"{option} {path!r}: the folder is not writable")
        return
    parent = next((p for p in folder.absolute().parents if p.exists()), None)
    if parent is None or not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise ArgumentError(f"{option} {path!r}: cannot create the folder "
                            f"(in {str(parent)!r})")


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    """Add the ``--json`` flag every printing command has.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The subcommand parser that gets ``--json``.
    """
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def emit(args: argparse.Namespace, payload: dict[str, Any], text: str) -> None:
    """Print ``payload`` as strict JSON when ``--json`` was given, else ``text`` with the
    payload's user text (and every other control character) escaped: the one way out.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments (``args.json``).
    payload : dict
        The result, as :func:`gfrf._results.dumps` encodes it.
    text : str
        The human-readable result.
    """
    if getattr(args, "json", False):
        print(dumps(payload))
    else:
        print(terminal_text(text, payload))


def emit_refusal(args: argparse.Namespace, payload: dict[str, Any], line: str) -> None:
    """Say why a valid request got no answer (exit 1): ``line`` as one escaped line on
    stderr and, with ``--json``, ``payload`` plus ``"refused": line`` as strict JSON on
    stdout (a JSON reader never gets an empty stdout).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments (``args.json``).
    payload : dict
        What is known of the request (model, amplitude, ...).
    line : str
        The reason, without the ``gfrf: refused:`` prefix.
    """
    if getattr(args, "json", False):
        print(dumps({**payload, "refused": line}), flush=True)
    print(f"gfrf: refused: {printable(line)}", file=sys.stderr)


def _free_text(value: Any) -> set[str]:
    """The strings in ``value`` (a payload) that hold a character :func:`printable` escapes."""
    if isinstance(value, str):
        return {value} if printable(value) != value else set()
    if isinstance(value, dict):
        return set().union(*map(_free_text, value.values())) if value else set()
    if isinstance(value, (list, tuple)):
        return set().union(*map(_free_text, value)) if value else set()
    return set()


def terminal_text(text: str, payload: Any = None) -> str:
    """``text`` safe for a terminal: text of the payload (a model's name, description,
    input, ...) with its newlines and controls escaped where it appears, then every other
    control character but newline and tab escaped (no ESC sequence, carriage return or
    bidirectional override reaches the terminal).

    Parameters
    ----------
    text : str
        The human-readable result.
    payload : object, optional
        The result payload (dict, list or str); its strings holding control characters
        are escaped where they appear in ``text``.

    Returns
    -------
    str
        ``text`` with every control character but newline and tab escaped.
    """
    for value in sorted(_free_text(payload), key=len, reverse=True):
        text = text.replace(value, printable(value))
    return printable(text, keep="\n\t")
