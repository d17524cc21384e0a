"""Tests of gfrf.bounds.enclosure: sound, third-order box bounds of |H_n| near a sharp peak."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from gfrf.bounds.branch_bound import box_bounds
from gfrf.bounds.norms import kernel_norm
from gfrf.kernels.compiled import HAVE_NUMBA
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model, resolve_model

PENDULUM = "models/hanging_pendulum.toml"
MIXED = "D(y,2) + 0.3*D(y) + 1.5*y + 0.4*y**2 - 0.2*y**3 + 0.1*y*u = u"


@pytest.fixture(scope="module")
def peak() -> tuple[object, np.ndarray, float]:
    """The pendulum's H5 and a maximiser found by the local search (lower end)."""
    m = load_model(PENDULUM).plant
    b = kernel_norm(m, 5, max_boxes=0, proof="float")
    return m, np.array(b.argmax), b.lower


@pytest.mark.parametrize("width", [1e-2, 3e-3, 1e-3, 3e-4, 1e-4])
def test_bounds_hold_on_boxes_around_the_peak(peak, width: float) -> None:
    m, x, _ = peak
    rng = np.random.default_rng(11)
    centres = x + rng.uniform(-width, width, (40, 5))
    lo, hi = centres - width / 2, centres + width / 2
    bound, _, _ = box_bounds(m, 5, lo, hi)
    k = kernel(m, 5)
    for j in range(40):
        points = lo[j] + rng.uniform(0, 1, (400, 5)) * (hi[j] - lo[j])
        points[:32] = np.where(rng.uniform(size=(32, 5)) < 0.5, lo[j], hi[j])  # corners
        assert np.abs(k(*points.T)).max() <= bound[j] * (1 + 1e-12)


def test_overestimate_is_third_order_at_the_peak(peak) -> None:
    # bound / |H(centre)| - 1 for a box centred on the maximiser: a second-order
    # enclosure shrinks it 100x per 10x in width, a third-order one 1000x
    m, x, best = peak
    excess = []
    for width in (1e-3, 1e-4):
        bound, value, _ = box_bounds(m, 5, (x - width / 2)[None], (x + width / 2)[None])
        assert abs(value[0]) == pytest.approx(best, rel=1e-12)
        excess.append(bound[0] / best - 1)
    assert 0 < excess[1] < excess[0] / 500
    assert excess[1] < 1e-4


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")
@pytest.mark.parametrize(("text", "n"), [(MIXED, 3), (PENDULUM, 5),
                                        ("models/identified_example.toml", 5)])
def test_fused_loops_match_the_numpy_arithmetic(text: str, n: int) -> None:
    m = load_model(text).plant if text.endswith(".toml") else parse_model(text)
    rng = np.random.default_rng(4)
    centre = rng.uniform(-2, 2, (200, n))
    half = 10.0 ** rng.uniform(-4, 0, (200, 1)) * rng.uniform(0.2, 1.0, (200, n))
    fused = box_bounds(m, n, centre - half, centre + half, compiled=True)
    plain = box_bounds(m, n, centre - half, centre + half)
    np.testing.assert_allclose(fused[0], plain[0], rtol=1e-12)
    np.testing.assert_allclose(fused[1], plain[1], rtol=1e-12)


@pytest.mark.slow
def test_cartpole_h5_bracket_closes_to_1e3() -> None:
    # relative gap <= 1e-3 for ||H5|| of the cart-pole plant
    m = load_model("models/cartpole.toml").plant
    b = kernel_norm(m, 5, tol=1e-3, max_boxes=2_000_000)
    assert b.gap <= 1e-3
    k = kernel(m, 5)
    sample = np.random.default_rng(9).uniform(-20, 20, (5, 200000))
    assert np.abs(k(*sample)).max() <= b.upper
    assert abs(k(*b.argmax)) == pytest.approx(b.lower, rel=1e-12)


@pytest.mark.slow
def test_pendulum_h5_bracket_closes_to_1e3(peak) -> None:
    m, x, best = peak
    b = kernel_norm(m, 5, tol=1e-3, max_boxes=2_000_000)
    assert b.gap <= 1e-3 and b.upper_proof == "float" and b.lower_proof == "interval"
    assert b.lower >= best * (1 - 1e-12)
    k = kernel(m, 5)
    near = x + np.random.default_rng(8).uniform(-0.05, 0.05, (200000, 5))
    assert np.abs(k(*near.T)).max() <= b.upper


CLUSTER = [1.0, 0.15, 2.0251, 0.151005, 1.0201]  # (s^2 + 0.05 s + 1)(s^2 + 0.1 s + 1.0201)


