"""Lohner's QR step: the enclosure of a set of solutions does not wrap.

Independent reference: the exact flow of a linear oscillator, the matrix exponential
(scipy's expm) applied to the corners of the starting box.
"""

from __future__ import annotations

import numpy as np
from flint import arb, ctx
from scipy.linalg import expm

from gfrf import parse_model
from gfrf.twosided.enclose import _apriori, _chain, _Field, _series, flow
from gfrf.twosided.lohner import LohnerSet, lohner_step

#: y'' + 0.2 y' + y = u with u = 0.5: z' = A z + (0, 0.5).
A = np.array([[0.0, 1.0], [-1.0, -0.2]])
U = 0.5
H = 0.125
STEPS = 200  # 25 s: about four turns of the oscillator


def _exact(z0: np.ndarray, t: float) -> np.ndarray:
    # the equilibrium (U, 0) and the decaying rotation around it
    eq = np.array([U, 0.0])
    return eq + expm(A * t) @ (z0 - eq)


def test_a_rotated_box_keeps_its_true_size_and_holds_the_exact_corners() -> None:
    shape = flow(parse_model("D(y,2) + 0.2*D(y) + y = u"))
    assert shape is not None
    old = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = 128, 25
    try:
        field = _Field(shape[0], _chain(*shape), [])
        field.u_const = arb(U)
        radius = 1e-6
        centre = np.array([0.3, -0.2])
        S = LohnerSet.of_box([arb(0.3, radius), arb(-0.2, radius)])
        for _ in range(STEPS):
            nxt = lohner_step(field, S, arb(H), 24, _apriori, _series)
            assert nxt is not None
            S = nxt
    finally:
        ctx.prec, ctx.cap = old
    hull = S.hull()
    t = STEPS * H
    corners = [centre + radius * np.array(s) for s in ((1, 1), (1, -1), (-1, 1), (-1, -1))]
    images = np.array([_exact(c, t) for c in corners])
    for j in range(2):
        lo, hi = float(hull[j].lower()), float(hull[j].upper())
        assert lo <= images[:, j].min() and images[:, j].max() <= hi
        # within a small factor of the best box around the true image (the rotated and
        # decayed box); a wrapped box grows by |J| at every step: by e^25 here
        best = np.abs(expm(A * t)).sum(axis=1)[j] * 2 * radius
        assert hi - lo <= 10 * best


def test_the_step_refuses_without_an_a_priori_enclosure() -> None:
    shape = flow(parse_model("D(y,2) + y - y**3 = u"))
    assert shape is not None
    field = _Field(shape[0], _chain(*shape), [])
    S = LohnerSet.of_box([arb(1e8), arb(1e8)])
    assert lohner_step(field, S, arb(1.0), 24, _apriori, _series) is None
