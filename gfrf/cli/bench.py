"""``gfrf bench [--out DIR]``: run the speed-vs-error benchmarks; with ``--out``, write
``DIR/speed-vs-error.md`` and its figures (nothing is written without it).  Runs from
any directory: the bundled models are found next to the package
(:data:`gfrf.bench.MODELS_DIR`)."""

from __future__ import annotations

import argparse

from gfrf.cli._output import add_json_flag, check_output_folder, emit

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``bench``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    bench = subparsers.add_parser(
        "bench", help="time each kernel against its naive baseline; write speed-vs-error.md",
        description="Measure time and error of every computational kernel and of the naive "
                    "baseline in the same run; write OUT/speed-vs-error.md.")
    bench.add_argument("--out", default=None, metavar="DIR",
                       help="write DIR/speed-vs-error.md and its figures (default: write "
                            "nothing, print the tables; `make bench` passes reports/)")
    bench.add_argument("--quick", action="store_true", help="small sizes, for a smoke test")
    bench.add_argument("--only", action="append", metavar="NAME",
                       help="run only the sections whose module name contains NAME")
    add_json_flag(bench)
    bench.set_defaults(func=_bench)


def _bench(args: argparse.Namespace) -> int:
    from gfrf.bench import run_all, write_report

    if args.out is not None:
        check_output_folder("--out", args.out)
    sections = run_all(quick=args.quick, only=args.only, out_dir=args.out)
    path = None if args.out is None else write_report(sections, args.out)
    payload = {"report": None if path is None else str(path),
               "sections": [{"title": s.title, "columns": s.columns, "rows": s.rows,
                             "notes": s.notes} for s in sections]}
    emit(args, payload, "\n".join(s.to_markdown() for s in sections)
         + ("" if path is None else f"\nwrote {path}"))
    return 0
