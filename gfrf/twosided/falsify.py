"""The upper side: the smallest bounded input whose response from rest escapes.

Two input families are searched, both switched on at t = 0 with the system at rest:

* **switching inputs** u = +-U, the sign following a state function s = c . z
  (z = (y, y', ..., y^(n-1))): the velocity, a*y + y' (the energy-pumping input of an
  oscillator and its phase-shifted variants; Pontryagin's principle gives a bounded
  input's extremals this bang-bang form), and each state alone (for a first-order
  model, a constant input); then a count-bounded optimiser over a (golden-section
  steps on the switching function's phase).  Their amplitude is sup|u| = U, the
  L-infinity size of the lower side's class.  Not for NARX models or models that use
  input derivatives;
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
:mod:`gfrf.twosided.enclose` encloses it.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile
from gfrf.twosided.escape import DEFAULT_LEVEL, EscapeRegion, escape_levels, escape_region

__all__ = ["Falsification", "falsify", "ESCAPE_LEVEL", "CAP_FACTOR", "CHECK_RTOLS",
           "MARGINS", "MAX_RUN_STEPS", "tones_text", "switching_text"]

#: Escape level of a model without a scale of its own (see :mod:`gfrf.twosided.escape`).
ESCAPE_LEVEL = DEFAULT_LEVEL
#: The search cap: this many times the reference amplitude (the static bound, or r*, or 1).
CAP_FACTOR = 10.0
#: Longest horizon in seconds (continuous models).
T_MAX = 400.0
#: Horizon: this many time constants of the slowest linear mode ...
TIME_CONSTANTS = 40.0
#: ... and at least this many periods of the slowest linear mode.
PERIODS = 10.0
#: NARX horizon in samples: at least, at most.
SAMPLES = (500, 2000)
#: RK4 steps of one run at most: a stiff model's horizon is shortened to fit (stated).
MAX_RUN_STEPS = 200_000
#: Frequencies of the first stage.
N_FREQUENCIES = 48
#: Halvings from the cap, then bisections of the escaping amplitude.
HALVINGS, BISECTIONS = 12, 10
#: Factors on the best edge tried for the witness, in order.
MARGINS = (1.02, 1.03, 1.05, 1.08, 1.12)
#: The two DOP853 tolerances of the witness check (rtol; atol = rtol * 1e-3).
CHECK_RTOLS = (1e-9, 1e-11)
#: Relative agreement of the two escape times.
TIME_AGREEMENT = 0.01
#: Candidates (best edges) tried for a witness at most.
MAX_CANDIDATES = 4
#: Phases a (times the reference frequency) of s = y' + a*y tried, then golden steps.
PHASES = (-0.5, -0.2, 0.2, 0.5)
GOLDEN_STEPS = 6

Tone = tuple[float, float, float]


def tones_text(tones: list[Tone]) -> str:
    """The input u(t) = sum A cos(omega t + phi) as gfrf input text (exact float reprs).

    Parameters
    ----------
    tones : list of tuple of float
        ``(A, omega, phi)`` per tone: amplitude, angular frequency in rad/s, phase in rad.
    """
    return " + ".join(f"{a!r}*cos({w!r}*t + {p!r})" for a, w, p in tones)


def switching_text(amplitude: float, first_sign: int, switch_times: list[float]) -> str:
    """The switching input in words (all switch times when few, else the first and last)."""
    times = [f"{t:.6g}" for t in switch_times]
    if len(times) > 8:
        times = times[:4] + [f"... ({len(switch_times) - 6} more)"] + times[-2:]
    start = f"u = {'+' if first_sign > 0 else '-'}{amplitude!r} on [0, t1)"
    if not switch_times:
        return f"u = {first_sign * amplitude!r} (constant)"
    return (f"{start}, the sign alternating at each of {len(switch_times)} switch times t = "
            + ", ".join(times) + " s")


def _scaled(shape: list[Tone], amplitude: float) -> list[Tone]:
    return [(a * amplitude, w, p) for a, w, p in shape]


@dataclass(frozen=True)
class Falsification:
    """Result of :func:`falsify`.

    Attributes
    ----------
    upper : float or None
        The witness's amplitude: sup|u| = U of a switching input, the sum of the tone
        amplitudes of a sum of tones; None: no escape up to ``cap``.
    kind : str or None
        ``"switching"`` or ``"tones"``.
    tones : list of (amplitude, omega_rad_s, phase_rad)
        A tone witness u = sum A cos(omega t + phi), switched on at t = 0 from rest.
    first_sign : int
        A switching witness: u = first_sign * U on [0, t1).
    switch_times : list of float
        A switching witness: the times (s) at which the sign of u alternates.
    t_escape : float or None
        Escape time (s) of the witness under DOP853 at the tighter tolerance
        (NARX: of the recursion).
    edge : float or None
        The smallest escaping amplitude the search found (the witness has a margin on it).
    cap : float
        The search cap on the amplitude.
    t_end : float
        The horizon in seconds.
    runs : int
        Simulations run.
    escape : str
        What escape meant, and how the witness was checked.
    region : EscapeRegion or None
        The certified escape region used (oscillators).
    levels : list of float
        Escape level of each state.
    candidates : list of dict
        The edges found per input shape, for reports.
    """

    upper: float | None
    tones: list[Tone]
    t_escape: float | None
    edge: float | None
    cap: float
    t_end: float
    runs: int
    escape: str
    kind: str | None = None
    first_sign: int = 1
    switch_times: list[float] = field(default_factory=list, repr=False)
    region: EscapeRegion | None = field(default=None, repr=False)
    levels: list[float] = field(default_factory=list, repr=False)
    discrete: bool = False
    candidates: list[dict[str, Any]] = field(default_factory=list, repr=False)

    def witness(self) -> dict[str, Any] | None:
        """The JSON witness (``kind`` ``"tones"`` or ``"switching"``), or None."""
        if self.upper is None:
            return None
        if self.kind == "switching":
            return {"kind": "switching", "amplitude": self.upper,
                    "first_sign": self.first_sign, "switch_times": list(self.switch_times),
                    "t_escape": self.t_escape}
        return {"kind": "tones", "tones": [list(t) for t in self.tones],
                "t_escape": self.t_escape}

    def input_text(self) -> str:
        """The witness input in words."""
        if self.kind == "switching":
            return switching_text(self.upper or 0.0, self.first_sign, self.switch_times)
        return f"u = {tones_text(self.tones)}"


class _Runner:
    """Escape tests of one system on the fast path (fixed step) or the NARX recursion."""

    def __init__(self, system: Any, model: Model, top_omega: float):
        self.system = system
        self.model = model
        self.runs = 0
        self.notes: list[str] = []
        ev = np.asarray(self.system.linear_eigenvalues, dtype=complex)
        self.levels = escape_levels(model, ev, system.n_states)
        self.discrete = self.system.discrete
        self.module = self.bang = None
        if self.discrete:
            mod = float(np.max(np.abs(ev))) if ev.size else 0.0
            decay = -math.log(mod) if 0 < mod < 1 else 1.0
            n = int(min(SAMPLES[1], max(SAMPLES[0], math.ceil(TIME_CONSTANTS / decay))))
            self.t_end = n * float(self.system.sample_time)  # type: ignore[arg-type]
            self.samples = n
            return
        nonzero = np.abs(ev[np.abs(ev) > 0])
        slow = float(np.min(np.abs(ev.real))) if ev.size else 1.0
        fast = float(np.max(np.abs(ev))) if ev.size else 1.0
        period = 2 * math.pi / float(nonzero.min()) if nonzero.size else 2 * math.pi
        self.t_end = float(min(T_MAX, max(PERIODS * period,
                                          TIME_CONSTANTS / max(slow, 1e-12))))
        h = min(0.5 / max(fast, 1e-12), 2 * math.pi / top_omega / 40)
        if self.t_end / h > MAX_RUN_STEPS:
            self.notes.append(f"horizon shortened from {self.t_end:.4g} s to fit MAX_RUN_STEPS "
                              f"= {MAX_RUN_STEPS} RK4 steps of {h:.3g} s")
            self.t_end = MAX_RUN_STEPS * h
        self.steps = max(1, int(math.ceil(self.t_end / h)))
        self.h = self.t_end / self.steps
        self.orders = []
        for name in self.system.input_names:
            head, _, k = name.rpartition("__")
            self.orders.append(int(k) if k.isdigit() and head else 0)
        from gfrf.sim.fastsim import compile_system, numba_available

        if numba_available():
            self.module = compile_system(self.system)[0]
            if all(k == 0 for k in self.orders) and not self.system.closed_loop:
                from gfrf.twosided.switching import switching_module

                self.bang = switching_module(self.system)

    def region(self, amplitude: float) -> EscapeRegion | None:
        if self.discrete or self.system.closed_loop or self.system.n_states != 2:
            return None
        return escape_region(self.model, amplitude)

    def _escaped_states(self, Z: np.ndarray, region: EscapeRegion | None) -> bool:
        with np.errstate(invalid="ignore"):
            if not np.all(np.abs(Z) < self.levels):
                return True
            if region is not None:
                y, p = Z[:, 0], Z[:, 1]
                return bool(np.any((y >= region.y_plus) & (p >= 0))
                            or np.any((y <= -region.y_minus) & (p <= 0)))
        return False

    def escapes(self, tones: list[Tone], refine: int = 1) -> bool:
        """True if the response from rest to ``tones`` escapes."""
        self.runs += 1
        region = self.region(sum(abs(a) for a, _, _ in tones))
        if self.discrete or self.module is None:
            return self._simulate(tones, 1e-7, region) is not None
        from gfrf.sim.fastsim import _rk4

        steps, h = self.steps * refine, self.h / refine
        t = np.arange(2 * steps + 1) * (0.5 * h)
        V = np.zeros((t.size, len(self.orders)))
        for a, w, p in tones:
            for j, k in enumerate(self.orders):
                V[:, j] += a * w**k * np.cos(w * t + p + k * math.pi / 2)
        z0 = np.zeros(self.system.n_states)
        with np.errstate(all="ignore"):
            Z, _, _, done = _rk4(self.module, z0, np.array([steps], dtype=np.int64),
                                 np.array([h]), V, V[-1:].copy(), steps, float(self.levels[0]))
        return self._escaped_states(Z[:done + 1], region)

    def switch(self, c: Any, amplitude: float, first_sign: int = 1) -> Any:
        """The feedback run u = U sign(c . z) (a :class:`~.switching.SwitchRun`); for a
        NARX model ``c`` names a sign rule of :mod:`gfrf.twosided.narx_signs`."""
        from gfrf.twosided.switching import run_switching

        self.runs += 1
        if self.discrete:
            from gfrf.twosided.narx_signs import run_signs

            return run_signs(self.system, c, amplitude, self.samples, float(self.levels[0]))
        region = self.region(amplitude)
        return run_switching(self.bang, self.system.n_states, c, amplitude, first_sign,  # type: ignore[arg-type]
                             self.h, self.steps, self.levels,
                             region.flags() if region is not None else (0.0, 0.0, 0.0))

    def _simulate(self, tones: list[Tone], rtol: float, region: EscapeRegion | None
                  ) -> float | None:
        """Escape time of ``tones`` (scipy DOP853, or the NARX recursion), or None."""
        if self.discrete:
            from gfrf.sim.simulation import simulate

            with warnings.catch_warnings():  # "expect growth": escaping is looked for
                warnings.simplefilter("ignore", UserWarning)
                res = simulate(self.system, tones_text(tones), t_end=self.t_end,
                               method="dop853", rtol=rtol, atol=rtol * 1e-3,
                               blowup=float(self.levels[0]), n_out=2)
            return res.blowup_time if res.status == "blowup" else None
        from gfrf.twosided.switching import dop853_escape

        orders = self.orders

        def values(t: float, v: np.ndarray) -> None:
            v[:] = 0.0
            for a, w, p in tones:
                for j, k in enumerate(orders):
                    v[j] += a * w**k * math.cos(w * t + p + k * math.pi / 2)

        return dop853_escape(self.system, values, [0.0, self.t_end], self.levels, rtol,
                             region)

    def confirm(self, tones: list[Tone]) -> float | None:
        """Escape time of ``tones`` if the independent checks agree that it escapes."""
        region = self.region(sum(abs(a) for a, _, _ in tones))
        if self.discrete:
            self.runs += 1
            return self._simulate(tones, 1e-9, region)
        if not (self.escapes(tones) and self.escapes(tones, refine=2)):
            return None
        return self._agreeing([self._simulate(tones, rtol, region) for rtol in CHECK_RTOLS])

    def confirm_switching(self, amplitude: float, first_sign: int, times: list[float]
                          ) -> float | None:
        from gfrf.twosided.switching import replay

        if self.discrete:
            from gfrf.twosided.narx_signs import replay_signs

            self.runs += 1
            return replay_signs(self.system, amplitude, first_sign, times, self.samples,
                                float(self.levels[0]))
        region = self.region(amplitude)
        self.runs += len(CHECK_RTOLS)
        return self._agreeing([replay(self.system, amplitude, first_sign, times, self.t_end,
                                      self.levels, rtol, region) for rtol in CHECK_RTOLS])

    @staticmethod
    def _agreeing(times: list[float | None]) -> float | None:
        if any(t is None for t in times):
            return None
        ts = [float(t) for t in times if t is not None]
        if abs(ts[0] - ts[-1]) > TIME_AGREEMENT * max(ts):
            return None
        return ts[-1]


def _frequencies(runner_ev: np.ndarray, discrete: bool, sample_time: float | None
                 ) -> tuple[np.ndarray, float]:
    """The first-stage grid (rad/s) and the least damped mode's frequency."""
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


