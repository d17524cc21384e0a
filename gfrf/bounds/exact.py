"""Exact stability tests and pole reports on the given float coefficients.

Every float coefficient is a dyadic rational, so a model written with floats defines
exact polynomials.  This module decides on those exact polynomials, with no
tolerance:

* Hurwitz stability (all roots in Re s < 0) by the Routh array in rational arithmetic,
  Schur stability (all roots in |z| < 1) by the same test after the Cayley map
  z = (1 + s) / (1 - s), and, when a polynomial is not stable, whether some root lies
  strictly outside or all offending roots lie on the boundary (a real root of the gcd
  of the real and imaginary parts of A(j w), decided by exact root isolation).

It also holds the exact-polynomial and Arb (python-flint) helpers that the rigorous
sups of :mod:`gfrf.bounds.exact_sup` and the enclosures of :mod:`gfrf.bounds.enclosure`
build on: the exact fractions of float coefficients, rigorous root isolation, the
real and imaginary parts of p(j w), and outward rounding of Arb balls to floats.

Examples
--------
>>> hurwitz([1.0, 2e-6, 1.0])
True
>>> p = poles([1.0, 0.0, 1.0])
>>> p.stable, p.outside, p.boundary
(False, False, (-1j, 1j))
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError

__all__ = ["PoleReport", "hurwitz", "schur", "poles", "cayley", "fractions", "format_roots",
           "arb_lower", "arb_upper"]

#: Working precision (bits) of the first ball evaluation; the sups of
#: :mod:`gfrf.bounds.exact_sup` double it up to their ``_MAX_PREC``.
_PREC = 128


def _flint() -> Any:
    import flint

    return flint


@contextmanager
def _precision(bits: int) -> Iterator[None]:
    """Arb working precision ``bits`` inside the block (python-flint's global context)."""
    ctx = _flint().ctx
    saved = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = saved


def fractions(coefficients: Sequence[Any] | np.ndarray) -> list[Fraction]:
    """The exact rational values of finite coefficients, leading zeros dropped.

    Floats are taken at their exact (dyadic) values; Fractions and ints as they are,
    so exactly formed products (e.g. a closed-loop polynomial) stay exact.

    Parameters
    ----------
    coefficients : sequence or numpy.ndarray
        Coefficients, highest power first: floats, ints or Fractions.

    Returns
    -------
    list of Fraction
        The exact values, at least one (``[0]`` for the zero polynomial).
    """
    if isinstance(coefficients, list | tuple) and any(
            isinstance(c, Fraction | int) and not isinstance(c, bool) for c in coefficients):
        items: list[Any] = [c if isinstance(c, Fraction | int) else float(c)
                            for c in coefficients]
    else:
        items = np.atleast_1d(np.asarray(coefficients, dtype=float)).tolist()
    out = []
    for c in items:
        if isinstance(c, float) and not math.isfinite(c):
            raise ArgumentError(f"polynomial coefficient {c!r} is not finite")
        out.append(Fraction(c))
    while len(out) > 1 and out[0] == 0:
        out.pop(0)
    return out or [Fraction(0)]


def _qpoly(highest_first: Sequence[Fraction]) -> Any:
    """fmpq_poly (lowest power first) of a highest-first list of Fractions."""
    flint = _flint()
    return flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator)
                            for c in reversed(highest_first)])


def _coeffs(p: Any) -> list[Fraction]:
    """Lowest-first Fractions of an fmpq_poly."""
    return [Fraction(int(c.p), int(c.q)) for c in p.coeffs()]


# -- stability ------------------------------------------------------------------------
def _routh(highest_first: list[Fraction]) -> bool:
    """Routh's test: every entry of the first column of the Routh array is positive."""
    a = highest_first if highest_first[0] > 0 else [-c for c in highest_first]
    n = len(a) - 1
    if n == 0:
        return True
    r0, r1 = a[0::2], a[1::2]
    for _ in range(n):
        if not r1 or r1[0] <= 0:
            return False
        width = max(len(r0), len(r1))
        r0 = r0 + [Fraction(0)] * (width + 1 - len(r0))
        r1p = r1 + [Fraction(0)] * (width + 1 - len(r1))
        ratio = r0[0] / r1[0]
        r2 = [r0[i + 1] - ratio * r1p[i + 1] for i in range(width)]
        while r2 and r2[-1] == 0:
            r2.pop()
        r0, r1 = r1, r2
    return True


