"""Work caps of the branch-and-bound: boxes times jet operations per box, never time.

:func:`box_work` counts the jet operations of one enclosure of H_n from the kernel's
straight-line code (machine-independent); :func:`default_budget` divides
:data:`DEFAULT_WORK` (about 8 s of enclosures on one core) by it, so every default search
of :mod:`gfrf.bounds.branch_bound` costs about the same whatever the kernel's size;
:func:`budget_note` announces a larger budget before the work; :func:`check_budget`
validates one.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from gfrf.errors import ArgumentError
from gfrf.kernels.compiled import kernel_source, rename, step_text
from gfrf.kernels.recursion import GFRFGenerator, generator
from gfrf.model.equation import Model

__all__ = ["MAX_ORDER", "BOX_LIMIT", "MAX_OPEN", "DEFAULT_WORK", "LEAST_BUDGET",
           "SECONDS_PER_WORK", "box_work", "kernel_operations", "default_budget",
           "budget_note", "check_budget"]

#: Highest kernel order searched (the enclosure costs 2^n vertices and n^2 Hessian bounds).
MAX_ORDER = 5
#: Most boxes any search may be given (bounds the cost of every input: about 10 min).
BOX_LIMIT = 20_000_000
#: Most open (undecided) boxes a search keeps: about 100 bytes each at order 5, so
#: about 50 MB.  When a split would exceed it the search stops with the bracket it has
#: (sound: the open boxes' bounds are still in the upper end).
MAX_OPEN = 500_000
#: Work of the default budget (:func:`default_budget`), in jet operations times boxes:
#: about 8 s of enclosures on one core of the 2-core 2026 machine, where one jet
#: operation on one box takes 0.2-0.3 us with the fused loops (measured on the
#: pendulum's and the cart-pole's H5, ``gfrf bench``).
DEFAULT_WORK = 36_000_000
#: Fewest boxes a default budget gives: one box, so that the default work of a large
#: kernel (a 13-term NARX model's H5: about 7,000 operations per box) stays within
#: :data:`DEFAULT_WORK` instead of a fixed box count.
LEAST_BUDGET = 1


def _taylor_source(gen: GFRFGenerator, n: int, symmetric: bool) -> str:
    """Source of ``taylor_kernel(x, inv_a)``: the recursion with 1/A as a call."""
    lines = ["def taylor_kernel(x, inv_a):",
             f"    {', '.join(f'x{i}' for i in range(n))}, = x"]
    names: dict[tuple[int, ...], str] = {}

    def emit(block: tuple[int, ...]) -> str:
        if block in names:
            return names[block]
        plan = gen.plan(len(block), symmetric)
        if plan.is_zero:
            names[block] = "0.0"
            return "0.0"
        label = "h_" + "_".join(map(str, block))
        assignments, reduced = step_text(gen, len(block), symmetric)
        mapping = {str(v): f"x{block[i]}" for i, v in enumerate(gen.variables(len(block)))}
        for sub, placeholder in zip(plan.blocks, plan.placeholders, strict=True):
            mapping[str(placeholder)] = emit(tuple(block[j] for j in sub))
        mapping.update({lhs: f"{label}{lhs}" for lhs, _ in assignments})
        for lhs, value in assignments:
            lines.append(f"    {label}{lhs} = {rename(value, mapping)}")
        lines.append(f"    {label} = -({rename(reduced, mapping)}) * inv_a({block!r})")
        names[block] = label
        return label

    lines.append(f"    return {emit(tuple(range(n)))}")
    return "\n".join(lines) + "\n"


@lru_cache(maxsize=32)
def _compiled(gen: GFRFGenerator, n: int, symmetric: bool) -> tuple[Callable[..., Any],
                                                                     Callable[..., Any]]:
    """(Taylor enclosure function, scalar point function) of H_n."""
    namespace: dict[str, Any] = {"cmath_exp": np.exp}  # the point code of a NARX model
    exec(compile(_taylor_source(gen, n, symmetric), f"<gfrf taylor H{n}>", "exec"),
         namespace)
    exec(compile(kernel_source(gen, n, symmetric, "point_kernel"), f"<gfrf H{n}>", "exec"),
         namespace)
    return namespace["taylor_kernel"], namespace["point_kernel"]


class _Count:
    """Stands for a jet in the straight-line code of H_n and counts the jet operations.

    ``phase`` mirrors the carrier of a NARX jet (:class:`gfrf.bounds.enclosure.Jet`): a
    sum of two terms on different carriers costs two more products (the turns that
    align them).  ``pure`` marks a pure carrier (a NARX variable, a product or scaling
    of them): a product with one is a scaling of the other jet and counts nothing.
    """

    def __init__(self, tally: list[int], phase: tuple[int, ...] = (), pure: bool = False
                 ) -> None:
        self.tally, self.phase, self.pure = tally, phase, pure

    def _op(self, other: object = None) -> _Count:
        self.tally[0] += 1
        return self

    def _sum(self, other: object = None) -> _Count:
        theirs = other.phase if isinstance(other, _Count) else ()
        self.tally[0] += 1 if theirs == self.phase else 9
        return self

    def _product(self, other: object = None) -> _Count:
        if not isinstance(other, _Count):  # a scaling
            self.tally[0] += 1
            return self
        if not (self.pure or other.pure):
            self.tally[0] += 1
        if other.phase:
            return _Count(self.tally, tuple(sorted(self.phase + other.phase)),
                          self.pure and other.pure)
        return _Count(self.tally, self.phase, self.pure and other.pure)

    __add__ = __radd__ = __sub__ = __rsub__ = _sum
    __mul__ = __rmul__ = _product

    def __neg__(self) -> _Count:
        return self._op()


@lru_cache(maxsize=32)
def _operations(gen: GFRFGenerator, n: int, symmetric: bool, discrete: bool = False) -> int:
    """Jet operations of one enclosure of H_n: the code's sums and products, and 1/A
    factors counted as 4 (their value, derivatives and sup bounds cost about that); for a
    NARX model (``discrete``) a sum on two carriers counts 9 (measured: its two turns
    are products over the joint coordinates, in numpy; the fused turn of
    :func:`gfrf.bounds.jet_kernels.jet_turn` made the identified example's H5 search about
    30 % cheaper, a margin the count keeps)."""
    tally = [0]

    def inv_a(_block: tuple[int, ...]) -> _Count:
        tally[0] += 4
        return _Count(tally)

    _compiled(gen, n, symmetric)[0]([_Count(tally, (i,), True) if discrete else _Count(tally)
                                     for i in range(n)], inv_a)
    return max(tally[0], 1)


def box_work(model: Model, n: int, symmetric: bool = True) -> int:
    """Jet operations per box of the branch-and-bound of H_n: both enclosures of a box
    (a NARX box gets one, :func:`gfrf.bounds.enclosure.enclose`).

    A count from the kernel's straight-line code, independent of the machine: the cost
    of a box is about proportional to it (0.2-0.3 us per operation on one core of a
    2-core 2026 machine, fused loops).

    Parameters
    ----------
    model : Model
        The plant model.
    n : int
        The order of the kernel.
    symmetric : bool, optional
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    int
        The count, at least 1.
    """
    operations = _operations(generator(model), n, symmetric, model.is_discrete)
    return operations if model.is_discrete else 2 * operations


def kernel_operations(model: Model, n: int, symmetric: bool = True) -> int:
    """Operations of one evaluation of H_n: the sums and products of its straight-line
    code (the unit of the local search's work cap, :mod:`gfrf.bounds.local_search`).

    Parameters
    ----------
    model : Model
        The plant model.
    n : int
        The order of the kernel.
    symmetric : bool, optional
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    int
        The count, at least 1.
    """
    return _operations(generator(model), n, symmetric)


def default_budget(model: Model, n: int, symmetric: bool = True) -> int:
    """Boxes the default search of H_n may evaluate: :data:`DEFAULT_WORK` divided by
    :func:`box_work` (about 8 s of enclosures on one core), at least
    :data:`LEAST_BUDGET`.  The order enters through the kernel's size; the tolerance
    through where the search stops (on ``tol`` or on this budget, whichever is first).
    A count of work, so the bracket never depends on the machine's speed.

    Parameters
    ----------
    model : Model
        The plant model.
    n : int
        The order of the kernel.
    symmetric : bool, optional
        The symmetric kernel instead of the asymmetric one.

    Returns
    -------
    int
        The number of boxes, in [:data:`LEAST_BUDGET`, :data:`BOX_LIMIT`].
    """
    return min(BOX_LIMIT, max(LEAST_BUDGET, DEFAULT_WORK // box_work(model, n, symmetric)))


#: CPU seconds per unit of work (jet operation on one box) used to announce a budget's
#: cost: DEFAULT_WORK is about 8 s on one core of the 2-core machine under load.
SECONDS_PER_WORK = 8.0 / DEFAULT_WORK


def budget_note(model: Model, n: int, symmetric: bool, max_boxes: int) -> str | None:
    """A line announcing, before the search, that ``max_boxes`` allows more work than the
    default cap (with its time estimate and its memory bound: :data:`MAX_OPEN` open boxes
    of 16 (n + 1) bytes), or None when it does not.

    Parameters
    ----------
    model : Model
        The plant model.
    n : int
        The order of the kernel.
    symmetric : bool
        The symmetric kernel instead of the asymmetric one.
    max_boxes : int
        The budget asked for.

    Returns
    -------
    str or None
        The line, or None.
    """
    if not 2 <= n <= MAX_ORDER:
        return None
    default = default_budget(model, n, symmetric)
    if max_boxes <= default:
        return None
    seconds = max_boxes * box_work(model, n, symmetric) * SECONDS_PER_WORK
    return (f"max_boxes {max_boxes} allows up to about {seconds:.3g} s of branch-and-bound "
            f"on one core (the default cap is {default} boxes, about "
            f"{default * box_work(model, n, symmetric) * SECONDS_PER_WORK:.2g} s); the "
            "search stops sooner when the gap reaches tol; its memory stays bounded: at "
            f"most {MAX_OPEN} open boxes, {MAX_OPEN * 16 * (n + 1) / 1e6:.0f} MB of box arrays")


def check_budget(max_boxes: object, least: int) -> int:
    """``max_boxes`` as an int in [least, BOX_LIMIT] (any integer type), else ArgumentError.

    Parameters
    ----------
    max_boxes : object
        The value given.
    least : int
        The smallest budget accepted.

    Returns
    -------
    int
        ``max_boxes`` as a Python int.
    """
    if (isinstance(max_boxes, bool) or not isinstance(max_boxes, numbers.Integral)
            or not least <= int(max_boxes) <= BOX_LIMIT):
        raise ArgumentError(f"max_boxes must be an integer in [{least}, {BOX_LIMIT}], got "
                            f"{max_boxes!r}")
    return int(max_boxes)
