"""The cart-pole loop of paper 001 (section 5) in the time domain: two nonlinear trials.

The companion of :mod:`gfrf.papers.cartpole` (the linear-loop findings); each trial is a
function returning a result object with ``to_dict``:

* :func:`lagged_simulation` - integrates the lagged *nonlinear* loop of eq (12), the
  controller times ``1/(tau s + 1)`` (whose linear loop
  :func:`gfrf.papers.cartpole.lagged_loops` finds unstable), with
  :func:`scipy.integrate.solve_ivp` and watches it diverge.
* :func:`loop_drive` - the closed loop driven at its own corner frequency over many
  periods (it has no resonance: both poles are real), polynomial and physical equation.

Angular frequencies are in rad/s, times in s, angles in rad unless a name says deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf._results import Result, short_repr
from gfrf.errors import ArgumentError
from gfrf.model.modelfile import ModelFile
from gfrf.papers.cartpole import _loop_parts
from gfrf.stability.loops import closed_loop

__all__ = ["LagSimulation", "DriveTrial", "LoopDrive", "lagged_simulation", "loop_drive",
           "has_physical_equation"]


@dataclass(frozen=True, kw_only=True)
class LagSimulation(Result):
    """A run of the lagged nonlinear loop (eq (12), one lag tau) from rest at an angle.

    Attributes
    ----------
    tau : float
    theta0 : float
        Initial angle (rad); theta'(0) = 0 and the lag state at theta0.
    escape : float
        |theta| (rad) at which the run is stopped as diverged.
    escape_time : float or None
        When |theta| reached ``escape`` (s), None if it stayed below up to ``t_end``.
    t_end : float
    growth_rate : float or None
        Slope of ln|theta| between |theta| = 1e2 theta0 and 1e4 theta0 (1/s), when both
        are reached before the escape (start small for a clean linear growth rate).
    feedback : int
    peak : float
        max |theta| over the run.
    """

    tau: float
    theta0: float
    escape: float
    escape_time: float | None
    t_end: float
    growth_rate: float | None
    feedback: int
    peak: float

    @property
    def diverged(self) -> bool:
        return self.escape_time is not None

    def __repr__(self) -> str:
        return short_repr(self, "tau", "theta0", "escape_time", "growth_rate")

    def _computed(self) -> dict[str, Any]:
        return {"diverged": self.diverged}


def _equation_rhs(mf: ModelFile) -> Any:
    """theta'' as a function of (theta, theta', u) from the plant's coefficient table.

    Every term is ``coefficient * prod D^k theta * u^j``; terms holding theta'' (at most
    once each) form its factor, the rest the right-hand side.
    """
    rows = mf.plant.coefficient_table()
    top = max(max(r["y_orders"], default=0) for r in rows)
    if top != 2 or any(k > 0 for r in rows for k in r["u_orders"]):
        raise ArgumentError("the lagged simulation needs a second-order plant without input "
                            "derivatives")
    if any(r["y_orders"].count(2) > 1 for r in rows):
        raise ArgumentError("the plant equation is not linear in theta''")

    def rhs(theta: float, dtheta: float, u: float) -> float:
        lead = rest = 0.0
        for r in rows:
            value = r["coefficient"] * u ** len(r["u_orders"])
            for k in r["y_orders"]:
                if k != 2:
                    value *= theta if k == 0 else dtheta
            if 2 in r["y_orders"]:
                lead += value
            else:
                rest += value
        return -rest / lead

    return rhs


def lagged_simulation(mf: ModelFile, tau: float, theta0: float = math.radians(5.0),
                      t_end: float = 1.0, escape: float = 1.0,
                      feedback: int | None = None, c: float | None = None) -> LagSimulation:
    """Integrate the nonlinear loop with the controller (a s^2 + b s + c)/(tau s + 1).

    The controller is realised as ``q1 theta' + q0 theta + r0 z`` with the lag state
    ``tau z' = theta - z``, where ``q1 = a/tau``, ``q0 = (b - a/tau)/tau``,
    ``r0 = c - q0`` (polynomial division), so ``u = f (q1 theta' + q0 theta + r0 z)``
    needs no theta'' and the loop is explicit.  Integrated by
    :func:`scipy.integrate.solve_ivp` (DOP853, rtol 1e-10) until |theta| = ``escape``;
    meant for the diverging loop (a stable lagged loop is stiff for DOP853).

    Parameters
    ----------
    mf : ModelFile
        Plant (eq (12): ``models/cartpole.toml``) and ideal controller.
    tau : float
        Lag (s).
    theta0 : float
        Initial angle (rad).
    t_end : float
        Horizon (s).
    escape : float
        |theta| (rad) counted as diverged.
    feedback : int, optional
        Override the file's sign.
    c : float, optional
        Override the controller's constant coefficient.

    Returns
    -------
    LagSimulation
    """
    from scipy.integrate import solve_ivp

    _, _, num_c, den_c, f = _loop_parts(mf)
    f = f if feedback is None else feedback
    if not (tau > 0 and t_end > 0 and escape > abs(theta0) > 0):
        raise ArgumentError("need tau > 0, t_end > 0 and 0 < |theta0| < escape")
    a, b = num_c[0] / den_c[0], num_c[1] / den_c[0]
    cc = num_c[2] / den_c[0] if c is None else c
    q1, q0 = a / tau, (b - a / tau) / tau
    r0 = cc - q0
    theta_dd = _equation_rhs(mf)

    def rates(_t: float, x: np.ndarray) -> list[float]:
        u = f * (q1 * x[1] + q0 * x[0] + r0 * x[2])
        return [x[1], theta_dd(x[0], x[1], u), (x[0] - x[2]) / tau]

    def out(_t: float, x: np.ndarray) -> float:
        return abs(x[0]) - escape

    out.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(rates, (0.0, t_end), [theta0, 0.0, theta0], method="DOP853",
                    rtol=1e-10, atol=1e-14 * max(1.0, abs(theta0)), events=out,
                    dense_output=True)
    escape_time = float(sol.t_events[0][0]) if sol.t_events[0].size else None
    growth = None
    grid = np.linspace(0.0, float(sol.t[-1]), 200001)
    size = np.abs(sol.sol(grid)[0])
    lo, hi = 1e2 * abs(theta0), 1e4 * abs(theta0)
    if hi < escape and size.max() >= hi:
        i, j = int(np.argmax(size >= lo)), int(np.argmax(size >= hi))
        if j > i:
            growth = float(math.log(size[j] / size[i]) / (grid[j] - grid[i]))
    return LagSimulation(tau=float(tau),
                         theta0=float(theta0),
                         escape=float(escape),
                         escape_time=escape_time,
                         t_end=float(t_end),
                         growth_rate=growth,
                         feedback=f,
                         peak=float(size.max()))


@dataclass(frozen=True, kw_only=True)
class DriveTrial(Result):
    """One closed-loop run driven by a cosine reference (amplitude: of the reference r)."""

    equation: str
    target_deg: float
    amplitude: float
    bounded: bool
    peak: float
    blowup_time: float | None


@dataclass(frozen=True, kw_only=True)
class LoopDrive(Result):
    """The ideal linear closed loop's frequency scales and cosine-driven runs.

    Attributes
    ----------
    poles : tuple of complex
        Closed-loop poles (y/r).
    resonant : bool
        A complex pole pair exists (the loop can resonate).
    omega : float
        Drive frequency (rad/s): the least damped complex pair's |p| if ``resonant``,
        otherwise the fastest pole's |p| (the corner of the loop's gain).
    gain : float
        |y/r(j omega)| of the linear loop.
    t_end : float
        Horizon (s), ``periods`` periods of the drive.
    periods : int
    trials : tuple of DriveTrial
    """

    poles: tuple[complex, ...]
    resonant: bool
    omega: float
    gain: float
    t_end: float
    periods: int
    trials: tuple[DriveTrial, ...]

    def __repr__(self) -> str:
        return short_repr(self, "omega", "resonant", "t_end")


def has_physical_equation(mf: ModelFile) -> bool:
    """The file's untruncated equation differs from its polynomial (eq (12)'s file, not
    eq (16)'s, whose "physical" equation is the polynomial itself).

    Parameters
    ----------
    mf : ModelFile
        The model file.

    Returns
    -------
    bool
        Whether it has a distinct physical equation.
    """
    physical = mf.plant.physical
    return physical is not None and (physical - mf.plant.polynomial()).expand() != 0


def loop_drive(mf: ModelFile, angles_deg: tuple[float, ...] = (5.0, 10.0, 15.0),
               periods: int = 100, blowup: float = 1e3) -> LoopDrive:
    """Drive the closed loop u = C(r - y) with r = A cos(omega t) at its own frequency scale.

    A is chosen so that the *linear* loop's steady angle amplitude |T(j omega)| A
    (T = y/r) is each of ``angles_deg``; the nonlinear loop (polynomial equation, and the
    physical one when the file has a distinct one, :func:`has_physical_equation`) is
    simulated by :func:`gfrf.sim.simulation.simulate` over ``periods`` periods, started
    on the linear loop's periodic steady state y = Re(T A e^{j omega t}) (y(0), y'(0)):
    from rest, the slow pole's transient (time constant about 200 s on the cart-pole)
    would last the whole run and double the peak.

    Parameters
    ----------
    mf : ModelFile
        The cart-pole model file, with its controller.
    angles_deg : tuple of float, optional
        The linear loop's steady angle amplitudes, in degrees.
    periods : int, optional
        Periods of the reference simulated.
    blowup : float, optional
        The threshold on |y| at which a run counts as blown up.

    Returns
    -------
    LoopDrive
        The runs.
    """
    from gfrf.sim.simulation import simulate
    from gfrf.sim.system import build_system

    loop = closed_loop(mf)
    poles = tuple(complex(p) for p in loop.poles)
    pairs = [p for p in poles if p.imag > 0]
    if pairs:
        omega = abs(max(pairs, key=lambda p: p.real / abs(p)))
    else:
        omega = max(abs(p) for p in poles)
    gain = float(abs(loop.reference_to_output(1j * omega)))
    t_end = periods * 2.0 * math.pi / omega
    equations = ["polynomial"] + (["physical"] if has_physical_equation(mf) else [])
    trials = []
    steady = complex(loop.reference_to_output(1j * omega)) / gain  # per unit angle
    for eq in equations:
        system = build_system(mf, closed_loop=True, equation=eq)
        for deg in angles_deg:
            amp = math.radians(deg) / gain
            start = [math.radians(deg) * steady.real, -math.radians(deg) * omega * steady.imag]
            res = simulate(system, f"{amp!r}*cos({omega!r}*t)", t_end=t_end, rtol=1e-8,
                           atol=1e-11, blowup=blowup, initial=start)
            trials.append(DriveTrial(equation=eq, target_deg=deg, amplitude=amp,
                                     bounded=res.bounded, peak=res.peak,
                                     blowup_time=res.blowup_time))
    return LoopDrive(poles=poles,
                     resonant=bool(pairs),
                     omega=float(omega),
                     gain=gain,
                     t_end=float(t_end),
                     periods=periods,
                     trials=tuple(trials))
