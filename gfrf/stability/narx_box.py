"""An invariant box of a NARX recursion: a certificate checked in exact rational arithmetic.

For the state form x[k+1] = f(x[k], v[k]) of a NARX model
(:func:`gfrf.stability.polysys.state_form`: x = lagged outputs and inputs, v = u[k]), a
box B = [lo_1, hi_1] x .. x [lo_n, hi_n] holding the origin with

    f(B, [-U, U]) subset of B

is invariant: from rest, every input with sup|u| <= U keeps the state in B, so the output
stays bounded (an induction on k, no approximation).  The box is taken in coordinates
s = T(x) with an exact polynomial inverse x = X(s) (checked: X(T(x)) = x): y[k-1] minus
phi(u[k-2], ..), the terms of the recursion that depend on the inputs only (shifted one
step), which keeps the correlation between the newest output and the inputs it already
holds; the observer form of the older output lags; and the real modal basis of the
output block's linear part.

The box is found by iterating the recursion on boxes (outward hull, float interval
arithmetic: a proposal), its end points rounded to dyadic rationals, and the inclusion is
then checked in exact rational arithmetic (python-flint ``fmpq``): the image of every cell
of a subdivision is enclosed term by term (each monomial's range on a cell is exact, the
sum of the ranges contains the polynomial's).  U is bisected; the work is bounded by
counts (iterations, cells, bisection steps), never by time.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.polysys import Poly, PolySystem, padd, pcompose, pdegree, pscale

__all__ = ["BoxResult", "box_certificate", "check_box", "box_map", "recursion", "FORMAT",
           "MAX_CELLS", "ITERATIONS", "BISECTIONS",
           "coordinates"]

FORMAT = "gfrf-narx-box"
#: Cells of the subdivision of B x [-U, U] on which the image is enclosed.
MAX_CELLS = 4096
#: Box iterations per trial U, and bisection steps on U (each with an exact check).
ITERATIONS = 200
BISECTIONS = 12
_BACKOFF = 4
#: The coarse float screening of each coordinate choice: cells and bisection steps.
SCREEN_CELLS = 256
SCREEN_STEPS = 6
#: Relative growth of the box per iteration (pushes the iteration past fixed points).
_GROW = 1e-3
#: A box wider than this (relative to U + 1) is taken as an escape.
_ESCAPE = 1e6
#: End points are rounded outward to multiples of 2**-_DYADIC.
_DYADIC = 40


@dataclass(frozen=True, kw_only=True)
class BoxResult:
    """A verified invariant box.

    Attributes
    ----------
    radius : float
        A float at or below the certificate's exact U; ``inf`` for a linear recursion
        (the box scaled by t is invariant for t * U).
    bound : float
        A float at or above the largest |y| the box allows (every output stays below it;
        ``inf`` for a linear recursion: the bound grows with U).
    certificate : dict
        U, the coordinates and the box as exact rationals (``"p/q"`` texts), re-checkable by
        :func:`check_box`.
    work : int
        Box iterations spent (all trial U together).
    """

    radius: float
    bound: float
    certificate: dict[str, Any] = field(repr=False)
    work: int


def _var(i: int, nv: int) -> Poly:
    return {tuple(int(j == i) for j in range(nv)): Fraction(1)}


def _phi(system: PolySystem) -> Poly:
    """The input-only terms of the newest output's recursion, shifted one step back."""
    n = system.n
    nv = n + 1
    ny = min(system.bounded_states, default=n)
    nu = n - ny
    out: Poly = {}
    for k, c in system.f[0].items():
        if any(k[:ny]):
            continue
        shifted = [0] * nv
        ok = True
        for idx in range(ny, nv):
            if not k[idx]:
                continue
            lag = 0 if idx == n else idx - ny + 1
            if lag + 1 > nu:
                ok = False
                break
            shifted[ny + lag] += k[idx]
        if ok and any(shifted):
            out[tuple(shifted)] = out.get(tuple(shifted), Fraction(0)) + c
    return {k: c for k, c in out.items() if c}


