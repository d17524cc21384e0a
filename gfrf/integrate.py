"""The integrators' common ground: a model in state form, a run's result, the scipy path.

:func:`gfrf.simulation.build_system` generates an :class:`OdeSystem` (the right-hand
side as Python source) from a model; :func:`integrate_scipy` runs it with scipy's
``solve_ivp`` under a work budget of right-hand-side evaluations, and
:mod:`gfrf.fastsim` runs the same source compiled with numba.  Both return a
:class:`SimulationResult`.  This module imports neither of them, so the simulation
modules form no import cycle (simulation -> fastsim -> integrate).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from gfrf._results import short_repr, simulation_figure, simulation_markdown
from gfrf.signals import InputSignal

__all__ = ["OdeSystem", "SimulationResult", "MAX_RHS_EVALUATIONS", "SCIPY_METHODS",
           "integrate_scipy", "input_values", "plant_input", "budget_name"]

#: scipy ``solve_ivp`` names of the integration methods (the fast path is ``"fast"``).
SCIPY_METHODS = {"rk45": "RK45", "dop853": "DOP853", "radau": "Radau", "lsoda": "LSODA"}
#: Default work budget of a simulation: right-hand-side evaluations of a scipy run
#: (NARX: samples of the recursion).  The bundled uses need at most about 6e4 (100 s
#: runs of every bundled model in ``gfrf validate`` and the reports: <= 1.1e4; the
#: speed report's 200 s pendulum at rtol 1e-10: 6.0e4); 10^6 takes 25-40 s of
#: pure-Python right-hand side.  Raise it with ``max_evaluations`` (CLI
#: ``--max-evaluations``) for longer horizons.
MAX_RHS_EVALUATIONS = 1_000_000


@dataclass(frozen=True)
class OdeSystem:
    """A model in first-order state form, generated once from sympy.

    Attributes
    ----------
    n_states : int
        Number of states: output derivatives 0..n-1 then controller states.
    order : int
        Output order n (highest output derivative in the equation).
    n_inputs : int
        Number of input values passed to the right-hand side: u, u', ... (open loop)
        or r (closed loop).
    source : str
        Python source of ``rhs(z, v, out)`` and ``plant_input(z, v, dz)`` (module
        ``math``), shared by scipy and numba.
    linear_eigenvalues : numpy.ndarray
        Eigenvalues (1/s) of the Jacobian at z = 0, v = 0.
    discrete : bool
        True for a NARX model (then ``source`` is the recursion ``y[k] = ...``).
    """

    n_states: int
    order: int
    n_inputs: int
    source: str
    linear_eigenvalues: np.ndarray
    label: str
    closed_loop: bool = False
    discrete: bool = False
    sample_time: float | None = None
    notes: tuple[str, ...] = ()
    _functions: dict[str, Callable[..., Any]] = field(default_factory=dict, repr=False,
                                                      compare=False)

    @property
    def linear_unstable(self) -> bool:
        """True if a linearised eigenvalue has a positive real part (|z| > 1 for NARX).

        A marginal linearisation (eigenvalues on the axis, e.g. an undamped
        oscillator) is not called unstable.
        """
        ev = self.linear_eigenvalues
        if ev.size == 0:
            return False
        if self.discrete:
            return bool(np.any(np.abs(ev) > 1.0 + 1e-12))
        return bool(np.any(ev.real > 1e-9 * max(1.0, float(np.max(np.abs(ev))))))

    def function(self, name: str) -> Callable[..., Any]:
        """The compiled pure-Python function ``rhs`` or ``plant_input`` of :attr:`source`."""
        if not self._functions:
            namespace: dict[str, Any] = {"math": math}
            exec(compile(self.source, f"<gfrf rhs {self.label}>", "exec"), namespace)  # noqa: S102
            self._functions.update({k: namespace[k] for k in ("rhs", "plant_input")})
        return self._functions[name]


@dataclass
class SimulationResult:
    """Output of :func:`simulate`.

    Attributes
    ----------
    t : numpy.ndarray
        Times in seconds (up to the blow-up time if the run blew up).
    y : numpy.ndarray
        Output y(t).
    u : numpy.ndarray
        Plant input u(t) (in closed loop: r + feedback*C[y]).
    states : numpy.ndarray
        State trajectory, shape (n_states, len(t)).
    status : str
        ``"ok"``, ``"blowup"`` (|y| reached the threshold or the state became
        non-finite) or ``"failed"`` (the integrator gave up).
    blowup_time : float or None
        Time in seconds at which |y| crossed the blow-up threshold.
    wall_time, compile_time : float
        Seconds spent integrating, and (fast path) loading/compiling with numba.
    """

    t: np.ndarray
    y: np.ndarray
    u: np.ndarray
    states: np.ndarray
    status: str
    method: str
    blowup_time: float | None = None
    message: str = ""
    nfev: int = 0
    wall_time: float = 0.0
    compile_time: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def bounded(self) -> bool:
        """True if the run reached t_end without blowing up."""
        return self.status == "ok"

    @property
    def peak(self) -> float:
        """max |y| over the run."""
        return float(np.max(np.abs(self.y))) if self.y.size else 0.0

    def to_dict(self, arrays: bool = False) -> dict[str, Any]:
        """JSON-ready summary; ``arrays=True`` adds t, y, u."""
        out: dict[str, Any] = {
            "status": self.status, "method": self.method, "blowup_time": self.blowup_time,
            "message": self.message, "t_final": float(self.t[-1]) if self.t.size else 0.0,
            "samples": int(self.t.size), "peak_abs_y": self.peak,
            "y_final": float(self.y[-1]) if self.y.size else None,
            "nfev": self.nfev, "wall_time_s": self.wall_time,
            "compile_time_s": self.compile_time, "notes": list(self.notes)}
        if arrays:
            out.update(t=self.t.tolist(), y=self.y.tolist(), u=self.u.tolist())
        return out

    def __repr__(self) -> str:
        return short_repr(self, "status", "method", "peak",
                          t_final=float(self.t[-1]) if self.t.size else 0.0)

    def _repr_markdown_(self) -> str:
        return simulation_markdown(self)

    def plot(self) -> Any:
        """y(t) and u(t) (the plant input; r + feedback*C[y] in closed loop), t in seconds.

        Returns
        -------
        matplotlib.figure.Figure
            Made without pyplot (works with any backend; display it or ``savefig``).
        """
        return simulation_figure(self)


def budget_name(max_evaluations: int) -> str:
    return "MAX_RHS_EVALUATIONS" if max_evaluations == MAX_RHS_EVALUATIONS \
        else "max_evaluations"


def input_values(signal: InputSignal, n_inputs: int, t: np.ndarray) -> np.ndarray:
    """Array (n_inputs, len(t)) of u, u', ... at times ``t`` (seconds)."""
    return np.array([signal.derivative(k)(t) for k in range(n_inputs)]).reshape(n_inputs, -1)