def _switching_stage(runner: _Runner, ref: float, cap: float
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
        Search the reference of the closed loop.
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
    omegas, ref = _frequencies(ev, system.discrete, system.sample_time)
    nyquist = math.pi / float(system.sample_time) if system.discrete else None
    top = float(np.max(omegas)) * (3.0 if not system.discrete else 1.0)
    runner = _Runner(system, model, top)
    total = len(omegas) + 3 * 6 + 7 + 1
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
    found: list[tuple[float, int, list[Tone]]] = []
    for w in omegas:
        edge = _edge(lambda a, s=[(1.0, float(w), 0.0)]: runner.escapes(_scaled(s, a)),
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
            edge = _edge(lambda a, s=shape: runner.escapes(_scaled(s, a)), tone_cap)
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
        + [(e, len(switched) + i, "tones", s) for e, i, s in found])
    candidates.sort(key=lambda x: (x[0], x[1]))
    listed = [{"edge": e, "kind": k, **({"tones": [list(t) for t in s]} if k == "tones" else
                                        {"switching_function": s if isinstance(s, str)
                                         else [float(x) for x in s]})}
              for e, _, k, s in candidates]
    common = dict(cap=cap, t_end=runner.t_end, escape=escape, levels=list(runner.levels),
                  discrete=runner.discrete, candidates=listed)
    above = [c for c in candidates if c[0] * MARGINS[-1] >= floor]
    for edge, _, kind, shape in above[:MAX_CANDIDATES]:
        for factor in MARGINS:
            amp = edge * factor
            if amp < floor:
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
            tones = _scaled(shape, amp)
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


def _level_reason(levels: np.ndarray) -> str:
    if levels[0] == DEFAULT_LEVEL:
        return f"{DEFAULT_LEVEL:g}, no nonzero real equilibrium to scale by"
    return "100x the largest nonzero real equilibrium, times |lambda|^j for y^(j)"
