"""The static map and a proven upper bound on the true radius of the norm series.

Three numbers describe how far the norm series sum_n ||H_n|| r^n converges:

* ``radius`` (elsewhere, :mod:`gfrf.bounds.majorant`): r*, a proven *lower* bound on its radius.
* :func:`radius_upper`: a proven *upper* bound, from the zero-frequency kernels.  At
  zero frequency (s = 0, or q = 1 for a NARX model) every derivative factor vanishes
  (every lag is the same value), so H_n(0, .., 0) = c_n are the Taylor coefficients
  of the static input-output map: the branch y(u) with y(0) = 0 of the algebraic
  equation P(y, u) = 0 obtained by keeping the terms without derivatives.  Because
  ||H_n|| >= |c_n|, the true radius is at most the radius of sum c_n u^n, which is the
  modulus of the nearest singular point of that branch.  The bound is the modulus of
  a root sigma of the discriminant of P in y at which the branch is proven singular:
  the branch is tracked along the segment [0, sigma] in Arb ball arithmetic
  (Weierstrass root-inclusion discs, valid for every u of a ball covering a piece of
  the segment; the branch's disc meets no other, so it holds exactly one root; a
  fold of other sheets on the way does not matter), it is shown to enter a disc D
  around the double
  root y0 of P(., sigma) on whose boundary P(., u) has no zero for u on the rest of
  the segment, D holds exactly two roots at sigma, and P_u != 0 on D x {sigma}.  Were
  the branch analytic at sigma, y(sigma) = y0 and P_y y' + P_u = 0 there would force
  P_u(y0, sigma) = 0: so it is singular, and the radius is at most |sigma|.
* ``radius_estimate`` (:mod:`gfrf.stability.estimate`): an estimate of the true radius
  from many terms of a lower-bound series, clamped into [r*, radius_upper]: an
  estimate, never a proof.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> m = parse_model("y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]", sample_time=0.1)
>>> [float(c) for c in static_series(m, 3)]  # exact values of the float coefficients
[0.0, 2.0, 0.0, -1.6]
>>> round(radius_upper(m).value, 6)  # branch points at +-i sqrt(5/16)
0.559017
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from gfrf._results import Result
from gfrf.bounds.exact import arb_upper
from gfrf.model.equation import Model

__all__ = ["StaticBound", "static_series", "radius_upper",
           "loop_radius_upper"]

#: Most pieces of the segment the branch tracking may use (a work count, not a time).
MAX_TRACK_STEPS = 4000
#: Arb working precision (bits) of the branch tracking.
PRECISION = 128


@dataclass(frozen=True, kw_only=True)
class StaticBound(Result):
    """A proven upper bound on the true radius of the norm series.

    Attributes
    ----------
    value : float
        A float >= |sigma| (rounded up): the radius of the static series is at most it.
    branch_point : complex
        sigma, midpoint of its Arb enclosure.
    double_root : complex
        y0, the static output value at which the branch folds.
    exact : bool
        True when no other singular candidate is nearer than sigma, so the static
        series' radius equals |sigma| (not only is at most it).
    detail : str
        The proof in one sentence.
    """

    value: float
    branch_point: complex
    double_root: complex
    exact: bool
    detail: str

    def _computed(self) -> dict[str, Any]:
        return {"branch_point": [self.branch_point.real, self.branch_point.imag],
                "double_root": [self.double_root.real, self.double_root.imag]}


def _static_terms(model: Model) -> dict[tuple[int, int], Fraction] | None:
    """Exact coefficients {(i, j): c} of y^i u^j of the static equation P(y, u) = 0, as
    written in the model text (0.2 is 1/5); None when one of them is not rational."""
    out: dict[tuple[int, int], Fraction] = {}
    for t in model.terms:
        if not model.is_discrete and any(t.y_orders + t.u_orders):
            continue  # a derivative factor is zero at zero frequency
        key = (len(t.y_orders), len(t.u_orders))
        value = t.exact
        if value is None:
            return None
        out[key] = out.get(key, Fraction(0)) + value
    return {k: v for k, v in out.items() if v != 0}


def static_series(model: Model, n_max: int) -> list[Fraction]:
    """Exact Taylor coefficients c_0..c_{n_max} of the static branch y(u), y(0) = 0.

    c_n = H_n(0, .., 0) (s = 0 or q = 1), of the model as written (decimals as exact
    rationals).  Returns an empty list when the static map is not defined by the linear
    part (A(0) = 0: no finite static gain) or a static coefficient as written is irrational.

    Parameters
    ----------
    model : Model
        The plant model.
    n_max : int
        Highest coefficient, >= 0.

    Returns
    -------
    list of Fraction
        c_0..c_{n_max} (c_0 = 0), or ``[]``.
    """
    p = _static_terms(model)
    if p is None:
        return []
    a0 = p.get((1, 0), Fraction(0))
    if a0 == 0 or (0, 0) in p:  # no finite static gain, or a constant term (y(0) != 0)
        return []
    y = [Fraction(0)] * (n_max + 1)
    for n in range(1, n_max + 1):
        total = -p.get((0, 1), Fraction(0)) if n == 1 else Fraction(0)
        for (i, j), c in p.items():
            if i + j < 2 or j > n:
                continue
            total -= c * _power_coefficient(y, i, n - j)
        y[n] = total / a0
    return y


def _power_coefficient(y: list[Fraction], i: int, n: int) -> Fraction:
    """Coefficient of u^n in y(u)^i (y[0] = 0), from the known y[1..n-1]."""
    acc = [Fraction(1)] + [Fraction(0)] * n
    for _ in range(i):
        acc = [sum((acc[k] * y[m - k] for k in range(m)), Fraction(0)) for m in range(n + 1)]
    return acc[n]


def _coefficient_polys(p: dict[tuple[int, int], Fraction]) -> list[Any]:
    """fmpq_poly coefficients p_i(u) of y^i, i = 0..degree in y."""
    from flint import fmpq, fmpq_poly

    deg_y = max(i for i, _ in p)
    deg_u = max(j for _, j in p)
    rows = [[Fraction(0)] * (deg_u + 1) for _ in range(deg_y + 1)]
    for (i, j), c in p.items():
        rows[i][j] = c
    return [fmpq_poly([fmpq(c.numerator, c.denominator) for c in row]) for row in rows]


def _discriminant(polys: list[Any]) -> Any:
    """Discriminant in y of sum p_i(u) y^i (resultant of P and P_y over Q[u])."""
    import sympy as sp

    u, y = sp.symbols("u y")
    expr = sum(sp.Poly([sp.Rational(int(c.p), int(c.q)) for c in reversed(q.coeffs())] or [0],
                       u).as_expr() * y ** i for i, q in enumerate(polys))
    disc = sp.Poly(sp.resultant(expr, sp.diff(expr, y), y), u)
    from flint import fmpq, fmpq_poly

    coeffs = [sp.Rational(c) for c in reversed(disc.all_coeffs())]
    return fmpq_poly([fmpq(int(c.p), int(c.q)) for c in coeffs])


def _eval(q: Any, u: Any) -> Any:
    """fmpq_poly q at the acb ball u (Horner, outward rounded)."""
    from flint import acb

    acc = acb(0)
    for c in reversed(q.coeffs()):
        acc = acc * u + acb(c)
    return acc


def _eval_p(polys: list[Any], y: Any, u: Any) -> Any:
    from flint import acb

    acc = acb(0)
    for q in reversed(polys):
        acc = acc * y + _eval(q, u)
    return acc


def _derivative_u(polys: list[Any]) -> list[Any]:
    return [q.derivative() for q in polys]


def _segment(sigma: Any, a: float, b: float) -> Any:
    """An acb ball covering {t sigma : t in [a, b]}."""
    from flint import acb, arb

    return sigma * acb(arb((a + b) / 2, (b - a) / 2 * (1 + 1e-12)))


def _discs(polys: list[Any], u: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """Weierstrass inclusion discs (centres, radii) of the roots of P(., u) for every u
    in the ball ``u`` (their union holds every root, a connected component of m discs
    exactly m roots); None unless the leading coefficient excludes 0."""
    from flint import acb

    d = len(polys) - 1
    lead = _eval(polys[-1], u)
    low = float(lead.abs_lower())
    if d < 1 or not low > 0:
        return None
    mid = [complex(_eval(q, acb(u.mid()))) for q in polys]
    z = np.roots(mid[::-1])
    if z.size != d or not np.all(np.isfinite(z)):
        return None
    radii = np.empty(d)
    for j in range(d):
        prod = 1.0
        for k in range(d):
            if k != j:
                prod *= abs(z[j] - z[k])
        if prod == 0.0:
            return None
        value = _eval_p(polys, acb(complex(z[j])), u)
        radii[j] = d * arb_upper(value.abs_upper()) / (low * prod) * (1 + 1e-9)
    return z, radii


def _certify(polys: list[Any], sigma: Any) -> complex | None:
    """The double root y0 if the branch through (0, 0) is proven singular at sigma."""
    from flint import acb

    d = len(polys) - 1
    sigma_mid = complex(sigma.mid())
    at_sigma = np.roots([complex(_eval(q, acb(sigma_mid))) for q in polys][::-1])
    if at_sigma.size != d:
        return None
    gaps = {(j, k): abs(at_sigma[j] - at_sigma[k]) for j in range(d) for k in range(j)}
    pair = min(gaps, key=gaps.__getitem__)
    y0 = complex(0.5 * (at_sigma[pair[0]] + at_sigma[pair[1]]))
    others = [at_sigma[i] for i in range(d) if i not in pair]
    start = _start(polys, sigma)
    if start is None:
        return None
    t, delta = start
    h, steps = min(1.0 / 16, t), 0
    current = (0j, delta)
    while steps < MAX_TRACK_STEPS:
        steps += 1
        b = min(1.0, t + h)
        discs = _discs(polys, _segment(sigma, t, b)) if b < 1.0 else None
        linked = None if discs is None else _link(discs, current)
        if linked is None:
            h *= 0.5
            if h < 1e-14:
                return None
            continue
        current, t, h = linked, b, min(2 * h, 0.25)
        if t > 0.5 and _end_stage(polys, sigma, t, current, y0, others):
            return y0
    return None


def _start(polys: list[Any], sigma: Any) -> tuple[float, float] | None:
    """(t0, delta): for every u in [0, t0] sigma the branch is the only root of P(., u)
    in |y| < delta (Rouche at u = 0, no root on |y| = delta along the piece)."""
    from flint import acb, arb

    p1 = abs(float(polys[1].coeffs()[0])) if polys[1].coeffs() else 0.0
    higher = [abs(float(q.coeffs()[0])) if q.coeffs() else 0.0 for q in polys[2:]]
    delta = 1.0
    while p1 * delta <= 2 * sum(c * delta ** (i + 2) for i, c in enumerate(higher)):
        delta *= 0.5
        if delta < 1e-12:
            return None
    pieces = 256
    for k in range(1, 40):
        t0 = 2.0 ** -k
        piece = _segment(sigma, 0.0, t0)
        ok = True
        for j in range(pieces):
            angle = 2 * math.pi * (j + 0.5) / pieces
            half = delta * math.pi / pieces * 1.01
            ball = acb(delta * complex(math.cos(angle), math.sin(angle))) + acb(
                arb(0, half), arb(0, half))
            if _eval_p(polys, ball, piece).contains(0):
                ok = False
                break
        if ok:
            return t0, delta
    return None


def _link(discs: tuple[np.ndarray, np.ndarray],
          current: tuple[complex, float]) -> tuple[complex, float] | None:
    """The disc of this piece holding the tracked root: the only one meeting the last,
    and disjoint from every other disc (a component of one disc: exactly one root).
    Other roots' discs may overlap each other (a fold of other sheets is harmless)."""
    z, radii = discs
    c, r = current
    hits = [j for j in range(z.size) if abs(z[j] - c) <= radii[j] + r]
    if len(hits) != 1:
        return None
    j = hits[0]
    if any(abs(z[j] - z[k]) <= radii[j] + radii[k] for k in range(z.size) if k != j):
        return None
    return complex(z[j]), float(radii[j])