@pytest.mark.parametrize("k", [0, 1, 2, 3])
def test_modulus_derivative_bounds_hold(k: int) -> None:
    # sup over an interval of |d^k/dw^k 1/|A(j w)|| against 30-digit mpmath derivatives
    import mpmath as mp

    from gfrf.bounds.inverse import InverseA

    inverse = InverseA(np.array(CLUSTER))
    mp.mp.dps = 30

    def m(w: mp.mpf) -> mp.mpf:
        s = 1j * w
        return 1 / abs(sum(c * s ** (len(CLUSTER) - 1 - i) for i, c in enumerate(CLUSTER)))

    for lo, hi in ((0.9, 1.1), (0.97, 0.99), (-2.0, 3.0), (5.0, 6.0)):
        bound = inverse.modulus_bounds(np.array([lo]), np.array([hi]))[0, k]
        grid = [mp.mpf(lo) + (mp.mpf(hi) - lo) * i / 400 for i in range(401)]
        sup = max(abs(mp.diff(m, w, k)) for w in grid)
        assert float(sup) <= bound * (1 + 1e-9)


def test_modulus_point_values_match_mpmath() -> None:
    import mpmath as mp

    from gfrf.bounds.inverse import InverseA

    inverse = InverseA(np.array(CLUSTER))
    mp.mp.dps = 30

    def m(w: mp.mpf) -> mp.mpf:
        s = 1j * w
        return 1 / abs(sum(c * s ** (len(CLUSTER) - 1 - i) for i, c in enumerate(CLUSTER)))

    points = np.array([-1.3, 0.2, 0.98, 1.0, 2.5])
    values = inverse.modulus_point(points, inverse.centre_error(points, 0 * points, 0 * points))
    for k in range(3):
        ref = np.array([float(mp.diff(m, mp.mpf(w), k)) for w in points])
        np.testing.assert_allclose(values[k], ref, rtol=1e-10, atol=1e-12 * np.abs(ref).max())


@pytest.mark.parametrize(("text", "free"), [
    (PENDULUM, True), ("models/duffing.toml", True), (MIXED, False),
    ("models/cartpole.toml", False)])
def test_modulus_leaves_only_without_input_in_nonlinear_terms(text: str, free: bool) -> None:
    from gfrf.bounds.branch_bound import _input_free

    m = load_model(text).plant if text.endswith(".toml") else parse_model(text)
    assert _input_free(m) is free


def test_box_corners_must_be_finite_and_ordered() -> None:
    from gfrf.errors import ArgumentError

    m = parse_model(MIXED)
    for lo, hi in (([[np.nan, 0.0, 0.0]], [[1.0, 1.0, 1.0]]),
                   ([[0.0, 0.0, 0.0]], [[np.inf, 1.0, 1.0]]),
                   ([[1.0, 0.0, 0.0]], [[0.0, 1.0, 1.0]]),
                   ([[0.0, 0.0]], [[1.0, 1.0]])):
        with pytest.raises(ArgumentError):
            box_bounds(m, 3, np.array(lo), np.array(hi))


def test_budget_accepts_numpy_integers() -> None:
    m = parse_model(MIXED)
    assert kernel_norm(m, 3, max_boxes=np.int64(2000)).upper == kernel_norm(
        m, 3, max_boxes=2000).upper


MODELS = Path(__file__).resolve().parents[2] / "models"
_MIXED_LAGS = ("y[k] = 0.5*y[k-1] - 0.2*y[k-2] + 0.6*u[k-1] + 0.3*u[k-2] + 0.15*y[k-1]*u[k-1] "
               "- 0.1*u[k-1]**2 + 0.05*y[k-2]*u[k-3] - 0.05*y[k-1]**3 "
               "+ 0.03*y[k-1]**2*u[k-2]")


@pytest.mark.parametrize(("source", "n"), [("identified_example.toml", 5),
                                           ("narx_example.toml", 5), (_MIXED_LAGS, 3)])
@pytest.mark.parametrize("radius", [0.05, 0.5, 3.0])
def test_narx_box_bounds_with_carriers_contain_sampled_values(source: str, n: int,
                                                              radius: float) -> None:
    # NARX jets carry the phase of each q_i = exp(-j w_i T) exactly (sums of terms on
    # different carriers turn one of them): the bounds must still hold everywhere
    model = (resolve_model(source, sample_time=0.1) if "=" in source
             else load_model(MODELS / source)).plant
    k = kernel(model, n)
    rng = np.random.default_rng(11)
    centres = rng.uniform(-math.pi / 0.1, math.pi / 0.1, (30, n))
    lo, hi = centres - radius, centres + radius
    bound, centre_value, _ = box_bounds(model, n, lo, hi)
    assert np.allclose(centre_value, np.abs(k(*centres.T)), rtol=1e-9)
    for _ in range(30):
        x = rng.uniform(lo, hi)
        assert np.all(np.abs(k(*x.T)) <= bound * (1 + 1e-12))
