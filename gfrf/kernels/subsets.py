"""Symmetric GFRFs on arrays by subset convolution: harmonic probing run bottom-up.

Probing the model with u(t) = sum_i exp(s_i*t) gives, for every nonempty subset S of the
frequencies, the coefficient Y_S = |S|! * H_{|S|}^sym(s_S) of exp((sum of s_S)*t) by

    A(z_S) * Y_S = -sum over the nonlinear and input terms c * (f_1 * ... * f_r)(S),

where z_S is the sum of the s_i in S (a discrete model: the product of its q_i), the
factor of an output derivative D^l is g_l(B) = Y_B * z_B^l, that of an input derivative
D^k is s_i^k on a single frequency {i} (zero on larger sets), and ``*`` is the subset
convolution (f * g)(S) = sum over nonempty proper B of S of f(B) * g(S \\ B), commutative
and associative.  Terms sharing their first factors share those convolutions (the terms'
factor lists form a trie, and a convolution is linear in its second argument), and every
convolution of every subset is computed once for all the subsets that contain it (a
square f * (c*f) over the half of the pairs whose first block holds the lowest element): the
cart-pole's H7 needs 1,508 products of arrays where the recursion
(:mod:`gfrf.kernels.numeric`) runs 7,474 complex operations per point.

Each value is kept as ``c * j**p * array`` (c a float, p 0 or 1): the frequencies of a
continuous model are j*w, so sums, powers and the kernels of a model whose A(j*w) and
derivative weights are real stay real arrays, and constant factors are folded into ``c``
instead of being multiplied into arrays.  Sizes that no chain of terms reaches (even
orders of an odd nonlinearity) are skipped.  The numpy path of a symmetric kernel runs
here where the kernel is real on the axis (:func:`real_on_the_axis`: the cart-pole's H7 at
10^5 points in 0.39x the recursion's CPU time); with complex values the products cost
more than the recursion's grouped, CSE'd steps, which then run instead.  Every value is
elementwise arithmetic in a fixed order, so a point's value does not depend on the other
points of its call, on the slicing, or on any cache.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

__all__ = ["SubsetPlan", "subset_plan", "evaluate_subsets", "real_on_the_axis"]

#: A value ``c * j**p * array`` (``array`` None: the constant 1).
_Value = tuple[float, int, Any]
#: A factor of a term: (0, l) an output derivative D^l, (1, k) an input derivative D^k.
_Factor = tuple[int, int]


@dataclass(frozen=True)
class _Node:
    """A node of the terms' trie: the sum over its children f of f * (child's value),
    plus ``constant`` on the empty set (the coefficient of the terms ending here)."""

    constant: float
    children: tuple[tuple[_Factor, int], ...]  # (factor, index of the child node)


@dataclass(frozen=True)
class SubsetPlan:
    """What :func:`evaluate_subsets` does for one model and order, fixed once.

    Attributes
    ----------
    order : int
        The kernel's order n.
    nodes : tuple
        The trie of the terms' factor lists, root first, parents before children.
    work : tuple
        Per subset mask in increasing size: ``(mask, [(node, [(child, factor, B, rest),
        ...]), ...])``, the nonzero products of each node's convolutions at the subset.
    products : int
        The number of products of arrays of one evaluation (:func:`evaluate_subsets`
        costs about two array operations per product).
    """

    order: int
    nodes: tuple[_Node, ...]
    work: tuple[tuple[int, tuple[tuple[int, tuple[tuple[int, _Factor, int, int], ...]],
                                 ...]], ...]
    products: int


def _trie(model: Any) -> tuple[_Node, ...]:
    """The trie of the nonlinear and input terms' sorted factor lists (root first)."""
    raw: list[dict[Any, Any]] = [{}]
    for term in model.terms:
        if term.is_linear_output:
            continue
        factors = sorted((0, order) for order in term.y_orders) + sorted(
            (1, order) for order in term.u_orders)
        node = 0
        for factor in factors:
            if factor not in raw[node]:
                raw.append({})
                raw[node][factor] = len(raw) - 1
            node = raw[node][factor]
        raw[node][None] = raw[node].get(None, 0.0) + term.coefficient
    return tuple(_Node(constant=node.get(None, 0.0),
                       children=tuple((f, i) for f, i in node.items() if f is not None))
                 for node in raw)


def _squares(nodes: tuple[_Node, ...]) -> tuple[tuple[_Node, ...], set[int]]:
    """The trie with each square f * (c*f) taken over the ordered pairs whose first block
    holds the lowest element, its constant doubled (the other half of the pairs are the
    same products swapped); and the children whose convolutions are so restricted."""
    out = list(nodes)
    lowest: set[int] = set()
    for node in nodes:
        for factor, child in node.children:
            inner = nodes[child]
            if not inner.constant and len(inner.children) == 1 \
                    and inner.children[0][0] == factor and factor[0] == 0:
                leaf = inner.children[0][1]
                if not nodes[leaf].children:
                    out[leaf] = _Node(constant=2.0 * nodes[leaf].constant, children=())
                    lowest.add(child)
    return tuple(out), lowest


