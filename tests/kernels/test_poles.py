"""The poles of the linear part against closed forms (continuous and NARX)."""

from __future__ import annotations

import cmath

import numpy as np

from gfrf.kernels.poles import linear_poles
from gfrf.model.equation import parse_model


def _sorted(values) -> list[complex]:
    return sorted((complex(v) for v in values), key=lambda z: (round(z.real, 9), z.imag))


def test_continuous_poles_are_the_roots_of_a_in_s():
    # s^2 + 2 s + 5 = 0: s = -1 +- 2j, whatever scale the equation is written in
    for scale in (1.0, 1e-90, 3e40):
        s = linear_poles(parse_model(f"{scale}*D(y,2) + {2 * scale}*D(y) + {5 * scale}*y = u"))
        assert np.allclose(_sorted(s), _sorted([-1 - 2j, -1 + 2j]), rtol=1e-12)


def test_narx_poles_map_z_poles_by_the_logarithm():
    # y[k] = 1.2 y[k-1] - 0.72 y[k-2] + u[k-1]: z^2 - 1.2 z + 0.72 = 0, z = 0.6 +- 0.6j,
    # and a pole z of the transfer function in z is s = ln(z) / T
    model = parse_model("y[k] = 1.2*y[k-1] - 0.72*y[k-2] + u[k-1]", sample_time=0.1)
    expected = [cmath.log(0.6 + 0.6j) / 0.1, cmath.log(0.6 - 0.6j) / 0.1]
    assert np.allclose(_sorted(linear_poles(model)), _sorted(expected), rtol=1e-12)
    # a first-order loop y[k] = 0.5 y[k-1] + u[k-1]: one real pole, ln(0.5) / T
    first = linear_poles(parse_model("y[k] = 0.5*y[k-1] + u[k-1]", sample_time=0.2))
    assert np.allclose(first, [np.log(0.5) / 0.2], rtol=1e-12)


def test_a_constant_linear_part_has_no_poles():
    assert linear_poles(parse_model("y + y**3 = u")).size == 0


def test_a_negative_real_narx_pole_is_a_resonance_at_the_nyquist_frequency():
    # y[k] = -0.5 y[k-1] + u[k-1]: z = -0.5, |H1| peaks at w = pi / T; half-width ln 2 / T
    from gfrf.kernels.plot import resonances
    from gfrf.kernels.recursion import kernel

    model = parse_model("y[k] = -0.5*y[k-1] + u[k-1]", sample_time=0.1)
    (w, half), = resonances(kernel(model, 1))
    assert np.isclose(w, np.pi / 0.1, rtol=1e-12) and np.isclose(half, np.log(2) / 0.1)