def _end_stage(polys: list[Any], sigma: Any, t: float, current: tuple[complex, float],
               y0: complex, others: list[complex]) -> bool:
    """Checks (2)-(4) of the module docstring for a disc D(y0, rho) from t to sigma."""
    from flint import acb, arb

    c, r = current
    d = len(polys) - 1
    rho = 2.0 * (abs(c - y0) + r)
    if not rho > 0 or any(abs(o - y0) <= 2 * rho for o in others):
        return False
    rest = _segment(sigma, t, 1.0)
    if not _eval(polys[-1], rest).abs_lower() > 0:
        return False
    pieces = 256
    for k in range(pieces):  # no root on the circle |y - y0| = rho for u on the rest
        point = y0 + rho * complex(math.cos(2 * math.pi * (k + 0.5) / pieces),
                                   math.sin(2 * math.pi * (k + 0.5) / pieces))
        ball = acb(point) + acb(arb(0, rho * math.pi / pieces * 1.01),
                                arb(0, rho * math.pi / pieces * 1.01))
        if _eval_p(polys, ball, rest).contains(0):
            return False
    eps = rho / (2 * (1 + d))  # two roots in D at sigma, the others simple outside D
    approx = [y0 + eps, y0 - eps, *others]
    lead_low = float(_eval(polys[-1], sigma).abs_lower())
    if not lead_low > 0:  # sigma is a zero of the leading coefficient: not a fold
        return False
    radii = []
    for j, zj in enumerate(approx):
        prod = math.prod(abs(zj - zk) for k, zk in enumerate(approx) if k != j)
        value = _eval_p(polys, acb(zj), sigma)
        radii.append(d * arb_upper(value.abs_upper()) / (lead_low * prod) * (1 + 1e-9))
    if any(abs(approx[j] - y0) + radii[j] >= rho for j in (0, 1)):
        return False
    for j in range(2, d):
        if abs(approx[j] - y0) - radii[j] <= rho:
            return False
        for k in range(2, j):
            if abs(approx[j] - approx[k]) <= radii[j] + radii[k]:
                return False
    disc_ball = acb(y0) + acb(arb(0, rho), arb(0, rho))
    return not _eval_p(_derivative_u(polys), disc_ball, sigma).contains(0)


