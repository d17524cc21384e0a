"""The upper side: the smallest bounded input whose response from rest escapes.

Three input families are searched, all switched on at t = 0 with the system at rest:

* **switching inputs** u = +-U, the sign following a state function s = c . z
  (z = (y, y', ..., y^(n-1))): the velocity, a*y + y' (the energy-pumping input of an
  oscillator and its phase-shifted variants; Pontryagin's principle gives a bounded
  input's extremals this bang-bang form), and each state alone (for a first-order
  model, a constant input); then a count-bounded optimiser over a (golden-section
  steps on the switching function's phase).  Their amplitude is sup|u| = U, the
  L-infinity size of the lower side's class.  In a loop with a proper controller z
  also holds the controller's states and the input is the reference r.  Not for NARX
  models (sign sequences instead) or systems that read input derivatives;
* **chirps** u = A cos(omega_0 t + (omega_1 - omega_0) t^2 / (2 T)) on [0, T]
  (:data:`CHIRPS`: sweeps across the least damped mode, down and up), amplitude
  A = sup|u|; continuous models on the fast path, below the best switching edge;
* **sums of tones** u = sum A cos(omega t + phi) on a log grid of frequencies spanning
  the linear part's eigenvalue moduli (x 0.2 .. x 3), the exact sub- and
  super-harmonics 1/3, 1/2, 2, 3 of the least damped mode, then a finer grid (0.5 %
  steps), phases and two-tone inputs around the best three.  Their amplitude is
  sum A (>= sup|u|).  Searched only below the best switching edge.

For each shape the escaping amplitude is found by halving from the cap, then bisection,
on fixed-step RK4 compiled by numba (:mod:`gfrf.twosided.switching`,
:mod:`gfrf.sim.fastsim`; NARX models run their recursion).  *Escape* is defined by the
model (:mod:`gfrf.twosided.escape`): entering a certified escape region of an
oscillator, or any state leaving the level derived from the model's scale (or a
non-finite state).

The witness is the best edge times 1.02 (then 1.03, 1.05, 1.08, 1.12, then the next
candidate).  A switching witness records its switch times from the feedback run; it is
accepted only if that open-loop input escapes under scipy's DOP853 at rtol 1e-9 and
1e-11 (each switch an integration boundary) with escape times within 1 %.  A tone
witness must also escape at half the step.  Every stop is on work (grid sizes,
bisection counts), never on time: the same model gives the same witness, byte for
byte.  The witness is a simulation fact (estimate-grade) until
:mod:`gfrf.twosided.enclose` encloses it.  The witness and its JSON are
:mod:`gfrf.twosided.witness`; the escape tests of one system :mod:`gfrf.twosided.runner`.
For a closed loop the input searched is the reference r of u = C(r - y) (switching
references with a proper controller; chirps and sums of tones, whose exact derivatives
r', r'' an improper controller reads).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile
from gfrf.twosided.escape import DEFAULT_LEVEL
from gfrf.twosided.runner import CHECK_RTOLS, MAX_RUN_STEPS, TIME_AGREEMENT, EscapeRunner
from gfrf.twosided.witness import Chirp, Falsification, Tone, scaled, switching_text, tones_text

__all__ = ["Falsification", "falsify", "chirp_edges", "frequencies", "ESCAPE_LEVEL",
           "CAP_FACTOR", "CHECK_RTOLS", "MARGINS", "MAX_RUN_STEPS", "tones_text", "switching_text"]

#: Escape level of a model without a scale of its own (see :mod:`gfrf.twosided.escape`).
ESCAPE_LEVEL = DEFAULT_LEVEL
#: The search cap: this many times the reference amplitude (the static bound, or r*, or 1).
CAP_FACTOR = 10.0
#: Frequencies of the first stage.
N_FREQUENCIES = 48
#: Halvings from the cap, then bisections of the escaping amplitude.
HALVINGS, BISECTIONS = 12, 10
#: Factors on the best edge tried for the witness, in order.
MARGINS = (1.02, 1.03, 1.05, 1.08, 1.12)
#: Candidates (best edges) tried for a witness at most.
MAX_CANDIDATES = 4
#: Phases a (times the reference frequency) of s = y' + a*y tried, then golden steps.
PHASES = (-0.5, -0.2, 0.2, 0.5)
GOLDEN_STEPS = 6
#: Chirps tried: (start, end) frequency as multiples of the least damped mode's, and the
#: duration as a fraction of the horizon (down-sweeps follow a softening resonance).
CHIRPS = ((1.0, 0.5, 0.5), (1.3, 0.6, 0.5), (0.6, 1.3, 0.5), (1.3, 0.6, 0.25))


def frequencies(runner_ev: np.ndarray, discrete: bool, sample_time: float | None
                ) -> tuple[np.ndarray, float]:
    """The first-stage grid (rad/s) and the least damped mode's frequency.

    Parameters
    ----------
    runner_ev : numpy.ndarray
        Eigenvalues of the linear part (a NARX model: unused).
    discrete : bool
        A NARX model: the grid spans 1 % of the Nyquist frequency to it.
    sample_time : float or None
        The NARX sample time (s).

    Returns
    -------
    numpy.ndarray
        The grid (rad/s).
    float
        The least damped mode's frequency (a NARX model: a quarter of Nyquist).
    """
    if discrete:
        nyquist = math.pi / float(sample_time)  # type: ignore[arg-type]
        grid = np.geomspace(0.01 * nyquist, nyquist, N_FREQUENCIES)
        return grid, nyquist / 4
    ev = runner_ev[np.abs(runner_ev) > 0]
    if ev.size == 0:
        return np.geomspace(0.1, 10.0, N_FREQUENCIES), 1.0
    mods = np.abs(ev)
    ref = float(mods[np.argmin(np.abs(ev.real) / mods)])
    base = np.geomspace(0.2 * float(mods.min()), 3 * float(mods.max()), N_FREQUENCIES)
    extra = ref * np.array([1 / 3, 1 / 2, 2.0, 3.0])
    return np.unique(np.concatenate((base, extra))), ref


def _edge(escapes: Callable[[float], bool], cap: float) -> float | None:
    """Smallest escaping amplitude found by halving from ``cap`` and bisection."""
    if not escapes(cap):
        return None
    hi, lo = cap, 0.0
    for _ in range(HALVINGS):
        a = hi / 2
        if escapes(a):
            hi = a
        else:
            lo = a
            break
    if lo == 0.0:
        return hi
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        if escapes(mid):
            hi = mid
        else:
            lo = mid
    return hi


def _refinements(w: float, best: bool, nyquist: float | None) -> list[list[Tone]]:
    steps = (-6, -4, -3, -2, -1, 1, 2, 3, 4, 6) if best else (-3, -1, 1, 3)
    shapes = [[(1.0, w * (1 + 0.005 * j), 0.0)] for j in steps]
    if best:
        shapes += [[(1.0, w, p)] for p in (math.pi / 2, math.pi, 3 * math.pi / 2)]
        for m in (2.0, 3.0, 0.5, 1 / 3):
            shapes.append([(0.75, w, 0.0), (0.25, m * w, 0.0)])
    if nyquist is not None:
        shapes = [s for s in shapes if all(0 < t[1] <= nyquist for t in s)]
    return shapes


def _switching_functions(n: int, ref: float) -> list[np.ndarray]:
    """c of s = c . z: each state alone, then y' + a*ref*y for the phases a (both signs)."""
    out = []
    for j in range(n):
        e = np.zeros(n)
        e[j] = 1.0
        out += [e, -e]
    if n >= 2:
        for a in PHASES:
            c = np.zeros(n)
            c[1], c[0] = 1.0, a * ref
            out += [c, -c]
    return out


