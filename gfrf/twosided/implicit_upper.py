"""The upper side of an implicit loop (:mod:`gfrf.stability.implicit`), in the lower side's
input class: bounded plant-input signals d (d = C r for a loop with an improper
controller), sup|d| <= U.

Candidates (all from rest, d = +-U piecewise constant, the issue's switching witness
form ``first_sign`` and ``switch_times``):

* d = +U and d = -U held constant;
* d = -U until the state has settled at the equilibrium of d = -U (|y - y_-| and |y'|
  below 1e-6 of |y_-|), then d = +U (and the mirror): the largest swing a bounded
  input makes in an overdamped loop.

*Escape* is reaching the singular set of the loop: |D(y)| <= 1e-6 |D(0)|, where the
highest derivative y^(m) = -R / D is unbounded (the loop's equation stops determining
it), or a non-finite state.  The smallest escaping U is found by doubling from the
proven lower side, then bisection (counts, never time); the witness is that edge times
1.02 and must escape under DOP853 at rtol 1e-9 and 1e-11 with the switch as an
integration boundary, escape times within 1 %.  A simulation fact: estimate-grade
(the enclosure code of :mod:`gfrf.twosided.enclose` does not take a rational field).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf.stability.implicit import ImplicitLoop
from gfrf.stability.implicit_region import LoopField

__all__ = ["ImplicitWitness", "implicit_witness", "SINGULAR_LEVEL", "HORIZON"]

#: Escape: |D(y)| at or below this fraction of |D(0)|.
SINGULAR_LEVEL = 1e-6
#: Horizon of one run (s) and the settling tolerance of the first phase.
HORIZON = 50.0
_SETTLE = 1e-6
DOUBLINGS, BISECTIONS = 12, 8
MARGIN = 1.02
RTOLS = (1e-9, 1e-11)


@dataclass(frozen=True)
class ImplicitWitness:
    """A switching input d = first_sign * U on [0, t1), then alternating, that reaches
    the singular set (estimate-grade).

    Attributes
    ----------
    amplitude : float
        U = sup|d|.
    first_sign : int
        +1 or -1.
    switch_times : tuple of float
        Switch times (s); empty for a constant input.
    t_escape : float
        When the run reached the singular set (s), at rtol 1e-11.
    edge : float
        The smallest escaping amplitude found by bisection (the witness is 1.02 x it).
    runs : int
        Simulations run.
    """

    amplitude: float
    first_sign: int
    switch_times: tuple[float, ...]
    t_escape: float
    edge: float
    runs: int

    def witness(self) -> dict[str, Any]:
        """The issue's switching witness JSON (the input is d)."""
        return {"kind": "switching", "signal": "d", "amplitude": self.amplitude,
                "first_sign": self.first_sign, "switch_times": list(self.switch_times),
                "t_escape": self.t_escape}

    def text(self, name: str) -> str:
        """The witness in words.

        Parameters
        ----------
        name : str
            The signal's name in the text (``"d"``).

        Returns
        -------
        str
        """
        sign = "+" if self.first_sign > 0 else "-"
        if not self.switch_times:
            return f"{name} = {sign}{self.amplitude:.6g} constant"
        return (f"{name} = {sign}{self.amplitude:.6g} until t = {self.switch_times[0]:.6g} s, "
                f"then {'-' if sign == '+' else '+'}{self.amplitude:.6g}")


