"""``gfrf verdict`` and ``gfrf norm``: Theorems 1/2 and GFRF norm brackets (rad/s).

``gfrf verdict MODEL [--order N] [--amplitude R] [--margin PARAM] [--proof LEVEL]
[--norms none|fast|tight] [--json]`` applies
Theorem 2 when the model file has a ``[controller]``, Theorem 1 otherwise; it prints
every condition with pass/FAIL/open and its numbers, the bracket of ||H_n|| for
n = 1..N at the tightness ``--norms`` (default ``fast``: certified majorant upper end,
one local search for the lower end; ``tight``: branch-and-bound; ``none``: no brackets),
the series terms, the certified radius r* and the verdict (the same at every
``--norms``).  Exit code 0:
stability proven; 1: not proven or unstable; 2: bad input.

``gfrf norm MODEL --order N [--tol T] [--asymmetric] [--proof LEVEL] [--json]`` prints
the bracket [lower, upper] of ||H_N||_inf (symmetric kernel unless ``--asymmetric``),
its relative gap, whether it converged and how each end is established.  Infinite norms
print as ``inf`` (JSON ``"inf"``).  Exit code 0 when the bracket converged
(``Bound.converged``: certified, relative gap <= ``--tol``) and the linear part is
asymptotically stable; 1 otherwise (an open bracket, estimates, or the L-infinity norm on
the axis of an unstable linear part, which the line says).

``--proof none|float|interval`` (default ``interval``: it costs about as much as the
float path, see ``gfrf bench``, section "Proof levels") chooses the level of proof;
the text says "proven" only for interval results; the JSON has ``"proof_level"`` (the
level asked: ``--proof`` echoed) and the levels reached: ``"proof"`` beside every bound
(and ``"upper_proof"``, ``"lower_proof"``) and ``"radius_proof"`` beside r*.
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING

from gfrf._results import proof_word
from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, emit, terminal_text
from gfrf.errors import ArgumentError

if TYPE_CHECKING:  # imported where used: building the parser stays cheap
    from gfrf.bounds.norms import Bound
    from gfrf.stability.verdicts import Verdict

__all__ = ["register"]

_PROOF_HELP = ("level of proof asked, echoed as 'proof_level' in --json (the level reached is "
               "'proof', per end 'upper_proof' / 'lower_proof', for r* 'radius_proof': weaker "
               "or stronger than asked): 'interval' (default; proven enclosures in exact "
               "rational and Arb ball arithmetic, measured at about the cost of the float "
               "path), 'float' (the same sound method in double precision, rounding not "
               "accounted for) or 'none' (estimates; never a 'stable' verdict); stability of "
               "the linear part is decided exactly at every level")


def _add_proof(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--proof", choices=("none", "float", "interval"), default="interval",
                        help=_PROOF_HELP)


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``verdict`` and ``norm``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    v = subparsers.add_parser(
        "verdict", help="stability verdict by Theorem 1 (open loop) or 2 (with controller)",
        description="Check every condition of the paper's Theorem 1 (no controller) or "
                    "Theorem 2 (model file with [controller]); the norm series is decided "
                    "by its certified radius of convergence r* in the input amplitude. "
                    "Exit code 0: stability proven, 1: not proven or unstable, 2: bad input.")
    add_model_argument(v)
    v.add_argument("--order", type=int, default=5,
                   help="highest order of the reported norm brackets (default 5)")
    v.add_argument("--amplitude", type=float, default=1.0, metavar="R",
                   help="input amplitude r at which the series is tested (default 1)")
    v.add_argument("--margin", metavar="PARAM", default=None,
                   help="also find the boundary value of this model-file parameter for a "
                        "certified 'stable' verdict at the amplitude")
    v.add_argument("--norms", choices=("none", "fast", "tight"), default="fast",
                   help="tightness of the printed ||H_n|| brackets: 'fast' (default; certified "
                        "majorant upper end, one local search for the lower end), 'tight' "
                        "(adds the branch-and-bound and every local search: slower) or "
                        "'none' (no brackets, no radius estimate); the verdict, r* and the "
                        "conditions do not depend on it")
    v.add_argument("--threshold", action="store_true",
                   help="also print the two-sided answer of 'gfrf threshold' (proven lower "
                        "side, falsified upper side with its witness)")
    _add_proof(v)
    add_json_flag(v)
    v.set_defaults(func=_verdict)

    n = subparsers.add_parser(
        "norm", help="bracket [lower, upper] of the H-infinity norm of H_n",
        description="Bracket ||H_n||_inf = sup over R^n of |H_n(j w_1, .., j w_n)| (rad/s): "
                    "certified upper bound, best-found lower bound. Exit code 0: the "
                    "bracket converged (certified, relative gap <= --tol) and the linear "
                    "part is stable; 1: not converged, estimates, or an unstable linear "
                    "part; 2: bad input.")
    add_model_argument(n)
    n.add_argument("--order", type=int, required=True, help="kernel order n >= 1")
    n.add_argument("--tol", type=float, default=1e-3, help="target relative gap (default 1e-3)")
    n.add_argument("--max-boxes", type=int, default=None, metavar="N",
                   help="work budget of the branch-and-bound, in boxes evaluated (default: "
                        "a cap of about 8 s of work on one core, from the kernel's size; 0 "
                        "skips it; at most 20000000): the bracket depends on it, never on "
                        "time")
    n.add_argument("--asymmetric", action="store_true",
                   help="norm of the asymmetric kernel of the recursion (default symmetric)")
    n.add_argument("--cross-check", action="store_true",
                   help="order 1: also print python-control's norm(sys, 'inf') (imports "
                        "python-control)")
    _add_proof(n)
    add_json_flag(n)
    n.set_defaults(func=_norm)


def _num(x: float | None) -> str:
    if x is None:
        return "-"
    return "inf" if math.isinf(x) else f"{x:.10g}"


def _bound_label(b: Bound) -> str:
    """'proven' only when both ends are interval; a proven upper end whose witness ball
    was too wide to prove the lower end says so."""
    if not b.certified:
        return "estimate"
    if b.proof == "float" and b.upper_proof == "interval":
        return "upper proven, lower float witness"
    return proof_word(b.proof)


def _bound_line(b: Bound) -> str:
    gap = "inf" if math.isinf(b.gap) else f"{b.gap:.2e}"
    kind = ("" if b.stable else
            "  (L-infinity norm on the axis, not H-infinity: linear part unstable)")
    return (f"  ||H{b.order}|| in [{_num(b.lower)}, {_num(b.upper)}]  gap {gap}  "
            f"{_bound_label(b)}{kind}")


def _check_order(order: int) -> None:
    """Refuse an order outside 1..MAX_KERNEL_ORDER before any work."""
    from gfrf.kernels.recursion import check_order

    check_order(order, "--order")


def _norm(args: argparse.Namespace) -> int:
    _check_order(args.order)
    mf = resolve_model(args)
    from gfrf.bounds.branch_bound import BOX_LIMIT, budget_note
    from gfrf.bounds.norms import kernel_norm

    if args.max_boxes is not None and not 0 <= args.max_boxes <= BOX_LIMIT:
        raise ArgumentError(f"--max-boxes must be between 0 and {BOX_LIMIT}, got "
                            f"{args.max_boxes}")
    note = None if args.max_boxes is None else budget_note(mf.plant, args.order,
                                                           not args.asymmetric, args.max_boxes)
    if note:  # said before the work starts (stderr: stdout stays the result)
        print(terminal_text(f"gfrf: note: --{note.replace('_', '-', 1)}"), file=sys.stderr,
              flush=True)
    b = kernel_norm(mf.plant, args.order, not args.asymmetric, args.tol,
                    max_boxes=args.max_boxes,
                    proof=args.proof, cross_check=args.cross_check, progress=None)
    kind = "symmetric" if not args.asymmetric else "asymmetric"
    lines = [f"{mf.name}: {kind} kernel, angular frequencies in rad/s, proof level asked "
             f"{args.proof}, reached {_reached(b)}", _bound_line(b), _converged_line(b),
             f"  attained at w = ({', '.join(f'{w:.8g}' for w in b.argmax)}) rad/s",
             f"  method: {b.method}"]
    if b.reference is not None:
        lines.append(f"  python-control norm(sys, 'inf'): {b.reference:.10g}")
    lines += [f"  note: {note}" for note in b.notes]
    emit(args, {"model": mf.name, "proof_level": args.proof, **b.to_dict()}, "\n".join(lines))
    return 0 if b.stable and b.converged else 1


def _reached(b: Bound) -> str:
    """The proof level reached: the weaker end's, with each end's when they differ."""
    upper, lower = b.upper_proof or b.proof, b.lower_proof or b.proof
    return b.proof if upper == lower else f"{b.proof} (upper end {upper}, lower end {lower})"


def _converged_line(b: Bound) -> str:
    if not b.certified:
        return "  not converged: an estimate (proof level none) is never converged"
    gap = "inf" if math.isinf(b.gap) else f"{b.gap:.3g}"
    return (f"  converged: gap {gap} <= tol {b.tol:g}" if b.converged
            else f"  not converged: gap {gap} > tol {b.tol:g}")


def _mark(passed: bool | None) -> str:
    return {True: "pass", False: "FAIL", None: "open"}[passed]


def _verdict_text(name: str, v: Verdict, proof: str = "") -> list[str]:
    kind = "open loop" if v.theorem == 1 else "closed loop"
    level = f", proof level {proof}" if proof else ""
    lines = [f"{name}: Theorem {v.theorem} ({kind}), amplitude r = {v.amplitude:g}{level}",
             *([f"loop: {v.loop}"] if v.loop else []), "", "Conditions:"]
    lines += [f"  [{_mark(c.passed)}] {c.name}: {c.detail}" for c in v.conditions]
    plant = "the plant's " if v.loop else ""  # Theorem 2: these are the plant's numbers
    if v.norms:
        lines += ["", f"Norms ({plant}symmetric kernels, rad/s):"] + [_bound_line(b)
                                                                      for b in v.norms]
    lines += ["", f"Series ({plant}majorant M_n >= ||H_n||, term M_n r^n"
              + (" at plant input amplitude r; loop: theta_n rho_1^n r^n, reference r):"
                 if v.loop else "):")]
    for row in v.series:
        extra = (f"  theta_n rho_1^n r^n = {_num(row['theta_term'])}"
                 if "theta_term" in row else "")
        lines.append(f"  n = {row['order']}: M_n = {_num(row['majorant'])}, "
                     f"term = {_num(row['majorant_term'])}{extra}")
    lines += ["", f"radius (lower bound r*, {v.radius_kind}): {_num(v.radius)}"
              + (" (units of the reference r)" if v.loop else "")]
    if v.loop_radius_upper is not None:
        lines.append(f"loop radius_upper (proven upper bound of the loop's true radius, units "
                     f"of r): {_num(v.loop_radius_upper)}")
    if v.radius_upper is not None:
        lines.append(f"radius_upper (proven upper bound of the {v.estimate_of}): "
                     f"{_num(v.radius_upper)}")
    if v.radius_estimate is not None:
        lines.append(f"radius_estimate (estimate of the true radius of the {v.estimate_of}; "
                     f"not a proof): {v.radius_estimate:.4g}")
    lines += [f"verdict: {v.verdict}", v.summary]
    return lines


def _verdict(args: argparse.Namespace) -> int:
    _check_order(args.order)
    mf = resolve_model(args)
    from gfrf.stability.criteria import parameter_margin, verdict

    v = verdict(mf, args.order, args.amplitude, proof=args.proof, norms=args.norms)
    payload = {"model": mf.name, "proof_level": args.proof, "norms_level": args.norms,
               **v.to_dict()}
    lines = _verdict_text(mf.name, v, args.proof)
    if args.margin:
        margin = parameter_margin(mf, args.margin, args.amplitude)
        payload["margin"] = margin.to_dict()
        lines.append(f"margin: certified stable for {margin.parameter} {margin.direction} "
                     f"{margin.value:.6g} at r = {margin.amplitude:g} (file value "
                     f"{margin.current:g})")
    if args.threshold:
        from gfrf.twosided.threshold import threshold

        t = threshold(mf, order=args.order)
        both = t.verdict_at(args.amplitude)
        payload["threshold"] = {**t.to_dict(), "verdict_at_amplitude": both}
        lines += ["", "Threshold:", t.text(),
                  f"two-sided verdict at r = {args.amplitude:g}: {both}"]
        return _emit_exit(args, payload, lines, both)
    return _emit_exit(args, payload, lines, v.verdict)


def _emit_exit(args: argparse.Namespace, payload: dict, lines: list[str], verdict: str) -> int:
    emit(args, payload, "\n".join(lines))
    return 0 if verdict == "stable" else 1