def _linear_coefficients(system: PolySystem) -> tuple[list[Fraction], list[Fraction]]:
    """(a_1..a_ny, b_0..b_nu): the linear terms of the newest output's recursion."""
    n = system.n
    ny = min(system.bounded_states, default=n)
    f0 = system.f[0]

    def coef(idx: int) -> Fraction:
        return f0.get(tuple(int(j == idx) for j in range(n + 1)), Fraction(0))

    a = [coef(i) for i in range(ny)]
    b = [coef(n)] + [coef(ny + j) for j in range(n - ny)]
    return a, b


def coordinates(system: PolySystem, phi: Poly, observer: bool
                ) -> tuple[list[Poly], list[Poly]] | None:
    """(T, X): the coordinates s = T(x) and their exact inverse x = X(s).

    s_0 = y[k-1] - phi(lagged inputs); with ``observer`` the older output lags are replaced
    by the linear part of the recursion they still feed (observer form: s_j = the part of
    y[k+j-1] that the lags >= j + 1 contribute), the lagged inputs are kept.

    Parameters
    ----------
    system : PolySystem
        A discrete state form with ``bounded_states`` = the lagged inputs.
    phi : Poly
        A polynomial in the lagged inputs only (``{}``: none).
    observer : bool
        Use observer coordinates for y[k-2], .., y[k-ny].

    Returns
    -------
    (list of Poly, list of Poly) or None
        T in the variables (x, v) and X in the variables (s, v); None when the observer
        form is singular (the oldest output lag has a zero linear coefficient).
    """
    n = system.n
    nv = n + 1
    ny = min(system.bounded_states, default=n)
    T = [padd(_var(0, nv), pscale(phi, Fraction(-1)))] + [_var(i, nv) for i in range(1, n)]
    X = [padd(_var(0, nv), phi)] + [_var(i, nv) for i in range(1, n)]
    if observer and ny >= 2:
        a, b = _linear_coefficients(system)
        if a[ny - 1] == 0:
            return None
        # s_{j-1} = sum_{i=j}^{ny} a_i y[k-(i-j+2)] + b_i u[k-(i-j+2)], j = 2..ny
        for j in range(2, ny + 1):
            row: Poly = {}
            for i in range(j, ny + 1):
                lag = i - j + 2
                row = padd(row, pscale(_var(lag - 1, nv), a[i - 1]))
                if i < len(b) and lag <= n - ny:
                    row = padd(row, pscale(_var(ny + lag - 1, nv), b[i]))
            T[j - 1] = row
        # invert: s_{j-1} holds y[k-(ny-j+2)] with coefficient a_ny; solve from j = ny down
        for j in range(ny, 1, -1):
            top = ny - j + 2  # the oldest output lag in s_{j-1}
            rest = padd(T[j - 1], pscale(_var(top - 1, nv), Fraction(-1) * a[ny - 1]))
            X[top - 1] = pscale(padd(_var(j - 1, nv), pscale(pcompose(rest, X + [_var(n, nv)],
                                                                        nv), Fraction(-1))),
                                1 / a[ny - 1])
    return T, X


def box_map(system: PolySystem, T: list[Poly], X: list[Poly]) -> list[Poly]:
    """The recursion in the coordinates s = T(x): s' = g(s, v) = T(f(X(s), v), v).

    Parameters
    ----------
    system : PolySystem
        A discrete state form.
    T, X : list of Poly
        The coordinates and their inverse (:func:`coordinates`).

    Returns
    -------
    list of Poly
        g, one exact polynomial per state, in the variables (s, v).
    """
    nv = system.n + 1
    v = _var(system.n, nv)
    F = [pcompose(p, X + [v], nv) for p in system.f]
    return [pcompose(t, F + [v], nv) for t in T]


def _splits(g: list[Poly], nv: int, cells: int) -> list[int]:
    """Pieces per variable: only the variables that occur nonlinearly or in several terms."""
    count = [0] * nv
    for p in g:
        for k in p:
            for i, e in enumerate(k):
                if e:
                    count[i] += 1 if e == 1 else 2
    dims = [i for i in range(nv) if count[i] > 1]
    per = max(1, int(math.floor(cells ** (1 / max(len(dims), 1)) + 1e-9)))
    return [per if i in dims else 1 for i in range(nv)]


