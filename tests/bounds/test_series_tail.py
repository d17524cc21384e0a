"""The tail sum_{n > N} ||H_n|| a^n of the norm series (gfrf.bounds.series_tail).

Reference: for a pure cubic y'' + 2 z y' + y + c y^3 = u the majorant series solves
X = b r + b c X^3 (b = sup|H1| = sup|1/A| in closed form), whose coefficients follow by
Lagrange inversion: M_{2k+1} = b^{2k+1} (b c)^k C(3k, k) / (2k + 1).  The tail is summed
with mpmath to 30 digits.
"""

from __future__ import annotations

import math

import mpmath
import pytest

from gfrf.bounds.majorant import majorant
from gfrf.bounds.series_tail import series_tail
from gfrf.model.equation import parse_model


def _exact_tail(zeta: float, c: float, amplitude: float, order: int) -> mpmath.mpf:
    mpmath.mp.dps = 30
    b = 1 / (2 * mpmath.mpf(zeta) * mpmath.sqrt(1 - mpmath.mpf(zeta) ** 2))
    g = b * mpmath.mpf(c) * b ** 2 * mpmath.mpf(amplitude) ** 2

    def term(k: mpmath.mpf) -> mpmath.mpf:
        return b * amplitude * mpmath.binomial(3 * k, k) / (2 * k + 1) * g ** k

    first = max(0, math.ceil((order + 1 - 1) / 2))   # orders 2k + 1 > order
    return mpmath.nsum(term, [first, mpmath.inf])


@pytest.mark.parametrize(("c", "amplitude", "order"),
                         [(0.5, 0.015, 3), (0.5, 0.015, 5), (1.0, 0.001, 7), (0.3, 0.04, 5)])
def test_tail_contains_the_majorant_series_tail(c: float, amplitude: float, order: int) -> None:
    zeta = 0.1
    maj = majorant(parse_model(f"D(y,2) + {2 * zeta}*D(y) + y + {c}*y**3 = u"))
    bound, proof = series_tail(maj, amplitude, order)
    exact = _exact_tail(zeta, c, amplitude, order)
    assert proof == "interval"
    assert exact <= bound <= 1.01 * exact


def test_tail_is_inf_at_or_beyond_the_radius() -> None:
    maj = majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    assert series_tail(maj, 0.1, 5) == (math.inf, "none")
    assert series_tail(maj, 0.0, 5)[0] == 0.0


def test_tail_of_a_finite_series() -> None:
    """y'' + 0.2 y' + y + c u^2 = u has H2 = -c / A only: the tail beyond order 1 is
    c a^2 sup|1/A| (closed form; the proven sup is within 1e-6), beyond order 2 it is 0
    (up to the smallest float); a linear model has no tail at all."""
    zeta, c, a = 0.1, 0.5, 0.1
    maj = majorant(parse_model(f"D(y,2) + {2 * zeta}*D(y) + y + {c}*u**2 = u"))
    exact = c * a ** 2 / (2 * zeta * math.sqrt(1 - zeta ** 2))
    first, proof = series_tail(maj, a, 1)
    assert proof == "interval" and exact <= first <= exact * (1 + 1e-5)
    assert series_tail(maj, a, 2)[0] <= 1e-300
    assert series_tail(majorant(parse_model("D(y,2) + 0.2*D(y) + y = u")), a, 1)[0] == 0.0
