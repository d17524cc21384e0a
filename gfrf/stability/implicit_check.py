"""Exact re-verification of an invariant polygon of a second-order implicit loop.

The loop (:mod:`gfrf.stability.implicit`) is D(y) y'' + R(y, y', d) = 0 with D of y
alone and R affine in the bounded input d.  With q = s D (s = sign D(0)) and the
polynomial field g = (q v, -s R) (v = y'), a certificate is a polygon P (vertices
exact rationals, clockwise) and a bound U.  It holds when, in rational arithmetic only:

1. P is simple: its vertices split at the leftmost and rightmost vertex into an upper
   chain of strictly increasing y and a lower chain of strictly decreasing y, each
   vertex strictly on its side of the other chain (an x-monotone polygon, clockwise);
2. the rest state (0, 0) is strictly inside P;
3. q(y) > level q(0) for every y in [y_min, y_max] of P (so the loop's y'' = -R / D is
   defined and locally Lipschitz on P, the field f = g / q has the direction of g, and
   |D| stays above the stated ``level`` of |D(0)|; level 0 when the file states none);
4. on every closed edge [a, b] with outward normal n = (-(b - a)_v, (b - a)_y):
   n . g(x, d) < 0 for every |d| <= U, i.e. A(t) + U |B(t)| < 0 on t in [0, 1] where
   n . g = A + d B along x = a + t (b - a): both A + U B and A - U B are negative,
   decided exactly by Bernstein coefficients with subdivision (counted).

Then every solution of the loop from rest under any input with sup|d| <= U stays in P
(Nagumo: the field points strictly into P on its boundary, also at the vertices), so
|y| <= max |y| over P < the nearest zero of D, and the loop is bounded.
"""

from __future__ import annotations

from fractions import Fraction
from math import comb
from typing import Any

from gfrf.stability._rational import read_rational
from gfrf.stability.implicit import ImplicitLoop

__all__ = ["FORMAT", "KIND", "check_region", "polygon_parts", "bound", "MAX_VERTICES",
           "MAX_SUBDIVISIONS"]

#: The ``format`` value of an implicit-loop certificate file.
FORMAT = "gfrf-implicit-region"
KIND = "polygon-2d"
#: Most vertices a certificate may have.
MAX_VERTICES = 20_000
#: Bernstein subdivisions one check may spend in total.
MAX_SUBDIVISIONS = 200_000
#: Longest text of one rational.
MAX_RATIONAL_CHARS = 200

TPoly = list[Fraction]  # coefficients in t, lowest first


def _q(text: Any) -> Fraction:
    """A rational from its text ``"p/q"`` (or an int), at most :data:`MAX_RATIONAL_CHARS`
    characters (:func:`gfrf.stability._rational.read_rational`)."""
    return read_rational(text, MAX_RATIONAL_CHARS)


def _tmul(a: TPoly, b: TPoly) -> TPoly:
    out = [Fraction(0)] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        if x:
            for j, y in enumerate(b):
                out[i + j] += x * y
    return out


def _tadd(a: TPoly, b: TPoly) -> TPoly:
    n = max(len(a), len(b))
    return [(a[i] if i < len(a) else 0) + (b[i] if i < len(b) else 0) for i in range(n)]  # type: ignore[misc]


def _on_line(p: dict[tuple[int, int], Fraction], y: TPoly, v: TPoly) -> TPoly:
    """p(y(t), v(t)) for a polynomial p in (y, v)."""
    out: TPoly = [Fraction(0)]
    ypow: dict[int, TPoly] = {0: [Fraction(1)]}
    vpow: dict[int, TPoly] = {0: [Fraction(1)]}
    for (i, j), c in p.items():
        for pw, base, e in ((ypow, y, i), (vpow, v, j)):
            k = max(pw)
            while k < e:
                pw[k + 1] = _tmul(pw[k], base)
                k += 1
        out = _tadd(out, [c * x for x in _tmul(ypow[i], vpow[j])])
    return out


class _Budget:
    def __init__(self) -> None:
        self.left = MAX_SUBDIVISIONS


def _bernstein(p: TPoly) -> list[Fraction]:
    n = len(p) - 1
    return [sum((Fraction(comb(j, k), comb(n, k)) * p[k] for k in range(j + 1)), Fraction(0))
            for j in range(n + 1)]


