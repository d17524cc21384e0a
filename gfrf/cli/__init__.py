"""Command-line interface ``gfrf``: argument parsing, printing, exit codes; no mathematics.

Each feature registers its sub-commands from its own module (``gfrf.cli.<feature>``),
listed in :data:`COMMAND_MODULES`.  Every command that prints results accepts
``--json``.  Exit codes: 0 success (for ``verdict``: stability proven), 1 a
negative or inconclusive answer or a computation that found no answer (a
:class:`gfrf.errors.ConvergenceError`: the input was valid), 2 bad input only.

May import: everything (it is the top layer); nothing imports it.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
import warnings
from collections.abc import Sequence
from typing import Any

from gfrf import __version__
from gfrf.errors import ConvergenceError, GfrfError

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
    "gfrf.cli.estimate",
    "gfrf.cli.ofrf",
    "gfrf.cli.plot",
    "gfrf.cli.threshold",
    "gfrf.cli.frc",
)


class _Parser(argparse.ArgumentParser):
    """ArgumentParser whose usage errors exit with code 2 and a one-line message.

    Values that start with a minus and a digit (``--at -1.5,1.5,1.5``,
    ``--initial -0.26,0``, ``--amplitude -.5``) are values, not options: none of our
    options looks like a negative number.  (Python 3.13's argparse does the same.)
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str) -> None:
        self.exit(2, f"gfrf: error: {_one_line(message)}\n")


def build_parser() -> argparse.ArgumentParser:
    """Build the top-level parser with every registered sub-command."""
    parser = _Parser(
        prog="gfrf",
        description="Stability of polynomial nonlinear systems from their generalized "
        "frequency response functions. Angular frequencies are in rad/s.",
    )
    parser.add_argument("--version", action="version", version=f"gfrf {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    subparsers.required = True
    for name in COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def _run(argv: Sequence[str] | None) -> int:
    """Parse ``argv`` and run the command; errors of the user's making become exit 2."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except ConvergenceError as exc:  # valid input, the computation found no answer: exit 1
        if getattr(args, "json", False):
            from gfrf._results import dumps

            print(dumps({"command": args.command, "error": str(exc)}), flush=True)
        print(f"gfrf: error: {_one_line(str(exc))}", file=sys.stderr)
        return 1
    except GfrfError as exc:
        print(f"gfrf: error: {_one_line(str(exc))}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise  # the reader went away: handled quietly by main
    except OSError as exc:
        print(_one_line(f"gfrf: error: {exc.strerror or exc}: {exc.filename or ''}"
                        .rstrip(": ")), file=sys.stderr)
        return 2


def _warning_line(message: Warning | str, category: type[Warning], filename: str,
                  lineno: int, line: str | None = None) -> str:
    """A warning as one line ``gfrf: warning: ...`` (no source path, no code line)."""
    return f"gfrf: warning: {_one_line(' '.join(str(message).split()))}\n"


def _one_line(text: str) -> str:
    """``text`` with every control character escaped, newlines included: one line on a
    terminal (user text may be in it)."""
    from gfrf.model.safetext import printable

    return printable(text)


def _interrupted(own_command_line: bool) -> int:
    """Say ``gfrf: interrupted`` and give exit code 130.  Run as the process's own
    command (``argv`` from ``sys.argv``), the process ends here: the work has unwound
    (outputs untouched, worker processes killed), the exit handlers run, and the
    interpreter's teardown of the numerical modules, which would keep a Ctrl-C waiting
    another 0.5-0.8 s, is skipped."""
    print("gfrf: interrupted", file=sys.stderr)
    if own_command_line:
        import atexit

        atexit._run_exitfuncs()  # the exit handlers (multiprocessing's among them) still run
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):  # a closed or gone reader: nothing to flush to
                pass
        os._exit(130)
    return 130


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the process exit code.

    Warnings are printed as one line ``gfrf: warning: ...``.  Ctrl-C exits with 130
    and the one line ``gfrf: interrupted`` (files being written are left as they
    were: outputs are replaced atomically); called without ``argv`` (the ``gfrf``
    command) the process then ends at once (``os._exit``).  A closed stdout (``gfrf ... | head``)
    exits quietly with 141, as a process killed by SIGPIPE.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after the program name; ``None`` reads ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit code: 0 answered, 1 not proven / not converged, 2 bad input,
        130 interrupted, 141 closed stdout.
    """
    formatwarning = warnings.formatwarning  # formatting only: recorders still record
    warnings.formatwarning = _warning_line
    try:
        try:
            return _run(argv)
        finally:
            warnings.formatwarning = formatwarning
            sys.stdout.flush()  # a reader that went away shows up here, not at exit
    except KeyboardInterrupt:
        return _interrupted(argv is None)
    except SystemError as exc:
        # Ctrl-C that lands while compiled code calls back into Python (numba boxing a
        # result) surfaces as a SystemError caused by the KeyboardInterrupt
        if not isinstance(exc.__cause__, KeyboardInterrupt):
            raise
        return _interrupted(argv is None)
    except BrokenPipeError:
        # Python flushes stdout again at exit: point it at /dev/null so that it is quiet.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return 141


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
