"""A proven escape for an implicit loop (:mod:`gfrf.stability.implicit`): the solution
from rest under a constant witness d = +-U, enclosed in Arb balls until |D| has reached
the loop's breakdown level (:data:`gfrf.stability.implicit.SINGULAR_LEVEL` |D(0)|).

The loop's own field y'' = -R / D is rational; the enclosure runs on the polynomial
field of the rescaled time dtau = dt q0 SCALE / q(y) (q = s D, q0 = q(0), positive until
the level is reached):

    y' = q v / (q0 SCALE),   v' = -s R(y, v, d) / (q0 SCALE),   t' = q / (q0 SCALE),

the same trajectory, with the real time t carried as a third state so that the time of
the escape is enclosed too.  It is the interval Taylor method with a rigorous remainder
and Lohner's QR step of :mod:`gfrf.twosided.lohner` (the field, a priori enclosure and
Taylor series of :mod:`gfrf.twosided.enclose`), order ``ORDER``, exact coefficients.
The escape is proven when the enclosure of y has passed +-y_level, points where
q <= level q0 holds exactly (checked in rationals): y is continuous from 0, so the
solution went through one of them.  Work is bounded by step counts, never by time.
"""

from __future__ import annotations

import math
from fractions import Fraction

from gfrf.stability.implicit import SINGULAR_LEVEL, ImplicitLoop
from gfrf.stability.implicit_check import polygon_parts
from gfrf.twosided.enclose import Enclosure, Monomials

__all__ = ["enclose_implicit_witness", "ORDER", "MAX_STEPS", "SCALE", "METHOD"]

#: Taylor order of a step, working precision (bits), longest step (rescaled time).
ORDER, BITS, LONGEST = 12, 64, 0.125
#: Time scaling of the rescaled field (longer steps in tau for the same dynamics).
SCALE = 4
#: Taylor steps (tried, halved ones included) at most.
MAX_STEPS = 3_000
MIN_STEP = 2.0**-40
#: The method in words.
METHOD = (f"interval Taylor enclosure in Arb balls of the loop in the rescaled time "
          f"dt = |D(y)| / |D(0)| dtau / {SCALE} (a polynomial field; order {ORDER}, "
          "Lagrange remainder, Lohner's QR step)")


def _level_point(q: dict[tuple[int, int], Fraction], sign: int) -> Fraction | None:
    """A rational y of the given sign, the first (to 2^-60) where q(y) <= level q(0)."""
    q0 = q.get((0, 0), Fraction(0))

    def qv(y: Fraction) -> Fraction:
        return sum((c * y**i for (i, _), c in q.items()), Fraction(0))

    target = SINGULAR_LEVEL * q0
    hi = Fraction(sign)
    for _ in range(40):
        if qv(hi) <= target:
            break
        hi *= 2
    else:
        return None
    lo = Fraction(0)
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if qv(mid) > target else (lo, mid)
    y = Fraction(float(hi))  # a double: the level a box is compared with
    while qv(y) > target:
        y = Fraction(math.nextafter(float(y), math.copysign(math.inf, sign)))
    return y


