"""An implicit (rational) state form: a loop whose highest derivative has a polynomial
coefficient, e.g. a plant under an improper polynomial controller.

With a polynomial controller C(s) = (c_q s^q + .. + c_0) / d_0 (improper: no states of its
own) the loop u = C(r - y) (feedback -1; u = C(r + y) for +1) gives the plant

    u = d - C y   (d = C r: the reference acts exactly as a plant-input signal d),

so with d as the bounded input the loop is the implicit ODE

    D(x) y^(m) + R(x, d) = 0,    x = (y, y', .., y^(m-1)),  m = max(plant order, q),

D and R exact rational polynomials.  Where D != 0 it is the rational vector field
x' = f(x, d) = (x_2, .., x_m, -R / D).  Multiplied by s D(x) (s = sign D(0)), positive
near the equilibrium, it is the polynomial field g(x, d) = (s D x_2, .., s D x_m, -s R):
the same trajectories in a rescaled time, on every set where s D > 0.  A set
{V <= c} invariant for g under every |d| <= U, on which s D >= delta > 0, is invariant
for the loop (on its boundary grad V . f = grad V . g / (s D) < 0).  The certificate
engine (:mod:`gfrf.stability.sos`) searches g; :mod:`gfrf.stability.implicit_sos` adds the
check that s D stays positive.

The same construction serves a model without a controller whose highest derivative
enters with a polynomial coefficient (d = u).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile
from gfrf.stability.polysys import (
    MAX_STATES,
    Poly,
    PolySystem,
    StateFormError,
    exact_coefficient,
    exact_transfer_function,
    padd,
    pmul,
    pscale,
)

__all__ = ["ImplicitLoop", "implicit_form", "D_INPUT", "SINGULAR_LEVEL"]

#: What the input d of a loop with an improper polynomial controller is.
D_INPUT = "d = C r (the reference through the controller, a plant-input signal)"
#: The loop's breakdown level: |D(x)| <= SINGULAR_LEVEL |D(0)|, where y^(m) = -R / D (and
#: the controller's output with it) is 1 / SINGULAR_LEVEL times its scale.  Below the
#: input that drives the state onto D = 0 itself, a bounded input only brings |D|
#: arbitrarily close to 0, so the two sides of the threshold speak of this level.
SINGULAR_LEVEL = Fraction(1, 10**6)


@dataclass(frozen=True)
class ImplicitLoop:
    """D(x) y^(m) + R(x, d) = 0 with exact rational polynomials in (x_1, .., x_m, d).

    Attributes
    ----------
    D : Poly
        The coefficient of the highest derivative y^(m) (no d in it).
    R : Poly
        Everything else.
    states : tuple of str
        The state names (``y``, ``D(y,1)``, ..).
    input_name : str
        The bounded input: ``u`` (no controller) or :data:`D_INPUT`.
    sign : int
        The sign of D(0) (nonzero): the rescaled field is ``sign * D * f``.
    loop : bool
        A controller closes the loop (then d = C r).
    """

    D: Poly
    R: Poly
    states: tuple[str, ...]
    input_name: str
    sign: int
    loop: bool

    @property
    def n(self) -> int:
        """Number of states m."""
        return len(self.states)

    def scaled(self) -> PolySystem:
        """The polynomial field g = sign * D * f (same trajectories where sign * D > 0)."""
        n = self.n
        nv = n + 1
        s = Fraction(self.sign)
        sD = pscale(self.D, s)
        f: list[Poly] = []
        for i in range(n - 1):
            nxt = {tuple(int(j == i + 1) for j in range(nv)): Fraction(1)}
            f.append(pmul(sD, nxt))
        f.append(pscale(self.R, -s))
        return PolySystem(tuple(f), False, self.states,
                          f"{self.input_name}; time rescaled by {'-' if s < 0 else ''}D(x)")

    def field(self, x: list[float], d: float) -> list[float]:
        """f(x, d) in floats (an estimate, for simulation).

        Parameters
        ----------
        x : list of float
            The state (y, y', ..., y^(m-1)).
        d : float
            The plant-input signal.

        Returns
        -------
        list of float
            dx/dt.
        """
        import numpy as np

        from gfrf.stability.polysys import peval

        pt = np.array([list(x) + [d]], dtype=float)
        Dv = float(peval(self.D, pt)[0])
        Rv = float(peval(self.R, pt)[0])
        return list(x[1:]) + [-Rv / Dv]


def _term_poly(coefficient: Fraction, y_orders: tuple[int, ...], u_count: int, u_poly: Poly,
               nv: int) -> Poly:
    k = [0] * nv
    for o in y_orders:
        k[o] += 1
    p: Poly = {tuple(k): coefficient}
    for _ in range(u_count):
        p = pmul(p, u_poly)
    return p


def implicit_form(model: ModelFile | Model) -> ImplicitLoop:
    """The implicit state form D(x) y^(m) + R(x, d) = 0 of a model or of its loop.

    Parameters
    ----------
    model : ModelFile or Model
        A continuous plant without input derivatives, alone (d = u) or closed by a
        transfer-function controller whose denominator is a constant (a polynomial
        controller, proper or not) with u = C(r - y) (or C(r + y) for feedback +1).

    Returns
    -------
    ImplicitLoop

    Raises
    ------
    StateFormError
        The model has no such form (the message says why): a discrete plant, a
        derivative of u, a controller with dynamics of its own, the highest derivative
        entering nonlinearly or with a coefficient that vanishes at the equilibrium or
        depends on the input, or more than ``MAX_STATES`` states.
    """
    mf = model if isinstance(model, ModelFile) else ModelFile(plant=model)
    plant = mf.plant
    if plant.is_discrete:
        raise StateFormError("a discrete plant has no implicit ODE form")
    ctrl = mf.controller
    gains: list[Fraction] = []
    fb = Fraction(-1)
    if ctrl is not None:
        if not ctrl.is_linear:
            raise StateFormError("a polynomial controller equation (only transfer functions)")
        num, den = exact_transfer_function(ctrl)
        while len(den) > 1 and den[0] == 0:
            den = den[1:]
        if len(den) != 1 or den[0] == 0:
            raise StateFormError("the controller has dynamics of its own (a denominator "
                                 "of degree >= 1): use the polynomial state form")
        num = [c / den[0] for c in num]
        gains = list(reversed(num))  # c_0, c_1, .., c_q
        fb = Fraction(ctrl.feedback)
    for t in plant.terms:
        if any(o != 0 for o in t.u_orders):
            raise StateFormError(f"the term {t.monomial()} has a derivative of the input")
    n_plant = max((o for t in plant.terms for o in t.y_orders), default=0)
    m = max(n_plant, len(gains) - 1)
    if m < 1:
        raise StateFormError("the loop has no derivative of the output")
    if m > MAX_STATES:
        raise StateFormError(f"{m} states, above the engine's limit MAX_STATES = {MAX_STATES}")
    nv = m + 2  # y, y', .., y^(m), d
    d_var: Poly = {tuple(int(j == m + 1) for j in range(nv)): Fraction(1)}
    # u = d + fb * sum_j c_j y^(j)   (u = C(r + fb y), d = C r)
    u_poly = padd(d_var, *({tuple(int(i == j) for i in range(nv)): fb * c}
                           for j, c in enumerate(gains) if c))
    total = padd(*(_term_poly(exact_coefficient(t), t.y_orders, len(t.u_orders), u_poly, nv)
                   for t in plant.terms))
    top = m
    if any(k[top] > 1 for k in total):
        raise StateFormError(f"the highest derivative D(y,{m}) enters nonlinearly")
    D = {k[:top] + k[top + 1:]: c for k, c in total.items() if k[top] == 1}
    R = {k[:top] + k[top + 1:]: c for k, c in total.items() if k[top] == 0}
    if not D:
        raise StateFormError(f"the coefficient of D(y,{m}) is zero")
    if any(k[-1] for k in D):
        raise StateFormError(f"the coefficient of D(y,{m}) depends on the input")
    d0 = D.get((0,) * (m + 1), Fraction(0))
    if d0 == 0:
        raise StateFormError(f"the coefficient of D(y,{m}) vanishes at the equilibrium")
    if R.get((0,) * (m + 1), Fraction(0)) != 0:
        raise StateFormError("the origin is not an equilibrium at zero input")
    names = tuple("y" if i == 0 else f"D(y,{i})" for i in range(m))
    loop = ctrl is not None
    return ImplicitLoop(D=D, R=R, states=names, input_name=D_INPUT if loop else "u",
                        sign=1 if d0 > 0 else -1, loop=loop)
