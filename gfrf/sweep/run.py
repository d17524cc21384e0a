"""Parameter sweeps: verdict, radius r*, norms or simulated boundedness over a grid.

A sweep evaluates one quantity at every point of a grid over model-file parameters
(``rho`` and ``L`` of the pendulum, the controller gains ``a, b, c`` of the cart-pole
loop).  The symbolic work is done once: :func:`gfrf.model.template.model_template` turns the
file into coefficient formulas, and each point only evaluates them and runs the
numeric criteria.  Points are grouped in chunks, one task per chunk, submitted to any
:class:`concurrent.futures.Executor`:

* ``local`` (default): in this process, no set-up;
* ``processes``: a ``dask.distributed`` LocalCluster of one single-threaded worker
  process per core of this machine;
* any other string: the address of a running dask scheduler
  (``tcp://host:8786``), used through ``Client(address).get_executor()``.

What is evaluated per point (``what``):

=========  ================================================================================
verdict    Theorem 1 (open loop) or 2 (with controller) at the amplitude: ``verdict``,
           ``radius`` r*, ``linear_stable``
radius     r* only (independent of the amplitude), ``linear_stable``
norm       ``h1`` = ||H1|| (exact) and the certified majorant ``M2..M<order>`` of ||H_n||
bounded    a simulation of the polynomial model (closed loop with a controller) driven
           by ``amplitude * cos(w_r t)`` at the resonance w_r of H1: ``bounded``,
           ``peak`` max|y|, ``blowup_time``
=========  ================================================================================

Continuous and discrete (NARX, ``sample_time``) models, with a transfer-function or a
polynomial controller, all go through the template; a structure it does not cover (a
``sample_time`` depending on a swept parameter) falls back to a full
:func:`gfrf.model.template.rebuild` of the file per point, much slower.  Every row has
``path``: ``template`` or ``rebuild``, the route its model file took.
Every row also has ``error``: empty, or the message of a point where the model is
invalid (a vanishing coefficient, ...), so one bad point does not stop a sweep.
Angular frequencies are in rad/s, amplitudes in input units.

Examples
--------
>>> data = {"equation": "D(y,2) + c*D(y) + y + 0.5*y**3 = u", "parameters": {"c": 0.2}}
>>> result = sweep(data, [parse_axis("c=0.1:0.4:2")], what="radius")
>>> [round(row["radius"], 4) for row in result.rows]
[0.0172, 0.1336]
"""

from __future__ import annotations

import contextlib
import csv
import itertools
import math
import re
import time
import warnings
from collections import Counter
from collections.abc import Mapping, Sequence
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gfrf._atomic import atomic_open, atomic_write_bytes
from gfrf._results import Result, short_repr
from gfrf.errors import ArgumentError, GfrfError
from gfrf.sweep.schedulers import SCHEDULER_TIMEOUT, InlineExecutor, check_scheduler, executor

if TYPE_CHECKING:
    from gfrf.model.template import ModelTemplate

__all__ = ["MAX_GRID_POINTS", "Axis", "SweepResult", "parse_axis", "grid", "sweep", "executor",
           "WHAT", "evaluate_point", "check_output", "check_scheduler", "SCHEDULER_TIMEOUT"]

#: Most points of one sweep grid (the product of the axes' N), checked before any work.
MAX_GRID_POINTS = 1_000_000
#: Quantities a sweep can evaluate.
WHAT = ("verdict", "radius", "norm", "bounded")

_AXIS = re.compile(r"^\s*([A-Za-z_]\w*)\s*=\s*([^:]*):([^:]*):([^:]*)$")


@dataclass(frozen=True)
class Axis:
    """One swept parameter: its name and its values (START:STOP:N, endpoints included)."""

    name: str
    values: tuple[float, ...]


def parse_axis(spec: str) -> Axis:
    """Parse ``NAME=START:STOP:N`` (N >= 1 equally spaced values, both ends included).

    Parameters
    ----------
    spec : str
        The ``--param`` text.

    Returns
    -------
    Axis
        The parameter's name and values.

    Raises
    ------
    ArgumentError
        Bad syntax, a non-numeric bound or N < 1; the message quotes ``spec``.
    """
    match = _AXIS.match(spec)
    if not match:
        raise ArgumentError(f"--param {spec!r}: expected NAME=START:STOP:N, "
                            f"e.g. rho=0.1:2:20")
    name, start, stop, count = match.groups()
    bounds = []
    for text in (start, stop):
        try:
            value = float(text)
        except ValueError:
            raise ArgumentError(f"--param {spec!r}: {text.strip()!r} is not a number") from None
        if not math.isfinite(value):
            raise ArgumentError(f"--param {spec!r}: bounds must be finite")
        bounds.append(value)
    try:
        n = int(count)
    except ValueError:
        raise ArgumentError(f"--param {spec!r}: N = {count.strip()!r} is not an integer") \
            from None
    if not 1 <= n <= MAX_GRID_POINTS:
        raise ArgumentError(f"--param {spec!r}: N = {n} must be between 1 and "
                            f"MAX_GRID_POINTS = {MAX_GRID_POINTS}")
    import numpy as np

    return Axis(name, tuple(float(v) for v in np.linspace(bounds[0], bounds[1], n)))


