"""``gfrf threshold``: stable below ``lower`` (proven), unstable at ``upper`` (a witness).

``gfrf threshold MODEL [--order N] [--json]`` prints the largest proven radius with its
certificate (Theorem 1 or 2's r*, the energy certificate of a damped hardening
oscillator), the smallest escaping sum of tones the falsifier found (the witness, its
escape time and what escape meant) and the answer in words; a progress bar on stderr
when it is a terminal.  ``--json`` prints the JSON contract (``lower`` is the
string ``"inf"`` for a global certificate, as everywhere in the CLI's JSON).  Exit
code 0: both sides closed (a global certificate, or a witness); 1: no escape found up
to the search cap and no global certificate (unknown above ``lower``); 2: bad input.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable
from typing import Any

from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, emit

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``threshold``."""
    p = subparsers.add_parser(
        "threshold", help="two-sided answer: proven-stable amplitude and escaping witness",
        description="Stable below 'lower' (proven: Theorem 1/2's r* or an energy "
                    "certificate for every bounded input), unstable at 'upper' (a sum of "
                    "tones switched on at t = 0 whose response from rest escapes: a "
                    "simulation witness), unknown in between. Exit code 0: both sides "
                    "closed; 1: no escape found up to the search cap; 2: bad input.")
    add_model_argument(p)
    p.add_argument("--order", type=int, default=5,
                   help="order of the verdict behind r* (default 5)")
    add_json_flag(p)
    p.set_defaults(func=_threshold)


def _progress() -> tuple[Callable[[int, int], None] | None, Any]:
    """A tqdm bar on stderr when it is a terminal, else nothing."""
    if not sys.stderr.isatty():
        return None, None
    from tqdm import tqdm

    bar = tqdm(total=1, desc="falsifier", unit="shape", leave=False, file=sys.stderr)

    def update(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()

    return update, bar


def _threshold(args: argparse.Namespace) -> int:
    from gfrf.kernels.recursion import check_order

    check_order(args.order, "--order")
    mf = resolve_model(args)
    from gfrf.twosided.threshold import threshold

    update, bar = _progress()
    try:
        result = threshold(mf, order=args.order, progress=update)
    finally:
        if bar is not None:
            bar.close()
    emit(args, result.to_dict(), result.text())
    closed = math.isinf(result.lower) or result.upper is not None
    return 0 if closed else 1
