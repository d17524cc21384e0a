"""Exact enclosures of polynomials on many grid boxes at once, in integer arithmetic.

A grid box of the NARX paving (:mod:`gfrf.stability.narx_paving`) has end points that are
integers times one rational scale per variable: the cell edges -R + c 2R/N are
(2c - N) R/N, the input pieces -U + 2Uj/p are (2j - p) U/p.  A term c x^e of a polynomial
is then c scale^e times a product of integer powers, whose range on the box is an exact
integer interval (numpy ``int64`` where no product can reach 2**62, Python integers
otherwise).  Summing the terms with their rational coefficients brought to one
denominator gives the natural interval enclosure of the polynomial, every bound an exact
rational ``numerator / denominator``: no rounding anywhere, vectorised over the boxes.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from gfrf.stability.polysys import Poly

__all__ = ["enclose", "CHUNK"]

#: Boxes enclosed per vectorised block (bounds the memory of one block).
CHUNK = 1 << 15
_SAFE = 2**62


def _power(a: np.ndarray, b: np.ndarray, e: int) -> tuple[np.ndarray, np.ndarray]:
    """The exact range of x**e for x in the integer interval [a, b]."""
    ae, be = a**e, b**e
    if e % 2:
        return ae, be
    zero = (a < 0) & (b > 0)
    lo = np.where(zero, 0, np.minimum(ae, be))
    return lo, np.maximum(ae, be)


def _term_range(factors: list[tuple[int, int]], a: np.ndarray, b: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """The exact integer range of prod x_i**e_i on the boxes with integer corners a, b."""
    m = a.shape[0]
    lo = np.ones(m, dtype=a.dtype)
    hi = lo.copy()
    for i, e in factors:
        p0, p1 = _power(a[:, i], b[:, i], e)
        pr = (lo * p0, lo * p1, hi * p0, hi * p1)
        lo = np.minimum(np.minimum(pr[0], pr[1]), np.minimum(pr[2], pr[3]))
        hi = np.maximum(np.maximum(pr[0], pr[1]), np.maximum(pr[2], pr[3]))
    return lo, hi


def enclose(polys: list[Poly], a: np.ndarray, b: np.ndarray, scales: list[Fraction]
            ) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """Exact rational bounds of each polynomial on each box.

    Box r is the product over variables i of [a[r, i] scales[i], b[r, i] scales[i]].

    Parameters
    ----------
    polys : list of Poly
        Polynomials with exact rational coefficients in the variables of the boxes.
    a, b : numpy.ndarray
        Integer corners (rows: boxes, columns: variables), a <= b.
    scales : list of Fraction
        The positive scale of each variable.

    Returns
    -------
    list of (numpy.ndarray, numpy.ndarray, int)
        Per polynomial: numerators of the lower and upper bounds (Python integers,
        object arrays) and their common positive denominator; the polynomial's range on
        box r lies in [lo[r] / den, hi[r] / den].
    """
    top = int(max(np.max(np.abs(a), initial=0), np.max(np.abs(b), initial=0)))
    out = []
    for p in polys:
        terms = [(c * math.prod((scales[i] ** e for i, e in enumerate(k) if e), start=1),
                  [(i, e) for i, e in enumerate(k) if e]) for k, c in p.items() if c]
        den = math.lcm(1, *(Fraction(c).denominator for c, _ in terms))
        lo = np.zeros(a.shape[0], dtype=object)
        hi = np.zeros(a.shape[0], dtype=object)
        for c, factors in terms:
            k = int(c * den)
            small = top ** sum(e for _, e in factors) < _SAFE
            ai = a if small else a.astype(object)
            bi = b if small else b.astype(object)
            t0, t1 = _term_range(factors, ai, bi)
            t0, t1 = t0.astype(object), t1.astype(object)
            if k > 0:
                lo += k * t0
                hi += k * t1
            else:
                lo += k * t1
                hi += k * t0
        out.append((lo, hi, den))
    return out
