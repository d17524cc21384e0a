"""The two enumerations the GFRF recursion is made of: compositions and ordered set partitions."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Iterator
from functools import lru_cache

__all__ = ["compositions", "ordered_set_partitions", "ordered_partition_count",
           "recursion_work"]


@lru_cache(maxsize=256)
def compositions(total: int, parts: int) -> tuple[tuple[int, ...], ...]:
    """All ordered ways of writing ``total`` as a sum of ``parts`` positive integers.

    >>> compositions(4, 2)
    ((1, 3), (2, 2), (3, 1))
    >>> compositions(0, 0)
    ((),)
    """
    if parts == 0:
        return ((),) if total == 0 else ()
    if parts == 1:
        return ((total,),) if total >= 1 else ()
    return tuple((first, *tail) for first in range(1, total - parts + 2)
                 for tail in compositions(total - first, parts - 1))


def ordered_set_partitions(items: tuple[int, ...], parts: int
                           ) -> Iterator[list[tuple[int, ...]]]:
    """All ordered partitions of ``items`` into ``parts`` non-empty blocks.

    Parameters
    ----------
    items : tuple of int
        The items.
    parts : int
        The number of blocks, >= 0.

    Examples
    --------
    >>> list(ordered_set_partitions((0, 1), 2))
    [[(0,), (1,)], [(1,), (0,)]]
    """
    if parts == 0:
        if not items:
            yield []
        return
    if len(items) < parts:
        return
    if parts == 1:
        yield [items]
        return
    for size in range(1, len(items) - parts + 2):
        for first in itertools.combinations(items, size):
            remaining = tuple(i for i in items if i not in first)
            for tail in ordered_set_partitions(remaining, parts - 1):
                yield [first, *tail]


@lru_cache(maxsize=1024)
def ordered_partition_count(n: int, parts: int) -> int:
    """Number of ordered partitions of n items into ``parts`` blocks, ``parts! S(n, parts)``.

    >>> ordered_partition_count(3, 2)
    6
    """
    if parts == 0:
        return 1 if n == 0 else 0
    if n < parts:
        return 0
    # p! S(n, p) = sum_j (-1)^j C(p, j) (p - j)^n (inclusion-exclusion, exact integers).
    return sum((-1) ** j * math.comb(parts, j) * (parts - j) ** n for j in range(parts + 1))


def recursion_work(degrees: Iterable[int], n: int) -> int:
    """A-priori size of the GFRF recursion up to order n: block assignments summed over
    the nonlinear terms (their total ``degrees``) and the orders 2..n.

    It bounds the symbolic plan (the memoised lower orders add at most this much again),
    so a kernel order can be refused before any work.

    Parameters
    ----------
    degrees : iterable of int
        The total degree of each term; degrees below 2 are ignored.
    n : int
        The highest order.

    Returns
    -------
    int
        The count.

    Examples
    --------
    >>> recursion_work([3], 3)
    6
    """
    degrees = tuple(d for d in degrees if d >= 2)
    return sum(ordered_partition_count(m, p) for m in range(2, n + 1) for p in degrees)
