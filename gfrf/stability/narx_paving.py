"""An invariant paving of a NARX recursion: a union of grid cells, checked exactly.

A box (:mod:`gfrf.stability.narx_box`) treats the output coordinates as independent; the
set the recursion really reaches is often much thinner (consecutive outputs are
correlated).  Here the output coordinates s_0 .. s_{ny-1} (in the coordinates s = T(x) of
:func:`gfrf.stability.narx_box.coordinates`) are covered by a uniform grid, and the set

    Omega = (union of the cells in S) x [-U, U]^(lagged inputs)

is built by following the recursion from the cell of the rest state (every cell the
enclosure of a cell's image touches joins S).  Omega is invariant when the enclosure of
the image of every cell of S, for every |v| <= U, is covered by cells of S: from rest,
every input with sup|u| <= U keeps the state in Omega.  The search runs in floats (a
proposal); the closure is then re-checked with every enclosure in exact rational
arithmetic (python-flint ``fmpq``).  The work is bounded by counts (cells, input pieces,
bisection steps), never by time.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.narx_box import (
    _above,
    _below,
    _candidates,
    _frac,
    _outward,
    _poly_from,
    _poly_to,
    box_map,
    coordinates_error,
    recursion,
)
from gfrf.stability.polysys import Poly, PolySystem

__all__ = ["PavingResult", "paving_certificate", "check_paving", "FORMAT",
           "GRID", "PIECES", "BISECTIONS", "MAX_OUTPUT_LAGS"]

FORMAT = "gfrf-narx-paving"
#: Grid cells per output coordinate, pieces per input coordinate of a cell's image
#: (and of all input coordinates together).
GRID = 96
PIECES = 6
_PIECE_BUDGET = 36
#: Bisection steps on U (float search), then exact checks while backing off.
BISECTIONS = 8
_BACKOFF = 4
#: Output lags a paving covers (cells grow as GRID ** lags).
MAX_OUTPUT_LAGS = 2
#: Grid half-widths tried, as multiples of the simulated extent.
_SPANS = (1.5, 3.0)
#: The coarse screening of each coordinate choice: grid and bisection steps.
SCREEN_GRID = 48
SCREEN_STEPS = 4
#: Doublings of U from the start, and the simulated runs and steps sizing the grid.
_DOUBLINGS = 12
_RUNS = 100
_STEPS = 120


@dataclass(frozen=True)
class PavingResult:
    """A verified invariant paving.

    Attributes
    ----------
    radius : float
        A float at or below the certificate's exact U.
    bound : float
        A float at or above the largest |y| the paving allows.
    cells : int
        Cells of the paving.
    certificate : dict
        U, the coordinates, the grid and the cells (exact rationals as ``"p/q"``),
        re-checkable by :func:`check_paving`.
    """

    radius: float
    bound: float
    cells: int
    certificate: dict[str, Any] = field(repr=False)


def _pieces(g: list[Poly], ny: int, nv: int) -> list[int]:
    """Pieces per input coordinate: those occurring nonlinearly or in several terms."""
    count = [0] * nv
    for p in g[:ny]:
        for k in p:
            for i, e in enumerate(k):
                if e:
                    count[i] += 1 if e == 1 else 2
    split = [i for i in range(ny, nv) if count[i] > 1]
    per = max(1, min(PIECES, int(_PIECE_BUDGET ** (1 / max(len(split), 1)) + 1e-9)))
    return [per if i in split else 1 for i in range(nv)]


def _terms(g: list[Poly], ny: int) -> list[list[tuple[Any, tuple[tuple[int, int], ...]]]]:
    return [[(c, tuple((i, e) for i, e in enumerate(k) if e)) for k, c in p.items()]
            for p in g[:ny]]


def _images_float(terms: list[Any], a: np.ndarray, b: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Float enclosures (rows: sub-boxes with corners a, b) of the output coordinates."""
    m = a.shape[0]
    lo = np.zeros((m, len(terms)))
    hi = np.zeros((m, len(terms)))
    for j, tl in enumerate(terms):
        for c, factors in tl:
            tlo = np.full(m, float(c))
            thi = tlo.copy()
            for i, e in factors:
                ae, be = a[:, i] ** e, b[:, i] ** e
                if e % 2:
                    plo, phi = ae, be
                else:
                    plo = np.where((a[:, i] < 0) & (b[:, i] > 0), 0.0, np.minimum(ae, be))
                    phi = np.maximum(ae, be)
                pr = np.stack([tlo * plo, tlo * phi, thi * plo, thi * phi])
                tlo, thi = pr.min(axis=0), pr.max(axis=0)
            lo[:, j] += tlo
            hi[:, j] += thi
    return lo, hi


