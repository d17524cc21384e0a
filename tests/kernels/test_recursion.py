"""Tests of gfrf.kernels.recursion against closed forms derived by hand and against
harmonic probing."""

import itertools
import math

import numpy as np
import pytest
import sympy as sp

from gfrf.errors import ArgumentError
from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model

RNG = np.random.default_rng(20261122)

B, C, K3, K2 = 0.2, 1.5, 0.7, 0.4
DUFFING = parse_model(f"D(y,2) + {B}*D(y) + {C}*y + {K3}*y**3 = u")
QUADRATIC = parse_model(f"D(y,2) + {B}*D(y) + {C}*y + {K2}*y**2 = u")
CARTPOLE = parse_model("D(y,2) - 67.578*y + 11.2455*y**3 + 0.1475*y*D(y)**2 "
                       "+ 0.1475*y**2*D(y,2) + 39.3185*u - 19.66*y**2*u = 0")
# every term type: pure output, pure input (with derivatives), cross terms with
# derivatives on both signals, products of derivatives, even and odd degrees
EVERYTHING = parse_model("D(y,2) + 0.3*D(y) + 2*y + 0.4*y**2 + 0.2*y*D(u) - 0.1*u**2 "
                         "+ 0.3*D(y)*D(u,2) + 0.05*D(y,2)*y**2 - 0.2*y*D(y)**2 "
                         "+ 0.1*u**3 = u + 0.5*D(u)")
NARX = parse_model("y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1] "
                   "+ 0.1*y[k-2]*y[k-1] + 0.3*u[k]**2", sample_time=0.1)


def h1(w):
    """Hand-derived H1 of D(y,2) + B D(y) + C y = u: 1/(C - w^2 + j B w)."""
    return 1.0 / (C - w**2 + 1j * B * w)


def test_duffing_h1_closed_form():
    w = RNG.uniform(-5, 5, 50)
    np.testing.assert_allclose(kernel(DUFFING, 1)(w), h1(w), rtol=1e-14)


def test_duffing_h3_closed_form():
    # Probing with three tones: A(Omega) Y_123 + K3 * 3! * Y_1 Y_2 Y_3 = 0, Y_123 = 3! H3.
    w1, w2, w3 = RNG.uniform(-4, 4, (3, 200))
    expected = -K3 * h1(w1) * h1(w2) * h1(w3) * h1(w1 + w2 + w3)
    np.testing.assert_allclose(kernel(DUFFING, 3)(w1, w2, w3), expected, rtol=1e-13)


def test_quadratic_oscillator_h2_h3_closed_forms():
    w1, w2, w3 = RNG.uniform(-4, 4, (3, 200))
    h2 = -K2 * h1(w1) * h1(w2) * h1(w1 + w2)
    np.testing.assert_allclose(kernel(QUADRATIC, 2)(w1, w2), h2, rtol=1e-13)
    # Y_123 = -K2 * 2 * sum_i Y_i Y_jk / A: H3 = (2 K2^2 / 3) H1(sum) prod H1 * sum H1(pair)
    h3 = (2 * K2**2 / 3) * h1(w1 + w2 + w3) * h1(w1) * h1(w2) * h1(w3) * (
        h1(w1 + w2) + h1(w1 + w3) + h1(w2 + w3))
    np.testing.assert_allclose(kernel(QUADRATIC, 3)(w1, w2, w3), h3, rtol=1e-13)


def test_narx_h1_h2_hand_derived():
    a, b, c, T = 0.6, 1.3, 0.25, 0.05
    m = parse_model(f"y[k] = {a}*y[k-1] + {b}*u[k-1] + {c}*y[k-1]*u[k-1]", sample_time=T)
    w1, w2 = RNG.uniform(-30, 30, (2, 100))
    q1, q2 = np.exp(-1j * w1 * T), np.exp(-1j * w2 * T)
    g1 = b * q1 / (1 - a * q1)
    g2 = b * q2 / (1 - a * q2)
    np.testing.assert_allclose(kernel(m, 1)(w1), g1, rtol=1e-14)
    # coefficient of q1 q2: (1 - a q1 q2) 2 H2 = c q1 q2 (H1(w1) + H1(w2))
    expected = c * q1 * q2 * (g1 + g2) / (2 * (1 - a * q1 * q2))
    np.testing.assert_allclose(kernel(m, 2)(w1, w2), expected, rtol=1e-13)


@pytest.mark.parametrize("model", [CARTPOLE, EVERYTHING, NARX], ids=["cartpole", "all-terms",
                                                                     "narx"])
@pytest.mark.parametrize("n", [1, 2, 3, 4, 5])
def test_recursion_agrees_with_harmonic_probing(model, n):
    for _ in range(3):
        w = RNG.uniform(-6, 6, n)
        ours = complex(kernel(model, n)(*w))
        reference = probe_kernel(model, list(w))
        assert abs(ours - reference) <= 1e-12 * max(abs(reference), 1e-300) + 1e-300