def _switching_stage(runner: EscapeRunner, ref: float, cap: float
                     ) -> list[tuple[float, int, np.ndarray]]:
    """Edges of the switching inputs: the fixed functions, then golden steps on the phase."""
    n = runner.system.n_states
    found: list[tuple[float, int, np.ndarray]] = []

    def edge_of(c: np.ndarray, top: float) -> float | None:
        return _edge(lambda a: runner.switch(c, a).escaped, top)

    for c in _switching_functions(n, ref):
        e = edge_of(c, cap)
        if e is not None:
            found.append((e, len(found), c))
    if n < 2 or not found:
        return found
    # golden-section steps on a in s = sign * (y' + a*ref*y), around the best edge
    best = min(found, key=lambda x: (x[0], x[1]))
    sign = 1.0 if best[2][1] > 0 else -1.0 if best[2][1] < 0 else 0.0
    if sign == 0.0:
        return found
    a0 = best[2][0] / (sign * ref)
    lo, hi = a0 - 0.3, a0 + 0.3
    memo: dict[float, float] = {}

    def value(a: float) -> float:
        if a not in memo:
            c = np.zeros(n)
            c[1], c[0] = sign, sign * a * ref
            e = edge_of(c, min(cap, 1.5 * best[0]))
            memo[a] = math.inf if e is None else e
            if e is not None:
                found.append((e, len(found), c))
        return memo[a]

    g = (math.sqrt(5) - 1) / 2
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    for _ in range(GOLDEN_STEPS):
        if value(x1) <= value(x2):
            hi, x2 = x2, x1
            x1 = hi - g * (hi - lo)
        else:
            lo, x1 = x1, x2
            x2 = lo + g * (hi - lo)
    return found


