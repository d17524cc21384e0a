"""A local energy certificate: an invariant sublevel set for every input below a size.

For a damped oscillator ``a2 y'' + c y' + g(y) + b u = 0`` (the class of
:mod:`gfrf.stability.energy`) whose restoring force softens (the pendulum), no
certificate holds for every amplitude, but a sublevel set of

    V = y'^2/2 + F(y) + eps*y*y',  F(y) = int_0^y f,  f = g/a2,

inside the potential well can be invariant for all inputs with sup|u| <= U.  Write
y'' = -k y' - f(y) + w (k = c/a2, w = -b u/a2).  Along solutions

    dV/dt = Wf(y, y') + (y' + eps*y) w,  Wf = -(k - eps) y'^2 - eps*k*y*y' - eps*y*f(y).

If the box B holds the origin, V > lev on the border of B, and every point of B with
V = lev has Wf + |y' + eps*y| W < 0, then the component of {V <= lev} holding the origin
lies in B and no solution from rest can leave it while |w| <= W: the state is bounded for
every input with sup|u| <= U = W |a2/b|, of any shape and duration (L-infinity), which
contains Theorem 1's class of size U (a sum of tones with sum of amplitudes U has sup
|u| <= U).  eps, lev and W are searched in floating point on rays from the origin; the
two conditions are then checked in Arb ball arithmetic (python-flint) on a recursive
subdivision of B (every ball operation encloses the exact value): the radius is proven
(``"interval"``).  The work is bounded by box counts, never by time.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from gfrf.model.equation import Model
from gfrf.stability.energy import Certificate, _structure, energy_certificate

__all__ = ["local_energy_certificate", "LOCAL_METHOD", "MAX_BOXES"]

#: The method name of the local certificate.
LOCAL_METHOD = "invariant sublevel set of V = E + eps*y*y' (every input with sup|u| <= U)"
#: Largest number of boxes examined by one proof attempt.
MAX_BOXES = 60_000
#: Smallest box side, relative to the box B, before a proof attempt gives up.
_MIN_SIDE = 2.0**-14
#: eps / k tried, and the fractions of the largest closed level tried.
_EPS = (Fraction(1, 20), Fraction(1, 10), Fraction(1, 5), Fraction(3, 10), Fraction(2, 5))
_LEVELS = np.linspace(0.05, 0.98, 32)
_RAYS = 720
#: Safety factors on the floating-point W tried for the proof, in order.
_SHRINK = (0.97, 0.9, 0.75)


class _Poly:
    """f as exact coefficients, V and Wf in floats (numpy) and in Arb balls."""

    def __init__(self, k: Fraction, f: dict[int, Fraction], eps: Fraction):
        self.k, self.f, self.eps = k, f, eps

    def v_float(self, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        # F = sum f_n y^(n+1) / (n+1) by Horner (array powers are slow library calls)
        coefficients = [0.0] * (max(self.f, default=0) + 2)
        for n, q in self.f.items():
            coefficients[n + 1] = float(q / (n + 1))
        F = np.zeros_like(y)
        for c in reversed(coefficients):
            F = F * y + c
        return p * p / 2 + F + float(self.eps) * y * p

    def w_float(self, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        k, e = float(self.k), float(self.eps)
        fy = sum(float(q) * y**n for n, q in self.f.items())
        return -(k - e) * p * p - e * k * y * p - e * y * fy

    def balls(self, y: object, p: object) -> tuple[object, object, object]:
        """(V, Wf, |p + eps*y|) as Arb balls over the balls y, p."""
        from flint import arb, fmpq

        def q(x: Fraction) -> object:
            return arb(fmpq(x.numerator, x.denominator))

        F = sum((q(c / (n + 1)) * y ** (n + 1) for n, c in self.f.items()), arb(0))
        fy = sum((q(c) * y**n for n, c in self.f.items()), arb(0))
        e, k = q(self.eps), q(self.k)
        V = p * p / 2 + F + e * y * p
        W = -(k - e) * p * p - e * k * y * p - e * y * fy
        return V, W, abs(p + e * y)


def _ray_levels(poly: _Poly, r_max: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Directions, radii grid, and the largest level whose sublevel set closes on every ray."""
    th = np.linspace(0, 2 * np.pi, _RAYS, endpoint=False)
    r = np.linspace(0, r_max, 2000)[1:]
    y, p = np.outer(np.cos(th), r), np.outer(np.sin(th), r)
    with np.errstate(all="ignore"):
        V = poly.v_float(y, p)
    # on each ray, V must rise to its first local maximum (the pass) or to r_max
    rising = np.diff(V, axis=1) > 0
    first_fall = np.where(~rising.all(axis=1), np.argmin(rising, axis=1), rising.shape[1])
    peak = V[np.arange(_RAYS), np.minimum(first_fall, V.shape[1] - 1)]
    return th, r, float(np.min(peak))


def _float_search(poly: _Poly, r_max: float) -> tuple[float, float]:
    """(level, W) maximising W on rays, for this eps."""
    th, r, top = _ray_levels(poly, r_max)
    if not top > 0:
        return 0.0, 0.0
    best = (0.0, 0.0)
    y, p = np.outer(np.cos(th), r), np.outer(np.sin(th), r)
    with np.errstate(all="ignore"):
        V = poly.v_float(y, p)
    for frac in _LEVELS:
        lev = frac * top
        idx = np.argmax(V >= lev, axis=1)  # first crossing on each ray
        yb, pb = y[np.arange(_RAYS), idx], p[np.arange(_RAYS), idx]
        wf = poly.w_float(yb, pb)
        gain = np.abs(pb + float(poly.eps) * yb)
        with np.errstate(all="ignore"):
            w = float(np.min(np.where(gain > 0, -wf / gain, np.inf)))
        if w > best[1]:
            best = (float(lev), w)
    return best


