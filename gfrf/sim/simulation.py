"""Time simulation of model files: open and closed loop, polynomial or physical equation.

A continuous model ``F(y, y', ..., y^(n), u, u', ...) = 0`` is solved once, with sympy,
for its highest output derivative y^(n) (the equation must be linear in it, which every
mechanical model is), giving the first-order state form z = (y, y', ..., y^(n-1))
that is printed to Python source (common subexpressions eliminated) and compiled.
The same source feeds scipy's ``solve_ivp`` here and the numba fast path in
:mod:`gfrf.sim.fastsim`, so both integrate the same right-hand side.

``equation="physical"`` (default) integrates the untruncated equation of the model
file (``sin``/``cos`` kept) when it has one; ``"polynomial"`` the truncated model the
GFRFs describe.  ``closed_loop=True`` closes the loop with the file's controller,
``u = r + feedback*C[y]`` (feedback -1: ``u = r - C[y]``), where the given input is
the reference r.  A controller C(s) = num/den is split into a polynomial part q(s)
acting on derivatives of y and a strictly proper rest realised in controllable
canonical form (extra states).  The cart-pole controller a s^2 + b s + c is improper:
its s^2 term feeds theta'' back into u, so the loop equation is implicit in theta''.
It is solved algebraically for theta'' (plant and controller are both linear in it),
which is exact as long as the coefficient of theta'' stays non-zero; where it vanishes
the state becomes non-finite and the run stops there like a blow-up, with its time.

A polynomial controller (``[controller] equation``) is a model whose output w = C[y]
(named like the plant input) gives ``u = r + feedback*w``: its output derivatives
w, ..., w^(m-1) join the state, and the plant and controller equations are solved for
y^(n) and w^(m) (one after the other, or as the linear system they form when each
holds the other's unknown, e.g. a controller using y^(n) with a static output m = 0).
Plant input derivatives D(u,j), j <= m, are then allowed; the reference r, r', ...
must be given.  A NARX plant is closed with a polynomial controller or a transfer
function read as ``control.tf(num, den, sample_time)`` (powers of z, highest first;
equal lengths: coefficients of 1, z^-1, ...) by direct recursion of (y[k], w[k]).

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
from collections.abc import Callable
from typing import Any

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import Model
from gfrf.model.limits import quote
from gfrf.model.modelfile import Controller, ModelFile
from gfrf.model.signals import InputSignal, T, parse_input, zero_input
from gfrf.sim.integrate import (
    MAX_RHS_EVALUATIONS,
    OdeSystem,
    SimulationResult,
    budget_name,
    integrate_scipy,
)

__all__ = ["OdeSystem", "SimulationResult", "build_system", "simulate", "METHODS",
           "MAX_RHS_EVALUATIONS", "AUTO_RK45_RTOL", "auto_method"]

#: Integration methods: ``"auto"`` (:func:`auto_method`), scipy's RK45, DOP853, Radau,
#: LSODA, and the numba fast path.
METHODS = ("auto", "rk45", "dop853", "radau", "lsoda", "fast")
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

    Examples
    --------
    >>> auto_method(1e-3), auto_method(1e-4), auto_method(1e-8)
    ('rk45', 'rk45', 'dop853')
    """
    return "rk45" if rtol >= AUTO_RK45_RTOL else "dop853"
def _solve_for(expr: sp.Expr, top: sp.Symbol, what: str) -> sp.Expr:
    coefficient = sp.diff(expr, top)
    if coefficient == 0:
        raise ModelError(f"the {what} does not contain its highest output term {top}")
    if sp.diff(coefficient, top) != 0:
        raise ModelError(f"the {what} is not linear in its highest output term {top}: "
                         f"cannot put it in state form")
    return -expr.subs(top, 0) / coefficient


