"""``gfrf plot``: a picture of the kernel H_n of a model, written to a file.

``gfrf plot MODEL --order N [--range W] [--what magnitude|phase] --out FILE`` draws the
Bode plot of H1, the |H2(jw1, jw2)| map (log colour scale), or for N >= 3 the
diagonal slice and a 2-D slice with the other frequencies fixed (stated on the
figure), on a grid that adapts to the resonances, and marks where the sup found by
``gfrf norm`` sits (``--no-mark`` skips that search).  The figure format follows the
suffix of FILE (png, svg, pdf, ...); it is written atomically with matplotlib's Agg
backend.  Exit 0 on success, 2 for bad input.
"""

from __future__ import annotations

import argparse
from typing import Any

from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, check_plot_path, emit
from gfrf.errors import ArgumentError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``plot``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    cmd = subparsers.add_parser(
        "plot", help="picture of the kernel H_n (Bode of H1, |H2| map, slices of Hn)",
        description="Draw H_n of a model (rad/s): H1 as a Bode plot (dB, degrees), H2 as "
                    "a map of |H2(j w1, j w2)| on a log colour scale, Hn >= 3 as the "
                    "diagonal slice and a 2-D slice with w3..wn fixed.  The grid adapts to "
                    "the resonances; the sup of |H_n| found by gfrf norm is marked.")
    add_model_argument(cmd)
    cmd.add_argument("--order", type=int, required=True, help="kernel order n >= 1")
    cmd.add_argument("--range", type=float, default=None, metavar="W", dest="omega_range",
                     help="largest angular frequency in rad/s (default: from the resonances; "
                          "NARX: the Nyquist frequency pi/T)")
    cmd.add_argument("--what", choices=("magnitude", "phase"), default="magnitude",
                     help="what the maps and slices show (H1 always shows both)")
    cmd.add_argument("--out", required=True, metavar="FILE",
                     help="figure file; the format follows the suffix (.png, .svg, .pdf, ...)")
    cmd.add_argument("--no-mark", action="store_true",
                     help="do not search the sup of |H_n| (gfrf norm) to mark it")
    add_json_flag(cmd)
    cmd.set_defaults(func=_plot)


def _plot(args: argparse.Namespace) -> int:
    check_plot_path(args.out)
    from gfrf.kernels.recursion import check_order

    check_order(args.order, "--order")
    if args.omega_range is not None and not 0 < args.omega_range < float("inf"):
        raise ArgumentError(f"--range must be a positive frequency in rad/s, got "
                            f"{args.omega_range}")
    mf = resolve_model(args)
    import matplotlib

    matplotlib.use("Agg")  # never a window, whatever MPLBACKEND says

    from gfrf._atomic import atomic_write_figure
    from gfrf.kernels.recursion import kernel

    k = kernel(mf.plant, args.order)
    mark = None
    sup = None
    sup_proof = None
    if not args.no_mark and not k.is_zero:
        from gfrf.bounds.norms import kernel_norm

        bound = kernel_norm(mf.plant, args.order, proof="float")
        if bound.argmax and all(abs(w) < float("inf") for w in bound.argmax):
            mark, sup, sup_proof = tuple(bound.argmax), bound.lower, bound.lower_proof
    fig = k.plot(omega_range=args.omega_range, what=args.what, mark=mark)
    atomic_write_figure(fig, args.out, dpi=110)
    payload: dict[str, Any] = {"model": mf.name, "order": args.order, "what": args.what,
                               "out": args.out, "zero": k.is_zero, "sup_at": mark,
                               "sup": sup, "sup_proof": sup_proof}
    text = f"{mf.name}: H{args.order} ({args.what}) written to {args.out}"
    if mark is not None:
        text += (f"; sup |H{args.order}| = {sup:.6g} at "
                 f"({', '.join(f'{w:.6g}' for w in mark)}) rad/s marked (the witness of "
                 f"gfrf norm: a lower bound of ||H{args.order}||, {sup_proof})")
    emit(args, payload, text)
    return 0
