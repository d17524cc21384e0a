"""A second stability certificate: an energy function, for every bounded input.

Theorem 1 proves that the norm series converges for inputs of Theorem 1's class (sums of
tones, amplitude = the L1 norm of the spectrum) below r*.  For a damped oscillator with
a hardening restoring force,

    a2 y'' + c y' + g(y) + b u = 0,   c / a2 > 0,   g'(0) / a2 > 0,   g / a2 a polynomial
    of odd degree d >= 3 with a positive leading coefficient,

a Lyapunov function with a cross term proves much more: every solution is bounded for
*every* bounded input, of any size (bounded-input bounded-state for L-infinity inputs).
With y'' = -k y' - f(y) + w (k = c/a2, f = g/a2, w = -b u/a2, |w| <= W), take

    V = y'^2/2 + F(y) + eps*y*y',  F(y) = int_0^y f,  eps = k/2.

Then dV/dt = -(k - eps) y'^2 - eps*k*y*y' - eps*y*f(y) + (y' + eps*y) w.  With
alpha = k/4 (so k - eps - alpha = k/4 > 0), completing the square in y' gives
dV/dt + alpha |x|^2 <= P(y) + sqrt(1 + eps^2) W |x|, where
P(y) = eps^2 k^2 y^2 / (4 (k - eps - alpha)) + alpha y^2 - eps*y*f(y) is a polynomial of
even degree d + 1 >= 4 with the negative leading coefficient -eps*lead(f): bounded
above, by M say.  So dV/dt < 0 wherever |x| > R(W) (finite), and V >= gamma |x|^2 - C
(the same completion: F has even degree d + 1 with a positive leading coefficient), so
V, hence the state, stays bounded along every solution.  The certificate's hypotheses
are signs and parities of the model's coefficients, checked exactly (the sign of a
quotient of doubles is exact): its proof level is ``"exact"``.

Its input class (every bounded input) contains Theorem 1's class of every size (a sum of
tones with sum of amplitudes r has sup |u| <= r), so it dominates Theorem 1 wherever it
applies: radius infinity.  It says nothing about the Volterra series itself (which may
diverge beyond the static branch point, :mod:`gfrf.stability.static`): it is a statement
about the solutions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from gfrf._results import Result
from gfrf.model.equation import Model

__all__ = ["Certificate", "energy_certificate", "ENERGY_METHOD", "LINF_CLASS"]

#: The method name of the energy certificate.
ENERGY_METHOD = "energy function V = E + eps*y*y' (hardening, damped)"
#: The input class of the energy certificate.
LINF_CLASS = ("every bounded input u(t) (L-infinity, any size), from any initial state; "
              "contains Theorem 1's class (sums of tones, sum of amplitudes <= r) for every r")


@dataclass(frozen=True, kw_only=True)
class Certificate(Result):
    """One proven lower side: stability for every input of ``input_class`` below ``radius``.

    Attributes
    ----------
    method : str
        What proves it.
    radius : float
        Amplitude below which stability is proven (``inf``: every amplitude).
    proof : str
        ``"exact"`` (exact arithmetic), ``"interval"`` (ball arithmetic), ``"float"``
        (certified in double precision) or ``"none"``.
    input_class : str
        The inputs, and the norm the radius is measured in.
    detail : str
        The certificate itself, in words and formulas.
    property : str
        What is proven for those inputs (bounded; returns to the equilibrium; ...).
    """

    _order = ("method", "radius", "proof", "input_class", "property")

    method: str
    radius: float
    proof: str
    input_class: str
    detail: str = ""
    property: str = ""

    def _computed(self) -> dict[str, Any]:
        return {"radius": float(self.radius)}


def _structure(model: Model) -> tuple[Fraction, Fraction, dict[int, Fraction], Fraction] | str:
    """(a2, c, {power: coefficient of y**power}, b) of a2 y'' + c y' + g(y) + b u, or why not."""
    if model.is_discrete:
        return "a discrete-time (NARX) model"
    a2 = c = b = Fraction(0)
    g: dict[int, Fraction] = {}
    for term in model.terms:
        q = term.exact  # the exact value as written (0.2 is 1/5)
        if q is None:
            return f"the coefficient of {term.monomial()} as written is not rational"
        ys, us = term.y_orders, term.u_orders
        if not us and ys == (2,):
            a2 += q
        elif not us and ys == (1,):
            c += q
        elif not us and ys and all(o == 0 for o in ys):
            g[len(ys)] = g.get(len(ys), Fraction(0)) + q
        elif not ys and us == (0,):
            b += q
        else:
            return f"the term {term.monomial()} is outside a2*y'' + c*y' + g(y) + b*u"
    if a2 == 0:
        return "no second derivative term"
    return a2, c, g, b


def energy_certificate(model: Model) -> Certificate | None:
    """The energy certificate of a damped hardening oscillator, or None if it does not apply.

    Parameters
    ----------
    model : Model
        A continuous polynomial model.

    Returns
    -------
    Certificate or None
        Radius ``inf``, proof ``"exact"``, when the model is ``a2 y'' + c y' + g(y) + b u
        = 0`` with c/a2 > 0, g'(0)/a2 > 0 (a stable linear part) and g/a2 of odd degree
        >= 3 with a positive leading coefficient (see the module docstring for the
        proof); None otherwise.

    Examples
    --------
    >>> from gfrf.model.equation import parse_model
    >>> energy_certificate(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")).radius
    inf
    >>> energy_certificate(parse_model("D(y,2) + 0.2*D(y) + y - 0.5*y**3 = u")) is None
    True
    """
    found = _structure(model)
    if isinstance(found, str):
        return None
    a2, c, g, b = found
    g = {p: q for p, q in g.items() if q != 0}
    if not g or b == 0:
        return None
    k = c / a2
    d = max(g)
    lead = g[d] / a2
    # k > 0 and f'(0) > 0: the linear part is asymptotically stable (H1 is stable), so
    # "bounded for every bounded input" is stability, not only boundedness
    if not (k > 0 and g.get(1, Fraction(0)) / a2 > 0 and d >= 3 and d % 2 == 1 and lead > 0):
        return None
    eps, alpha = k / 2, k / 4
    assert k - eps - alpha > 0 and eps > 0 and alpha > 0
    # P(y) = (eps^2 k^2 / (4 (k - eps - alpha)) + alpha) y^2 - eps y f(y): its top
    # coefficient (degree d + 1 >= 4) is -eps*lead < 0, so P is bounded above.
    top = -eps * lead
    assert top < 0
    f_text = " + ".join(f"{float(q / a2):.12g}*y**{p}" for p, q in sorted(g.items()))
    detail = (f"y'' = -k y' - f(y) + w with k = c/a2 = {float(k):.12g} > 0, f(y) = {f_text} "
              f"(odd degree {d}, leading coefficient {float(lead):.12g} > 0); "
              f"V = y'^2/2 + F(y) + eps*y*y' with eps = k/2 = {float(eps):.12g}; "
              f"dV/dt + alpha*|x|^2 <= P(y) + sqrt(1 + eps^2)*|w|*|x| with alpha = k/4, "
              f"P of degree {d + 1} with leading coefficient {float(top):.6g} < 0 (bounded "
              "above), and V >= gamma*|x|^2 - C: every solution under a bounded input is "
              "bounded (signs checked in exact rational arithmetic)")
    return Certificate(method=ENERGY_METHOD, radius=math.inf, proof="exact",
                       input_class=LINF_CLASS, detail=detail,
                       property="bounded: every solution under every bounded input stays bounded "
                       "(from any initial state); not: returns to the equilibrium")
