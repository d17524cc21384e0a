"""Nelder-Mead simplex minimisation in plain numpy (no scipy import).

The lower ends of the kernel-norm brackets (:mod:`gfrf.bounds.norms`,
:mod:`gfrf.bounds.branch_bound`)
polish their best start points with Nelder-Mead.  ``scipy.optimize`` costs about a third
of a second to import, more than the rest of ``gfrf norm``'s start-up, so this module
carries the algorithm itself: the same steps, in the same order and with the same
floating-point expressions, as ``scipy.optimize.minimize(method="Nelder-Mead")``
(``scipy/optimize/_optimize.py::_minimize_neldermead``, non-adaptive coefficients,
no bounds), so the two agree to the last bit on the same objective.  Deterministic:
it stops on the simplex size, an iteration count or an evaluation count, never on time.

Examples
--------
>>> import numpy as np
>>> res = nelder_mead(lambda x: float((x[0] - 1.0) ** 2 + 10.0 * (x[1] + 2.0) ** 2),
...                   np.zeros(2), xatol=1e-10, fatol=1e-12)
>>> np.allclose(res.x, [1.0, -2.0], atol=1e-8)
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gfrf.errors import ArgumentError

__all__ = ["SimplexResult", "nelder_mead"]

# Reflection, expansion, contraction and shrink coefficients (scipy's non-adaptive ones).
_RHO, _CHI, _PSI, _SIGMA = 1, 2, 0.5, 0.5
# Default initial simplex: each nonzero coordinate of x0 scaled by 1.05, a zero one set
# to 0.00025 (scipy's ``nonzdelt`` and ``zdelt``).
_NONZDELT, _ZDELT = 0.05, 0.00025


@dataclass(frozen=True, kw_only=True)
class SimplexResult:
    """Outcome of :func:`nelder_mead`.

    Parameters
    ----------
    x : numpy.ndarray
        Best vertex of the final simplex.
    fun : float
        Objective value at ``x``.
    nfev : int
        Objective evaluations made.
    nit : int
        Iterations counted as scipy counts them (starting at 1).
    converged : bool
        True when the ``xatol`` / ``fatol`` test stopped the search, False when
        ``maxiter`` or ``maxfev`` did.
    """

    x: np.ndarray
    fun: float
    nfev: int
    nit: int
    converged: bool


class _Exhausted(Exception):
    """The evaluation budget ``maxfev`` is spent (internal control flow)."""


def _initial_simplex(x0: np.ndarray) -> np.ndarray:
    """scipy's default simplex around ``x0``: one coordinate perturbed per vertex."""
    sim = np.empty((x0.size + 1, x0.size), dtype=float)
    sim[0] = x0
    for k in range(x0.size):
        y = np.array(x0, copy=True)
        y[k] = (1 + _NONZDELT) * y[k] if y[k] != 0 else _ZDELT
        sim[k + 1] = y
    return sim


def _budgets(n: int, maxiter: int | None, maxfev: int | None) -> tuple[float, float]:
    """Iteration and evaluation limits, defaults as in scipy (200 n each if neither given)."""
    for name, value in (("maxiter", maxiter), ("maxfev", maxfev)):
        if value is not None and value < 1:
            raise ArgumentError(f"nelder_mead: {name} must be at least 1, got {value}")
    if maxiter is None and maxfev is None:
        return 200 * n, 200 * n
    return (math.inf if maxiter is None else float(maxiter),
            math.inf if maxfev is None else float(maxfev))