@pytest.mark.parametrize("model", [CARTPOLE, EVERYTHING, NARX], ids=["cartpole", "all-terms",
                                                                     "narx"])
@pytest.mark.parametrize("n", [2, 3, 4])
def test_symmetric_kernel_is_symmetric_and_the_average_of_the_asymmetric(model, n):
    w = RNG.uniform(-5, 5, (n, 20))
    sym = kernel(model, n)
    asym = kernel(model, n, symmetric=False)
    perms = list(itertools.permutations(range(n)))
    average = sum(asym(*(w[p] for p in perm)) for perm in perms) / len(perms)
    for perm in perms:
        np.testing.assert_allclose(sym(*(w[p] for p in perm)), sym(*w), rtol=1e-13, atol=1e-300)
    np.testing.assert_allclose(average, sym(*w), rtol=1e-12, atol=1e-300)


def test_asymmetric_kernel_is_not_symmetric_in_general():
    w = np.array([0.3, 1.7, -0.9])
    asym = kernel(EVERYTHING, 3, symmetric=False)
    assert abs(asym(*w) - asym(*w[::-1])) > 1e-6


def test_even_kernels_of_an_odd_nonlinearity_vanish_structurally():
    for n in (2, 4, 6):
        k = kernel(CARTPOLE, n)
        assert k.is_zero
        assert k.expr == 0
        w = RNG.uniform(-3, 3, n)
        assert kernel(CARTPOLE, n)(*w) == 0
        assert abs(probe_kernel(CARTPOLE, list(w))) < 1e-12
    assert not kernel(CARTPOLE, 7).is_zero


def test_symbolic_expression_matches_numeric_form():
    for model, n in [(CARTPOLE, 3), (EVERYTHING, 3), (NARX, 2)]:
        k = kernel(model, n)
        f = sp.lambdify(k.variables, k.expr, "numpy")
        w = RNG.uniform(-3, 3, n)
        args = (np.exp(-1j * w * model.sample_time) if model.is_discrete else 1j * w)
        assert complex(f(*args)) == pytest.approx(complex(k(*w)), rel=1e-12)


def test_broadcasting_like_numpy():
    k = kernel(DUFFING, 3)
    w = np.linspace(-2, 2, 5)
    out = k(w[:, None, None], w[None, :, None], 0.5)
    assert out.shape == (5, 5, 1) and out.dtype == np.complex128
    assert complex(out[1, 3, 0]) == pytest.approx(complex(k(w[1], w[3], 0.5)), rel=1e-14)


def test_high_order_kernel_is_finite_and_agrees_with_probing():
    w = RNG.uniform(-2, 2, 7)
    value = complex(kernel(CARTPOLE, 7)(*w))
    assert math.isfinite(abs(value))
    assert value == pytest.approx(probe_kernel(CARTPOLE, list(w)), rel=1e-11)


@pytest.mark.parametrize("n", [0, -1, 99, 2.5, True])
def test_bad_orders_are_refused(n):
    with pytest.raises(ArgumentError):
        kernel(DUFFING, n)


def test_wrong_number_of_frequencies_and_non_finite_values():
    with pytest.raises(ArgumentError, match="takes 3"):
        kernel(DUFFING, 3)(1.0, 2.0)
    with pytest.raises(ArgumentError, match="finite"):
        kernel(DUFFING, 1)(np.nan)


@pytest.mark.parametrize("model, n", [(CARTPOLE, 3), (EVERYTHING, 4), (NARX, 3), (CARTPOLE, 5)])
def test_compiled_ufunc_agrees_with_numpy_path(model, n):
    pytest.importorskip("numba")
    w = RNG.uniform(-5, 5, (n, 200))
    np.testing.assert_allclose(kernel(model, n).compiled()(*w), kernel(model, n)(*w),
                               rtol=1e-12)


def test_models_differing_only_in_a_coefficient_do_not_share_kernels():
    # regression: sweeps build many models of one structure; the memo must see coefficients
    a = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    b = parse_model("D(y,2) + 0.4*D(y) + y + 0.5*y**3 = u")
    assert a != b
    assert complex(kernel(a, 1)(1.0)) == pytest.approx(1 / 0.2j)
    assert complex(kernel(b, 1)(1.0)) == pytest.approx(1 / 0.4j)


def test_large_broadcast_evaluation_is_sliced_consistently() -> None:
    """Beyond one slice (16,384 points) the values equal the row-by-row ones, with the
    broadcast shape kept (a grid of 240 x 300 frequencies)."""
    from gfrf.model.modelfile import load_model

    m = load_model("models/cartpole.toml").plant
    k3 = kernel(m, 3)
    w1 = np.linspace(-7.0, 7.0, 240)[:, None]
    w2 = np.linspace(-5.0, 6.0, 300)[None, :]
    grid = k3(w1, w2, 0.7)
    assert grid.shape == (240, 300)
    rows = np.array([k3(np.full(300, w), w2[0], 0.7) for w in w1[:, 0]])
    assert np.array_equal(grid, rows)
