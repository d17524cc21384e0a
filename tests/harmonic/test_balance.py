"""The harmonic-balance equations: exact projection, analytic Jacobians, NARX balance."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gfrf.errors import ArgumentError
from gfrf.harmonic.balance import Balance, samples_needed
from gfrf.harmonic.curve import frc
from gfrf.model.equation import parse_model

CONTINUOUS = "D(y,2) + 0.1*D(y) + y + 0.3*y**3 + 0.2*y**2*D(y) - 0.1*y*u = D(u) + u"
NARX = "y[k] = 1.2*y[k-1] - 0.5*y[k-2] - 0.1*y[k-1]**3 + 0.5*u[k-1] + 0.05*y[k-1]*u[k-2]"


def _model(kind: str):
    return parse_model(CONTINUOUS) if kind == "ode" else parse_model(NARX, sample_time=0.5)


def test_the_minimum_sample_count_is_the_exact_galerkin_projection() -> None:
    """With (degree + 1) H + 1 samples no product aliases onto a kept harmonic: the
    projection equals the one on a grid eight times finer."""
    for kind in ("ode", "narx"):
        m = _model(kind)
        coarse = Balance(m.terms, 5, sample_time=m.sample_time)
        assert coarse.samples == samples_needed(m.degree, 5) == 4 * 5 + 1
        fine = Balance(m.terms, 5, sample_time=m.sample_time, samples=8 * coarse.samples)
        x = np.random.default_rng(1).normal(size=coarse.size) * 0.4
        e, f = coarse.evaluate(x, 1.3, 0.7), fine.evaluate(x, 1.3, 0.7)
        np.testing.assert_allclose(e.residual, f.residual, atol=1e-13)
        np.testing.assert_allclose(e.jac_x, f.jac_x, atol=1e-13)


def test_one_sample_fewer_aliases() -> None:
    m = _model("ode")
    short = Balance(m.terms, 5)
    x = np.random.default_rng(2).normal(size=short.size) * 0.4
    exact = short.evaluate(x, 1.3, 0.7).residual
    tau = 2 * math.pi * np.arange(short.samples - 1) / (short.samples - 1)
    # rebuild the projection on one sample fewer by hand: it must differ
    basis = np.ones((tau.size, short.size))
    basis[:, 1::2] = np.cos(np.outer(tau, np.arange(1, 6)))
    basis[:, 2::2] = np.sin(np.outer(tau, np.arange(1, 6)))
    samples, _ = short.residual_samples(x, 1.3, 0.7, tau.size)
    projected = basis.T @ samples * 2 / tau.size
    projected[0] /= 2
    assert np.max(np.abs(projected - exact)) > 1e-6


@pytest.mark.parametrize("kind", ["ode", "narx"])
def test_jacobians_match_central_differences(kind: str) -> None:
    m = _model(kind)
    b = Balance(m.terms, 4, sample_time=m.sample_time)
    x = np.random.default_rng(3).normal(size=b.size) * 0.3
    w, a, h = 1.1, 0.6, 1e-6
    e = b.evaluate(x, w, a)
    eye = np.eye(b.size)
    fd = np.column_stack([(b.evaluate(x + h * eye[i], w, a).residual
                           - b.evaluate(x - h * eye[i], w, a).residual) / (2 * h)
                          for i in range(b.size)])
    np.testing.assert_allclose(e.jac_x, fd, atol=1e-7)
    np.testing.assert_allclose(e.jac_omega, (b.evaluate(x, w + h, a).residual
                                             - b.evaluate(x, w - h, a).residual) / (2 * h),
                               atol=1e-7)
    np.testing.assert_allclose(e.jac_amplitude, (b.evaluate(x, w, a + h).residual
                                                 - b.evaluate(x, w, a - h).residual) / (2 * h),
                               atol=1e-7)


def test_narx_balance_is_the_steady_state_of_the_recursion() -> None:
    """The balanced trigonometric polynomial, sampled at k T, is what the difference
    equation settles to under u[k] = A cos(omega k T)."""
    m = parse_model("y[k] = 1.2*y[k-1] - 0.5*y[k-2] - 0.1*y[k-1]**3 + 0.5*u[k-1]",
                    sample_time=1.0)
    w, amp, harmonics = 2 * math.pi / 8, 0.6, 15
    point = frc(m, (0.05, amp), w, vary="amplitude", harmonics=harmonics).points[-1]
    assert point.forcing == pytest.approx(amp, abs=1e-15)
    n = 3000
    y = np.zeros(n)
    u = amp * np.cos(w * np.arange(n))
    for k in range(2, n):
        y[k] = 1.2 * y[k - 1] - 0.5 * y[k - 2] - 0.1 * y[k - 1] ** 3 + 0.5 * u[k - 1]
    ks = np.arange(n - 64, n)
    h = np.arange(1, harmonics + 1)
    c = point.coefficients
    hb = c[0] + np.cos(w * np.outer(ks, h)) @ c[1::2] + np.sin(w * np.outer(ks, h)) @ c[2::2]
    assert np.max(np.abs(hb - y[ks])) < 1e-9 * np.max(np.abs(y[ks]))


def test_harmonics_are_bounded() -> None:
    m = _model("ode")
    for bad in (0, -1, 1.5, True, 10_000):
        with pytest.raises(ArgumentError, match="harmonics"):
            Balance(m.terms, bad)
