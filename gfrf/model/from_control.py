"""Models from python-control objects: :func:`from_tf` and :func:`from_nlsys`.

:func:`from_tf` builds the polynomial model of a transfer function G with a static
polynomial nonlinearity, either in a feedback loop (``y = G (u - f(y))``) or in series
before it (``y = G f(u)``).  The transfer function's coefficients are numbers; the
equation text is generated here from numbers only and read by :func:`parse_model`.
The coefficients of a python-control object are doubles, and the model they define is
the one with those doubles: its terms carry no written decimal values, so the exact and
ball-arithmetic proofs take every coefficient at its binary value
(:attr:`gfrf.model.equation.Term.exact`), unlike a model written as text, where ``0.2``
is 1/5.

:func:`from_nlsys` recovers the polynomial model of a continuous ``control.nlsys``
about an equilibrium.  Its right-hand side is Python code: it is only *evaluated*
(never read as text), at points around the equilibrium, and the polynomial of total
degree ``order`` in the deviations (x - x0, u - u0) is recovered by least squares on
more points than coefficients.  The result is then **checked** at as many fresh random
points: when the code does not reproduce the polynomial to rounding (it is not a
polynomial of that degree, e.g. ``sin``), the system is refused.  The model must be a
chain of integrators (states y, y', ..., y^(n-1), the last one's derivative any
function of the states and the input) with the output the first state, which
:func:`gfrf.to_nlsys` produces; other state forms have no input-output polynomial
equation in general and are refused.

Examples
--------
>>> import control
>>> m = from_tf(control.tf([1], [1, 0.2, 1]), {3: 0.5})
>>> m.equation()
'0.5*y**3 + y + 0.2*D(y) + D(y,2) - u = 0'
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import MAX_DERIVATIVE_ORDER, Model, parse_model
from gfrf.model.limits import MAX_DEGREE, MAX_TERMS, MAX_TEXT_LENGTH

__all__ = ["from_tf", "from_nlsys", "NLSYS_POINTS_FACTOR"]

#: Fit points per unknown coefficient (and as many again to check the fit).
NLSYS_POINTS_FACTOR = 3
#: Largest number of monomials :func:`from_nlsys` recovers.
_MAX_MONOMIALS = 2000


def _coefficients(nonlinearity: Mapping[int, float] | Sequence[float]) -> dict[int, float]:
    if isinstance(nonlinearity, Mapping):
        items = list(nonlinearity.items())
    elif isinstance(nonlinearity, (list, tuple)):
        items = list(enumerate(nonlinearity))
    else:
        raise ArgumentError("nonlinearity must be {power: coefficient} or a list of "
                            "coefficients indexed by power")
    out: dict[int, float] = {}
    for power, coef in items:
        if isinstance(power, bool) or not isinstance(power, int) or not 0 <= power <= MAX_DEGREE:
            raise ArgumentError(f"nonlinearity power must be an integer in 0..MAX_DEGREE = "
                                f"{MAX_DEGREE}, got {power!r}")
        if isinstance(coef, complex) or np.iscomplexobj(coef):
            raise ArgumentError(f"nonlinearity coefficient of power {power} is complex: a "
                                f"model's coefficients are real")
        try:
            value = float(coef)
        except (TypeError, ValueError, OverflowError):
            raise ArgumentError(f"nonlinearity coefficient of power {power} must be a number, "
                                f"got {coef!r}") from None
        if not math.isfinite(value):
            raise ArgumentError(f"nonlinearity coefficient of power {power} is not finite")
        if value:
            out[power] = value
    if out.get(0):
        raise ArgumentError("the nonlinearity has a constant term: (0, 0) would not be an "
                            "equilibrium")
    return out


def _tf_polys(G: Any) -> tuple[np.ndarray, np.ndarray, float | None]:
    try:
        raw = [np.atleast_1d(np.asarray(G.num[0][0])), np.atleast_1d(np.asarray(G.den[0][0]))]
        ninputs, noutputs = G.ninputs, G.noutputs
        if any(r.ndim != 1 or r.dtype.kind not in "biufc" for r in raw):
            raise TypeError
    except (AttributeError, IndexError, KeyError, TypeError, ValueError):
        raise ArgumentError("G must be a SISO control.TransferFunction (control.tf(num, den))") \
            from None
    if any(np.iscomplexobj(r) and np.any(r.imag != 0) for r in raw):
        raise ArgumentError("G has complex coefficients: a model's coefficients are real")
    num, den = (r.real.astype(float) for r in raw)
    if (ninputs, noutputs) != (1, 1):
        raise ArgumentError(f"G must be SISO, got {noutputs} outputs x {ninputs} inputs")
    num = np.trim_zeros(num, "f")
    den = np.trim_zeros(den, "f")
    if not den.size or not num.size:
        raise ArgumentError("G has a zero numerator or denominator")
    if not (np.all(np.isfinite(num)) and np.all(np.isfinite(den))):
        raise ArgumentError("G has non-finite coefficients")
    if num.size > den.size:
        raise ArgumentError("G is improper (numerator degree above the denominator's)")
    if den.size - 1 > MAX_DERIVATIVE_ORDER:
        raise ArgumentError(f"G has degree {den.size - 1}, above MAX_DERIVATIVE_ORDER = "
                            f"{MAX_DERIVATIVE_ORDER} (the highest derivative or lag of a model)")
    dt = G.dt
    if dt is True:
        raise ArgumentError("G is discrete with an unspecified sample time (dt=True): give dt")
    return num, den, (float(dt) if dt else None)


def _d(name: str, order: int, discrete: bool) -> str:
    if discrete:
        return f"{name}[k-{order}]" if order else f"{name}[k]"
    return name if order == 0 else f"D({name},{order})"


def _power_derivative(name: str, power: int, order: int) -> dict[tuple[int, ...], int]:
    """D^order (name**power) as {sorted derivative orders of the factors: integer coefficient}
    (Leibniz rule; exact integers)."""
    terms: dict[tuple[int, ...], int] = {(0,) * power: 1}
    for _ in range(order):
        nxt: dict[tuple[int, ...], int] = {}
        for orders, c in terms.items():
            for i in range(len(orders)):
                new = tuple(sorted(orders[:i] + (orders[i] + 1,) + orders[i + 1:]))
                nxt[new] = nxt.get(new, 0) + c
        terms = nxt
    return terms


def _partitions(total: int, parts: int) -> int:
    """Partitions of ``total`` into at most ``parts`` parts: the terms of D^total (y**parts)."""
    ways = [1] + [0] * total
    for k in range(1, parts + 1):  # conjugate: partitions into parts of size <= parts
        for t in range(k, total + 1):
            ways[t] += ways[t - k]
    return ways[total]


def _expansion_size(num: np.ndarray, powers: Sequence[int], discrete: bool) -> tuple[int, int]:
    """Terms and (over-)estimated characters of the expanded model, before expanding."""
    terms = chars = 0
    for i, b in enumerate(num):
        if not b:
            continue
        degree = num.size - 1 - i
        for power in powers:
            count = 1 if discrete else _partitions(degree, power)
            terms += count
            chars += count * (30 + 11 * power)
    return terms, chars


def _monomial(name: str, orders: Sequence[int], discrete: bool) -> str:
    return "*".join(_d(name, k, discrete) for k in orders)


def from_tf(G: Any, nonlinearity: Mapping[int, float] | Sequence[float], *,
            connection: str = "feedback") -> Model:
    """The polynomial model of a transfer function with a static polynomial nonlinearity.

    Parameters
    ----------
    G : control.TransferFunction
        SISO, continuous (in s) or discrete (in z, with its sample time ``dt``); proper.
    nonlinearity : mapping or sequence
        f as ``{power: coefficient}`` (or a list indexed by power); no constant term.
    connection : {"feedback", "series"}
        ``"feedback"``: ``y = G (u - f(y))`` (f, e.g. ``{3: 0.5}``, acts as a force at
        G's input); ``"series"``: ``y = G f(u)`` (f is the static input map, e.g.
        ``{1: 1, 3: 0.1}``).

    Returns
    -------
    Model
        ``den(D) y + num(D) f(y) = num(D) u`` or ``den(D) y = num(D) f(u)`` (D = d/dt, or
        the backward shift for a discrete G).
    """
    if connection not in ("feedback", "series"):
        raise ArgumentError(f"connection must be 'feedback' or 'series', got {connection!r}")
    coeffs = _coefficients(nonlinearity)
    num, den, dt = _tf_polys(G)
    discrete = dt is not None
    terms, chars = _expansion_size(num, list(coeffs), discrete)
    if terms > MAX_TERMS or chars > MAX_TEXT_LENGTH:
        raise ArgumentError(f"the numerator's derivatives of the nonlinearity expand to "
                            f"{terms} terms (about {chars} characters), above MAX_TERMS = "
                            f"{MAX_TERMS} or MAX_TEXT_LENGTH = {MAX_TEXT_LENGTH}: lower the "
                            f"numerator's degree or the nonlinearity's")
    n = den.size - 1
    lhs: list[str] = []
    rhs: list[str] = []
    # d-th power of D in den(D) is den[n - d]; discrete: z^d -> lag n - d
    for i, a in enumerate(den):
        if a:
            lhs.append(f"{float(a)!r}*{_d('y', n - i if not discrete else i, discrete)}")
    name = "y" if connection == "feedback" else "u"
    target = lhs if connection == "feedback" else rhs
    shift = n - (num.size - 1)
    for i, b in enumerate(num):
        if not b:
            continue
        degree = num.size - 1 - i
        if connection == "feedback":
            rhs.append(f"{float(b)!r}*{_d('u', shift + i if discrete else degree, discrete)}")
        for power, c in coeffs.items():
            if connection == "feedback" and power == 0:
                continue
            if discrete:
                parts = {(shift + i,) * power: 1}
            else:
                parts = _power_derivative(name, power, degree)
            for orders, k in parts.items():
                target.append(f"{float(b * c * k)!r}*{_monomial(name, orders, discrete)}")
    if not rhs:
        raise ArgumentError("the model has no input term (a zero series nonlinearity)")
    text = f"{' + '.join(lhs)} = {' + '.join(rhs)}"
    return parse_model(text, sample_time=dt, exact=False)


def _call(sys: Any, which: str, x: np.ndarray, u: np.ndarray, size: int) -> np.ndarray:
    try:
        value = (sys.dynamics if which == "rhs" else sys.output)(0.0, x, u)
    except Exception as exc:
        raise ModelError(f"the system's {'update' if which == 'rhs' else 'output'} function "
                         f"failed at x = {x.tolist()}, u = {u.tolist()}: "
                         f"{type(exc).__name__}: {exc}") from None
    try:
        array = np.asarray(value)
        if array.dtype.kind not in "biuf":
            raise TypeError(f"values of type {array.dtype}")
        out = array.astype(float).reshape(-1)
    except (TypeError, ValueError, OverflowError) as exc:
        raise ModelError(f"the system's {'update' if which == 'rhs' else 'output'} function "
                         f"returned {type(value).__name__}, not real numbers: {exc}") from None
    if out.size != size:
        raise ModelError(f"the system's {'update' if which == 'rhs' else 'output'} function "
                         f"returned {out.size} values, expected {size}")
    if not np.all(np.isfinite(out)):
        raise ModelError(f"the system's function is not finite at x = {x.tolist()}, "
                         f"u = {u.tolist()}")
    return out


def from_nlsys(sys: Any, x0: Sequence[float] | float = 0.0, u0: float = 0.0, *,
               order: int = 3, scale: float = 1.0, seed: int = 0) -> Model:
    """The polynomial model of a continuous SISO ``control.nlsys`` about an equilibrium.

    Parameters
    ----------
    sys : control.NonlinearIOSystem
        Continuous, one input, one output; states a chain of integrators
        (x_i' = x_{i+1}) with output y = x_1 (the form :func:`gfrf.to_nlsys` produces).
    x0 : sequence of float or float
        The equilibrium state (updfcn(x0, u0) = 0).
    u0 : float
        The input at the equilibrium.
    order : int
        Total degree of the polynomial recovered (the model's degree).
    scale : float
        Half-width of the box around (x0, u0) where the code is evaluated.
    seed : int
        Seed of the sample points (the result does not depend on the clock).

    Returns
    -------
    Model
        In the deviations y = x_1 - x0_1 and u - u0: ``D(y,n) = P(y, .., D(y,n-1), u)``.

    Raises
    ------
    ModelError
        Not an nlsys of that form, not an equilibrium, or a right-hand side that is
        not a polynomial of total degree ``order`` (checked at fresh random points).
    """
    try:
        n, nin, nout, dt = sys.nstates, sys.ninputs, sys.noutputs, sys.dt
        sys.dynamics  # noqa: B018 - the attribute test
    except AttributeError:
        raise ModelError("from_nlsys needs a control.NonlinearIOSystem (control.nlsys); "
                         "for a transfer function use gfrf.from_tf") from None
    if not all(isinstance(v, int) and not isinstance(v, bool) for v in (n, nin, nout)):
        raise ModelError(f"from_nlsys needs integer nstates, ninputs and noutputs, got "
                         f"{type(n).__name__}, {type(nin).__name__}, {type(nout).__name__}")
    if (nin, nout) != (1, 1) or n < 1:
        raise ModelError(f"from_nlsys needs one input, one output and a state, got {nin} "
                         f"inputs, {nout} outputs, {n} states")
    if not (dt is None or (isinstance(dt, (int, float)) and not isinstance(dt, bool)
                           and dt == 0)):
        raise ModelError("from_nlsys handles continuous systems only (dt = 0)")
    if isinstance(order, bool) or not isinstance(order, int) or not 1 <= order <= 12:
        raise ModelError(f"order must be an integer in 1..12, got {order!r}")
    try:
        x0 = np.broadcast_to(np.asarray(x0, dtype=float), (n,)).copy()
        u0 = float(u0)
        scale = float(scale)
    except (TypeError, ValueError, OverflowError):
        raise ModelError(f"x0 must be a number or {n} numbers, u0 and scale numbers") from None
    if not (np.all(np.isfinite(x0)) and math.isfinite(u0) and math.isfinite(scale)
            and scale > 0):
        raise ModelError("x0, u0 and scale must be finite (scale > 0)")
    rhs0 = _call(sys, "rhs", x0, np.array([u0]), n)
    if np.max(np.abs(rhs0)) > 1e-12 * (1 + np.max(np.abs(x0)) + abs(u0)):
        raise ModelError(f"(x0, u0) is not an equilibrium: updfcn = {rhs0.tolist()}")
    count = math.comb(n + 1 + order, order)  # monomials of degree <= order in n + 1 atoms
    if count > _MAX_MONOMIALS:
        raise ModelError(f"{n} states to order {order} give {count} monomials, "
                         f"above {_MAX_MONOMIALS}")
    monomials = [m for d in range(order + 1)
                 for m in itertools.combinations_with_replacement(range(n + 1), d)]
    rng = np.random.default_rng(seed)
    count = NLSYS_POINTS_FACTOR * len(monomials)
    points = rng.uniform(-scale, scale, size=(2 * count, n + 1))

    def basis(p: np.ndarray) -> np.ndarray:
        return np.array([[np.prod(row[list(m)]) for m in monomials] for row in p])

    values = np.array([_call(sys, "rhs", x0 + p[:n], np.array([u0 + p[n]]), n) for p in points])
    outputs = np.array([_call(sys, "out", x0 + p[:n], np.array([u0 + p[n]]), 1)[0]
                        for p in points[:count]])
    if not np.allclose(outputs, x0[0] + points[:count, 0], rtol=1e-12, atol=1e-12 * scale):
        raise ModelError("from_nlsys needs the output y = x[0] (the first state)")
    for i in range(n - 1):
        if not np.allclose(values[:, i], points[:, i + 1], rtol=1e-12, atol=1e-12 * scale):
            raise ModelError(f"from_nlsys needs a chain of integrators: x[{i}]' = x[{i + 1}] "
                             f"does not hold; other state forms have no input-output "
                             f"polynomial equation in general")
    fit, check = basis(points[:count]), basis(points[count:])
    last = values[:, n - 1]
    coef, *_ = np.linalg.lstsq(fit, last[:count], rcond=None)
    size = np.max(np.abs(last)) + 1e-300
    residual = float(np.max(np.abs(check @ coef - last[count:])))
    if residual > 1e-9 * size:
        raise ModelError(f"the right-hand side is not a polynomial of total degree {order} "
                         f"in (x - x0, u - u0): the recovered polynomial misses it by "
                         f"{residual:.3g} (relative {residual / size:.3g}) at fresh points; "
                         f"raise order if it is a polynomial, else write the Taylor "
                         f"model as text (gfrf.parse_model with truncation=)")
    atoms = [_d("y", i, False) for i in range(n)] + ["u"]
    # 13 significant digits: the fit's rounding (~1e-15 relative) is not carried into
    # the model (1.0 stays 1.0); coefficients below 1e-11 of the largest value are rounding.
    terms = [f"{float(f'{-c:.13g}')!r}*" + "*".join(atoms[i] for i in m)
             for c, m in zip(coef, monomials, strict=True) if m and abs(c) > 1e-11 * size]
    if not terms:
        raise ModelError("the recovered right-hand side is zero")
    return parse_model(f"{_d('y', n, False)} + {' + '.join(terms)} = 0", exact=False)
