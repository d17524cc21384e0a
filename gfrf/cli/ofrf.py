"""``gfrf ofrf``: the output spectrum at one frequency as a polynomial in a parameter.

``gfrf ofrf MODEL --param NAME --input TEXT --omega W --order N`` prints the OFRF
coefficients (complex amplitude ``amplitude*exp(j*phase)`` of the output component at
W, as ``gfrf predict`` prints it, = sum coefficients[k]*NAME**k) and the NOFRFs of the
same input at the file's value of NAME.  MODEL is a model file whose ``[parameters]``
holds NAME, or an equation text with ``--param NAME=VALUE``.  Exit 0 on success, 2 for
bad input (unknown parameter, a parameter in the linear output part, a plant without a
steady state, an input that is not a sum of tones).
"""

from __future__ import annotations

import argparse
import cmath
import math
import sys
from typing import Any

from gfrf.cli._output import add_json_flag, emit, terminal_text
from gfrf.errors import ArgumentError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``ofrf``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    cmd = subparsers.add_parser(
        "ofrf", help="output frequency response function: Y(jW) as a polynomial in a parameter",
        description="Lang & Billings' OFRF: the complex amplitude of the steady-state output "
                    "at W (rad/s) for a sum of tones, as a polynomial in one parameter of "
                    "the model file (it may enter every term except the linear output "
                    "part), computed by the GFRF recursion up to --order (not fitted); "
                    "and the NOFRFs G_n(jW) = Y_n(W)/U_n(W) at the file's value.  The "
                    "coefficients are the exact order-N truncation (an estimate of the "
                    "steady state, valid below the series radius r*).")
    cmd.add_argument("model", metavar="MODEL",
                     help="a model file with a [parameters] table, or an equation in quotes "
                          "that uses the parameter, e.g. 'D(y,2) + 0.2*D(y) + y + c*y**3 = u'")
    cmd.add_argument("--param", required=True, metavar="NAME[=VALUE]",
                     help="the parameter; =VALUE sets its value (needed for an inline "
                          "equation; overrides the file's)")
    cmd.add_argument("--sample-time", type=float, default=None, metavar="T",
                     help="sample time in s when MODEL is an inline discrete (NARX) equation")
    cmd.add_argument("--input", required=True, metavar="TEXT",
                     help="a sum of tones, e.g. '0.1*cos(1.0*t)'")
    cmd.add_argument("--omega", required=True, type=float, metavar="W",
                     help="output frequency in rad/s (a harmonic or intermodulation "
                          "frequency of the input)")
    cmd.add_argument("--order", type=int, default=5, help="truncation order N (default 5; up to "
                     "MAX_OFRF_ORDER = 64 as MAX_OFRF_WORK allows)")
    add_json_flag(cmd)
    cmd.set_defaults(func=_ofrf)


def _pair(z: complex) -> str:
    return f"{z.real:+.10g} {z.imag:+.10g}j"


def _truncation_line(o: Any, size: float) -> str:
    """The truncation error bound at the file's value, or why there is none."""
    if o.truncation_bound == math.inf:
        return (f"  truncation error: not bounded (input amplitude {o.amplitude:.6g} not "
                f"below the certified series radius): simulate instead")
    relative = o.truncation_bound / size if size > 0 else math.inf
    return (f"  truncation error (orders > {o.order}) at {o.parameter} = {o.value:.6g}: "
            f"at most {o.truncation_bound:.3g} ({relative:.3g} relative, "
            f"{o.truncation_proof}); for a smaller error simulation + a fit is the better tool")


def _ofrf(args: argparse.Namespace) -> int:
    from gfrf.model.modelfile import looks_like_path, read_table
    from gfrf.model.signals import parse_input
    from gfrf.sim.ofrf import check_ofrf_order, ofrf

    check_ofrf_order(args.order, "--order")
    name, eq, text = args.param.partition("=")
    name = name.strip()
    value = None
    if eq:
        try:
            value = float(text)
        except ValueError:
            raise ArgumentError(f"--param {args.param!r}: the value after = must be a "
                                f"number") from None
    args.param = name
    if looks_like_path(args.model):
        from gfrf.model.modelfile import bundled_or_path

        args.model = bundled_or_path(args.model)
        data = dict(read_table(args.model))
        if value is not None:
            data["parameters"] = {**(data.get("parameters") or {}), name: value}
    elif value is None:
        raise ArgumentError(f"MODEL {args.model!r}: an inline equation needs the value of "
                            f"its parameter, --param {name}=VALUE (or a model file whose "
                            f"[parameters] table holds {name})")
    else:
        data = {"equation": args.model, "name": "inline model", "parameters": {name: value}}
        if args.sample_time is not None:
            data["sample_time"] = args.sample_time
    signal = parse_input(args.input)
    if not signal.tones:
        raise ArgumentError(f"--input {args.input!r} is not a sum of sinusoids "
                            f"A*sin(w*t + p) / A*cos(w*t + p)")
    o = ofrf(data, args.param, signal.tones, args.omega, args.order, path=args.model)
    if o.warning:
        print(terminal_text(f"gfrf: warning: {o.warning}"), file=sys.stderr)
    name = data.get("name") or args.model
    at = o(o.value)
    lines = [f"{name}: output at omega = {o.omega:.6g} rad/s for {args.input}, order "
             f"{o.order}",
             f"  complex amplitude (amplitude*exp(j*phase), as gfrf predict) = "
             f"sum P_k * {o.parameter}**k:",
             "  k   P_k"]
    lines += [f"  {k:<3d} {_pair(c)}" for k, c in enumerate(o.coefficients)]
    lines.append(f"  at {o.parameter} = {o.value:.6g} (estimate: the series truncated at "
                 f"order {o.order}): amplitude {abs(at):.6g}, phase "
                 f"{cmath.phase(at):+.6f} rad; input amplitude "
                 f"{o.amplitude:.6g}, series radius r* = {o.radius:.6g}")
    lines.append(_truncation_line(o, abs(at)))
    lines.append(f"  NOFRFs G_n(j{o.omega:.6g}) = Y_n/U_n at {o.parameter} = {o.value:.6g}:")
    for n, g in o.nofrf().items():
        lines.append(f"  n = {n:<2d} " + ("undefined (U_n = 0 at this frequency)"
                                          if g is None else _pair(g)))
    payload: dict[str, Any] = {"model": name, "input": args.input, **o.to_dict()}
    emit(args, payload, "\n".join(lines))
    return 0