class _Runs:
    def __init__(self, form: ImplicitLoop):
        self.fl = LoopField(form)
        self.sing = self.fl.singular()
        self.q0 = self.fl.qf(0.0)
        self.count = 0

    def rhs(self, _t: float, x: np.ndarray, d: float) -> list[float]:
        y, v = float(x[0]), float(x[1])
        return [v, (self.fl.g0(y, v) + d * self.fl.g1(y, v)) / self.fl.qf(y)]

    def _escape_event(self) -> Any:
        def ev(_t: float, x: np.ndarray, _d: float) -> float:
            return self.fl.qf(float(x[0])) - SINGULAR_LEVEL * self.q0

        ev.terminal = True  # type: ignore[attr-defined]
        return ev

    def run(self, U: float, first: int, switch: float | None, rtol: float
            ) -> tuple[bool, float]:
        """(escaped, time) of d = first*U, switched at ``switch``."""
        from scipy.integrate import solve_ivp

        self.count += 1
        x0 = np.zeros(2)
        t0 = 0.0
        pieces = [(first * U, switch if switch is not None else HORIZON)]
        if switch is not None:
            pieces.append((-first * U, HORIZON))
        for d, t_end in pieces:
            with np.errstate(all="ignore"):
                sol = solve_ivp(self.rhs, (t0, t_end), x0, args=(d,), method="DOP853",
                                rtol=rtol, atol=rtol * 1e-3, events=self._escape_event())
            if sol.status == 1 or not np.all(np.isfinite(sol.y[:, -1])):
                return True, float(sol.t[-1])
            if sol.status != 0:
                return True, float(sol.t[-1])
            x0, t0 = sol.y[:, -1], float(sol.t[-1])
        return False, HORIZON

    def settle(self, U: float, first: int) -> float | None:
        """When d = first*U from rest has settled at its equilibrium (rounded), or None."""
        from scipy.integrate import solve_ivp

        yeq = self.fl.equilibrium(U, first, self.sing[1] if first > 0 else self.sing[0])
        if yeq is None:
            return None
        tol = _SETTLE * max(abs(yeq), 1e-12)

        def near(_t: float, x: np.ndarray, _d: float) -> float:
            return math.hypot(float(x[0]) - yeq, float(x[1])) - tol

        near.terminal = True  # type: ignore[attr-defined]
        self.count += 1
        with np.errstate(all="ignore"):
            sol = solve_ivp(self.rhs, (0.0, HORIZON), np.zeros(2), args=(first * U,),
                            method="DOP853", rtol=1e-10, atol=1e-13,
                            events=[near, self._escape_event()])
        if sol.status != 1 or sol.t_events[0].size == 0:
            return None
        return float(f"{float(sol.t_events[0][0]):.6g}")

    def escapes(self, U: float) -> tuple[int, float | None] | None:
        """The first candidate (first_sign, switch) that escapes at U, or None."""
        for first in (1, -1):
            if self.run(U, first, None, 1e-8)[0]:
                return first, None
        for first in (-1, 1):
            t1 = self.settle(U, first)
            if t1 is not None and self.run(U, first, t1, 1e-8)[0]:
                return first, t1
        return None


def implicit_witness(form: ImplicitLoop, lower: float) -> ImplicitWitness | None:
    """The smallest escaping switching input found above ``lower`` (estimate-grade).

    Parameters
    ----------
    form : ImplicitLoop
        A second-order implicit loop.
    lower : float
        The proven lower side (the search starts above it).

    Returns
    -------
    ImplicitWitness or None
        None when nothing escaped up to ``lower * 2**DOUBLINGS``.
    """
    try:
        runs = _Runs(form)
    except ValueError:
        return None
    lo = max(lower, 1e-12)
    hi = 2 * lo
    for _ in range(DOUBLINGS):
        if runs.escapes(hi) is not None:
            break
        lo, hi = hi, 2 * hi
    else:
        return None
    for _ in range(BISECTIONS):
        mid = (lo + hi) / 2
        if runs.escapes(mid) is not None:
            hi = mid
        else:
            lo = mid
    for factor in (MARGIN, MARGIN**2, MARGIN**4):
        U = float(f"{hi * factor:.6g}")
        cand = runs.escapes(U)
        if cand is None:
            continue
        first, t1 = cand
        results = [runs.run(U, first, t1, rtol) for rtol in RTOLS]
        if all(r[0] for r in results) and abs(results[0][1] - results[1][1]) <= \
                0.01 * max(results[1][1], 1e-12):
            return ImplicitWitness(amplitude=U, first_sign=first,
                                   switch_times=() if t1 is None else (t1,),
                                   t_escape=results[1][1], edge=hi, runs=runs.count)
    return None
