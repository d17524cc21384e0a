"""The poles of a model's linear part, as points s of the s-plane (rad/s).

One rule for every stage that places frequencies on the resonances of H1 = -B/A (the
kernel plots' grids, the start points of the norm searches, the resonant lower bounds
of the estimate): the roots of A(s) for a continuous model; for a discrete (NARX)
model the nonzero roots q of A(q) (A's coefficients by lag, lowest first) mapped by
q = exp(-s T), so s = -(ln|q| + j arg q) / T, with |Im s| <= pi / T.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> s = linear_poles(parse_model("D(y,2) + 2*D(y) + 5*y = u"))
>>> sorted((float(p.real), float(abs(p.imag))) for p in s)
[(-1.0, 2.0), (-1.0, 2.0)]
"""

from __future__ import annotations

import numpy as np

from gfrf.model.equation import Model
from gfrf.model.scaling import normalized

__all__ = ["linear_poles"]


def linear_poles(model: Model) -> np.ndarray:
    """The poles s (rad/s) of the linear part of ``model``, each conjugate pair in full.

    Parameters
    ----------
    model : Model
        A continuous or discrete (NARX) model.

    Returns
    -------
    numpy.ndarray
        Complex poles, in :func:`numpy.roots` order; empty when A is a constant.  A
        NARX root q = 0 (a pure delay) has no s and is left out.
    """
    a = normalized(model).linear_output
    den = np.array([a.get(k, 0.0) for k in range(max(a) + 1)])
    if den.size < 2:
        return np.zeros(0, dtype=complex)
    if not model.is_discrete:
        return np.asarray(np.roots(den[::-1]), dtype=complex)
    q = np.roots(den[::-1])
    q = q[q != 0]
    step = float(model.sample_time)  # type: ignore[arg-type]
    return np.asarray(-np.log(np.abs(q)) / step - 1j * (np.angle(q) / step), dtype=complex)
