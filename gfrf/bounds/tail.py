"""Certified bound of |H_n(j w_1 .. j w_n)| where some |w_i| exceeds a width W (rad/s).

The tail of the branch-and-bound of :mod:`gfrf.bounds.branch_bound`.  Notation: sigma_B is the
frequency sum of a block B of coordinates, A the linear output polynomial, and for a
derivative power l (0 at the top, l_i for an output factor D(y, l_i) of a term)

    M_{m,l} >= sup over R^m of |sigma^l H_m|      (the majorant, :mod:`gfrf.bounds.majorant`),
    K_l = sup over R of |x^l / A(j x)|,    G_l(V) = sup over |x| >= V of |x^l / A(j x)|.

The recursion H_m = -P_m / A(sigma) writes P_m, for every term of weight |c| with p
output factors and q input factors (u, whose modulus is 1 on the axis), as a sum over
compositions m - q = m_1 + .. + m_p of products of the p *slot* factors
sigma_{B_i}^{l_i} H_{m_i}(B_i) and the q input slots (one coordinate each).  The
asymmetric kernel uses contiguous blocks, the symmetric one averages over ordered set
partitions with weights summing to one per composition; every bound below holds for
each block assignment, hence for both kernels.  Two quantities are bounded for each
order m >= 1, power l and threshold V > 0:

    T_1(m, l, V) >= |sigma^l H_m|  wherever some |w_i| >= V,
    T_2(m, l, V) >= |sigma^l H_m|  wherever two distinct |w_i|, |w_j| >= V   (m >= 2).

**Order one.**  T_1(1, l, V) = sup over |x| >= V of |x^l H1(j x)|, proven (Arb,
:class:`gfrf.bounds.exact_sup.SupBeyond`).  A block of one coordinate cannot hold two.

**One large coordinate** (|w_i| >= W).  For a split 0 < alpha < 1 (best of a few):

* |sigma| >= alpha W: |sigma^l / A(sigma)| <= G_l(alpha W), and P_m <= N_1(m, W), where
  N_1 is the numerator bound with the coordinate w_i placed in one slot: for each
  composition the largest, over the slots, of T_1(m_k, l_k, W) times the other slots'
  M (an input slot contributes 1).
* |sigma| < alpha W: the other coordinates sum to sigma - w_i, of modulus above
  (1 - alpha) W, so a second coordinate has |w_j| > V = (1 - alpha) W / (m - 1).
  |sigma^l / A| <= K_l and P_m <= N_2(m, W, V), the numerator bound with the two large
  coordinates placed: in two different output slots a, b (T_1(m_a, l_a, W) times
  T_1(m_b, l_b, V), or the reverse, times the other slots' M), in the same output slot
  k (T_2(m_k, l_k, V) times the others' M), in an output slot and an input slot
  (T_1 of the output slot times the others' M), or in two input slots (the product of
  all M, when q >= 2).

  T_1(m, l, W) = min(M_{m,l}, min over alpha of max(G_l(alpha W) N_1, K_l N_2)).

**Two large coordinates** (|w_i|, |w_j| >= V): T_2(m, l, V) = min(M_{m,l}, K_l N_2(m, V, V)).

Why this decays.  The previous recursion bounded the near case |sigma| < alpha W with
ONE slot's tail times every other slot's global sup; when that slot is a factor
s^2 H1 of relative degree 0 (the cart-pole's theta^2 theta''), nothing decays and the
tail bound had a floor (0.041 for the cart-pole's H5, above ||H5|| = 0.0111).  With
both large coordinates placed, each product holds two tails (or one block holding two
large coordinates, bounded recursively), and in the cart-pole every pair of slots has
at most one non-decaying member (powers l = 0, 0, 2 / 0, 1, 1 / 0, 0, 0 / 0, 0 and u),
so one factor always decays; the top factor has l = 0 and G_0 ~ 1/W^2.  The bound of
its H5 then falls like 1/W^2 (0.0065 at W = 500, 7.2e-5 at 5000), as the sampled sup
does.  Nothing assumes decay: a factor that does not decay (an input slot, H1 or s^l/A
of relative degree 0 or 1, a term u^2 or y D(y,2)^2) enters with its exact sup beyond V
or its global sup, so the bound stays sound (for the H3 of y D(y,2)^2 it stays within
0.1 % of the kernel's non-zero limit far out).  Products and sums are formed in double
precision from proven sups (relative rounding ~1e-15, as in
:meth:`gfrf.bounds.majorant.Majorant.coefficients`).
Cost: memoised on (order, power, threshold); about 5 ms per call at order 5.
"""

from __future__ import annotations

import math
from functools import cache, lru_cache

import numpy as np

from gfrf.bounds.majorant import Majorant, linear_polynomials, majorant
from gfrf.kernels.combinatorics import compositions
from gfrf.model.equation import Model

