"""A proven escape: the solution from rest under the witness, enclosed in Arb balls.

The model ``sum_t c_t prod D(y, o) prod D(u, o) = 0`` (a continuous polynomial model
whose highest output derivative y^(n) appears in one linear term a_n y^(n)) becomes
the polynomial flow z' = F(z, u) in z = (y, ..., y^(n-1)); a closed loop u = C(r - y)
with a proper linear controller becomes the loop's flow in z = (y, ..., y^(n-1), the
controller's states) with the reference r as input (:func:`loop_flow`, the state form
of :mod:`gfrf.stability.polysys`).  A tone A cos(omega t + phi)
adds the exact oscillator (c, s)' = omega (-s, c), so a tone witness is an autonomous
polynomial flow too, a chirp A cos(omega_0 t + k t^2) (models without input
derivatives) adds (c, s, tau)' = ((omega_0 + 2 k tau)(-s, c), 1) with u = A c, and a
switching witness is one with a constant u on each segment between switch times.
Coefficients, amplitudes, frequencies and switch times are the exact values of the
doubles the model and the witness hold.

Each step of length h (exact dyadic lengths; the switch times are step boundaries) is
the interval Taylor method with a rigorous remainder (Moore's method): an a priori
enclosure B with X + [0, h] F(B) inside B (Picard-Lindelof: every solution from the
box X stays in B over the step), the Taylor coefficients z_k of the solution from a
point c (Picard iteration on Arb power series, python-flint ``arb_series``), and the
Lagrange remainder h^K z_K(B):

    z(h) in sum_{k<K} z_k(c) h^k + h^K z_K(B).

The set is carried in Lohner's form c + B R (:mod:`gfrf.twosided.lohner`: a point, an
orthogonal basis from a QR factorisation, a box of coefficients), advanced by the
mean-value form with an enclosure of the flow's Jacobian, so a rotating oscillator does
not wrap its box step after step.  The escape is proven when the set's hull lies in the
certified escape region of an oscillator (:mod:`gfrf.twosided.escape`: every solution
in it escapes under every input of the witness's size), or for other models beyond the
stated level of a state (the definition of escape there).  Work is bounded by step counts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from gfrf._results import Result
from gfrf.model.equation import Model, Term
from gfrf.model.modelfile import ModelFile
from gfrf.twosided.lohner import LohnerSet, lohner_step

__all__ = ["Enclosure", "enclose_witness", "flow", "loop_flow", "ORDER", "MAX_STEPS",
           "PRECISIONS"]

#: Taylor order K of a step.
ORDER = 24
#: Smallest halving of a step (s).
MIN_STEP = 2.0**-50
#: Taylor steps (tried, including halved ones) of one attempt at most; an attempt whose
#: witness needs more steps of its longest step is not started.
MAX_STEPS = 3_000
#: (working precision in bits, longest step in s) of the attempts, in turn: a shorter
#: step makes the Lagrange remainder smaller.
PRECISIONS = ((128, 2.0**-2), (128, 2.0**-3), (192, 2.0**-4))
#: Why an attempt ended without escape when its boxes stayed narrow to the horizon.
_HORIZON = "the horizon was reached"
#: The method in words.
METHOD = ("interval Taylor enclosure in Arb ball arithmetic from rest (order 24, steps <= 1/4 s, "
          "a priori enclosure and Lagrange remainder; Lohner's QR step against wrapping)")


@dataclass(frozen=True, kw_only=True, repr=False)
class Enclosure(Result):
    """Result of :func:`enclose_witness` (``to_dict`` names ``precision``
    ``precision_bits``).

    Attributes
    ----------
    proven : bool
        The enclosure entered the escape region (or passed the level).
    t_proven : float or None
        The time (s) at which it did.
    steps : int
        Taylor steps taken.
    precision : int
        Working precision in bits of the last attempt.
    width : float
        Largest radius of the last box.
    reason : str
        Why not proven, or what was proven.
    method : str
        How the enclosure was computed.
    """

    _keys = {"precision": "precision_bits"}

    proven: bool
    t_proven: float | None
    steps: int
    precision: int
    width: float
    reason: str
    method: str = METHOD


#: (coefficient, exponents) pairs; a coefficient is exact, or rational bounds (lo, hi) of
#: one computed from an irrational written coefficient.
Monomials = list[tuple[Fraction | tuple[Fraction, Fraction], tuple[int, ...]]]


def _quotient(t: Term, top: Term) -> Fraction | tuple[Fraction, Fraction] | None:
    """-c/a of the written coefficients c of ``t`` and a of ``top``: exact when both are
    rational, else rational bounds from :meth:`gfrf.model.equation.Term.bounds` (an
    irrational coefficient's double widened by a relative 2^-50); None if a may be 0."""
    c, a = t.exact, top.exact
    if c is not None and a is not None:
        return -c / a if a else None
    (c_lo, c_hi), (a_lo, a_hi) = t.bounds(), top.bounds()
    if a_lo <= 0 <= a_hi:
        return None
    ends = [-p / q for p in (c_lo, c_hi) for q in (a_lo, a_hi)]
    return min(ends), max(ends)


def _ball(q: Fraction | tuple[Fraction, Fraction]) -> Any:
    """An Arb ball containing the exact coefficient or the bounds."""
    from flint import arb, fmpq

    if isinstance(q, tuple):
        return arb(fmpq(q[0].numerator, q[0].denominator)).union(
            arb(fmpq(q[1].numerator, q[1].denominator)))
    return arb(fmpq(q.numerator, q.denominator))


def flow(model: Model) -> tuple[int, Monomials] | None:
    """(n, monomials of y^(n)) with exponents over (y, ..., y^(n-1), u, u', ...), or None.

    None: a discrete model, y^(n) not in one linear term with a constant coefficient, or
    that coefficient zero as written.  The coefficients are the exact values written in
    the model text (``0.2`` is 1/5, :attr:`gfrf.model.equation.Term.exact`; rational
    bounds for an irrational one), so an enclosure built on them contains the solution
    of the model as written.

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    tuple or None
        n, and the monomials of y^(n) as (coefficient, exponents) pairs with exact
        rational coefficients (or rational bounds, see :data:`Monomials`).
    """
    if model.is_discrete or not model.terms:
        return None
    n = max((max(t.y_orders, default=0) for t in model.terms), default=0)
    if n == 0:
        return None
    top = [t for t in model.terms if n in t.y_orders]
    if len(top) != 1 or top[0].y_orders != (n,) or top[0].u_orders:
        return None
    quotients = [_quotient(t, top[0]) for t in model.terms if t is not top[0]]
    if any(q is None for q in quotients):
        return None
    nu = 1 + max((max(t.u_orders, default=0) for t in model.terms), default=0)
    out: Monomials = []
    for t, q in zip((t for t in model.terms if t is not top[0]), quotients, strict=True):
        if q is None or (not isinstance(q, tuple) and q == 0):
            continue
        e = [0] * (n + nu)
        for o in t.y_orders:
            e[o] += 1
        for o in t.u_orders:
            e[n + o] += 1
        out.append((q, tuple(e)))
    return n, out


def loop_flow(source: Any) -> tuple[int, list[Monomials], tuple[str, ...]] | None:
    """(n, rows, state names) of a closed loop with a proper linear controller, or None.

    The loop u = C(r - y) in the polynomial state form of
    :func:`gfrf.stability.polysys.state_form` (the plant's companion state, then the
    controller's controllable canonical state, in the order of
    :func:`gfrf.sim.system.build_system`): row i holds the monomials of x_i' with
    exponents over (x_0, ..., x_{n-1}, r) and exact rational coefficients.

    Parameters
    ----------
    source : ModelFile
        A model file with a ``[controller]`` (a proper transfer function).

    Returns
    -------
    tuple or None
        None when the loop has no such state form (an improper or polynomial controller,
        a discrete plant, input derivatives in the plant).
    """
    from gfrf.stability.polysys import StateFormError, state_form

    try:
        system = state_form(source)
    except StateFormError:
        return None
    if system.discrete:
        return None
    rows: list[Monomials] = [[(q, tuple(k)) for k, q in sorted(p.items())] for p in system.f]
    names = tuple(_derivative_name(int(s[4:-1])) if s.startswith("D(y,") else s
                  for s in system.states)
    return system.n, rows, names


def _derivative_name(j: int) -> str:
    """y, y', y'', y^(3), ... for the j-th derivative of the output."""
    return "y" + "'" * j if j < 3 else f"y^({j})"


def _chain(n: int, monos: Monomials) -> list[Monomials]:
    """The rows of the companion form: x_i' = x_{i+1}, x_{n-1}' = the monomials."""
    width = len(monos[0][1]) if monos else n + 1
    rows: list[Monomials] = [[(Fraction(1), tuple(int(j == i + 1) for j in range(width)))]
                             for i in range(n - 1)]
    return rows + [monos]


class _Field:
    """z' = F(z) on the state (x_0..x_{n-1}, then per tone c, s; or the chirp's c, s, tau),
    x_i' a polynomial row in (x, u, u', ...), u per segment, from the tones or the chirp."""

    def __init__(self, n: int, rows: list[Monomials], tones: list[tuple[float, float, float]],
                 chirp: Any = None):
        from flint import arb

        self.n, self.tones = n, tones
        width = max((len(e) for row in rows for _, e in row), default=n + 1)
        self.nu = width - n
        # a row that is one variable with coefficient 1 is that variable (no products)
        self.rows: list[Any] = []
        for row in rows:
            if len(row) == 1 and row[0][0] == 1 and sum(row[0][1]) == 1:
                self.rows.append(row[0][1].index(1))
            else:
                self.rows.append([(_ball(q), e) for q, e in row])
        self.u_const: Any = arb(0)
        self.chirp = None if chirp is None else (  # A, omega_0, 2k: balls of the exact values
            arb(chirp.amplitude), arb(chirp.omega_start),
            (arb(chirp.omega_end) - arb(chirp.omega_start)) / arb(chirp.duration))
        self.dim = n + 2 * len(tones) + (3 if chirp is not None else 0)

    def inputs(self, z: list[Any]) -> list[Any]:
        """u, u', ... from the constant input, the chirp or the tone states."""
        if self.chirp is not None:  # only for models without input derivatives
            return [self.chirp[0] * z[self.n]]
        if not self.tones:
            return [self.u_const] + [0] * (self.nu - 1)
        from flint import arb

        out = []
        for k in range(self.nu):
            total: Any = 0
            for i, (a, w, _) in enumerate(self.tones):
                c, s = z[self.n + 2 * i], z[self.n + 2 * i + 1]
                rot = (c, -s, -c, s)[k % 4]  # d^k/dt^k cos(theta) in (c, s)
                total = total + arb(a) * arb(w) ** k * rot  # w > 0
            out.append(total)
        return out

    def __call__(self, z: list[Any]) -> list[Any]:
        vals = list(z[:self.n]) + self.inputs(z)
        out = []
        for row in self.rows:
            if isinstance(row, int):
                out.append(vals[row])
                continue
            total: Any = 0
            for q, e in row:
                term: Any = q
                for j, p in enumerate(e):
                    for _ in range(p):  # products, never a power (Arb's pow of a ball
                        term = term * vals[j]  # holding 0 can be nan)
                total = total + term
            out.append(total)
        for i, (_, w, _) in enumerate(self.tones):
            from flint import arb

            c, s = z[self.n + 2 * i], z[self.n + 2 * i + 1]
            out += [-arb(w) * s, arb(w) * c]
        if self.chirp is not None:
            c, s, tau = z[self.n], z[self.n + 1], z[self.n + 2]
            freq = tau * self.chirp[2] + self.chirp[1]  # omega_0 + 2 k tau
            out += [-(freq * s), freq * c, tau * 0 + 1]
        return out


def _series(field: _Field, z0: list[Any], K: int) -> list[list[Any]] | None:
    """Taylor coefficients 0..K of the solution from z0 (balls), by Picard iteration;
    None when a ball is not finite.

    Iteration j makes the coefficients of order j exact (those below it stay), so it
    works on series of j + 1 terms only."""
    from flint import arb_series

    z = [arb_series([x], prec=1) for x in z0]
    for j in range(1, K + 1):
        f = field(z)
        z = [arb_series([x0], prec=j + 1) + (fi if isinstance(fi, arb_series) else
                                              arb_series([fi], prec=j)).integral()
             for x0, fi in zip(z0, f, strict=True)]
    out = []
    for s in z:
        c = s.coeffs()
        # Arb drops trailing zero coefficients, so they are padded, but only for a series
        # that holds K + 1 terms (python-flint truncates at ctx.cap) of finite balls
        if s.prec < K + 1 or not all(x.is_finite() for x in c):
            return None
        out.append((c + [0] * (K + 1))[:K + 1])
    return out


def _finite(b: Any) -> bool:
    """A ball with a finite midpoint and a radius a double can hold."""
    return bool(b.is_finite()) and math.isfinite(float(b.rad())) \
        and math.isfinite(float(b.mid()))


def _inflate(b: Any) -> Any:
    """b widened by a fifth of its radius and a little more (room for the Picard check)."""
    from flint import arb

    return b + arb(0, 0.2 * float(b.rad()) + 1e-9 * float(abs(b.mid())) + 1e-60)


def _apriori(field: Any, X: list[Any], h: Any) -> list[Any] | None:
    """A box holding every solution from the box X over [0, h], or None."""
    from flint import arb

    span = h * arb(0.5, 0.5)  # [0, h]
    B = [x + span * f for x, f in zip(X, field(X), strict=True)]
    B = [_inflate(b) for b in B]
    for _ in range(10):
        if not all(_finite(b) for b in B):
            return None
        trial = [x + span * f for x, f in zip(X, field(B), strict=True)]
        if all(_finite(t) and b.contains(t) for b, t in zip(B, trial, strict=True)):
            return B
        B = [_inflate(t) for t in trial]
    return None


def enclose_witness(model: Model | ModelFile, falsification: Any, *,
                    trace: list[tuple[Any, list[Any]]] | None = None) -> Enclosure | None:
    """Enclose the escape of the falsifier's witness in ball arithmetic, or None.

    Parameters
    ----------
    model : Model or ModelFile
        The open-loop plant the witness drives, or a model file with a proper linear
        ``[controller]``: then the witness is the reference r of the loop u = C(r - y),
        enclosed on the loop's state (plant and controller, :func:`loop_flow`).
    falsification : Falsification
        With a witness (``upper`` not None).
    trace : list, optional
        Receives ``(t, boxes)`` after every step of the last attempt (t an Arb ball:
        the exact step time; boxes: the state's balls), for checks.

    Returns
    -------
    Enclosure or None
        None when the model is outside the supported class (a discrete model, an
        implicit highest derivative, a loop without a polynomial state form) or there is
        no witness.
    """
    f = falsification
    if f is None or f.upper is None:
        return None
    if isinstance(model, ModelFile) and model.controller is not None:
        loop = loop_flow(model)
        if loop is None:
            return None
        n, rows, names = loop
    else:
        plant = model.plant if isinstance(model, ModelFile) else model
        if plant.is_discrete:
            return _narx(plant, f)
        shape = flow(plant)
        if shape is None:
            return None
        n, monos = shape
        rows = _chain(n, monos)
        names = tuple(_derivative_name(j) for j in range(n))
    width = max((len(e) for row in rows for _, e in row), default=n + 1)
    if f.kind == "chirp" and (f.chirp is None or width - n > 1):
        return None  # a chirp drives models without input derivatives only
    last = None
    for bits, step in PRECISIONS:
        if (f.t_escape or f.t_end) / step > MAX_STEPS:
            break
        if trace is not None:
            trace.clear()
        last = _attempt(n, rows, names, f, bits, step, trace)
        if last.proven or last.reason == _HORIZON:
            # a narrow enclosure that stayed out of the escape to the horizon: a finer
            # step would enclose the same non-escaping trajectory
            return last
    return last or Enclosure(proven=False, t_proven=None, steps=0, precision=0, width=0.0,
                             reason=f"not attempted: the escape at t = {f.t_escape:.6g} s "
                                    f"needs more than MAX_STEPS = {MAX_STEPS} steps")


def _attempt(n: int, rows: list[Monomials], names: tuple[str, ...], f: Any, bits: int,
             longest: float, trace: list[tuple[Any, list[Any]]] | None) -> Enclosure:
    from flint import arb, ctx

    old = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = bits, ORDER + 1  # series ops truncate at ctx.cap terms
    try:
        tones = list(f.tones) if f.kind == "tones" else []
        chirp = f.chirp if f.kind == "chirp" else None
        field = _Field(n, rows, tones, chirp)
        X = [arb(0)] * n
        for _, _, p in tones:
            X += [arb(p).cos(), arb(p).sin()]
        if chirp is not None:
            X += [arb(1), arb(0), arb(0)]
        S = LohnerSet.of_box(X)
        region = f.region
        horizon = (f.t_escape or f.t_end) * 1.5
        if chirp is not None:
            horizon = min(horizon, chirp.duration)
        edges = [0.0, *(f.switch_times if f.kind == "switching" else []), horizon]
        sign = f.first_sign
        steps = 0
        step = longest
        t = arb(0)
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            field.u_const = arb(sign * f.upper)
            t = arb(a)
            while True:
                left = arb(b) - t
                if not left > 0:
                    break
                h = arb(step) if left > step else left
                nxt = _advance(field, S, h)
                steps += 1
                while nxt is None and h.mid() >= MIN_STEP and steps <= MAX_STEPS:
                    h = h / 2
                    nxt = _advance(field, S, h)
                    steps += 1
                step = min(longest, 2 * float(h.mid())) if nxt is not None else step
                if nxt is None or steps > MAX_STEPS:
                    why = "no a priori enclosure" if nxt is None else f"MAX_STEPS = {MAX_STEPS}"
                    return Enclosure(proven=False, t_proven=None, steps=steps,
                                     precision=bits, width=_width(X),
                                     reason=f"stopped at t = {float(t.mid()):.6g} s: {why}")
                S, t = nxt, t + h
                X = S.hull()
                if trace is not None:
                    trace.append((t, list(X)))
                hit = _escaped(X, region, list(f.levels), names)
                if hit:
                    return Enclosure(proven=True, t_proven=float(t.mid()), steps=steps,
                                     precision=bits, width=_width(X), reason=hit)
                if not all(math.isfinite(float(x.rad())) and x.rad() < 1e-3 * (1 + abs(x.mid()))
                           for x in X):
                    return Enclosure(proven=False, t_proven=None, steps=steps,
                                     precision=bits, width=_width(X),
                                     reason=f"the boxes grew too wide by t = "
                                            f"{float(t.mid()):.6g} s")
            sign = -sign
        return Enclosure(proven=False, t_proven=None, steps=steps, precision=bits,
                         width=_width(X), reason=_HORIZON)
    finally:
        ctx.prec, ctx.cap = old


def _advance(field: _Field, S: LohnerSet, h: Any) -> LohnerSet | None:
    return lohner_step(field, S, h, ORDER, _apriori, _series)


def _width(X: list[Any]) -> float:
    return max(float(x.rad()) for x in X)


def _escaped(X: list[Any], region: Any, levels: list[float], names: tuple[str, ...]) -> str:
    """Why the box X is inside the escape, or '' (``names``: the system's states)."""
    if region is not None and len(names) == 2:
        y, v = X[0], X[1]
        if math.isfinite(region.y_plus) and y >= region.y_plus and v >= 0:
            return f"y >= {region.y_plus:.6g} and y' >= 0 (the certified escape region)"
        if math.isfinite(region.y_minus) and y <= -region.y_minus and v <= 0:
            return f"y <= {-region.y_minus:.6g} and y' <= 0 (the certified escape region)"
    for j, (level, name) in enumerate(zip(levels, names, strict=False)):
        if math.isfinite(level) and abs(X[j]) > level:
            return f"|{name}| > {level:.6g} (the stated escape level)"
    return ""


def _narx(model: Model, f: Any) -> Enclosure | None:
    """The NARX recursion from rest under the witness in Arb balls (the proof)."""
    from flint import arb, ctx

    top = [t for t in model.terms if 0 in t.y_orders]
    if len(top) != 1 or top[0].y_orders != (0,) or top[0].u_orders:
        return None
    terms: list[tuple[Any, tuple[int, ...], tuple[int, ...]]] = []
    for t in model.terms:
        if t is not top[0]:
            q = _quotient(t, top[0])
            if q is None:
                return None  # y[k]'s coefficient zero as written
            terms.append((_ball(q), t.y_orders, t.u_orders))
    T = float(model.sample_time)  # type: ignore[arg-type]
    level = f.levels[0] if f.levels else math.inf
    n = int(math.ceil(1.5 * (f.t_escape or f.t_end) / T)) + 1
    old = ctx.prec
    ctx.prec = PRECISIONS[0][0]
    try:
        y: list[Any] = []
        u: list[Any] = []
        for k in range(min(n, MAX_STEPS)):
            if f.kind == "switching":  # the sign at sample k: flips at the switch samples
                flips = sum(1 for s in f.switch_times if round(s / T) <= k)
                u.append(arb(f.first_sign * (-1) ** flips * f.upper))
            else:
                u.append(sum((arb(a) * (arb(w) * arb(k) * arb(T) + arb(p)).cos()
                              for a, w, p in f.tones), arb(0)))
            total = arb(0)
            for q, ys, us in terms:
                term: Any = q
                for o in ys:
                    term = term * (y[k - o] if k - o >= 0 else 0)
                for o in us:
                    term = term * (u[k - o] if k - o >= 0 else 0)
                total = total + term
            y.append(total)
            if abs(total) > level:
                return Enclosure(proven=True, t_proven=k * T, steps=k + 1,
                                 precision=PRECISIONS[0][0], width=float(total.rad()),
                                 reason=f"|y| > {level:.6g} (the stated escape level)",
                                 method="the NARX recursion from rest in Arb ball arithmetic")
            if not total.is_finite():
                break
        return Enclosure(proven=False, t_proven=None, steps=len(y), precision=PRECISIONS[0][0],
                         width=float(y[-1].rad()) if y else 0.0,
                         reason="the recursion's balls did not pass the level",
                         method="the NARX recursion from rest in Arb ball arithmetic")
    finally:
        ctx.prec = old
