"""What escape means: the certified escape region of an oscillator and the level scale."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from gfrf import parse_model
from gfrf.twosided.escape import LEVEL_FACTOR, escape_levels, escape_region


def test_escape_region_is_where_the_restoring_force_loses_to_every_input() -> None:
    """y'' + 0.2 y' + y - 0.3 y^3 = u, U = 0.2: p(y) = y^3 * 0.3 - y - 0.2 > 0 beyond y+
    (sympy's exact real roots), and y+ is not far beyond p's largest root."""
    region = escape_region(parse_model("D(y,2) + 0.2*D(y) + y - 0.3*y**3 = u"), 0.2)
    assert region is not None
    y = sp.Symbol("y", real=True)
    p = sp.Rational(3, 10) * y**3 - y - sp.Rational(1, 5)
    top = max(float(r) for r in sp.real_roots(sp.Poly(p, y)))
    assert top < region.y_plus < top * 1.001
    assert all(float(p.subs(y, region.y_plus + d)) > 0 for d in (0, 0.1, 10, 1e6))
    # the left side: q(y) = -0.3 y^3 + y - 0.2 > 0 for y <= -y_minus
    q = -sp.Rational(3, 10) * y**3 + y - sp.Rational(1, 5)
    low = min(float(r) for r in sp.real_roots(sp.Poly(q, y)))
    assert -low < region.y_minus < -low * 1.001


def test_no_escape_region_for_a_hardening_spring() -> None:
    assert escape_region(parse_model("D(y,2) + 0.2*D(y) + y + 0.3*y**3 = u"), 1.0) is None


def test_escape_level_follows_the_separatrix_not_a_fixed_1e6() -> None:
    """y'' + 0.2 y' + y - 5e-15 y^3 = u: equilibria at +-1/sqrt(5e-15) = 1.41e7."""
    m = parse_model("D(y,2) + 0.2*D(y) + y - 5e-15*y**3 = u")
    levels = escape_levels(m, np.array([-0.1 + 0.995j, -0.1 - 0.995j]), 2)
    assert math.isclose(levels[0], LEVEL_FACTOR / math.sqrt(5e-15), rel_tol=1e-9)
    assert levels[1] >= levels[0]
