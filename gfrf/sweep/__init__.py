"""Parameter sweeps: a verdict or simulation on every point of a grid, in parallel.

:mod:`.run` holds the grid, the schedulers (threads, processes, a dask cluster) and
:func:`sweep`; :mod:`.plot` draws a sweep; :mod:`._dask_worker` is the worker preload.

May import: :mod:`gfrf.sim` and everything below it, and the shared helpers.
Public face: :func:`sweep`, :class:`SweepResult`, :func:`check_scheduler`,
:func:`parse_axis`.
"""
