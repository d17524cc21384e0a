"""Certified bound of |H_n(j w_1 .. j w_n)| where some |w_i| exceeds a width W (rad/s).

The tail of the branch-and-bound of :mod:`gfrf.branch_bound`: outside the box
|w_i| <= W a recursion on the majorant bounds |H_n|.  Either the block sum sigma
satisfies |sigma| >= alpha W, and the top factor sigma^l / A(j sigma) is bounded by its
exact sup over |sigma| >= alpha W, or two coordinates exceed (1 - alpha) W / (m-1) and
(unless both are input slots) one of them sits in a lower-order factor, bounded
recursively (best alpha of a few); H1 factors use their exact sup over |w| >= V.
The one-dimensional sups are proven (Arb, :class:`gfrf.exact.SupBeyond`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import cache, lru_cache

import numpy as np

from gfrf.combinatorics import compositions
from gfrf.majorant import Majorant, linear_polynomials, majorant
from gfrf.model import Model

__all__ = ["tail_bound"]

#: Splits |sigma| >= alpha W of the tail recursion tried at each level.
_ALPHAS = (0.25, 0.5, 0.75)


class _Beyond:
    """sup over |w| >= v of |N(j w) / D(j w)| (coefficients highest first), proven.

    A proven upper bound (:class:`gfrf.exact.SupBeyond`: exact stationary points
    isolated once by Arb, ball evaluation per query, outward rounding), so a cluster
    of lightly damped poles cannot make the tail bound too small.
    """

    def __init__(self, num: np.ndarray, den: np.ndarray) -> None:
        from gfrf.exact import SupBeyond

        self.bound = SupBeyond(num, den)

    def sup(self, v: float) -> float:
        """Upper bound of the sup over |w| >= v."""
        return self.bound.upper(v)


@lru_cache(maxsize=64)
def _beyond(num: tuple[float, ...], den: tuple[float, ...]) -> _Beyond:
    """:class:`_Beyond` of N/D, built once (its stationary points are isolated once)."""
    return _Beyond(np.array(num), np.array(den))


def tail_bound(model: Model, n: int, width: float, maj: Majorant | None = None) -> float:
    """Certified bound of |H_n| where some |w_i| > ``width`` (rad/s).

    Valid for the symmetric and the asymmetric kernel (see the module docstring).

    Parameters
    ----------
    model : Model
        Continuous-time model.
    n : int
        Kernel order.
    width : float
        W in rad/s.
    maj : Majorant, optional
        ``majorant(model)`` if already computed.

    Returns
    -------
    float
    """
    maj = majorant(model) if maj is None else maj
    num, den = linear_polynomials(model)
    full = maj.coefficients(n)
    idx = {ell: i for i, ell in enumerate(maj.powers)}

    def m(order: int, ell: int) -> float:
        return float(full[order, idx[ell]])

    def numerator(order: int, part: Callable[[int, int], float] | None) -> float:
        """Sum of the terms' bounds; ``part`` bounds the factor holding a large w."""
        total = 0.0
        for t in maj.terms:
            p = len(t.y_orders)
            for sizes in compositions(order - t.q, p) if p or order == t.q else []:
                factors = [m(s, ell) for s, ell in zip(sizes, t.y_orders, strict=True)]
                if part is None:
                    best = math.prod(factors)
                else:
                    best = math.prod(factors) if t.q >= 2 else 0.0
                    for k, (s, ell) in enumerate(zip(sizes, t.y_orders, strict=True)):
                        others = math.prod(factors[:k] + factors[k + 1:])
                        best = max(best, part(s, ell) * others if others else 0.0)
                total += t.weight * best if best else 0.0
        return total

    key = tuple(den.tolist())
    linear = {ell: _beyond((*num.tolist(), *[0.0] * ell), key) for ell in maj.powers}
    gain = {ell: _beyond((1.0, *[0.0] * ell), key) for ell in maj.powers}
    whole = {order: numerator(order, None) for order in range(2, n + 1)}

    @cache
    def tail(order: int, ell: int, w: float) -> float:
        if order == 1:
            return linear[ell].sup(w)
        best = math.inf
        for alpha in _ALPHAS:
            v = (1 - alpha) * w / (order - 1)
            near = maj.gains[ell] * numerator(order, lambda s, e, v=v: tail(s, e, v))
            best = min(best, max(gain[ell].sup(alpha * w) * whole[order], near))
        return best

    return tail(n, 0, float(width))