def _prove(poly: _Poly, lev: float, W: float, half: tuple[float, float]) -> bool:
    """Ball-arithmetic check of the two conditions on the box [-hy, hy] x [-hp, hp]."""
    from flint import arb

    hy, hp = half
    lev_b, W_b = arb(lev), arb(W)
    # 1. V > lev on the border of B
    n = 512
    for i in range(n):
        a = -1 + 2 * i / n
        ys = arb(hy * (a + 1 / n), hy / n)
        ps = arb(hp * (a + 1 / n), hp / n)
        for y, p in ((ys, arb(hp)), (ys, arb(-hp)), (arb(hy), ps), (arb(-hy), ps)):
            if not poly.balls(y, p)[0] > lev_b:
                return False
    # 2. Wf + |p + eps y| W < 0 wherever V = lev in B
    stack = [(0.0, 0.0, hy, hp)]
    boxes = 0
    while stack:
        cy, cp, ry, rp = stack.pop()
        boxes += 1
        if boxes > MAX_BOXES or ry < _MIN_SIDE * hy:
            return False
        V, Wf, gain = poly.balls(arb(cy, ry), arb(cp, rp))
        if V < lev_b or V > lev_b:
            continue
        if Wf + gain * W_b < 0:
            continue
        stack += [(cy + sy * ry / 2, cp + sp * rp / 2, ry / 2, rp / 2)
                  for sy in (-1, 1) for sp in (-1, 1)]
    return True


def local_energy_certificate(model: Model) -> Certificate | None:
    """A proven L-infinity radius U from an invariant sublevel set, or None.

    Parameters
    ----------
    model : Model
        A continuous model of the class ``a2 y'' + c y' + g(y) + b u = 0`` with c/a2 > 0
        and g'(0)/a2 > 0, for which :func:`gfrf.stability.energy.energy_certificate`
        does not apply (else that global certificate is the answer).

    Returns
    -------
    Certificate or None
        Radius U (sup|u| <= U keeps every solution from rest bounded), proof
        ``"interval"``; None outside the class or when no proof succeeded.

    Examples
    --------
    >>> from gfrf.model.equation import parse_model
    >>> c = local_energy_certificate(parse_model("D(y,2) + 0.5*D(y) + 2.45*y - 0.4*y**3 = u"))
    >>> 0.4 < c.radius < 2.31
    True
    """
    found = _structure(model)
    if isinstance(found, str) or energy_certificate(model) is not None:
        return None
    a2, c, g, b = found
    f = {n: q / a2 for n, q in g.items() if q != 0}
    k = c / a2
    if b == 0 or not (k > 0 and f.get(1, Fraction(0)) > 0):
        return None
    gain = abs(a2 / b)
    # the well's scale: the smallest positive root of f(y)/y or f(-y)/y, else 10/sqrt(f1)
    coeffs = [float(f.get(n, 0)) for n in range(max(f), 0, -1)]
    roots = [abs(z) for z in np.roots(coeffs) if abs(z.imag) < 1e-9 * max(1, abs(z))] \
        if len(coeffs) > 1 else []
    r_max = 3.0 * max([x for x in roots if x > 0], default=10.0 / math.sqrt(float(f[1])))
    r_max *= max(1.0, math.sqrt(float(f[1])))
    tried = []
    for ratio in _EPS:
        eps = k * ratio
        if float(eps) ** 2 >= float(f[1]):
            continue
        poly = _Poly(k, f, eps)
        lev, W = _float_search(poly, r_max)
        if W > 0:
            tried.append((W, lev, eps, poly))
    for W, lev, eps, poly in sorted(tried, key=lambda t: -t[0])[:2]:
        th, r, _ = _ray_levels(poly, r_max)
        y, p = np.outer(np.cos(th), r), np.outer(np.sin(th), r)
        inside = poly.v_float(y, p) <= lev
        reach = np.where(inside.all(axis=1), r[-1], r[np.argmin(inside, axis=1)])
        half = (1.25 * float(np.max(np.abs(np.cos(th)) * reach)),
                1.25 * float(np.max(np.abs(np.sin(th)) * reach)))
        for shrink in _SHRINK:
            w_try = W * shrink
            if _prove(poly, lev, w_try, half):
                U = w_try * float(gain)
                detail = (f"V = y'^2/2 + F(y) + eps*y*y' with eps = {float(eps):.6g}, the "
                          f"component of V <= {lev:.6g} holding the origin (inside |y| <= "
                          f"{half[0]:.4g}, |y'| <= {half[1]:.4g}, V > level on that box's "
                          f"border) is invariant for |w| <= {w_try:.6g}: dV/dt < 0 on its "
                          "boundary, checked in Arb ball arithmetic on a box subdivision")
                return Certificate(method=LOCAL_METHOD, radius=U, proof="interval",
                                   input_class="every input u(t) with sup|u| <= U "
                                   "(L-infinity), from rest; contains Theorem 1's class of "
                                   "size U", detail=detail,
                                   property="bounded: every solution from rest stays in the "
                                   "invariant set {V <= level}; not: returns to the "
                                   "equilibrium")
    return None
