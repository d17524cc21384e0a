"""Numeric evaluation of a GFRF on arrays, in numpy.

A symmetric kernel that is real at real frequencies (the cart-pole's:
:func:`gfrf.kernels.subsets.real_on_the_axis`) is computed by subset convolution on real arrays
(:mod:`gfrf.kernels.subsets`) in slices of :data:`SUBSET_SLICE` points.  Otherwise the
recursion runs bottom-up over blocks: each order's recursion step is the
common-subexpression-eliminated text of :func:`gfrf.kernels.compiled.step_text` (the same
code the compiled kernel runs, small powers written as products) made once into a plain
Python function of numpy arrays; the kernel on the whole set of frequencies calls it once
per block of every lower order, memoised per call, so no symbolic object is touched per
point.  Points are evaluated in slices of :data:`SLICE`, which keeps every temporary array
in the processor's cache.  The path depends on the model and the order only, never on the
points or the cache.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from gfrf.kernels.compiled import Recursion, step_text
from gfrf.kernels.subsets import evaluate_subsets, real_on_the_axis

__all__ = ["SLICE", "SUBSET_SLICE", "step_function", "evaluate"]

#: Points per slice of a numeric evaluation: the recursion's temporaries (a few per term,
#: 64 kB each) then stay in cache instead of each being a fresh multi-megabyte allocation
#: (4-5x the rate at 10^6 points for the cart-pole's H3 and H5; the cart-pole's H7 at
#: 10^5 points takes 1.39 s CPU in slices of 4,096 points, 1.94 s in slices of 16,384).
SLICE = 4_096
#: Points per slice of the subset convolution on real arrays (32-64 MB of them for the
#: cart-pole's H7; fewer slices, less of Python's bookkeeping per point).
SUBSET_SLICE = 8_192


def step_function(gen: Recursion, m: int, symmetric: bool) -> Callable[..., Any]:
    """The numerator of the recursion step of order ``m`` as a function of arrays.

    Parameters
    ----------
    gen : Recursion
        The model's GFRF generator.
    m : int
        The order of the step, >= 1.
    symmetric : bool
        The symmetric kernel's step instead of the asymmetric one's.

    Returns
    -------
    callable
        ``f(variables..., placeholders...)``: the numerator P_m at the block's variables
        (s_i = j*omega_i, or q_i) and the lower-order kernels' values on its sub-blocks, in
        the order of ``gen.variables(m)`` and ``gen.plan(m, symmetric).placeholders``.
    """
    plan = gen.plan(m, symmetric)
    assignments, reduced = step_text(gen, m, symmetric)
    names = [str(v) for v in gen.variables(m)] + [str(p) for p in plan.placeholders]
    lines = [f"def numerator({', '.join(names)}):"]
    lines += [f"    {lhs} = {value}" for lhs, value in assignments]
    lines.append(f"    return {reduced}")
    namespace: dict[str, Any] = {}
    # The text is generated from the model's float coefficients and fixed names only
    # (as sympy's lambdify would generate it); no user text reaches it.
    exec(compile("\n".join(lines) + "\n", f"<gfrf H{m} step>", "exec"), namespace)
    return namespace["numerator"]


def evaluate(gen: Recursion, steps: Callable[[int], Callable[..., Any]],
             denominator: np.ndarray, n: int, omegas: list[np.ndarray],
             symmetric: bool) -> np.ndarray:
    """Numeric H_n at broadcastable arrays of angular frequencies (rad/s, or complex).

    Parameters
    ----------
    gen : Recursion
        The model's GFRF generator.
    steps : callable
        ``steps(m)``: the memoised :func:`step_function` of order m.
    denominator : numpy.ndarray
        Coefficients of A, highest power first (:func:`numpy.polyval` order).
    n : int
        The order of the kernel, >= 1 and structurally nonzero.
    omegas : list of numpy.ndarray
        n arrays that broadcast together.
    symmetric : bool
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    numpy.ndarray of complex128
        H_n with the broadcast shape (inf or nan at a pole).
    """
    shape = np.broadcast_shapes(*(np.shape(w) for w in omegas))
    size = math.prod(shape)
    subsets = symmetric and real_on_the_axis(gen, n)
    step = SUBSET_SLICE if subsets else SLICE
    if size <= step:
        return _slice(gen, steps, denominator, n, omegas, symmetric, shape, subsets)
    flat = [np.broadcast_to(w, shape).reshape(-1) for w in omegas]
    out = np.empty(size, dtype=np.complex128)
    for start in range(0, size, step):
        part = [w[start:start + step] for w in flat]
        out[start:start + step] = _slice(gen, steps, denominator, n, part, symmetric,
                                         part[0].shape, subsets)
    return out.reshape(shape)


def _slice(gen: Recursion, steps: Callable[[int], Callable[..., Any]],
           denominator: np.ndarray, n: int, omegas: list[np.ndarray], symmetric: bool,
           shape: tuple[int, ...], subsets: bool) -> np.ndarray:
    """:func:`evaluate` on one slice (``shape``: the broadcast shape; ``subsets``: by
    :func:`gfrf.kernels.subsets.evaluate_subsets`)."""
    if subsets:
        variables = [np.ravel(v) for v in np.broadcast_arrays(*omegas)]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            result = evaluate_subsets(gen, n, variables)  # real arrays at real w
        return np.array(np.broadcast_to(result, (math.prod(shape),)),
                        dtype=np.complex128).reshape(shape)
    discrete = gen.model.is_discrete
    if discrete:
        sample_time = float(gen.model.sample_time or 0.0)
        xs = [np.exp(-1j * w * sample_time) for w in omegas]
    else:
        xs = [1j * w for w in omegas]
    memo: dict[tuple[int, ...], np.ndarray] = {}

    def value(block: tuple[int, ...]) -> np.ndarray:
        if block not in memo:
            m = len(block)
            plan = gen.plan(m, symmetric)
            if plan.is_zero:
                memo[block] = np.zeros((), dtype=np.complex128)
            else:
                sub = [xs[i] for i in block]
                lower = [value(tuple(block[j] for j in b)) for b in plan.blocks]
                numerator = steps(m)(*sub, *lower)
                combined = math.prod(sub) if discrete else sum(sub)
                memo[block] = -numerator / np.polyval(denominator, combined)
        return memo[block]

    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        result = value(tuple(range(n)))
    return np.broadcast_to(np.asarray(result, dtype=np.complex128), shape).copy()