__all__ = ["tail_bound"]

#: Splits |sigma| >= alpha W of the tail recursion tried at each level.
_ALPHAS = (0.25, 0.5, 0.75)


class _Beyond:
    """sup over |w| >= v of |N(j w) / D(j w)| (coefficients highest first), proven.

    A proven upper bound (:class:`gfrf.bounds.exact_sup.SupBeyond`: exact stationary points
    isolated once by Arb, ball evaluation per query, outward rounding), so a cluster
    of lightly damped poles cannot make the tail bound too small.
    """

    def __init__(self, num: np.ndarray, den: np.ndarray) -> None:
        from gfrf.bounds.exact_sup import SupBeyond

        self.bound = SupBeyond(num, den)

    def sup(self, v: float) -> float:
        """Upper bound of the sup over |w| >= v."""
        return self.bound.upper(v)


@lru_cache(maxsize=64)
def _beyond(num: tuple[float, ...], den: tuple[float, ...]) -> _Beyond:
    """:class:`_Beyond` of N/D, built once (its stationary points are isolated once)."""
    return _Beyond(np.array(num), np.array(den))


def _prod(values: list[float]) -> float:
    """Product with 0 * inf = 0 (a structurally absent factor stays absent)."""
    return 0.0 if 0.0 in values else math.prod(values)


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
        ``inf`` when the majorant is not finite.
    """
    maj = majorant(model) if maj is None else maj
    if not maj.finite:
        return math.inf
    num, den = linear_polynomials(model)
    full = maj.coefficients(n)
    idx = {ell: i for i, ell in enumerate(maj.powers)}

    def m(order: int, ell: int) -> float:
        return float(full[order, idx[ell]])

    # (weight, q, output slots (size, power)) of every term and composition of each order
    layouts: dict[int, list[tuple[float, int, tuple[tuple[int, int], ...]]]] = {}
    for order in range(2, n + 1):
        layouts[order] = [
            (t.weight, t.q, tuple(zip(sizes, t.y_orders, strict=True)))
            for t in maj.terms if t.weight
            for sizes in (compositions(order - t.q, len(t.y_orders))
                          if t.y_orders or order == t.q else ())]

    key = tuple(den.tolist())
    linear = {ell: _beyond((*num.tolist(), *[0.0] * ell), key) for ell in maj.powers}
    gain = {ell: _beyond((1.0, *[0.0] * ell), key) for ell in maj.powers}

    def n1(order: int, w: float) -> float:
        """Numerator bound with one coordinate |w_i| >= w placed in some slot."""
        total = 0.0
        for weight, q, slots in layouts[order]:
            sups = [m(s, ell) for s, ell in slots]
            best = _prod(sups) if q else 0.0
            for k, (s, ell) in enumerate(slots):
                best = max(best, _prod([one(s, ell, w), *sups[:k], *sups[k + 1:]]))
            total += weight * best
        return total

    def n2(order: int, w: float, v: float) -> float:
        """Numerator bound with |w_i| >= w and |w_j| >= v (i != j) placed in slots."""
        total = 0.0
        for weight, q, slots in layouts[order]:
            sups = [m(s, ell) for s, ell in slots]
            best = _prod(sups) if q >= 2 else 0.0
            for a, (sa, la) in enumerate(slots):
                rest = sups[:a] + sups[a + 1:]
                if q:  # the other large coordinate in an input slot
                    best = max(best, _prod([one(sa, la, v), *rest]))
                if sa >= 2:  # both in this slot's block
                    best = max(best, _prod([two(sa, la, v), *rest]))
                for b, (sb, lb) in enumerate(slots):
                    if b != a:
                        others = [x for k, x in enumerate(sups) if k not in (a, b)]
                        best = max(best, _prod([one(sa, la, w), one(sb, lb, v), *others]))
            total += weight * best
        return total

    @cache
    def one(order: int, ell: int, w: float) -> float:
        """T_1: bound of |sigma^ell H_order| where some |w_i| >= w."""
        if order == 1:
            return min(m(1, ell), linear[ell].sup(w))
        best = m(order, ell)
        if best == 0.0:
            return 0.0
        far = n1(order, w)
        for alpha in _ALPHAS:
            v = (1 - alpha) * w / (order - 1)
            near = maj.gains[ell] * n2(order, w, v)
            best = min(best, max(gain[ell].sup(alpha * w) * far, near))
        return best

    @cache
    def two(order: int, ell: int, v: float) -> float:
        """T_2: bound of |sigma^ell H_order| where two distinct |w_i|, |w_j| >= v."""
        best = m(order, ell)
        return 0.0 if best == 0.0 else min(best, maj.gains[ell] * n2(order, v, v))

    return one(n, 0, float(width))
