"""The first-order state form of a model file: open and closed loop, polynomial or physical.

A continuous model ``F(y, y', ..., y^(n), u, u', ...) = 0`` is solved once, with sympy,
for its highest output derivative y^(n) (the equation must be linear in it, which every
mechanical model is), giving the first-order state form z = (y, y', ..., y^(n-1))
that is printed to Python source (common subexpressions eliminated) and compiled.
The same source feeds scipy's ``solve_ivp`` (:func:`gfrf.sim.simulation.simulate`) and
the numba fast path in :mod:`gfrf.sim.fastsim`, so both integrate the same right-hand side.

``equation="physical"`` (default) takes the untruncated equation of the model
file (``sin``/``cos`` kept) when it has one; ``"polynomial"`` the truncated model the
GFRFs describe.  ``closed_loop=True`` closes the loop with the file's controller C in
the one convention of gfrf, that of Theorem 2 and of python-control's
``feedback(C*G, 1)``: the controller acts on the error, ``u = C(e)`` with
``e = r + feedback*y`` (feedback -1, negative feedback: ``u = C(r - y)``), and the
given input is the reference r, in the units of y.  A controller C(s) = num/den is
split into a polynomial part q(s) acting on derivatives of e and a strictly proper rest
realised in controllable canonical form (extra states driven by e).  An improper
controller needs derivatives of the reference up to the degree of q: they are inputs
of the state form (``r, r', ...``), taken exactly from an input given as an
expression (a tone's are exact; a jump's would be an impulse and is refused by the
simulator).  The cart-pole controller a s^2 + b s + c is improper: its s^2 term feeds
theta'' back into u, so the loop equation is implicit in theta''.
It is solved algebraically for theta'' (plant and controller are both linear in it),
which is exact as long as the coefficient of theta'' stays non-zero; where it vanishes
the state becomes non-finite and the run stops there like a blow-up, with its time.

A polynomial controller (``[controller] equation``) is a model whose input is named
like the plant output and whose output w (named like the plant input) is the plant
input, ``u = w = C[e]``: its input atoms D(y,k) become e^(k) = r^(k) + feedback*y^(k),
its output derivatives w, ..., w^(m-1) join the state, and the plant and controller
equations are solved for y^(n) and w^(m) (one after the other, or as the linear system
they form when each holds the other's unknown, e.g. a controller using y^(n) with a
static output m = 0).  Plant input derivatives D(u,j), j <= m, are then allowed; the
reference r, r', ... up to the controller's highest input derivative must be given.
A NARX plant is closed with a polynomial controller or a transfer function read as
``control.tf(num, den, sample_time)`` (powers of z, highest first; equal lengths:
coefficients of 1, z^-1, ...) by direct recursion of (y[k], w[k]), the controller
reading e[k-i] = r[k-i] + feedback*y[k-i].

The linearisation at z = 0 is computed with the state form (``linear_eigenvalues`` of
the :class:`gfrf.sim.integrate.OdeSystem`), for the simulation to report an unstable
linear part.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import sympy as sp

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import Model
from gfrf.model.modelfile import Controller, ModelFile, resolve_model
from gfrf.sim.integrate import OdeSystem

__all__ = ["build_system"]


def _solve_for(expr: sp.Expr, top: sp.Symbol, what: str) -> sp.Expr:
    coefficient = sp.diff(expr, top)
    if coefficient == 0:
        raise ModelError(f"the {what} does not contain its highest output term {top}")
    if sp.diff(coefficient, top) != 0:
        raise ModelError(f"the {what} is not linear in its highest output term {top}: "
                         f"cannot put it in state form")
    return -expr.subs(top, 0) / coefficient


def _error(ctrl: Controller, y_atom: Callable[[int], sp.Symbol], k: int) -> sp.Expr:
    """e^(k) = r^(k) + feedback*y^(k): the controller's input (the loop error), order k."""
    return _r(k) + ctrl.feedback * y_atom(k)


def _r(k: int) -> sp.Symbol:
    """The reference r, its k-th derivative (continuous) or lag k (NARX)."""
    return sp.Symbol(f"_r__{k}", real=True)


def _controller_law(ctrl: Controller, y_atom: Callable[[int], sp.Symbol], order: int
                    ) -> tuple[sp.Expr, list[sp.Symbol], list[sp.Expr], int]:
    """u = C(e), e = r + feedback*y, C = num/den: (u expression, controller states, their
    rates, the highest reference derivative the law reads)."""
    s = sp.Symbol("s")
    num = sp.Poly([sp.Float(c) for c in ctrl.num], s)
    den = sp.Poly([sp.Float(c) for c in ctrl.den], s)
    quotient, remainder = num.div(den)
    if quotient.degree() > order:
        raise ModelError(f"the controller's improper part has degree {quotient.degree()}, "
                         f"above the plant order {order}: the loop has no state form")
    v = sum((sp.Float(c) * _error(ctrl, y_atom, k)
             for k, c in enumerate(reversed(quotient.all_coeffs()))), sp.Integer(0))
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
        rates.append(-sum(d[i] * states[i] for i in range(m)) + _error(ctrl, y_atom, 0))
        v += sum(rc[i] * states[i] for i in range(m))
    return v, states, rates, max(quotient.degree(), 0)


