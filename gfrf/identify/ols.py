"""Forward orthogonal least squares: the error reduction ratio ranking of candidate terms.

:func:`error_reduction_ratio` ranks candidate regressors as sysidentpy's FROLS does
(Chen, Billings and Luo 1989): at step ``i`` the candidate with the largest error
reduction ratio ``(w_j . y)^2 / (|w_j|^2 |y|^2)``, ``w_j`` the candidate made orthogonal
to those already chosen, joins the model.  sysidentpy applies a Householder reflection
to every remaining column at each step, with a copy of the whole matrix; here the
remaining candidates are rows of one contiguous array, made orthogonal to each chosen
regressor by a rank-one (modified Gram-Schmidt) update, so a step costs
``O(rows * candidates)`` and a whole ranking ``O(rows * candidates * terms)`` with no
copy.  The chosen regressors are orthogonalised twice against the earlier ones, so the
basis stays orthonormal to working precision.  The order of the remaining candidates,
and so the choice among exact ties, follows sysidentpy's column swaps.
"""

from __future__ import annotations

import numpy as np

__all__ = ["error_reduction_ratio"]

_EPS = float(np.finfo(np.float64).eps)


def error_reduction_ratio(psi: np.ndarray, y: np.ndarray, terms: int,
                          overwrite: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The error reduction ratios and order of the first ``terms`` regressors chosen.

    Parameters
    ----------
    psi : numpy.ndarray
        Candidate regressors, one per column (``rows x candidates``).
    y : numpy.ndarray
        The target, ``rows`` samples.
    terms : int
        Number of regressors to choose (at most the candidates).
    overwrite : bool, optional
        ``psi`` may be overwritten: when ``psi.T`` is C-contiguous (one candidate per
        contiguous row) the ranking works in it, with no copy.

    Returns
    -------
    err : numpy.ndarray
        One entry per candidate: the ratio of the regressor chosen at each step, for
        steps ``0 .. terms`` (the one after the last chosen included when there is one,
        as sysidentpy reports it), zero beyond.
    order : numpy.ndarray
        The candidate indices chosen, ``terms`` of them, in order.
    """
    rows, count = psi.shape
    target = np.asarray(y, dtype=float).ravel()
    squared_y = max(float(target @ target), _EPS)
    # one candidate per contiguous row, in the order of ``position``
    work = psi.T if overwrite and psi.dtype == np.float64 and psi.T.flags.c_contiguous \
        else np.array(psi.T, dtype=float, order="C")
    residual = target.copy()
    position = np.arange(count)  # candidate at each position, swapped as sysidentpy does
    basis = np.empty((min(terms, count), rows))
    err = np.zeros(count)
    for i in range(min(terms + 1, count)):
        rest = work[i:]
        numerators = rest @ residual
        denominators = np.einsum("ij,ij->i", rest, rest)
        denominators[denominators == 0.0] = _EPS
        ratios = numerators**2 / (denominators * squared_y) + _EPS
        best = int(np.argmax(ratios)) + i
        err[i] = ratios[best - i]
        if i == terms:
            break
        position[[i, best]] = position[[best, i]]
        work[[i, best]] = work[[best, i]]
        chosen = work[i].copy()
        for _ in range(2):  # twice is enough (Kahan, Parlett)
            chosen -= basis[:i].T @ (basis[:i] @ chosen)
        norm = float(np.linalg.norm(chosen))
        q = chosen / norm if norm > 0.0 else chosen
        basis[i] = q
        work[i + 1:] -= np.outer(work[i + 1:] @ q, q)
        residual -= (q @ residual) * q
    return err, position[:terms].copy()
