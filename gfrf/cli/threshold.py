"""``gfrf threshold``: stable below ``lower`` (proven), unstable at ``upper`` (a witness).

``gfrf threshold MODEL [--order N] [--json]`` prints the largest proven radius with its
certificate (Theorem 1 or 2's r*, the energy certificate of a damped hardening
oscillator, the exactly re-checked sum-of-squares certificates), the smallest escaping
bounded input the falsifier found (the witness: a switching input or a sum of tones, its
escape time, what escape meant, and whether its escape is proven) and the answer in
words; a progress bar on stderr when it is a terminal.  ``--json`` prints the JSON
contract (``lower`` is the string ``"inf"`` for a global certificate, as everywhere in
the CLI's JSON).  Exit code 0: both sides closed (``Threshold.answered``: a proven
``lower > 0`` that is global or met by a witness, or an exactly decided unstable
equilibrium); 1: nothing proven below (``lower = 0``), or no escape found up to the
search cap and no global certificate (unknown above ``lower``); 2: bad input.
``--certificate-out FILE`` writes the certificate behind ``lower`` (sum-of-squares,
NARX invariant box or paving) as exact rationals; ``gfrf certificate check MODEL FILE``
re-verifies it (exit 0 holds, 1 refused, 2 a malformed file or one for another model).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from typing import Any

from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, check_output_file, emit, terminal_text

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``threshold``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    p = subparsers.add_parser(
        "threshold", help="two-sided answer: proven-stable amplitude and escaping witness",
        description="Stable below 'lower' for every input with sup|u| <= lower (for a loop: "
                    "every reference with sup|r| <= lower, u = C(r - y); proven by an energy "
                    "or an exactly re-checked sum-of-squares certificate; Theorem 1/2's r*, "
                    "for sums of tones only, is listed beside it), unstable at 'upper' (a "
                    "switching input u = +-U or a sum of tones, switched on at t = 0, whose "
                    "response from rest escapes: a witness, proven when its Arb enclosure "
                    "enters the escape region), unknown in between. Exit code 0: both sides "
                    "closed (a proven lower > 0, global or met by a witness; or an "
                    "unstable equilibrium); 1: nothing proven below, or no escape found "
                    "up to the search cap; 2: bad input.")
    add_model_argument(p)
    p.add_argument("--order", type=int, default=5,
                   help="order of the verdict behind r* (default 5)")
    p.add_argument("--certificate-out", metavar="FILE",
                   help="write the certificate behind 'lower' as JSON, every number an "
                        "exact rational: a sum-of-squares one (V, multipliers, U, c, the "
                        "state map) or a NARX invariant box or paving (U, coordinates, box "
                        "or cells); re-check it with 'gfrf certificate check MODEL FILE'")
    add_json_flag(p)
    p.set_defaults(func=_threshold)
    c = subparsers.add_parser(
        "certificate", help="re-verify a certificate file from scratch",
        description="'gfrf certificate check MODEL FILE' rebuilds the model's state form and "
                    "re-verifies the certificate in exact rational arithmetic, without a "
                    "search: a sum-of-squares file's polynomial identity and Gram "
                    "matrices, a NARX box's or paving's inclusion of the image of every "
                    "cell. Exit 0: it holds; 1: refused; 2: bad input (a malformed file, a "
                    "number or size above a stated limit, a NARX file for another model).")
    sub = c.add_subparsers(dest="action", required=True)
    chk = sub.add_parser("check", help="re-verify a certificate for a model")
    add_model_argument(chk)
    chk.add_argument("file", help="the certificate (JSON) written by --certificate-out")
    add_json_flag(chk)
    chk.set_defaults(func=_check)


def _check(args: argparse.Namespace) -> int:
    mf = resolve_model(args)
    from gfrf.stability.sos_check import check_certificate

    result = check_certificate(mf, args.file)
    emit(args, result.to_dict(), result.text())
    return 0 if result.valid else 1


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
    check_output_file("--certificate-out", args.certificate_out)
    mf = resolve_model(args)
    from gfrf.twosided.threshold import threshold

    update, bar = _progress()
    try:
        result = threshold(mf, order=args.order, progress=update)
    finally:
        if bar is not None:
            bar.close()
    emit(args, result.to_dict(), result.text())
    if args.certificate_out is not None:
        from gfrf._atomic import atomic_write_text

        if result.certificate_file is None:
            print(terminal_text(f"no certificate file to write to {args.certificate_out!r} "
                                f"(lower's method, {result.lower_method}, has none)"),
                  file=sys.stderr)
        else:
            atomic_write_text(args.certificate_out,
                              json.dumps(result.certificate_file, indent=1) + "\n")
    return 0 if result.answered else 1