def grid(axes: Sequence[Axis]) -> list[dict[str, float]]:
    """All points of the grid, the last axis varying fastest.

    Parameters
    ----------
    axes : sequence of Axis
        The swept parameters (at most :data:`MAX_GRID_POINTS` points, each name once).

    Returns
    -------
    list of dict
        ``{name: value}`` per point.
    """
    names = [a.name for a in axes]
    size = math.prod(len(a.values) for a in axes)
    if size > MAX_GRID_POINTS:
        raise ArgumentError(f"the grid has {size} points, more than MAX_GRID_POINTS = "
                            f"{MAX_GRID_POINTS}")
    if len(set(names)) != len(names):
        twice = next(n for n in names if names.count(n) > 1)
        raise ArgumentError(f"parameter {twice!r} is swept twice")
    return [dict(zip(names, values, strict=True))
            for values in itertools.product(*(a.values for a in axes))]


@dataclass(frozen=True)
class _Task:
    """What every chunk needs: the template and the options (pickled once per chunk).

    ``template`` is None on the rebuild route: each point re-parses ``data``.
    """

    template: ModelTemplate | None
    what: str
    amplitude: float
    order: int
    t_end: float
    data: Mapping[str, Any] = field(default_factory=dict)
    file: str = ""

    @property
    def path(self) -> str:
        """The route of the points: ``template`` or ``rebuild``."""
        return "rebuild" if self.template is None else "template"


def _linear_stable(v: Any) -> bool:
    return bool(next(c.passed for c in v.conditions if c.name.startswith("linear")))


def evaluate_point(task: _Task, point: Mapping[str, float]) -> dict[str, Any]:
    """The row of one grid point (parameters first, then the results, then ``error``).

    Parameters
    ----------
    task : _Task
        The sweep's model (template or text), what to compute and its settings.
    point : mapping of str to float
        The parameter values of the point.

    Returns
    -------
    dict
        The row.
    """
    from gfrf.bounds.majorant import majorant
    from gfrf.bounds.norms import h1_norm
    from gfrf.model.template import rebuild
    from gfrf.stability.criteria import verdict

    row: dict[str, Any] = dict(point)
    try:
        mf = (rebuild(task.data, point, task.file) if task.template is None
              else task.template.instantiate(point))
        if task.what in ("verdict", "radius"):
            v = verdict(mf, 1, task.amplitude, with_norms=False)
            if task.what == "verdict":
                row.update(verdict=v.verdict, theorem=v.theorem)
            row.update(radius=v.radius, radius_proof=v.radius_proof,
                       linear_stable=_linear_stable(v))
        elif task.what == "norm":
            bound = h1_norm(mf.plant)
            coefficients = majorant(mf.plant).coefficients(task.order)[:, 0]
            row.update(h1=bound.upper, h1_proof=bound.upper_proof or bound.proof,
                       linear_stable=bool(bound.stable))
            row.update({f"M{n}": float(coefficients[n]) for n in range(2, task.order + 1)})
        else:
            row.update(_simulate(mf, task))
        row["path"], row["error"] = task.path, ""
    except GfrfError as exc:
        row["path"], row["error"] = task.path, str(exc)
    except (TypeError, ValueError, ArithmeticError) as exc:
        # a coefficient formula that is complex or not a number at this point (a
        # fractional power of a negative parameter, ...): this row's error, not the sweep's
        where = ", ".join(f"{name} = {value:g}" for name, value in point.items())
        row["path"], row["error"] = task.path, (f"at {where}: the model is not real-valued "
                                                f"here ({type(exc).__name__}: {exc})")
    return row


def _failure_notes(rows: list[dict[str, Any]]) -> list[str]:
    """One note per distinct failure message (the real cause: an invalid model, a work
    budget, no convergence...), with its count, most frequent first."""
    causes = Counter(r["error"] for r in rows if r["error"])
    return [f"{count} of {len(rows)} point(s) failed: {cause}"
            for cause, count in sorted(causes.items(), key=lambda kv: (-kv[1], kv[0]))[:5]]