def nelder_mead(fun: Callable[[np.ndarray], float], x0: np.ndarray, *,
                initial_simplex: np.ndarray | None = None, xatol: float = 1e-4,
                fatol: float = 1e-4, maxiter: int | None = None,
                maxfev: int | None = None) -> SimplexResult:
    """Minimise ``fun`` over R^N by the Nelder-Mead simplex method.

    The algorithm of ``scipy.optimize.minimize(fun, x0, method="Nelder-Mead",
    options=...)`` with the same options and defaults (reflection 1, expansion 2,
    contraction 0.5, shrink 0.5): same vertices, same evaluations, same stopping rule.

    Parameters
    ----------
    fun : callable
        Objective ``fun(x) -> float`` on a 1-D array of length N (it receives a copy).
        A NaN value sorts last, so that vertex is replaced first.
    x0 : numpy.ndarray
        Starting point, shape (N,).
    initial_simplex : numpy.ndarray, optional
        The N + 1 starting vertices, shape (N + 1, N); overrides the default simplex
        built from ``x0`` (scipy's: each coordinate in turn scaled by 1.05, or set to
        0.00025 where it is zero).
    xatol : float, optional
        Convergence needs every vertex within ``xatol`` of the best one in every
        coordinate ...
    fatol : float, optional
        ... and every vertex value within ``fatol`` of the best value (scipy's test).
    maxiter : int, optional
        Largest iteration count.  Default 200 N when ``maxfev`` is not given either,
        else unlimited.
    maxfev : int, optional
        Largest number of objective evaluations; the search stops as soon as it is
        spent, even mid-step.  Default 200 N when ``maxiter`` is not given either,
        else unlimited.

    Returns
    -------
    SimplexResult
        Best vertex, its value, evaluations and iterations, and whether the tolerance
        test (rather than a budget) ended the search.

    Raises
    ------
    ArgumentError
        ``x0`` is not a non-empty finite vector, ``initial_simplex`` is not (N + 1, N)
        and finite, or a budget is below 1.

    Notes
    -----
    scipy reports ``fun = min(final values)``, which is NaN if any vertex value is
    NaN; here ``fun`` is the value at ``x``.  Everything else is scipy's.
    """
    x0 = np.asarray(x0, dtype=float)
    if x0.ndim != 1 or x0.size == 0 or not np.all(np.isfinite(x0)):
        raise ArgumentError(f"nelder_mead: x0 must be a non-empty finite vector, got {x0!r}")
    n = x0.size
    if initial_simplex is None:
        sim = _initial_simplex(x0)
    else:
        sim = np.array(initial_simplex, dtype=float)
        if sim.shape != (n + 1, n) or not np.all(np.isfinite(sim)):
            raise ArgumentError(f"nelder_mead: initial_simplex must be a finite array of "
                                f"shape ({n + 1}, {n}), got shape {sim.shape}")
    max_iter, max_fev = _budgets(n, maxiter, maxfev)
    nfev = 0

    def evaluate(x: np.ndarray) -> float:
        nonlocal nfev
        if nfev >= max_fev:
            raise _Exhausted
        nfev += 1
        return float(fun(np.copy(x)))

    fsim = np.full(n + 1, np.inf)
    try:
        for k in range(n + 1):
            fsim[k] = evaluate(sim[k])
    except _Exhausted:
        pass
    # scipy sorts twice here; argsort need not be stable, so the second sort can reorder
    # ties, and is kept for identical vertices.
    for _ in range(2):
        order = np.argsort(fsim)
        sim, fsim = np.take(sim, order, 0), np.take(fsim, order, 0)

    iterations, converged = 1, False
    while nfev < max_fev and iterations < max_iter:
        try:
            if (np.max(np.ravel(np.abs(sim[1:] - sim[0]))) <= xatol
                    and np.max(np.abs(fsim[0] - fsim[1:])) <= fatol):
                converged = True
                break
            _step(sim, fsim, evaluate)
            iterations += 1
        except _Exhausted:
            pass
        order = np.argsort(fsim)
        sim, fsim = np.take(sim, order, 0), np.take(fsim, order, 0)
    return SimplexResult(x=sim[0], fun=float(fsim[0]), nfev=nfev, nit=iterations,
                         converged=converged)


def _step(sim: np.ndarray, fsim: np.ndarray, evaluate: Callable[[np.ndarray], float]
          ) -> None:
    """One Nelder-Mead step on the sorted simplex, in place (scipy's expressions)."""
    n = sim.shape[1]
    xbar = np.add.reduce(sim[:-1], 0) / n
    xr = (1 + _RHO) * xbar - _RHO * sim[-1]
    fxr = evaluate(xr)
    if fxr < fsim[0]:
        xe = (1 + _RHO * _CHI) * xbar - _RHO * _CHI * sim[-1]
        fxe = evaluate(xe)
        sim[-1], fsim[-1] = (xe, fxe) if fxe < fxr else (xr, fxr)
        return
    if fxr < fsim[-2]:
        sim[-1], fsim[-1] = xr, fxr
        return
    if fxr < fsim[-1]:  # outside contraction
        xc = (1 + _PSI * _RHO) * xbar - _PSI * _RHO * sim[-1]
        fxc = evaluate(xc)
        if fxc <= fxr:
            sim[-1], fsim[-1] = xc, fxc
            return
    else:  # inside contraction
        xcc = (1 - _PSI) * xbar + _PSI * sim[-1]
        fxcc = evaluate(xcc)
        if fxcc < fsim[-1]:
            sim[-1], fsim[-1] = xcc, fxcc
            return
    for j in range(1, n + 1):  # shrink towards the best vertex
        sim[j] = sim[0] + _SIGMA * (sim[j] - sim[0])
        fsim[j] = evaluate(sim[j])
