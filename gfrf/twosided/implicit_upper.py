"""The upper side of an implicit loop (:mod:`gfrf.stability.implicit`), in the lower side's
input class: bounded plant-input signals d (d = C r for a loop with an improper
controller), sup|d| <= U.

*Escape* is reaching the loop's breakdown level |D(y)| <= SINGULAR_LEVEL |D(0)|
(:data:`gfrf.stability.implicit.SINGULAR_LEVEL`), where y'' = -R / D and the controller's
output are 1e6 times their scale, or a non-finite state.  It is a stated level: below
the constant input whose equilibrium reaches D = 0 itself, a bounded input brings |D|
arbitrarily close to 0 without reaching it (near D = 0, while y' falls by v, the
distance to D = 0 shrinks by a factor exp(-c v): y turns back before D = 0), so the
lower side's polygon is kept above the same level.

Candidates: d = +U and d = -U held constant from rest (the switching witness
form with no switch).  Switching inputs were measured on the cart-pole loops and
reach the level no sooner: with its overdamped loop every swing ends as close to
D = 0 as the constant's (d = U sign(y') and one switch after settling at d = -U, at
U = 150 to 400, come as close as the constant to within 0.003 in log10 of the
distance to D = 0).  The smallest
escaping U is found by doubling from the proven lower side, then bisection (counts,
never time); the witness is that edge times 1.02 and must escape under DOP853 at
rtol 1e-9 and 1e-11, escape times within 1 %.  :func:`gfrf.twosided.implicit_enclose.
enclose_implicit_witness` proves it in ball arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf.stability.implicit import SINGULAR_LEVEL, ImplicitLoop
from gfrf.stability.implicit_region import LoopField

__all__ = ["ImplicitWitness", "implicit_witness", "SINGULAR_LEVEL", "HORIZON"]

#: Horizon of one run (s).
HORIZON = 50.0
DOUBLINGS, BISECTIONS = 12, 8
MARGIN = 1.02
RTOLS = (1e-9, 1e-11)


@dataclass(frozen=True)
class ImplicitWitness:
    """A switching input d = first_sign * U on [0, t1), then alternating, that reaches
    the loop's breakdown level (a simulation; ``enclosure`` says whether it is proven).

    Attributes
    ----------
    amplitude : float
        U = sup|d|.
    first_sign : int
        +1 or -1.
    switch_times : tuple of float
        Switch times (s); empty for a constant input.
    t_escape : float
        When the run reached the breakdown level (s), at rtol 1e-11.
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
        """The switching witness JSON (the input is d)."""
        return {"kind": "switching", "signal": "d", "amplitude": self.amplitude,
                "first_sign": self.first_sign, "switch_times": list(self.switch_times),
                "t_escape": self.t_escape,
                "escape": f"|D(y)| <= {float(SINGULAR_LEVEL):g} |D(0)|"}

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
        self.q0 = self.fl.qf(0.0)
        self.count = 0

    def rhs(self, _t: float, x: np.ndarray, d: float) -> list[float]:
        y, v = float(x[0]), float(x[1])
        return [v, (self.fl.g0(y, v) + d * self.fl.g1(y, v)) / self.fl.qf(y)]

    def _escape_event(self) -> Any:
        def ev(_t: float, x: np.ndarray, _d: float) -> float:
            return self.fl.qf(float(x[0])) - float(SINGULAR_LEVEL) * self.q0

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

    def escapes(self, U: float) -> tuple[int, float | None] | None:
        """The first candidate (first_sign, switch) that escapes at U, or None."""
        for first in (1, -1):
            if self.run(U, first, None, 1e-8)[0]:
                return first, None
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
