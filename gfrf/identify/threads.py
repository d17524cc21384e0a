"""BLAS on one thread while identifying: :func:`one_blas_thread`.

Identification multiplies tall, thin matrices (many rows, a few columns) and the
verdict's harmonic balance small complex ones; there OpenBLAS threads only wait for each
other, and on two loaded cores they tripled the CPU time of ``gfrf identify``.  One
thread also makes the sums' order, hence the last bits, the same on every machine.
threadpoolctl (the optional extra ``gfrf[identify]``) sets the limit; without it the
work runs as the caller set BLAS.
"""

from __future__ import annotations

import contextlib
from typing import Any

__all__ = ["one_blas_thread"]


def one_blas_thread() -> Any:
    """A context manager with BLAS on one thread (a no-op without threadpoolctl).

    Returns
    -------
    context manager
        ``threadpoolctl.threadpool_limits(limits=1, user_api="blas")`` or
        ``contextlib.nullcontext()``.
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")
