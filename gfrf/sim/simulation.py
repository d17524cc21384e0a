"""Time simulation of model files: open and closed loop, polynomial or physical equation.

:func:`simulate` runs the state form that :func:`gfrf.sim.system.build_system` generates
(the model solved for its highest output derivative, the loop closed with the file's
controller; see that module): with scipy's ``solve_ivp``
(:func:`gfrf.sim.integrate.integrate_scipy`), with the numba fast path in
:mod:`gfrf.sim.fastsim`, or for a NARX model by direct recursion on t = k*T.

Before integrating, the linearisation at z = 0 is checked: an unstable linear part
(open-loop cart-pole, an unstable closed loop) is reported in ``notes`` and as a
``UserWarning``, and every run stops at ``blowup`` (default 1e6) on |y| with status
``"blowup"`` and the blow-up time, never with silent NaN arrays.  Discrete (NARX)
models are simulated by direct recursion on t = k*T.

Work is bounded by counts, never by time: a scipy run stops after ``max_evaluations``
(default :data:`MAX_RHS_EVALUATIONS`) right-hand-side evaluations with status
``"failed"`` and a message naming the limit and the time reached; a NARX recursion
longer than that many samples, and an input with a tone ``sin(w*t + p)``/``cos(...)``
that repeats more than ``max_evaluations/2`` times over t_end (no integrator resolves
a period with fewer than two evaluations), are refused before any work.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> res = simulate(parse_model("D(y) + y = u"), "step(t)", t_end=2.0, rtol=1e-10, atol=1e-12)
>>> bool(abs(res.y[-1] - (1 - __import__("math").exp(-2.0))) < 1e-8)
True
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from dataclasses import replace
from typing import Any

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.model.equation import Model
from gfrf.model.limits import quote
from gfrf.model.modelfile import ModelFile
from gfrf.model.signals import InputSignal, T, parse_input, zero_input
from gfrf.sim.integrate import (
    MAX_RHS_EVALUATIONS,
    OdeSystem,
    SimulationResult,
    budget_name,
    integrate_scipy,
)
from gfrf.sim.system import build_system

__all__ = ["OdeSystem", "SimulationResult", "simulate", "METHODS",
           "MAX_RHS_EVALUATIONS", "AUTO_RK45_RTOL", "auto_method"]


#: Integration methods: ``"auto"`` (:func:`auto_method`), scipy's RK45, DOP853, Radau,
#: LSODA, and the numba fast path.
METHODS = ("auto", "rk45", "dop853", "radau", "lsoda", "fast")
#: A run whose state form reads derivatives of the input refuses a smooth input that
#: changes on a time scale below this fraction of the system's fastest time scale
#: (1/max|eigenvalue| of the linearisation): on the cart-pole loop, the run under
#: ``tanh((t-1)/w)`` moves by 1e-3 relative between rtol 1e-6 and 1e-10 at w = 1e-5 s
#: (2e-4 of its 0.05 s), by 1.3 % at w = 1e-7, and is wrong by 10x at w = 1e-9.
STEEPNESS_LIMIT = 1e-3
#: ``method="auto"`` takes RK45 at rtol >= this, DOP853 below (:func:`auto_method`).
AUTO_RK45_RTOL = 1e-4


def auto_method(rtol: float) -> str:
    """The scipy method ``method="auto"`` runs at relative tolerance ``rtol``.

    ``"rk45"`` (Dormand-Prince 5(4)) when ``rtol >= 1e-4`` (:data:`AUTO_RK45_RTOL`),
    ``"dop853"`` (order 8) below.  Decided by ``rtol`` alone, never by timing.  The
    rule is what ``gfrf bench`` measures on the bundled models (pendulums, Duffing,
    cart-pole loops; ``reports/speed-vs-error.md``): DOP853 takes fewer steps at any
    rtol below 1e-4, but at 1e-4 and looser RK45 is as fast or faster, and on the
    cart-pole loop, whose fast closed-loop pole (-24 1/s) limits the step of an
    explicit method, DOP853 is slower there.

    Parameters
    ----------
    rtol : float
        The relative tolerance.

    Returns
    -------
    str
        ``"rk45"`` or ``"dop853"``.

    Examples
    --------
    >>> auto_method(1e-3), auto_method(1e-4), auto_method(1e-8)
    ('rk45', 'rk45', 'dop853')
    """
    return "rk45" if rtol >= AUTO_RK45_RTOL else "dop853"


def _check(t_end: float, rtol: float, atol: float, blowup: float) -> None:
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and t_end > 0):
        raise ArgumentError(f"t_end must be a positive number of seconds, got {t_end!r}")
    for name, value in (("rtol", rtol), ("atol", atol), ("blowup", blowup)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ArgumentError(f"{name} must be a positive number, got {value!r}")


def _initial(system: OdeSystem, initial: Any) -> np.ndarray:
    z0 = np.zeros(system.n_states)
    if initial is None:
        return z0
    values = np.atleast_1d(np.asarray(initial, dtype=float))
    limit = system.order
    if values.ndim != 1 or values.size > limit or not np.all(np.isfinite(values)):
        raise ArgumentError(f"initial conditions must be up to {limit} finite numbers "
                            f"(y, y', ... for continuous models; y[-1], y[-2], ... for NARX), "
                            f"got {initial!r}")
    z0[:values.size] = values
    return z0


def simulate(source: ModelFile | Model | OdeSystem, input: str | InputSignal | None = None,
             *, t_end: float, closed_loop: bool = False, equation: str = "physical",
             initial: Any = None, method: str = "auto", rtol: float = 1e-8,
             atol: float = 1e-10, t_eval: np.ndarray | None = None, n_out: int = 2001,
             blowup: float = 1e6, dt: float | None = None,
             max_evaluations: int = MAX_RHS_EVALUATIONS) -> SimulationResult:
    """Simulate a model from an input and/or initial conditions.

    Parameters
    ----------
    source : ModelFile, Model or OdeSystem
        What to simulate (an :class:`OdeSystem` from :func:`build_system` is reused as is).
    input : str or InputSignal, optional
        Input u(t) (open loop) or reference r(t) (closed loop); text as in
        :func:`gfrf.model.signals.parse_input`.  None: zero.
    t_end : float
        Final time in seconds (> 0).
    closed_loop, equation
        See :func:`build_system`.
    initial : sequence of float, optional
        y(0), y'(0), ... (radians, rad/s for the pendulums); NARX: y[-1], y[-2], ...
    method : {"auto", "rk45", "dop853", "radau", "lsoda", "fast"}
        scipy ``solve_ivp`` method (stepped by :func:`gfrf.sim.integrate.integrate_scipy`),
        or the numba fixed-step RK4 of :mod:`gfrf.sim.fastsim`.  The default ``"auto"`` is
        RK45 at ``rtol >= 1e-4`` and DOP853 below (:func:`auto_method`; so DOP853 at the
        default rtol); the result's ``method`` names the one run.  On the bundled models
        it takes less time than plain ``solve_ivp`` RK45 on a hand-written ``f(t, y)``
        at the same rtol, at every rtol from 1e-3 to 1e-10 (``reports/speed-vs-error.md``).
    rtol, atol : float
        Tolerances of ``solve_ivp`` (> 0).  The fast path uses them only when ``dt``
        is not given, to choose its step by step doubling.
    t_eval : array_like, optional
        Output times in seconds; default ``n_out`` points on [0, t_end].
    n_out : int
        Number of output times when ``t_eval`` is not given (continuous time).
    blowup : float
        Threshold on |y| at which the run is stopped and reported as a blow-up.
    dt : float, optional
        Fixed step in seconds of the fast path.
    max_evaluations : int
        Work budget: right-hand-side evaluations of a scipy run (at its exhaustion the
        run stops with status ``"failed"``), samples of a NARX recursion; an input tone
        with more than ``max_evaluations/2`` periods over ``t_end`` is refused.  The
        fast path is bounded by :data:`gfrf.sim.fastsim.MAX_STEPS` instead.

    Returns
    -------
    SimulationResult

    Raises
    ------
    ArgumentError
        Bad arguments, a NARX run longer than ``max_evaluations`` samples, an input
        tone too fast for ``max_evaluations`` over ``t_end``.
    """
    _check(t_end, rtol, atol, blowup)
    if not (isinstance(max_evaluations, int) and max_evaluations >= 1):
        raise ArgumentError(f"max_evaluations must be a positive integer, got "
                            f"{max_evaluations!r}")
    if method not in METHODS:
        raise ArgumentError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if method == "auto":
        method = auto_method(rtol)
    system = source if isinstance(source, OdeSystem) else build_system(
        source, closed_loop=closed_loop, equation=equation)
    z0 = _initial(system, initial)
    signal = _signal(input, system)
    _check_impulses(signal, t_end, system)
    _check_work(system, signal, t_end, max_evaluations)
    notes = list(system.notes)
    if system.linear_unstable:
        ev = ", ".join(f"{complex(e):.4g}" for e in system.linear_eigenvalues)
        note = (f"the linearisation of the {'closed loop' if system.closed_loop else 'system'} "
                f"is unstable (eigenvalues {ev}): expect growth; the run stops at |y| = "
                f"{blowup:g}")
        warnings.warn(note, UserWarning, stacklevel=2)
        notes.append(note)
    if t_eval is None:
        t_eval = np.linspace(0.0, t_end, n_out) if not system.discrete else None
    else:
        t_eval = np.asarray(t_eval, dtype=float)
        if t_eval.ndim != 1 or t_eval.size < 1 or np.any(np.diff(t_eval) <= 0) \
                or t_eval[0] < 0 or t_eval[-1] > t_end:
            raise ArgumentError("t_eval must be increasing times within [0, t_end]")
    starts: list[float] = []
    for k in range(system.n_inputs if not system.discrete else 1):
        try:
            with np.errstate(all="ignore"):
                value = float(signal.derivative(k)(0.0))
        except OverflowError:  # an exact integer of the text beyond a float, e.g. 99**150
            value = math.inf
        if not math.isfinite(value):
            raise ArgumentError(f"the input{' derivative ' + str(k) if k else ''} is not "
                                f"finite at t = 0 s: u(t) = {signal.text[:80]}"
                                + (f"; {_loop_reads(system)}" if k else ""))
        starts.append(value)
    switch_on = _switch_on_note(system, starts, initial)
    if switch_on:
        notes.append(switch_on)
    start = time.perf_counter()
    if system.discrete:
        result = _narx(system, signal, z0, t_end, blowup)
    elif method == "fast":
        from gfrf.sim.fastsim import simulate_fast
        result = simulate_fast(system, signal, z0, t_end, t_eval, blowup=blowup, dt=dt,
                               rtol=rtol, atol=atol, max_evaluations=max_evaluations)
    else:
        result = integrate_scipy(system, signal, z0=z0, t_end=t_end, t_eval=t_eval, method=method,
                                 rtol=rtol, atol=atol, blowup=blowup,
                                 max_evaluations=max_evaluations)
    return replace(result, wall_time=time.perf_counter() - start - result.compile_time,
                   notes=notes + result.notes)


def _check_work(system: OdeSystem, signal: InputSignal, t_end: float,
                max_evaluations: int) -> None:
    """Refuse, before any work, a run that cannot fit in ``max_evaluations``.

    NARX: more samples than the budget.  Continuous: a term ``sin``/``cos``/``tan`` of
    ``w*t + p`` in the input with more than ``max_evaluations/2`` periods over t_end.
    """
    name = f"{budget_name(max_evaluations)} = {max_evaluations}"
    if system.discrete:
        samples = math.floor(t_end / float(system.sample_time)) + 1  # type: ignore[arg-type]
        if samples > max_evaluations:
            raise ArgumentError(f"t_end = {t_end:g} s is {samples} samples of "
                                f"{system.sample_time:g} s, more than the work budget "
                                f"{name} (samples)")
        return
    limit = max_evaluations // 2
    for term, w in _frequencies(signal.expr):
        periods = w * t_end / (2 * math.pi)
        if periods > limit:
            raise ArgumentError(f"the input term {term} has angular frequency "
                                f"{w:.4g} rad/s: {periods:.4g} periods over "
                                f"t_end = {t_end:g} s, more than {limit} (half the work "
                                f"budget {name}: an integrator needs at least two "
                                f"right-hand-side evaluations per period)")


@functools.lru_cache(maxsize=64)
def _frequencies(expr: sp.Expr | None) -> tuple[tuple[str, float], ...]:
    """(term, |w| in rad/s) of each ``sin``/``cos``/``tan`` of ``w*t + p`` in ``expr``."""
    out = []
    for term in sorted(expr.atoms(sp.sin, sp.cos, sp.tan) if expr is not None else (),
                       key=sp.default_sort_key):
        rate = sp.diff(term.args[0], T)
        if rate.free_symbols or not rate.is_real:  # not linear in t (or not real)
            continue
        try:
            w = abs(float(rate))
        except OverflowError:
            w = math.inf
        out.append((str(term), w))
    return tuple(out)


#: The zero input (immutable) built once per derivative count, not lambdified per run.
_zero_input = functools.lru_cache(maxsize=8)(zero_input)


def _signal(input_: str | InputSignal | None, system: OdeSystem) -> InputSignal:
    # A NARX model reads past samples of u, not derivatives: only u itself is needed.
    need = 0 if system.discrete else system.n_inputs - 1
    if input_ is None:
        return _zero_input(need)
    if isinstance(input_, InputSignal):
        if input_.max_derivative < need:
            raise ArgumentError(f"the model needs {need} input derivatives; build the "
                                f"input with max_derivative={need}")
        return input_
    return parse_input(input_, max_derivative=need)


def _loop_reads(system: OdeSystem) -> str:
    """Why a state form reads derivatives of its input, in words."""
    if system.closed_loop:
        return (f"the loop u = C(r - y) with an improper controller reads the reference r "
                f"and its derivatives up to order {system.n_inputs - 1}")
    return f"the model uses derivatives of u up to order {system.n_inputs - 1}"


def _switch_on_note(system: OdeSystem, starts: list[float], initial: Any) -> str:
    """The note for a run from rest whose input reads derivatives (a D(u) term or an
    improper controller) and does not start at rest: the switch-on at t = 0 is a jump
    of u (or r) or of a derivative, whose impulse the run leaves out."""
    if system.discrete or initial is not None or system.n_inputs <= 1:
        return ""
    moving = [k for k, v in enumerate(starts[:-1]) if v != 0.0]
    if not moving:
        return ""
    name = "r" if system.closed_loop else "u"
    first = moving[0]
    primes = "'" * first
    needed = (f"{name} and its first {system.n_inputs - 2} derivative(s)"
              if system.n_inputs > 2 else name)
    return (f"{name}{primes}(0) = {starts[first]:.6g}, not 0: {_loop_reads(system)}, and "
            f"the run starts from rest at t = 0+ without the impulse that switching {name} "
            f"on at t = 0 sends through them (python-control's forced_response includes "
            f"it); {needed} starting at 0 avoid(s) the difference")


def _check_impulses(signal: InputSignal, t_end: float, system: OdeSystem) -> None:
    """Refuse an input whose derivative the state form reads (a D(u) term, or an
    improper controller's derivatives of the reference) is an impulse in (0, t_end]."""
    if system.discrete or system.n_inputs <= 1:
        return
    times = signal.impulses(t_end)
    if times is None or times.size:
        where = ("at a time that is not known in closed form" if times is None else
                 f"at t = {', '.join(f'{x:.6g}' for x in times[:3])} s"
                 + (f" (and {times.size - 3} more)" if times.size > 3 else ""))
        raise ArgumentError(
            f"{_loop_reads(system)}, and the input {quote(signal.text)} jumps (or its "
            f"slope does) {where}: the derivative there is an impulse (Dirac delta), which "
            "no integrator represents; use a smooth input instead, e.g. "
            "0.5*(1 + tanh((t-1)/0.01)) for step(t-1)")
    _check_steepness(signal, t_end, system)


def _check_steepness(signal: InputSignal, t_end: float, system: OdeSystem) -> None:
    """Refuse a smooth input so steep (``tanh((t-1)/1e-9)``) that the derivatives the
    state form reads spike beyond what a double-precision integrator resolves: its time
    scale below :data:`STEEPNESS_LIMIT` times the system's fastest time scale."""
    unresolved = signal.unresolved_parts(t_end)
    if unresolved:
        raise ArgumentError(
            f"{_loop_reads(system)}, and the smoothness of the input {quote(signal.text)} "
            f"over [0, {t_end:g}] s cannot be judged from {', '.join(unresolved[:3])} (a "
            f"function of an argument that is not a polynomial in t, or a power with a "
            f"pole): it may jump, and the impulse of its derivative would be lost; write "
            f"the input with polynomial arguments, e.g. 0.5*(1 + tanh((t-1)/0.01)) for a "
            f"smoothed jump")
    scale = signal.time_scale(t_end)
    rates = np.abs(np.asarray(system.linear_eigenvalues, dtype=complex))
    if scale is None or not rates.size or not np.max(rates) > 0:
        return
    fastest = 1.0 / float(np.max(rates))
    if scale < STEEPNESS_LIMIT * fastest:
        raise ArgumentError(
            f"{_loop_reads(system)}, and the input {quote(signal.text)} changes on a time "
            f"scale of {scale:.3g} s, below {STEEPNESS_LIMIT:g} times the system's fastest "
            f"time scale {fastest:.3g} s: the derivatives spike (size ~ 1/scale^k) beyond "
            f"what an integrator resolves in double precision, and the run would be wrong; "
            f"use a smoothed jump at least {STEEPNESS_LIMIT * fastest:.3g} s wide")


def _narx(system: OdeSystem, signal: InputSignal, z0: np.ndarray, t_end: float,
          blowup: float) -> SimulationResult:
    rhs, pin = system.function("rhs"), system.function("plant_input")
    period = float(system.sample_time)  # type: ignore[arg-type]
    steps = int(math.floor(t_end / period)) + 1
    t = np.arange(steps) * period
    v_seq = signal(t)
    lags, a = system.n_inputs, system.order
    y, u = np.zeros(steps), np.zeros(steps)
    z = z0.copy()
    out = np.empty(2 if system.closed_loop else 1)
    status, blow_t, message = "ok", None, "recursion finished"
    for k in range(steps):
        v = [v_seq[k - i] if k - i >= 0 else 0.0 for i in range(lags)]
        rhs(z, v, out)
        y[k], u[k] = out[0], pin(z, v, out)
        if not math.isfinite(y[k]) or abs(y[k]) >= blowup:
            status, blow_t = "blowup", float(t[k])
            message = f"|y| reached {blowup:g} at t = {blow_t:.6g} s (sample {k})"
            y, t, u = y[:k + 1], t[:k + 1], u[:k + 1]
            break
        z = _shift(z, a, out)
    return SimulationResult(t=t, y=y, u=u, states=y[None, :], status=status,
                            method="recursion", blowup_time=blow_t, message=message,
                            nfev=int(t.size))


def _shift(z: np.ndarray, a: int, out: np.ndarray) -> np.ndarray:
    """Next NARX state: the a output lags, then (in a loop) the controller-output lags."""
    y_part = np.concatenate((out[:1], z[:a][:-1])) if a else z[:0]
    w_part = np.concatenate((out[1:], z[a:][:-1])) if z.size > a else z[:0]
    return np.concatenate((y_part, w_part))