def _subboxes(ny: int, nv: int, U: float, pieces: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Corners of the input-coordinate pieces (output columns left zero)."""
    grids = [np.linspace(-U, U, pieces[i] + 1) for i in range(ny, nv)]
    combos = list(itertools.product(*[range(pieces[i]) for i in range(ny, nv)]))
    a = np.zeros((len(combos), nv))
    b = np.zeros((len(combos), nv))
    for r, combo in enumerate(combos):
        for d, j in enumerate(combo):
            a[r, ny + d], b[r, ny + d] = grids[d][j], grids[d][j + 1]
    return a, b


def _search(terms: list[Any], ny: int, nv: int, U: float, R: np.ndarray, N: int,
            pieces: list[int]) -> set[tuple[int, ...]] | None:
    """Float closure of the cell of rest under the recursion, or None when it leaves the grid."""
    h = 2 * R / N
    ua, ub = _subboxes(ny, nv, U, pieces)
    start = tuple(int(x) for x in np.minimum(np.floor(R / h), N - 1))
    S = {start}
    frontier = [start]
    while frontier:
        cells = np.array(frontier, dtype=float)
        frontier = []
        a = np.repeat(ua, len(cells), axis=0)
        b = np.repeat(ub, len(cells), axis=0)
        cl = np.tile(cells, (len(ua), 1))
        a[:, :ny] = -R + cl * h
        b[:, :ny] = -R + (cl + 1) * h
        with np.errstate(all="ignore"):
            lo, hi = _images_float(terms, a, b)
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))) \
                or np.any(lo + R < 0) or np.any(hi - R > 0):
            return None
        pad = 1e-9 * (1 + np.abs(lo) + np.abs(hi))
        i0 = np.floor((lo - pad + R) / h).astype(np.int64)
        i1 = np.ceil((hi + pad + R) / h).astype(np.int64) - 1
        if np.any(i0 < 0) or np.any(i1 >= N):
            return None
        for row in np.unique(np.c_[i0, i1], axis=0).tolist():
            for cell in itertools.product(*[range(p, max(p, q) + 1)
                                            for p, q in zip(row[:ny], row[ny:], strict=True)]):
                if cell not in S:
                    S.add(cell)
                    frontier.append(cell)
    return S


def check_paving(system: PolySystem, cert: dict[str, Any]) -> str:
    """Re-verify an invariant-paving certificate from scratch (exact rational arithmetic).

    Parameters
    ----------
    system : PolySystem
        The NARX state form the certificate speaks about.
    cert : dict
        The certificate (:attr:`PavingResult.certificate`).

    Returns
    -------
    str
        ``""`` when every condition holds, else the first one that fails.
    """
    from flint import fmpq

    n = system.n
    nv = n + 1
    ny = min(system.bounded_states, default=n)
    try:
        if cert.get("format") != FORMAT or cert.get("states") != list(system.states):
            return "the certificate is not an invariant paving of this state form"
        U = Fraction(cert["U"])
        T = [_poly_from(p, nv) for p in cert["T"]]
        X = [_poly_from(p, nv) for p in cert["X"]]
        R = [Fraction(x) for x in cert["R"]]
        N = int(cert["N"])
        pieces = [int(p) for p in cert["pieces"]]
        S = {tuple(int(i) for i in c) for c in cert["cells"]}
    except (KeyError, ValueError, TypeError, ZeroDivisionError, AttributeError):
        return "the certificate is malformed"
    if not (len(T) == len(X) == n and len(R) == ny and len(pieces) == nv) or U <= 0:
        return "the certificate has the wrong size"
    if ny > MAX_OUTPUT_LAGS or not 1 <= N <= GRID or min(R) <= 0 \
            or any(not 1 <= p <= PIECES for p in pieces) or np.prod(pieces) > _PIECE_BUDGET \
            or any(len(c) != ny or min(c) < 0 or max(c) >= N for c in S) or not S:
        return "the grid, the pieces or the cells are out of range"
    why = coordinates_error(T, X, n)
    if why:
        return why
    h = [2 * r / N for r in R]
    if not any(all(-R[d] + c[d] * h[d] <= 0 <= -R[d] + (c[d] + 1) * h[d] for d in range(ny))
               for c in S):
        return "no cell holds the rest state"
    g = box_map(system, T, X)
    # the lagged-input coordinates: their image over the whole grid lies in [-U, U]
    from gfrf.stability.narx_box import _enclosure_exact

    whole = _enclosure_exact(g[ny:], [-r for r in R] + [-U] * (nv - ny), R + [U] * (nv - ny),
                             [1] * ny + pieces[ny:])
    if any(_frac(a) < -U or _frac(b) > U for a, b in whole):
        return "the lagged inputs leave [-U, U]"
    q = [fmpq(x.numerator, x.denominator) for x in (*R, U)]
    Rq, Uq = q[:ny], q[ny]
    hq = [2 * r / N for r in Rq]
    upieces = [[(-Uq + 2 * Uq * j / pieces[i], -Uq + 2 * Uq * (j + 1) / pieces[i])
                for j in range(pieces[i])] for i in range(ny, nv)]
    terms = [[(fmpq(c.numerator, c.denominator), f) for c, f in tl] for tl in _terms(g, ny)]
    table = _occupancy(S, N, ny)
    for cell in S:
        box = [(-Rq[d] + cell[d] * hq[d], -Rq[d] + (cell[d] + 1) * hq[d]) for d in range(ny)]
        for upart in itertools.product(*upieces):
            full = box + list(upart)
            need = []
            for d, tl in enumerate(terms):
                lo = hi = fmpq(0)
                for c, factors in tl:
                    tlo = thi = c
                    for i, e in factors:
                        x0, x1 = full[i]
                        p0, p1 = _pow(x0, x1, e)
                        pr = (tlo * p0, tlo * p1, thi * p0, thi * p1)
                        tlo, thi = min(pr), max(pr)
                    lo += tlo
                    hi += thi
                i0 = ((lo + Rq[d]) / hq[d]).floor()
                i1 = max(int(((hi + Rq[d]) / hq[d]).ceil()) - 1, int(i0))
                need.append((int(i0), i1))
            if not _covered(table, need):
                return f"the image of cell {list(cell)} leaves the paving"
    return ""


def _occupancy(S: set[tuple[int, ...]], N: int, ny: int) -> np.ndarray:
    """Summed-area table of the cells: entry [i+1, j+1] counts the cells <= (i, j)."""
    occ = np.zeros((N + 1,) * ny, dtype=np.int64)
    for c in S:
        occ[tuple(i + 1 for i in c)] = 1
    for axis in range(ny):
        occ = np.cumsum(occ, axis=axis)
    return occ


def _covered(table: np.ndarray, need: list[tuple[int, int]]) -> bool:
    """Every grid cell of the block ``need`` (index ranges, inclusive) is in the paving:
    its count from the summed-area table (inclusion-exclusion) equals its size."""
    N = table.shape[0] - 1
    if any(i0 < 0 or i1 >= N for i0, i1 in need):
        return False
    count = 0
    for corner in itertools.product((0, 1), repeat=len(need)):
        idx = tuple(need[d][1] + 1 if b else need[d][0] for d, b in enumerate(corner))
        count += int(table[idx]) * (-1) ** (len(need) - sum(corner))
    return count == int(np.prod([i1 - i0 + 1 for i0, i1 in need]))


def _pow(a: Any, b: Any, e: int) -> tuple[Any, Any]:
    if e % 2 or a >= 0:
        return a**e, b**e
    if b <= 0:
        return b**e, a**e
    return 0 * a, max(a**e, b**e)


def _extent(g: list[Poly], n: int, U: float) -> np.ndarray:
    """Largest |s_i| along simulated inputs of size U (a float estimate that only sizes
    the grid): random signs and random levels, fixed seed."""
    keys = sorted({k for p in g for k in p})
    E = np.array(keys, dtype=float)  # monomial exponents, one row per monomial
    C = np.array([[float(p.get(k, 0)) for k in keys] for p in g])  # (n, monomials)
    rng = np.random.default_rng(0)
    state = np.zeros((_RUNS, n))
    top = np.zeros(n)
    with np.errstate(all="ignore"):
        for k in range(_STEPS):
            v = U * (rng.choice([-1.0, 1.0], size=_RUNS) if k % 2
                     else rng.uniform(-1.0, 1.0, size=_RUNS))
            pts = np.c_[state, v]
            mono = np.prod(pts[:, None, :] ** E[None, :, :], axis=2)
            state = mono @ C.T
            state[~np.isfinite(state)] = 0.0
            top = np.maximum(top, np.abs(state).max(axis=0))
    return top


def _closes(g: list[Poly], terms: list[Any], pieces: list[int], ny: int, U: float,
            N: int) -> tuple[np.ndarray, set[tuple[int, ...]]] | None:
    """A float paving at U on an N-per-lag grid (each span of the simulated extent)."""
    n = len(g)
    ext = np.maximum(_extent(g, n, U)[:ny], 1e-9 + U)
    for span in _SPANS:
        R = span * ext
        S = _search(terms, ny, n + 1, U, R, N, pieces)
        if S is not None:
            return R, S
    return None


def _bracket(g: list[Poly], terms: list[Any], pieces: list[int], ny: int, start: float,
             N: int, steps: int) -> tuple[float, float]:
    """(lo, hi): lo closes on the grid (0 if nothing does), hi does not."""
    lo, U = 0.0, start
    for _ in range(_DOUBLINGS):
        if _closes(g, terms, pieces, ny, U, N) is None:
            break
        lo, U = U, 2 * U
    hi = U
    for _ in range(steps):
        mid = (lo + hi) / 2 if lo else hi / 4
        if _closes(g, terms, pieces, ny, mid, N) is not None:
            lo = mid
        else:
            hi = mid
    return lo, hi


def paving_certificate(system: PolySystem, start: float = 0.0) -> PavingResult | None:
    """The largest U (doubling, then bisection) with an exactly verified invariant paving.

    Every coordinate choice of :func:`gfrf.stability.narx_box.coordinates` (and the
    modal one) is screened on a coarse grid; the best is bisected on the
    :data:`GRID` grid and checked exactly, backing off U a little when the check fails.

    Parameters
    ----------
    system : PolySystem
        A discrete (NARX) state form with at most :data:`MAX_OUTPUT_LAGS` output lags.
    start : float
        The first U tried (e.g. a radius already proven); 0: 1/64.

    Returns
    -------
    PavingResult or None
        None when no U is verified.
    """
    n = system.n
    nv = n + 1
    ny = min(system.bounded_states, default=n)
    if not system.discrete or ny > MAX_OUTPUT_LAGS or not system.equilibrium_ok():
        return None
    start = start if start > 0 else 2.0**-6
    screened = []
    for T, X in _candidates(system):
        g = box_map(system, T, X)
        terms, pieces = _terms(g, ny), _pieces(g, ny, nv)
        lo, hi = _bracket(g, terms, pieces, ny, start, SCREEN_GRID, SCREEN_STEPS)
        screened.append((lo, hi, T, X, g, terms, pieces))
    lo, hi, T, X, g, terms, pieces = max(screened, key=lambda t: t[0])
    if lo <= 0:
        return None
    for _ in range(BISECTIONS):
        mid = (lo + hi) / 2
        if _closes(g, terms, pieces, ny, mid, GRID) is not None:
            lo = mid
        else:
            hi = mid
    for k in range(_BACKOFF):
        U = _outward(lo * (1 - 0.02 * k), False)
        found = _closes(g, terms, pieces, ny, float(U), GRID)
        if U <= 0 or found is None:
            continue
        Rq = [_outward(float(r), True) for r in found[0]]
        S = _search(terms, ny, nv, float(U), np.array([float(r) for r in Rq]), GRID, pieces)
        if S is None:
            continue
        cert = {"format": FORMAT, "kind": "narx-paving", "version": 1,
                "state_map": system.map_text(), "states": list(system.states),
                "recursion": recursion(system), "U": str(U),
                "T": [_poly_to(p) for p in T], "X": [_poly_to(p) for p in X],
                "R": [str(r) for r in Rq], "N": GRID, "pieces": pieces,
                "cells": sorted([list(c) for c in S])}
        if check_paving(system, cert) == "":
            h = [2 * r / GRID for r in Rq]
            bound = _y_bound(system, X, Rq, h, S, U, ny)
            return PavingResult(radius=_below(U), bound=_above(bound), cells=len(S),
                                certificate=cert)
    return None


def _y_bound(system: PolySystem, X: list[Poly], R: list[Fraction], h: list[Fraction],
             S: set[tuple[int, ...]], U: Fraction, ny: int) -> Fraction:
    """An exact bound on |y[k-1]|, .., |y[k-ny]| over the paving."""
    from gfrf.stability.narx_box import _enclosure_exact

    nv = system.n + 1
    top = Fraction(0)
    for cell in S:
        lo = [-R[d] + cell[d] * h[d] for d in range(ny)] + [-U] * (nv - ny)
        hi = [-R[d] + (cell[d] + 1) * h[d] for d in range(ny)] + [U] * (nv - ny)
        for a, b in _enclosure_exact(X[:ny], lo, hi, [1] * nv):
            top = max(top, abs(_frac(a)), abs(_frac(b)))
    return top
