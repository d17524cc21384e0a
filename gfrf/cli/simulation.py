"""``gfrf simulate``, ``gfrf predict``, ``gfrf validate``: simulation vs frequency domain.

``gfrf simulate MODEL --input TEXT --t-end T`` integrates the model (the untruncated
physical equation when the file has one, ``--polynomial`` for the truncated model),
``--closed-loop`` with the file's controller (the input is then the reference),
``--initial y0,dy0`` for initial conditions.  Exit code 0 when the run reaches
t_end, 1 when it blows up or fails (one line ``FAILED: ...``, e.g. the work budget
``--max-evaluations``, default :data:`gfrf.sim.integrate.MAX_RHS_EVALUATIONS`, was spent:
it names the limit and the time reached), 2 for bad input (among them an input tone
too fast for that budget over t_end).  ``gfrf predict MODEL --input TEXT
--order N`` lists the steady-state harmonics of a sum of tones (rad/s); exit 1 (one
line) when the plant's linear part is not stable (no steady state exists) or the input
amplitude, the sum of the tone amplitudes, is at or beyond the series radius r*
(naming r* and the amplitude), unless ``--force``.
``gfrf validate MODEL`` computes the verdict and simulates inputs below and above its
radius r* (and closed loops from initial angles); exit 0 when no simulation
contradicts the verdict, 1 when one does.
"""

from __future__ import annotations

import argparse
import warnings
from typing import TYPE_CHECKING, Any

from gfrf._atomic import atomic_open, atomic_write_figure
from gfrf.cli._models import add_model_argument, resolve_model
from gfrf.cli._output import add_json_flag, check_output_file, check_plot_path, emit, emit_refusal
from gfrf.errors import ArgumentError
from gfrf.model.safetext import plot_text

if TYPE_CHECKING:  # the numerical modules are imported where used: the parser stays cheap
    from gfrf.sim.integrate import SimulationResult

__all__ = ["register", "METHODS"]

#: Same as :data:`gfrf.sim.simulation.METHODS` (kept here so that building the parser does not
#: import scipy/sympy; a test asserts equality).
METHODS: tuple[str, ...] = ("auto", "rk45", "dop853", "radau", "lsoda", "fast")


#: Most output samples a simulation may return (8 bytes each per state: 10^6 is ~50 MB).
MAX_OUTPUT_POINTS = 1_000_000

