"""A storage function that is cheap to state and costly to check, for the hostile tests of
``gfrf certificate check``: V = |x|^2 + (sum of 120 random monomials)^2 on four states and
one input (exponent tuples of length 5), a true sum of squares with thousands of terms."""

from __future__ import annotations

import itertools
import random


def padded_square(seed: int = 0, count: int = 120
                  ) -> tuple[dict[tuple[int, ...], int], list[list[int]]]:
    """V's coefficients by exponent (the square of ``count`` monomials of degree 1..24 in
    four states, drawn with ``seed``, plus |x|^2) and those monomials: the basis of the
    all-ones Gram matrix of V - |x|^2."""
    rng = random.Random(seed)
    monomials = [[*m, 0] for m in itertools.product(range(7), repeat=4) if sum(m)]
    basis = rng.sample(monomials, count)
    V: dict[tuple[int, ...], int] = {}
    for a in basis:
        for b in basis:
            k = tuple(x + y for x, y in zip(a, b, strict=True))
            V[k] = V.get(k, 0) + 1
    for i in range(4):
        k = (*(2 * int(j == i) for j in range(4)), 0)
        V[k] = V.get(k, 0) + 1
    return V, basis
