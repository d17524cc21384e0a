"""The local search behind the lower end of :func:`gfrf.bounds.norms.kernel_norm`.

|H_n| is evaluated at the start points of :func:`gfrf.bounds.starts.start_points` (built
from the resonance frequencies of the linear part), and the best starts are polished:
Nelder-Mead on -log|H_n| for n <= 4, a batched pattern search (one vectorised call per
step) above.  Every search is bounded by a count of work, never by time: evaluations
of H_n times the operations of one evaluation (the straight-line code's sums and
products, :func:`gfrf.bounds.budget.kernel_operations`), at most
:data:`SEARCH_WORK` per search.  A search stopped by that cap returns the best point it
has (a lower end is any attained value, so it stays sound); :class:`SearchResult` says
whether it did.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf.bounds.majorant import linear_polynomials
from gfrf.bounds.rational import discrete_rational_sup, rational_sup
from gfrf.bounds.simplex import nelder_mead
from gfrf.bounds.starts import start_points
from gfrf.kernels.poles import linear_poles
from gfrf.model.equation import Model

__all__ = ["SEARCH_WORK", "SearchResult", "frequencies", "local_search"]

#: Work of one local search (evaluations of H_n times operations per evaluation):
#: 72 million, about 0.5-2 s of numpy evaluations on one core.  Every bundled model's
#: searches end far below it (at most 4,251 evaluations of at most 727 operations).
SEARCH_WORK = 72_000_000


@dataclass(frozen=True, kw_only=True)
class SearchResult:
    """Best |H_n| found by :func:`local_search` and the work it spent.

    Attributes
    ----------
    value : float
        The best |H_n| found.
    argmax : tuple of float
        Where it is attained (rad/s).
    evaluations : int
        Points at which H_n was evaluated.
    capped : bool
        True when a search stopped on :data:`SEARCH_WORK` rather than converging.
    """

    value: float
    argmax: tuple[float, ...]
    evaluations: int
    capped: bool


def frequencies(model: Model, proof: str) -> tuple[list[float], float]:
    """Resonance frequencies (rad/s, >= 0) of the linear part and a local length scale.

    Parameters
    ----------
    model : Model
        The plant model (continuous or NARX).
    proof : {"interval", "float", "none"}
        Proof level of the sups whose arguments are the peak frequencies.

    Returns
    -------
    tuple of (list of float, float)
        The sorted frequencies (0 included) and the initial step of the local searches.
    """
    num, den = linear_polynomials(model)
    if model.is_discrete:
        peaks = [discrete_rational_sup(num, den, model.sample_time, proof).omega,  # type: ignore[arg-type]
                 discrete_rational_sup(np.ones(1), den, model.sample_time, proof).omega]  # type: ignore[arg-type]
        return sorted({0.0, *(abs(p) for p in peaks if math.isfinite(p))}), \
            0.01 * math.pi / model.sample_time  # type: ignore[operator]
    poles = linear_poles(model)
    freqs = {0.0, *(float(abs(p.imag)) for p in poles)}
    for res in (rational_sup(num, den, proof), rational_sup(np.ones(1), den, proof)):
        if math.isfinite(res.omega):
            freqs.add(float(res.omega))
    damping = [abs(p.real) for p in poles if abs(p.real) > 0]
    scale = min(max(0.25 * min(damping, default=1.0), 1e-9), 0.5)
    rounded = sorted({round(f, 12) for f in freqs})
    return rounded, scale


def local_search(k: Any, model: Model, n: int, symmetric: bool, upper: float, tol: float,
                 proof: str, operations: int, searches: int | None = None) -> SearchResult:
    """Best |H_n| from resonance start points, locally maximised within a work cap.

    Parameters
    ----------
    k : callable
        ``k(*w)``: H_n at angular frequencies (rad/s), vectorised.
    model : Model
        The plant model (its linear part gives the start points).
    n : int
        Kernel order.
    symmetric : bool
        Symmetric kernel (starts up to permutation) or the asymmetric one.
    upper : float
        A known upper bound: the searches stop once the best value is within ``tol``.
    tol : float
        Relative gap at which further searches are not run.
    proof : {"interval", "float", "none"}
        Proof level of the resonance frequencies (:func:`frequencies`).
    operations : int
        Operations of one evaluation of H_n (the unit of :data:`SEARCH_WORK`).
    searches : int or None, optional
        Most local searches (default: up to 12 for n <= 4 and 2 above).

    Returns
    -------
    SearchResult
    """
    freqs, scale = frequencies(model, proof)
    starts = start_points(freqs, n)
    if not symmetric and n <= 4:
        starts = np.unique(np.array([p for s in starts for p in itertools.permutations(s)]),
                           axis=0)
    values = np.abs(k(*starts.T))
    values[~np.isfinite(values)] = 0.0
    order = np.argsort(values)[::-1]
    best, best_x = float(values[order[0]]), tuple(float(v) for v in starts[order[0]])
    evaluations, capped = len(starts), False
    most_points = max(1, SEARCH_WORK // max(1, operations))
    batch = 4 if n <= 4 else 1
    most = 3 * batch if n <= 4 else 2
    for count, i in enumerate(order[: most if searches is None else min(most, searches)]):
        if count >= batch and (upper - best) <= tol * upper:
            break
        x, value, spent, stopped = (_nelder_mead(k, starts[i], scale, most_points) if n <= 4
                                    else _pattern_search(k, starts[i], scale, most_points))
        evaluations += spent
        capped = capped or stopped
        if math.isfinite(value) and value > best:
            best, best_x = value, tuple(float(v) for v in x)
    return SearchResult(value=best, argmax=best_x, evaluations=evaluations, capped=capped)


def _nelder_mead(k: Any, x0: np.ndarray, scale: float, most_points: int
                 ) -> tuple[np.ndarray, float, int, bool]:
    """Nelder-Mead on -log|H_n| (low orders, where a scalar evaluation is cheap):
    (x, |H_n(x)|, evaluations, stopped on the cap)."""
    n = x0.size
    calls = [0]

    def objective(x: np.ndarray) -> float:
        calls[0] += 1
        v = abs(complex(k(*x)))
        return -math.log(v) if v > 0 and math.isfinite(v) else 1e300

    simplex = np.vstack([x0, x0 + scale * np.eye(n)])
    maxfev = min(800 * n, most_points)
    res = nelder_mead(objective, x0, initial_simplex=simplex, xatol=1e-12 * (1 + scale),
                      fatol=1e-14, maxiter=600 * n, maxfev=maxfev)
    return res.x, abs(complex(k(*res.x))), calls[0] + 1, maxfev < 800 * n and \
        calls[0] >= maxfev


def _pattern_search(k: Any, x0: np.ndarray, scale: float, most_points: int
                    ) -> tuple[np.ndarray, float, int, bool]:
    """Batched pattern search along +-e_i and +-e_i +- e_j (one vectorised call per step):
    (x, |H_n(x)|, evaluations, stopped on the cap)."""
    n = x0.size
    eye = np.eye(n)
    pairs = [eye[i] + sign * eye[j] for i in range(n) for j in range(i + 1, n)
             for sign in (1.0, -1.0)]
    directions = np.vstack([eye, -eye, *pairs, *(-p for p in pairs)])
    x, value = x0.copy(), float(abs(k(*x0)))
    evaluations, step = 1, scale
    while step > 1e-12 * (1 + scale):
        if evaluations + len(directions) > most_points:
            return x, value, evaluations, True
        trial = x + step * directions
        values = np.abs(k(*trial.T))
        evaluations += len(directions)
        values[~np.isfinite(values)] = 0.0
        j = int(np.argmax(values))
        if values[j] > value:
            x, value = trial[j], float(values[j])
        else:
            step *= 0.5
    return x, value, evaluations, False
