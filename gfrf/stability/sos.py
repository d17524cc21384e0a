"""Sum-of-squares certificates for any polynomial system with a bounded input.

The model is put in state form (:func:`gfrf.stability.polysys.state_form`: the ODE's
companion state, the closed loop with the controller's states, or NARX's lagged outputs
and inputs).  A storage function V is searched, and the largest U such that the
sublevel set {V <= c} is invariant for every input with sup|v| <= U (the S-procedure,
:mod:`gfrf.stability.sos_check` states the identities), or, for a continuous system,
a radially unbounded V whose derivative is negative outside a compact set for every
bounded input (global: every bounded input keeps every solution bounded).  For a
continuous system the verified quadratic V is then improved to degree 4 by the V-lambda
iteration of :mod:`gfrf.stability.sos_poly`.

The semidefinite programs are solved by Clarabel through cvxpy.  Their answer is only a
proposal: every number is rounded to a rational, the Gram matrix of the remainder is
corrected so the polynomial identity holds exactly, and :func:`gfrf.stability.sos_check.check_dict`
re-verifies it in rational arithmetic (exact charpoly).  A radius is reported only after
that check passed (proof ``"interval"``); a proposal that fails is dropped.  The work is
bounded by counts (candidate levels, bisection steps), never by time.
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.polysys import (
    Poly,
    PolySystem,
    padd,
    pcompose,
    pdegree,
    pmul,
    pscale,
)
from gfrf.stability.sos_check import (
    FORMAT,
    check_dict,
    gram_poly,
    gram_to,
    poly_to,
    vdot,
)
from gfrf.stability.sos_core import (
    SosResult,
    _monomials,
    _Program,
    _project,
    _r,
    _rgram,
)
from gfrf.stability.sos_global import global_certificate

__all__ = ["SosResult", "sos_certificate", "BISECTIONS", "LEVELS"]

#: Steps on U (each one SDP and, when feasible, one exact check), and levels c tried.
BISECTIONS = 7
LEVELS = 2
#: Sampled estimates the shape search of the quadratic V may spend.
SHAPE_EVALUATIONS = 200
#: Largest Gram matrix the search builds (larger systems are not searched).
MAX_GRAM_SEARCH = 40
#: Strictness margin eps on the boundary, relative to the level c.
_EPS = Fraction(1, 2**16)
_SAMPLES = 3000


def _quadratic(P: np.ndarray, n: int) -> Poly:
    V: Poly = {}
    for i in range(n):
        for j in range(i, n):
            k = [0] * (n + 1)
            k[i] += 1
            k[j] += 1
            V[tuple(k)] = _r(P[i, i] if i == j else 2 * P[i, j])
    return {k: c for k, c in V.items() if c}


def _lyapunov(system: PolySystem) -> np.ndarray | None:
    import scipy.linalg as sl

    A = np.array([[float(x) for x in row] for row in system.jacobian()])
    n = system.n
    try:
        if system.discrete:
            P = sl.solve_discrete_lyapunov(A.T, np.eye(n))
        else:
            P = sl.solve_continuous_lyapunov(A.T, -np.eye(n))
    except (ValueError, np.linalg.LinAlgError):
        return None
    P = (P + P.T) / 2
    if not np.all(np.isfinite(P)) or np.min(np.linalg.eigvalsh(P)) <= 0:
        return None
    return P / np.max(np.abs(P))


class _Scaled:
    """p(s * base, v) for many s and v at fixed sample points (monomials evaluated once)."""

    def __init__(self, p: Poly, base: np.ndarray):
        keys = list(p)
        self.coef = np.array([float(p[k]) for k in keys])
        self.dx = np.array([sum(k[:-1]) for k in keys], dtype=float)
        self.dv = np.array([k[-1] for k in keys], dtype=float)
        self.M = np.stack([np.prod(base ** np.asarray(k[:-1]), axis=1) for k in keys], axis=1) \
            if keys else np.zeros((base.shape[0], 0))

    def __call__(self, s: float, v: float) -> np.ndarray:
        with np.errstate(all="ignore"):
            w = self.coef * s ** self.dx * np.where(self.dv > 0, v ** self.dv, 1.0)
        return self.M @ w


def _estimate_levels(system: PolySystem, V: Poly, P: np.ndarray, samples: int = _SAMPLES,
                     levels: int = 36, steps: int = 30) -> list[tuple[float, float]]:
    """(c, U estimate) by sampling the level sets, best first (a proposal only)."""
    n = system.n
    rng = np.random.default_rng(0)
    s = rng.normal(size=(samples, n))
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    L = np.linalg.cholesky(P)
    base = np.linalg.solve(L.T, s.T).T  # V(base) = 1
    fracs = np.linspace(-1, 1, 5)
    if system.discrete:
        ev = _Scaled(pcompose(V, list(system.f), n + 1), base)
        bounded = list(system.bounded_states)
        scales = (1.0, 0.7, 0.4)
    else:
        ev = _Scaled(vdot(V, system), base)
    out = []
    for c in np.geomspace(1e-4, 1e3, levels):
        r = math.sqrt(c)
        lo, hi = 0.0, 10.0 * r + 10.0
        for _ in range(steps):
            U = (lo + hi) / 2
            if system.discrete:
                ok = True
                for sc in scales:
                    inside = (np.all(np.abs(sc * r * base[:, bounded]) <= U, axis=1)
                              if bounded else np.ones(len(base), bool))
                    ok = ok and all(bool(np.all(ev(sc * r, fr * U)[inside] <= c))
                                    for fr in fracs)
            else:
                ok = all(bool(np.all(ev(r, fr * U) < 0)) for fr in fracs)
            lo, hi = (U, hi) if ok else (lo, U)
        if lo > 0:
            out.append((float(c), lo))
    out.sort(key=lambda t: -t[1])
    return out


def _local_program(system: PolySystem, V: Poly, c: Fraction, U: Fraction
                   ) -> tuple[Any, dict[str, Any]]:
    n = system.n
    nv = n + 1
    zero = (0,) * nv
    v2 = {tuple(2 * int(j == n) for j in range(nv)): Fraction(1)}
    box = padd({zero: U * U}, pscale(v2, Fraction(-1)))
    prog = _Program()
    blocks: dict[str, Any] = {}
    if not system.discrete:
        dV = vdot(V, system)
        D = pdegree(dV) + pdegree(dV) % 2
        D = max(D, 2)
        p = padd(pscale(dV, Fraction(-1)),
                 {tuple(2 * int(j == i) for j in range(nv)): -_EPS * c for i in range(n)})
        prog.constant(p, 1.0)
        lam_b = _monomials(nv, range(D - 1), 2)
        blocks["lambda"] = (lam_b, prog.free(lam_b, padd(V, {zero: -c}), 1.0))
        mu_b = _monomials(nv, range(D // 2), 0)
        blocks["mu"] = (mu_b, prog.gram(mu_b, box, -1.0))
        sig_b = _monomials(nv, range(D // 2 + 1), 1)
        blocks["sigma"] = (sig_b, prog.gram(sig_b, {zero: Fraction(1)}, -1.0))
        return prog, blocks
    Vf = pcompose(V, list(system.f), nv)
    D = pdegree(Vf) + pdegree(Vf) % 2
    prog.constant(padd({zero: c}, pscale(Vf, Fraction(-1))), 1.0)
    half = _monomials(nv, range(D // 2), D)
    blocks["lambda"] = (half, prog.gram(half, padd({zero: c}, pscale(V, Fraction(-1))), -1.0))
    blocks["mu"] = (half, prog.gram(half, box, -1.0))
    blocks["nu"] = []
    for j in system.bounded_states:
        xj2 = {tuple(2 * int(i == j) for i in range(nv)): Fraction(1)}
        blocks["nu"].append((half, prog.gram(half, padd({zero: U * U},
                                                        pscale(xj2, Fraction(-1))), -1.0)))
    sig_b = _monomials(nv, range(D // 2 + 1), D)
    blocks["sigma"] = (sig_b, prog.gram(sig_b, {zero: Fraction(1)}, -1.0))
    return prog, blocks


def _local_certificate(system: PolySystem, V: Poly, c: Fraction, U: Fraction,
                       blocks: dict[str, Any]) -> dict[str, Any] | None:
    """Round the proposal, make the identity exact, return the certificate (unchecked)."""
    n = system.n
    nv = n + 1
    zero = (0,) * nv
    kind = "local-discrete" if system.discrete else "local-continuous"
    cert: dict[str, Any] = {"format": FORMAT, "version": 1, "kind": kind,
                            "state_map": system.map_text(), "states": list(system.states),
                            "V": poly_to(V), "c": str(c), "U": str(U)}
    mult: dict[str, Any] = {}
    box = padd({zero: U * U}, {tuple(2 * int(j == n) for j in range(nv)): Fraction(-1)})
    mu_b, mu_var = blocks["mu"]
    mu_Q = _rgram(mu_var)
    mult["mu"] = gram_to(mu_b, mu_Q)
    rest = pscale(pmul(gram_poly(mu_b, mu_Q), box), Fraction(-1))
    if kind == "local-continuous":
        cert["epsilon"] = str(_EPS * c)
        lam_b, lam_var = blocks["lambda"]
        lam = {k: _r(x) for k, x in zip(lam_b, np.asarray(lam_var.value), strict=True)
               if _r(x)}
        mult["lambda"] = poly_to(lam)
        target = padd(pscale(vdot(V, system), Fraction(-1)),
                      {tuple(2 * int(j == i) for j in range(nv)): -_EPS * c for i in range(n)},
                      pmul(lam, padd(V, {zero: -c})), rest)
    else:
        lam_b, lam_var = blocks["lambda"]
        lam_Q = _rgram(lam_var)
        mult["lambda"] = gram_to(lam_b, lam_Q)
        target = padd({zero: c}, pscale(pcompose(V, list(system.f), nv), Fraction(-1)),
                      pscale(pmul(gram_poly(lam_b, lam_Q), padd({zero: c},
                                                                pscale(V, Fraction(-1)))),
                             Fraction(-1)), rest)
        mult["nu"] = []
        for j, (nb, nvar) in zip(system.bounded_states, blocks["nu"], strict=True):
            nQ = _rgram(nvar)
            mult["nu"].append(gram_to(nb, nQ))
            xj = {tuple(2 * int(i == j) for i in range(nv)): Fraction(-1), zero: U * U}
            target = padd(target, pscale(pmul(gram_poly(nb, nQ), xj), Fraction(-1)))
    sig_b, sig_var = blocks["sigma"]
    sig_Q = _project(sig_b, _rgram(sig_var), target)
    if sig_Q is None:
        return None
    mult["sigma"] = gram_to(sig_b, sig_Q)
    cert["multipliers"] = mult
    return cert


def _shape(system: PolySystem, P0: np.ndarray) -> np.ndarray:
    """P improved by a deterministic Nelder-Mead search (at most SHAPE_EVALUATIONS
    sampled estimates of U) over its Cholesky factor: a proposal, checked later."""
    from scipy.optimize import minimize

    n = system.n
    L0 = np.linalg.cholesky(P0)
    idx = np.tril_indices(n)

    def build(z: np.ndarray) -> np.ndarray:
        L = np.zeros((n, n))
        L[idx] = z
        P = L @ L.T
        return P / np.max(np.abs(P))

    def cost(z: np.ndarray) -> float:
        P = build(z)
        if np.min(np.linalg.eigvalsh(P)) <= 1e-9:
            return 0.0
        est = _estimate_levels(system, _quadratic(P, n), P, samples=600, levels=14, steps=16)
        return -est[0][1] if est else 0.0

    res = minimize(cost, L0[idx], method="Nelder-Mead",
                   options={"maxfev": SHAPE_EVALUATIONS, "xatol": 1e-3, "fatol": 1e-6})
    best = build(res.x)
    return best if res.fun < cost(L0[idx]) else P0


def _local(system: PolySystem) -> tuple[SosResult | None, int]:
    P = _lyapunov(system)
    if P is None:
        return None, 0
    P = _shape(system, P)
    n = system.n
    V = _quadratic(P, n)
    Pq = np.array([[float(V.get(tuple(int(m == i) + int(m == j) for m in range(n + 1)),
                                0)) / (1 if i == j else 2) for j in range(n)]
                   for i in range(n)])
    levels = _estimate_levels(system, V, Pq)
    solves = 0
    best: SosResult | None = None
    for c_float, u_est in levels[:LEVELS]:
        c = _r(c_float)
        lo, hi = 0.0, u_est
        good: Fraction | None = None
        # the sampled U first (often provable as it is), then bisection below it
        for step in range(BISECTIONS):
            U = _r(0.95 * u_est if step == 0 else (lo + hi) / 2)
            if U <= 0:
                break
            prog, blocks = _local_program(system, V, c, U)
            solves += 1
            if prog.solve():
                cert = _local_certificate(system, V, c, U, blocks)
                if cert is not None and check_dict(system, cert) == "":
                    good = U
                    if best is None or float(U) > best.radius:
                        best = SosResult(radius=_below(U), kind=cert["kind"],
                                         certificate=cert, solves=solves, property=_BOUNDED)
                    lo = float(U)
                    if step == 0:
                        break
                    continue
            hi = float(U)
        if good is not None:
            break
    if best is not None:
        best = SosResult(radius=best.radius, kind=best.kind, certificate=best.certificate,
                         solves=solves, property=best.property)
    return best, solves


_BOUNDED = ("bounded: every solution from rest stays in the invariant set {V <= c} "
            "(not: returns to the equilibrium)")


def _below(x: Fraction) -> float:
    """The largest float <= x."""
    f = float(x)
    return f if Fraction(f) <= x else math.nextafter(f, -math.inf)


def search_size(system: PolySystem) -> int:
    """Size of the largest Gram matrix of the local search (its work grows as its cube)."""
    nv = system.n + 1
    if system.discrete:
        D = 2 * max(pdegree(p) for p in system.f)
        return len(_monomials(nv, range(D // 2 + 1), D))
    D = max(pdegree(p) for p in system.f) + 1
    D += D % 2
    return len(_monomials(nv, range(D // 2 + 1), 1))


def sos_certificate(system: PolySystem, *, global_search: bool = True, degree: int = 4
                    ) -> tuple[SosResult | None, int]:
    """The best verified SOS certificate of a polynomial system, or None.

    Parameters
    ----------
    system : PolySystem
        The state form (:func:`gfrf.stability.polysys.state_form`).
    global_search : bool
        Try a global certificate (every bounded input) first.
    degree : int
        Degree of the local storage function of a continuous system: 2 (the quadratic V
        only) or 4 (the quadratic V improved by the V-lambda iteration of
        :func:`gfrf.stability.sos_poly.improve`).

    Returns
    -------
    (SosResult or None, int)
        The certificate (exactly re-verified) and the number of SDPs solved.
    """
    solves = 0
    if global_search:
        res, k = global_certificate(system)
        solves += k
        if res is not None:
            return res, solves
    res, k = _local(system)
    solves += k
    if res is not None and not system.discrete and degree > 2:
        from gfrf.stability.sos_poly import improve

        cert, k = improve(system, res.certificate)
        solves += k
        if cert is not None and Fraction(cert["U"]) > Fraction(res.certificate["U"]):
            res = SosResult(radius=_below(Fraction(cert["U"])), kind=cert["kind"],
                            certificate=cert, solves=solves, property=_BOUNDED)
    if res is not None:
        res = SosResult(radius=res.radius, kind=res.kind, certificate=res.certificate,
                        solves=solves, property=res.property)
    return res, solves