def radius_upper(model: Model, shift: int = 0) -> StaticBound | None:
    """Proven upper bound on the true radius of sum ||H_n|| r^n from the static map.

    Parameters
    ----------
    model : Model
    shift : int
        Work on the amplitude-scaled map y = 2^shift Y, u = 2^shift U (exact on the
        rational coefficients: c_ij -> c_ij 2^(shift (i + j - 1))) and scale the branch
        point back; :func:`gfrf.bounds.radius_scaling.amplitude_shift` gives the shift
        that makes the problem O(1) (a cubic coefficient 5e27 puts the fold at 5e-15).

    Returns
    -------
    StaticBound or None
        None when the static map has no finite gain (A(0) = 0), is linear, has an
        irrational coefficient as written, or no
        candidate branch point could be proven singular within the work budget.
    """
    p = _static_terms(model)
    return None if p is None else _upper_of(p, "u", "||H_n|| >= |H_n(0,..,0)|", shift)


def loop_radius_upper(model: Model, gain: Fraction, feedback: int,
                      shift: int = 0) -> StaticBound | None:
    """Proven upper bound on the true radius, in units of the reference r, of the norm
    series of the closed loop u = C(r + feedback * y) with static controller gain C(0).

    At zero frequency the loop's kernels from r to y are the Taylor coefficients of the
    branch y(r) of P(y, C(0) (r + feedback y)) = 0 (P the plant's static equation), so
    the static fold of that map bounds the loop's true radius as :func:`radius_upper`
    bounds the plant's.  Exact: the substitution is done on the rational coefficients.

    Parameters
    ----------
    model : Model
        The plant.
    gain : Fraction
        The controller's static gain C(0) (finite).
    feedback : {-1, 1}
    shift : int
        As for :func:`radius_upper` (y = 2^shift Y, r = 2^shift R, exact).

    Returns
    -------
    StaticBound or None
        As :func:`radius_upper`; ``value`` is in units of r.

    Examples
    --------
    >>> from gfrf.model.equation import parse_model
    >>> m = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    >>> k = Fraction(1, 1000)  # (1+k) y + y^3/2 = k r: |r| = 2 sqrt(2) (1+k)^1.5 / (3 sqrt(3) k)
    >>> b = loop_radius_upper(m, k, -1)
    >>> abs(b.value - 2 * 2 ** 0.5 * 1.001 ** 1.5 / (3 * 3 ** 0.5 * 0.001)) < 1e-9 * b.value
    True
    """
    p = _static_terms(model)
    if p is None:
        return None
    loop: dict[tuple[int, int], Fraction] = {}
    for (i, j), c in p.items():
        for m in range(j + 1):  # (k r + k f y)^j = sum_m C(j, m) (k r)^m (k f y)^(j - m)
            key = (i + j - m, m)
            loop[key] = (loop.get(key, Fraction(0))
                         + c * math.comb(j, m) * gain ** j * Fraction(feedback) ** (j - m))
    loop = {k: v for k, v in loop.items() if v != 0}
    return _upper_of(loop, "r", "the loop's ||G_n|| >= |G_n(0,..,0)| (r to y)", shift) \
        if loop else None