@lru_cache(maxsize=64)
def subset_plan(gen: Any, n: int) -> SubsetPlan:
    """The fixed schedule of the symmetric H_n of ``gen``'s model (memoised).

    Parameters
    ----------
    gen : gfrf.kernels.generator.GFRFGenerator
        The model's generator (its ``structurally_nonzero`` orders are skipped).
    n : int
        The kernel's order, >= 1.

    Returns
    -------
    SubsetPlan
    """
    nodes, lowest = _squares(_trie(gen.model))
    nonzero = {m for m in range(1, n + 1) if gen.structurally_nonzero(m)}
    sizes: list[set[int]] = [set() for _ in nodes]
    for index in reversed(range(len(nodes))):  # children have larger indices
        node = nodes[index]
        if node.constant:
            sizes[index].add(0)
        for (kind, _), child in node.children:
            own = nonzero if kind == 0 else {1}
            sizes[index] |= {a + b for a in own for b in sizes[child] if a + b <= n}
    full = (1 << n) - 1
    masks = sorted(range(1, full + 1), key=lambda mask: (mask.bit_count(), mask))
    work = []
    products = 0
    for mask in masks:
        size = mask.bit_count()
        per_node = []
        for index, node in enumerate(nodes):
            if size not in sizes[index]:
                continue
            pairs = []
            for factor, child in node.children:
                if factor[0] == 1:
                    blocks = [1 << i for i in range(n) if mask >> i & 1]
                else:
                    blocks = [b for b in _submasks(mask) if b.bit_count() in nonzero
                              and (child not in lowest or b & mask & -mask)]
                for block in blocks:
                    rest = mask ^ block
                    if rest.bit_count() in sizes[child] and (rest or nodes[child].constant):
                        pairs.append((child, factor, block, rest))
            products += len(pairs)
            per_node.append((index, tuple(pairs)))
        work.append((mask, tuple(per_node)))
    return SubsetPlan(order=n, nodes=nodes, work=tuple(work), products=products)


@lru_cache(maxsize=64)
def real_on_the_axis(gen: Any, n: int) -> bool:
    """Whether H_n of a continuous model is real at real frequencies, structurally.

    True when every value of :func:`evaluate_subsets` is a real array times a real
    constant (A(j*w) has only even powers of s, and every term's derivatives pair up,
    as in the cart-pole): decided by the kinds of the values, which do not depend on the
    points (one evaluation at one point).  Then this module's path runs on real arrays
    and is the numpy path of the symmetric kernel (about 0.4x the recursion's time for the
    cart-pole's H7 at 10^5 points); with complex values its products cost more than the
    recursion's operations (1.0-1.6x measured on the bundled models), so the recursion runs.

    Parameters
    ----------
    gen : gfrf.kernels.generator.GFRFGenerator
        The model's generator.
    n : int
        The kernel's order, >= 1 and structurally nonzero.

    Returns
    -------
    bool
    """
    if gen.model.is_discrete:
        return False
    with np.errstate(all="ignore"):
        value = evaluate_subsets(gen, n, [np.ones(1)] * n)
    return value.dtype.kind == "f"


def _submasks(mask: int) -> list[int]:
    """The nonempty submasks of ``mask``, in decreasing order."""
    out = []
    block = mask
    while block:
        out.append(block)
        block = (block - 1) & mask
    return out


def _mul(a: _Value, b: _Value) -> _Value:
    c, p = a[0] * b[0], a[1] + b[1]
    if p == 2:
        c, p = -c, 0
    if a[2] is None:
        return c, p, b[2]
    return c, p, a[2] if b[2] is None else a[2] * b[2]


def _add(a: _Value | None, b: _Value) -> _Value:
    if a is None or a[0] == 0.0:
        return b
    if b[0] == 0.0:
        return a
    ratio: complex | float = b[0] / a[0]
    if b[1] != a[1]:  # j*(b's array) in a's power: times j or -j
        ratio = ratio * (1j if b[1] > a[1] else -1j)
    if a[2] is None and b[2] is None:  # two constants: one constant (an array only if complex)
        total = 1.0 + ratio
        if isinstance(total, complex):
            return a[0], a[1], np.asarray(total)
        return a[0] * total, a[1], None
    x = 1.0 if a[2] is None else a[2]
    y = 1.0 if b[2] is None else b[2]
    if ratio == 1.0:
        return a[0], a[1], x + y
    if ratio == -1.0:
        return a[0], a[1], x - y
    return a[0], a[1], x + ratio * y