def _controller_law(ctrl: Controller, y_atom: Callable[[int], sp.Symbol], order: int,
                    r: sp.Symbol) -> tuple[sp.Expr, list[sp.Symbol], list[sp.Expr]]:
    """u = r + feedback*C[y] with C = num/den: (u expression, controller states, their rates)."""
    s = sp.Symbol("s")
    num = sp.Poly([sp.Float(c) for c in ctrl.num], s)
    den = sp.Poly([sp.Float(c) for c in ctrl.den], s)
    quotient, remainder = num.div(den)
    if quotient.degree() > order:
        raise ModelError(f"the controller's improper part has degree {quotient.degree()}, "
                         f"above the plant order {order}: the loop has no state form")
    v = sum((sp.Float(c) * y_atom(k) for k, c in enumerate(reversed(quotient.all_coeffs()))),
            sp.Integer(0))
    states: list[sp.Symbol] = []
    rates: list[sp.Expr] = []
    m = den.degree()
    if m > 0 and not remainder.is_zero:
        lead = den.LC()
        d = [c / lead for c in reversed(den.all_coeffs())]  # d0..dm, dm = 1
        rc = [c / lead for c in reversed(remainder.all_coeffs())]
        rc += [0] * (m - len(rc))
        states = [sp.Symbol(f"xc{i}", real=True) for i in range(m)]
        rates = [states[i + 1] for i in range(m - 1)]
        rates.append(-sum(d[i] * states[i] for i in range(m)) + y_atom(0))
        v += sum(rc[i] * states[i] for i in range(m))
    return r + ctrl.feedback * v, states, rates


def _orders(expr: sp.Expr, name: str) -> list[int]:
    """Sorted derivative orders (lags for NARX) of the atoms ``name__k`` in ``expr``."""
    return sorted(int(a.name.rsplit("__", 1)[1]) for a in expr.free_symbols
                  if a.name.startswith(f"{name}__"))


def _w(k: int) -> sp.Symbol:
    """Controller output w (C[y]; the plant input is u = r + feedback*w), order or lag k."""
    return sp.Symbol(f"_w__{k}", real=True)


def _controller_equation(ctrl: Controller, plant: Model, equation: str) -> sp.Expr:
    """The controller as ``expression = 0`` in its output atoms :func:`_w` and plant output.

    A polynomial controller's output atoms (named like the plant input) are renamed to
    w; a transfer function (discrete plants only here) is read as ``control.tf(num, den,
    sample_time)``: powers of z, highest first, so that after left-padding num to the
    length of den the entries are the coefficients of 1, z^-1, z^-2, ... and
    ``sum den_i w[k-i] = sum num_i y[k-i]``.
    """
    if ctrl.model is not None:
        c = ctrl.model
        expr = c.physical if equation == "physical" and c.physical is not None \
            else c.polynomial()
        return expr.xreplace({plant.atom(c.output, k): _w(k) for k in _orders(expr, c.output)})
    num = np.trim_zeros(np.asarray(ctrl.num, dtype=float), "f")
    den = np.trim_zeros(np.asarray(ctrl.den, dtype=float), "f")
    if num.size > den.size:
        raise ModelError("the discrete controller num/den (powers of z, highest first, as "
                         "control.tf) has more zeros than poles: it is not causal")
    num = np.concatenate([np.zeros(den.size - num.size), num])
    return sum((sp.Float(a) * _w(i) - sp.Float(b) * plant.atom(plant.output, i)
                for i, (a, b) in enumerate(zip(den, num, strict=True))), sp.Integer(0))


def _solve_pair(loop: sp.Expr, ctrl: sp.Expr, top_y: sp.Symbol,
                top_w: sp.Symbol) -> tuple[sp.Expr, sp.Expr]:
    """Solve the plant (``loop``) and controller equations for top_y and top_w.

    Sequentially when one equation lacks the other's unknown; otherwise as the linear
    system both form (each must be linear in both unknowns jointly).
    """
    if not loop.has(top_w):
        y_top = _solve_for(loop, top_y, "closed-loop plant equation")
        return y_top, _solve_for(ctrl.xreplace({top_y: y_top}), top_w, "controller equation")
    if not ctrl.has(top_y):
        w_top = _solve_for(ctrl, top_w, "controller equation")
        return _solve_for(loop.xreplace({top_w: w_top}), top_y,
                          "closed-loop plant equation"), w_top
    eqs = sp.Matrix([loop, ctrl])
    jac = eqs.jacobian([top_y, top_w])
    if any(entry.has(top_y) or entry.has(top_w) for entry in jac):
        raise ModelError(f"plant and controller are coupled through {top_y} and {top_w} "
                         f"but not jointly linear in them: cannot put the loop in state form")
    if sp.simplify(jac.det()) == 0:
        raise ModelError(f"plant and controller equations are singular in {top_y}, {top_w}")
    sol = jac.LUsolve(-eqs.xreplace({top_y: 0, top_w: 0}))
    return sol[0], sol[1]