def chirp_edges(runner: EscapeRunner, ref: float, cap: float
                ) -> list[tuple[float, int, Chirp]]:
    """The escaping amplitude of each chirp of :data:`CHIRPS` (those found below ``cap``).

    Parameters
    ----------
    runner : EscapeRunner
        The escape tests of the system (``runner.chirps`` must hold).
    ref : float
        The least damped mode's frequency (rad/s): the chirps sweep multiples of it.
    cap : float
        Largest amplitude searched.

    Returns
    -------
    list of (edge, index, Chirp)
        The edge found and the chirp at unit amplitude, in the order of :data:`CHIRPS`.
    """
    chirped: list[tuple[float, int, Chirp]] = []
    for w0, w1, part in CHIRPS:
        unit = Chirp(amplitude=1.0, omega_start=w0 * ref, omega_end=w1 * ref,
                     duration=part * runner.t_end)
        edge = _edge(lambda a, c=unit: runner.escapes_chirp(replace(c, amplitude=a)), cap)
        if edge is not None:
            chirped.append((edge, len(chirped), unit))
    return chirped


def falsify(source: ModelFile | Model, cap: float, *, closed_loop: bool = False,
            floor: float = 0.0,
            progress: Callable[[int, int], None] | None = None) -> Falsification:
    """Search bounded inputs for the smallest amplitude whose response from rest escapes.

    Parameters
    ----------
    source : ModelFile or Model
        The model (a model file with ``closed_loop`` for the loop with its controller).
    cap : float
        Largest amplitude searched (> 0).
    closed_loop : bool
        Search the reference r of the closed loop u = C(r - y) (the loop Theorem 2 and
        the certificate engine analyse).
    floor : float
        A proven lower radius: witnesses below it are not reported (a switching input
        below Theorem 1's r* lies outside its class of sums of tones; either way a
        witness under ``lower`` is never printed).
    progress : callable, optional
        Called as ``progress(done, total)`` after each input shape.

    Returns
    -------
    Falsification
    """
    from gfrf.sim.system import build_system

    model = source.plant if isinstance(source, ModelFile) else source
    system = build_system(source, closed_loop=closed_loop, equation="polynomial")
    ev = np.asarray(system.linear_eigenvalues, dtype=complex)
    omegas, ref = frequencies(ev, system.discrete, system.sample_time)
    nyquist = math.pi / float(system.sample_time) if system.discrete else None
    top = float(np.max(omegas)) * (3.0 if not system.discrete else 1.0)
    runner = EscapeRunner(system, model, top)
    total = len(omegas) + 3 * 6 + 7 + 2
    done = 0

    def tick() -> None:
        nonlocal done
        done += 1
        if progress:
            progress(min(done, total), total)

    switched: list[tuple[float, int, Any]]
    if runner.bang is not None:
        switched = list(_switching_stage(runner, ref, cap))
    elif runner.discrete and not closed_loop:
        from gfrf.twosided.narx_signs import RULES

        switched = []
        for rule in RULES:
            e = _edge(lambda a, r=rule: runner.switch(r, a).escaped, cap)
            if e is not None:
                switched.append((e, len(switched), rule))
    else:
        switched = []
    tick()
    best_switch = min([e for e, _, _ in switched], default=math.inf)
    tone_cap = min(cap, best_switch) if best_switch * MARGINS[-1] >= floor else cap
    chirped = chirp_edges(runner, ref, tone_cap) if runner.chirps else []
    tick()
    found: list[tuple[float, int, list[Tone]]] = []
    for w in omegas:
        edge = _edge(lambda a, s=[(1.0, float(w), 0.0)]: runner.escapes(scaled(s, a)),
                     tone_cap)
        if edge is not None:
            found.append((edge, len(found), [(1.0, float(w), 0.0)]))
        tick()
    best_w: list[float] = []
    for _, _, shape in sorted(found):
        w = shape[0][1]
        if all(abs(w / b - 1) > 0.05 for b in best_w):
            best_w.append(w)
        if len(best_w) == 3:
            break
    for i, w in enumerate(best_w):
        for shape in _refinements(w, i == 0, nyquist):
            edge = _edge(lambda a, s=shape: runner.escapes(scaled(s, a)), tone_cap)
            if edge is not None:
                found.append((edge, len(found), shape))
            tick()
    region = runner.region(cap)
    level_text = ", ".join(f"{x:.4g}" for x in runner.levels)
    what = (f"the certified escape region of the oscillator ({region.text()} at the cap; "
            "every solution entering it escapes under every input of that size) or "
            if region is not None else "")
    escape = (f"entering {what}a state beyond its level |z_j| >= ({level_text}) "
              f"(z = y, y', ...: {_level_reason(runner.levels)}) or non-finite, from rest "
              f"within {runner.t_end:g} s; "
              + ("NARX recursion, re-run" if runner.discrete else
                 f"found on fixed-step RK4 (step {runner.h:.4g} s), confirmed by DOP853 at "
                 f"rtol {CHECK_RTOLS[0]:g} and {CHECK_RTOLS[1]:g} (escape times within "
                 f"{TIME_AGREEMENT:.0%}; switches as integration boundaries)")
              + f"; margin {MARGINS[0]:g}x or more on the edge found")
    if runner.notes:
        escape += "; " + "; ".join(runner.notes)
    candidates: list[tuple[float, int, str, Any]] = (
        [(e, i, "switching", c) for e, i, c in switched]
        + [(e, len(switched) + i, "tones", s) for e, i, s in found]
        + [(e, len(switched) + len(found) + i, "chirp", c) for e, i, c in chirped])
    candidates.sort(key=lambda x: (x[0], x[1]))
    listed = [{"edge": e, "kind": k, **_shape(k, s)} for e, _, k, s in candidates]
    common = dict(cap=cap, t_end=runner.t_end, escape=escape, levels=list(runner.levels),
                  discrete=runner.discrete, candidates=listed)
    above = [c for c in candidates if c[0] * MARGINS[-1] >= floor]
    for edge, _, kind, shape in above[:MAX_CANDIDATES]:
        for factor in MARGINS:
            amp = edge * factor
            if amp < floor:
                continue
            if kind == "chirp":
                chirp = replace(shape, amplitude=amp)
                t_escape = runner.confirm_chirp(chirp)
                if t_escape is not None:
                    if progress:
                        progress(total, total)
                    return Falsification(amp, [], t_escape, edge, runs=runner.runs,
                                         kind="chirp", chirp=chirp,
                                         region=runner.region(amp), **common)
                continue
            if kind == "switching":
                run = runner.switch(shape, amp)
                if not run.escaped:
                    continue
                t_escape = runner.confirm_switching(amp, run.first_sign, run.switch_times)
                if t_escape is not None:
                    if progress:
                        progress(total, total)
                    return Falsification(amp, [], t_escape, edge, runs=runner.runs,
                                         kind="switching", first_sign=run.first_sign,
                                         switch_times=run.switch_times,
                                         region=runner.region(amp), **common)
                continue
            tones = scaled(shape, amp)
            t_escape = runner.confirm(tones)
            if t_escape is not None:
                if progress:
                    progress(total, total)
                return Falsification(sum(a for a, _, _ in tones), tones, t_escape, edge,
                                     runs=runner.runs, kind="tones",
                                     region=runner.region(amp), **common)
    if progress:
        progress(total, total)
    return Falsification(None, [], None, None, runs=runner.runs, **common)


def _shape(kind: str, shape: Any) -> dict[str, Any]:
    """A candidate's input shape for the JSON ``candidates`` list."""
    if kind == "tones":
        return {"tones": [list(t) for t in shape]}
    if kind == "chirp":
        return {"chirp": {"omega_start": shape.omega_start, "omega_end": shape.omega_end,
                          "duration": shape.duration}}
    return {"switching_function": shape if isinstance(shape, str)
            else [float(x) for x in shape]}


def _level_reason(levels: np.ndarray) -> str:
    if levels[0] == DEFAULT_LEVEL:
        return f"{DEFAULT_LEVEL:g}, no nonzero real equilibrium to scale by"
    return "100x the largest nonzero real equilibrium, times |lambda|^j for y^(j)"
