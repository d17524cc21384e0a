"""``gfrf report``: regenerate the Markdown reports and their figures.

``gfrf report [--out reports/] [--quick] [MODEL ...] [--json]``: with no MODEL, the
paper reports, one verdict page per bundled model and an index; with MODEL
arguments (model files), only those models' pages.
"""

from __future__ import annotations

import argparse

from gfrf.cli._output import add_json_flag, check_output_folder, emit
from gfrf.errors import ModelError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``report``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    rep = subparsers.add_parser(
        "report", help="regenerate the Markdown reports (paper reproduction, model pages)",
        description="Write OUT/paper-gfrf.md, OUT/paper-periodic.md, OUT/models/<model>.md "
                    "and their PNG figures, deterministically. With MODEL arguments, only "
                    "those models' verdict pages.")
    rep.add_argument("models", nargs="*", metavar="MODEL", help="model files (default: all)")
    rep.add_argument("--out", default="reports", help="output folder (default reports/)")
    rep.add_argument("--quick", action="store_true",
                     help="reduced setting (norm order 3, 20 s simulations), for tests")
    add_json_flag(rep)
    rep.set_defaults(func=_report)


def _report(args: argparse.Namespace) -> int:
    from gfrf.report import write_reports

    for m in args.models:
        if not m.endswith(".toml"):
            raise ModelError(f"gfrf report takes model files (*.toml), got {m!r}")
    check_output_folder("--out", args.out)
    paths = write_reports(args.out, args.models or None, args.quick)
    emit(args, {"written": [str(p) for p in paths]},
         "\n".join(f"wrote {p}" for p in paths))
    return 0
