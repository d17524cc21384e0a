"""``gfrf transition`` and ``gfrf periodic``: the parametrically excited pendulum.

``gfrf transition --eps E --amplitude A --branch 0|1/4 --method M [--order K] [--json]``
prints ``delta`` on the transition curve for the orbit with ``x(0) = A``
(``--side upper``: the upper boundary of the ``1/4`` tongue, orbit with ``x(0) = 0`` and
turning point ``x(pi) = A``; energy (49), averaging case 3, exact);
``gfrf periodic --eps E [--delta D] --amplitude A --branch ... --method M [--json]``
prints the maximum error of the method's periodic orbit against the shooting orbit
(time dimensionless, excitation angular frequency 1).
"""

from __future__ import annotations

import argparse
import math

from gfrf.cli._output import add_json_flag, emit

__all__ = ["register", "METHODS"]

#: Same as :data:`gfrf.periodic.compare.METHODS` (kept here so that building the parser
#: does not import scipy/sympy; a test asserts equality).
METHODS: tuple[str, ...] = ("perturbation", "homotopy", "energy", "averaging", "exact")


def _common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--eps", type=float, required=True, help="excitation eps = A/L")
    p.add_argument("--amplitude", type=float, required=True,
                   help="x(0) of the periodic orbit (x'(0) = 0), in rad")
    p.add_argument("--branch", default="1/4", choices=["0", "1/4"],
                   help="transition curve through delta = 0 (period 2 pi) or 1/4 (period "
                        "4 pi); default 1/4")
    p.add_argument("--side", default="lower", choices=["lower", "upper"],
                   help="branch 1/4 only: lower curve 1/4 - eps/2 + ... (default; orbit even, "
                        "x'(0) = 0) or upper curve 1/4 + eps/2 + ... (energy (49), averaging "
                        "case 3, exact; orbit odd, x(0) = 0, amplitude = x(pi))")
    p.add_argument("--method", required=True, choices=METHODS, help="solution method")
    p.add_argument("--order", type=int, default=None,
                   help="order for perturbation (powers of eps) or homotopy (deformation "
                        "order); default 4")
    p.add_argument("--equation", default="4", choices=["4", "3"],
                   help="truncated eq (4) or sin(x) eq (3) (all methods but energy; the "
                        "exact orbit solves the same equation); default 4")
    add_json_flag(p)


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``transition`` and ``periodic``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    tr = subparsers.add_parser(
        "transition", help="delta on a transition curve of the parametric pendulum",
        description="delta on the transition curve (branch 0 or 1/4) of "
                    "x'' + (delta + eps cos t)(x - x^3/6) = 0 for the periodic orbit with "
                    "x(0) = amplitude, by one of the paper's methods or exactly (shooting).")
    _common(tr)
    tr.set_defaults(func=_transition)
    pe = subparsers.add_parser(
        "periodic", help="error of a method's periodic orbit against the exact orbit",
        description="Compare the method's periodic orbit with the Newton-shooting orbit of "
                    "eq (4): at equal x(0) = amplitude on the transition curve, or, with "
                    "--delta, at that delta (amplitude then only guesses x(0)).")
    _common(pe)
    pe.add_argument("--delta", type=float, default=None,
                    help="compare at this delta instead of on the exact transition value")
    pe.set_defaults(func=_periodic)


def _transition(args: argparse.Namespace) -> int:
    from gfrf.errors import ArgumentError
    from gfrf.periodic.compare import method_transition
    from gfrf.periodic.equation import check_paper_range

    check_paper_range(args.eps)
    r = method_transition(args.method, args.eps, args.amplitude, branch=args.branch,
                          order=args.order, side=args.side, equation=int(args.equation))
    if math.isnan(r.delta):
        raise ArgumentError(f"{args.method}: no transition value for eps={args.eps}, "
                            f"amplitude={args.amplitude} (eq (48) has no real root)")
    payload = r.to_dict()
    order = f", order {payload['order']}" if payload["order"] is not None else ""
    where = (f"x(0) = {args.amplitude:g}" if args.side == "lower"
             else f"upper side, x(0) = 0, x(pi) = {args.amplitude:g}")
    emit(args, payload,
         f"delta = {payload['delta']:.12g}  ({payload['method']}{order}, branch "
         f"{args.branch}, eps = {args.eps:g}, {where}, eq ({payload['equation']}))")
    return 0


def _periodic(args: argparse.Namespace) -> int:
    from gfrf.errors import ArgumentError
    from gfrf.periodic.compare import compare_periodic
    from gfrf.periodic.equation import check_paper_range

    check_paper_range(args.eps, args.delta)
    r = compare_periodic(args.method, args.eps, args.amplitude, branch=args.branch,
                         order=args.order, delta=args.delta, side=args.side,
                         equation=int(args.equation))
    if math.isnan(r.max_error):
        raise ArgumentError(f"{args.method}: no periodic orbit for eps={args.eps} "
                            f"(its transition equation has no real root)")
    emit(args, r.to_dict(),
         f"max_error = {r.max_error:.3e} over one period; delta {r.delta_method:.10g} "
         f"(exact {r.delta_exact:.10g}, error {r.delta_error:.3e}); "
         f"{'x(0)' if r.side == 'lower' else 'x(pi)'} {r.amplitude_method:.6g} "
         f"(exact {r.amplitude_exact:.6g}); {r.method}, branch "
         f"{r.branch}, {r.side} side, eps = {r.eps:g}, eq ({r.equation})")
    return 0
