"""Start points of the searches for ||H_n||: multisets of +-resonance frequencies.

Shared by the local search of :func:`gfrf.bounds.norms.kernel_norm` and the branch-and-bound
of :mod:`gfrf.bounds.branch_bound` started without a witness.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable

import numpy as np

__all__ = ["MAX_STARTS", "start_points"]

#: Largest number of start points evaluated for the lower bound.
MAX_STARTS = 4000


def start_points(freqs: Iterable[float], n: int) -> np.ndarray:
    """Multisets of +-resonances of size n, and size n-1 completed to hit a resonance.

    Each multiset is one representative up to permutation and global sign (|H_n| of the
    symmetric kernel is invariant under both); about :data:`MAX_STARTS` of each kind.

    Parameters
    ----------
    freqs : iterable of float
        The resonance frequencies in rad/s (0 may be among them).
    n : int
        The order of the kernel, >= 1.

    Returns
    -------
    numpy.ndarray
        One start point of n frequencies (rad/s) per row.

    Examples
    --------
    >>> start_points([0.0, 1.0], 2).tolist()
    [[-2.0, 1.0], [-1.0, -1.0], [-1.0, 0.0], [-1.0, 1.0], [0.0, 0.0]]
    """
    freqs = list(freqs)
    values = sorted({*freqs, *(-f for f in freqs)})
    targets = [f for f in values if f != 0.0] or [0.0]
    points = set()

    def add(p: tuple[float, ...]) -> None:
        p_sorted = tuple(sorted(p))
        q_sorted = tuple(sorted(-x for x in p))
        points.add(min(p_sorted, q_sorted))

    for combo in itertools.combinations_with_replacement(values, n):
        add(combo)
        if len(points) > MAX_STARTS:
            break
    for combo in itertools.combinations_with_replacement(values, n - 1):
        for t in targets:
            add((*combo, t - sum(combo)))
        if len(points) > 2 * MAX_STARTS:
            break
    return np.array(sorted(points))
