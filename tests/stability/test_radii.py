"""The three radii: proven lower r*, proven upper bound, labelled estimate.

Every reference is independent of gfrf.stability.static and gfrf.stability.estimate:
closed-form branch points of the static maps, sympy series of the closed-form static branch,
numpy roots of the critical points, direct evaluation of the symbolic kernels
(gfrf.kernels.recursion) and the certified majorant (gfrf.bounds.majorant).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from gfrf.bounds.majorant import majorant
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.stability.criteria import verdict
from gfrf.stability.estimate import fit_radius, resonant_lower_bounds
from gfrf.stability.static import radius_upper, static_series

NARX = "models/narx_example.toml"
PENDULUM = "models/hanging_pendulum_damped.toml"
CARTPOLE = "models/cartpole.toml"


def test_narx_upper_bound_is_the_closed_form_branch_point() -> None:
    # 0.2 u y^2 + 0.5 y - u = 0: discriminant 0.25 + 0.8 u^2 = 0 at u = +-i sqrt(5/16).
    bound = radius_upper(load_model(NARX).plant)
    assert bound is not None and bound.exact
    assert bound.value == pytest.approx(math.sqrt(5 / 16), rel=1e-14)
    assert bound.value >= math.sqrt(5 / 16) * (1 - 1e-15)  # rounded up
    assert abs(bound.branch_point.real) < 1e-12


def test_narx_static_series_matches_the_closed_form_branch() -> None:
    u = sp.symbols("u")
    branch = (-sp.Rational(1, 2) + sp.sqrt(sp.Rational(1, 4) + sp.Rational(4, 5) * u**2)) / (
        sp.Rational(2, 5) * u)
    reference = sp.series(branch, u, 0, 12).removeO()
    got = static_series(load_model(NARX).plant, 11)
    for n in range(12):
        assert float(got[n]) == pytest.approx(float(reference.coeff(u, n)), rel=1e-12, abs=0)


def test_narx_verdict_labels_three_radii() -> None:
    v = verdict(load_model(NARX), order=3)
    d = v.to_dict()
    assert set(d["radius_kinds"]) == {"radius", "radius_upper", "radius_estimate"}
    assert d["radius_kinds"]["radius"].startswith("lower bound r*")
    assert d["radius_kinds"]["radius"].endswith(", proven")
    assert "estimate" in d["radius_kinds"]["radius_estimate"]
    assert d["radius_upper"] == pytest.approx(math.sqrt(5 / 16), rel=1e-14)
    # r* (proven lower) <= estimate <= proven upper; here the bounds pinch to 0.559.
    assert d["radius"] <= d["radius_upper"]
    assert d["radius"] * (1 - 1e-8) <= d["radius_estimate"] <= d["radius_upper"]
    assert d["radius_estimate"] < 0.6  # the old two-term ratio said 0.79
    assert v.verdict != "stable"


def _pendulum_upper() -> float:
    # theta'' + .. + (g/L)(theta - theta^3/6) = u: u'(theta) = 0 at theta^2 = 2,
    # |u| = (g/L) sqrt(2) (1 - 1/3).
    g, length = 9.8, 4.0
    return g / length * math.sqrt(2) * 2 / 3


def test_pendulum_upper_bound_closed_form_and_estimate_inside() -> None:
    mf = load_model(PENDULUM)
    bound = radius_upper(mf.plant)
    assert bound is not None and bound.value == pytest.approx(_pendulum_upper(), rel=1e-14)
    v = verdict(mf, order=3)
    assert v.radius_upper == pytest.approx(_pendulum_upper(), rel=1e-14)
    assert v.radius <= v.radius_estimate <= v.radius_upper
    # the two-term ratio said 0.983, more terms "about 0.9 or less".
    assert v.radius_estimate <= 0.92
    # an amplitude between r* and the estimate is never called stable
    between = 0.5 * (v.radius + v.radius_estimate)
    assert verdict(mf, order=3, amplitude=between).verdict == "inconclusive"


def test_cartpole_upper_bound_from_critical_values() -> None:
    # static map of eq (12): u = theta (67.578 - 11.2455 theta^2) / (39.3185 - 19.66 theta^2)
    a, b, c, d = 67.578, 11.2455, 39.3185, 19.66
    # g' = 0: numerator of ((a - 3 b t^2)(c - d t^2) + 2 d t^2 (a - b t^2)) in t
    crit = np.roots([b * d, 0.0, -(3 * b * c - d * a), 0.0, a * c])
    values = [abs(t * (a - b * t * t) / (c - d * t * t)) for t in crit]
    reference = min(values)
    assert reference == pytest.approx(1.84613, abs=1e-5)
    v = verdict(load_model(CARTPOLE), order=3)
    assert v.radius_upper is not None and v.radius_upper <= 1.846 + 2e-4
    assert v.radius_upper == pytest.approx(reference, rel=1e-9)
    assert v.estimate_lower is not None
    assert v.estimate_lower <= v.radius_estimate <= v.radius_upper
    assert "plant" in v.estimate_of and v.verdict != "stable"


def test_quadratic_static_map_closed_form() -> None:
    # y + y^2 = u: y = (-1 + sqrt(1 + 4u))/2, branch point u = -1/4.
    bound = radius_upper(parse_model("D(y) + y + y**2 = u"))
    assert bound is not None and bound.value == pytest.approx(0.25, rel=1e-15)
    assert bound.double_root == pytest.approx(-0.5, abs=1e-12)


def test_fold_of_other_sheets_is_not_taken_for_the_branch() -> None:
    # u = y + 1.85 y^2 + 0.9 y^3: critical points y = -1 (u = -0.05, a fold of the two
    # other sheets: the branch through 0 is y = -0.0556 there, regular) and y = -10/27.
    bound = radius_upper(parse_model("D(y) + y + 1.85*y**2 + 0.9*y**3 = u"))
    y = Fraction(-10, 27)
    reference = abs(y + Fraction(185, 100) * y**2 + Fraction(9, 10) * y**3)
    assert bound is not None and not bound.exact
    assert bound.value == pytest.approx(float(reference), rel=1e-14)
    # the exact static series agrees: its root test approaches 0.1623, not 0.05
    coefficients = static_series(parse_model("D(y) + y + 1.85*y**2 + 0.9*y**3 = u"), 60)
    assert abs(float(coefficients[60])) ** (-1 / 60) > 0.15


def test_static_series_equals_zero_frequency_kernels() -> None:
    plant = load_model(PENDULUM).plant
    series = static_series(plant, 5)
    for n in (1, 3, 5):
        value = complex(kernel(plant, n)(*([0.0] * n)))
        assert value.real == pytest.approx(float(series[n]), rel=1e-12)
    assert series[2] == Fraction(0)


def test_resonant_lower_bounds_are_kernel_values_and_below_the_majorant() -> None:
    plant = load_model(PENDULUM).plant
    lower = resonant_lower_bounds(plant, 24)
    maj = majorant(plant)
    for n in range(1, 25):
        assert lower[n] <= maj.proven_upper(n) * (1 + 1e-12)
    # L_3 = |H3| at (w, w, -w) for some resonance w: at least the value at the |H1| peak
    k3 = kernel(plant, 3)
    w_r = 1.5247950681976907  # argmax of |H1| (proven sup of gfrf.bounds.norms, rad/s)
    assert lower[3] >= abs(complex(k3(w_r, w_r, -w_r))) * (1 - 1e-12)
    assert lower[3] <= abs(complex(k3(w_r, w_r, -w_r))) * 1.01


@pytest.mark.parametrize(("path", "reference"), [
    (NARX, math.sqrt(5 / 16)),
    (PENDULUM, 9.8 / 4.0 * math.sqrt(2) * 2 / 3),
    (CARTPOLE, 1.8461280582),  # critical values, see test_cartpole_upper_bound_...
])
def test_tail_fit_recovers_closed_form_radius_of_the_static_series(path: str,
                                                                   reference: float) -> None:
    """The estimator, fed the exact static series (orders 1..24), finds its closed-form
    radius: the extrapolation is checked where the answer is known (the cart-pole's
    conjugate branch points make the sequence oscillate)."""
    series = [abs(float(c)) for c in static_series(load_model(path).plant, 24)]
    radius, used, _, last = fit_radius(series)
    assert used >= 3 and last == 23
    assert radius == pytest.approx(reference, rel=0.01)


def test_page_headline_never_says_stable_on_an_estimate() -> None:
    from gfrf.report.model_facts import VerdictFacts
    from gfrf.report.model_page import headline

    model = parse_model("D(y,2) + D(y) + 2*y + y**3 = u")
    for level, stable_headline in (("interval", True), ("none", False)):
        v = verdict(model, order=1, amplitude=0.1, with_norms=False, proof=level)
        assert v.radius > 0
        first = headline(VerdictFacts.of(v))
        assert ("stable (L2)" in first) is stable_headline
        assert ("proven lower bound" in first) is stable_headline
    assert "stable" not in verdict(model, 1, 0.1, False, "none").verdict


@pytest.mark.parametrize(("path", "w"), [(PENDULUM, 0.77), (NARX, 2.1), (CARTPOLE, 4.1)])
def test_harmonic_values_are_symmetric_kernel_values(path: str, w: float) -> None:
    """Y[k, l] / C(n, k) of the harmonic recursion is H_n(w x k, -w x l) of
    gfrf.kernels.recursion."""
    from gfrf.stability.estimate import _harmonic_coefficients

    plant = load_model(path).plant
    y = _harmonic_coefficients(plant, w, 5)
    assert y is not None
    for n in (3, 5):
        k_n = kernel(plant, n)
        for k in range(n + 1):
            direct = complex(k_n(*([w] * k + [-w] * (n - k))))
            got = y[k, n - k] / math.comb(n, k)
            assert abs(got - direct) <= 1e-10 * max(abs(direct), 1e-12)
