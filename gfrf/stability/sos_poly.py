"""Higher-degree storage functions for the local continuous-time SOS certificate.

A verified quadratic V (:mod:`gfrf.stability.sos`) is the starting point.  Normalised
to the level c = 1, it is improved by alternating two convex programs (the V-lambda
iteration):

* **V step** -- the multipliers lambda, mu fixed; V of degree 4, the level c and
  t = U^2 are the variables:  maximise t  subject to
  -dV/dt - eps|x|^2 + lambda (V - c) - mu (t - v^2) SOS  and  V - g|x|^2 SOS with its
  Gram matrix >= 2g I (V radially unbounded, so {V <= c} is compact; the margin keeps the
  next step strictly feasible), 1/2 <= c <= 2; V is then divided by c;
* **multiplier step** -- V fixed, U just below the V step's optimum (bisection below
  it when infeasible): lambda free, mu SOS, the same identity at level 1 (a feasibility
  problem: its interior solution survives the rounding to rationals).

Where the full monomial bases would exceed :data:`MAX_GRAM` (a third-order plant under
a PI controller: four states, a Gram matrix of side 50), V's terms above degree 2 are
restricted to products with the states that enter the system nonlinearly (structured
bases of :class:`_Shape`: side 30).  When the rounds from the quadratic V make no
proposal, they are started again from V + V^2/4 (:func:`_seed`).

The previous V stays feasible in the next V step, so the proposed U never decreases.
The rounds stop after :data:`ROUNDS` or when U grew by less than :data:`GAP` (relative).
Each multiplier step's solution is rounded to rationals and made exact
(:func:`gfrf.stability.sos_core._project`); the proposals are re-verified by
:func:`gfrf.stability.sos_check.check_dict`, the largest U first, and only one that
passed is returned.  The work is bounded by counts and gaps, never by time.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.polysys import Poly, PolySystem, padd, pdegree, pdiff, pmul, pscale
from gfrf.stability.sos_check import (
    FORMAT,
    check_dict,
    gram_poly,
    gram_to,
    poly_from,
    poly_to,
    vdot,
)
from gfrf.stability.sos_core import _monomials, _Program, _project, _r, _rgram

__all__ = ["improve", "ROUNDS", "STEPS", "GAP", "DEGREE"]

#: V-lambda rounds at most, bisection steps on U in each multiplier step, and the
#: relative gain of U below which the rounds stop.
ROUNDS = 30
STEPS = 3
GAP = Fraction(1, 200)
#: The multiplier step's first U, relative to the V step's optimum.
_BACKOFF = 0.995
#: The quartic part SEED V^2 added to the quadratic start (see :func:`_seed`); 0: none.
SEED = Fraction(1, 4)
#: Degree of the improved storage function.
DEGREE = 4
#: Radial unboundedness margin g (V - g|x|^2 SOS) and strictness eps, with c = 1.
_GAMMA = Fraction(1, 2**12)
_EPS = Fraction(1, 2**16)
#: Clarabel's tolerances (the exact check decides; looser is fewer iterations).
_TOL = {"tol_gap_abs": 1e-7, "tol_gap_rel": 1e-7, "tol_feas": 1e-7}
#: Largest Gram matrix (side) the improvement builds.
MAX_GRAM = 40


def _xmono(n: int, nv: int, i: int) -> tuple[int, ...]:
    return tuple(2 * int(j == i) for j in range(nv))


class _Shape:
    """Monomial bases of one system at one degree of V.

    ``structured``: V's terms above degree 2 are products of the states that enter f
    nonlinearly with the others (V = x^T P x + sum over such states x_k of x_k x^T Q_k x
    + ...: V's Gram basis is x and x_k x), lambda a polynomial in x of degree <= 2, mu
    quadratic, and the identity's Gram basis 1, x, v, x_i x_j, v x_i and x_k x_i x_j:
    smaller semidefinite programs for systems whose full bases are too large.
    """

    def __init__(self, system: PolySystem, dV: int, structured: bool = False):
        n = system.n
        nv = n + 1
        self.n, self.nv, self.dV = n, nv, dV
        df = max(pdegree(p) for p in system.f)
        D = dV - 1 + df
        self.D = D + D % 2
        self.v_basis = _monomials(nv, range(2, dV + 1), 0, xonly=True)
        self.vq_basis = _monomials(nv, range(1, dV // 2 + 1), 0, xonly=True)
        self.lam_basis = _monomials(nv, range(self.D - dV + 1), 2)
        self.mu_basis = _monomials(nv, range(self.D // 2), 0, xonly=True)
        self.sig_basis = _monomials(nv, range(self.D // 2 + 1), 1)
        if structured and dV == 4 and self.D == 6:
            bent = {i for p in system.f for k in p if sum(k[:n]) >= 2
                    for i in range(n) if k[i]}
            lin = _monomials(nv, range(1, 2), 0, xonly=True)
            quad = _monomials(nv, range(2, 3), 0, xonly=True)
            self.vq_basis = lin + [q for q in quad if any(q[i] for i in bent)]
            self.v_basis = sorted({tuple(a + b for a, b in zip(p, q, strict=True))
                                   for p in self.vq_basis for q in self.vq_basis},
                                  key=lambda k: (sum(k), k))
            self.lam_basis = _monomials(nv, range(3), 0, xonly=True)
            self.mu_basis = _monomials(nv, range(2), 0, xonly=True)
            self.sig_basis = (_monomials(nv, range(3), 1)
                              + [k for k in _monomials(nv, range(3, 4), 0, xonly=True)
                                 if any(k[i] for i in bent)])
        zero = (0,) * nv
        self.zero = zero
        self.norm2: Poly = {_xmono(n, nv, i): Fraction(1) for i in range(n)}
        self.v2: Poly = {tuple(2 * int(j == n) for j in range(nv)): Fraction(1)}

    def size(self) -> int:
        return max(len(self.sig_basis), len(self.vq_basis))


def _solve(progs: list[_Program], objective: Any = None) -> bool:
    """Solve coefficient-matching programs sharing variables (maximise ``objective``)."""

    cp = progs[0].cp
    cons = []
    for prog in progs:
        expr, b = prog.residual()
        cons.append(expr + b == 0)
        cons.extend(prog.constraints)
    goal = cp.Maximize(objective) if objective is not None else cp.Minimize(0)
    prob = cp.Problem(goal, cons)
    try:
        prob.solve(solver="CLARABEL", **_TOL)
    except cp.error.SolverError:
        return False
    return prob.status == "optimal"


def _v_step(system: PolySystem, sh: _Shape, lam: Poly, mu: Poly
            ) -> tuple[Poly, float] | None:
    """V (degree sh.dV) and U maximising U^2 with lambda, mu fixed (a proposal)."""
    import cvxpy as cp

    n = sh.n
    prog = _Program()
    a = cp.Variable(len(sh.v_basis))
    t = cp.Variable(1)
    entries: dict[tuple[int, int], float] = {}
    for j, k in enumerate(sh.v_basis):
        mono = {k: Fraction(1)}
        dk = padd(*(pmul(pdiff(mono, i), system.f[i]) for i in range(n)))
        for m, c in padd(pscale(dk, Fraction(-1)), pmul(lam, mono)).items():
            key = (prog._row(m), j)
            entries[key] = entries.get(key, 0.0) + float(c)
    prog.parts.append((entries, a))
    prog.parts.append(({(prog._row(m), 0): -float(c) for m, c in mu.items()}, t))
    cv = cp.Variable(1)
    prog.parts.append(({(prog._row(m), 0): -float(c) for m, c in lam.items()}, cv))
    prog.constant(padd(pscale(sh.norm2, -_EPS), pmul(mu, sh.v2)), 1.0)
    prog.gram(sh.sig_basis, {sh.zero: Fraction(1)}, -1.0)
    pv = _Program()
    pv.parts.append(({(pv._row(k), j): 1.0 for j, k in enumerate(sh.v_basis)}, a))
    pv.constant(sh.norm2, -float(_GAMMA))
    QV = pv.gram(sh.vq_basis, {sh.zero: Fraction(1)}, -1.0)
    # a margin: the next multiplier step's sigma_V stays strictly inside the cone
    pv.constraints += [t <= 1e6, QV >> 2 * float(_GAMMA) * np.eye(len(sh.vq_basis)),
                       cv >= 0.5, cv <= 2]
    if (not _solve([prog, pv], t[0]) or a.value is None or t.value is None
            or cv.value is None):
        return None
    cval = float(np.asarray(cv.value)[0])
    V = {k: _r(x / cval) for k, x in zip(sh.v_basis, np.asarray(a.value), strict=True)
         if _r(x / cval)}
    return V, float(np.asarray(t.value)[0])


def _m_step(system: PolySystem, sh: _Shape, V: Poly, U: Fraction
            ) -> tuple[dict[str, Any], Poly, Poly] | None:
    """Multipliers for a fixed V at level 1 and input bound U: the rounded, exactly
    projected certificate (not yet checked) with lambda and mu; None when infeasible."""
    zero = sh.zero
    box = padd({zero: U * U}, pscale(sh.v2, Fraction(-1)))
    prog = _Program()
    prog.constant(padd(pscale(vdot(V, system), Fraction(-1)), pscale(sh.norm2, -_EPS)), 1.0)
    lam_var = prog.free(sh.lam_basis, padd(V, {zero: Fraction(-1)}), 1.0)
    mu_var = prog.gram(sh.mu_basis, box, -1.0)
    sig_var = prog.gram(sh.sig_basis, {zero: Fraction(1)}, -1.0)
    pv = _Program()
    pv.constant(padd(V, pscale(sh.norm2, -_GAMMA)), 1.0)
    sv_var = pv.gram(sh.vq_basis, {zero: Fraction(1)}, -1.0)
    if not _solve([prog, pv]) or sig_var.value is None or lam_var.value is None:
        return None
    lam = {k: _r(x) for k, x in zip(sh.lam_basis, np.asarray(lam_var.value), strict=True)
           if _r(x)}
    mu_Q = _rgram(mu_var)
    mu = gram_poly(sh.mu_basis, mu_Q)
    target = padd(pscale(vdot(V, system), Fraction(-1)), pscale(sh.norm2, -_EPS),
                  pmul(lam, padd(V, {zero: Fraction(-1)})), pscale(pmul(mu, box), Fraction(-1)))
    sig_Q = _project(sh.sig_basis, _rgram(sig_var), target)
    sv_Q = _project(sh.vq_basis, _rgram(sv_var), padd(V, pscale(sh.norm2, -_GAMMA)))
    if sig_Q is None or sv_Q is None:
        return None
    cert = {"format": FORMAT, "version": 1, "kind": "local-continuous",
            "state_map": system.map_text(), "states": list(system.states),
            "V": poly_to(V), "c": "1", "U": str(U), "epsilon": str(_EPS),
            "gamma": str(_GAMMA),
            "multipliers": {"mu": gram_to(sh.mu_basis, mu_Q), "lambda": poly_to(lam),
                            "sigma": gram_to(sh.sig_basis, sig_Q),
                            "sigma_V": gram_to(sh.vq_basis, sv_Q)}}
    return cert, lam, mu


def _rounds(system: PolySystem, sh: _Shape, V: Poly, U_best: Fraction
            ) -> tuple[list[dict[str, Any]], int]:
    """The V-lambda rounds from V (level 1, verified at U_best): the proposals (rounded,
    not yet checked) and the number of SDPs solved."""
    start = _m_step(system, sh, V, U_best)
    solves = 1
    if start is None:
        return [], solves
    _, lam, mu = start
    found: list[dict[str, Any]] = []
    for _ in range(ROUNDS):
        step = _v_step(system, sh, lam, mu)
        solves += 1
        if step is None or step[1] <= float(U_best) ** 2:
            break
        V, t = step
        top = float(np.sqrt(t))
        lo, hi = float(U_best), top
        gained = Fraction(0)
        for k in range(STEPS):
            # just inside the V step's optimum first: its boundary would not survive rounding
            U = _r(top * _BACKOFF if k == 0 else (lo + hi) / 2)
            found_k = _m_step(system, sh, V, U)
            solves += 1
            if found_k is not None:
                found.append(found_k[0])
                gained = U / U_best - 1
                U_best, lam, mu = U, found_k[1], found_k[2]
                break
            hi = float(U)
        if gained < GAP:
            break
    return found, solves


def _seed(V: Poly) -> Poly:
    """(V + SEED V^2) / (1 + SEED): the same set {V <= 1} (the map is increasing), with
    quartic terms, so the multipliers found for it leave the V step room to reshape them
    (from a quadratic V alone, lambda's quadratic part may be indefinite, and no quartic
    term of V is then feasible): the second start, when the first made no proposal."""
    W = pscale(padd(V, pscale(pmul(V, V), SEED)), 1 / (1 + SEED))
    return {k: _r(float(c)) for k, c in W.items() if _r(float(c))}


def improve(system: PolySystem, certificate: dict[str, Any]
            ) -> tuple[dict[str, Any] | None, int]:
    """A verified certificate with a larger U than ``certificate``'s, or None.

    Parameters
    ----------
    system : PolySystem
        A continuous-time system.
    certificate : dict
        A verified ``local-continuous`` certificate with a quadratic V (the start).

    Returns
    -------
    (dict or None, int)
        The best exactly re-checked certificate found with a larger U (None if none),
        and the number of SDPs solved.
    """
    sh = _Shape(system, DEGREE)
    if sh.size() > MAX_GRAM:
        sh = _Shape(system, DEGREE, structured=True)
    if system.discrete or sh.size() > MAX_GRAM:
        return None, 0
    nv = sh.nv
    c0 = Fraction(certificate["c"])
    V = {k: x / c0 for k, x in poly_from(certificate["V"], nv).items()}
    U0 = Fraction(certificate["U"])
    found: list[dict[str, Any]] = []  # proposals
    solves = 0
    for start in (V, _seed(V)) if SEED else (V,):
        props, k = _rounds(system, sh, start, U0)
        found += props
        solves += k
        if props:
            break
    for cert in sorted(found, key=lambda c: -Fraction(c["U"])):  # the largest U first
        if check_dict(system, cert) == "":
            return cert, solves
    return None, solves
