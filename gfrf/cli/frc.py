"""``gfrf frc``: the frequency response curve by harmonic balance and continuation.

``gfrf frc MODEL --amplitude A --omega LO:HI [--harmonics H] [--json] [--plot FILE]``
follows the periodic steady states under ``u = A cos(omega t)`` from LO to HI through
their folds, with the stability of every point (Floquet multipliers by Hill's method),
the folds and the backbone.  ``--vary amplitude`` follows them in A from LO to HI
(``--amplitude LO:HI``) at one frequency (``--omega W``).  ``--json`` prints
``{"harmonics", "points": [{"omega", "amplitude", "stable", "coefficients"}], "folds":
[{"omega", "amplitude"}], ...}`` (:meth:`gfrf.harmonic.curve.FrequencyResponseCurve.to_dict`).
Exit 0: the branch reached the end of the range; 1: it stopped before (points ran out,
or no step converged); 2: bad input.
"""

from __future__ import annotations

import argparse
import math

from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, check_plot_path, emit
from gfrf.errors import ArgumentError

__all__ = ["register"]

#: Same as :data:`gfrf.harmonic.curve.DEFAULT_HARMONICS` (the parser imports no numerics).
DEFAULT_HARMONICS = 9
#: Rows of the printed table (the JSON has every point).
TABLE_ROWS = 12


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``frc``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    p = subparsers.add_parser(
        "frc", help="frequency response curve beyond r*: harmonic balance, folds, stability",
        description="Periodic steady states of the model under u = A*cos(omega*t) by "
                    "harmonic balance with H harmonics (exact alternating frequency-time), "
                    "followed by pseudo-arclength continuation through folds; the stability "
                    "of every point from its Floquet multipliers (Hill's method), the folds "
                    "(jump frequencies) and the backbone of the unforced undamped system. "
                    "Estimates: the output says how large the neglected harmonics are. "
                    "Exit 0: the whole range; 1: the branch stopped early; 2: bad input.")
    add_model_argument(p)
    p.add_argument("--amplitude", required=True, metavar="A",
                   help="forcing amplitude A; LO:HI with --vary amplitude")
    p.add_argument("--omega", required=True, metavar="LO:HI",
                   help="frequency range in rad/s; one frequency W with --vary amplitude")
    p.add_argument("--harmonics", type=int, default=DEFAULT_HARMONICS, metavar="H",
                   help=f"harmonics kept (default {DEFAULT_HARMONICS}: the Duffing "
                        f"textbook curves to 1e-6; raise it when the output says so)")
    p.add_argument("--vary", choices=("omega", "amplitude"), default="omega",
                   help="continuation parameter (default omega)")
    p.add_argument("--step", type=float, default=0.02,
                   help="largest arclength step, scaled variables (default 0.02; smaller: "
                        "denser curve)")
    p.add_argument("--max-points", type=int, default=None,
                   help="most points of the branch (default 2000, fewer when many "
                        "harmonics make each point costly)")
    p.add_argument("--plot", metavar="FILE", default=None,
                   help="write the curve (amplitude against omega) to FILE (.png, .svg, ...)")
    add_json_flag(p)
    p.set_defaults(func=_frc)


def _number(option: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ArgumentError(f"{option} {text!r}: not a number") from None
    if not math.isfinite(value):
        raise ArgumentError(f"{option} {text!r}: not a finite number")
    return value


def _range(option: str, text: str) -> tuple[float, float]:
    parts = text.split(":")
    if len(parts) != 2:
        raise ArgumentError(f"{option} {text!r}: expected LO:HI, e.g. 0.5:3")
    return _number(option, parts[0]), _number(option, parts[1])


def _size(value: object) -> str:
    """A summary value: text as it is, a relative size to 2 digits (below 1e-12: the
    last bits of floating point, printed as such so the text is the same everywhere)."""
    if isinstance(value, str):
        return value
    assert isinstance(value, float)
    return "below 1e-12" if value < 1e-12 else f"{value:.2g}"


def _frc(args: argparse.Namespace) -> int:
    check_plot_path(args.plot)
    if args.vary == "omega":
        amplitude: float | tuple[float, float] = _number("--amplitude", args.amplitude)
        omega: float | tuple[float, float] = _range("--omega", args.omega)
    else:
        amplitude = _range("--amplitude", args.amplitude)
        omega = _number("--omega", args.omega)
    mf = resolve_model(args)
    from gfrf.harmonic.curve import frc

    curve = frc(mf.plant, amplitude, omega, harmonics=args.harmonics, vary=args.vary,
                step=args.step, max_points=args.max_points)
    if args.plot:
        _plot(curve, args.plot)
    if isinstance(omega, tuple):
        what = f"u = {amplitude:g}*cos(omega*t), omega from {omega[0]:g} to {omega[1]:g} rad/s"
    else:
        low, high = amplitude if isinstance(amplitude, tuple) else (amplitude, amplitude)
        what = f"u = A*cos({omega:g}*t), A from {low:g} to {high:g}"
    lines = [f"{curve.equation}: frequency response curve under {what}",
             f"  harmonic balance (estimate), H = {curve.harmonics}, {curve.samples} samples "
             f"per period; stability from Floquet multipliers (Hill's method)"]
    lines += [f"  {name}: {_size(value)}" for name, value in curve.summary_rows()[1:]]
    if curve.backbone:
        w, a, _ = curve.backbone[-1]
        lines.append(f"  backbone (unforced, undamped): omega = {curve.backbone[0][0]:.6g} "
                     f"rad/s at amplitude 0 to {w:.6g} rad/s at {a:.6g}")
    lines += [f"  note: {note}" for note in curve.notes]
    lines.append(f"  {'omega':>10s}  {'A':>10s}  {'amplitude':>10s}  stable")
    every = max(1, math.ceil(len(curve.points) / TABLE_ROWS))
    shown = list(curve.points[::every])
    if shown[-1] is not curve.points[-1]:
        shown.append(curve.points[-1])
    lines += [f"  {p.omega:10.6g}  {p.forcing:10.6g}  {p.amplitude:10.6g}  "
              f"{'yes' if p.stable else 'no'}" for p in shown]
    lines.append(f"  ({len(curve.points)} points; --json prints them all with their "
                 f"harmonics)")
    emit(args, curve.to_dict(), "\n".join(lines))
    return 0 if curve.complete else 1


def _plot(curve: object, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from gfrf._atomic import atomic_write_figure

    atomic_write_figure(curve.plot(), path, dpi=110)  # type: ignore[attr-defined]