def register(subparsers: argparse._SubParsersAction) -> None:
    """Register ``simulate``, ``predict`` and ``validate``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        The gfrf parser's subcommand collection the parsers are added to.
    """
    sim = subparsers.add_parser(
        "simulate", help="time simulation of a model (open or closed loop)",
        description="Simulate a model from an input u(t) (t in seconds) and/or initial "
                    "conditions; report blow-up instead of returning NaN.")
    add_model_argument(sim)
    sim.add_argument("--input", default=None, metavar="TEXT",
                     help="input (reference in closed loop) as an expression in t, e.g. "
                          "'0.1*sin(1.2*t)', 'step(t)', or csv:FILE; default zero")
    sim.add_argument("--t-end", type=float, required=True, metavar="T",
                     help="final time in seconds")
    sim.add_argument("--closed-loop", action="store_true",
                     help="close the loop with the model file's controller")
    sim.add_argument("--polynomial", action="store_true",
                     help="simulate the truncated polynomial model, not the physical equation")
    sim.add_argument("--initial", default=None, metavar="Y0,DY0,...",
                     help="initial output and derivatives (NARX: past outputs)")
    sim.add_argument("--method", choices=METHODS, default="auto",
                     help="integrator (default auto: rk45 at --rtol >= 1e-4, dop853 below; "
                          "fast = numba fixed-step RK4)")
    sim.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance (> 0)")
    sim.add_argument("--atol", type=float, default=1e-10, help="absolute tolerance (> 0)")
    sim.add_argument("--dt", type=float, default=None,
                     help="fixed step in seconds of --method fast (default: from --rtol)")
    sim.add_argument("--points", type=int, default=2001, help="output samples (default 2001)")
    sim.add_argument("--blowup", type=float, default=1e6,
                     help="|y| at which the run is stopped as a blow-up")
    sim.add_argument("--max-evaluations", type=int, default=None, metavar="N",
                     help="work budget: right-hand-side evaluations of a scipy run (NARX: "
                          "samples) before it stops as failed (default "
                          "MAX_RHS_EVALUATIONS = 1000000)")
    sim.add_argument("--csv", default=None, metavar="FILE", help="write t,y,u to a CSV file")
    sim.add_argument("--plot", default=None, metavar="FILE.png", help="write a plot")
    add_json_flag(sim)
    sim.set_defaults(func=_simulate)

    pred = subparsers.add_parser(
        "predict", help="Volterra prediction of the steady state for a sum of tones",
        description="Steady-state harmonics and intermodulation products (rad/s) of a "
                    "sum of sinusoids predicted from the GFRFs up to --order.  The input "
                    "amplitude is the sum of the tone amplitudes (the peak |u| over all "
                    "phases).  The prediction is refused (exit 1) unless --force when "
                    "the plant's linear part is not stable (no steady state exists) or "
                    "the amplitude is at or beyond the series radius r*.")
    add_model_argument(pred)
    pred.add_argument("--input", required=True, metavar="TEXT",
                      help="a sum of tones, e.g. '0.01*sin(1.565*t) + 0.005*cos(3*t)'")
    pred.add_argument("--order", type=int, default=3, help="highest kernel order N")
    pred.add_argument("--force", action="store_true",
                      help="predict even for a plant whose linear part is not stable, "
                           "or when the input amplitude (sum of the tone amplitudes) is at "
                           "or beyond the series radius r*; the output then carries a "
                           "warning")
    add_json_flag(pred)
    pred.set_defaults(func=_predict)

    val = subparsers.add_parser(
        "validate", help="verdict vs simulation: inputs below and above the radius r*",
        description="Compute the verdict (Theorem 1 or 2) and simulate the polynomial "
                    "model with a cosine at the |H1| peak, two tones and a seeded random "
                    "input of size 0.5 r* and 2 r* (and the radius estimate and beyond), "
                    "plus the closed loop from initial angles 5, 10, 15 degrees.  Exit 0 "
                    "when no run below r* blows up, 1 otherwise.")
    add_model_argument(val)
    val.add_argument("--t-end", type=float, default=100.0, metavar="T",
                     help="horizon of every run in seconds (default 100)")
    val.add_argument("--method", choices=METHODS, default="fast",
                     help="integrator (default: the numba fast path)")
    val.add_argument("--seed", type=int, default=0, help="seed of the random input")
    add_json_flag(val)
    val.set_defaults(func=_validate)


def _initial(text: str | None) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ArgumentError(f"--initial must be comma-separated numbers, got {text!r}") \
            from None


def _simulate(args: argparse.Namespace) -> int:
    import numpy as np
    from tqdm import tqdm

    from gfrf.sim.integrate import MAX_RHS_EVALUATIONS
    from gfrf.sim.simulation import simulate

    check_plot_path(args.plot)
    check_output_file("--csv", args.csv)
    mf = resolve_model(args)
    if not 2 <= args.points <= MAX_OUTPUT_POINTS:
        raise ArgumentError(f"--points must be between 2 and MAX_OUTPUT_POINTS = "
                            f"{MAX_OUTPUT_POINTS}, got {args.points}")
    long_run = args.t_end > 1000 and args.method != "fast"
    with tqdm(total=1, desc="simulating", disable=None if long_run else True,
              leave=False) as bar:
        res = simulate(mf, args.input, t_end=args.t_end, closed_loop=args.closed_loop,
                       equation="polynomial" if args.polynomial else "physical",
                       initial=_initial(args.initial), method=args.method, rtol=args.rtol,
                       atol=args.atol, dt=args.dt, n_out=args.points, blowup=args.blowup,
                       max_evaluations=MAX_RHS_EVALUATIONS if args.max_evaluations is None
                       else args.max_evaluations)
        bar.update(1)
    if args.csv is not None:
        with atomic_open(args.csv, "w", newline="") as fh:  # opened once (FIFOs)
            np.savetxt(fh, np.c_[res.t, res.y, res.u], delimiter=",", header="t,y,u",
                       comments="")
    if args.plot:
        _plot(res, args.plot, mf.name, mf.plant.output)
    payload: dict[str, Any] = {"model": mf.name, "input": args.input, "t_end": args.t_end,
                               "closed_loop": args.closed_loop, **res.to_dict()}
    # No wall time in the text: the same command prints the same bytes (it is in --json).
    lines = [f"{mf.name}: {res.status} ({res.method}, {res.nfev} evaluations)",
             f"  t in [0, {res.t[-1]:.6g}] s, {res.t.size} samples, max |{mf.plant.output}| = "
             f"{res.peak:.6g}, final {mf.plant.output} = {res.y[-1]:.6g}" if res.t.size else
             "  no output sample before the run stopped"]
    if res.blowup_time is not None:
        lines.append(f"  BLOW-UP: {res.message}")
    elif res.status == "failed":
        lines.append(f"  FAILED: {res.message}")
    lines += [f"  note: {n}" for n in res.notes]
    emit(args, payload, "\n".join(lines))
    return 0 if res.bounded else 1


