"""Floquet stability of a harmonic-balance solution by Hill's method.

Along the periodic solution the linearised equation is ``sum_l g_l(t) D^l dy = 0``
(continuous; ``g_l`` = dF/d(D^l y) on the orbit, the partials of
:meth:`gfrf.harmonic.balance.Balance.evaluate`) or ``sum_l g_l(t) dy[k-l] = 0``
(discrete).  Floquet's ansatz ``dy = exp(lambda t) p(t)`` (``mu^k p(kT)``) with p a
trigonometric polynomial of harmonics -H..H turns it into the polynomial eigenvalue
problem

    sum_l G_l (D + lambda)^l c = 0        or        sum_l mu^(L-l) G_l S_l c = 0,

with G_l the matrix of multiplication by g_l on the harmonics (exact from the balance's
samples), D the derivative (j n omega on harmonic n) and S_l the lag (exp(-j n omega l T)),
all real matrices on the cosine and sine coefficients.  It is solved as a
companion eigenproblem of size d (2H + 1), d the output order (or largest lag).  Each
true exponent appears 2H + 1 times, shifted by j n omega; the d physically relevant
ones are those whose eigenvector's harmonic weight is centred on harmonic 0 (the
eigenvector criterion of Lazarus and Thomas, 2010), the others are copies or
artefacts of the truncation; a copy has the same multiplier, so of candidates with
equal multipliers one is kept (a multiplier -1 has the two copies lambda +- j omega/2
equally centred).  The multipliers over one forcing period are
``rho = exp(lambda 2 pi / omega)`` (discrete: ``mu^(2 pi / (omega T))``); the solution is
stable when every ``|rho| < 1``, a fold has a multiplier crossing +1 and a
period-doubling one crossing -1.

For a NARX model the ansatz is imposed on the continuous interpolant, at every phase
of the forcing at once.  When omega T / (2 pi) is irrational (the generic case along a
continuation) the sampled sequence meets every phase and the moduli are its Lyapunov
multipliers; at a rational ratio the sampled system sees only finitely many phases and
its monodromy over one period can differ slightly (1e-4 relative in the tests): a
stability decision within that of the unit circle is not to be trusted there.

May import: numpy and :mod:`gfrf.harmonic.balance`.
"""

from __future__ import annotations

import math

import numpy as np

from gfrf.harmonic.balance import Balance

__all__ = ["floquet_multipliers"]

#: Largest condition number of the leading coefficient matrix (the Toeplitz matrix of
#: dF/d(highest derivative)) for which the companion form is built.
_MAX_CONDITION = 1e12
#: Relative distance below which two multipliers are the same (one exponent's copies).
_SAME = 1e-7


def floquet_multipliers(balance: Balance, partials: dict[int, np.ndarray],
                        omega: float) -> np.ndarray | None:
    """The Floquet multipliers over one forcing period of a balanced solution.

    Parameters
    ----------
    balance : Balance
        The harmonic balance the solution satisfies.
    partials : dict
        ``{l: samples of dF/d(D^l y)}`` on the orbit (:class:`~.balance.Evaluation`).
    omega : float
        Forcing frequency in rad/s.

    Returns
    -------
    ndarray or None
        The d multipliers (complex), or None when the leading coefficient of the
        linearised equation is singular on the orbit (no state form there).
    """
    h = balance.harmonics
    size = 2 * h + 1
    degree = max(partials)
    top = partials[degree]
    if np.min(np.abs(top)) <= 1e-9 * np.max(np.abs(top)) or np.min(top) < 0 < np.max(top):
        return None  # dF/d(highest term) vanishes on the orbit: no state form there
    g = {order: balance.multiplication(values) for order, values in partials.items()}
    k = np.arange(h + 1)
    coeffs = []
    for j in range(degree + 1):
        q = np.zeros((size, size))
        if balance.sample_time is None:
            for order in range(j, degree + 1):
                if order in g:
                    q += math.comb(order, j) * g[order] @ balance.operator(
                        (1j * k * omega) ** (order - j))
        elif degree - j in g:
            lag = degree - j
            q = g[lag] @ balance.operator(np.exp(-1j * k * omega * lag * balance.sample_time))
        coeffs.append(q)
    lead = coeffs[degree]
    if degree == 0 or not np.isfinite(lead).all() or np.linalg.cond(lead) > _MAX_CONDITION:
        return None
    lower = np.linalg.solve(lead, np.hstack(coeffs[:degree]))
    companion = np.zeros((degree * size, degree * size))
    companion[:-size, size:] = np.eye((degree - 1) * size)
    companion[-size:, :] = -lower
    values, vectors = np.linalg.eig(companion)
    if not np.isfinite(values).all():
        return None
    weight = np.abs(vectors[:size]) ** 2
    harmonic = np.concatenate([[0], np.repeat(np.arange(1, h + 1), 2)])
    centre = (harmonic @ weight) / weight.sum(axis=0)
    period = 2.0 * math.pi / omega
    with np.errstate(divide="ignore", over="ignore"):  # |rho| = inf: unstable
        if balance.sample_time is None:
            rho = np.exp(values * period)
        else:
            rho = np.exp(np.log(values.astype(complex)) * period / balance.sample_time)
    chosen: list[complex] = []
    for i in np.argsort(centre, kind="stable"):
        # a copy lambda + j n omega has the same multiplier: keep one of each
        if all(abs(rho[i] - r) > _SAME * max(abs(r), 1e-300) for r in chosen):
            chosen.append(complex(rho[i]))
            if len(chosen) == degree:
                break
    return np.array(chosen)
