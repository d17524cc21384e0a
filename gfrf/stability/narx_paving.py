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
arithmetic (integer corners times one rational scale per variable,
:mod:`gfrf.stability.narx_cells`).  The search screens each coordinate choice on a coarse
grid, then bisects U on the fine grid with many pieces of the inputs (a cell's image is
a thin curve along the input, enclosed piece by piece).  The work is bounded by counts
(cells, input pieces, bisection steps), never by time.
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
from gfrf.stability.narx_cells import CHUNK, enclose
from gfrf.stability.polysys import Poly, PolySystem

__all__ = ["PavingResult", "paving_certificate", "check_paving", "FORMAT",
           "GRID", "PIECES", "PIECE_BUDGET", "FINE_GRID", "FINE_PIECES", "MAX_SEARCH_CELLS",
           "BISECTIONS", "MAX_OUTPUT_LAGS"]

FORMAT = "gfrf-narx-paving"
#: Largest grid (cells per output coordinate) and input pieces (per input coordinate, and
#: of all input coordinates together) a certificate may use.
GRID = 256
PIECES = 64
PIECE_BUDGET = 64
#: The search's middle grid, pieces and bisection steps (from the screened radius up),
#: then its fine grid and pieces, bisected between the middle radius and FINE_REACH
#: times it.
MID_GRID = 96
MID_PIECES = 24
MID_STEPS = 6
FINE_GRID = 192
FINE_PIECES = 48
FINE_REACH = 1.25
#: A float search that reaches more cells than this counts as not closing.
MAX_SEARCH_CELLS = 24_000
#: Bisection steps on U on the fine grid (float search), then exact checks while
#: backing off.
BISECTIONS = 5
_BACKOFF = 4
#: Output lags a paving covers (cells grow as GRID ** lags).
MAX_OUTPUT_LAGS = 2
#: Grid half-widths tried, as multiples of the simulated extent.
_SPANS = (1.5, 3.0)
#: The coarse screening of each coordinate choice: grid, pieces and bisection steps.
SCREEN_GRID = 48
SCREEN_PIECES = 16
SCREEN_STEPS = 4
#: Doublings of U from the start, and the simulated runs and steps sizing the grid.
_DOUBLINGS = 12
_RUNS = 100
_STEPS = 120


@dataclass(frozen=True, kw_only=True)
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