def hurwitz(coefficients: Sequence[float] | np.ndarray) -> bool:
    """Whether the polynomial (highest power first) has all roots in Re s < 0, exactly.

    Routh's criterion in rational arithmetic on the exact values of the floats.

    Parameters
    ----------
    coefficients : sequence of float or numpy.ndarray
        The polynomial in s, highest power first, not all zero.

    Returns
    -------
    bool
        True when every root has Re s < 0.
    """
    a = fractions(coefficients)
    if a[0] == 0:
        raise ArgumentError("the polynomial is zero")
    return _routh(a)


def cayley(highest_first: Sequence[Fraction], degree: int) -> list[Fraction]:
    """sum p_k (1 + s)^k (1 - s)^(degree - k) for p(z) = sum p_k z^k (highest first in, out).

    Maps |z| < 1 to Re s < 0 and |z| = 1 to the imaginary axis (z = -1 to s = inf).

    Parameters
    ----------
    highest_first : sequence of Fraction
        p, highest power of z first.
    degree : int
        The degree used for the map, at least that of p.

    Returns
    -------
    list of Fraction
        The mapped polynomial in s, highest power first.
    """
    flint = _flint()
    low = list(reversed(highest_first))
    plus, minus = flint.fmpq_poly([1, 1]), flint.fmpq_poly([1, -1])
    total = flint.fmpq_poly([])
    for k, c in enumerate(low):
        if c:
            total += flint.fmpq(c.numerator, c.denominator) * plus ** k * minus ** (degree - k)
    coeffs = list(reversed(_coeffs(total)))
    return coeffs or [Fraction(0)]


def schur(coefficients: Sequence[float] | np.ndarray) -> bool:
    """Whether the polynomial in z (highest power first) has all roots in |z| < 1, exactly.

    Parameters
    ----------
    coefficients : sequence of float or numpy.ndarray
        The polynomial in z, highest power first, not all zero.

    Returns
    -------
    bool
        True when every root has |z| < 1.
    """
    a = fractions(coefficients)
    if a[0] == 0:
        raise ArgumentError("the polynomial is zero")
    mapped = cayley(a, len(a) - 1)
    if len(mapped) < len(a):  # degree drop: a root at z = -1
        return False
    return _routh(mapped)


@dataclass(frozen=True)
class PoleReport:
    """Exact location of the roots of A relative to the stability boundary.

    Attributes
    ----------
    stable : bool
        Every root strictly inside (Re s < 0, or |z| < 1), decided exactly.
    outside : bool
        Some root strictly outside (Re s > 0, or |z| > 1), decided exactly.
    boundary : tuple of complex
        Roots exactly on the boundary (approximate values, for display).
    roots : numpy.ndarray
        All roots with multiplicity (midpoints of rigorous enclosures), for display.
    """

    stable: bool
    outside: bool
    boundary: tuple[complex, ...] = field(default=())
    roots: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=complex))


def _roots(p: Any) -> list[tuple[Any, int]]:
    """Rigorously isolated complex roots (acb, multiplicity) of a nonzero fmpq_poly."""
    if p.degree() < 1:
        return []
    return p.complex_roots()


def _real_roots(p: Any) -> list[tuple[Any, int]]:
    """The real roots of p (Arb returns them with an exactly zero imaginary part)."""
    return [(r.real, m) for r, m in _roots(p) if r.imag.is_zero()]


def _even_odd(p: Any) -> tuple[Any, Any]:
    """(E, O) with p(j w) = E(w) + j O(w), real polynomials in w."""
    flint = _flint()
    e, o = [], []
    for k, c in enumerate(p.coeffs()):
        sign = -1 if k % 4 >= 2 else 1
        (e if k % 2 == 0 else o).append(sign * c)
        (o if k % 2 == 0 else e).append(0)
    return flint.fmpq_poly(e), flint.fmpq_poly(o)


def _axis_part(p: Any) -> Any:
    """gcd(E, O) in Q[w]: its real roots w are the roots j w of p on the imaginary axis."""
    e, o = _even_odd(p)
    if o.degree() < 0:
        return e
    if e.degree() < 0:
        return o
    return e.gcd(o)


def _complex_mid(r: Any) -> complex:
    return complex(float(r.real.mid()), float(r.imag.mid()))