def plant_input(system: OdeSystem, states: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The plant input u along a trajectory (evaluates ``plant_input`` of the source)."""
    rhs, pin = system.function("rhs"), system.function("plant_input")
    out = np.empty(system.n_states)
    u = np.empty(states.shape[1])
    for i in range(states.shape[1]):
        rhs(states[:, i], v[:, i], out)
        u[i] = pin(states[:, i], v[:, i], out)
    return u


def integrate_scipy(system: OdeSystem, signal: InputSignal, z0: np.ndarray, t_end: float,
           t_eval: np.ndarray, method: str, rtol: float, atol: float,
           blowup: float, max_evaluations: int = MAX_RHS_EVALUATIONS) -> SimulationResult:
    """``solve_ivp``, stopped by a terminal event at blow-up or when the budget is spent.

    The budget is checked after each accepted step (the overrun is at most one step's
    evaluations); the run then ends at that step's time with status ``"failed"``.
    """
    rhs = system.function("rhs")
    funcs = [signal.derivative(k) for k in range(system.n_inputs)]
    count = [0]
    cut: list[float] = []  # time of the step after which the budget was spent

    def f(t: float, z: np.ndarray) -> np.ndarray:
        count[0] += 1
        v = [float(g(t)) for g in funcs]
        out = np.empty(system.n_states)
        try:
            rhs(z, v, out)
        except ZeroDivisionError:
            out[:] = np.nan
        return out

    def escape(t: float, z: np.ndarray) -> float:
        return blowup - abs(z[0]) if np.all(np.isfinite(z)) else -1.0

    def budget(t: float, z: np.ndarray) -> float:
        # Called by solve_ivp after each accepted step at its time t (and, once cut,
        # by the root search between the last two steps): zero at the cut time.
        if not cut and count[0] >= max_evaluations:
            cut.append(t)
        return cut[0] - t if cut else 1.0

    escape.terminal = True  # type: ignore[attr-defined]
    budget.terminal = True  # type: ignore[attr-defined]
    with np.errstate(all="ignore"):
        sol = solve_ivp(f, (0.0, t_end), z0, method=SCIPY_METHODS[method], t_eval=t_eval,
                        rtol=rtol, atol=atol, events=[escape, budget])
    # A run that fails before its first output time returns an empty list.
    states = np.asarray(sol.y, dtype=float).reshape(z0.size, -1)
    times = np.asarray(sol.t, dtype=float)
    finite = np.all(np.isfinite(states), axis=0)
    status, blow_t, message = "ok", None, sol.message
    if sol.t_events[0].size:
        status, blow_t = "blowup", float(sol.t_events[0][0])
        message = f"|y| reached {blowup:g} at t = {blow_t:.6g} s"
    elif sol.t_events[1].size:
        status = "failed"
        message = (f"stopped at t = {cut[0]:.6g} s of {t_end:g} s: {count[0]} right-hand-"
                   f"side evaluations reached the work budget "
                   f"{budget_name(max_evaluations)} = {max_evaluations}")
    elif not finite.all() or sol.status < 0:
        first = int(np.argmin(finite)) if not finite.all() else states.shape[1]
        states = states[:, :first]
        blow_t = float(times[first]) if first < times.size else float(times[-1]) \
            if times.size else 0.0
        status = "blowup" if not finite.all() else "failed"
        message = f"the integration failed near t = {blow_t:.6g} s: {sol.message}"
    t = times[:states.shape[1]]
    v = input_values(signal, system.n_inputs, t)
    u = plant_input(system, states, v) if t.size else np.zeros(0)
    return SimulationResult(t=t, y=states[0] if states.size else np.zeros(0), u=u,
                            states=states, status=status, method=method,
                            blowup_time=blow_t, message=message, nfev=count[0])
