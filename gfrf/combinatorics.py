"""The two enumerations the GFRF recursion is made of: compositions and ordered set partitions."""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from functools import lru_cache

__all__ = ["compositions", "ordered_set_partitions"]


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