def _polynomial_loop(expr: sp.Expr, model: Model, ctrl: Controller, equation: str
                     ) -> tuple[list[sp.Symbol], list[sp.Expr], list[sp.Symbol], sp.Expr,
                                list[str]]:
    """Continuous loop with a polynomial controller: (states, rates, inputs, u, notes).

    States are y, ..., y^(n-1) then w, ..., w^(m-1) (m: the controller's output order);
    the inputs are r, r', ... up to the plant's highest input derivative.
    """
    y_atom = lambda k: model.atom(model.output, k)  # noqa: E731
    cexpr = _controller_equation(ctrl, model, equation)
    n = _orders(expr, model.output)[-1]
    u_orders = _orders(expr, model.input)
    w_orders, p_orders = _orders(cexpr, "_w"), _orders(cexpr, model.output)
    if not w_orders:
        raise ModelError("the controller equation does not contain its output "
                         f"{model.input}")
    m, p, q = w_orders[-1], max(p_orders, default=0), max(u_orders, default=0)
    if p > n:
        raise ModelError(f"the controller uses D({model.output},{p}), above the plant order "
                         f"{n}: the loop has no state form")
    if q > m:
        raise ModelError(f"the plant uses D({model.input},{q}), above the controller's output "
                         f"order {m}: the loop has no state form")
    r = [sp.Symbol(f"_r__{j}", real=True) for j in range(q + 1)]
    loop = expr.xreplace({model.atom(model.input, j): r[j] + ctrl.feedback * _w(j)
                          for j in u_orders})
    y_top, w_top = _solve_pair(loop, cexpr, y_atom(n), _w(m))
    notes = [f"the controller uses D({model.output},{n}): the loop is implicit; solved "
             f"algebraically for D({model.output},{n})"] if p == n else []
    z = [y_atom(k) for k in range(n)] + [_w(k) for k in range(m)]
    rates = [y_atom(k + 1) for k in range(n - 1)] + [y_top]
    rates += [_w(k + 1) for k in range(m - 1)] + ([w_top] if m else [])
    plant_u = r[0] + ctrl.feedback * (_w(0) if m else w_top)
    return z, rates, r, plant_u, notes


def _source(z: list[sp.Symbol], v: list[sp.Symbol], rates: list[sp.Expr],
            plant_u: sp.Expr, dz: list[sp.Symbol]) -> tuple[str, tuple[str, ...]]:
    """Python source of rhs(z, v, out) and plant_input(z, v, dz), cse-optimised.

    Also the body of the same right-hand side as statements that end in ``return [...]``
    (states and inputs bound by name), which :func:`gfrf.sim.integrate.integrate_scipy`
    completes with the input's expression into one function of (t, z).
    """
    lines = ["def rhs(z, v, out):"]
    unpack = [f"    {s.name} = z[{i}]" for i, s in enumerate(z)]
    unpack += [f"    {s.name} = v[{i}]" for i, s in enumerate(v)]
    subs, reduced = sp.cse(rates, symbols=sp.numbered_symbols("_c"))
    common = [f"{name} = {sp.pycode(expr)}" for name, expr in subs]
    lines += unpack
    lines += [f"    {line}" for line in common]
    lines += [f"    out[{i}] = {sp.pycode(expr)}" for i, expr in enumerate(reduced)]
    lines += ["", "", "def plant_input(z, v, dz):"]
    lines += unpack + [f"    {s.name} = dz[{i}]" for i, s in enumerate(dz)]
    lines.append(f"    return {sp.pycode(plant_u)}")
    # A Python float power of a negative base with a fractional exponent other than
    # +-1/2 (printed as math.sqrt, which raises) is complex where numpy gives nan: such a
    # right-hand side is left to the numpy-scalar ``rhs`` (no fused body).
    fused = all(p.exp.is_Integer or p.exp in (sp.S.Half, -sp.S.Half)
                for p in sp.Tuple(*rates, *(e for _, e in subs), *reduced).atoms(sp.Pow))
    body = (*common, f"return [{', '.join(sp.pycode(expr) for expr in reduced)}]") \
        if fused else ()
    return "\n".join(lines) + "\n", body