def _upper_of(p: dict[tuple[int, int], Fraction], variable: str,
              why: str, shift: int = 0) -> StaticBound | None:
    """The proven static branch point of P(y, v) = sum p_ij y^i v^j = 0 (v = ``variable``),
    found on the map scaled by 2^shift in y and v and scaled back exactly."""
    from flint import ctx

    if p.get((1, 0), Fraction(0)) == 0 or (0, 0) in p or max(i for i, _ in p) < 2:
        return None
    p = {(i, j): c * Fraction(2) ** (shift * (i + j - 1)) for (i, j), c in p.items()}
    saved = ctx.prec
    ctx.prec = PRECISION
    try:
        polys = _coefficient_polys(p)
        disc = _discriminant(polys)
        if disc == 0:
            return None
        lead = polys[-1]
        candidates = [s for s, _ in disc.complex_roots()]
        if lead.degree() > 0:
            candidates += [s for s, _ in lead.complex_roots()]
        candidates = [s for s in candidates if not s.contains(0)]
        candidates.sort(key=lambda s: float(abs(s).mid()))
        if not candidates:
            return None
        nearest = float(abs(candidates[0]).abs_lower())
        for sigma in candidates:
            y0 = _certify(polys, sigma)
            if y0 is not None:
                value = math.ldexp(arb_upper(abs(sigma)), shift)
                exact = value <= math.ldexp(nearest, shift) * (1 + 1e-12)
                mid = complex(sigma.mid())
                s = complex(math.ldexp(mid.real, shift), math.ldexp(mid.imag, shift))
                y0 = complex(math.ldexp(y0.real, shift), math.ldexp(y0.imag, shift))
                return StaticBound(value=value, branch_point=s, double_root=y0, exact=exact,
                                   detail=f"static branch point {variable} = {_fmt(s)} "
                                   f"(|{variable}| = "
                                   f"{value:.6g}): the static branch y({variable}) folds at y = "
                                   f"{_fmt(y0)}, proven in ball arithmetic; {why}")
        return None
    finally:
        ctx.prec = saved


def _fmt(z: complex) -> str:
    if abs(z.imag) <= 1e-14 * abs(z):
        return f"{z.real:.6g}"
    if abs(z.real) <= 1e-14 * abs(z):
        return f"{z.imag:.6g}i"
    return f"{z.real:.6g}{z.imag:+.6g}i"
