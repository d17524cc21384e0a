"""The search of an invariant polygon for a second-order implicit loop (a proposal that
:func:`gfrf.stability.implicit_check.check_region` then re-verifies exactly).

For the loop D(y) y'' + R(y, y', d) = 0 (:mod:`gfrf.stability.implicit`) and a bound U:

* the equilibria y_+ and y_- under the constant inputs d = +U and d = -U are found on
  the axis y' = 0 (bisection between 0 and the nearest zero y_D of D);
* the upper chain is a trajectory, in the rescaled time of g = (q v, -s R) (polynomial,
  no singularity), of the *outward-biased worst field*: the d = +-U that maximises v'
  at each point, its direction turned outward by a small angle (scaled down where q is
  below ``TURN_FLOOR`` q(0), so that the chain cannot cross the singular line, which is
  invariant for g) and lifted by a constant that moves its equilibrium beyond y_+; it
  starts at (y_L, eta) left of y_- and stops where it reaches v = 0 right of y_+; the
  lower chain is the mirror construction from (y_R, -eta) right of y_+ with the d that
  minimises v';
* y_L and y_R start half-way between y_-+ and the singular set and move outward, to
  ``GAMMA`` of the distance to the singular set at which the opposite chain ended, until
  each chain ends inside the other's start (at most ``ROUNDS`` rounds): near the singular
  set the loop is fast and a swing from y_L reaches nearly as far on the other side;
* the two chains, sampled by arc length and turning angle, are the polygon.  A true
  solution under any |d| <= U crosses a biased trajectory only inward; the bias pays
  for the chords.

A polygon is kept only when |D| >= ``level`` |D(0)| on it (the level the falsifier's
escape is defined by), so that the lower and the upper side speak of one property.
The largest U is found by bisection between a proven value and ``U_hi`` on a fixed
grid of bias parameters.  The work is bounded by counts (bisection steps, parameter
sets, rounds, vertices, the integrator's step cap), never by time.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf.stability.implicit import SINGULAR_LEVEL, ImplicitLoop
from gfrf.stability.implicit_check import FORMAT, KIND, check_region, polygon_parts

__all__ = ["region_certificate", "certificate_at", "LoopField", "VERTICES", "BISECTIONS",
           "PARAMETERS"]

#: Vertices per chain.
VERTICES = 500
#: Bisection steps on U.
BISECTIONS = 8
#: (turn angle, where the biased equilibrium lies as a fraction of (y_R - y_+), eta as a
#: fraction of max |v|).
PARAMETERS = tuple(itertools.product((1e-4,), (0.4, 0.2), (1e-3,)))
#: Rounds of moving y_L, y_R outward, and how far beyond a chain's end they move.
ROUNDS, GAMMA = 8, 0.5
#: Below this fraction of q(0) the turn angle shrinks with q.
TURN_FLOOR = 1e-3
#: Steps of the chain integration at most.
MAX_STEPS = 200_000
_ROUND = 2**44


class LoopField:
    """q, -s R0, -s R1 of a second-order implicit loop evaluated in floats (estimates:
    for the search and for simulation, never for the check).

    Parameters
    ----------
    form : ImplicitLoop
        The loop; ValueError when it does not fit (see
        :func:`gfrf.stability.implicit_check.polygon_parts`).
    """

    def __init__(self, form: ImplicitLoop):
        q, r0, r1 = polygon_parts(form)
        self.q = [(k[0], float(c)) for k, c in q.items()]
        self.r0 = [(k, float(c)) for k, c in r0.items()]
        self.r1 = [(k, float(c)) for k, c in r1.items()]

    def qf(self, y: float) -> float:
        """q(y) = s D(y) (positive near the equilibrium) at the output value ``y``.

        Parameters
        ----------
        y : float
            The output value.

        Returns
        -------
        float
        """
        return sum(c * y**i for i, c in self.q)

    def g0(self, y: float, v: float) -> float:
        """-s R(y, v, 0) at the state (y, v = y').

        Parameters
        ----------
        y, v : float
            The state: output and its derivative.

        Returns
        -------
        float
        """
        return sum(c * y**i * v**j for (i, j), c in self.r0)

    def g1(self, y: float, v: float) -> float:
        """The coefficient of d in -s R at the state (y, v = y').

        Parameters
        ----------
        y, v : float
            The state: output and its derivative.

        Returns
        -------
        float
        """
        return sum(c * y**i * v**j for (i, j), c in self.r1)

    def singular(self) -> tuple[float, float]:
        """(nearest zero of q left of 0, right of 0); +-inf when none within 1e6."""
        out = []
        for sgn in (-1.0, 1.0):
            hi = 1.0
            while self.qf(sgn * hi) > 0 and hi < 1e6:
                hi *= 2
            if self.qf(sgn * hi) > 0:
                out.append(sgn * math.inf)
                continue
            lo = 0.0
            for _ in range(80):
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if self.qf(sgn * mid) > 0 else (lo, mid)
            out.append(sgn * lo)
        return out[0], out[1]

    def equilibrium(self, U: float, sgn: int, edge: float) -> float | None:
        """The first root of g0 + sgn U g1 on the axis v = 0 from 0 towards ``edge``.

        Parameters
        ----------
        U : float
            The input bound.
        sgn : int
            The sign of the constant input d = sgn U.
        edge : float
            Where to stop looking (a zero of q, or +-inf).

        Returns
        -------
        float or None
            The root, or None when there is none before ``edge``.
        """
        f = [self.g0(0, 0) + sgn * U * self.g1(0, 0)]
        if not math.isfinite(edge):
            return None
        ys = np.linspace(0, edge, 4001)[1:]
        prev = f[0] if f[0] != 0 else sgn * 1.0
        for a, b in zip(np.concatenate(([0.0], ys[:-1])), ys, strict=True):
            val = self.g0(b, 0) + sgn * U * self.g1(b, 0)
            if (val > 0) != (prev > 0):
                lo, hi = a, b
                for _ in range(80):
                    mid = (lo + hi) / 2
                    vm = self.g0(mid, 0) + sgn * U * self.g1(mid, 0)
                    lo, hi = (mid, hi) if (vm > 0) == (prev > 0) else (lo, mid)
                return lo
            prev = val
        return None


def _chain(fl: LoopField, U: float, start: tuple[float, float], sgn: int, angle: float,
           lift: float, scale: tuple[float, float]) -> np.ndarray | None:
    from scipy.integrate import solve_ivp

    Y, V = scale
    q0 = fl.qf(0.0)

    def rhs(_t: float, x: np.ndarray) -> list[float]:
        y, v = float(x[0]), float(x[1])
        qy = fl.qf(y)
        turn = angle * min(1.0, qy / (TURN_FLOOR * q0))
        ca, sa = math.cos(turn), math.sin(turn)
        g2 = fl.g0(y, v) + sgn * U * abs(fl.g1(y, v))
        a, b = qy * v / Y, g2 / V
        return [(ca * a - sa * b) * Y, (sa * a + ca * b) * V + sgn * lift]

    def cross(_t: float, x: np.ndarray) -> float:
        return float(x[1])

    cross.terminal = True  # type: ignore[attr-defined]
    cross.direction = -sgn  # type: ignore[attr-defined]
    with np.errstate(all="ignore"):
        sol = solve_ivp(rhs, (0.0, 1e6), list(start), method="LSODA", rtol=1e-10, atol=1e-13,
                        events=cross, dense_output=True)
    if sol.status != 1 or not np.all(np.isfinite(sol.y)):
        return None
    tt = np.linspace(sol.t[0], sol.t[-1], 40 * VERTICES + 1)
    X = sol.sol(tt).T
    # vertices equally spaced in arc length plus turning angle (the chords' error)
    dX = np.diff(X / np.array([Y, V]), axis=0)
    seg = np.linalg.norm(dX, axis=1)
    turn_k = np.abs(np.diff(np.unwrap(np.arctan2(dX[:, 1], dX[:, 0])), prepend=0.0))
    turn_k[0] = 0.0
    measure = seg + turn_k * seg.sum() / max(float(turn_k.sum()), 1e-300)
    arc = np.concatenate(([0.0], np.cumsum(measure)))
    idx = np.unique(np.clip(np.searchsorted(arc, np.linspace(0, arc[-1], VERTICES)), 0,
                            len(X) - 1))
    pts = X[idx]
    pts[-1] = X[-1]
    pts[-1, 1] = 0.0
    return pts


def _polygon(fl: LoopField, U: float, sing: tuple[float, float], params: tuple[float, ...]
             ) -> list[tuple[float, float]] | None:
    angle, mfrac, eta = params
    yp = fl.equilibrium(U, 1, sing[1])
    ym = fl.equilibrium(U, -1, sing[0])
    if yp is None or ym is None or not yp > 0 > ym:
        return None
    yL, yR = (ym + sing[0]) / 2, (yp + sing[1]) / 2
    for _ in range(ROUNDS):
        ys_r, ys_l = yp + (yR - yp) * mfrac, ym + (yL - ym) * mfrac
        lift_u = -(fl.g0(ys_r, 0) + U * abs(fl.g1(ys_r, 0)))
        lift_l = fl.g0(ys_l, 0) - U * abs(fl.g1(ys_l, 0))
        if not (lift_u > 0 and lift_l > 0):
            return None
        Y = max(abs(yL), abs(yR))
        first = _chain(fl, U, (yL, 1e-3), 1, 0.0, lift_u, (Y, 1.0))
        if first is None:
            return None
        V = float(np.max(np.abs(first[:, 1])))
        up = _chain(fl, U, (yL, eta * V), 1, angle, lift_u, (Y, V))
        lo = _chain(fl, U, (yR, -eta * V), -1, angle, lift_l, (Y, V))
        if up is None or lo is None or not (sing[0] < lo[-1, 0] and up[-1, 0] < sing[1]):
            return None
        if up[-1, 0] < yR and lo[-1, 0] > yL:
            return [(float(a), float(b)) for a, b in np.concatenate((up, lo))]
        yR = max(yR, sing[1] - (sing[1] - up[-1, 0]) * GAMMA)
        yL = min(yL, sing[0] + (lo[-1, 0] - sing[0]) * GAMMA)
    return None


def _sampled_ok(fl: LoopField, U: float, P: list[tuple[float, float]]) -> bool:
    """The level and the edge condition on 5 points per edge (floats: a filter before the
    exact check)."""
    A = np.array(P)
    q0 = fl.qf(0.0)
    if min(fl.qf(float(y)) for y in np.linspace(A[:, 0].min(), A[:, 0].max(), 201)) \
            <= 1.01 * float(SINGULAR_LEVEL) * q0:
        return False
    B = np.roll(A, -1, axis=0)
    for t in np.linspace(0, 1, 5):
        X = A + t * (B - A)
        e = B - A
        for (y, v), (ey, ev) in zip(X, e, strict=True):
            val = -ev * fl.qf(y) * v + ey * fl.g0(y, v)
            if val + U * abs(ey * fl.g1(y, v)) >= 0:
                return False
    return True


def _exact(form: ImplicitLoop, U: float, P: list[tuple[float, float]]
           ) -> dict[str, Any] | None:
    Ur = Fraction(U).limit_denominator(2**20)
    verts = [[str(Fraction(round(y * _ROUND), _ROUND)), str(Fraction(round(v * _ROUND), _ROUND))]
             for y, v in P]
    cert = {"format": FORMAT, "version": 1, "kind": KIND, "states": list(form.states),
            "input": form.input_name, "U": str(Ur), "level": str(SINGULAR_LEVEL),
            "vertices": verts}
    return cert if check_region(form, cert) == "" else None


def certificate_at(form: ImplicitLoop, U: float) -> dict[str, Any] | None:
    """An exactly verified invariant polygon for the bound U, or None.

    Parameters
    ----------
    form : ImplicitLoop
        A second-order implicit loop.
    U : float
        The input bound.

    Returns
    -------
    dict or None
        The certificate (``check_region`` passed).
    """
    fl = LoopField(form)
    return _try(form, fl, U, fl.singular())[0]


def _try(form: ImplicitLoop, fl: LoopField, U: float, sing: tuple[float, float]
         ) -> tuple[dict[str, Any] | None, int]:
    tried = 0
    for params in PARAMETERS:
        P = _polygon(fl, U, sing, params)
        tried += 1
        if P is not None and _sampled_ok(fl, U, P):
            cert = _exact(form, U, P)
            if cert is not None:
                return cert, tried
    return None, tried


def region_certificate(form: ImplicitLoop, U_hi: float
                       ) -> tuple[dict[str, Any] | None, int]:
    """The largest-U exactly verified invariant polygon found below ``U_hi``.

    Parameters
    ----------
    form : ImplicitLoop
        A second-order implicit loop (D of y alone, R affine in d).
    U_hi : float
        Where to stop: an input bound known to fail (a witness), or a search cap.

    Returns
    -------
    (dict or None, int)
        The certificate (``check_region`` passed) and the number of polygons built.
    """
    try:
        fl = LoopField(form)
    except ValueError:
        return None, 0
    sing = fl.singular()
    best: dict[str, Any] | None = None
    work = 0
    lo, hi = 0.0, float(U_hi)
    U = hi / 2
    # halve from U_hi / 2 until one passes, then bisect between it and the last failure
    for _ in range(14):
        cert, k = _try(form, fl, U, sing)
        work += k
        if cert is not None:
            best, lo = cert, U
            break
        hi, U = U, U / 2
    if best is None:
        return None, work
    for _ in range(BISECTIONS):
        U = (lo + hi) / 2
        cert, k = _try(form, fl, U, sing)
        work += k
        if cert is not None:
            best, lo = cert, U
        else:
            hi = U
    return best, work