def build_system(source: ModelFile | Model, *, closed_loop: bool = False,
                 equation: str = "physical") -> OdeSystem:
    """Generate the first-order state form of a model (open or closed loop).

    Parameters
    ----------
    source : ModelFile or Model
        A loaded model file (needed for ``closed_loop``) or a bare model.
    closed_loop : bool, optional
        Close the loop with the model file's controller; the input becomes the reference.
    equation : {"physical", "polynomial"}
        The untruncated equation (when the model has one) or the truncated polynomial.

    Returns
    -------
    OdeSystem

    Raises
    ------
    ModelError
        No controller for a closed loop, an equation not linear in its highest output
        derivative, a controller too improper for the plant (or, for a polynomial
        controller, a plant input derivative above the controller's output order), input
        derivatives in a loop with a transfer-function controller, a non-causal discrete
        controller.
    """
    mf = source if isinstance(source, ModelFile) else None
    model = source.plant if isinstance(source, ModelFile) else source
    if equation not in ("physical", "polynomial"):
        raise ArgumentError(f"equation must be 'physical' or 'polynomial', got {equation!r}")
    expr = model.physical if (equation == "physical" and model.physical is not None) \
        else model.polynomial()
    label = f"{model.output}: {equation}{', closed loop' if closed_loop else ''}"
    y_atom = lambda k: model.atom(model.output, k)  # noqa: E731
    u_atom = lambda k: model.atom(model.input, k)  # noqa: E731
    y_orders, u_orders = _orders(expr, model.output), _orders(expr, model.input)
    ctrl = None
    if closed_loop:
        if mf is None or mf.controller is None:
            raise ModelError("closed loop requested but the model file has no [controller]")
        ctrl = mf.controller
    if model.is_discrete:
        if ctrl is not None:
            return _narx_loop(model, expr, ctrl, equation, label)
        return _narx_system(model, expr, y_orders, u_orders, label)
    n = y_orders[-1]
    notes: list[str] = []
    if ctrl is not None and ctrl.model is not None:
        z, rates, inputs, plant_u, notes = _polynomial_loop(expr, model, ctrl, equation)
    elif ctrl is not None:
        if any(k > 0 for k in u_orders):
            raise ModelError("closed-loop simulation with input derivatives D(u,k) in the "
                             "plant is not supported with a transfer-function controller")
        r = sp.Symbol("_r__0", real=True)
        law, ctrl_states, ctrl_rates = _controller_law(ctrl, y_atom, n, r)
        if law.has(y_atom(n)):
            notes.append(f"the controller is improper: its D({model.output},{n}) term makes "
                         f"the loop implicit; solved algebraically for D({model.output},{n})")
        top = _solve_for(expr.xreplace({u_atom(0): law}), y_atom(n), "closed-loop equation")
        z = [y_atom(k) for k in range(n)] + ctrl_states
        rates = [y_atom(k + 1) for k in range(n - 1)] + [top]
        rates += [rate.xreplace({y_atom(n): top}) for rate in ctrl_rates]
        plant_u, inputs = law, [r]
    else:
        top = _solve_for(expr, y_atom(n), "model equation")
        inputs = [u_atom(k) for k in range(max(u_orders) + 1)]
        plant_u = u_atom(0)
        z = [y_atom(k) for k in range(n)]
        rates = [y_atom(k + 1) for k in range(n - 1)] + [top]
    dz = [sp.Symbol(f"_dz{i}", real=True) for i in range(len(z))]
    plant_u = plant_u.xreplace({y_atom(n): dz[n - 1]})
    jac = sp.Matrix(rates).jacobian(z).subs({s: 0 for s in z + inputs})
    eig = np.linalg.eigvals(np.array(jac.evalf(), dtype=float)) if z else np.zeros(0)
    source, body = _source(z, inputs, rates, plant_u, dz)
    return OdeSystem(n_states=len(z), order=n, n_inputs=len(inputs), source=source,
                     linear_eigenvalues=eig, label=label, closed_loop=closed_loop,
                     notes=tuple(notes), state_names=tuple(s.name for s in z),
                     input_names=tuple(s.name for s in inputs), rhs_body=body)


def _narx_system(model: Model, expr: sp.Expr, y_orders: list[int], u_orders: list[int],
                 label: str) -> OdeSystem:
    y_atom = lambda k: model.atom(model.output, k)  # noqa: E731
    now = _solve_for(expr, y_atom(0), "NARX equation")
    lags = max(y_orders)
    z = [y_atom(k) for k in range(1, lags + 1)]
    inputs = [model.atom(model.input, k) for k in range(max(u_orders) + 1)]
    jac = sp.Matrix([now] + z[:-1]).jacobian(z).subs({s: 0 for s in z + inputs})
    eig = np.linalg.eigvals(np.array(jac.evalf(), dtype=float)) if z else np.zeros(0)
    src, _ = _source(z, inputs, [now], inputs[0], [])
    return OdeSystem(n_states=len(z), order=lags, n_inputs=len(inputs), source=src,
                     linear_eigenvalues=eig, label=label, discrete=True,
                     sample_time=model.sample_time)


