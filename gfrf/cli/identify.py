"""``gfrf identify``: measured data (CSV) to an identified NARX model, its file and its verdict.

``gfrf identify DATA.csv --output y --input u [--sample-time T] [--ylag 2 --ulag 2
--degree 3] [--criterion bic] [--out model.toml] [--json]`` fits a polynomial NARMAX
model with FROLS (:func:`gfrf.identify.fit.identify`; terms pruned on the
held-out free run unless ``--no-prune``), prints the identified equation (and the full
one when terms were pruned), its noise terms and operating point, r* with its spread,
the validation on the held-out end of the data against the noise floor
(:mod:`gfrf.identify.validate`) and, when the model is adequate (or with ``--force``,
marked), the verdict of Theorem 1 with the identification's rule
(:func:`gfrf.identify.trust.identified_verdict`); it writes the model file when
``--out`` is given.  Exit codes: 0 an adequate model and stability proven, 1 not adequate, not
proven or unstable, 2 bad input.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gfrf.cli._output import add_json_flag, check_output_file, emit
from gfrf.errors import ArgumentError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``identify``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    p = subparsers.add_parser(
        "identify", help="identify a polynomial NARMAX model from CSV data (FROLS), "
                         "validate it and give its verdict",
        description="Fit a polynomial NARMAX model to the output and input columns of a "
                    "CSV file with FROLS (terms, and lags and degree when not "
                    "given, by an information criterion; a constant term or an input mean "
                    "makes an operating point; noise terms when the residuals are "
                    "coloured), validate it on the held-out end of the data (free run and "
                    "correlation tests), write the model file (--out) and print the "
                    "stability verdict if the model passes validation. Exit code 0: "
                    "adequate model, stability proven; 1: not adequate, not proven or "
                    "unstable; 2: bad input.")
    p.add_argument("data", metavar="DATA.csv", help="CSV file with a header row")
    p.add_argument("--output", default="y", help="output column name (default y)")
    p.add_argument("--input", default="u", help="input column name (default u)")
    p.add_argument("--sample-time", type=float, default=None, metavar="T",
                   help="sample time of the data in s (default: the step of the time "
                        "column; both given must agree)")
    p.add_argument("--time", default="t", help="time column name, used when present "
                                               "(default t)")
    p.add_argument("--missing", default="refuse", choices=("refuse", "drop", "interpolate"),
                   help="rows with missing values: refuse (default), drop (keep the longest "
                        "run of complete rows) or interpolate (linearly)")
    p.add_argument("--ylag", type=int, default=None,
                   help="largest output lag (default: lags and degree not given are "
                        "chosen by the criterion among lag 1-3, degree 1-3)")
    p.add_argument("--ulag", type=int, default=None, help="largest input lag")
    p.add_argument("--degree", type=int, default=None, help="polynomial degree")
    p.add_argument("--noise", default="auto", choices=("auto", "yes", "no"),
                   help="NARMAX noise terms by extended least squares: when the training "
                        "residuals are coloured (auto, default; output error when they "
                        "cannot whiten them), always, never")
    p.add_argument("--force", action="store_true",
                   help="give the verdict even when the model is not adequate (the output "
                        "is marked; the exit code stays 1)")
    p.add_argument("--criterion", default="bic", choices=("bic", "aic", "aicc", "fpe", "lilc"),
                   help="information criterion for the number of terms (default bic)")
    p.add_argument("--max-terms", type=int, default=15,
                   help="largest number of terms the criterion considers (default 15)")
    p.add_argument("--no-prune", action="store_true",
                   help="keep every term the criterion chose (default: remove those whose "
                        "removal keeps the held-out free run within its band)")
    p.add_argument("--holdout", type=float, default=0.25,
                   help="fraction of samples at the end held out for validation (default 0.25)")
    p.add_argument("--out", default=None, metavar="MODEL.toml",
                   help="write the identified model file here (atomically)")
    p.add_argument("--name", default="", help="model name in the file")
    p.add_argument("--order", type=int, default=5,
                   help="highest order of the verdict's norm brackets (default 5)")
    p.add_argument("--amplitude", type=float, default=1.0, metavar="R",
                   help="input amplitude r of the verdict (default 1)")
    add_json_flag(p)
    p.set_defaults(func=_identify)


def _check_out(out: str) -> Path:
    path = Path(out)
    if path.suffix != ".toml":
        raise ArgumentError(f"--out must name a .toml model file, got {out!r}")
    check_output_file("--out", out)
    return path


def _sample_time(given: float | None, from_time: float | None, time: str) -> float:
    """T from --sample-time and the time column: one of them, or both agreeing."""
    if given is None and from_time is None:
        raise ArgumentError(f"give --sample-time: the data have no time column {time!r}")
    if given is None:
        assert from_time is not None
        return from_time
    if from_time is not None and abs(given - from_time) > 1e-6 * from_time:
        raise ArgumentError(f"--sample-time {given:g} disagrees with the time column "
                            f"{time!r}, whose step is {from_time:.10g}")
    return given


def _identify(args: argparse.Namespace) -> int:
    from gfrf.cli.stability import _verdict_text
    from gfrf.identify.data import read_data
    from gfrf.identify.fit import identify
    from gfrf.identify.narx import narx_equation
    from gfrf.identify.operating import SIGNIFICANT_DIGITS
    from gfrf.identify.output import load_text, model_file_text, write_atomic
    from gfrf.identify.trust import identified_verdict
    from gfrf.model.safetext import printable

    out = _check_out(args.out) if args.out else None
    data = read_data(args.data, args.output, args.input, time=args.time, missing=args.missing)
    sample_time = _sample_time(args.sample_time, data.sample_time, args.time)
    result = identify(data.y, data.u, sample_time, ylag=args.ylag, ulag=args.ulag,
                      degree=args.degree, criterion=args.criterion, max_terms=args.max_terms,
                      holdout=args.holdout, output=args.output, input=args.input,
                      noise={"auto": None, "yes": True, "no": False}[args.noise],
                      prune=not args.no_prune)
    text = model_file_text(result, args.data, name=args.name)
    model_file = load_text(text, str(out) if out else "")
    if out is not None:
        write_atomic(out, text)
    lines = [f"identified from {printable(args.data)} ({result.n_samples} samples, T = "
             f"{result.model.sample_time:g} s; 6 digits shown, {SIGNIFICANT_DIGITS} in the "
             f"model file and --json):", f"  {narx_equation(result.model, 6)}",
             f"  {result.noise_text()}", result.operating_text(),
             f"fit: {result.quality_text()}"]
    if result.structure:
        s = result.settings
        lines.append(f"structure: --ylag {s['ylag']} --ulag {s['ulag']} --degree "
                     f"{s['degree']} chosen by {s['criterion'].upper()} among " + ", ".join(
                         f"({r['ylag']},{r['ulag']},{r['degree']}): {r[s['criterion']]:.6g}"
                         for r in result.structure) + " ((ylag,ulag,degree): criterion)")
    if result.pruning is not None:
        lines.append(result.pruning.text())
    if result.full_model is not None:
        lines.append(f"  with every term: {narx_equation(result.full_model, 6)}")
    if result.radius is not None:
        lines.append(result.radius.text())
    lines += [f"note: {printable(n)}" for n in data.notes + result.notes]
    assert result.validation is not None
    lines += result.validation.text()
    lines.append(f"model file: {out}" if out else "model file: not written (give --out FILE)")
    payload = {"identification": result.to_dict(), "data_file": args.data,
               "model_file": str(out) if out else None,
               "data_notes": list(data.notes), "verdict": None, "forced": False}
    if not result.adequate and not args.force:
        lines += ["", "the model does not fit: no verdict (give --force to see one anyway, "
                      "marked as such)"]
        emit(args, payload, "\n".join(lines))
        return 1
    v = identified_verdict(result, model_file, args.order, args.amplitude)
    payload["verdict"] = v.to_dict()
    if not result.adequate:
        payload["forced"] = True
        lines += ["", "FORCED: the verdict below is of a model that did NOT pass validation; "
                      "it says nothing reliable about the system that produced the data"]
    lines += [""] + _verdict_text(printable(model_file.name), v)
    emit(args, payload, "\n".join(lines))
    return 0 if v.verdict == "stable" and result.adequate else 1