def _pieces(g: list[Poly], ny: int, nv: int, budget: int) -> list[int]:
    """Pieces per input coordinate: those occurring nonlinearly or in several terms."""
    count = [0] * nv
    for p in g[:ny]:
        for k in p:
            for i, e in enumerate(k):
                if e:
                    count[i] += 1 if e == 1 else 2
    split = [i for i in range(ny, nv) if count[i] > 1]
    per = max(1, min(PIECES, int(budget ** (1 / max(len(split), 1)) + 1e-9)))
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
    """Float closure of the cell of rest under the recursion, or None when it leaves the grid
    (or holds more than :data:`MAX_SEARCH_CELLS` cells)."""
    h = 2 * R / N
    ua, ub = _subboxes(ny, nv, U, pieces)
    start = tuple(int(x) for x in np.minimum(np.floor(R / h), N - 1))
    occ = np.zeros((N,) * ny, dtype=bool)
    occ[start] = True
    frontier = np.array([start], dtype=np.int64)
    while len(frontier):
        cells = frontier.astype(float)
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
        i1 = np.maximum(np.ceil((hi + pad + R) / h).astype(np.int64) - 1, i0)
        if np.any(i0 < 0) or np.any(i1 >= N):
            return None
        width = i1 - i0 + 1
        hit = np.zeros_like(occ)
        for off in itertools.product(*[range(int(w)) for w in width.max(axis=0)]):
            sel = np.all(width > np.array(off), axis=1)
            hit[tuple((i0[sel] + np.array(off)).T)] = True
        new = hit & ~occ
        occ |= hit
        if occ.sum() > MAX_SEARCH_CELLS:
            return None
        frontier = np.argwhere(new)
    return {tuple(c) for c in np.argwhere(occ).tolist()}


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
            or any(not 1 <= p <= PIECES for p in pieces) or np.prod(pieces) > PIECE_BUDGET \
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
    cells = sorted(S)
    table = _occupancy(S, N, ny)
    for a, b, owner in _boxes(cells, N, ny, nv, pieces):
        need = []
        for d, (lo, hi, den) in enumerate(enclose(g[:ny], a, b, _scales(R, U, N, pieces, ny))):
            # cell index of x: floor((x + R) / h) = floor((x N + R N) / (2 R)), x = num / den
            num, rd = R[d].numerator, R[d].denominator
            step = 2 * num * den
            i0 = (lo * (N * rd) + den * num * N) // step
            i1 = -((-(hi * (N * rd) + den * num * N)) // step) - 1
            need.append((i0, np.maximum(i1, i0)))
        bad = _uncovered(table, need, N)
        if bad is not None:
            return f"the image of cell {list(cells[owner[bad]])} leaves the paving"
    return ""


def _scales(R: list[Fraction], U: Fraction, N: int, pieces: list[int], ny: int
            ) -> list[Fraction]:
    """Per variable: the rational unit of the integer box corners."""
    return [r / N for r in R] + [U / p for p in pieces[ny:]]


def _boxes(cells: list[tuple[int, ...]], N: int, ny: int, nv: int, pieces: list[int]
           ) -> Any:
    """Blocks of integer box corners (cell x input piece) and the cell of each box."""
    combos = np.array(list(itertools.product(*[range(p) for p in pieces[ny:]])),
                      dtype=np.int64).reshape(-1, nv - ny)
    per = max(1, CHUNK // len(combos))
    for start in range(0, len(cells), per):
        block = np.array(cells[start:start + per], dtype=np.int64).reshape(-1, ny)
        owner = np.repeat(np.arange(start, start + len(block)), len(combos))
        a = np.empty((len(owner), nv), dtype=np.int64)
        a[:, :ny] = 2 * np.repeat(block, len(combos), axis=0) - N
        a[:, ny:] = 2 * np.tile(combos, (len(block), 1)) - np.array(pieces[ny:])
        yield a, a + 2, owner


def _uncovered(table: np.ndarray, need: list[tuple[np.ndarray, np.ndarray]], N: int
               ) -> int | None:
    """The first box whose block of needed cells is not all in the paving, or None:
    counted from the summed-area table (inclusion-exclusion) against the block's size."""
    out = np.zeros(len(need[0][0]), dtype=bool)
    for i0, i1 in need:
        out |= (i0 < 0) | (i1 >= N)
    if np.any(out):
        return int(np.flatnonzero(out)[0])
    idx = [(i0.astype(np.int64), i1.astype(np.int64)) for i0, i1 in need]
    count = np.zeros(len(out), dtype=np.int64)
    for corner in itertools.product((0, 1), repeat=len(idx)):
        at = tuple(i1 + 1 if c else i0 for (i0, i1), c in zip(idx, corner, strict=True))
        count += table[at] * (-1) ** (len(idx) - sum(corner))
    size = np.prod([i1 - i0 + 1 for i0, i1 in idx], axis=0)
    bad = np.flatnonzero(count != size)
    return int(bad[0]) if len(bad) else None


def _occupancy(S: set[tuple[int, ...]], N: int, ny: int) -> np.ndarray:
    """Summed-area table of the cells: entry [i+1, j+1] counts the cells <= (i, j)."""
    occ = np.zeros((N + 1,) * ny, dtype=np.int64)
    for c in S:
        occ[tuple(i + 1 for i in c)] = 1
    for axis in range(ny):
        occ = np.cumsum(occ, axis=axis)
    return occ


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
        S = _search(terms, ny, nv=n + 1, U=U, R=R, N=N, pieces=pieces)
        if S is not None:
            return R, S
    return None


def _bracket(g: list[Poly], terms: list[Any], pieces: list[int], ny: int, start: float,
             N: int, steps: int, top: float = 0.0) -> tuple[float, float, np.ndarray | None]:
    """(lo, hi, R): lo closes on the grid of half-widths R (0 and None if nothing does),
    hi does not.  With ``top`` > ``start`` the bracket is (start, top), else it is found by
    doubling from ``start``."""
    lo, U, R = 0.0, start, None
    for _ in range(_DOUBLINGS if top <= start else 0):
        found = _closes(g, terms, pieces, ny, U, N)
        if found is None:
            break
        lo, U, R = U, 2 * U, found[0]
    hi = U if top <= start else top
    if top > start:
        lo = start
    for _ in range(steps):
        mid = (lo + hi) / 2 if lo else hi / 4
        found = _closes(g, terms, pieces, ny, mid, N)
        if found is not None:
            lo, R = mid, found[0]
        else:
            hi = mid
    if lo and R is None:
        found = _closes(g, terms, pieces, ny, lo, N)
        lo, R = (lo, found[0]) if found is not None else (0.0, None)
    return lo, hi, R


def paving_certificate(system: PolySystem, start: float = 0.0) -> PavingResult | None:
    """The largest U (doubling, then bisection) with an exactly verified invariant paving.

    Every coordinate choice of :func:`gfrf.stability.narx_box.coordinates` (and the
    modal one) is screened on a coarse grid (:data:`SCREEN_GRID`, :data:`SCREEN_PIECES`);
    the best is bracketed and bisected on the :data:`FINE_GRID` grid with
    :data:`FINE_PIECES` input pieces and checked exactly, backing off U a little when
    the check fails.

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
        terms = _terms(g, ny)
        lo, _, _ = _bracket(g, terms, pieces=_pieces(g, ny, nv, SCREEN_PIECES), ny=ny, start=start,
                            N=SCREEN_GRID, steps=SCREEN_STEPS)
        screened.append((lo, T, X, g, terms))
    lo, T, X, g, terms = max(screened, key=lambda t: t[0])
    if lo <= 0:
        return None
    lo, _, _ = _bracket(g, terms, pieces=_pieces(g, ny, nv, MID_PIECES), ny=ny, start=lo,
                        N=MID_GRID, steps=MID_STEPS)
    pieces = _pieces(g, ny, nv, FINE_PIECES)
    lo, _, R = _bracket(g, terms, pieces=pieces, ny=ny, start=lo, N=FINE_GRID, steps=BISECTIONS,
                        top=lo * FINE_REACH)
    if R is None:
        return None
    for k in range(_BACKOFF):
        U = _outward(lo * (1 - 0.02 * k), False)
        if U <= 0:
            break
        Rq = [_outward(float(r), True) for r in R]
        S = _search(terms, ny, nv=nv, U=float(U), R=np.array([float(r) for r in Rq]), N=FINE_GRID,
                    pieces=pieces)
        if S is None:
            continue
        cert = {"format": FORMAT, "kind": "narx-paving", "version": 1,
                "state_map": system.map_text(), "states": list(system.states),
                "recursion": recursion(system), "U": str(U),
                "T": [_poly_to(p) for p in T], "X": [_poly_to(p) for p in X],
                "R": [str(r) for r in Rq], "N": FINE_GRID, "pieces": pieces,
                "cells": sorted([list(c) for c in S])}
        if check_paving(system, cert) == "":
            bound = _y_bound(X, Rq, sorted(S), U, ny, FINE_GRID)
            return PavingResult(radius=_below(U), bound=_above(bound), cells=len(S),
                                certificate=cert)
    return None


def _y_bound(X: list[Poly], R: list[Fraction], cells: list[tuple[int, ...]], U: Fraction,
             ny: int, N: int) -> Fraction:
    """An exact bound on |y[k-1]|, .., |y[k-ny]| over the paving."""
    nv = len(X) + 1
    top = Fraction(0)
    for a, b, _ in _boxes(cells, N, ny, nv, [1] * nv):
        for lo, hi, den in enclose(X[:ny], a, b, _scales(R, U, N, [1] * nv, ny)):
            top = max(top, Fraction(max(-min(lo), max(hi)), den))
    return top