def _plot(res: SimulationResult, path: str, title: str, output: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(6, 4.5))
    ax1.plot(res.t, res.y)
    ax1.set_ylabel(output)
    ax1.set_title(f"{plot_text(title, limit=80)} ({res.status})", parse_math=False)
    ax2.plot(res.t, res.u, color="tab:orange")
    ax2.set_ylabel("u")
    ax2.set_xlabel("t (s)")
    fig.tight_layout()
    try:
        atomic_write_figure(fig, path, dpi=110)
    finally:
        plt.close(fig)


def _predict(args: argparse.Namespace) -> int:
    import numpy as np

    from gfrf._results import proof_word
    from gfrf.kernels.recursion import check_order
    from gfrf.model.signals import parse_input
    from gfrf.sim.volterra import BeyondRadiusError, NoSteadyStateError, predict

    check_order(args.order, "--order")
    mf = resolve_model(args)
    signal = parse_input(args.input)
    if not signal.tones:
        raise ArgumentError(f"--input {args.input!r} is not a sum of sinusoids "
                            f"A*sin(w*t + p) / A*cos(w*t + p)")
    try:
        p = predict(mf.plant, signal.tones, args.order, force=args.force)
    except (NoSteadyStateError, BeyondRadiusError) as exc:
        emit_refusal(args, {"model": mf.name, "input": args.input, "order": args.order,
                            "amplitude": getattr(exc, "amplitude", None),
                            "radius": getattr(exc, "radius", None)},
                     f"{exc} (--force to predict anyway)")
        return 1
    kind = proof_word(p.radius_proof)
    lines = [f"{mf.name}: steady state to order {args.order} for {args.input}",
             f"  input amplitude {p.amplitude:.6g} (sum of tone amplitudes), "
             f"series radius r* = {p.radius:.6g} ({kind})"]
    if p.warning:
        lines.append(f"  WARNING: {p.warning}")
    lines += ["  omega (rad/s)   f (Hz)      amplitude       phase (rad)"]
    lines += [f"  {c.omega:<15.6g} {c.omega / (2 * np.pi):<11.5g} {c.amplitude:<15.6g} "
              f"{c.phase:+.6f}" for c in p.components]
    emit(args, {"model": mf.name, **p.to_dict()}, "\n".join(lines))
    return 0


def _validate(args: argparse.Namespace) -> int:
    from gfrf.sim.validation import validate

    mf = resolve_model(args)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # unstable linearisations: in notes
        result = validate(mf, t_end=args.t_end, seed=args.seed, method=args.method)
    estimate = ("" if result.radius_estimate is None else
                f", radius estimate {result.radius_estimate:.6g}")
    lines = [f"{mf.name}: Theorem {result.theorem} {result.verdict}, r* = "
             f"{result.radius:.6g}{estimate}; {len(result.trials)} runs of "
             f"{result.t_end:g} s, resonance {result.resonance:.4g} rad/s",
             "  input                      equation    at        r           bounded  "
             "max |y|"]
    lines += [f"  {t.kind:<26} {t.equation:<11} {t.label:<9} {t.amplitude:<11.4g} "
              f"{'yes' if t.bounded else 'NO':<8} {t.peak:.4g}" for t in result.trials]
    lines += [f"  note: {n}" for n in result.notes]
    bad = result.contradictions
    lines.append(f"  contradictions of the verdict: {len(bad)}")
    emit(args, result.to_dict(), "\n".join(lines))
    return 1 if bad else 0
