"""The NARX lower side: the invariant box enters the certificates and heads the answer."""

from __future__ import annotations

from fractions import Fraction

from conftest import MODELS

from gfrf.model.modelfile import resolve_model
from gfrf.stability.energy import Certificate
from gfrf.twosided.lower import lower_side
from gfrf.twosided.lower_narx import BOX_METHOD


def test_narx_example_lower_is_the_exactly_checked_box_above_the_series_radius():
    # Theorem 1's r* of y[k] = 0.5y[k-1] - 0.2y[k-1]^2 u[k-2] + u[k-1] is sqrt(5)/4
    mf = resolve_model(MODELS / "narx_example.toml")
    side = lower_side(mf, Certificate("theorem 1", 5**0.5 / 4, "interval", "tones"))
    assert side.best is not None and side.best.method == BOX_METHOD
    assert side.best.proof == "exact" and side.best.radius > 2.5 * 5**0.5 / 4
    # the falsifier's escape of this model is at 1.7109: the proof must stay below it
    assert side.best.radius < 1.7109
    # the headline's re-checkable file is the box's, with its exact U
    assert side.best_file is not None and side.best_file["format"] == "gfrf-narx-box"
    assert float(Fraction(side.best_file["U"])) >= side.best.radius
