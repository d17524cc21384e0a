"""Preload of the dask worker processes of :func:`gfrf.sweep.run.sweep` (``processes``).

The workers share the terminal's process group, so a Ctrl-C reaches them too; there
asyncio's handler would raise KeyboardInterrupt and print a traceback.  The interrupt is
the client's to handle (it exits 130 and closes the cluster), so workers ignore it.
"""

from __future__ import annotations

import signal
from typing import Any


def dask_setup(worker: Any) -> None:
    """Ignore SIGINT in this worker process (dask calls this when the worker starts)."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the process's main thread: leave the handler as it is
        pass