def _report(p: Any) -> PoleReport:
    """PoleReport of a continuous-time polynomial p (fmpq_poly) with no root at infinity."""
    flint = _flint()
    roots = np.array([_complex_mid(r) for r, m in _roots(p) for _ in range(m)], dtype=complex)
    highest = list(reversed(_coeffs(p)))
    if _routh(highest):
        return PoleReport(True, False, (), roots)
    axis = [(w, m) for w, m in _real_roots(_axis_part(p))]
    if not axis:  # not Hurwitz and no root on the axis: a root has Re s > 0
        return PoleReport(False, True, (), roots)
    mirror = flint.fmpq_poly([c if k % 2 == 0 else -c for k, c in enumerate(p.coeffs())])
    g = p.gcd(mirror)  # axis roots (full multiplicity) and pairs r, -r
    rest = p // g
    outside = not _routh(list(reversed(_coeffs(rest))))
    if not outside:
        # g(j w) is a real polynomial (times a power of j): all roots on the axis iff
        # all its roots in w are real (with multiplicity)
        e, o = _even_odd(g)
        gw = e if e.degree() >= 0 else o
        real_count = sum(m for _, m in _real_roots(gw))
        outside = real_count < g.degree()
    boundary = tuple(complex(0.0, float(w.mid())) for w, m in axis for _ in range(m))
    return PoleReport(False, outside, boundary, roots)


def poles(coefficients: Sequence[Any] | np.ndarray, discrete: bool = False) -> PoleReport:
    """Exact location of the roots of a polynomial (highest power first).

    Parameters
    ----------
    coefficients : array_like
        Continuous: A(s), highest power of s first.  Discrete: z^L A(1/z), highest
        power of z first.  Floats (at their exact values) or Fractions.
    discrete : bool
        Boundary |z| = 1 instead of Re s = 0.

    Returns
    -------
    PoleReport
    """
    a = fractions(coefficients)
    if a[0] == 0:
        raise ArgumentError("the polynomial is zero")
    p = _qpoly(a)
    if not discrete:
        return _report(p)
    roots = np.array([_complex_mid(r) for r, m in _roots(p) for _ in range(m)], dtype=complex)
    n = len(a) - 1
    mapped = cayley(a, n)
    at_minus_one = n - (len(mapped) - 1)
    rep = _report(_qpoly(mapped))
    boundary = [complex(-1.0, 0.0)] * at_minus_one
    for s in rep.boundary:  # s = j t  ->  z = (1 + j t) / (1 - j t)
        boundary.append(complex((1 + s) / (1 - s)))
    stable = rep.stable and at_minus_one == 0
    return PoleReport(stable, rep.outside, tuple(boundary), roots)




# -- Arb balls to floats, roots as text -----------------------------------------------
def arb_lower(x: Any) -> float:
    """The largest float <= every point of the Arb ball ``x`` (-inf if unbounded).

    Parameters
    ----------
    x : flint.arb
        The ball.

    Returns
    -------
    float
        The lower end, rounded down.
    """
    return _down(x)


def arb_upper(x: Any) -> float:
    """The smallest float >= every point of the Arb ball ``x`` (inf if unbounded).

    Parameters
    ----------
    x : flint.arb
        The ball.

    Returns
    -------
    float
        The upper end, rounded up.
    """
    return _up(x)


def format_roots(roots: Sequence[complex], name: str = "s") -> str:
    """Roots as text, conjugate pairs merged: ``s = 0, s = -0.5 +- 2j``.

    Parameters
    ----------
    roots : sequence of complex
        The roots.
    name : str, optional
        The variable's name.

    Returns
    -------
    str
        Comma-separated ``name = value`` items.
    """
    parts = []
    for r in roots:
        if r.imag < 0 and any(abs(q - r.conjugate()) <= 1e-12 * (1 + abs(r)) for q in roots):
            continue
        text = f"{r.real:.6g}" if r.imag == 0 else (
            f"{r.real:.6g} +- {abs(r.imag):.6g}j" if r.imag > 0 and r.real != 0 else
            f"+-{abs(r.imag):.6g}j" if r.real == 0 else f"{r.real:.6g} - {abs(r.imag):.6g}j")
        parts.append(f"{name} = {text}")
    return ", ".join(parts)


def _down(x: Any) -> float:
    """Largest float <= the lower end of the arb ball x."""
    return _to_float(x.lower(), -1)


def _up(x: Any) -> float:
    """Smallest float >= the upper end of the arb ball x."""
    return _to_float(x.upper(), +1)


def _to_float(exact: Any, direction: int) -> float:
    if not exact.is_finite():
        return math.inf if direction > 0 else -math.inf
    man, exp = exact.mid().man_exp()
    value = Fraction(int(man)) * (Fraction(2) ** int(exp))
    try:
        f = float(value)
    except OverflowError:  # beyond the float range: round outward, or to the largest float
        big = sys.float_info.max
        if value > 0:
            return math.inf if direction > 0 else big
        return -big if direction > 0 else -math.inf
    if direction > 0 and Fraction(f) < value:
        f = math.nextafter(f, math.inf)
    if direction < 0 and Fraction(f) > value:
        f = math.nextafter(f, -math.inf)
    return f