def _pow_range(a: Any, b: Any, e: int) -> tuple[Any, Any]:
    if e % 2 or a >= 0:
        return a**e, b**e
    if b <= 0:
        return b**e, a**e
    return 0 * a, max(a**e, b**e)


def _enclose_float(g: list[Poly], lo: np.ndarray, hi: np.ndarray,
                   splits: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Float interval enclosure of g on the box (a proposal: no directed rounding)."""
    nv = len(lo)
    edges = [np.linspace(lo[i], hi[i], splits[i] + 1) for i in range(nv)]
    grids = np.meshgrid(*[np.arange(s) for s in splits], indexing="ij")
    idx = [gr.ravel() for gr in grids]
    a = [edges[i][idx[i]] for i in range(nv)]
    b = [edges[i][idx[i] + 1] for i in range(nv)]
    olo, ohi = np.empty(len(g)), np.empty(len(g))
    for j, p in enumerate(g):
        slo = np.zeros(len(idx[0]))
        shi = np.zeros(len(idx[0]))
        for k, c in p.items():
            tlo = np.full(len(idx[0]), float(c))
            thi = tlo.copy()
            for i, e in enumerate(k):
                if not e:
                    continue
                if e % 2:
                    plo, phi_ = a[i] ** e, b[i] ** e
                else:
                    ae, be = a[i] ** e, b[i] ** e
                    cross = (a[i] < 0) & (b[i] > 0)
                    plo = np.where(cross, 0.0, np.minimum(ae, be))
                    phi_ = np.maximum(ae, be)
                prods = np.stack([tlo * plo, tlo * phi_, thi * plo, thi * phi_])
                tlo, thi = prods.min(axis=0), prods.max(axis=0)
            slo += tlo
            shi += thi
        olo[j], ohi[j] = slo.min(), shi.max()
    return olo, ohi


def _enclosure_exact(g: list[Poly], lo: list[Fraction], hi: list[Fraction],
                     splits: list[int]) -> list[tuple[Any, Any]]:
    """Exact rational enclosure of each g_j on the box (python-flint fmpq)."""
    from flint import fmpq

    def q(x: Fraction) -> Any:
        return fmpq(x.numerator, x.denominator)

    nv = len(lo)
    pieces = []
    for i in range(nv):
        a, b = q(lo[i]), q(hi[i])
        s = splits[i]
        pieces.append([(a + (b - a) * j / s, a + (b - a) * (j + 1) / s) for j in range(s)])
    terms = [[(q(c), [(i, e) for i, e in enumerate(k) if e]) for k, c in p.items()]
             for p in g]
    out: list[list[Any]] = [[None, None] for _ in g]
    for cell in itertools.product(*pieces):
        cache: dict[tuple[int, int], tuple[Any, Any]] = {}
        for j, tl in enumerate(terms):
            slo = shi = fmpq(0)
            for c, factors in tl:
                tlo = thi = c
                for i, e in factors:
                    r = cache.get((i, e))
                    if r is None:
                        r = cache[(i, e)] = _pow_range(cell[i][0], cell[i][1], e)
                    prods = (tlo * r[0], tlo * r[1], thi * r[0], thi * r[1])
                    tlo, thi = min(prods), max(prods)
                slo += tlo
                shi += thi
            cur = out[j]
            if cur[0] is None or slo < cur[0]:
                cur[0] = slo
            if cur[1] is None or shi > cur[1]:
                cur[1] = shi
    return [(c[0], c[1]) for c in out]


def _frac(x: Any) -> Fraction:
    return Fraction(int(x.p), int(x.q))


def _outward(x: float, up: bool) -> Fraction:
    s = 2**_DYADIC
    return Fraction(math.ceil(x * s) if up else math.floor(x * s), s)


def _poly_to(p: Poly) -> dict[str, str]:
    return {",".join(map(str, k)): str(c) for k, c in sorted(p.items())}


def _poly_from(d: dict[str, str], nv: int) -> Poly:
    out: Poly = {}
    for k, c in d.items():
        key = tuple(int(e) for e in k.split(","))
        if len(key) != nv or min(key) < 0:
            raise ValueError(k)
        out[key] = Fraction(c)
    return {k: c for k, c in out.items() if c}


def recursion(system: PolySystem) -> list[dict[str, str]]:
    """The recursion x[k+1] = f(x[k], v[k]) as exact rationals (the form a file records).

    Parameters
    ----------
    system : PolySystem
        A discrete state form.

    Returns
    -------
    list of dict
        One ``{"e_1,..,e_n,e_v": "p/q"}`` table per state.
    """
    return [_poly_to(p) for p in system.f]


def check_box(system: PolySystem, cert: dict[str, Any]) -> str:
    """Re-verify an invariant-box certificate from scratch (exact rational arithmetic).

    Checks that x = X(s) inverts s = T(x) exactly, that T maps rest to 0, that the box
    holds 0, and that the image of the box under s' = T(f(X(s), v)) for every
    |v| <= U lies in the box (enclosed cell by cell).

    Parameters
    ----------
    system : PolySystem
        The NARX state form the certificate speaks about.
    cert : dict
        The certificate (:attr:`BoxResult.certificate`).

    Returns
    -------
    str
        ``""`` when every condition holds, else the first one that fails.
    """
    n = system.n
    nv = n + 1
    try:
        if cert.get("format") != FORMAT or cert.get("states") != list(system.states):
            return "the certificate is not an invariant box of this state form"
        U = Fraction(cert["U"])
        T = [_poly_from(p, nv) for p in cert["T"]]
        X = [_poly_from(p, nv) for p in cert["X"]]
        lo = [Fraction(x) for x in cert["lo"]]
        hi = [Fraction(x) for x in cert["hi"]]
        splits = [int(s) for s in cert["splits"]]
    except (KeyError, ValueError, TypeError, ZeroDivisionError, AttributeError):
        return "the certificate is malformed"
    if not (len(T) == len(X) == len(lo) == len(hi) == n and len(splits) == nv) or U <= 0:
        return "the certificate has the wrong size"
    if any(s < 1 for s in splits) or math.prod(splits) > MAX_CELLS:
        return f"the subdivision is empty or above MAX_CELLS = {MAX_CELLS}"
    why = coordinates_error(T, X, n)
    if why:
        return why
    if any(not lo[i] <= 0 <= hi[i] for i in range(n)):
        return "the box does not hold the rest state"
    image = _enclosure_exact(box_map(system, T, X), lo + [-U], hi + [U], splits)
    for i, (a, b) in enumerate(image):
        if _frac(a) < lo[i] or _frac(b) > hi[i]:
            return f"the image of the box leaves it in coordinate s_{i}"
    return ""


def coordinates_error(T: list[Poly], X: list[Poly], n: int) -> str:
    """Why the certificate coordinates s = T(x), x = X(s) of an ``n``-state form are not
    usable (``""`` when they are): they depend on the input, X does not invert T exactly,
    or T does not map rest to 0."""
    nv = n + 1
    if any(k[n] for p in T + X for k in p):
        return "the coordinates must not depend on the input v"
    v = _var(n, nv)
    if any(pcompose(X[i], T + [v], nv) != _var(i, nv) for i in range(n)):
        return "X is not the inverse of the coordinates T"
    if any((0,) * nv in p for p in T):
        return "the coordinates do not map rest to 0"
    return ""


def _iterate(g: list[Poly], ny: int, n: int, U: float, splits: list[int]
             ) -> tuple[np.ndarray, np.ndarray, int] | None:
    """The box iteration at one U (float proposal), or None when it escapes."""
    lo = np.zeros(n + 1)
    hi = np.zeros(n + 1)
    lo[ny:], hi[ny:] = -U, U
    cap = _ESCAPE * (U + 1)
    for it in range(1, ITERATIONS + 1):
        with np.errstate(all="ignore"):
            ilo, ihi = _enclose_float(g, lo, hi, splits)
        if not (np.all(np.isfinite(ilo)) and np.all(np.isfinite(ihi))):
            return None
        if np.all(ilo[:ny] >= lo[:ny]) and np.all(ihi[:ny] <= hi[:ny]):
            return lo, hi, it
        nlo, nhi = np.minimum(lo[:ny], ilo[:ny]), np.maximum(hi[:ny], ihi[:ny])
        width = nhi - nlo
        lo[:ny], hi[:ny] = nlo - _GROW * width, nhi + _GROW * width
        if not np.all(np.isfinite(lo)) or np.max(np.abs(np.r_[lo, hi])) > cap:
            return None
    return None


def _try(system: PolySystem, T: list[Poly], X: list[Poly], g: list[Poly],
         splits: list[int], U: Fraction) -> tuple[dict[str, Any] | None, int]:
    n = system.n
    ny = min(system.bounded_states, default=n)
    found = _iterate(g, ny, n, float(U), splits)
    if found is None:
        return None, ITERATIONS
    lo, hi, work = found
    pad = 1e-9 * (1 + np.max(np.abs(np.r_[lo, hi])))
    qlo = [_outward(float(x) - pad, False) for x in lo[:ny]] + [-U] * (n - ny)
    qhi = [_outward(float(x) + pad, True) for x in hi[:ny]] + [U] * (n - ny)
    cert = {"format": FORMAT, "kind": "narx-box", "version": 1,
            "state_map": system.map_text(), "states": list(system.states),
            "recursion": recursion(system), "U": str(U),
            "T": [_poly_to(p) for p in T], "X": [_poly_to(p) for p in X],
            "lo": [str(x) for x in qlo], "hi": [str(x) for x in qhi], "splits": splits}
    return (cert if check_box(system, cert) == "" else None), work


def _modal(system: PolySystem, T: list[Poly], X: list[Poly]
           ) -> tuple[list[Poly], list[Poly]] | None:
    """(T, X) followed by the real modal (Jordan) basis of the output block's linear part."""
    n = system.n
    nv = n + 1
    ny = min(system.bounded_states, default=n)
    g = box_map(system, T, X)
    A = np.array([[float(g[i].get(tuple(int(m == j) for m in range(nv)), 0))
                   for j in range(ny)] for i in range(ny)])
    lam, vec = np.linalg.eig(A)
    cols: list[np.ndarray] = []
    for k in np.argsort(-np.abs(lam)):
        if lam[k].imag > 1e-12:
            cols += [vec[:, k].real, vec[:, k].imag]
        elif abs(lam[k].imag) <= 1e-12:
            cols.append(vec[:, k].real)
    if len(cols) != ny:
        return None
    V = np.array(cols).T
    if not np.all(np.isfinite(V)) or np.linalg.cond(V) > 1e6:
        return None
    V = V / np.max(np.abs(V))
    Vq = [[_outward(float(V[i, j]), False) for j in range(ny)] for i in range(ny)]
    # exact inverse of Vq (Gauss-Jordan in rationals)
    aug = [row[:] + [Fraction(int(i == j)) for j in range(ny)] for i, row in enumerate(Vq)]
    for c in range(ny):
        piv = next((r for r in range(c, ny) if aug[r][c] != 0), None)
        if piv is None:
            return None
        aug[c], aug[piv] = aug[piv], aug[c]
        aug[c] = [x / aug[c][c] for x in aug[c]]
        for r in range(ny):
            if r != c and aug[r][c] != 0:
                aug[r] = [x - aug[r][c] * y for x, y in zip(aug[r], aug[c], strict=True)]
    Vinv = [row[ny:] for row in aug]
    # z = Vinv s_y: T_new = Vinv T_y; s_y = Vq z: X_new = X(Vq z, rest)
    Tn = [padd(*(pscale(T[j], Vinv[i][j]) for j in range(ny))) for i in range(ny)] + T[ny:]
    sub = [padd(*(pscale(_var(j, nv), Vq[i][j]) for j in range(ny))) for i in range(ny)]
    sub += [_var(i, nv) for i in range(ny, nv)]
    Xn = [pcompose(x, sub, nv) for x in X]
    return Tn, Xn


def _candidates(system: PolySystem) -> list[tuple[list[Poly], list[Poly]]]:
    phi = _phi(system)
    out = []
    for p in ({}, phi) if phi else ({},):
        for observer in (False, True):
            c = coordinates(system, p, observer)
            if c is not None and c not in out:
                out.append(c)
    ny = min(system.bounded_states, default=system.n)
    base = coordinates(system, {}, True)
    if ny >= 2 and base is not None:
        modal = _modal(system, *base)
        if modal is not None:
            out.append(modal)
    return out


def _float_radius(g: list[Poly], ny: int, n: int, splits: list[int], lo: float,
                  steps: int) -> tuple[float, float, int]:
    """Bracket (lo, hi) of the largest U whose float box iteration closes, and the work."""
    work = 0
    hi = 2 * lo if lo else 1.0
    while hi <= 2**20:
        found = _iterate(g, ny, n, hi, splits)
        work += found[2] if found else ITERATIONS
        if found is None:
            break
        lo, hi = hi, 2 * hi
    for _ in range(steps):
        mid = (lo + hi) / 2
        found = _iterate(g, ny, n, mid, splits)
        work += found[2] if found else ITERATIONS
        lo, hi = (mid, hi) if found else (lo, mid)
    return lo, hi, work


def box_certificate(system: PolySystem) -> BoxResult | None:
    """The largest U (by bisection) with an exactly verified invariant box, or None.

    Every coordinate choice (:func:`coordinates` and the modal one) is screened with a
    coarse float search (:data:`SCREEN_CELLS` cells, :data:`SCREEN_STEPS` bisection
    steps); the best one is bisected further in floats (:data:`BISECTIONS` steps on
    :data:`MAX_CELLS` cells), and its U is accepted only after the exact check (backing
    off by 1 % steps, at most 4, when that fails).  A linear recursion answers ``inf``.

    Parameters
    ----------
    system : PolySystem
        A discrete (NARX) state form.

    Returns
    -------
    BoxResult or None
    """
    if not system.discrete or not system.equilibrium_ok():
        return None
    n = system.n
    ny = min(system.bounded_states, default=n)
    work = 0
    screened = []
    for T, X in _candidates(system):
        g = box_map(system, T, X)
        lo_f, hi_f, w = _float_radius(g, ny, n, _splits(g, n + 1, SCREEN_CELLS), 0.0,
                                      SCREEN_STEPS)
        work += w
        screened.append((lo_f, hi_f, T, X, g))
    lo_f, hi_f, T, X, g = max(screened, key=lambda t: t[0])
    if lo_f <= 0:
        return None
    splits = _splits(g, n + 1, MAX_CELLS)
    # float bisection on the fine cells, then the exact check, backing off U a little
    lo, hi = 0.0, 1.5 * hi_f
    trial = lo_f
    for _ in range(BISECTIONS):
        found = _iterate(g, ny, n, trial, splits)
        work += found[2] if found else ITERATIONS
        lo, hi = (trial, hi) if found else (lo, trial)
        trial = (lo + hi) / 2
        if hi - lo <= hi * 2**-12:
            break
    best: tuple[dict[str, Any], Fraction] | None = None
    for k in range(_BACKOFF):
        U = _outward(lo * (1 - 0.01 * k), False)
        if U <= 0:
            break
        cert, w = _try(system, T, X, g, splits, U)
        work += w
        if cert is not None:
            best = (cert, U)
            break
    if best is None:
        return None
    cert, U = best
    lo_b = [Fraction(x) for x in cert["lo"]] + [-U]
    hi_b = [Fraction(x) for x in cert["hi"]] + [U]
    ys = _enclosure_exact(X[:ny], lo_b, hi_b, cert["splits"])
    bound = max(max(abs(_frac(a)), abs(_frac(b))) for a, b in ys)
    if all(pdegree(p) <= 1 for p in system.f):
        # a linear recursion: t * box is invariant for t * U, every t > 0
        return BoxResult(radius=math.inf, bound=math.inf, certificate=cert, work=work)
    return BoxResult(radius=_below(U), bound=_above(bound), certificate=cert, work=work)


def _below(x: Fraction) -> float:
    f = float(x)
    return f if Fraction(f) <= x else math.nextafter(f, -math.inf)


def _above(x: Fraction) -> float:
    f = float(x)
    return f if Fraction(f) >= x else math.nextafter(f, math.inf)