def _orders(expr: sp.Expr, name: str) -> list[int]:
    """Sorted derivative orders (lags for NARX) of the atoms ``name__k`` in ``expr``."""
    return sorted(int(a.name.rsplit("__", 1)[1]) for a in expr.free_symbols
                  if a.name.startswith(f"{name}__"))


def _w(k: int) -> sp.Symbol:
    """Controller output w = C[e], the plant input u, order or lag k."""
    return sp.Symbol(f"_w__{k}", real=True)


def _controller_equation(ctrl: Controller, plant: Model, equation: str) -> sp.Expr:
    """The controller as ``expression = 0`` in its output atoms :func:`_w` and plant output.

    A polynomial controller's output atoms (named like the plant input) are renamed to
    w (its input atoms, named like the plant output, are still y: :func:`_on_error`
    makes them the error); a transfer function (discrete plants only here) is read as
    ``control.tf(num, den, sample_time)``: powers of z, highest first, so that after
    left-padding num to the length of den the entries are the coefficients of 1, z^-1, z^-2, ... and
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


def _on_error(cexpr: sp.Expr, ctrl: Controller, plant: Model) -> tuple[sp.Expr, int]:
    """The controller equation read on the error: each y^(k) (lag k for NARX) becomes
    r^(k) + feedback*y^(k); also the highest k (0 when it reads none)."""
    ks = _orders(cexpr, plant.output)
    y_atom = lambda k: plant.atom(plant.output, k)  # noqa: E731
    return (cexpr.xreplace({y_atom(k): _error(ctrl, y_atom, k) for k in ks}),
            max(ks, default=0))


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
    the inputs are r, r', ... up to the controller's highest input derivative.
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
    loop = expr.xreplace({model.atom(model.input, j): _w(j) for j in u_orders})
    cexpr, _ = _on_error(cexpr, ctrl, model)
    r = [_r(j) for j in range(p + 1)]
    y_top, w_top = _solve_pair(loop, cexpr, y_atom(n), _w(m))
    notes = [f"the controller uses D({model.output},{n}): the loop is implicit; solved "
             f"algebraically for D({model.output},{n})"] if p == n else []
    z = [y_atom(k) for k in range(n)] + [_w(k) for k in range(m)]
    rates = [y_atom(k + 1) for k in range(n - 1)] + [y_top]
    rates += [_w(k + 1) for k in range(m - 1)] + ([w_top] if m else [])
    plant_u = _w(0) if m else w_top
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
    if not isinstance(source, Model):
        source = resolve_model(source)
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
        law, ctrl_states, ctrl_rates, k_r = _controller_law(ctrl, y_atom, n)
        if law.has(y_atom(n)):
            notes.append(f"the controller is improper: its D({model.output},{n}) term makes "
                         f"the loop implicit; solved algebraically for D({model.output},{n})")
        top = _solve_for(expr.xreplace({u_atom(0): law}), y_atom(n), "closed-loop equation")
        z = [y_atom(k) for k in range(n)] + ctrl_states
        rates = [y_atom(k + 1) for k in range(n - 1)] + [top]
        rates += [rate.xreplace({y_atom(n): top}) for rate in ctrl_rates]
        plant_u, inputs = law, [_r(k) for k in range(k_r + 1)]
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
    (p: the controller's largest input lag); u[k] = w[k] = C[e][k], e = r + feedback*y.
    """
    y_atom = lambda k: model.atom(model.output, k)  # noqa: E731
    cexpr = _controller_equation(ctrl, model, equation)
    u_orders = _orders(expr, model.input)
    q = max(u_orders, default=0)
    loop = expr.xreplace({model.atom(model.input, j): _w(j) for j in u_orders})
    a = max(_orders(expr, model.output) + _orders(cexpr, model.output))
    cexpr, p = _on_error(cexpr, ctrl, model)
    r = [_r(j) for j in range(p + 1)]
    y_now, w_now = _solve_pair(loop, cexpr, y_atom(0), _w(0))
    b = max(_orders(cexpr, "_w") + [q])
    z = [y_atom(k) for k in range(1, a + 1)] + [_w(k) for k in range(1, b + 1)]
    step = ([y_now] + z[:a - 1] if a else []) + ([w_now] + z[a:-1] if b else [])
    jac = sp.Matrix(step).jacobian(z).subs({s: 0 for s in z + r})
    eig = np.linalg.eigvals(np.array(jac.evalf(), dtype=float)) if z else np.zeros(0)
    src, _ = _source(z, r, [y_now, w_now], _w(0), [y_atom(0), _w(0)])
    return OdeSystem(n_states=len(z), order=a, n_inputs=len(r), source=src,
                     linear_eigenvalues=eig, label=label, closed_loop=True, discrete=True,
                     sample_time=model.sample_time)
