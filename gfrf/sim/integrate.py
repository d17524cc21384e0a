"""The integrators' common ground: a model in state form, a run's result, the scipy path.

:func:`gfrf.sim.system.build_system` generates an :class:`OdeSystem` (the right-hand
side as Python source) from a model; :func:`integrate_scipy` steps one of scipy's
``solve_ivp`` solvers on it (the right-hand side and the input fused into one generated
function) under a work budget of right-hand-side evaluations, and
:mod:`gfrf.sim.fastsim` runs the same source compiled with numba.  Both return a
:class:`SimulationResult`.  This module imports neither of them, so the simulation
modules form no import cycle (simulation -> fastsim -> integrate).
"""

from __future__ import annotations

import functools
import math
import types
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf._results import short_repr, simulation_figure, simulation_markdown
from gfrf.model.signals import InputSignal

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


#: The ``math`` names of generated sources, as numpy ufuncs (for whole trajectories).
_NUMPY_MATH = types.SimpleNamespace(
    **{name: getattr(np, name) for name in ("sin", "cos", "tan", "exp", "log", "sqrt", "tanh",
                                            "sinh", "cosh", "arctan", "pi", "e")},
    atan=np.arctan, copysign=np.copysign, fabs=np.fabs)


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
    state_names, input_names : tuple of str
        Names the generated code gives the states and the inputs (continuous models).
    rhs_body : tuple of str
        The right-hand side as statements in those names ending in ``return [...]``
        (continuous models; empty for NARX), completed by :func:`integrate_scipy` into
        one function of (t, z) with the input's expression.
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
    state_names: tuple[str, ...] = ()
    input_names: tuple[str, ...] = ()
    rhs_body: tuple[str, ...] = ()
    _functions: dict[str, Any] = field(default_factory=dict, repr=False,
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
        """The compiled pure-Python function ``rhs`` or ``plant_input`` of :attr:`source`.

        Parameters
        ----------
        name : str
            ``"rhs"`` or ``"plant_input"``.

        Returns
        -------
        callable
            The function, compiled once and kept.
        """
        if name not in self._functions:
            namespace: dict[str, Any] = {"math": math}
            exec(compile(self.source, f"<gfrf rhs {self.label}>", "exec"), namespace)
            self._functions.update({k: namespace[k] for k in ("rhs", "plant_input")})
        return self._functions[name]

    def vector_function(self, name: str) -> Callable[..., Any]:
        """``rhs`` or ``plant_input`` of :attr:`source` run on arrays (one column a sample).

        The same generated source, with its ``math`` functions taken from numpy
        (:data:`_NUMPY_MATH`); a function numpy lacks raises ``AttributeError`` when called.

        Parameters
        ----------
        name : str
            ``"rhs"`` or ``"plant_input"``.

        Returns
        -------
        callable
            The function on arrays, compiled once and kept.
        """
        key = f"{name}[numpy]"
        if key not in self._functions:
            namespace: dict[str, Any] = {"math": _NUMPY_MATH}
            exec(compile(self.source, f"<gfrf rhs {self.label}>", "exec"), namespace)
            self._functions.update({f"{k}[numpy]": namespace[k] for k in ("rhs", "plant_input")})
        return self._functions[key]


@dataclass(frozen=True, kw_only=True)
class SimulationResult:
    """Output of :func:`simulate`.

    ``to_dict`` stays written out: it summarises the samples (final time and value, peak)
    and adds them only on request (``arrays=True``); the state trajectory ``states`` is
    left out.

    Attributes
    ----------
    t : numpy.ndarray
        Times in seconds (up to the blow-up time if the run blew up).
    y : numpy.ndarray
        Output y(t).
    u : numpy.ndarray
        Plant input u(t) (in closed loop: C(r + feedback*y)).
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
        """JSON-ready summary; ``arrays=True`` adds t, y, u.

        Parameters
        ----------
        arrays : bool, optional
            Include the samples t (s), y and u as lists.

        Returns
        -------
        dict
            The summary.
        """
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
        """y(t) and u(t) (the plant input; C(r + feedback*y) in closed loop), t in seconds.

        Returns
        -------
        matplotlib.figure.Figure
            Made without pyplot (works with any backend; display it or ``savefig``).
        """
        return simulation_figure(self)


def budget_name(max_evaluations: int) -> str:
    """The name of the work budget for a message.

    Parameters
    ----------
    max_evaluations : int
        The budget of right-hand-side evaluations in force.

    Returns
    -------
    str
        ``"MAX_RHS_EVALUATIONS"`` when it is the default, else ``"max_evaluations"``.
    """
    return "MAX_RHS_EVALUATIONS" if max_evaluations == MAX_RHS_EVALUATIONS \
        else "max_evaluations"


def input_values(signal: InputSignal, n_inputs: int, t: np.ndarray) -> np.ndarray:
    """Array (n_inputs, len(t)) of u, u', ... at times ``t`` (seconds).

    Parameters
    ----------
    signal : InputSignal
        The input.
    n_inputs : int
        Number of rows: u and its first ``n_inputs - 1`` derivatives.
    t : numpy.ndarray
        Times in s.

    Returns
    -------
    numpy.ndarray
        Float array of shape (n_inputs, len(t)).
    """
    return np.array([signal.derivative(k)(t) for k in range(n_inputs)]).reshape(n_inputs, -1)


def plant_input(system: OdeSystem, states: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The plant input u along a trajectory (evaluates ``plant_input`` of the source).

    The source is run once on whole rows (its ``math`` functions taken from numpy, see
    :meth:`OdeSystem.vector_function`); a source that does not run on arrays is run
    sample by sample.

    Parameters
    ----------
    system : OdeSystem
        The generated state form.
    states : numpy.ndarray
        States, shape (n_states, N), one column per sample.
    v : numpy.ndarray
        Input vectors (u, u', ...), shape (n_inputs, N).

    Returns
    -------
    numpy.ndarray
        The N values of u.
    """
    n = states.shape[1]
    try:
        rhs, pin = system.vector_function("rhs"), system.vector_function("plant_input")
        out = np.empty((system.n_states, n))
        with np.errstate(all="ignore"):
            rhs(states, v, out)
            return np.broadcast_to(np.asarray(pin(states, v, out), dtype=float), (n,)).copy()
    except (AttributeError, TypeError, ValueError):  # e.g. a conditional on a sample
        pass
    rhs, pin = system.function("rhs"), system.function("plant_input")
    dz = np.empty(system.n_states)
    u = np.empty(n)
    for i in range(n):
        rhs(states[:, i], v[:, i], dz)
        u[i] = pin(states[:, i], v[:, i], dz)
    return u


#: sympy functions whose ``math`` printing agrees with numpy's on floats (or raises,
#: and the evaluation then falls back to numpy), see :func:`_input_code`.
_MATH_FUNCTIONS = ("sin", "cos", "tan", "sinh", "cosh", "tanh", "atan", "exp", "log", "Abs",
                   "sign", "Heaviside")
#: Time argument of the generated right-hand side (no model or input name starts with _).
_TIME = "_t"


@functools.lru_cache(maxsize=256)
def _input_code(expr: Any, k: int) -> str | None:
    """Python (``math``) code of the k-th derivative of ``expr`` in the time ``_t``, or None.

    Only for expressions built from :data:`_MATH_FUNCTIONS` and powers with exponent an
    integer or +-1/2 (printed as ``math.sqrt``): a Python float power of a negative base
    with another fractional exponent is complex, where numpy gives nan.  The expression
    comes from the whitelisting parser of :mod:`gfrf.model.signals`; sympy prints it.
    """
    import sympy as sp

    from gfrf.model.signals import T

    current = sp.diff(expr, T, k) if k else expr
    allowed = tuple(getattr(sp, name) for name in _MATH_FUNCTIONS)
    if any(not isinstance(f, allowed) for f in current.atoms(sp.Function)):
        return None
    if any(not (p.exp.is_Integer or p.exp in (sp.S.Half, -sp.S.Half))
           for p in current.atoms(sp.Pow)):
        return None
    return str(sp.pycode(current.xreplace({T: sp.Symbol(_TIME, real=True)})))


def _fused_rhs(system: OdeSystem, signal: InputSignal,
               slow: Callable[[float, np.ndarray], np.ndarray]
               ) -> Callable[[float, np.ndarray], list[float] | np.ndarray] | None:
    """The right-hand side and the input as one generated function ``f(t, z)``, or None.

    One Python frame per evaluation, states unpacked as Python floats, the input
    evaluated by ``math`` (:func:`_input_code`): cheaper than a hand-written
    ``f(t, y)`` that works on numpy scalars.  An arithmetic or domain error (``log``
    of a negative number, an overflow, a division by zero) sends that evaluation to
    ``slow`` (numpy scalars: inf/nan as before).  None for a CSV input, an input
    outside :data:`_MATH_FUNCTIONS`, or a system without :attr:`OdeSystem.rhs_body`.
    The last function made is kept on the system, for the same input text only (then
    its ``slow``, from an input of the same expression, is equivalent).
    """
    if not system.rhs_body or signal.expr is None:
        return None
    codes = [_input_code(signal.expr, k) for k in range(system.n_inputs)]
    if any(code is None for code in codes):
        return None
    cached = system._functions.get("fused")
    if cached is not None and cached[0] == codes:  # the same input on the same system
        return cached[1]
    lines = [f"def f({_TIME}, _z):", "    try:"]
    if system.state_names:
        lines.append(f"        {', '.join(system.state_names)}, = _z.tolist()")
    lines += [f"        {name} = {code}"
              for name, code in zip(system.input_names, codes, strict=True)]
    lines += [f"        {line}" for line in system.rhs_body]
    lines += ["    except (ArithmeticError, ValueError):", f"        return _slow({_TIME}, _z)"]
    namespace: dict[str, Any] = {"math": math, "_slow": slow}
    exec(compile("\n".join(lines) + "\n", f"<gfrf rhs {system.label}>", "exec"),
         namespace)
    system._functions["fused"] = (codes, namespace["f"])  # one entry: a sweep changes it
    return namespace["f"]


#: Dense outputs evaluated together (a batch holds ~0.5 kB per step of a small system).
_DENSE_BATCH = 4096


def _dense_values(pieces: list[tuple[int, int, Any]], t_eval: np.ndarray) -> np.ndarray:
    """States at ``t_eval[i0:N]`` from the steps' dense outputs, all at once.

    ``pieces`` are consecutive ``(i, j, dense)``: ``dense(t_eval[i:j])`` for each
    accepted step, i0 the first i and N the last j.  scipy's RK45 and DOP853
    interpolants (classes ``RkDenseOutput``, ``Dop853DenseOutput``) are evaluated here
    for every sample in one numpy pass by their own formulas (the per-step calls cost
    ~10 us each); any other interpolant (Radau, LSODA) is called per step.
    """
    dense = [d for _, _, d in pieces]
    t = t_eval[pieces[0][0]:pieces[-1][1]]
    kinds = {type(d).__name__ for d in dense}
    if kinds in ({"RkDenseOutput"}, {"Dop853DenseOutput"}):
        try:
            return _batched(pieces, dense, t, kinds)
        except AttributeError:  # another scipy's private attributes: the public calls
            pass
    return np.hstack([d(t_eval[i:j]) for i, j, d in pieces])


def _batched(pieces: list[tuple[int, int, Any]], dense: list[Any], t: np.ndarray,
             kinds: set[str]) -> np.ndarray:
    """:func:`_dense_values` of RK45 or DOP853 steps from the interpolants' attributes."""
    step = np.repeat(np.arange(len(pieces)), [j - i for i, j, _ in pieces])
    h = np.array([d.h for d in dense])[step]
    x = (t - np.array([d.t_old for d in dense])[step]) / h
    y_old = np.array([d.y_old for d in dense])[step].T
    if kinds == {"RkDenseOutput"}:  # y_old + h * Q @ (x, x^2, ...)
        q = np.array([d.Q for d in dense])[step]  # (N, n, order + 1)
        p = np.cumprod(np.tile(x, (q.shape[2], 1)), axis=0)
        y = h * np.einsum("snk,ks->ns", q, p)
    else:  # Dop853DenseOutput: nested products in x and 1 - x
        f = np.array([d.F for d in dense])[step]  # (N, 7, n)
        y = np.zeros_like(y_old)
        for k in range(f.shape[1]):
            y += f[:, f.shape[1] - 1 - k, :].T
            y *= x if k % 2 == 0 else 1 - x
    return y + y_old


def integrate_scipy(system: OdeSystem, signal: InputSignal, z0: np.ndarray, t_end: float,
           t_eval: np.ndarray, method: str, rtol: float, atol: float,
           blowup: float, max_evaluations: int = MAX_RHS_EVALUATIONS) -> SimulationResult:
    """A scipy ``OdeSolver`` stepped to t_end, stopped at blow-up or when the budget is spent.

    The solver (``RK45``, ``DOP853``, ``Radau``, ``LSODA``) is stepped here as
    ``solve_ivp`` steps it, with its dense output evaluated at the ``t_eval`` times each
    step covers, but without ``solve_ivp``'s event machinery: after each accepted step
    |y| is compared with ``blowup`` (a crossing, or a non-finite state, is located by
    ``brentq`` on the step's dense output, as ``solve_ivp`` locates a terminal event)
    and the evaluation count with ``max_evaluations`` (the overrun is at most one
    step's evaluations; the run then ends at that step's time with status
    ``"failed"``).  The right-hand side is :func:`_fused_rhs` where it applies (else the
    source's ``rhs`` on numpy scalars with the input's numpy callables); the evaluations
    counted are the solver's (``nfev``, and for Radau also its finite-difference
    Jacobian's).

    Parameters
    ----------
    system : OdeSystem
        The generated state form.
    signal : InputSignal
        The input u(t), t in s.
    z0 : numpy.ndarray
        The initial state.
    t_end : float
        The end time in s.
    t_eval : numpy.ndarray
        Increasing output times in s, within [0, t_end].
    method : str
        ``"rk45"``, ``"dop853"``, ``"radau"`` or ``"lsoda"``.
    rtol, atol : float
        The solver's relative and absolute tolerances.
    blowup : float
        The threshold on |y|.
    max_evaluations : int, optional
        The budget of right-hand-side evaluations.

    Returns
    -------
    SimulationResult
        The samples at the ``t_eval`` times reached, and the status.
    """
    import scipy.integrate as si

    n, n_in = system.n_states, system.n_inputs
    rhs = system.function("rhs")
    exact = [signal.derivative(k) for k in range(n_in)]

    def slow(t: float, z: np.ndarray) -> np.ndarray:
        res = np.empty(n)
        try:
            rhs(z, [float(g(t)) for g in exact], res)
        except ZeroDivisionError:
            res[:] = np.nan
        return res

    f = _fused_rhs(system, signal, slow) or slow
    calls = 0
    radau = method == "radau"  # its finite-difference Jacobian bypasses the solver's count

    def counted(t: float, z: np.ndarray) -> list[float] | np.ndarray:
        nonlocal calls
        calls += 1
        return f(t, z)

    def evaluations() -> int:
        return calls if radau else int(solver.nfev)

    def escape(z: list[float]) -> float:  # solve_ivp's event function, on floats
        return blowup - abs(z[0]) if all(map(math.isfinite, z)) else -1.0

    pieces: list[tuple[int, int, Any]] = []  # (first, end) of t_eval per dense output
    values: list[np.ndarray] = []  # states at the samples of earlier batches of pieces
    status, blow_t, cut = "ok", None, None
    message = "The solver successfully reached the end of the integration interval."
    times_out = t_eval.tolist()
    with np.errstate(all="ignore"):
        # |y(0)| at or above the threshold is a blow-up at 0 (a sign change of the escape
        # function would otherwise be reported where |y| comes back below it); scipy's
        # first-step choice turns a non-finite f(0, z0) into a NaN step that its step
        # loop retries forever: both stop before any step.
        start, calls0 = None, 0
        if escape(z0.tolist()) <= 0:
            start = f"|y(0)| = {abs(z0[0]):g} is at or above the blow-up threshold {blowup:g}"
        elif not np.all(np.isfinite(np.asarray(f(0.0, z0), dtype=float))):
            start = ("the right-hand side is not finite at t = 0 s (the initial state is "
                     "outside the model's domain)")
            calls0 = 1
        if start is not None:
            return SimulationResult(
                t=np.zeros(0), y=np.zeros(0), u=np.zeros(0), states=np.zeros((n, 0)),
                status="blowup", method=method, blowup_time=0.0, message=start, nfev=calls0)
        solver = getattr(si, SCIPY_METHODS[method])(counted if radau else f, 0.0, z0, t_end,
                                                    rtol=rtol, atol=atol)
        g_old = escape(z0.tolist())
        i, next_out = 0, times_out[0]
        while solver.status == "running":
            try:
                step_message = solver.step()
            except ValueError as exc:  # Radau's LU of a non-finite Jacobian
                solver.status, step_message = "failed", f"the solver failed: {exc}"
            if solver.status == "failed":
                status, message = "failed", step_message or "the solver failed"
                break
            t = solver.t
            sol = None
            g_new = escape(solver.y.tolist())
            if (g_old <= 0 <= g_new) or (g_new <= 0 <= g_old):  # a sign change, as solve_ivp
                from scipy.optimize import brentq
                sol = solver.dense_output()
                eps = 4 * np.finfo(float).eps
                a, b = escape(sol(solver.t_old).tolist()), escape(sol(t).tolist())
                if (a <= 0 <= b) or (b <= 0 <= a):
                    t = brentq(lambda s, sol=sol: escape(sol(s).tolist()), solver.t_old, t,
                               xtol=eps, rtol=eps)
                else:  # an interpolant not finite at t_old (LSODA): the last finite state
                    t = solver.t_old
                status, blow_t = "blowup", float(t)
                message = f"|y| reached {blowup:g} at t = {blow_t:.6g} s"
            g_old = g_new
            if t >= next_out:  # output times in (t_old, t], from the step's dense output
                j = int(np.searchsorted(t_eval, t, side="right"))
                pieces.append((i, j, solver.dense_output() if sol is None else sol))
                if len(pieces) == _DENSE_BATCH:  # bounded memory on long runs
                    values.append(_dense_values(pieces, t_eval))
                    pieces = []
                i = j
                next_out = times_out[i] if i < len(times_out) else math.inf
            if status == "blowup":
                break
            if evaluations() >= max_evaluations and solver.status == "running":
                cut, status = t, "failed"
                message = (f"stopped at t = {cut:.6g} s of {t_end:g} s: {evaluations()} "
                           f"right-hand-side evaluations reached the work budget "
                           f"{budget_name(max_evaluations)} = {max_evaluations}")
                break
    # A run that fails before its first output time has no samples.
    if pieces:
        values.append(_dense_values(pieces, t_eval))
    states = np.hstack(values) if values else np.zeros((n, 0))
    times = t_eval[:states.shape[1]]
    finite = np.all(np.isfinite(states), axis=0)
    if blow_t is None and cut is None and (not finite.all() or status == "failed"):
        first = int(np.argmin(finite)) if not finite.all() else states.shape[1]
        states = states[:, :first]
        blow_t = float(times[first]) if first < times.size else float(times[-1]) \
            if times.size else 0.0
        message = f"the integration failed near t = {blow_t:.6g} s: {message}"
        status = "blowup" if not finite.all() else "failed"
    finite = np.all(np.isfinite(states), axis=0)  # an interpolant's NaN never printed
    states = states[:, :int(np.argmin(finite)) if not finite.all() else states.shape[1]]
    t_out = times[:states.shape[1]]
    v = input_values(signal, n_in, t_out)
    u = plant_input(system, states, v) if t_out.size else np.zeros(0)
    return SimulationResult(t=t_out, y=states[0] if states.size else np.zeros(0), u=u,
                            states=states, status=status, method=method,
                            blowup_time=blow_t, message=message, nfev=evaluations())
