"""``gfrf show`` and ``gfrf kernel``: the model and its GFRFs (angular frequency in rad/s)."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, emit
from gfrf.errors import ArgumentError

if TYPE_CHECKING:
    import sympy as sp

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``show`` and ``kernel``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    show = subparsers.add_parser(
        "show", help="print a model, its coefficient table and its GFRFs H1..Hn",
        description="Print the polynomial model, its coefficients and the symbolic GFRFs "
                    "H1..Hn in s_i = j*omega_i (rad/s), or q_i = exp(-j*omega_i*T) for NARX.")
    add_model_argument(show)
    show.add_argument("--order", type=int, default=3, help="highest kernel order (default 3)")
    show.add_argument("--latex", action="store_true", help="print the kernels as LaTeX")
    show.add_argument("--asymmetric", action="store_true",
                      help="the asymmetric kernels of the recursion instead of the symmetric")
    add_json_flag(show)
    show.set_defaults(func=_show)

    value = subparsers.add_parser(
        "kernel", help="value of the symmetric kernel Hn at given angular frequencies",
        description="Evaluate H_n(j*w1, ..., j*wn) at angular frequencies in rad/s.")
    add_model_argument(value)
    value.add_argument("--order", type=int, required=True, help="kernel order n")
    value.add_argument("--at", required=True, metavar="W1,...,WN",
                       help="n comma-separated angular frequencies in rad/s")
    value.add_argument("--asymmetric", action="store_true",
                       help="evaluate the asymmetric kernel instead of the symmetric one")
    add_json_flag(value)
    value.add_argument("--max-work", type=int, default=None, metavar="TERMS",
                       help="most symbolic terms of the recursion (default 6000, about 9 s "
                            "on one core; a larger order is refused before the work with "
                            "its estimate)")
    value.set_defaults(func=_kernel)


def _format(expr: sp.Expr, latex: bool) -> str:
    """Exact rationals of the recursion shown as 10-digit decimals."""
    import sympy as sp

    shown = sp.N(expr, 10)
    return sp.latex(shown) if latex else str(shown)


def _show(args: argparse.Namespace) -> int:
    from gfrf.kernels.recursion import check_order, kernel

    mf = resolve_model(args)
    model = mf.plant
    symmetric = not args.asymmetric
    check_order(args.order, "--order")
    rows = []
    for n in range(1, args.order + 1):
        k = kernel(model, n, symmetric)
        rows.append({"order": n, "zero": k.is_zero,
                     "recursive": _format(k.recursive_expr, args.latex),
                     "explicit": _format(k.expr, args.latex) if n <= 3 else None})
    variable = ("q_i = exp(-j*omega_i*T)" if model.is_discrete else "s_i = j*omega_i")
    time_base = (f"discrete, T = {model.sample_time:g} s" if model.is_discrete
                 else "continuous")
    lines = [f"{mf.name}", f"  {model.equation()}",
             f"  {time_base}, degree {model.degree}, max order {model.max_order}", "",
             "  coefficient      monomial          kind"]
    lines += [f"  {r['coefficient']:<+16.8g} {r['monomial']:<17} {r['kind']}"
              for r in model.coefficient_table()]
    lines += ["", f"{'Symmetric' if symmetric else 'Asymmetric'} GFRFs in {variable}:"]
    for r in rows:
        body = "0 (structurally zero)" if r["zero"] else r["recursive"]
        lines.append(f"  H{r['order']} = {body}")
    payload = {"model": mf.to_dict(), "symmetric": symmetric, "variable": variable,
               "kernels": rows}
    emit(args, payload, "\n".join(lines))
    return 0


def _parse_omegas(text: str, order: int) -> list[float]:
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ArgumentError(f"--at must be comma-separated numbers in rad/s, got {text!r}") \
            from None
    if len(values) != order:
        raise ArgumentError(f"--at needs {order} angular frequencies for H{order}, "
                            f"got {len(values)}")
    if not all(math.isfinite(v) for v in values):
        raise ArgumentError(f"--at values must be finite, got {text!r}")
    return values


def _kernel(args: argparse.Namespace) -> int:
    import numpy as np

    from gfrf.kernels.pointwise import point_value
    from gfrf.kernels.recursion import check_order, kernel

    check_order(args.order, "--order")
    mf = resolve_model(args)
    k = kernel(mf.plant, args.order, not args.asymmetric, max_terms=args.max_work)
    omega = _parse_omegas(args.at, args.order)
    point = point_value(k, omega)
    head = f"H{args.order}(j*{omega} rad/s)"
    payload: dict[str, object] = {"order": args.order, "omega": omega,
                                  "symmetric": not args.asymmetric, "model": mf.name,
                                  "method": point.method}
    if point.pole is not None:  # valid input, no finite value: exit 1
        sentence = point.pole.text(mf.plant.is_discrete)
        payload["pole"] = {"block": [i + 1 for i in point.pole.block],
                           "omega": point.pole.omega, "exact": point.pole.exact,
                           "detail": sentence}
        emit(args, payload, f"{head}: no value, H{args.order} has a pole there: {sentence}")
        return 1
    if point.value is None:
        payload["abs_decimal"] = point.magnitude
        emit(args, payload, f"{head}: |H| = {point.magnitude} exceeds the float range")
        return 1
    value = point.value
    payload.update({"re": value.real, "im": value.imag, "abs": abs(value),
                    "phase_deg": float(np.degrees(np.angle(value)))})
    if point.method == "mpmath" and value == 0:
        payload["abs_decimal"] = point.magnitude
    text = (f"{head} = {value.real:.12g} {value.imag:+.12g}j"
            f"   |H| = {abs(value):.12g}, phase = {payload['phase_deg']:.6g} deg")
    if point.method == "mpmath":
        text += f"  (evaluated in 50-digit mpmath: |H| = {point.magnitude})"
    emit(args, payload, text)
    return 0
