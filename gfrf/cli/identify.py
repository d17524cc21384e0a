"""``gfrf identify``: measured data (CSV) to an identified NARX model, its file and its verdict.

``gfrf identify DATA.csv --output y --input u --sample-time T [--ylag 2 --ulag 2
--degree 3] [--criterion bic] [--out model.toml] [--json]`` fits a polynomial NARX
model with sysidentpy's FROLS (:func:`gfrf.identify.fit.identify`), prints the identified
equation, the fit quality on the held-out end of the data and the verdict of
Theorem 1, and writes the model file when ``--out`` is given.  Exit codes as
``gfrf verdict``: 0 stability proven, 1 not proven or unstable, 2 bad input or
sysidentpy missing (the message says how to install it).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from gfrf.cli._output import add_json_flag, emit
from gfrf.errors import ArgumentError

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``identify``."""
    p = subparsers.add_parser(
        "identify", help="identify a polynomial NARX model from CSV data (sysidentpy FROLS) "
                         "and give its verdict",
        description="Fit a polynomial NARX model to the output and input columns of a CSV "
                    "file with sysidentpy's FROLS (number of terms by an information "
                    "criterion, no constant term), report the free-run error on the "
                    "held-out end of the data, write the model file (--out) and print the "
                    "stability verdict. Needs the optional extra gfrf[identify]. Exit code "
                    "0: stability proven, 1: not proven or unstable, 2: bad input.")
    p.add_argument("data", metavar="DATA.csv", help="CSV file with a header row")
    p.add_argument("--output", default="y", help="output column name (default y)")
    p.add_argument("--input", default="u", help="input column name (default u)")
    p.add_argument("--sample-time", type=float, required=True, metavar="T",
                   help="sample time of the data in s")
    p.add_argument("--ylag", type=int, default=2, help="largest output lag (default 2)")
    p.add_argument("--ulag", type=int, default=2, help="largest input lag (default 2)")
    p.add_argument("--degree", type=int, default=3, help="polynomial degree (default 3)")
    p.add_argument("--criterion", default="bic", choices=("bic", "aic", "aicc", "fpe", "lilc"),
                   help="information criterion for the number of terms (default bic)")
    p.add_argument("--max-terms", type=int, default=15,
                   help="largest number of terms the criterion considers (default 15)")
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
    folder = path.parent if str(path.parent) else Path(".")
    if path.suffix != ".toml":
        raise ArgumentError(f"--out must name a .toml model file, got {out!r}")
    if path.is_dir():
        raise ArgumentError(f"--out {out!r} is a directory")
    if not folder.is_dir() or not os.access(folder, os.W_OK):
        raise ArgumentError(f"--out: cannot write into {str(folder)!r}")
    return path


def _identify(args: argparse.Namespace) -> int:
    from gfrf.cli.stability import _verdict_text
    from gfrf.identify.data import read_csv
    from gfrf.identify.fit import identify
    from gfrf.identify.narx import narx_equation
    from gfrf.identify.output import load_text, model_file_text, write_atomic
    from gfrf.stability.criteria import verdict

    out = _check_out(args.out) if args.out else None
    y, u = read_csv(args.data, args.output, args.input)
    result = identify(y, u, args.sample_time, ylag=args.ylag, ulag=args.ulag,
                      degree=args.degree, criterion=args.criterion, max_terms=args.max_terms,
                      holdout=args.holdout, output=args.output, input=args.input)
    text = model_file_text(result, args.data, name=args.name)
    model_file = load_text(text, str(out) if out else "")
    if out is not None:
        write_atomic(out, text)
    v = verdict(model_file, args.order, args.amplitude)
    lines = [f"identified from {args.data} ({result.n_samples} samples, T = "
             f"{result.model.sample_time:g} s; 6 digits shown, exact in the model file and "
             f"--json):", f"  {narx_equation(result.model, 6)}",
             f"fit: {result.quality_text()}"]
    lines += [f"note: {n}" for n in result.notes]
    lines.append(f"model file: {out}" if out else "model file: not written (give --out FILE)")
    lines += [""] + _verdict_text(model_file.name, v)
    payload = {"identification": result.to_dict(), "model_file": str(out) if out else None,
               "verdict": v.to_dict()}
    emit(args, payload, "\n".join(lines))
    return 0 if v.verdict == "stable" else 1