def enclose_implicit_witness(form: ImplicitLoop, amplitude: float, first_sign: int,
                             switch_times: tuple[float, ...], t_escape: float
                             ) -> Enclosure | None:
    """Enclose the escape of a constant witness d = first_sign * amplitude, or None.

    Parameters
    ----------
    form : ImplicitLoop
        A second-order implicit loop with q of y alone and R affine in d.
    amplitude : float
        U (its exact double is the input).
    first_sign : int
        +1 or -1.
    switch_times : tuple of float
        Must be empty (a switch in real time is not a step boundary of the rescaled time).
    t_escape : float
        The simulated escape time (s), which sets the horizon (1.5 times its rescaled time).

    Returns
    -------
    Enclosure or None
        None when the witness switches or the loop does not fit; else ``proven`` says
        whether the enclosure passed the level.
    """
    from flint import arb, ctx

    from gfrf.twosided.enclose import _apriori, _Field, _series
    from gfrf.twosided.lohner import LohnerSet, lohner_step

    if switch_times:
        return None
    try:
        q, r0, r1 = polygon_parts(form)
    except ValueError:
        return None
    q0 = q.get((0, 0), Fraction(0))
    ends = [_level_point(q, s) for s in (1, -1)]
    finite = [abs(y) for y in ends if y is not None]
    if not q0 > 0 or not finite:
        return None
    y_level = max(finite)
    k = Fraction(1) / (q0 * SCALE)
    row_y: Monomials = [(c * k, (i, 1, 0, 0)) for (i, _), c in q.items()]
    row_v: Monomials = [(c * k, (i, j, 0, 0)) for (i, j), c in r0.items()]
    row_v += [(c * k, (i, j, 0, 1)) for (i, j), c in r1.items()]
    row_t: Monomials = [(c * k, (i, 0, 0, 0)) for (i, _), c in q.items()]
    rows = [row_y, row_v, row_t]
    horizon = 1.5 * _rescaled_time(form, amplitude * first_sign, t_escape)
    old = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = BITS, ORDER + 1
    try:
        field = _Field(3, rows, [])
        field.u_const = arb(first_sign * amplitude)
        S = LohnerSet.of_box([arb(0)] * 3)
        t, step, steps = arb(0), LONGEST, 0
        ylev = arb(float(y_level))
        while steps < MAX_STEPS and float(t.mid()) < horizon:
            h = arb(step)
            nxt = lohner_step(field, S, h, ORDER, _apriori, _series)
            steps += 1
            if nxt is None:
                if step / 2 < MIN_STEP:
                    break
                step /= 2
                continue
            S, t, step = nxt, t + h, min(LONGEST, 2 * step)
            X = S.hull()
            if abs(X[0]) > ylev:
                return Enclosure(proven=True, t_proven=float(X[2].upper()), steps=steps,
                                 precision=BITS, width=max(float(x.rad()) for x in X),
                                 reason=f"|y| > {abs(float(y_level))!r} (|D(y)| <= "
                                        f"{float(SINGULAR_LEVEL):g} |D(0)| there)",
                                 method=METHOD)
            if not all(math.isfinite(float(x.rad())) and x.rad() < 1e-3 for x in X):
                break
        return Enclosure(proven=False, t_proven=None, steps=steps, precision=BITS,
                         width=0.0, reason="the enclosure did not pass the level within "
                         f"MAX_STEPS = {MAX_STEPS} steps or the horizon", method=METHOD)
    finally:
        ctx.prec, ctx.cap = old


def _rescaled_time(form: ImplicitLoop, d: float, t_escape: float) -> float:
    """The rescaled time at which the float solution reaches the level (an estimate for
    the horizon only), or the horizon of its real time when it does not."""
    import numpy as np
    from scipy.integrate import solve_ivp

    from gfrf.stability.implicit_region import LoopField

    fl = LoopField(form)
    q0 = fl.qf(0.0)

    def rhs(_t: float, x: np.ndarray) -> list[float]:
        y, v = float(x[0]), float(x[1])
        qy = fl.qf(y)
        return [qy * v / (q0 * SCALE), (fl.g0(y, v) + d * fl.g1(y, v)) / (q0 * SCALE),
                qy / (q0 * SCALE)]

    def level(_t: float, x: np.ndarray) -> float:
        return fl.qf(float(x[0])) - float(SINGULAR_LEVEL) * q0

    def late(_t: float, x: np.ndarray) -> float:
        return float(x[2]) - 2 * t_escape

    level.terminal = late.terminal = True  # type: ignore[attr-defined]
    with np.errstate(all="ignore"):
        sol = solve_ivp(rhs, (0.0, 1e6), [0.0, 0.0, 0.0], method="DOP853", rtol=1e-10,
                        atol=1e-13, events=[level, late])
    return float(sol.t[-1])
