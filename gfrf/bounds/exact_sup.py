"""Rigorous sups of |N/D| on the stability boundary, on the given float coefficients.

Every float coefficient is a dyadic rational, so N and D are exact polynomials
(:mod:`gfrf.bounds.exact` reads them and decides their stability).  This module
encloses, with no tolerance:

* pole-zero cancellation (the gcd of N and D in Q[s]), done exactly first;
* the sup over real w of |N(j w) / D(j w)|, enclosed in a ball: the stationary points
  are the positive real roots of P'Q - PQ' (P = |N(j w)|^2, Q = |D(j w)|^2 as
  polynomials in x = w^2), isolated rigorously by FLINT/Arb (python-flint), and
  |N/D| is evaluated on their enclosures in ball arithmetic, with outward rounding to
  floats.  The result is a proof that the sup lies in [lower, upper], whatever the
  clustering of the poles.

The discrete case |N(q) / D(q)| on |q| = 1 maps to the continuous one by the Cayley
map q = (1 + s) / (1 - s), s = j t, w T = 2 atan|t|; q = -1 is the limit t -> inf.

A cheaper float path (``method="float"``) makes the same exact decisions and fails
closed where double precision could be wrong.  Both sups are memoised
(:func:`clear_caches` forgets them); :class:`SupBeyond` answers many tail bounds
sup over |w| >= v from one root isolation.

Examples
--------
>>> s = sup_abs([1.0], [1.0, 0.05, 2.45])
>>> s.lower <= 1 / (0.05 * (2.45 - 0.05**2 / 4) ** 0.5) <= s.upper
True
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from typing import Any

import numpy as np

from gfrf.bounds.exact import (
    _PREC,
    _axis_part,
    _coeffs,
    _complex_mid,
    _down,
    _even_odd,
    _flint,
    _precision,
    _qpoly,
    _real_roots,
    _roots,
    _up,
    cayley,
    fractions,
)
from gfrf.errors import ArgumentError

__all__ = ["ExactSup", "SupBeyond", "sup_abs", "discrete_sup_abs", "sup_abs_beyond",
           "clear_caches"]

#: Working precision (bits) at which a sup enclosure stops doubling (from ``_PREC``).
_MAX_PREC = 8192
#: Target relative width of a sup enclosure.
_REL_WIDTH = 2.0 ** -60


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
    return _sup_x(_abs2_in_x(n), _abs2_in_x(d), x_min)


def _sup_x(p: Any, q: Any, x_min: Fraction = Fraction(0)) -> tuple[Any, Any, float]:
    """As :func:`_sup_squared` for the polynomials ``p`` and ``q`` in x themselves (fmpq_poly,
    deg p <= deg q, q > 0 on x >= x_min)."""
    flint = _flint()
    x_min = flint.fmpq(x_min.numerator, x_min.denominator)
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
    missed), the upper end is ``inf`` with the reason, never a wrong finite number.
    The lower end is then the value at an evaluated witness (:func:`_witness_lower`),
    never the failed root-finder's inf.
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
                            f"{_FLOAT_RTOL:g} relative", cancelled,
                            _witness_lower(num, den, [0.0, *roots.real]))
        candidates += [float(r.real) for r in roots
                       if abs(r.imag) <= 1e-6 * (1 + abs(r)) and r.real > 0]
    xs = np.array(candidates)
    gamma = 2.0 * (pf.size + qf.size + 2) * 2.0 ** -53
    pv, qv = np.polyval(pf, xs), np.polyval(qf, xs)
    p_err, q_err = gamma * np.polyval(np.abs(pf), xs), gamma * np.polyval(np.abs(qf), xs)
    if np.any(qv - q_err <= 0):
        return _refused("|D(j w)|^2 at a stationary point is below its rounding error",
                        cancelled, _witness_lower(num, den, candidates))
    values = pv / qv
    best = int(np.argmax(values))
    value, omega = math.sqrt(max(float(values[best]), 0.0)), math.sqrt(candidates[best])
    worst = (pv + p_err) / (qv - q_err)
    if np.any(worst > (1 + _FLOAT_RTOL) * max(float(values[best]), 0.0)):
        return _refused("rounding could change the sup by more than "
                        f"{_FLOAT_RTOL:g} relative", cancelled,
                        _witness_lower(num, den, candidates))
    if p.degree() == q.degree():
        limit = math.sqrt(float(p.coeffs()[-1] / q.coeffs()[-1]))
        if limit > value:
            value, omega = limit, math.inf
    return ExactSup(value, value, value, omega, cancelled=cancelled)


def _refused(why: str, cancelled: tuple[complex, ...],
             witness: tuple[float, float]) -> ExactSup:
    lower, omega = witness
    return ExactSup(lower, math.inf, math.inf, omega,
                    f"ill-conditioned in double precision ({why}); the interval level "
                    "(proof='interval') encloses it", cancelled)


def _witness_lower(num: Any, den: Any, xs: list[float]) -> tuple[float, float]:
    """(lower end, omega): the largest |N/D| found at an evaluated w >= 0.

    Start points: w = sqrt(x) for the candidates x and |Im p| for the float poles p of D
    (a lightly damped cluster peaks near them); the best is refined by a pattern search
    in w.  Each value is evaluated in ball arithmetic at the exact float w (its lower end
    rounded down), so it is a value of |N/D| the sup is at least: the lower end of a
    refused float sup comes from an evaluated point, never from the failed roots.
    """
    flint = _flint()
    with _precision(_PREC):
        pa, qa = _arb_poly(_abs2_in_x(num)), _arb_poly(_abs2_in_x(den))

        def value(w: float) -> float:
            if not (math.isfinite(w) and w >= 0.0):
                return 0.0
            xb = flint.arb(w) * flint.arb(w)  # w exactly, x = w^2 in a ball
            qx = qa(xb)
            return _down((pa(xb) / qx).sqrt()) if qx > 0 else 0.0

        poles = np.roots([float(c) for c in reversed(den.coeffs())]) if den.degree() > 0 else []
        starts = [math.sqrt(x) for x in xs if math.isfinite(x) and x >= 0.0]
        starts += [abs(float(p.imag)) for p in poles if np.isfinite(p)]
        best, omega = max(((value(w), w) for w in starts), default=(0.0, 0.0))
        step = 1e-2 * max(omega, 1e-3)
        while step > 1e-17 * max(omega, 1e-300):
            left, right = value(omega - step), value(omega + step)
            if max(left, right) > best:
                best, omega = max((left, omega - step), (right, omega + step))
            else:
                step *= 0.5
    return best, omega


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

    Parameters
    ----------
    num, den : sequence of float or numpy.ndarray
        N and D, highest power of s first.
    omega_min : float
        The lower end of the frequency range in rad/s, finite and >= 0.

    Returns
    -------
    ExactSup
        The enclosure.
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
        """Proven upper bound of sup over |w| >= v (rad/s, v finite and >= 0).

        Parameters
        ----------
        v : float
            The lower end of the frequency range in rad/s.

        Returns
        -------
        float
            The bound (``inf`` for an unbounded ratio).
        """
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


def discrete_sup_abs(num: Sequence[Any] | np.ndarray, den: Sequence[Any] | np.ndarray,
                     sample_time: float, method: str = "interval") -> ExactSup:
    """Proven enclosure of sup over w in [0, pi/T] of |N(q)/D(q)|, q = exp(-j w T).

    Parameters
    ----------
    num, den : array_like
        Coefficients of powers of q, lowest power first (as lags appear): floats (at
        their exact values) or Fractions.
    sample_time : float
        T in seconds (only converts the argmax to rad/s).
    method : {"interval", "float"}
        As in :func:`sup_abs`.

    Returns
    -------
    ExactSup
        ``omega`` in rad/s; ``cancelled`` lists common roots in q.
    """
    n_high, d_high = fractions(_reversed(num)), fractions(_reversed(den))
    res = _sup_discrete(tuple(n_high), tuple(d_high), _method(method))
    if math.isfinite(res.omega):
        return ExactSup(res.lower, res.upper, res.value, res.omega / sample_time, res.reason,
                        res.cancelled)
    return ExactSup(res.lower, res.upper, res.value, math.pi / sample_time, res.reason,
                    res.cancelled)


def _reversed(coefficients: Sequence[Any] | np.ndarray) -> list[Any]:
    """Coefficients in reverse order: Fractions and ints kept, anything else as floats."""
    if isinstance(coefficients, list | tuple):
        return list(reversed(coefficients))
    return list(reversed(np.atleast_1d(np.asarray(coefficients, dtype=float)).tolist()))


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
