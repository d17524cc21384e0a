"""Bang-bang inputs u = +-U switching on the sign of a state function, compiled.

For a bounded input |u| <= U, Pontryagin's principle gives the extremal inputs a
bang-bang structure: u = U sign(s(t)) for a switching function s.  The classic
energy-pumping input of an oscillator is u = U sign(y') (the input does work y' u =
U |y'| >= 0); with damping or a phase lag, s = a*y + y' does better.  This module runs
the feedback u = U sign(c . z) (z: the state y, y', ..., y^(n-1)) on a fixed-step RK4,
compiled by numba from the model's generated right-hand side, and records each switch
at the step boundary where the sign of c . z turned against u.  The recorded switch
times then define an open-loop input (``first_sign``, ``switch_times``) that anyone can
replay: :func:`replay` integrates it with scipy's DOP853 segment by segment, each switch
an integration boundary (the input is constant on every segment).

Escape is leaving the box |z_j| < level_j (or a non-finite state), or entering a
certified escape region when one is given (see :mod:`gfrf.twosided.escape`).
"""

from __future__ import annotations

import bisect
import hashlib
import warnings
from collections.abc import Callable
from types import ModuleType
from typing import Any

import numpy as np

__all__ = ["SwitchRun", "switching_module", "run_switching", "replay", "dop853_escape",
           "MAX_SWITCHES"]

#: Most switches one run records (a chattering feedback stops here: no escape).
MAX_SWITCHES = 20_000

_LOOP = '''

@njit(cache={cache}, error_model="numpy")
def bang(z, c, amp, sign0, h, start, stop, level, region, times, state):
    n = z.size
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    k4 = np.empty(n)
    tmp = np.empty(n)
    v = np.zeros({n_inputs})
    u = state[0]
    ns = int(state[1])
    for i in range(start, stop):
        v[0] = u
        rhs(z, v, k1)
        for j in range(n):
            tmp[j] = z[j] + 0.5 * h * k1[j]
        rhs(tmp, v, k2)
        for j in range(n):
            tmp[j] = z[j] + 0.5 * h * k2[j]
        rhs(tmp, v, k3)
        for j in range(n):
            tmp[j] = z[j] + h * k3[j]
        rhs(tmp, v, k4)
        for j in range(n):
            z[j] = z[j] + h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
        for j in range(n):
            if not abs(z[j]) < level[j]:
                state[0] = u
                state[1] = ns
                return i + 1
        if region[0] > 0.0:
            if z[0] >= region[1] and z[1] >= 0.0:
                state[0] = u
                state[1] = ns
                return i + 1
            if z[0] <= -region[2] and z[1] <= 0.0:
                state[0] = u
                state[1] = ns
                return i + 1
        s = 0.0
        for j in range(n):
            s += c[j] * z[j]
        if s * u < 0.0:
            if ns >= times.size:
                state[0] = u
                state[1] = ns
                return -(i + 1)
            times[ns] = (i + 1) * h
            ns += 1
            u = -u
    state[0] = u
    state[1] = ns
    return 0
'''
_MODULES: dict[str, ModuleType] = {}
#: Steps per compiled call (the loop returns to Python between slices: Ctrl-C acts).
_SLICE = 2**15


def switching_module(system: Any) -> ModuleType:
    """The compiled module (``rhs`` and the switching loop ``bang``) of ``system``.

    Parameters
    ----------
    system : OdeSystem
        The model's generated state form (:func:`gfrf.sim.system.build_system`).

    Returns
    -------
    ModuleType
        The compiled module, cached on disk by the hash of its source.
    """
    from gfrf._cache import load_generated
    from gfrf.sim.fastsim import _DECORATOR

    def source(cache: bool) -> str:
        body = system.source.replace("def ", _DECORATOR.format(cache=cache) + "def ")
        return ("import math\n\nimport numpy as np\nfrom numba import njit\n\n\n" + body
                + _LOOP.format(cache=cache, n_inputs=system.n_inputs))

    name = "gfrf_bang_" + hashlib.sha256(source(True).encode()).hexdigest()[:24]
    if name not in _MODULES:
        _MODULES[name] = load_generated("fastsim", name, source)
    return _MODULES[name]


class SwitchRun:
    """One feedback run: ``escaped``, ``t_escape`` (s), ``switch_times`` (s)."""

    __slots__ = ("escaped", "t_escape", "switch_times", "first_sign")

    def __init__(self, escaped: bool, t_escape: float | None, switch_times: list[float],
                 first_sign: int):
        self.escaped, self.t_escape = escaped, t_escape
        self.switch_times, self.first_sign = switch_times, first_sign


