"""Command-line interface ``gfrf``: argument parsing, printing, exit codes; no mathematics.

Each feature registers its sub-commands from its own module (``gfrf.cli.<feature>``),
listed in :data:`COMMAND_MODULES`.  Every command that prints results accepts
``--json``.  Exit codes: 0 success (for ``verdict``: stability proven), 1 a
negative or inconclusive answer, 2 bad input.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from gfrf.errors import GfrfError

__all__ = ["main", "build_parser", "COMMAND_MODULES"]

#: Modules that each define ``register(subparsers)``; one line per feature.
COMMAND_MODULES: tuple[str, ...] = (
    "gfrf.cli.core",
    "gfrf.cli.bench",
    "gfrf.cli.simulation",
    "gfrf.cli.stability",
    "gfrf.cli.report",
    "gfrf.cli.periodic",
    "gfrf.cli.sweep",
    "gfrf.cli.identify",
)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors exit with code 2 and a one-line message."""

    def error(self, message: str) -> None:  # noqa: D401 - argparse API
        self.exit(2, f"gfrf: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every registered sub-command."""
    parser = _Parser(
        prog="gfrf",
        description="Stability of polynomial nonlinear systems from their generalized "
        "frequency response functions. Angular frequencies are in rad/s.",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    subparsers.required = True
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the process exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except GfrfError as exc:
        print(f"gfrf: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"gfrf: error: {exc.strerror or exc}: {exc.filename or ''}".rstrip(": "),
              file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