def _half(p: TPoly, upper: bool) -> TPoly:
    """p(t / 2) or p((1 + t) / 2)."""
    n = len(p)
    if not upper:
        return [c / 2**k for k, c in enumerate(p)]
    # p((1 + t)/2) = sum c_k 2^-k (1 + t)^k
    out = [Fraction(0)] * n
    for k, c in enumerate(p):
        if c:
            s = c / 2**k
            for j in range(k + 1):
                out[j] += s * comb(k, j)
    return out


def _negative(p: TPoly, budget: _Budget, depth: int = 0) -> bool:
    """p(t) < 0 for every t in [0, 1] (exact; False when undecided within the budget)."""
    while len(p) > 1 and p[-1] == 0:
        p = p[:-1]
    b = _bernstein(p)
    if max(b) < 0:
        return True
    if b[0] >= 0 or b[-1] >= 0 or depth > 40:
        return False
    budget.left -= 1
    if budget.left < 0:
        return False
    return _negative(_half(p, False), budget, depth + 1) and _negative(_half(p, True), budget,
                                                                        depth + 1)


def polygon_parts(form: ImplicitLoop) -> tuple[dict[tuple[int, int], Fraction],
                                               dict[tuple[int, int], Fraction],
                                               dict[tuple[int, int], Fraction]]:
    """(q, -s R0, -s R1) as polynomials in (y, v), so that g = (q v, -s R0 - s d R1).

    Parameters
    ----------
    form : ImplicitLoop
        The loop's implicit form.

    Returns
    -------
    tuple of dict
        The three polynomials, exponents (i, j) of y^i v^j.

    Raises
    ------
    ValueError
        Not 2 states, D depends on y', or R is not affine in d.
    """
    if form.n != 2:
        raise ValueError(f"the polygon certificate needs 2 states, the loop has {form.n}")
    s = Fraction(form.sign)
    if any(k[1] or k[2] for k in form.D):
        raise ValueError("the coefficient of the highest derivative depends on y'")
    if any(k[2] > 1 for k in form.R):
        raise ValueError("the loop is not affine in the input")
    q = {(k[0], 0): s * c for k, c in form.D.items()}
    r0 = {(k[0], k[1]): -s * c for k, c in form.R.items() if k[2] == 0}
    r1 = {(k[0], k[1]): -s * c for k, c in form.R.items() if k[2] == 1}
    return q, r0, r1


def _chains(P: list[tuple[Fraction, Fraction]]) -> str:
    n = len(P)
    ys = [p[0] for p in P]
    iL = min(range(n), key=lambda i: ys[i])
    iR = max(range(n), key=lambda i: ys[i])
    if ys.count(ys[iL]) != 1 or ys.count(ys[iR]) != 1:
        return "the leftmost and rightmost vertices must be unique"
    up = [P[(iL + k) % n] for k in range((iR - iL) % n + 1)]
    lo = [P[(iR + k) % n] for k in range((iL - iR) % n + 1)]
    if any(b[0] <= a[0] for a, b in zip(up, up[1:], strict=False)):
        return "the upper chain (leftmost to rightmost vertex) is not strictly increasing in y"
    if any(b[0] >= a[0] for a, b in zip(lo, lo[1:], strict=False)):
        return "the lower chain is not strictly decreasing in y"
    lo_inc = lo[::-1]

    def interp(chain: list[tuple[Fraction, Fraction]], y: Fraction) -> Fraction:
        lo_i, hi_i = 0, len(chain) - 1
        while hi_i - lo_i > 1:
            mid = (lo_i + hi_i) // 2
            if chain[mid][0] <= y:
                lo_i = mid
            else:
                hi_i = mid
        (y0, v0), (y1, v1) = chain[lo_i], chain[hi_i]
        return v0 + (v1 - v0) * (y - y0) / (y1 - y0)

    if any(interp(lo_inc, p[0]) >= p[1] for p in up[1:-1]):
        return "an upper-chain vertex is not above the lower chain"
    if any(interp(up, p[0]) <= p[1] for p in lo[1:-1]):
        return "a lower-chain vertex is not below the upper chain"
    if not (ys[iL] < 0 < ys[iR]) or not (interp(lo_inc, Fraction(0)) < 0 < interp(up, Fraction(0))):
        return "the rest state (0, 0) is not strictly inside the polygon"
    return ""


