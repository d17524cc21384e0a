"""How much symbolic work a kernel order needs, checked before that work is done.

:func:`check_recursion_work` refuses an order whose Billings / Peyton Jones recursion would
take more than about 10 s on one core, naming its estimate and the largest order that fits.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.kernels.combinatorics import recursion_work

__all__ = ["MAX_RECURSION_WORK", "MAX_PLAN_TERMS", "SECONDS_PER_TERM", "check_recursion_work"]

#: Largest a-priori recursion size (:func:`gfrf.kernels.combinatorics.recursion_work`) accepted:
#: order 11 of the cart-pole (1.0e6, about a minute) fits, its order 12 (3.1e6) does not.
MAX_RECURSION_WORK = 2_000_000
#: Most symbolic terms (summed over the recursion plans of orders 2..n) a kernel may need
#: by default: its plans and compiled numerators cost about 1.1-1.5 ms a term on one core
#: of a 2-core 2026 machine (the pendulum's H11: 8,303 terms, 10.7 s), so about 9 s.
MAX_PLAN_TERMS = 6_000
#: CPU seconds per symbolic term, for the refusal message (measured as above).
SECONDS_PER_TERM = 1.5e-3  # (the pendulum: 1.3e-3, the slowest measured: 1.5e-3)

def check_recursion_work(gen: Any, n: int, symmetric: bool = True,
                         max_terms: int | None = None) -> None:
    """Refuse an order whose recursion would take more than about 10 s, before that work.

    First the a-priori bound :data:`MAX_RECURSION_WORK` on the block assignments.  Then
    the plans of orders 2..n are built in turn (memoised: the kernel needs them) while
    their symbolic terms stay within ``max_terms`` (default :data:`MAX_PLAN_TERMS`); the
    next plan's terms are predicted, before it is built, as the last nonzero plan's
    times the growth of :func:`gfrf.kernels.combinatorics.recursion_work` (above the
    measured counts of every bundled model by 6-25 %).

    Parameters
    ----------
    gen : gfrf.kernels.recursion.GFRFGenerator
        The model's generator (:func:`gfrf.kernels.recursion.generator`): the plans it
        builds here are the kernel's, memoised.
    n : int
        Kernel order.
    symmetric : bool, optional
        Plans of the symmetric (default) or the asymmetric kernel.
    max_terms : int, optional
        Most symbolic terms (default :data:`MAX_PLAN_TERMS`).

    Raises
    ------
    ArgumentError
        The estimate is too big; the message names it, its time, the largest order that
        fits and ``max_terms`` (``gfrf kernel --max-work``) to go on anyway.
    """
    degrees = [t.degree for t in gen.model.terms]
    work = recursion_work(degrees, n)
    if work > MAX_RECURSION_WORK:
        fits = max((m for m in range(1, n)
                    if recursion_work(degrees, m) <= MAX_RECURSION_WORK), default=1)
        raise ArgumentError(f"kernel order {n} of this model needs about {work:.3g} block "
                            f"assignments, more than MAX_RECURSION_WORK = "
                            f"{MAX_RECURSION_WORK:.3g} (minutes of symbolic work); the "
                            f"largest order that fits is {fits}")
    limit = MAX_PLAN_TERMS if max_terms is None else max_terms
    total, last = 0, None
    for m in range(2, n + 1):
        if not gen.structurally_nonzero(m):
            continue
        if last is not None and (m, symmetric) not in gen._plans:
            predicted = total + last[1] * recursion_work(degrees, m) // max(
                recursion_work(degrees, last[0]), 1)
            if predicted > limit:
                raise ArgumentError(
                    f"kernel order {n} of this model needs about {predicted} symbolic terms "
                    f"(order {m} alone about {predicted - total}), more than "
                    f"{'MAX_PLAN_TERMS = ' if max_terms is None else 'max_terms = '}{limit} "
                    f"(about {predicted * SECONDS_PER_TERM:.0f} s of symbolic work on one "
                    f"core); the largest order that fits is {m - 1}; "
                    f"gfrf kernel --max-work {predicted} (max_terms) goes on anyway")
        size = len(sp.Add.make_args(gen.plan(m, symmetric).numerator))
        total, last = total + size, (m, size)
