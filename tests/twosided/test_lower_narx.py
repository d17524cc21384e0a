"""The NARX lower side: the invariant box enters the certificates and heads the answer."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from conftest import MODELS

from gfrf.model.modelfile import resolve_model
from gfrf.stability.energy import Certificate
from gfrf.twosided.lower import lower_side
from gfrf.twosided.lower_narx import BOX_METHOD


def test_narx_example_lower_is_the_exactly_checked_box_above_the_series_radius():
    # Theorem 1's r* of y[k] = 0.5y[k-1] - 0.2y[k-1]^2 u[k-2] + u[k-1] is sqrt(5)/4
    mf = resolve_model(MODELS / "narx_example.toml")
    side = lower_side(mf, Certificate(method="theorem 1", radius=5**0.5 / 4, proof="interval",
                                      input_class="tones"))
    assert side.best is not None and side.best.method == BOX_METHOD
    assert side.best.proof == "exact" and side.best.radius > 2.5 * 5**0.5 / 4
    # the falsifier's escape of this model is at 1.7109: the proof must stay below it
    assert side.best.radius < 1.7109
    # the headline's re-checkable file is the box's, with its exact U
    assert side.best_file is not None and side.best_file["format"] == "gfrf-narx-box"
    assert float(Fraction(side.best_file["U"])) >= side.best.radius


def _cubic_narx(u: np.ndarray) -> np.ndarray:
    """y[k] = 1.2y[k-1] - 0.5y[k-2] + 0.3u[k-1] + 0.1u[k-2] - 0.15y[k-1]^3 + 0.1y[k-1]u[k-1],
    written out independently of gfrf's parser and state form."""
    m, n = u.shape
    y = np.zeros((m, n))
    for k in range(2, n):
        y1, y2, u1, u2 = y[:, k - 1], y[:, k - 2], u[:, k - 1], u[:, k - 2]
        y[:, k] = 1.2 * y1 - 0.5 * y2 + 0.3 * u1 + 0.1 * u2 - 0.15 * y1**3 + 0.1 * y1 * u1
    return y


@pytest.mark.slow
def test_bounded_inputs_below_the_cubic_narx_paving_never_escape():
    """Random signs, random levels, square waves and sign feedback at the paving's radius
    stay inside its bound on |y| (an escape would make the exact check unsound)."""
    from gfrf.model.equation import parse_model
    from gfrf.stability.polysys import state_form
    from gfrf.twosided.lower_narx import PAVING_METHOD, narx_lower

    mf = resolve_model(parse_model(
        "y[k] = 1.2*y[k-1] - 0.5*y[k-2] + 0.3*u[k-1] + 0.1*u[k-2] - 0.15*y[k-1]**3 "
        "+ 0.1*y[k-1]*u[k-1]", sample_time=0.05))
    certs, files = narx_lower(state_form(mf), "every input with sup|u| <= U")
    paving = next(c for c in certs if c.method == PAVING_METHOD)
    U, N = paving.radius, 400
    bound = float(paving.detail.rsplit("|y| <= ", 1)[1])
    rng = np.random.default_rng(11)
    t = np.arange(N)
    rows = [U * rng.choice([-1.0, 1.0], size=(400, N)), U * rng.uniform(-1, 1, size=(400, N))]
    rows += [U * (-1.0) ** (t // p)[None, :] for p in range(1, 40)]
    y = _cubic_narx(np.vstack(rows))
    assert np.all(np.isfinite(y)) and np.max(np.abs(y)) <= bound
    # sign feedback on the output and on its increment, both signs
    for flip in (1.0, -1.0):
        for rule in (lambda y1, y2: y1, lambda y1, y2: y1 - y2):
            yy, uu = [0.0, 0.0], [0.0, 0.0]
            for _ in range(N):
                uu.append(flip * U * (1.0 if rule(yy[-1], yy[-2]) >= 0 else -1.0))
                yy.append(1.2 * yy[-1] - 0.5 * yy[-2] + 0.3 * uu[-2] + 0.1 * uu[-3]
                          - 0.15 * yy[-1]**3 + 0.1 * yy[-1] * uu[-2])
            assert max(map(abs, yy)) <= bound
    assert files[PAVING_METHOD]["format"] == "gfrf-narx-paving"
