"""The global sum-of-squares certificate: bounded for every bounded input.

For a continuous system x' = f0(x) + v b(x) (affine in the input), search V of degree 2
or 4 with V - g|x|^2 SOS and -grad V . f0 - g|x|^2 SOS (one SDP, V's coefficients are
variables), then, V fixed, -W - a G^2 - a|x|^2 + C SOS with W = grad V . f0 and
G = grad V . b: dV/dt <= -a|x|^2 + C + U^2 / (4a) for |v| <= U, negative outside a ball,
for every U.  Degree-4 terms of V are kept to the states the input does not drive, so G
stays linear.  Every proposal is re-checked exactly
(:func:`gfrf.stability.sos_check.check_dict`).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from gfrf.stability.polysys import PolySystem, padd, pdegree, pdiff, pmul, pscale
from gfrf.stability.sos_check import FORMAT, check_dict, gram_to, poly_to
from gfrf.stability.sos_core import (
    _GLOBAL,
    SosResult,
    _monomials,
    _Program,
    _project,
    _r,
    _rgram,
)

__all__ = ["global_certificate"]


def global_certificate(system: PolySystem) -> tuple[SosResult | None, int]:
    """A global certificate (every bounded input), exactly re-checked, or None.

    V of degree 2 or 4 with V - g|x|^2 SOS and -dV/dt|_{v=0} - g|x|^2 SOS, then the
    input's share: -W - a G^2 - a |x|^2 + C SOS (exactly checked).

    Parameters
    ----------
    system : PolySystem
        The system; a discrete one or one not affine in the input gets ``None`` without
        any solve.

    Returns
    -------
    SosResult or None
        The exactly re-checked certificate (``radius`` infinite), or None when no
        candidate passed.
    int
        The number of SDP solves made.
    """
    if system.discrete or not system.affine_in_input():
        return None, 0
    n = system.n
    nv = n + 1
    zero = (0,) * nv
    f0 = [{k: c for k, c in p.items() if k[-1] == 0} for p in system.f]
    b = [{k[:-1] + (0,): c for k, c in p.items() if k[-1] == 1} for p in system.f]
    df = max(pdegree(p) for p in f0)
    norm2 = {tuple(2 * int(j == i) for j in range(nv)): Fraction(1) for i in range(n)}
    solves = 0
    for dV in (2, 4):
        import cvxpy as cp

        # terms of degree > 2 only in states the input does not drive: G = grad V . b
        # stays linear, so a G^2 is dominated by the quadratic decay
        driven = {i for i in range(n) if b[i]}
        vb = [k for k in _monomials(nv, range(2, dV + 1), 0, xonly=True)
              if sum(k) == 2 or not any(k[i] for i in driven)]
        a = cp.Variable(len(vb))
        # V - g|x|^2 = sigma_V ;  -grad V . f0 - g|x|^2 = sigma_1
        gamma = Fraction(1, 100)
        prog = _Program()
        prog.parts.append(({(prog._row(k), j): 1.0 for j, k in enumerate(vb)}, a))
        prog.constant(norm2, -float(gamma))
        hb = [k for k in _monomials(nv, range(1, dV // 2 + 1), 0, xonly=True)
              if sum(k) == 1 or not any(k[i] for i in driven)]
        QV = prog.gram(hb, {zero: Fraction(1)}, -1.0)
        prog2 = _Program()
        entries: dict[tuple[int, int], float] = {}
        for j, k in enumerate(vb):
            Vk = {k: Fraction(1)}
            for i in range(n):
                for t, c in pmul(pdiff(Vk, i), f0[i]).items():
                    key = (prog2._row(t), j)
                    entries[key] = entries.get(key, 0.0) - float(c)
        prog2.parts.append((entries, a))
        prog2.constant(norm2, -float(gamma))
        deg = dV - 1 + df
        hb2 = _monomials(nv, range(1, (deg + deg % 2) // 2 + 1), 0, xonly=True)
        prog2.gram(hb2, {zero: Fraction(1)}, -1.0)
        ok = _solve_joint(prog, prog2)
        solves += 1
        if not ok:
            continue
        V = {k: _r(x) for k, x in zip(vb, np.asarray(a.value), strict=True) if _r(x)}
        sV = _project(hb, _rgram(QV), padd(V, pscale(norm2, -gamma)))
        if sV is None:
            continue
        W = padd(*(pmul(pdiff(V, i), f0[i]) for i in range(n)))
        G = padd(*(pmul(pdiff(V, i), b[i]) for i in range(n)))
        for alpha in (Fraction(1, 10), Fraction(1, 100), Fraction(1, 1000)):
            target = padd(pscale(W, Fraction(-1)), pscale(pmul(G, G), -alpha),
                          pscale(norm2, -alpha))
            D = max(pdegree(target), 2)
            D += D % 2
            sb = _monomials(nv, range(D // 2 + 1), 0, xonly=True)
            for _ in range(3):  # drop basis monomials the solver leaves at zero
                p3 = _Program()
                p3.constant(target, 1.0)
                Qs = p3.gram(sb, {zero: Fraction(1)}, -1.0)
                solves += 1
                if not p3.solve(skip=zero):
                    break
                diag = np.diag(Qs.value)
                keep = diag > 1e-7 * max(float(np.max(diag)), 1e-300)
                if keep.all():
                    break
                sb = [m for m, k in zip(sb, keep, strict=True) if k]
            if Qs.value is None:
                continue
            sQ = _project(sb, _rgram(Qs), target, free_constant=True)
            if sQ is None:
                continue
            cert = {"format": FORMAT, "version": 1, "kind": "global-continuous",
                    "state_map": system.map_text(), "states": list(system.states),
                    "V": poly_to(V), "gamma": str(gamma), "alpha": str(alpha),
                    "multipliers": {"sigma_V": gram_to(hb, sV), "sigma": gram_to(sb, sQ)}}
            if check_dict(system, cert) == "":
                return SosResult(radius=math.inf, kind="global-continuous", certificate=cert,
                                 solves=solves, property=_GLOBAL), solves
    return None, solves


def _solve_joint(p1: _Program, p2: _Program) -> bool:
    """Solve two coefficient-matching programs sharing variables together."""

    cp = p1.cp
    cons = []
    for prog in (p1, p2):
        expr, bvec = prog.residual()
        cons.append(expr + bvec == 0)
    prob = cp.Problem(cp.Minimize(0), cons)
    try:
        prob.solve(solver="CLARABEL")
    except cp.error.SolverError:
        return False
    return prob.status == "optimal"
