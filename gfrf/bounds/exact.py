"""Exact stability tests and rigorous sups of |N/D| on the given float coefficients.

Every float coefficient is a dyadic rational, so a model written with floats defines
exact polynomials.  This module decides on those exact polynomials, with no
tolerance:

* Hurwitz stability (all roots in Re s < 0) by the Routh array in rational arithmetic,
  Schur stability (all roots in |z| < 1) by the same test after the Cayley map
  z = (1 + s) / (1 - s), and, when a polynomial is not stable, whether some root lies
  strictly outside or all offending roots lie on the boundary (a real root of the gcd
  of the real and imaginary parts of A(j w), decided by exact root isolation);
* pole-zero cancellation (the gcd of N and D in Q[s]);
* the sup over real w of |N(j w) / D(j w)|, enclosed in a ball: the stationary points
  are the positive real roots of P'Q - PQ' (P = |N(j w)|^2, Q = |D(j w)|^2 as
  polynomials in x = w^2), isolated rigorously by FLINT/Arb (python-flint), and
  |N/D| is evaluated on their enclosures in ball arithmetic, with outward rounding to
  floats.  The result is a proof that the sup lies in [lower, upper], whatever the
  clustering of the poles.

The discrete case |N(q) / D(q)| on |q| = 1 maps to the continuous one by the Cayley
map q = (1 + s) / (1 - s), s = j t, w T = 2 atan|t|; q = -1 is the limit t -> inf.

Examples
--------
>>> hurwitz([1.0, 2e-6, 1.0])
True
>>> s = sup_abs([1.0], [1.0, 0.05, 2.45])
>>> s.lower <= 1 / (0.05 * (2.45 - 0.05**2 / 4) ** 0.5) <= s.upper
True
"""

from __future__ import annotations

import functools
import math
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError

__all__ = ["ExactSup", "PoleReport", "SupBeyond", "hurwitz", "schur", "poles", "sup_abs",
           "discrete_sup_abs", "sup_abs_beyond", "cayley", "format_roots", "arb_lower",
           "arb_upper", "clear_caches"]

#: Working precision (bits) of the first ball evaluation; doubled up to _MAX_PREC.
_PREC = 128
_MAX_PREC = 8192
#: Target relative width of a sup enclosure.
_REL_WIDTH = 2.0 ** -60


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
    """
    a = fractions(coefficients)
    if a[0] == 0:
        raise ArgumentError("the polynomial is zero")
    return _routh(a)


def cayley(highest_first: Sequence[Fraction], degree: int) -> list[Fraction]:
    """sum p_k (1 + s)^k (1 - s)^(degree - k) for p(z) = sum p_k z^k (highest first in, out).

    Maps |z| < 1 to Re s < 0 and |z| = 1 to the imaginary axis (z = -1 to s = inf).
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
    """Whether the polynomial in z (highest power first) has all roots in |z| < 1, exactly."""
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