def run_switching(module: ModuleType, n_states: int, c: np.ndarray, amplitude: float,
                  first_sign: int, h: float, steps: int, level: np.ndarray,
                  region: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> SwitchRun:
    """Run u = U sign(c . z) from rest (u = first_sign * U until the first switch).

    Parameters
    ----------
    module : ModuleType
        From :func:`switching_module`.
    n_states : int
        Number of states.
    c : numpy.ndarray
        The switching function's coefficients on the state.
    amplitude : float
        U.
    first_sign : int
        +1 or -1.
    h : float
        RK4 step (s).
    steps : int
        Steps to the horizon.
    level : numpy.ndarray
        Escape level of each state.
    region : (flag, y_plus, y_minus)
        With flag > 0, escape also when y >= y_plus and y' >= 0, or y <= -y_minus and
        y' <= 0 (a certified escape region of an oscillator).

    Returns
    -------
    SwitchRun
    """
    z = np.zeros(n_states)
    times = np.empty(MAX_SWITCHES)
    state = np.array([first_sign * amplitude, 0.0])
    reg = np.array(region, dtype=float)
    hit = 0
    with np.errstate(all="ignore"):
        for start in range(0, steps, _SLICE):
            hit = module.bang(z, np.asarray(c, dtype=float), amplitude, first_sign, h, start,
                              min(start + _SLICE, steps), level, reg, times, state)
            if hit != 0:
                break
    ns = int(state[1])
    escaped = hit > 0
    return SwitchRun(escaped, hit * h if escaped else None, times[:ns].tolist(), first_sign)


def dop853_escape(system: Any, values: Any, edges: list[float], level: np.ndarray,
                  rtol: float, region: Any = None, piecewise: bool = False) -> float | None:
    """Escape time under scipy's DOP853, integrating segment by segment, or None.

    ``values(t, v)`` fills the input vector v at time t (constant on a segment of a
    switching input: with ``piecewise``, called once per segment at its midpoint);
    ``edges`` are the segment boundaries (0, the switches, t_end).
    Escape: a state reaching its level, entering the ``region`` (an
    :class:`~gfrf.twosided.escape.EscapeRegion`), or DOP853 failing (its step size
    collapsing at a finite-time blow-up; the two tolerances must agree on the time).

    Parameters
    ----------
    system : OdeSystem
        The model's generated state form (:func:`gfrf.sim.system.build_system`).
    values : callable
        ``values(t, v)`` fills the input vector ``v`` at time ``t`` (s).
    edges : list of float
        Increasing segment boundaries in s, from 0 to the horizon; empty segments are
        skipped.
    level : numpy.ndarray
        Escape level of each state.
    rtol : float
        DOP853's relative tolerance (the absolute tolerance is ``rtol * 1e-3``).
    region : EscapeRegion, optional
        A certified escape region; None: escape by the levels only.
    piecewise : bool, optional
        The input is constant on each segment: ``values`` is called once per segment.

    Returns
    -------
    float or None
        The escape time in s, or None when the state stays inside to the last edge.
    """
    from scipy.integrate import solve_ivp

    rhs = system.function("rhs")
    n = system.n_states
    v = np.zeros(system.n_inputs)

    def field(t: float, z: np.ndarray) -> np.ndarray:
        out = np.empty(n)
        if not piecewise:
            values(t, v)
        rhs(z, v, out)
        return out

    events: list[Callable[..., float]] = [lambda _t, z, j=j: abs(z[j]) - level[j]
                                          for j in range(n)]
    if region is not None:
        yp, ym = region.y_plus, region.y_minus
        events.append(lambda _t, z: min(z[0] - yp, z[1]) if z[0] > 0 else -1.0)
        events.append(lambda _t, z: min(-z[0] - ym, -z[1]) if z[0] < 0 else -1.0)
    for e in events:
        e.terminal = True  # type: ignore[attr-defined]
        e.direction = 1  # type: ignore[attr-defined]
    z = np.zeros(n)
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            if b <= a:
                continue
            if piecewise:
                values(0.5 * (a + b), v)
            sol = solve_ivp(field, (a, b), z, method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                            events=events, first_step=None)
            if sol.status == 1:
                return float(next(te[0] for te in sol.t_events if te.size))
            end = sol.y[:, -1]
            if sol.status != 0 or not np.all(np.isfinite(end)):
                # the step size collapsed: a finite-time blow-up, evidence for the
                # validated integrator to settle
                return float(sol.t[-1])
            z = end
    return None


def replay(system: Any, amplitude: float, first_sign: int, switch_times: list[float],
           t_end: float, level: np.ndarray, rtol: float, region: Any = None) -> float | None:
    """Escape time of the open-loop switching input under DOP853, or None.

    The input is first_sign * U on [0, t1), then its sign alternates at each switch
    time; each segment is one ``solve_ivp`` call (no step crosses a switch).

    Parameters
    ----------
    system : OdeSystem
        The model's generated state form (:func:`gfrf.sim.system.build_system`).
    amplitude : float
        U, the size of the input.
    first_sign : int
        +1 or -1: the sign on [0, t1).
    switch_times : list of float
        Increasing switch times in s; those at or after ``t_end`` are ignored.
    t_end : float
        The horizon in s.
    level : numpy.ndarray
        Escape level of each state.
    rtol : float
        DOP853's relative tolerance (the absolute tolerance is ``rtol * 1e-3``).
    region : EscapeRegion, optional
        A certified escape region; None: escape by the levels only.

    Returns
    -------
    float or None
        The escape time in s, or None when the state stays inside to ``t_end``.
    """
    edges = [0.0, *[t for t in switch_times if t < t_end], t_end]

    def values(t: float, v: np.ndarray) -> None:
        k = bisect.bisect_right(switch_times, t)
        v[:] = 0.0
        v[0] = (first_sign if k % 2 == 0 else -first_sign) * amplitude

    return dop853_escape(system, values, edges, level, rtol, region, piecewise=True)
