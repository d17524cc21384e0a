"""A beam search over sign sequences u[k] = +-U: the NARX model's reachable set from rest.

The inputs of size U from rest reach a set of states that grows sample by sample; an
input escapes when that set leaves the escape level.  The beam keeps, at every sample,
the :data:`WIDTH` states with the largest score (the larger |y| of this sample and of
the next one with the next input 0: a sign acts on the output one sample later; ties by
index: the same beam on every run) among the two children u[k] = +U, -U of each
state of the previous beam, all advanced at once by the model's recursion on numpy
arrays (the generated ``rhs`` works elementwise).  The first child that leaves the
level (or is not finite) is the witness: its sign sequence, read back through the
parent links, becomes a switching input (``first_sign``, ``switch_times`` at the
sample times), replayed and proven like every other sign sequence.  The work is
WIDTH x 4 recursion steps per sample for at most :data:`HORIZON` samples.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gfrf.twosided.switching import SwitchRun

__all__ = ["beam_search", "WIDTH", "HORIZON"]

#: States kept per sample.
WIDTH = 1024
#: Samples searched at most.
HORIZON = 400


def beam_search(system: Any, amplitude: float, samples: int, level: float) -> SwitchRun:
    """The sign sequence found by the beam search, escaping or not.

    Parameters
    ----------
    system : OdeSystem
        The NARX model's generated recursion (its ``rhs``, ``sample_time``, ``order``,
        ``n_inputs``, ``n_states``).
    amplitude : float
        U, the size of the input.
    samples : int
        Number of samples at most (the search also stops at :data:`HORIZON`).
    level : float
        Escape when |y[k]| reaches it (or y[k] is not finite).

    Returns
    -------
    SwitchRun
        Escaped or not; for an escape, when (s) and the sample times (s) of the sign
        changes of the escaping sequence.
    """
    rhs = system.function("rhs")
    period = float(system.sample_time)
    lags, a, n = system.n_inputs, system.order, system.n_states
    z = np.zeros((n, 1))
    u = np.zeros((lags, 1))  # u[k], u[k-1], ... per beam member
    parents: list[np.ndarray] = []
    signs: list[np.ndarray] = []
    with np.errstate(all="ignore"):
        for k in range(min(samples, HORIZON)):
            m = z.shape[1]
            sign = np.concatenate((np.ones(m), -np.ones(m)))
            parent = np.concatenate((np.arange(m), np.arange(m)))
            zc, uc = z[:, parent], u[:, parent]
            uc = np.concatenate((sign[None, :] * amplitude, uc[:-1]), axis=0)
            out = np.zeros((1, 2 * m))
            rhs(zc, uc, out)
            y = out[0]
            parents.append(parent)
            signs.append(sign)
            bad = ~(np.abs(y) < level)
            if np.any(bad):
                return _witness(parents, signs, int(np.flatnonzero(bad)[0]), k, period)
            zn = np.concatenate((y[None, :], zc[:a - 1]), axis=0) if a else zc
            keep = np.argsort(-_lookahead(rhs, zn, uc, np.abs(y)),
                              kind="stable")[:WIDTH]
            parents[-1], signs[-1] = parent[keep], sign[keep]
            z = zn[:, keep]
            u = uc[:, keep]
    return SwitchRun(False, None, [], 1)


def _lookahead(rhs: Any, z: np.ndarray, u: np.ndarray, now: np.ndarray) -> np.ndarray:
    """The score of each child: the larger |y| of this sample and of the next one (the
    next input taken 0), so a sign that acts on the output one sample later is ranked by
    its effect."""
    un = np.concatenate((np.zeros((1, u.shape[1])), u[:-1]), axis=0)
    out = np.zeros((1, u.shape[1]))
    rhs(z, un, out)
    return np.maximum(now, np.where(np.isfinite(out[0]), np.abs(out[0]), np.inf))


def _witness(parents: list[np.ndarray], signs: list[np.ndarray], index: int, k: int,
             period: float) -> SwitchRun:
    """The escaping child's sign sequence, read back through the parent links."""
    seq = []
    for j in range(k, -1, -1):
        seq.append(int(signs[j][index]))
        index = int(parents[j][index])
    seq.reverse()
    times = [i * period for i in range(1, len(seq)) if seq[i] != seq[i - 1]]
    return SwitchRun(True, k * period, times, seq[0])