def _simulate(mf: Any, task: _Task) -> dict[str, Any]:
    from gfrf.sim.simulation import simulate
    from gfrf.sim.validation import resonance

    w = resonance(mf.plant)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # unstable linearisations are expected
        res = simulate(mf, f"{task.amplitude!r}*cos({w!r}*t)", t_end=task.t_end,
                       closed_loop=mf.controller is not None, equation="polynomial",
                       n_out=501)
    return {"bounded": res.bounded, "peak": res.peak, "blowup_time": res.blowup_time}


def _run_chunk(task: _Task, points: list[dict[str, float]]) -> list[dict[str, Any]]:
    return [evaluate_point(task, p) for p in points]


@dataclass(frozen=True, kw_only=True, repr=False)
class SweepResult(Result):
    """The table of a sweep: one row per grid point, in grid order.

    ``to_dict`` gives the axes as ``{name: values}`` and adds the number of points and the
    throughput.

    Attributes
    ----------
    axes : tuple of Axis
        The swept parameters and their values.
    what : str
        What each point computed (``verdict``, ``radius``, ``norm`` or ``bounded``).
    amplitude : float
        The input amplitude of the verdicts.
    rows : list of dict
        One row per grid point.
    columns : list of str
        The table's columns.
    seconds : float
        Wall time of the evaluation (template excluded).
    template_seconds : float
        Time of the symbolic work (once per sweep).
    scheduler : str
        Where the points ran.
    notes : list of str
        Points that failed and why, and how the model was rebuilt.
    """

    _order = ("what", "amplitude", "scheduler", "axes", "points", "seconds",
              "template_seconds", "points_per_second", "columns", "rows", "notes")

    axes: tuple[Axis, ...]
    what: str
    amplitude: float
    rows: list[dict[str, Any]]
    columns: list[str]
    seconds: float
    template_seconds: float
    scheduler: str
    notes: list[str] = field(default_factory=list)

    def __repr__(self) -> str:
        return short_repr(self, "what", "scheduler", points=len(self.rows),
                          errors=sum(1 for r in self.rows if r["error"]),
                          axes=[a.name for a in self.axes])

    @property
    def points_per_second(self) -> float:
        """Throughput of the evaluation."""
        return len(self.rows) / self.seconds if self.seconds > 0 else math.inf

    def write(self, path: str | Path) -> Path:
        """Write the table as CSV (``.csv``) or Parquet (``.parquet``, needs pyarrow).

        The file is replaced atomically: a write that fails midway leaves the previous
        file as it was.

        Parameters
        ----------
        path : str or Path
            The output file; its suffix chooses the format.

        Returns
        -------
        Path
            The file written.
        """
        p = Path(path)
        kind = check_output(p)
        if kind == "csv":  # a failed write leaves the previous table intact
            with atomic_open(p, "w", newline="") as fh:
                writer = csv.DictWriter(fh, fieldnames=self.columns)
                writer.writeheader()
                writer.writerows(self.rows)
            return p
        import pyarrow as pa
        import pyarrow.parquet as pq

        buffer = pa.BufferOutputStream()
        pq.write_table(pa.Table.from_pylist(self.rows), buffer)
        atomic_write_bytes(p, buffer.getvalue().to_pybytes())
        return p

    def _computed(self) -> dict[str, Any]:
        """The axes as ``{name: values}``, the number of points, the throughput."""
        return {"axes": {a.name: list(a.values) for a in self.axes}, "points": len(self.rows),
                "points_per_second": self.points_per_second}


def check_output(path: str | Path) -> str:
    """The table format of ``path`` from its suffix, ``csv`` or ``parquet``.

    Parameters
    ----------
    path : str or Path
        The output file.

    Returns
    -------
    str
        ``"csv"`` or ``"parquet"``.

    Raises
    ------
    ArgumentError
        Another suffix, or ``.parquet`` without pyarrow installed.
    """
    suffix = Path(path).suffix
    if suffix == ".csv":
        return "csv"
    if suffix != ".parquet":
        raise ArgumentError(f"output {str(path)!r}: the suffix {suffix!r} is neither '.csv' "
                            f"nor '.parquet'")
    try:
        import pyarrow  # noqa: F401 - availability check
    except ImportError:
        raise ArgumentError(f"output {str(path)!r}: Parquet needs pyarrow (pip install "
                            f"pyarrow); write a .csv instead") from None
    return "parquet"


def _columns(axes: Sequence[Axis], what: str, order: int) -> list[str]:
    names = [a.name for a in axes]
    extra = {"verdict": ["verdict", "theorem", "radius", "radius_proof", "linear_stable"],
             "radius": ["radius", "radius_proof", "linear_stable"],
             "norm": ["h1", "h1_proof", "linear_stable"]
             + [f"M{n}" for n in range(2, order + 1)],
             "bounded": ["bounded", "peak", "blowup_time"]}[what]
    return names + extra + ["path", "error"]