def poles(coefficients: Sequence[float] | np.ndarray, discrete: bool = False) -> PoleReport:
    """Exact location of the roots of a polynomial (highest power first).

    Parameters
    ----------
    coefficients : array_like
        Continuous: A(s), highest power of s first.  Discrete: z^L A(1/z), highest
        power of z first.
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


# -- rigorous sups ----------------------------------------------------------------------
@dataclass(frozen=True)
class ExactSup:
    """Rigorous enclosure of sup over real w of |N(j w) / D(j w)| (or |N(q)/D(q)|, |q| = 1).

    Attributes
    ----------
    lower, upper : float
        Proven bounds, lower <= sup <= upper (outward-rounded floats; inf if unbounded).
    value : float
        Best float estimate (midpoint of the enclosure of the maximum).
    omega : float
        Where it is attained (rad/s; inf for a limit at infinity, the pole's frequency
        for a pole on the boundary).
    reason : str
        Why the sup is infinite, or empty.
    cancelled : tuple of complex
        Common roots of N and D removed exactly before the sup (approximate values).
    """

    lower: float
    upper: float
    value: float
    omega: float
    reason: str = ""
    cancelled: tuple[complex, ...] = field(default=())


def clear_caches() -> None:
    """Forget the memoised sups (for timing a cold computation)."""
    _sup_continuous.cache_clear()
    _sup_discrete.cache_clear()


def arb_lower(x: Any) -> float:
    """The largest float <= every point of the Arb ball ``x`` (-inf if unbounded)."""
    return _down(x)


def arb_upper(x: Any) -> float:
    """The smallest float >= every point of the Arb ball ``x`` (inf if unbounded)."""
    return _up(x)


def format_roots(roots: Sequence[complex], name: str = "s") -> str:
    """Roots as text, conjugate pairs merged: ``s = 0, s = -0.5 +- 2j``."""
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


def _abs2_in_x(p: Any) -> Any:
    """|p(j w)|^2 as a polynomial in x = w^2."""
    flint = _flint()
    e, o = _even_odd(p)
    sq = e * e + o * o
    return flint.fmpq_poly(sq.coeffs()[0::2])


def _arb_poly(p: Any) -> Any:
    flint = _flint()
    return flint.arb_poly([flint.arb(c) for c in p.coeffs()])


def _sup_squared(n: Any, d: Any, x_min: Fraction = Fraction(0)) -> tuple[Any, Any, float]:
    """Enclosure of sup over x = w^2 >= x_min of P(x)/Q(x), Q > 0 there (proven by caller).

    The candidates are x = x_min, the limit x -> inf and the real roots x > x_min of
    P'Q - PQ', each evaluated in ball arithmetic on its rigorous enclosure.  Returns
    exact arb numbers (lower, upper) with lower <= sup <= upper, and the x of the best
    candidate (inf for the limit).  The precision doubles until the enclosure is
    narrower than 2^-60 relative.
    """
    flint = _flint()
    x_min = flint.fmpq(x_min.numerator, x_min.denominator)
    p, q = _abs2_in_x(n), _abs2_in_x(d)
    s = p.derivative() * q - p * q.derivative()
    if s.degree() >= 0:
        at_min = flint.fmpq_poly([-x_min, 1])
        while s(x_min) == 0:  # x = x_min is a candidate anyway
            s = s // at_min
    prec = _PREC
    while True:
        with _precision(prec):
            stationary = [] if s.degree() < 0 else [x for x, _ in _real_roots(s)]
            values = [(flint.arb(p(x_min) / q(x_min)), float(x_min))]
            if p.degree() == q.degree():
                values.append((flint.arb(p.coeffs()[-1] / q.coeffs()[-1]),
                               math.inf))
            pa, qa = _arb_poly(p), _arb_poly(q)
            ok = True
            for x in stationary:
                if x < x_min:
                    continue
                qx = qa(x)
                if not (x > x_min and qx > 0):  # enclosure too wide to decide: refine
                    ok = False
                    break
                values.append((pa(x) / qx, float(x.mid())))
            if ok:
                lower = functools.reduce(lambda a, b: a.max(b), (v[0].lower() for v in values))
                upper = functools.reduce(lambda a, b: a.max(b), (v[0].upper() for v in values))
                best = max(values, key=lambda v: float(v[0].mid()))
                if upper - lower <= _REL_WIDTH * upper or prec >= _MAX_PREC:
                    return lower, upper, best[1]
        if prec >= _MAX_PREC:
            raise ArgumentError(f"could not enclose the sup of |N/D| at {_MAX_PREC} bits")
        prec *= 2


def _strip_common(num: Any, den: Any) -> tuple[Any, Any, tuple[complex, ...]]:
    g = num.gcd(den)
    if g.degree() < 1:
        return num, den, ()
    cancelled = tuple(_complex_mid(r) for r, m in _roots(g) for _ in range(m))
    return num // g, den // g, cancelled


def _finish(num: Any, den: Any, cancelled: tuple[complex, ...],
            x_min: Fraction = Fraction(0)) -> ExactSup:
    flint = _flint()
    if num.degree() < 0:
        return ExactSup(0.0, 0.0, 0.0, 0.0, cancelled=cancelled)
    lo2, hi2, x = _sup_squared(num, den, x_min)
    with _precision(_PREC):
        lo, hi = flint.arb(lo2).sqrt(), flint.arb(hi2).sqrt()
        mid = flint.arb(lo2).union(flint.arb(hi2)).sqrt()
    omega = math.inf if math.isinf(x) else math.sqrt(x)
    return ExactSup(_down(lo), _up(hi), float(mid.mid()), omega, cancelled=cancelled)


def sup_abs(num: Sequence[float] | np.ndarray, den: Sequence[float] | np.ndarray,
            method: str = "interval") -> ExactSup:
    """Proven enclosure of sup over real w of |N(j w)/D(j w)| (highest power first).

    Common roots of N and D are cancelled exactly first (reported in ``cancelled``);
    an improper reduced fraction or a root of the reduced D on the imaginary axis
    gives an infinite sup with its reason.

    Parameters
    ----------
    num, den : array_like
        Float coefficients in s, highest power first; their exact values are used.
    method : {"interval", "float"}
        ``"interval"``: the stationary points are isolated by Arb and |N/D| enclosed
        in balls (a proof).  ``"float"``: the same exact decisions (cancellation, poles
        on the axis), then the stationary points by ``numpy.roots`` and |N/D| in
        double precision: ``lower = upper = value``, no enclosure (a cluster of
        lightly damped poles can make it wrong; it is cheaper).

    Returns
    -------
    ExactSup
    """
    return _sup_continuous(tuple(fractions(num)), tuple(fractions(den)), _method(method))


def _method(method: str) -> str:
    if method not in ("interval", "float"):
        raise ArgumentError(f"method must be 'interval' or 'float', got {method!r}")
    return method


#: The float path refuses (inf, with a reason) when rounding could move its sup by more
#: than this relative amount, or when stationary points cluster closer than this.
_FLOAT_RTOL = 1e-8


def _float_finish(num: Any, den: Any, cancelled: tuple[complex, ...]) -> ExactSup:
    """The float path of :func:`_finish`: numpy roots of P'Q - PQ', double evaluation.

    It fails closed: where the a-priori Horner error bounds of P and Q at a candidate
    could change the sup by more than ``_FLOAT_RTOL`` relative, or the float
    stationary points cluster (their positions are then unreliable, and a peak can be
    missed), the result is ``inf`` with the reason, never a wrong finite number.
    """
    if num.degree() < 0:
        return ExactSup(0.0, 0.0, 0.0, 0.0, cancelled=cancelled)
    p, q = _abs2_in_x(num), _abs2_in_x(den)
    s = p.derivative() * q - p * q.derivative()
    pf = np.array([float(c) for c in reversed(p.coeffs())])
    qf = np.array([float(c) for c in reversed(q.coeffs())])
    candidates = [0.0]
    if s.degree() >= 1:
        roots = np.roots([float(c) for c in reversed(s.coeffs())])
        # only roots that may be stationary points at x = w^2 >= 0 matter (a double root
        # at x = -1, as for q^2 / (1 - q/2), is no peak)
        roots = roots[roots.real >= -_FLOAT_RTOL * (1 + np.abs(roots))]
        gaps = np.abs(roots[:, None] - roots[None, :])
        np.fill_diagonal(gaps, np.inf)
        if roots.size > 1 and np.any(gaps < _FLOAT_RTOL * (1 + np.abs(roots))[:, None]):
            return _refused("stationary points of |N/D|^2 cluster closer than "
                            f"{_FLOAT_RTOL:g} relative", cancelled)
        candidates += [float(r.real) for r in roots
                       if abs(r.imag) <= 1e-6 * (1 + abs(r)) and r.real > 0]
    xs = np.array(candidates)
    gamma = 2.0 * (pf.size + qf.size + 2) * 2.0 ** -53
    pv, qv = np.polyval(pf, xs), np.polyval(qf, xs)
    p_err, q_err = gamma * np.polyval(np.abs(pf), xs), gamma * np.polyval(np.abs(qf), xs)
    if np.any(qv - q_err <= 0):
        return _refused("|D(j w)|^2 at a stationary point is below its rounding error",
                        cancelled)
    values = pv / qv
    best = int(np.argmax(values))
    value, omega = math.sqrt(max(float(values[best]), 0.0)), math.sqrt(candidates[best])
    worst = (pv + p_err) / (qv - q_err)
    if np.any(worst > (1 + _FLOAT_RTOL) * max(float(values[best]), 0.0)):
        return _refused("rounding could change the sup by more than "
                        f"{_FLOAT_RTOL:g} relative", cancelled)
    if p.degree() == q.degree():
        limit = math.sqrt(float(p.coeffs()[-1] / q.coeffs()[-1]))
        if limit > value:
            value, omega = limit, math.inf
    return ExactSup(value, value, value, omega, cancelled=cancelled)


def _refused(why: str, cancelled: tuple[complex, ...]) -> ExactSup:
    return ExactSup(math.inf, math.inf, math.inf, math.nan,
                    f"ill-conditioned in double precision ({why}); the interval level "
                    "(proof='interval') encloses it", cancelled)


def _reduced(num: tuple[Fraction, ...], den: tuple[Fraction, ...]
             ) -> tuple[Any, Any, tuple[complex, ...]] | ExactSup:
    """(numerator, denominator, cancelled roots) in lowest terms, or the sup 0 of a zero
    numerator; ZeroDivisionError for a zero denominator."""
    if den[0] == 0:
        raise ZeroDivisionError("denominator polynomial is zero")
    n, d = _qpoly(num), _qpoly(den)
    if n.degree() < 0:
        return ExactSup(0.0, 0.0, 0.0, 0.0)
    return _strip_common(n, d)


@lru_cache(maxsize=1024)
def _sup_continuous(num: tuple[Fraction, ...], den: tuple[Fraction, ...],
                    method: str = "interval") -> ExactSup:
    reduced = _reduced(num, den)
    if isinstance(reduced, ExactSup):
        return reduced
    n, d, cancelled = reduced
    if n.degree() > d.degree():
        return ExactSup(math.inf, math.inf, math.inf, math.inf,
                        f"improper: numerator degree {n.degree()} > denominator degree "
                        f"{d.degree()}", cancelled)
    axis = _real_roots(_axis_part(d))
    if axis:
        w = abs(float(axis[-1][0].mid()))
        return ExactSup(math.inf, math.inf, math.inf, w,
                        f"pole on the imaginary axis at s = {w:.6g}j (exact test)", cancelled)
    if method == "float":
        return _float_finish(n, d, cancelled)
    return _finish(n, d, cancelled)


def sup_abs_beyond(num: Sequence[float] | np.ndarray, den: Sequence[float] | np.ndarray,
                   omega_min: float) -> ExactSup:
    """Proven enclosure of sup over |w| >= omega_min of |N(j w)/D(j w)| (highest first).

    The tail bound a branch-and-bound needs outside its box; same method and
    conventions as :func:`sup_abs` (omega_min >= 0 is used exactly).
    """
    if not (math.isfinite(omega_min) and omega_min >= 0):
        raise ArgumentError(f"omega_min must be finite and >= 0, got {omega_min!r}")
    res = _sup_continuous(tuple(fractions(num)), tuple(fractions(den)))
    if not math.isfinite(res.upper) or res.upper == 0.0:
        return res
    n, d = _qpoly(fractions(num)), _qpoly(fractions(den))
    n, d, cancelled = _strip_common(n, d)
    return _finish(n, d, cancelled, Fraction(omega_min) ** 2)


class SupBeyond:
    """Proven upper bounds of sup over |w| >= v of |N(j w)/D(j w)|, for many v.

    The stationary points (real roots of P'Q - PQ' in x = w^2) are isolated once, in
    exact arithmetic and Arb; each query evaluates |N/D|^2 in ball arithmetic at
    x = v^2 (exactly), on every root enclosure that reaches beyond v^2 and at the
    limit x -> inf, and returns the outward-rounded square root of the largest upper
    end.  A root enclosure straddling v^2 is kept (it can only raise the bound).
    Where a ball is too wide to bound the quotient, :func:`sup_abs_beyond` (adaptive
    precision) answers.  The bound is as sound as :func:`sup_abs_beyond` and clusters
    of poles cost nothing extra, unlike float roots of P'Q - PQ'.

    Parameters
    ----------
    num, den : array_like
        Float (or Fraction) coefficients in s, highest power first, used exactly.

    Examples
    --------
    >>> b = SupBeyond([1.0], [1.0, 0.05, 2.45])
    >>> b.upper(0.0) >= 1 / (0.05 * (2.45 - 0.05**2 / 4) ** 0.5) > b.upper(10.0)
    True
    """

    def __init__(self, num: Sequence[Any], den: Sequence[Any]) -> None:
        self._num, self._den = tuple(fractions(num)), tuple(fractions(den))
        self.full = _sup_continuous(self._num, self._den)
        self._roots: list[Any] = []
        if not math.isfinite(self.full.upper) or self.full.upper == 0.0:
            return
        flint = _flint()
        n, d, _ = _strip_common(_qpoly(self._num), _qpoly(self._den))
        self._p, self._q = _abs2_in_x(n), _abs2_in_x(d)
        s = self._p.derivative() * self._q - self._p * self._q.derivative()
        self._prec = _PREC
        while True:  # enclosures narrow enough that |N/D|^2 on them is tight
            with _precision(self._prec):
                self._roots = [] if s.degree() < 0 else [x for x, _ in _real_roots(s)]
                pa, qa = _arb_poly(self._p), _arb_poly(self._q)
                values = [pa(x) / qa(x) for x in self._roots]
                if self._prec >= _MAX_PREC or all(
                        v.is_finite() and v.upper() - v.lower() <= _REL_WIDTH * v.upper()
                        for v in values):
                    break
            self._prec *= 2
        self._limit = (self._p.coeffs()[-1] / self._q.coeffs()[-1]
                       if self._p.degree() == self._q.degree() else flint.fmpq(0))

    def upper(self, v: float) -> float:
        """Proven upper bound of sup over |w| >= v (rad/s, v finite and >= 0)."""
        if not (math.isfinite(v) and v >= 0):
            raise ArgumentError(f"v must be finite and >= 0, got {v!r}")
        if not math.isfinite(self.full.upper) or self.full.upper == 0.0:
            return self.full.upper
        flint = _flint()
        x_min = Fraction(v) ** 2
        x_q = flint.fmpq(x_min.numerator, x_min.denominator)
        with _precision(self._prec):
            best = flint.arb(max(self._p(x_q) / self._q(x_q), self._limit))
            pa, qa = _arb_poly(self._p), _arb_poly(self._q)
            for x in self._roots:
                if x.upper() >= x_q:
                    best = best.max(pa(x) / qa(x))
            if not best.is_finite():
                return sup_abs_beyond(self._num, self._den, v).upper
            return _up(flint.arb(best.upper()).sqrt())


def discrete_sup_abs(num: Sequence[float] | np.ndarray, den: Sequence[float] | np.ndarray,
                     sample_time: float, method: str = "interval") -> ExactSup:
    """Proven enclosure of sup over w in [0, pi/T] of |N(q)/D(q)|, q = exp(-j w T).

    Parameters
    ----------
    num, den : array_like
        Coefficients of powers of q, lowest power first (as lags appear).
    sample_time : float
        T in seconds (only converts the argmax to rad/s).
    method : {"interval", "float"}
        As in :func:`sup_abs`.

    Returns
    -------
    ExactSup
        ``omega`` in rad/s; ``cancelled`` lists common roots in q.
    """
    n_high = fractions(list(reversed(np.atleast_1d(np.asarray(num, dtype=float)).tolist())))
    d_high = fractions(list(reversed(np.atleast_1d(np.asarray(den, dtype=float)).tolist())))
    res = _sup_discrete(tuple(n_high), tuple(d_high), _method(method))
    if math.isfinite(res.omega):
        return ExactSup(res.lower, res.upper, res.value, res.omega / sample_time, res.reason,
                        res.cancelled)
    return ExactSup(res.lower, res.upper, res.value, math.pi / sample_time, res.reason,
                    res.cancelled)


@lru_cache(maxsize=1024)
def _sup_discrete(num: tuple[Fraction, ...], den: tuple[Fraction, ...],
                  method: str = "interval") -> ExactSup:
    """As :func:`discrete_sup_abs` with highest-power-of-q-first Fractions; omega in rad/sample
    (inf stands for w T = pi)."""
    reduced = _reduced(num, den)
    if isinstance(reduced, ExactSup):
        return reduced
    n, d, cancelled = reduced
    if d(-1) == 0:
        return ExactSup(math.inf, math.inf, math.inf, math.inf,
                        "pole on the unit circle at z = -1 (exact test)", cancelled)
    m = max(n.degree(), d.degree())
    nt = _qpoly(cayley(list(reversed(_coeffs(n))), m))
    dt = _qpoly(cayley(list(reversed(_coeffs(d))), m))
    axis = _real_roots(_axis_part(dt))
    if axis:
        t = float(axis[-1][0].mid())
        w = 2.0 * math.atan(abs(t))
        z = complex(math.cos(w), math.sin(w))
        return ExactSup(math.inf, math.inf, math.inf, w,
                        f"pole on the unit circle at z = {z:.6g} (exact test)", cancelled)
    res = _float_finish(nt, dt, ()) if method == "float" else _finish(nt, dt, ())
    w = math.inf if math.isinf(res.omega) else 2.0 * math.atan(res.omega)
    return ExactSup(res.lower, res.upper, res.value, w, res.reason, cancelled)
