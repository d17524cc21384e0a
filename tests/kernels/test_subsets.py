"""The numpy path of the symmetric kernels (subset convolution) against harmonic probing
and the symbolic recursion, and its values bit for bit the same in every call."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import kernel
from gfrf.kernels.subsets import evaluate_subsets, real_on_the_axis
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from tests.conftest import MODELS

BUNDLED = sorted(p.name for p in MODELS.glob("*.toml") if "parametric" not in p.name)
# odd derivatives (a complex A(j w)), input derivatives, even orders, a discrete model
OTHERS = [
    "D(y,2) + 0.3*D(y) + 2*y + 0.4*y**2 + 0.2*y*D(u) - 0.1*u**2 + 0.3*D(y)*D(u,2) "
    "+ 0.05*D(y,2)*y**2 - 0.2*y*D(y)**2 + 0.1*u**3 = u + 0.5*D(u)",
    "D(y,3) + 2*D(y,2) + 3*D(y) + y + 0.5*D(y)**3 - 0.4*y*u*D(u) = D(u)",
    "y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1] + 0.1*y[k-2]*y[k-1] + 0.3*u[k]**2",
]


def _relative(a: complex, b: complex) -> float:
    return abs(a - b) / max(abs(b), 1e-300)


def _model(name: str) -> object:
    return load_model(MODELS / name).plant


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_kernels_h1_to_h5_agree_with_harmonic_probing(name: str) -> None:
    model = _model(name)
    rng = np.random.default_rng(7)
    scale = 1.0 if model.sample_time is None else 1.0 / model.sample_time
    for n in range(1, 6):
        w = rng.uniform(-3.0, 3.0, (n, 4)) * scale
        values = kernel(model, n)(*w)
        for j in range(w.shape[1]):
            exact = probe_kernel(model, list(w[:, j]))
            assert _relative(complex(values[j]), exact) <= 1e-12 or abs(exact) < 1e-300


def test_cartpole_h7_agrees_with_harmonic_probing() -> None:
    model = _model("cartpole.toml")
    w = np.random.default_rng(8).uniform(-20.0, 20.0, (7, 3))
    values = kernel(model, 7)(*w)
    for j in range(3):
        assert _relative(complex(values[j]), probe_kernel(model, list(w[:, j]))) <= 1e-12


@pytest.mark.parametrize("text", OTHERS)
def test_general_models_agree_with_probing_and_the_explicit_form(text: str) -> None:
    model = parse_model(text, sample_time=0.1 if "[k]" in text else None)
    rng = np.random.default_rng(9)
    for n in range(1, 5):
        k = kernel(model, n)
        w = rng.uniform(-2.0, 2.0, (n, 3))
        values = k(*w)
        variables = [np.exp(-0.1j * wi) if model.is_discrete else 1j * wi for wi in w]
        explicit = sp.lambdify(k.variables, k.expr, "numpy")(*variables)
        for j in range(3):
            exact = probe_kernel(model, list(w[:, j]))
            assert _relative(complex(values[j]), exact) <= 1e-12 or abs(exact) < 1e-300
            assert _relative(complex(values[j]), complex(np.broadcast_to(explicit, (3,))[j])) \
                <= 1e-11 or abs(exact) < 1e-300


@pytest.mark.parametrize("text", OTHERS)
def test_subset_convolution_agrees_with_probing_on_complex_kernels_too(text: str) -> None:
    model = parse_model(text, sample_time=0.1 if "[k]" in text else None)
    gen = kernel(model, 1)._gen
    w = np.random.default_rng(12).uniform(-2.0, 2.0, (5, 3))
    for n in range(1, 6):
        if not gen.structurally_nonzero(n):
            continue
        xs = [np.exp(-0.1j * wi) for wi in w[:n]] if model.is_discrete else list(w[:n])
        values = evaluate_subsets(gen, n, xs)
        for j in range(3):
            exact = probe_kernel(model, list(w[:n, j]))
            assert _relative(complex(values[j]), exact) <= 1e-12


def test_the_real_path_is_taken_exactly_where_the_kernel_is_real() -> None:
    # A(j w) = 67.578 + w^2 and every term's derivatives in pairs: real kernels
    cartpole = kernel(_model("cartpole.toml"), 5)
    assert real_on_the_axis(cartpole._gen, 5)
    w = np.random.default_rng(13).uniform(-20.0, 20.0, (5, 50))
    assert np.all(cartpole(*w).imag == 0.0)
    damped = kernel(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), 3)
    assert not real_on_the_axis(damped._gen, 3)
    assert not real_on_the_axis(kernel(parse_model(OTHERS[2], sample_time=0.1), 3)._gen, 3)


@pytest.mark.parametrize("model", [parse_model(OTHERS[0]), _model("cartpole.toml")])
def test_values_at_complex_s_agree_with_probing_at_those_s(model: object) -> None:
    s = np.array([0.3 + 1.1j, -0.2 - 0.7j, 0.1 + 0.4j])
    value = complex(kernel(model, 3).at_s(*s))
    # probing at s = j*omega with complex omega = -j*s
    assert _relative(value, probe_kernel(model, list(-1j * s))) <= 1e-12


def test_values_at_imaginary_s_are_the_values_at_real_frequencies() -> None:
    k = kernel(_model("cartpole.toml"), 5)
    w = np.random.default_rng(14).uniform(-20.0, 20.0, (5, 20))
    at_s, at_w = k.at_s(*(1j * w)), k(*w)  # complex division rounds as 1/b times a
    assert np.max(np.abs(at_s - at_w) / np.abs(at_w)) <= 1e-14


def test_every_point_is_bit_identical_alone_in_a_call_and_across_calls() -> None:
    k = kernel(_model("cartpole.toml"), 5)
    w = np.random.default_rng(10).uniform(-20.0, 20.0, (5, 9000))  # two slices
    first, second = k(*w), k(*w)
    assert first.tobytes() == second.tobytes()
    for j in (0, 4096, 8191, 8192, 8999):
        assert complex(k(*w[:, j])) == complex(first[j])


def test_a_compiled_kernel_in_memory_or_on_disk_leaves_the_numpy_values_unchanged(
        tmp_path: object, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("numba")
    monkeypatch.setenv("GFRF_CACHE_DIR", str(tmp_path))
    k = kernel(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), 3)
    w = np.random.default_rng(11).uniform(-3.0, 3.0, (3, 5000))
    cold = k(*w)
    compiled = k.compiled()(*w)  # built now: the ufunc memoised, the library on disk
    warm = k(*w)
    assert cold.tobytes() == warm.tobytes()
    assert np.max(np.abs(compiled - cold) / np.abs(cold)) <= 1e-12


@pytest.mark.parametrize(("equation", "at", "expected"), [
    ("y = u + 0.5*u**2", (1.0, 2.0), 0.5),
    ("y + 0.5*y**2 = u", (0.5, 1.0, 2.0), 0.5),  # y = sqrt(1 + 2u) - 1 = u - u^2/2 + u^3/2 - 5u^4/8
    ("y + 0.5*y**2 = u", (0.5, 1.0, 2.0, 3.0), -0.625),
    ("2*y + y*u = u", (1.0, 2.0), -0.25),  # y = u/2 - y u/2
    ("y + y**2 = u**2", (0.5, 1.0), 1.0),
])
def test_a_static_model_sums_constant_products_to_its_power_series(equation, at, expected):
    value = kernel(parse_model(equation), len(at))(*at)
    assert value == pytest.approx(expected, rel=1e-14)