def sweep(data: Mapping[str, Any], axes: Sequence[Axis], *, what: str = "verdict",
          amplitude: float = 1.0, order: int = 5, t_end: float = 50.0,
          scheduler: str | Executor = "local", workers: int | None = None,
          chunk_size: int | None = None, progress: bool | None = None,
          path: str = "") -> SweepResult:
    """Evaluate ``what`` at every point of the grid of ``axes``.

    Parameters
    ----------
    data : mapping
        The parsed TOML table of a model file (``tomllib.load``).
    axes : sequence of Axis
        Swept parameters (see :func:`parse_axis`).
    what : {"verdict", "radius", "norm", "bounded"}
    amplitude : float
        Input amplitude r of the verdict and of the simulations.
    order : int
        Highest order of the majorant columns (``norm``), 2..MAX_KERNEL_ORDER.
    t_end : float
        Simulated time in s (``bounded``).
    scheduler : str or Executor
        ``local``, ``processes`` or a dask scheduler address (see :func:`executor`), or
        an executor already running (reused, not closed: e.g. to time a warm cluster).
    workers : int, optional
        Worker processes for ``processes``; for an executor, its parallelism.
    chunk_size : int, optional
        Points per task; default: one in process (``local``: the progress bar moves per
        point), else about four tasks per worker, at most 64 points.
    progress : bool or None
        tqdm progress bar; None shows it on a terminal only.
    path : str
        The model file, for messages.

    Returns
    -------
    SweepResult
    """
    if what not in WHAT:
        raise ArgumentError(f"what must be one of {', '.join(WHAT)}, got {what!r}")
    if not (math.isfinite(amplitude) and amplitude > 0):
        raise ArgumentError(f"amplitude must be a positive finite number, got {amplitude!r}")
    from gfrf.kernels.recursion import check_order

    if check_order(order, "order") < 2:  # the first majorant column is M2
        raise ArgumentError(f"order must be at least 2, got {order!r}")
    if not axes:
        raise ArgumentError("a sweep needs at least one --param NAME=START:STOP:N")
    for name, value in (("chunk size", chunk_size), ("workers", workers)):
        if value is not None and (isinstance(value, bool) or value < 1):
            raise ArgumentError(f"{name} must be a positive integer, got {value!r}")
    if not (math.isfinite(t_end) and t_end > 0):
        raise ArgumentError(f"t_end must be a positive number of seconds, got {t_end!r}")
    from tqdm import tqdm

    from gfrf.model.template import TemplateUnsupported, model_template

    points = grid(axes)
    start = time.perf_counter()
    try:
        template: ModelTemplate | None = model_template(data, [a.name for a in axes], path)
    except TemplateUnsupported as exc:
        template, no_template = None, str(exc)
    task = _Task(template=template,
                 what=what,
                 amplitude=float(amplitude),
                 order=order,
                 t_end=float(t_end),
                 data=dict(data),
                 file=path)
    template_seconds = time.perf_counter() - start
    context = (contextlib.nullcontext((scheduler, workers or 1))
               if isinstance(scheduler, Executor) else executor(scheduler, workers))
    with context as (pool, n_workers):
        inline = isinstance(pool, InlineExecutor)  # one point per task: progress per point
        size = chunk_size or (1 if inline else
                              max(1, min(64, math.ceil(len(points) / (4 * n_workers)))))
        chunks = [points[i:i + size] for i in range(0, len(points), size)]
        results: list[list[dict[str, Any]]] = [[] for _ in chunks]
        disable = None if progress is None else not progress
        start = time.perf_counter()
        with tqdm(total=len(points), disable=disable, unit="pt", desc=f"sweep {what}") as bar:
            futures: dict[Future, int] = {}
            for i, chunk in enumerate(chunks):  # the in-process executor runs at submit
                future = pool.submit(_run_chunk, task, chunk)
                if inline:
                    results[i] = future.result()
                    bar.update(len(chunk))
                else:
                    futures[future] = i
            for future in as_completed(futures):
                results[futures[future]] = future.result()
                bar.update(len(results[futures[future]]))
        seconds = time.perf_counter() - start
    rows = [row for chunk in results for row in chunk]
    notes = _failure_notes(rows)
    if template is None:
        notes.append(f"no template for this model ({no_template}): every point re-parsed "
                     f"the file (path 'rebuild')")
    name = scheduler if isinstance(scheduler, str) else type(scheduler).__name__
    return SweepResult(axes=tuple(axes),
                       what=what,
                       amplitude=float(amplitude),
                       rows=rows,
                       columns=_columns(axes, what, order),
                       seconds=seconds,
                       template_seconds=template_seconds,
                       scheduler=name,
                       notes=notes)
