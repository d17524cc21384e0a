"""The upper side of ``gfrf threshold``: finding and proving an escaping bounded input.

Per model (open loop, and closed loops u = C(r - y) with a proper controller, whose input
is the reference r): the CPU time of the falsifier (:func:`gfrf.twosided.falsify.falsify`:
switching inputs, chirps and tones on compiled RK4, the witness confirmed by DOP853) and
of the proof (:func:`gfrf.twosided.enclose.enclose_witness`, Arb enclosure of the loop's
whole state), then the best chirp alone (the four sweeps of the falsifier up to the cap,
the witness at 1.02x-1.12x its edge confirmed by DOP853, then enclosed), beside the
baseline an auditor writes: bisection of a tone's amplitude on a frequency grid with
scipy's ``solve_ivp`` (DOP853, escape = |y| >= 1e3 as an event).  The error column is the
amplitude found against the proven lower radius (upper / lower: closer to 1 is tighter).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import replace

import numpy as np

from gfrf.bench import BenchSection, bundled_model, load_note

__all__ = ["run"]


#: The softening plant of the loop rows.
_SOFT = "D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u"


def _loop(num: list[float], den: list[float], equation: str = _SOFT) -> object:
    from gfrf.model.modelfile import model_from_dict

    return model_from_dict({"equation": equation,
                            "controller": {"num": num, "den": den, "feedback": -1}})


def _cases(quick: bool) -> list[tuple[str, object, float, bool]]:
    """(label, model, cap, chirp row) per model."""
    cases: list[tuple[str, object, float, bool]] = [
        ("hanging_pendulum_damped", bundled_model("hanging_pendulum_damped.toml"), 23.1,
         False),
        ("softening oscillator", _SOFT, 3.0, True),
        ("loop: softening plant, lead-lag C = (2s + 1)/(s + 2)", _loop([2, 1], [1, 2]), 7.0,
         True)]
    if not quick:
        import control

        from gfrf.model.from_control import from_tf

        cases += [("hanging_pendulum", bundled_model("hanging_pendulum.toml"), 23.1, False),
                  ("third-order plant 2/(s^3 + 1.2s^2 + 3s + 1), y^2 0.3, y^3 0.5",
                   from_tf(control.tf([2], [1, 1.2, 3, 1]), {2: 0.3, 3: 0.5}), 6.0, False),
                  ("loop: softening plant, P C = 1", _loop([1], [1]), 7.0, True),
                  ("loop: third-order plant, lead-lag C = (s + 0.5)/(s + 2)",
                   _loop([1, 0.5], [1, 2], "D(y,3) + 1.2*D(y,2) + 3*D(y) + y + 0.6*y**2 "
                                           "+ y**3 = 2*u"), 7.0, False)]
    return cases


def _chirp(mf: object, cap: float, closed: bool) -> tuple[object, float, object, float]:
    """The best chirp witness alone: (Falsification or None, find CPU, proof, prove CPU)."""
    from gfrf.sim.system import build_system
    from gfrf.twosided.enclose import enclose_witness
    from gfrf.twosided.falsify import MARGINS, chirp_edges, frequencies
    from gfrf.twosided.runner import EscapeRunner
    from gfrf.twosided.witness import Falsification

    t0 = time.process_time()
    system = build_system(mf, closed_loop=closed, equation="polynomial")  # type: ignore[arg-type]
    omegas, ref = frequencies(np.asarray(system.linear_eigenvalues, dtype=complex), False,
                              None)
    runner = EscapeRunner(system, mf.plant, 3 * float(np.max(omegas)))  # type: ignore[attr-defined]
    found = None
    for edge, _, unit in sorted(chirp_edges(runner, ref, cap) if runner.chirps else []):
        for factor in MARGINS:
            chirp = replace(unit, amplitude=edge * factor)
            t_escape = runner.confirm_chirp(chirp)
            if t_escape is not None:
                found = Falsification(chirp.amplitude, [], t_escape, edge, cap=cap,
                                      t_end=runner.t_end, runs=runner.runs, escape="",
                                      kind="chirp", chirp=chirp,
                                      region=runner.region(chirp.amplitude),
                                      levels=list(runner.levels))
                break
        if found is not None:
            break
    find = time.process_time() - t0
    if found is None:
        return None, find, None, 0.0
    t0 = time.process_time()
    proof = enclose_witness(mf if closed else mf.plant, found)  # type: ignore[arg-type,attr-defined]
    return found, find, proof, time.process_time() - t0


def _baseline(model: object, cap: float, quick: bool, closed: bool) -> float | None:
    """Smallest escaping tone amplitude: a frequency grid, amplitude bisection, solve_ivp."""
    from scipy.integrate import solve_ivp

    from gfrf.sim.system import build_system

    system = build_system(model, closed_loop=closed, equation="polynomial")  # type: ignore[arg-type]
    rhs = system.function("rhs")
    w0 = float(np.min(np.abs(system.linear_eigenvalues)))
    v = np.zeros(system.n_inputs)

    def escapes(a: float, w: float) -> bool:
        def f(t: float, z: np.ndarray) -> np.ndarray:
            out = np.empty(system.n_states)
            v[0] = a * math.cos(w * t)
            rhs(z, v, out)
            return out

        def big(t: float, z: np.ndarray) -> float:
            return abs(z[0]) - 1e3

        big.terminal = True  # type: ignore[attr-defined]
        with np.errstate(all="ignore"):
            sol = solve_ivp(f, (0, 200.0), np.zeros(system.n_states), method="DOP853",
                            rtol=1e-8, atol=1e-11, events=big)
        return sol.status != 0

    best = None
    for w in np.geomspace(0.5 * w0, 1.5 * w0, 6 if quick else 16):
        if not escapes(cap, w):
            continue
        lo, hi = 0.0, cap
        for _ in range(8 if quick else 12):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if escapes(mid, w) else (mid, hi)
        best = hi if best is None else min(best, hi)
    return best


def run(quick: bool) -> BenchSection:
    """Time the falsifier, the proof and the baseline per model; return the section.

    Parameters
    ----------
    quick : bool
        Leave out the undamped hanging pendulum, the third-order plant and two loops, and coarsen
        the baseline (6 frequencies and 8 amplitude bisections instead of 16 and 12).

    Returns
    -------
    BenchSection
        The section of ``speed-vs-error.md``: per model, the times of the falsifier, the
        proof and the baseline.
    """
    from gfrf.model.modelfile import resolve_model
    from gfrf.twosided.enclose import enclose_witness
    from gfrf.twosided.falsify import falsify
    from gfrf.twosided.threshold import threshold

    load = os.getloadavg()
    rows: list[list[object]] = []
    for label, source, cap, chirps in _cases(quick):
        mf = resolve_model(source)  # type: ignore[arg-type]
        closed = mf.controller is not None
        lower = threshold(mf, prove=False).lower
        t0 = time.process_time()
        f = falsify(mf, cap, closed_loop=closed, floor=lower)
        find = time.process_time() - t0
        t0 = time.process_time()
        proof = enclose_witness(mf if closed else mf.plant, f)
        prove = time.process_time() - t0
        chirp_cells = ["-", "-"]
        if chirps:
            c, c_find, c_proof, c_prove = _chirp(mf, cap, closed)
            kind = "interval" if c_proof is not None and c_proof.proven else "estimate"  # type: ignore[attr-defined]
            chirp_cells = [f"{c.upper:.5g} ({kind})" if c is not None  # type: ignore[attr-defined]
                           else "none up to the cap", f"{c_find:.1f} / {c_prove:.1f}"]
        t0 = time.process_time()
        base = _baseline(mf if closed else mf.plant, cap, quick, closed)
        base_cpu = time.process_time() - t0
        rows.append([label, f"{lower:.5g}", f"{f.upper:.5g} ({f.kind})" if f.upper else "-",
                     f"{f.upper / lower:.3f}" if f.upper and lower else "-", f"{find:.1f}",
                     "interval" if proof is not None and proof.proven else "estimate",
                     f"{prove:.1f}", *chirp_cells, f"{base:.5g}" if base else "-",
                     f"{base / lower:.3f}" if base and lower else "-", f"{base_cpu:.1f}"])
    return BenchSection(
        title="Upper side: the escaping bounded input, found and proven",
        intro=" ".join(__doc__.split("\n\n", 1)[1].split()),
        columns=["model", "lower (proven)", "upper (ours)", "upper/lower", "find CPU (s)",
                 "upper proof", "prove CPU (s)", "best chirp alone (proof)",
                 "chirp find / prove CPU (s)", "baseline (tone bisection)",
                 "baseline/lower", "baseline CPU (s)"],
        rows=rows, notes=["CPU seconds of this process (time.process_time).", load_note(load)])
