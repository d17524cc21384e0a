"""The upper side: the smallest sum of tones whose response from rest escapes.

The inputs are those of Theorem 1's class, u(t) = sum_i A_i cos(omega_i t + phi_i),
switched on at t = 0 with the system at rest; the amplitude is sum_i A_i (as
:func:`gfrf.sim.volterra.input_amplitude` counts it; in a loop, the reference's).
*Escape* means |y| >= :data:`ESCAPE_LEVEL` (or a non-finite state) before the horizon:
for a polynomial flow that has passed its separatrix this is a finite-time blow-up.

The search (all on the compiled fixed-step RK4 of :mod:`gfrf.sim.fastsim`; NARX models
run their recursion):

1. single tones (phase 0) on a log grid of frequencies spanning the linear part's
   eigenvalue moduli (x 0.2 .. x 3, so the softening and hardening shifts of the
   resonance and its super- and sub-harmonics are covered), plus the exact sub- and
   super-harmonics 1/3, 1/2, 2, 3 of the least damped mode; for each, the escaping
   amplitude is found by halving from the cap, then bisection;
2. around the three best frequencies: a finer frequency grid, the phases pi/2, pi,
   3 pi/2, and two-tone inputs (omega, 2 omega), (omega, 3 omega), (omega, omega/2),
   (omega, omega/3) sharing the amplitude 3:1;
3. the witness: the best edge times 1.02 (then 1.03, 1.05, 1.08, 1.12, then the next
   candidate), accepted only if it escapes on the fast path at the search step and at
   half of it, and under scipy's DOP853 at rtol 1e-9 and 1e-11 with escape times that
   agree to 1 %.  The margin keeps the witness away from the fractal edge where escape
   comes and goes with the tolerance.

Every stop is on work (grid sizes, bisection counts), never on time: the same model
gives the same witness, byte for byte.  The witness is a simulation fact (an estimate-
grade fact: no enclosure of the trajectory is computed).  Its amplitude is measured as a
sum of tone amplitudes of a tone switched on at t = 0, whose spectrum has an infinite L1
norm: it bounds neither Theorem 1's radius nor the static bound, and is reported beside
them in its own units.
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

__all__ = ["Falsification", "falsify", "ESCAPE_LEVEL", "CAP_FACTOR", "CHECK_RTOLS",
           "MARGINS", "tones_text"]

#: |y| at which a response counts as escaped (a blow-up of the polynomial flow).
ESCAPE_LEVEL = 1e6
#: The search cap: this many times the reference amplitude (the static bound, or r*, or 1).
CAP_FACTOR = 10.0
#: Longest horizon in seconds (continuous models).
T_MAX = 400.0
#: Horizon: this many time constants of the slowest linear mode.
TIME_CONSTANTS = 40.0
#: Shortest horizon in seconds.
T_MIN = 60.0
#: NARX horizon in samples: at least, at most.
SAMPLES = (500, 2000)
#: Frequencies of the first stage.
N_FREQUENCIES = 40
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

Tone = tuple[float, float, float]


def tones_text(tones: list[Tone]) -> str:
    """The input u(t) = sum A cos(omega t + phi) as gfrf input text (exact float reprs)."""
    return " + ".join(f"{a!r}*cos({w!r}*t + {p!r})" for a, w, p in tones)


def _scaled(shape: list[Tone], amplitude: float) -> list[Tone]:
    return [(a * amplitude, w, p) for a, w, p in shape]


@dataclass(frozen=True)
class Falsification:
    """Result of :func:`falsify`.

    Attributes
    ----------
    upper : float or None
        Sum of the witness's tone amplitudes; None: no escape up to ``cap``.
    tones : list of (amplitude, omega_rad_s, phase_rad)
        The witness u = sum A cos(omega t + phi), switched on at t = 0 from rest.
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
    candidates : list of dict
        The edges found per input shape (stage 1 and 2), for reports.
    """

    upper: float | None
    tones: list[Tone]
    t_escape: float | None
    edge: float | None
    cap: float
    t_end: float
    runs: int
    escape: str
    candidates: list[dict[str, Any]] = field(default_factory=list, repr=False)

    def witness(self) -> dict[str, Any] | None:
        """The JSON witness ``{"tones": [[A, omega, phase], ...], "t_escape": t}`` or None."""
        if self.upper is None:
            return None
        return {"tones": [list(t) for t in self.tones], "t_escape": self.t_escape}


class _Runner:
    """Escape tests of one system on the fast path (fixed step) or the NARX recursion."""

    def __init__(self, system: Any, top_omega: float):
        self.system = system
        self.runs = 0
        ev = np.asarray(self.system.linear_eigenvalues, dtype=complex)
        self.discrete = self.system.discrete
        if self.discrete:
            mod = float(np.max(np.abs(ev))) if ev.size else 0.0
            decay = -math.log(mod) if 0 < mod < 1 else 1.0
            n = int(min(SAMPLES[1], max(SAMPLES[0], math.ceil(TIME_CONSTANTS / decay))))
            self.t_end = n * float(self.system.sample_time)  # type: ignore[arg-type]
            return
        slow = float(np.min(np.abs(ev.real))) if ev.size else 1.0
        fast = float(np.max(np.abs(ev))) if ev.size else 1.0
        self.t_end = float(min(T_MAX, max(T_MIN, TIME_CONSTANTS / max(slow, 1e-12))))
        self.h = min(0.5 / max(fast, 1e-12), 2 * math.pi / top_omega / 40)
        self.steps = int(math.ceil(self.t_end / self.h))
        self.h = self.t_end / self.steps
        self.orders = []
        for name in self.system.input_names:
            head, _, k = name.rpartition("__")
            self.orders.append(int(k) if k.isdigit() and head else 0)
        from gfrf.sim.fastsim import compile_system, numba_available

        self.module = compile_system(self.system)[0] if numba_available() else None

    def escapes(self, tones: list[Tone], refine: int = 1) -> bool:
        """True if the response from rest to ``tones`` reaches :data:`ESCAPE_LEVEL`."""
        self.runs += 1
        if self.discrete or self.module is None:
            return self._simulate(tones, "dop853", 1e-7)[0]
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
                                 np.array([h]), V, V[-1:].copy(), steps, ESCAPE_LEVEL)
        return not abs(Z[done, 0]) < ESCAPE_LEVEL

    def _simulate(self, tones: list[Tone], method: str, rtol: float
                  ) -> tuple[bool, float | None]:
        from gfrf.sim.simulation import simulate

        with warnings.catch_warnings():  # "expect growth": escaping is what is looked for
            warnings.simplefilter("ignore", UserWarning)
            res = simulate(self.system, tones_text(tones), t_end=self.t_end, method=method,
                           rtol=rtol, atol=rtol * 1e-3, blowup=ESCAPE_LEVEL, n_out=2)
        return res.status == "blowup", res.blowup_time

    def confirm(self, tones: list[Tone]) -> float | None:
        """Escape time of ``tones`` if the independent checks agree that it escapes."""
        if self.discrete:
            self.runs += 1
            escaped, time = self._simulate(tones, "dop853", 1e-9)
            return time if escaped else None
        if not (self.escapes(tones) and self.escapes(tones, refine=2)):
            return None
        times = []
        for rtol in CHECK_RTOLS:
            self.runs += 1
            escaped, time = self._simulate(tones, "dop853", rtol)
            if not escaped or time is None:
                return None
            times.append(time)
        if abs(times[0] - times[1]) > TIME_AGREEMENT * max(times):
            return None
        return times[-1]


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


def _edge(runner: _Runner, shape: list[Tone], cap: float) -> float | None:
    """Smallest escaping amplitude of ``shape`` found by halving from ``cap`` and bisection."""
    if not runner.escapes(_scaled(shape, cap)):
        return None
    hi, lo = cap, 0.0
    for _ in range(HALVINGS):
        a = hi / 2
        if runner.escapes(_scaled(shape, a)):
            hi = a
        else:
            lo = a
            break
    if lo == 0.0:
        return hi
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        if runner.escapes(_scaled(shape, mid)):
            hi = mid
        else:
            lo = mid
    return hi


def _refinements(w: float, best: bool, nyquist: float | None) -> list[list[Tone]]:
    shapes = [[(1.0, w * (1 + 0.015 * j), 0.0)] for j in (-3, -2, -1, 1, 2, 3)]
    if best:
        shapes += [[(1.0, w, p)] for p in (math.pi / 2, math.pi, 3 * math.pi / 2)]
        for m in (2.0, 3.0, 0.5, 1 / 3):
            shapes.append([(0.75, w, 0.0), (0.25, m * w, 0.0)])
    if nyquist is not None:
        shapes = [s for s in shapes if all(0 < t[1] <= nyquist for t in s)]
    return shapes


def falsify(source: ModelFile | Model, cap: float, *, closed_loop: bool = False,
            progress: Callable[[int, int], None] | None = None) -> Falsification:
    """Search sums of tones for the smallest amplitude whose response from rest escapes.

    Parameters
    ----------
    source : ModelFile or Model
        The model (a model file with ``closed_loop`` for the loop with its controller).
    cap : float
        Largest amplitude searched (> 0).
    closed_loop : bool
        Search the reference of the closed loop.
    progress : callable, optional
        Called as ``progress(done, total)`` after each input shape.

    Returns
    -------
    Falsification
    """
    from gfrf.sim.system import build_system

    system = build_system(source, closed_loop=closed_loop, equation="polynomial")
    ev = np.asarray(system.linear_eigenvalues, dtype=complex)
    omegas, ref = _frequencies(ev, system.discrete, system.sample_time)
    nyquist = math.pi / float(system.sample_time) if system.discrete else None
    top = float(np.max(omegas)) * (3.0 if not system.discrete else 1.0)
    runner = _Runner(system, top)
    shapes = [[(1.0, float(w), 0.0)] for w in omegas]
    total = len(shapes) + 3 * 6 + 7
    found: list[tuple[float, int, list[Tone]]] = []
    done = 0
    for shape in shapes:
        edge = _edge(runner, shape, cap)
        if edge is not None:
            found.append((edge, len(found), shape))
        done += 1
        if progress:
            progress(done, total)
    best_w: list[float] = []
    for _, _, shape in sorted(found):
        w = shape[0][1]
        if all(abs(w / b - 1) > 0.05 for b in best_w):
            best_w.append(w)
        if len(best_w) == 3:
            break
    for i, w in enumerate(best_w):
        for shape in _refinements(w, i == 0, nyquist):
            edge = _edge(runner, shape, cap)
            if edge is not None:
                found.append((edge, len(found), shape))
            done += 1
            if progress:
                progress(min(done, total), total)
    escape = (f"|y| >= {ESCAPE_LEVEL:g} (blow-up) from rest within {runner.t_end:g} s; "
              + ("NARX recursion, re-run" if runner.discrete else
                 f"found on the fixed-step RK4 fast path (step {runner.h:.4g} s), confirmed "
                 f"at half the step and by DOP853 at rtol {CHECK_RTOLS[0]:g} and "
                 f"{CHECK_RTOLS[1]:g} (escape times within {TIME_AGREEMENT:.0%})")
              + f"; margin {MARGINS[0]:g}x or more on the edge found")
    candidates = [{"edge": e, "tones": [list(t) for t in s]} for e, _, s in sorted(found)]
    for edge, _, shape in sorted(found)[:MAX_CANDIDATES]:
        for factor in MARGINS:
            tones = _scaled(shape, edge * factor)
            t_escape = runner.confirm(tones)
            if t_escape is not None:
                if progress:
                    progress(total, total)
                return Falsification(sum(a for a, _, _ in tones), tones, t_escape, edge,
                                     cap, runner.t_end, runner.runs, escape, candidates)
    if progress:
        progress(total, total)
    return Falsification(None, [], None, None, cap, runner.t_end, runner.runs, escape,
                         candidates)