def check_region(form: ImplicitLoop, cert: dict[str, Any]) -> str:
    """Re-verify an invariant polygon exactly (empty string when it holds, else why not).

    Parameters
    ----------
    form : ImplicitLoop
        The model's own implicit form (never taken from the certificate).
    cert : dict
        The certificate: ``format``, ``kind``, ``states``, ``U``, ``vertices``
        (``[["p/q", "p/q"], ...]``, clockwise) and optionally ``level`` (``"p/q"``).

    Returns
    -------
    str
        ``""`` when every condition holds, else the first one that failed.
    """
    try:
        return _check(form, cert)
    except (ValueError, TypeError, KeyError, ZeroDivisionError) as exc:
        return f"malformed certificate: {str(exc)[:200]}"


def _check(form: ImplicitLoop, cert: dict[str, Any]) -> str:
    if cert.get("format") != FORMAT or cert.get("kind") != KIND:
        return f"not a {FORMAT} file of kind {KIND}"
    if list(cert.get("states", [])) != list(form.states) or cert.get("input") != form.input_name:
        return (f"the state map differs from the model's: file {str(cert.get('states'))[:80]}, "
                f"model {list(form.states)}")
    q, r0, r1 = polygon_parts(form)
    U = _q(cert["U"])
    if not U > 0:
        return "U must be positive"
    raw = cert["vertices"]
    if not isinstance(raw, list) or not 3 <= len(raw) <= MAX_VERTICES:
        return f"a polygon needs 3 to MAX_VERTICES = {MAX_VERTICES} vertices"
    P = []
    for item in raw:
        if not (isinstance(item, list) and len(item) == 2):
            return "a vertex must be a pair ['p/q', 'p/q']"
        P.append((_q(item[0]), _q(item[1])))
    why = _chains(P)
    if why:
        return why
    budget = _Budget()
    ymin = min(p[0] for p in P)
    ymax = max(p[0] for p in P)
    level = _q(cert.get("level", 0))
    if not 0 <= level < 1:
        return "level must be in [0, 1)"
    qline = _on_line(q, [ymin, ymax - ymin], [Fraction(0)])
    qline[0] -= level * q.get((0, 0), Fraction(0))
    if not _negative([-c for c in qline], budget):
        return ("the coefficient of the highest derivative is not bounded away from "
                + (f"{level} of its value at rest" if level else "0") + " on the polygon")
    n = len(P)
    for i in range(n):
        (y0, v0), (y1, v1) = P[i], P[(i + 1) % n]
        ey, ev = y1 - y0, v1 - v0
        y, v = [y0, ey], [v0, ev]
        qv = _tmul(_on_line(q, y, [Fraction(0)]), v)
        A = _tadd([-ev * c for c in qv], [ey * c for c in _on_line(r0, y, v)])
        B = [ey * c for c in _on_line(r1, y, v)]
        for sign in (1, -1):
            if not _negative(_tadd(A, [sign * U * c for c in B]), budget):
                return (f"the field does not point strictly into the polygon on edge {i} "
                        f"(from ({float(y0):.9g}, {float(v0):.9g}) to ({float(y1):.9g}, "
                        f"{float(v1):.9g})) for d = {'+' if sign > 0 else '-'}U"
                        + ("" if budget.left >= 0 else
                           f"; subdivision budget MAX_SUBDIVISIONS = {MAX_SUBDIVISIONS} spent"))
    return ""


def bound(cert: dict[str, Any]) -> tuple[float, float]:
    """(max |y|, max |y'|) over the polygon (floats, rounded outward).

    Parameters
    ----------
    cert : dict
        A ``gfrf-implicit-region`` certificate (its ``vertices``, rationals as text).

    Returns
    -------
    tuple of float
        The largest |y| and |y'| of its vertices.
    """
    ys = [abs(_q(p[0])) for p in cert["vertices"]]
    vs = [abs(_q(p[1])) for p in cert["vertices"]]
    return float(max(ys)), float(max(vs))
