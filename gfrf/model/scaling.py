"""Normalisation of a model before any numerics: results invariant under scaling.

Multiplying every term of ``sum(terms) = 0`` by a constant changes no GFRF (each
H_n = -P_n / A is a ratio in which both sides scale alike), so every number gfrf
computes must be invariant under it.  Floats are not: the coefficients of
|A(j w)|^2 underflow at 1e-90 and overflow at 1e155.  :func:`normalized` divides every
coefficient by the power of two nearest below the leading coefficient of A (the
highest derivative of y, or for a NARX model its lowest lag), so A's leading
coefficient lies in [1, 2).  A power of two is exact in binary floating point: the
normalised model evaluates to exactly the same H_n (bitwise, away from overflow), a
model already normalised is returned unchanged, and a scaled copy of a model gives
the same coefficients up to the rounding of the scaled decimals.

The kernels (:func:`gfrf.kernels.recursion.generator`) and the majorant
(:func:`gfrf.bounds.majorant.majorant`, :func:`gfrf.bounds.majorant.linear_polynomials`) build their
data from the normalised model; nothing else needs to.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> m = parse_model("1e-90*D(y,2) + 1e-90*y + 1e-90*y**3 = 1e-90*u")
>>> scale_of(m) == 2.0 ** -299
True
>>> normalized(m).linear_output == {0: 1e-90 * 2.0 ** 299, 2: 1e-90 * 2.0 ** 299}
True
"""

from __future__ import annotations

import dataclasses
import math
from fractions import Fraction
from functools import lru_cache

from gfrf.model.equation import Model, Term
from gfrf.model.exact import Written

__all__ = ["normalized", "scale_of", "amplitude_scaled"]


def scale_of(model: Model) -> float:
    """The power of two 2^e <= |leading coefficient of A| < 2^(e+1) (1 without A).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    float
        A power of two.
    """
    a = {k: c for k, c in model.linear_output.items() if c != 0.0}
    if not a:
        return 1.0
    lead = a[min(a)] if model.is_discrete else a[max(a)]
    _, exponent = math.frexp(abs(lead))
    return math.ldexp(1.0, exponent - 1)


def normalized(model: Model) -> Model:
    """``model`` with every coefficient divided by :func:`scale_of` (exactly).

    Parameters
    ----------
    model : Model

    Returns
    -------
    Model
        The same object when the scale is 1.
    """
    # memoised per model and its written values (terms compare by their doubles only)
    return _normalized(model, tuple(t.written for t in model.terms))


@lru_cache(maxsize=256)
def _normalized(model: Model, written: tuple[Written | None, ...]) -> Model:
    scale = scale_of(model)
    if scale == 1.0:
        return model
    factor = 1 / Fraction(scale)
    terms = tuple(_rescaled(t, t.coefficient / scale, factor) for t in model.terms)
    physical = model.physical
    if physical is not None:
        import sympy as sp

        physical = physical * sp.Rational(Fraction(1.0 / scale))
    return dataclasses.replace(model, terms=terms, physical=physical)


def amplitude_scaled(model: Model, shift: int) -> Model | None:
    """``model`` in the amplitude units y = 2^shift Y, u = 2^shift U (exactly).

    A term of degree d = p + q gets the coefficient c 2^(shift (d - 1)) (the equation
    divided by 2^shift), so the linear part and H1 are unchanged, H_n(Y) = 2^(shift (n - 1))
    H_n(y), and every radius in U is the radius in u divided by 2^shift.  None when some
    coefficient would leave the exact float range (overflow or subnormal).

    Parameters
    ----------
    model : Model
    shift : int

    Returns
    -------
    Model or None
        The same object for ``shift`` 0.
    """
    if shift == 0:
        return model
    terms = []
    for t in model.terms:
        c = math.ldexp(t.coefficient, shift * (t.degree - 1))
        if t.coefficient != 0.0 and (not math.isfinite(c) or abs(c) < 2.0 ** -1000
                                     or math.ldexp(c, -shift * (t.degree - 1)) != t.coefficient):
            return None
        terms.append(_rescaled(t, c, Fraction(2) ** (shift * (t.degree - 1))))
    return dataclasses.replace(model, terms=tuple(terms), physical=None)


def _rescaled(term: Term, coefficient: float, factor: Fraction) -> Term:
    """``term`` with the new double ``coefficient`` = its double times ``factor`` (a power
    of two, exact) and its written exact value scaled alike."""
    written = term.written
    if written is None or written.of != term.coefficient:
        return dataclasses.replace(term, coefficient=coefficient, written=None)
    value = None if written.value is None else written.value * factor
    return dataclasses.replace(term, coefficient=coefficient,
                               written=Written(coefficient, value))