def _narx_loop(model: Model, expr: sp.Expr, ctrl: Controller, equation: str,
               label: str) -> OdeSystem:
    """NARX plant in a loop: ``rhs`` gives (y[k], w[k]) from past y, past w and r lags.

    The state is (y[k-1], ..., y[k-a], w[k-1], ..., w[k-b]); the inputs r[k], ..., r[k-q]
    (q: the plant's largest input lag); u[k] = r[k] + feedback*w[k].
    """
    y_atom = lambda k: model.atom(model.output, k)  # noqa: E731
    cexpr = _controller_equation(ctrl, model, equation)
    u_orders = _orders(expr, model.input)
    q = max(u_orders, default=0)
    r = [sp.Symbol(f"_r__{j}", real=True) for j in range(q + 1)]
    loop = expr.xreplace({model.atom(model.input, j): r[j] + ctrl.feedback * _w(j)
                          for j in u_orders})
    y_now, w_now = _solve_pair(loop, cexpr, y_atom(0), _w(0))
    a = max(_orders(expr, model.output) + _orders(cexpr, model.output))
    b = max(_orders(cexpr, "_w") + [q])
    z = [y_atom(k) for k in range(1, a + 1)] + [_w(k) for k in range(1, b + 1)]
    step = ([y_now] + z[:a - 1] if a else []) + ([w_now] + z[a:-1] if b else [])
    jac = sp.Matrix(step).jacobian(z).subs({s: 0 for s in z + r})
    eig = np.linalg.eigvals(np.array(jac.evalf(), dtype=float)) if z else np.zeros(0)
    src, _ = _source(z, r, [y_now, w_now], r[0] + ctrl.feedback * _w(0), [y_atom(0), _w(0)])
    return OdeSystem(n_states=len(z), order=a, n_inputs=len(r), source=src,
                     linear_eigenvalues=eig, label=label, closed_loop=True, discrete=True,
                     sample_time=model.sample_time)


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


def simulate(source: ModelFile | Model | OdeSystem, input: str | InputSignal | None = None,  # noqa: A002
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
    _check_impulses(signal, t_end)
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
    for k in range(system.n_inputs if not system.discrete else 1):
        try:
            with np.errstate(all="ignore"):
                value = float(signal.derivative(k)(0.0))
        except OverflowError:  # an exact integer of the text beyond a float, e.g. 99**150
            value = math.inf
        if not math.isfinite(value):
            raise ArgumentError(f"the input{' derivative ' + str(k) if k else ''} is not "
                                f"finite at t = 0 s: u(t) = {signal.text[:80]}")
    start = time.perf_counter()
    if system.discrete:
        result = _narx(system, signal, z0, t_end, blowup)
    elif method == "fast":
        from gfrf.sim.fastsim import simulate_fast
        result = simulate_fast(system, signal, z0, t_end, t_eval, blowup=blowup, dt=dt,
                               rtol=rtol, atol=atol, max_evaluations=max_evaluations)
    else:
        result = integrate_scipy(system, signal, z0, t_end, t_eval, method, rtol, atol,
                                 blowup, max_evaluations)
    result.wall_time = time.perf_counter() - start - result.compile_time
    result.notes = notes + result.notes
    return result


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


def _check_impulses(signal: InputSignal, t_end: float) -> None:
    """Refuse an input whose derivative needed by a D(u) term is an impulse in (0, t_end]."""
    times = signal.impulses(t_end)
    if times is None or times.size:
        where = ("at a time that is not known in closed form" if times is None else
                 f"at t = {', '.join(f'{x:.6g}' for x in times[:3])} s"
                 + (f" (and {times.size - 3} more)" if times.size > 3 else ""))
        raise ArgumentError(
            f"the model uses derivatives of u up to order {signal.max_derivative}, and the "
            f"input {quote(signal.text)} jumps (or its slope does) {where}: the derivative "
            "there is an impulse (Dirac delta), which no integrator represents; use a "
            "smooth input instead, e.g. 0.5*(1 + tanh((t-1)/0.01)) for step(t-1)")


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
