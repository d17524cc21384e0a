"""Fused numba loops of the :class:`gfrf.bounds.enclosure.Jet` arithmetic (sum and product).

One pass over a batch of boxes per operation instead of a dozen numpy temporaries:
the same formulas as the numpy path of :mod:`gfrf.bounds.enclosure` (values, gradients and
Hessians at the centres, Leibniz's rule for the bounds D_0..D_3, then the Taylor-form
tightening): the whole enclosure of a box takes about half the time of the numpy
path (40 against 73 us per box for the pendulum's H5, one core).  Model-independent,
so compiled once per installation (numba ``cache=True``) and never per model.
Imported only when numba is installed (the ``fast`` extra).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["jet_add", "jet_mul"]


@njit(cache=True, inline="always")
def _abs(z):
    return np.sqrt(z.real * z.real + z.imag * z.imag)


@njit(cache=True, inline="always")
def _tighten(k, v, g, h, d, r):
    n = r.shape[1]
    first = 0.0
    second = 0.0
    for i in range(n):
        first += _abs(g[k, i]) * r[k, i]
        second += _abs(h[k, i, i]) * r[k, i] * r[k, i]
        for j in range(i + 1, n):
            second += 2.0 * _abs(h[k, i, j]) * r[k, i] * r[k, j]
    d3 = d[k, 3]
    forms = (abs(v[k]) + first + 0.5 * second + d3 / 6.0, first + second + 0.5 * d3,
             second + d3)
    for m in range(3):
        if forms[m] < d[k, m]:  # NaN forms keep the propagated bound
            d[k, m] = forms[m]
        if d[k, m] != d[k, m]:
            d[k, m] = np.inf


@njit(cache=True)
def jet_add(av, ag, ah, ad, ia, bv, bg, bh, bd, ib, r):
    """Sum of two jets, tightened.

    ``ag``/``ah`` are derivatives over a's coordinates, placed at positions ``ia`` of the
    union whose half-widths are ``r`` (N, m); likewise b.
    """
    size, m = r.shape
    v = av + bv
    g = np.zeros((size, m), np.complex128)
    h = np.zeros((size, m, m), np.complex128)
    d = ad + bd
    for k in range(size):
        for p in range(ia.size):
            g[k, ia[p]] += ag[k, p]
            for q in range(ia.size):
                h[k, ia[p], ia[q]] += ah[k, p, q]
        for p in range(ib.size):
            g[k, ib[p]] += bg[k, p]
            for q in range(ib.size):
                h[k, ib[p], ib[q]] += bh[k, p, q]
        _tighten(k, v, g, h, d, r)
    return v, g, h, d


@njit(cache=True)
def jet_mul(av, ag, ah, ad, ia, bv, bg, bh, bd, ib, r):
    """Product of two jets by Leibniz's rule, tightened (coordinates as in jet_add)."""
    size, m = r.shape
    v = np.empty(size, np.complex128)
    g = np.zeros((size, m), np.complex128)
    h = np.zeros((size, m, m), np.complex128)
    d = np.empty((size, 4))
    for k in range(size):
        a0, b0 = av[k], bv[k]
        v[k] = a0 * b0
        for p in range(ia.size):
            g[k, ia[p]] += ag[k, p] * b0
            for q in range(ia.size):
                h[k, ia[p], ia[q]] += ah[k, p, q] * b0
        for p in range(ib.size):
            g[k, ib[p]] += a0 * bg[k, p]
            for q in range(ib.size):
                h[k, ib[p], ib[q]] += a0 * bh[k, p, q]
        for p in range(ia.size):
            for q in range(ib.size):
                cross = ag[k, p] * bg[k, q]
                h[k, ia[p], ib[q]] += cross
                h[k, ib[q], ia[p]] += cross
        x0, x1, x2, x3 = ad[k, 0], ad[k, 1], ad[k, 2], ad[k, 3]
        y0, y1, y2, y3 = bd[k, 0], bd[k, 1], bd[k, 2], bd[k, 3]
        d[k, 0] = x0 * y0
        d[k, 1] = x1 * y0 + x0 * y1
        d[k, 2] = x2 * y0 + 2.0 * x1 * y1 + x0 * y2
        d[k, 3] = x3 * y0 + 3.0 * x2 * y1 + 3.0 * x1 * y2 + x0 * y3
        for j in range(4):
            if d[k, j] != d[k, j]:
                d[k, j] = np.inf
        _tighten(k, v, g, h, d, r)
    return v, g, h, d
