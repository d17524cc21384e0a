"""A polynomial model in state form, with exact rational coefficients.

The certificate engine (:mod:`gfrf.stability.sos`) works on a state-space system

    continuous:  x' = f(x, v),        discrete:  x[k+1] = f(x[k], v[k]),

with f a vector of polynomials in the state x (n components) and the bounded input v
(the last variable), every coefficient the exact rational value written in the model
text (``0.2`` is 1/5: :attr:`gfrf.model.equation.Term.exact`; a model built from doubles,
e.g. from python-control, is its doubles).
:func:`state_form` builds it from

* a continuous model ``a_n D(y,n) + (terms in y .. D(y,n-1), u) = 0``: the companion
  state x = (y, y', .., y^(n-1)), v = u (the highest derivative must enter linearly with
  a constant coefficient, and u without derivatives);
* a NARX model: x = (y[k-1], .., y[k-ny], u[k-1], .., u[k-nu]), v = u[k];
* a model file with a linear proper controller C = N/D: the plant's companion state and
  the controller's controllable canonical state z, with the loop u = C(r - y) (feedback
  -1; ``u = C(r + y)`` for +1) and v = r, the reference (Theorem 2's convention).

A polynomial is a ``dict`` from exponent tuples (length n + 1, the input last) to
:class:`fractions.Fraction`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from gfrf.model.equation import Model, Term
from gfrf.model.modelfile import Controller, ModelFile, resolve_model

__all__ = ["Poly", "PolySystem", "state_form", "exact_coefficient", "exact_transfer_function",
           "padd", "pmul", "pscale", "pdiff", "pcompose",
           "peval", "pdegree", "linear_poly"]

Poly = dict[tuple[int, ...], Fraction]

#: Largest state dimension the engine accepts (the SOS problems grow as n^degree).
MAX_STATES = 6


def padd(*ps: Poly) -> Poly:
    """Sum of polynomials (zero coefficients dropped).

    Parameters
    ----------
    *ps : Poly
        Polynomials (exponent tuple -> Fraction) in the same number of variables.

    Returns
    -------
    Poly
        Their sum; an empty sum is the zero polynomial ``{}``.
    """
    out: Poly = {}
    for p in ps:
        for k, c in p.items():
            out[k] = out.get(k, Fraction(0)) + c
    return {k: c for k, c in out.items() if c != 0}


def pscale(p: Poly, s: Fraction) -> Poly:
    """s * p.

    Parameters
    ----------
    p : Poly
        The polynomial (exponent tuple -> Fraction).
    s : Fraction
        The factor.

    Returns
    -------
    Poly
        ``s * p``, ``{}`` when ``s`` is zero.
    """
    return {k: c * s for k, c in p.items() if c * s != 0}


def pmul(p: Poly, q: Poly) -> Poly:
    """p * q.

    Parameters
    ----------
    p, q : Poly
        Polynomials (exponent tuple -> Fraction) in the same number of variables.

    Returns
    -------
    Poly
        Their exact product, zero coefficients dropped.
    """
    out: Poly = {}
    for a, x in p.items():
        for b, y in q.items():
            k = tuple(i + j for i, j in zip(a, b, strict=True))
            out[k] = out.get(k, Fraction(0)) + x * y
    return {k: c for k, c in out.items() if c != 0}


def pdiff(p: Poly, i: int) -> Poly:
    """d p / d var_i.

    Parameters
    ----------
    p : Poly
        The polynomial (exponent tuple -> Fraction).
    i : int
        Index of the variable, 0-based (a position in the exponent tuples).

    Returns
    -------
    Poly
        The exact partial derivative.
    """
    out: Poly = {}
    for k, c in p.items():
        if k[i]:
            kk = k[:i] + (k[i] - 1,) + k[i + 1:]
            out[kk] = out.get(kk, Fraction(0)) + c * k[i]
    return out


def pcompose(p: Poly, subs: list[Poly], nvars: int) -> Poly:
    """p(subs[0], .., subs[m-1]) with each substitute a polynomial in ``nvars`` variables.

    Parameters
    ----------
    p : Poly
        The outer polynomial, in ``len(subs)`` variables.
    subs : list of Poly
        One substitute per variable of ``p``, each in ``nvars`` variables.
    nvars : int
        Number of variables of the substitutes (and of the result).

    Returns
    -------
    Poly
        The exact composition.
    """
    out: Poly = {}
    zero = (0,) * nvars
    powers: dict[tuple[int, int], Poly] = {}

    def power(i: int, e: int) -> Poly:
        if e == 0:
            return {zero: Fraction(1)}
        if (i, e) not in powers:
            powers[(i, e)] = pmul(power(i, e - 1), subs[i])
        return powers[(i, e)]

    for k, c in p.items():
        term: Poly = {zero: c}
        for i, e in enumerate(k):
            if e:
                term = pmul(term, power(i, e))
        out = padd(out, term)
    return out


def pdegree(p: Poly) -> int:
    """Total degree (0 for the zero polynomial).

    Parameters
    ----------
    p : Poly
        The polynomial (exponent tuple -> Fraction).

    Returns
    -------
    int
        The largest total degree of its monomials.
    """
    return max((sum(k) for k in p), default=0)


def peval(p: Poly, points: np.ndarray) -> np.ndarray:
    """p at the rows of ``points`` (floats; shape (m, nvars)).

    Parameters
    ----------
    p : Poly
        The polynomial (exponent tuple -> Fraction), evaluated in float arithmetic.
    points : numpy.ndarray
        Float array of shape (m, nvars), one point per row.

    Returns
    -------
    numpy.ndarray
        The m values, float (an estimate: not an exact check).
    """
    out = np.zeros(points.shape[0])
    for k, c in p.items():
        out += float(c) * np.prod(points ** np.asarray(k), axis=1)
    return out


def linear_poly(row: list[Fraction], nvars: int) -> Poly:
    """sum row[i] * var_i.

    Parameters
    ----------
    row : list of Fraction
        The coefficients of the variables ``var_0 .. var_{len(row)-1}``.
    nvars : int
        Number of variables of the result (at least ``len(row)``).

    Returns
    -------
    Poly
        The linear form, zero coefficients dropped.
    """
    return {tuple(int(j == i) for j in range(nvars)): c for i, c in enumerate(row) if c != 0}


@dataclass(frozen=True)
class PolySystem:
    """x' = f(x, v) (or x[k+1] = f(x[k], v[k])) with exact rational polynomials.

    Attributes
    ----------
    f : tuple of Poly
        One polynomial per state, in the variables (x_1, .., x_n, v).
    discrete : bool
        Difference equation (NARX) instead of an ODE.
    states : tuple of str
        What each state is, e.g. ``"D(y,1)"``, ``"y[k-2]"``, ``"z1 (controller)"``.
    input_name : str
        The bounded input v (``"u"`` or ``"r (reference)"``).
    bounded_states : tuple of int
        States that are past inputs (NARX): bounded by the input bound too.
    """

    f: tuple[Poly, ...]
    discrete: bool
    states: tuple[str, ...]
    input_name: str = "u"
    bounded_states: tuple[int, ...] = ()

    @property
    def n(self) -> int:
        """Number of states."""
        return len(self.f)

    def jacobian(self) -> list[list[Fraction]]:
        """The exact linearisation A = df/dx at (0, 0)."""
        n = self.n
        return [[self.f[i].get(tuple(int(m == j) for m in range(n + 1)), Fraction(0))
                 for j in range(n)] for i in range(n)]

    def equilibrium_ok(self) -> bool:
        """f(0, 0) = 0 (and for discrete time the origin is a fixed point)."""
        zero = (0,) * (self.n + 1)
        return all(p.get(zero, Fraction(0)) == 0 for p in self.f)

    def affine_in_input(self) -> bool:
        """Every f_i has degree <= 1 in v."""
        return all(k[-1] <= 1 for p in self.f for k in p)

    def map_text(self) -> str:
        """The state map in words."""
        kind = "x[k+1] = f(x[k], v[k])" if self.discrete else "x' = f(x, v)"
        return f"{kind}, x = ({', '.join(self.states)}), v = {self.input_name}"


class StateFormError(ValueError):
    """The model has no polynomial state form the engine handles (the reason is the text)."""


def exact_coefficient(term: Term) -> Fraction:
    """The exact rational coefficient of ``term`` as written in the model text.

    Parameters
    ----------
    term : Term
        A model term.

    Returns
    -------
    Fraction
        :attr:`gfrf.model.equation.Term.exact` (the double's own value for a coefficient
        that never was text).

    Raises
    ------
    StateFormError
        The written coefficient is irrational (``pi``, ``sqrt(2)``): the exact engine
        needs rationals.
    """
    value = term.exact
    if value is None:
        raise StateFormError(f"the coefficient of {term.monomial()} as written is not "
                             f"rational (the exact engine needs rational coefficients)")
    return value


def exact_transfer_function(ctrl: Controller) -> tuple[list[Fraction], list[Fraction]]:
    """The exact ``(num, den)`` of a transfer-function controller as written.

    Parameters
    ----------
    ctrl : Controller
        A linear controller (from a model file: its written decimals; from python-control:
        its doubles, which are then the model).

    Returns
    -------
    tuple of list of Fraction
        Highest power first.

    Raises
    ------
    StateFormError
        An entry is irrational.
    """
    num, den = ctrl.exact_tf()
    if any(c is None for c in (*num, *den)):
        raise StateFormError("a controller coefficient as written is not rational (the "
                             "exact engine needs rational coefficients)")
    return list(num), list(den)  # type: ignore[arg-type]


def _continuous(model: Model) -> tuple[list[Poly], list[str], int]:
    """Companion form of a continuous model: (f, state names, n); v = u."""
    n = max((o for t in model.terms for o in t.y_orders), default=0)
    if n < 1:
        raise StateFormError("the model has no derivative of the output")
    nv = n + 1
    lead = Fraction(0)
    rest: Poly = {}
    for t in model.terms:
        if any(o != 0 for o in t.u_orders):
            raise StateFormError(f"the term {t.monomial()} has a derivative of the input")
        if n in t.y_orders:
            if t.y_orders != (n,) or t.u_orders:
                raise StateFormError(f"the highest derivative enters nonlinearly ({t.monomial()})")
            lead += exact_coefficient(t)
            continue
        k = [0] * nv
        for o in t.y_orders:
            k[o] += 1
        k[n] = len(t.u_orders)
        key = tuple(k)
        rest[key] = rest.get(key, Fraction(0)) + exact_coefficient(t)
    if lead == 0:
        raise StateFormError("the coefficient of the highest derivative is zero")
    f: list[Poly] = [linear_poly([Fraction(int(j == i + 1)) for j in range(n)], nv)
                     for i in range(n - 1)]
    f.append(pscale({k: c for k, c in rest.items() if c}, -1 / lead))
    names = ["y" if i == 0 else f"D(y,{i})" for i in range(n)]
    return f, names, n


def _narx(model: Model) -> PolySystem:
    ny = max((o for t in model.terms for o in t.y_orders), default=0)
    nu = max((o for t in model.terms for o in t.u_orders), default=0)
    if ny < 1:
        raise StateFormError("the NARX model has no lagged output")
    n = ny + nu
    nv = n + 1
    lead = Fraction(0)
    rest: Poly = {}
    for t in model.terms:
        if 0 in t.y_orders:
            if t.y_orders != (0,) or t.u_orders:
                raise StateFormError(f"y[k] enters nonlinearly ({t.monomial()})")
            lead += exact_coefficient(t)
            continue
        k = [0] * nv
        for o in t.y_orders:
            k[o - 1] += 1
        for o in t.u_orders:
            k[n if o == 0 else ny + o - 1] += 1
        key = tuple(k)
        rest[key] = rest.get(key, Fraction(0)) + exact_coefficient(t)
    if lead == 0:
        raise StateFormError("the coefficient of y[k] is zero")
    y_new = pscale({k: c for k, c in rest.items() if c}, -1 / lead)

    def var(i: int) -> Poly:
        return {tuple(int(j == i) for j in range(nv)): Fraction(1)}

    f = [y_new] + [var(i - 1) for i in range(1, ny)]
    if nu:
        f += [var(n)] + [var(ny + i - 1) for i in range(1, nu)]
    names = [f"y[k-{i}]" for i in range(1, ny + 1)] + [f"u[k-{i}]" for i in range(1, nu + 1)]
    return PolySystem(tuple(f), True, tuple(names), "u[k]", tuple(range(ny, n)))


def _controller_realisation(num: list[Fraction], den: list[Fraction]
                            ) -> tuple[list[list[Fraction]], list[Fraction], list[Fraction],
                                       Fraction]:
    """(A, B, C, D) of N/D in controllable canonical form (highest power first in)."""
    while len(num) > 1 and num[0] == 0:
        num = num[1:]
    while len(den) > 1 and den[0] == 0:
        den = den[1:]
    if den[0] == 0:
        raise StateFormError("the controller's denominator is zero")
    m = len(den) - 1
    if len(num) - 1 > m:
        raise StateFormError("the controller is improper (numerator degree above the "
                             "denominator's): it has no state form")
    lead = den[0]
    d = [c / lead for c in den]
    nn = [Fraction(0)] * (m + 1 - len(num)) + [c / lead for c in num]
    dd = nn[0]
    b = [nn[i] - dd * d[i] for i in range(m + 1)]  # remainder, highest first
    A = [[Fraction(int(j == i + 1)) for j in range(m)] for i in range(m - 1)]
    if m:
        A.append([-d[m - j] for j in range(m)])
    B = [Fraction(0)] * (m - 1) + [Fraction(1)] if m else []
    C = [b[m - j] for j in range(m)]
    return A, B, C, dd


def state_form(model: ModelFile | Model) -> PolySystem:
    """The exact polynomial state form of a model (or of a model file's closed loop).

    Parameters
    ----------
    model : ModelFile or Model
        A continuous model, a NARX model, or a model file whose linear proper controller
        closes the loop u = C(r - y) (r, the reference, is then the bounded input).

    Returns
    -------
    PolySystem

    Raises
    ------
    StateFormError
        The model has no such state form (the message says why).
    """
    mf = resolve_model(model)
    plant = mf.plant
    if plant.is_discrete:
        if mf.controller is not None:
            raise StateFormError("a discrete plant with a controller")
        system = _narx(plant)
    else:
        f, names, n = _continuous(plant)
        system = PolySystem(tuple(f), False, tuple(names))
        if mf.controller is not None:
            system = _close(system, mf)
    if system.n > MAX_STATES:
        raise StateFormError(f"{system.n} states, above the engine's limit MAX_STATES = "
                             f"{MAX_STATES}")
    return system


def _close(plant: PolySystem, mf: ModelFile) -> PolySystem:
    """Plant x' = f(x, u) with u = C(r + s y) (s = feedback sign): states (x, z), input r."""
    ctrl = mf.controller
    assert ctrl is not None
    if not ctrl.is_linear:
        raise StateFormError("a polynomial controller (only transfer functions are closed)")
    A, B, C, D = _controller_realisation(*exact_transfer_function(ctrl))
    n, m = plant.n, len(A)
    nv = n + m + 1
    sign = Fraction(ctrl.feedback)

    def var(i: int) -> Poly:
        return {tuple(int(j == i) for j in range(nv)): Fraction(1)}

    e = padd(var(n + m), pscale(var(0), sign))  # r + s*y
    u = padd(pscale(e, D), *(pscale(var(n + j), C[j]) for j in range(m)))
    subs = [var(i) for i in range(n)] + [u]
    f = [pcompose(p, subs, nv) for p in plant.f]
    for i in range(m):
        f.append(padd(*(pscale(var(n + j), A[i][j]) for j in range(m)), pscale(e, B[i])))
    names = plant.states + tuple(f"z{j + 1} (controller)" for j in range(m))
    return PolySystem(tuple(f), False, names, "r (reference; u = C(r - y))"
                      if ctrl.feedback == -1 else "r (reference; u = C(r + y))")