def _sum_products(products: list[tuple[_Value, _Value]]) -> _Value | None:
    """The sum of the products of the pairs, accumulated in place in one fresh array."""
    total: _Value | None = None
    owned = False  # total's array is a fresh array of this sum (not a stored value)
    for a, b in products:
        product = _mul(a, b)
        if owned and total is not None and product[1] == total[1] \
                and abs(product[0]) == abs(total[0]) and isinstance(product[2], np.ndarray) \
                and (total[2].dtype.kind == "c" or product[2].dtype.kind != "c") \
                and product[2].shape == total[2].shape:
            if product[0] == total[0]:
                np.add(total[2], product[2], out=total[2])
            else:
                np.subtract(total[2], product[2], out=total[2])
            continue
        stored = (a[2], b[2], None if total is None else total[2])
        total = product if total is None else _add(total, product)
        owned = isinstance(total[2], np.ndarray) and (
            total[2] is product[2] and a[2] is not None and b[2] is not None
            or all(total[2] is not v for v in stored))
    return total


def _unit(v: _Value) -> _Value:
    """``v`` with its coefficient +-1 (its magnitude multiplied into the array once)."""
    if v[2] is None or abs(v[0]) == 1.0:
        return v
    return math.copysign(1.0, v[0]), v[1], abs(v[0]) * v[2]


def _div(a: _Value, b: _Value) -> _Value:
    c, p = a[0] / b[0], a[1] - b[1]
    if p == -1:
        c, p = -c, 1
    if b[2] is None:
        return c, p, a[2]
    return c, p, (1.0 if a[2] is None else a[2]) / b[2]


def evaluate_subsets(gen: Any, n: int, xs: list[Any]) -> np.ndarray:
    """The symmetric H_n at the frequency variables ``xs`` (one slice of points).

    Parameters
    ----------
    gen : gfrf.kernels.generator.GFRFGenerator
        The model's generator.
    n : int
        The kernel's order, >= 1 and structurally nonzero.
    xs : list of numpy.ndarray
        n broadcast arrays: a continuous model's angular frequencies w_i (s_i = j*w_i),
        a discrete model's q_i = exp(-j*w_i*T).

    Returns
    -------
    numpy.ndarray
        H_n (complex128, or float64 when every value is real: the caller converts).
    """
    plan = subset_plan(gen, n)
    model = gen.model
    discrete = model.is_discrete
    linear = model.linear_output
    denominator = [float(linear.get(p, 0.0)) for p in range(max(linear) + 1)]
    x: list[_Value] = [(1.0, 0, v) if discrete else (1.0, 1, v) for v in xs]
    z: dict[int, _Value] = {}
    y: dict[int, _Value] = {}
    powers: dict[tuple[int, int], _Value] = {}
    weighted: dict[tuple[int, int], _Value] = {}
    values: list[dict[int, _Value]] = [{} for _ in plan.nodes]
    for index, node in enumerate(plan.nodes):
        if node.constant:
            values[index][0] = (node.constant, 0, None)

    def power(base: _Value, key: tuple[int, int]) -> _Value:
        if key not in powers:
            result: _Value = (1.0, 0, None)
            for _ in range(key[1]):
                result = _mul(result, base)
            powers[key] = _unit(result)
        return powers[key]

    def factor(f: _Factor, block: int) -> _Value | None:
        if f[0] == 1:
            i = block.bit_length() - 1
            return power(x[i], (-1 - i, f[1]))
        h = y.get(block)
        if h is None or f[1] == 0:
            return h
        key = (block, f[1])
        if key not in weighted:
            weighted[key] = _unit(_mul(h, power(z[block], key)))
        return weighted[key]

    for mask, per_node in plan.work:
        low = mask & -mask
        rest = mask ^ low
        first = x[low.bit_length() - 1]
        z[mask] = first if not rest else _unit(_mul(z[rest], first) if discrete
                                                else _add(z[rest], first))
        for index, pairs in per_node:
            total = _sum_products([(fa, vb) for child, f, block, remainder in pairs
                                   if (fa := factor(f, block)) is not None
                                   and (vb := values[child].get(remainder)) is not None])
            if index == 0:
                if total is not None and gen.structurally_nonzero(mask.bit_count()):
                    a: _Value = (denominator[-1], 0, None)
                    for coefficient in reversed(denominator[:-1]):
                        a = _add(_mul(a, z[mask]), (coefficient, 0, None))
                    y[mask] = _unit(_div(total, a))
                    y[mask] = (-y[mask][0], y[mask][1], y[mask][2])
            elif total is not None:
                values[index][mask] = _unit(total)
    full = (1 << n) - 1
    if full not in y:
        return np.zeros(np.broadcast_shapes(*(np.shape(v) for v in xs)), dtype=np.complex128)
    c, p, array = y[full]
    scale = c / math.factorial(n) * (1j if p else 1.0)
    shape = np.broadcast_shapes(*(np.shape(v) for v in xs))
    if array is None or np.shape(array) != shape:  # a constant kernel (no frequency in it)
        return np.full(shape, scale * (1.0 if array is None else array))
    return scale * array
