"""Ball-arithmetic value of a GFRF at one real frequency vector: proven witness points.

A lower bound ``||H_n|| >= |H_n(j w*)|`` is only as good as the evaluation at the
witness ``w*``.  :func:`kernel_ball` evaluates H_n(j w_1, .., j w_n) (rad/s) in Arb
complex balls (python-flint ``acb``) by the recursion of :mod:`gfrf.kernels.recursion`

    H_m(block) = -P_m(block) / A(sum of block),

P_m summed over the same term assignments (ordered set partitions with their weights
for the symmetric kernel, compositions for the asymmetric one) as
:class:`gfrf.kernels.recursion.GFRFGenerator`, with every model coefficient taken as
written (``0.2`` is 1/5, :meth:`gfrf.model.equation.Term.bounds`; an irrational one as a
ball around its double) and every frequency at its exact float value, so the ball
encloses the kernel of the model as written.  A discrete model uses q_i = exp(-j w_i T) as a ball.
:func:`witness_bound` turns |H_n| into float ends rounded outward.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> m = parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u")
>>> w = witness_bound(m, 3, (1.565, 1.565, -1.565))
>>> w.lower <= w.upper and w.relative_width < 1e-15
True
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any

from gfrf.bounds.exact import arb_lower, arb_upper
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import generator
from gfrf.model.equation import Model
from gfrf.model.exact import Written
from gfrf.model.scaling import normalized

__all__ = ["WitnessBound", "kernel_ball", "witness_bound"]

#: Working precisions (bits) tried in turn until |H_n| is enclosed to WIDTH relative.
_PRECISIONS = (128, 512)
#: Relative width of the enclosure below which a witness counts as proven to its digits.
WIDTH = 1e-10

# One assignment of a term: bounds of the coefficient as written x weight, output blocks
# with their derivative orders (lags), input slots with theirs.
_Step = tuple[tuple[Fraction, Fraction], tuple[tuple[tuple[int, ...], int], ...],
              tuple[tuple[int, int], ...]]


@dataclass(frozen=True)
class WitnessBound:
    """|H_n| at one frequency vector, enclosed: ``lower <= |H_n(j w)| <= upper``.

    Attributes
    ----------
    lower, upper : float
        Ends of the ball of |H_n| rounded outward to floats (``lower >= 0``).
    relative_width : float
        ``(upper - lower) / upper`` (0 for an exact zero, inf if unbounded).
    precision : int
        Arb working precision (bits) of the evaluation.
    """

    lower: float
    upper: float
    relative_width: float
    precision: int


def _steps(model: Model, m: int, symmetric: bool) -> tuple[_Step, ...]:
    """Every term assignment of order ``m`` (memoised per model, its written values, order
    and kind: models compare by their doubles only)."""
    return _written_steps(model, tuple(t.written for t in model.terms), m, symmetric)


@lru_cache(maxsize=256)
def _written_steps(model: Model, written: tuple[Written | None, ...], m: int,
                   symmetric: bool) -> tuple[_Step, ...]:
    gen = generator(model)
    steps = []
    if gen.structurally_nonzero(m):
        for term in normalized(model).terms:
            if term.is_linear_output:
                continue
            lo, hi = term.bounds()
            for weight, y_blocks, u_slots in gen._assignments(term, m, symmetric):
                factor = Fraction(int(weight.p), int(weight.q))
                steps.append(((lo * factor, hi * factor),
                              tuple(zip((tuple(b) for b in y_blocks), term.y_orders,
                                        strict=True)),
                              tuple(zip(u_slots, term.u_orders, strict=True))))
    return tuple(steps)


def kernel_ball(model: Model, n: int, omegas: Sequence[float], symmetric: bool = True,
                precision: int = 128) -> Any:
    """H_n(j w_1, .., j w_n) as an Arb complex ball (``flint.acb``), w in rad/s.

    Parameters
    ----------
    model : Model
    n : int
        Kernel order.
    omegas : sequence of float
        n finite angular frequencies (rad/s), taken at their exact float values.
    symmetric : bool, optional
        Symmetric kernel (default) or the asymmetric kernel of the recursion.
    precision : int, optional
        Arb working precision in bits.

    Returns
    -------
    flint.acb
        A ball that contains the exact value of the kernel of ``model`` as written
        (:meth:`gfrf.model.equation.Term.bounds`); non-finite if A(sum) may vanish there.
    """
    import flint

    if len(omegas) != n or not all(math.isfinite(float(w)) for w in omegas):
        raise ArgumentError(f"H{n} needs {n} finite angular frequencies (rad/s), got {omegas!r}")
    norm = normalized(model)
    discrete = norm.is_discrete
    saved = flint.ctx.prec
    flint.ctx.prec = precision
    try:
        linear = [(_ball(t.bounds()), t.y_orders[0]) for t in norm.terms
                  if t.is_linear_output]
        if discrete:
            step = flint.arb(flint.fmpq(*Fraction(norm.sample_time).as_integer_ratio()))
            xs = [flint.acb(0, -flint.arb(float(w)) * step).exp() for w in omegas]
        else:
            xs = [flint.acb(0, float(w)) for w in omegas]
        memo: dict[tuple[int, ...], Any] = {}
        combined: dict[tuple[int, ...], Any] = {}

        def total(block: tuple[int, ...]) -> Any:
            """s_1 + .. (continuous) or q_1 * .. (discrete) over a block of indices."""
            if block not in combined:
                value = xs[block[0]]
                for i in block[1:]:
                    value = value * xs[i] if discrete else value + xs[i]
                combined[block] = value
            return combined[block]

        def key(block: tuple[int, ...]) -> tuple[Any, ...]:
            # The symmetric kernel depends on the multiset of its frequencies only.
            return tuple(sorted(float(omegas[i]) for i in block)) if symmetric else block

        def value(block: tuple[int, ...]) -> Any:
            k = key(block)
            if k not in memo:
                numerator = flint.acb(0)
                for coefficient, y_parts, u_parts in _steps(model, len(block), symmetric):
                    product = flint.acb(_ball(coefficient))
                    for sub, order in y_parts:
                        inner = tuple(block[j] for j in sub)
                        product *= value(inner)
                        if order:
                            product *= total(inner) ** order
                    for slot, order in u_parts:
                        if order:
                            product *= xs[block[slot]] ** order
                    numerator += product
                z = total(block)
                denominator = flint.acb(0)
                for a, order in linear:
                    denominator += a * z ** order
                memo[k] = -numerator / denominator
            return memo[k]

        return value(tuple(range(n)))
    finally:
        flint.ctx.prec = saved


def _ball(bounds: tuple[Fraction, Fraction]) -> Any:
    """The Arb ball of the rational interval ``bounds`` (exact ends rounded outward)."""
    import flint

    lo, hi = (flint.arb(flint.fmpq(c.numerator, c.denominator)) for c in bounds)
    return lo if bounds[0] == bounds[1] else lo.union(hi)


def witness_bound(model: Model, n: int, omegas: Sequence[float],
                  symmetric: bool = True) -> WitnessBound:
    """Proven enclosure of |H_n| at the frequency vector ``omegas`` (rad/s).

    Evaluated at 128 bits, then at 512 bits if the ball is wider than :data:`WIDTH`
    relative (heavy cancellation); the ends are rounded outward to floats.

    Parameters
    ----------
    model : Model
        The plant model.
    n : int
        The order of the kernel.
    omegas : sequence of float
        n angular frequencies in rad/s.
    symmetric : bool, optional
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    WitnessBound
        ``lower`` is a proven lower bound of ``||H_n||_inf`` (of ``|H_n|`` at one point).
    """
    result = WitnessBound(0.0, math.inf, math.inf, _PRECISIONS[0])
    for bits in _PRECISIONS:
        ball = abs(kernel_ball(model, n, omegas, symmetric, bits))
        lower, upper = max(0.0, arb_lower(ball)), arb_upper(ball)
        width = (0.0 if upper == lower else
                 math.inf if not math.isfinite(upper) or upper == 0 else (upper - lower) / upper)
        result = WitnessBound(lower, upper, width, bits)
        if width <= WIDTH:
            break
    return result
