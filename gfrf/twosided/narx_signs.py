"""Sign sequences u[k] = +-U for a NARX model: the discrete bang-bang inputs.

The rules (from rest; y[k] = 0 and u[k] = 0 before k = 0): a constant +-U, alternating
signs of period 2 and 4, the feedback u[k] = +-U sign(y[k-1]) and
+-U sign(y[k-1] - y[k-2]) (the discrete velocity), and a beam search over the sign
sequences (:mod:`gfrf.twosided.narx_beam`).  A run returns the sample times at
which the sign changed, so the witness is the same switching input as a continuous one
(u = first_sign * U on [0, t1), alternating at each switch time), sampled at t = kT.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gfrf.twosided.switching import SwitchRun

__all__ = ["RULES", "run_signs", "replay_signs"]

#: The sign rules tried, by name ("beam": the search of :mod:`gfrf.twosided.narx_beam`).
RULES = ("constant", "-constant", "period 2", "period 4", "sign y", "-sign y",
         "sign dy", "-sign dy", "beam")


def _recursion(system: Any, sign_of: Any, amplitude: float, samples: int, level: float,
               period: float) -> SwitchRun:
    rhs = system.function("rhs")
    lags, a = system.n_inputs, system.order
    z = np.zeros(system.n_states)
    out = np.empty(1)
    u: list[float] = []
    y: list[float] = []
    times: list[float] = []
    first = 1
    with np.errstate(all="ignore"):
        for k in range(samples):
            s = sign_of(k, y)
            if k == 0:
                first = s
            elif s != (1 if u[-1] > 0 else -1):
                times.append(k * period)
            u.append(s * amplitude)
            v = [u[k - i] if k - i >= 0 else 0.0 for i in range(lags)]
            rhs(z, v, out)
            y.append(float(out[0]))
            if not abs(out[0]) < level:
                return SwitchRun(True, k * period, times, first)
            z = np.concatenate((out[:1], z[:a][:-1])) if a else z
    return SwitchRun(False, None, times, first)


def _rule(name: str) -> Any:
    flip = -1 if name.startswith("-") else 1

    def sgn(x: float) -> int:
        return flip if x >= 0 else -flip

    if name.endswith("constant"):
        return lambda k, y: flip
    if name == "period 2":
        return lambda k, y: 1 if k % 2 == 0 else -1
    if name == "period 4":
        return lambda k, y: 1 if k % 4 < 2 else -1
    if name.endswith("sign y"):
        return lambda k, y: sgn(y[-1]) if y else flip
    return lambda k, y: sgn(y[-1] - (y[-2] if len(y) > 1 else 0.0)) if y else flip


def run_signs(system: Any, rule: str, amplitude: float, samples: int, level: float
              ) -> SwitchRun:
    """Run the sign rule ``rule`` (one of :data:`RULES`) at amplitude U from rest.

    Parameters
    ----------
    system : OdeSystem
        The NARX model's generated recursion (its ``rhs``, ``sample_time``, ``order``,
        ``n_inputs``).
    rule : str
        One of :data:`RULES`.
    amplitude : float
        U, the size of the input.
    samples : int
        Number of samples to run.
    level : float
        Escape when |y[k]| reaches it (or y[k] is not finite).

    Returns
    -------
    SwitchRun
        Whether and when (s) y escaped, and the sample times (s) of the sign changes.
    """
    if rule == "beam":
        from gfrf.twosided.narx_beam import beam_search

        return beam_search(system, amplitude, samples, level)
    return _recursion(system, _rule(rule), amplitude, samples, level,
                      float(system.sample_time))


def replay_signs(system: Any, amplitude: float, first_sign: int, switch_times: list[float],
                 samples: int, level: float) -> float | None:
    """Escape time of the open-loop sign sequence (switches at sample times), or None.

    Parameters
    ----------
    system : OdeSystem
        The NARX model's generated recursion (its ``rhs``, ``sample_time``, ``order``,
        ``n_inputs``).
    amplitude : float
        U, the size of the input.
    first_sign : int
        +1 or -1: the sign at k = 0.
    switch_times : list of float
        Times in s at which the sign changes, rounded to the nearest sample.
    samples : int
        Number of samples to run.
    level : float
        Escape when |y[k]| reaches it (or y[k] is not finite).

    Returns
    -------
    float or None
        The escape time in s, or None.
    """
    period = float(system.sample_time)
    flips = {round(t / period) for t in switch_times}
    state = {"s": first_sign}

    def sign_of(k: int, _y: list[float]) -> int:
        if k in flips:
            state["s"] = -state["s"]
        return state["s"]

    run = _recursion(system, sign_of, amplitude, samples, level, period)
    return run.t_escape if run.escaped and math.isfinite(run.t_escape or math.nan) else None
