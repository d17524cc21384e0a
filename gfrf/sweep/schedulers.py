"""Where the points of a sweep run: in this process, in threads, in local processes (a
dask cluster started and stopped with the sweep) or on a dask scheduler's workers.

:func:`executor` gives a :class:`concurrent.futures.Executor` and its worker count;
:func:`check_scheduler` checks the ``--scheduler`` text before any work.  Ctrl-C while a
cluster starts or computes kills its worker processes at once.
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
from collections.abc import Iterator
from concurrent.futures import Executor, Future, ThreadPoolExecutor
from typing import Any
from urllib.parse import urlsplit

from gfrf.errors import ArgumentError

__all__ = ["executor", "check_scheduler", "InlineExecutor", "SCHEDULER_TIMEOUT"]

class InlineExecutor(Executor):
    """Runs each task at submission, in this process: the set-up-free default."""

    def submit(self, fn: Any, /, *args: Any, **kwargs: Any) -> Future:
        """Run ``fn(*args, **kwargs)`` now; its result or exception in a done future.

        Parameters
        ----------
        fn : callable
            The task.
        *args, **kwargs
            Its arguments.
        """
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:
            future.set_exception(exc)
        return future


#: Seconds a dask scheduler address has to answer (connect and handshake) before the
#: sweep gives up with an error; a listener that is not a dask scheduler never answers.
SCHEDULER_TIMEOUT = 10.0


def check_scheduler(scheduler: str) -> str:
    """Validate a ``--scheduler`` value; return it (``host:port`` becomes ``tcp://host:port``).

    Accepted: ``local``, ``processes`` and ``tcp://HOST:PORT`` (or ``HOST:PORT``).

    Parameters
    ----------
    scheduler : str
        The ``--scheduler`` text.

    Returns
    -------
    str
        The scheduler, an address with its scheme.

    Raises
    ------
    ArgumentError
        Another scheme (``inproc://`` is private to a process, ``tls://`` needs a
        security context the command line cannot pass, ``ucx://`` needs ucx-py), no
        host, or a port that is not an integer in 1..65535.
    """
    if scheduler in ("local", "processes"):
        return scheduler
    address = scheduler if "://" in scheduler else f"tcp://{scheduler}"
    scheme = address.split("://", 1)[0]
    why = {"inproc": "an in-process address belongs to another process",
           "tls": "TLS needs a security context (certificates), which this option cannot "
                  "pass; use a tcp:// address or the Python API with a Client",
           "ucx": "UCX needs ucx-py and a UCX network; use a tcp:// address"}
    if scheme != "tcp":
        reason = why.get(scheme, f"unknown scheme {scheme + '://'!r}; use 'local', "
                                 f"'processes' or tcp://host:port")
        raise ArgumentError(f"scheduler {scheduler!r}: {reason}")
    parts = urlsplit(address)
    try:
        port = parts.port
    except ValueError:
        port = None
    if not parts.hostname or port is None or not 1 <= port <= 65535 \
            or parts.path or parts.query or parts.fragment:
        raise ArgumentError(f"scheduler {scheduler!r}: expected tcp://HOST:PORT with a port "
                            f"in 1..65535, e.g. tcp://127.0.0.1:8786")
    return address


def _probe(address: str, timeout: float) -> None:
    """Connect to ``address`` and complete dask's handshake within ``timeout`` seconds.

    ``distributed.Client`` waits for the handshake without a time limit, so a listener
    that accepts but never speaks dask would hang it; this runs the handshake in a
    thread of its own (with its own event loop) and gives up after ``timeout``.
    """
    import asyncio

    from distributed.comm import connect

    async def handshake() -> None:
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
        await comm.close()

    pool = ThreadPoolExecutor(1)
    try:
        pool.submit(asyncio.run, handshake()).result(timeout=timeout + 1.0)
    except TimeoutError:
        raise ArgumentError(f"no dask scheduler answered at {address!r} within "
                            f"{timeout:g} s (nothing listens there, or what listens "
                            f"is not a dask scheduler)") from None
    except OSError as exc:
        raise ArgumentError(f"cannot reach the dask scheduler {address!r}: {exc}") from None
    finally:
        pool.shutdown(wait=False)


def _start_cluster(n: int) -> Any:
    """A LocalCluster of ``n`` single-threaded worker processes, started in a helper
    thread while this process's standard error (file descriptor 2) points to the null
    device.

    The worker processes inherit that descriptor: they share the terminal's process
    group, so a Ctrl-C while they start (importing, before their preload ignores it)
    interrupts their interpreter start-up, and the fatal error it prints must not reach
    the terminal.  Nothing of gfrf's output comes from a worker's standard error (dask's
    logs are silenced; a point's error reaches the sweep through its future).  This
    thread stays interruptible and gets its standard error back before anything is
    raised: on Ctrl-C the workers started so far are killed, dask's exit-time close of
    the half-started cluster is dropped (it asserted on the workers' state and printed a
    traceback), and KeyboardInterrupt propagates.
    """
    import threading

    from distributed import LocalCluster

    box: dict[str, Any] = {}

    def build() -> None:
        try:
            # silence_logs: dask's own log lines (on Ctrl-C the nanny and the workers log
            # ERRORs for the connections torn down) are not gfrf's output; a point's
            # error reaches the sweep through its future.  The preload makes workers
            # ignore Ctrl-C for good.
            box["cluster"] = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                          dashboard_address=None,
                                          silence_logs=logging.CRITICAL,
                                          preload=["gfrf.sweep._dask_worker"])
        except BaseException as exc:  # handed to the caller's thread
            box["error"] = exc

    thread = threading.Thread(target=build, name="gfrf-cluster-start", daemon=True)
    stderr = os.dup(2)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 2)
        thread.start()
        while thread.is_alive():
            thread.join(0.05)
    except KeyboardInterrupt:
        os.dup2(stderr, 2)
        _abandon_start()
        raise
    finally:
        os.dup2(stderr, 2)
        os.close(stderr)
        os.close(null)
    if "error" in box:
        raise box["error"]
    return box["cluster"]


def _abandon_start() -> None:
    """Kill the worker processes of an interrupted cluster start (SIGKILL) and drop
    dask's exit-time close of clusters, which would wait on them."""
    import atexit

    from distributed.deploy import spec

    atexit.unregister(spec.close_clusters)
    _silence_dask()  # the start goes on in its thread: its log lines are not ours
    _kill_children()
    atexit.register(_kill_children)  # and a worker it spawns meanwhile dies at exit


def _silence_dask() -> None:
    """Raise every dask logger to CRITICAL for good: the connections torn down by a
    Ctrl-C make dask log INFO lines and tracebacks, which are not gfrf's output (the
    level ``silence_logs`` sets is restored when the cluster closes, before those)."""
    for name in ("distributed", *logging.root.manager.loggerDict):
        if name.startswith("distributed"):
            logging.getLogger(name).setLevel(logging.CRITICAL)


def _kill_children() -> None:
    """SIGKILL this process's multiprocessing children (dask's worker processes) and reap
    them: no zombie outlives this process."""
    import multiprocessing

    children = multiprocessing.active_children()
    for child in children:
        with contextlib.suppress(OSError, AttributeError):
            child.kill()
    for child in children:
        child.join(1.0)


def _kill_workers(cluster: Any) -> None:
    """End the worker processes of a local cluster at once: each nanny is told not to
    restart its worker, the workers get SIGKILL and are reaped.  Closing the cluster then
    takes a fraction of a second instead of the seconds a graceful retirement takes."""
    from distributed.core import Status

    _silence_dask()
    for nanny in list(getattr(cluster, "workers", {}).values()):
        with contextlib.suppress(AttributeError):
            nanny.status = Status.closing_gracefully  # no restart of a killed worker
        pid = getattr(nanny, "pid", None)
        if pid:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
    _kill_children()


@contextlib.contextmanager
def executor(scheduler: str = "local", workers: int | None = None
             ) -> Iterator[tuple[Executor, int]]:
    """An executor for ``scheduler`` and its number of parallel workers; closed on exit.

    Parameters
    ----------
    scheduler : str
        ``local``, ``processes`` or a dask scheduler address ``tcp://host:port`` (see
        :func:`check_scheduler`).  An address must answer within
        :data:`SCHEDULER_TIMEOUT` seconds.
    workers : int, optional
        Worker processes of ``processes`` (default: the machine's cores).

    Raises
    ------
    ArgumentError
        dask.distributed is missing, the scheduler string is not understood, or no
        dask scheduler answers at the address in time.
    """
    scheduler = check_scheduler(scheduler)
    if scheduler == "local":
        yield InlineExecutor(), 1
        return
    try:
        from distributed import Client
    except ImportError:
        raise ArgumentError("scheduler 'processes' or an address needs dask.distributed: "
                            "pip install 'gfrf[dask]'") from None
    if scheduler == "processes":
        n = workers or os.cpu_count() or 1
        cluster = _start_cluster(n)
        with cluster:
            try:
                with Client(cluster) as client:
                    try:
                        yield client.get_executor(), n
                    except BaseException:
                        _kill_workers(cluster)  # Ctrl-C or an error: no graceful retirement
                        raise
            except BaseException:  # also a Ctrl-C while the client connects
                _kill_workers(cluster)
                raise
        return
    _probe(scheduler, SCHEDULER_TIMEOUT)
    try:
        client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise ArgumentError(f"cannot reach the dask scheduler {scheduler!r}: {exc}") from None
    with client:
        yield client.get_executor(), max(1, sum(client.nthreads().values()))
