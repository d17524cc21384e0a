"""``gfrf multisine`` and ``gfrf estimate``: measurements without a model.

``gfrf multisine --period N --sample-time T --out FILE.csv [--grid random-odd|isolating]
[--realisations M] [--periods P] [--rms R] [--levels 1,0.5] [--seed S] [--json]`` writes
an odd random-phase multisine (columns ``t,u,realisation``) and prints its grid.

``gfrf estimate DATA.csv --period N [--skip-periods K] [--model MODEL] [--plot FILE]
[--json]`` reads measured ``t,u,y[,realisation]`` and prints the best linear
approximation on the excited lines with its total, noise and distortion standard
deviations, the detection of even and odd distortion, and H2, H3 on the lines the
excitation isolates (:func:`gfrf.identify.nonparametric.estimate_gfrf`).  Exit codes: 0
answered, 2 bad input.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from gfrf.cli._output import add_json_flag, check_output_file, check_plot_path, emit
from gfrf.errors import ArgumentError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``multisine`` and ``estimate``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    m = subparsers.add_parser(
        "multisine", help="write an odd random-phase multisine excitation (CSV t,u,realisation)",
        description="Design an odd random-phase multisine: the random-odd grid (one odd line "
                    "in three left out, even lines free: detection of even and odd "
                    "distortion) or the isolating grid (sparse odd lines whose sums and "
                    "differences of two and three fall on lines of their own: H2 and H3 "
                    "there); several realisations (new phases) and periods, optionally at "
                    "several input levels. Writes t,u,realisation (t restarts in each "
                    "realisation) and prints the grid gfrf estimate expects.")
    m.add_argument("--period", type=int, required=True, metavar="N",
                   help="samples per period")
    m.add_argument("--sample-time", type=float, required=True, metavar="T",
                   help="sample time in s")
    m.add_argument("--out", required=True, metavar="FILE.csv", help="the CSV to write")
    m.add_argument("--grid", default="random-odd", choices=("random-odd", "isolating"),
                   help="frequency grid (default random-odd)")
    m.add_argument("--max-line", type=int, default=None, metavar="K",
                   help="highest excited line (default N/8, isolating N/6 - 1)")
    m.add_argument("--realisations", type=int, default=4, metavar="M",
                   help="phase realisations at each level (default 4)")
    m.add_argument("--periods", type=int, default=3, metavar="P",
                   help="periods of each realisation, the first for the transient "
                        "(default 3)")
    m.add_argument("--rms", type=float, default=1.0, help="RMS value of u (default 1)")
    m.add_argument("--levels", default="1", metavar="L1,L2,...",
                   help="input levels relative to --rms, e.g. 1,0.5: estimates are then "
                        "extrapolated to zero amplitude (default 1)")
    m.add_argument("--seed", type=int, default=0, help="seed of the phases (default 0)")
    add_json_flag(m)
    m.set_defaults(func=_multisine)

    e = subparsers.add_parser(
        "estimate", help="best linear approximation, its noise and distortion levels, and "
                         "nonparametric H2, H3 from periodic (multisine) data",
        description="Nonparametric estimates from measured periodic data: a CSV with "
                    "columns t,u,y and optionally realisation (an integer; each realisation "
                    "starts its own time axis and holds consecutive periods). Prints the "
                    "best linear approximation on the excited lines (those where |U| is "
                    "significantly non-zero) with the standard deviations of the estimate: "
                    "total (realisation to realisation), noise (period to period) and "
                    "nonlinear distortion (their difference); the even and odd distortion "
                    "seen on the non-excited lines; and H2, H3 on the lines the excitation "
                    "isolates. One input and one output only (MISO/MIMO data are refused). "
                    "Exit code 0: answered; 2: bad input.")
    e.add_argument("data", metavar="DATA.csv", help="CSV with columns t,u,y[,realisation]")
    e.add_argument("--period", type=int, required=True, metavar="N",
                   help="period in samples")
    e.add_argument("--skip-periods", type=int, default=0, metavar="K",
                   help="periods dropped at the start of each realisation (transients; "
                        "default 0)")
    e.add_argument("--model", default=None, metavar="MODEL",
                   help="a model file (or equation) whose GFRFs are compared with the "
                        "estimates on the same lines")
    e.add_argument("--sample-time", type=float, default=None, metavar="T",
                   help="sample time in s when --model is an inline discrete equation")
    e.add_argument("--plot", default=None, metavar="FILE.png",
                   help="write the figure: BLA with its levels, detection, H2 and H3")
    add_json_flag(e)
    e.set_defaults(func=_estimate)


def _levels(text: str) -> tuple[float, ...]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ArgumentError(f"--levels must be numbers separated by commas, got "
                            f"{text!r}") from None
    if not all(math.isfinite(v) for v in values):
        raise ArgumentError(f"--levels must be finite numbers, got {text!r}")
    return values


def _multisine(args: argparse.Namespace) -> int:
    from gfrf._atomic import atomic_write_text
    from gfrf.identify.multisine import multisine

    check_output_file("--out", args.out)
    design = multisine(args.period, args.sample_time, grid=args.grid, max_line=args.max_line,
                       realisations=args.realisations, periods=args.periods, rms=args.rms,
                       levels=_levels(args.levels), seed=args.seed)
    atomic_write_text(args.out, design.csv_text())
    payload = design.to_dict()
    payload["out"] = args.out
    w = design.omega
    text = [f"wrote {args.out}: {design.u.shape[0]} realisation(s) x {design.periods} "
            f"period(s) x N = {design.period} samples, T = {design.sample_time:g} s",
            f"grid {design.grid}: {len(design.lines)} excited odd lines from "
            f"{w[0]:.6g} to {w[-1]:.6g} rad/s (line spacing {w[0] / design.lines[0]:.6g} "
            f"rad/s)",
            f"isolated lines: {len(payload['h2_lines'])} for H2, {len(payload['h3_lines'])} "
            f"for H3",
            f"measure y, add it as a column, then: gfrf estimate FILE.csv --period "
            f"{design.period} --skip-periods 1"]
    emit(args, payload, "\n".join(text))
    return 0


def _estimate(args: argparse.Namespace) -> int:
    from gfrf.identify.nonparametric import estimate_gfrf

    check_plot_path(args.plot)
    model = None
    if args.model is not None:
        from gfrf.cli._models import resolve_model

        model = resolve_model(argparse.Namespace(model=args.model,
                                                 sample_time=args.sample_time))
    elif args.sample_time is not None:
        raise ArgumentError("--sample-time is for an inline --model equation; the data's "
                            "sample time is the step of its t column")
    result = estimate_gfrf(args.data, args.period, skip_periods=args.skip_periods,
                           model=model)
    if args.plot:
        from gfrf._atomic import atomic_write_figure

        atomic_write_figure(result.plot(), args.plot, dpi=110)
    payload = result.to_dict()
    emit(args, payload, "\n".join(_text(result, payload, args.plot)))
    return 0


def _db(value: float | None) -> str:
    if value is None:
        return "-"
    return f"{20 * math.log10(value):.1f}" if value > 0 else "-inf"


def _text(result: Any, payload: dict[str, Any], plot: str | None) -> list[str]:
    bla = result.bla
    lines = [f"{len(bla.lines)} excited lines from {bla.omega[0]:.6g} to {bla.omega[-1]:.6g} "
             f"rad/s; {bla.realisations} realisation(s) x {bla.periods} period(s) of "
             f"N = {bla.period}, T = {bla.sample_time:g} s"]
    lines += [f"note: {n}" for n in result.notes]

    def median(values: Any) -> float | None:
        return None if values is None else float(sorted(values)[len(values) // 2])

    lines.append(f"BLA: |G| from {_db(min(abs(bla.bla)))} to {_db(max(abs(bla.bla)))} dB; "
                 f"median std of the estimate {_db(median(bla.bla_std))} dB (noise "
                 f"{_db(median(bla.noise_std))} dB); median std of the nonlinear "
                 f"distortion of one realisation {_db(median(bla.distortion_std))} dB")
    if result.bla_bias.get("measured"):
        lines.append(result.bla_bias["note"])
    d = bla.detection
    for name in ("even", "odd"):
        ratio = d[f"{name}_ratio"]
        if ratio is None:
            why = (f"no {name} non-excited line" if d[f"{name}_lines"] == 0
                   else "one period: no noise level")
            lines.append(f"{name} distortion: not measurable ({why})")
            continue
        verdict = "detected" if d[f"{name}_detected"] else "not detected"
        lines.append(f"{name} distortion {verdict}: output power on the {d[f'{name}_lines']} "
                     f"{name} non-excited lines is {_db(math.sqrt(ratio))} dB above the "
                     f"noise")
    for name in ("h1", "h2", "h3"):
        k = getattr(result, name)
        if k is None:
            continue
        what = "H1 extrapolated to zero amplitude" if name == "h1" else name.upper()
        lines.append(f"{what}: on {k.omega.size} lines, median |{name.upper()}| "
                     f"{_db(median(abs(k.value)))} dB, median std {_db(median(k.value_std))} dB")
    comparison = payload.get("model")
    if comparison:
        for name in ("h1", "h2", "h3"):
            if name in comparison and comparison[name].get("within") is not None:
                of = ""
                if name == "h1":
                    of = (" (H1 extrapolated to zero amplitude)"
                          if comparison[name]["estimate"] != "bla" else
                          " (the BLA: it differs from H1 by terms growing with the "
                          "amplitude; measure at two levels, --levels 1,0.5)")
                lines.append(f"model {name.upper()}: {100 * comparison[name]['within']:.1f} % "
                             f"of the estimates within {comparison['sigmas']:g} standard "
                             f"deviations{of}")
        if "note" in comparison:
            lines.append(f"note: {comparison['note']}")
    lines.append(f"figure: {plot}" if plot else "figure: not written (give --plot FILE.png)")
    lines.append("(--json: the values on every line)")
    return lines
