"""Hard numeric cases: each result is checked against an independent high-precision value.

The reference is either a closed form evaluated with mpmath at 40 digits, or harmonic
probing (:func:`gfrf.kernels.probing.probe_kernel`, an algorithm sharing no code with the
recursion) run on mpmath numbers at 40 digits: the model's float coefficients and the
frequencies are exact binary numbers, so the reference is the exact kernel value to
~1e-35.  Tolerances are stated per case from the conditioning of the quantity (double
rounding, 1.1e-16, times the condition number), never from our own output.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from gfrf.bounds.norms import h1_norm, kernel_norm, linear_stability
from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.stability.theorem1 import theorem1

mp.mp.dps = 40


def reference(model, omegas: list[float]) -> complex:
    """Symmetric H_n at ``omegas`` (rad/s) by harmonic probing in 40-digit arithmetic."""
    return complex(probe_kernel(model, [mp.mpf(w) for w in omegas]))


def relative_error(value: complex, exact: complex) -> float:
    return abs(complex(value) - exact) / abs(exact)


def resonance_peak(zeta: float) -> mp.mpf:
    """sup |1/(s^2 + 2 zeta s + 1)| on s = j w: 1 / (2 zeta sqrt(1 - zeta^2))."""
    z = mp.mpf(zeta)
    return 1 / (2 * z * mp.sqrt(1 - z ** 2))


@pytest.mark.parametrize("zeta", [1e-3, 1e-6])
def test_light_damping_h1_peak_and_h3_norm(zeta: float) -> None:
    # A(s) = s^2 + 2 zeta s + 1, cubic 0.5 y^3: ||H1|| = sup|1/A|, and the majorant of H3,
    # |c3| ||H1||^3 sup|1/A| = 0.5 P^4, is attained at (w_r, w_r, -w_r).
    model = parse_model(f"D(y,2) + {2 * zeta!r}*D(y) + y + 0.5*y**3 = u")
    peak = resonance_peak(zeta)
    b1 = h1_norm(model)
    # |H1| is flat to second order at its peak: the value is accurate to ~eps.
    assert b1.upper == pytest.approx(float(peak), rel=1e-12)
    b3 = kernel_norm(model, 3)
    exact = float(mp.mpf("0.5") * peak ** 4)
    assert b3.upper == pytest.approx(exact, rel=1e-11)
    assert b3.lower <= exact * (1 + 1e-11)
    assert b3.lower == pytest.approx(exact, rel=1e-9)
    # The kernel value at the reported argmax against 40-digit probing there.
    at = list(b3.argmax)
    assert relative_error(kernel(model, 3)(*at), reference(model, at)) < 1e-10


def test_pole_within_1e8_of_the_axis() -> None:
    # Poles -1e-8 +- j sqrt(1 - 1e-16): still stable, ||H1|| = 5e7.  The peak is flat,
    # so its value is accurate to eps * (1 / zeta) at worst: tolerance 1e-8.
    model = parse_model("D(y,2) + 2e-08*D(y) + y = u")
    stable, poles = linear_stability(model)
    assert stable
    assert max(p.real for p in poles) == pytest.approx(-1e-8, rel=1e-6)
    assert h1_norm(model).upper == pytest.approx(float(resonance_peak(1e-8)), rel=1e-8)
    w = [1.0 - 1e-9]
    assert relative_error(kernel(model, 1)(*w), reference(model, w)) < 1e-6


def test_unstable_pole_within_1e8_of_the_axis_is_unstable() -> None:
    model = parse_model("D(y,2) - 2e-08*D(y) + y + 0.5*y**3 = u")
    assert theorem1(model, 1, with_norms=False).verdict == "unstable"


def test_pole_on_the_axis_is_refused_not_called_stable() -> None:
    model = parse_model("D(y,2) + y + 0.5*y**3 = u")
    bound = h1_norm(model)
    assert math.isinf(bound.upper)
    assert any("pole on the imaginary axis" in note for note in bound.notes)
    result = theorem1(model, 1, with_norms=False)
    assert result.verdict == "inconclusive"
    assert result.conditions[1].passed is False


def test_stiffness_ratio_1e6() -> None:
    # A(s) = (s + 1)(s + 1e6): H1 peaks at w = 0 with 1e-6.  Cubic 0.5 y^3: the majorant is
    # X = 1e-6 r + 0.5e-6 X^3, radius r* = 2 / (3 beta1 sqrt(3 g)), beta1 = 1e-6, g = 5e-7.
    model = parse_model("D(y,2) + 1000001*D(y) + 1000000*y + 0.5*y**3 = u")
    assert h1_norm(model).upper == pytest.approx(1e-6, rel=1e-12)
    for w in ([0.3, -2.0, 7.5], [1e3, 2.5e5, -1e6]):
        assert relative_error(kernel(model, 3)(*w), reference(model, w)) < 1e-12
    beta1, g = mp.mpf("1e-6"), mp.mpf("0.5e-6")
    exact = float(2 / (3 * beta1 * mp.sqrt(3 * g)))
    assert theorem1(model, 1, with_norms=False).radius == pytest.approx(exact, rel=1e-8)


@pytest.mark.slow
def test_kernel_order_9_against_probing() -> None:
    # Quadratic and cubic terms: every order up to 9 is structurally nonzero.
    model = parse_model("D(y,2) + 0.4*D(y) + y + 0.3*y**2 + 0.5*y**3 = u")
    w = [0.31, -0.77, 1.13, 0.52, -0.29, 0.91, -1.41, 0.17, 0.63]
    assert relative_error(kernel(model, 9)(*w), reference(model, w)) < 1e-10


def test_kernel_order_9_odd_nonlinearity() -> None:
    model = parse_model("D(y,2) + 2e-06*D(y) + y + 0.5*y**3 = u")
    w = [0.31, -0.77, 1.13, 0.52, -0.29, 0.91, -1.41, 0.17, 0.63]
    assert relative_error(kernel(model, 9)(*w), reference(model, w)) < 1e-10
    assert kernel(model, 8).is_zero


def test_coefficients_spanning_12_orders_of_magnitude() -> None:
    # Coefficients from 1e-6 to 1e6, every kind of term (pure output with derivatives,
    # cross, pure input).
    model = parse_model("1e-6*D(y,2) + 1e-3*D(y) + 1e6*y + 1e-5*y**2*D(y) + 1e5*y**3"
                        " + 1e-4*y*u + 1e3*u**3 = u")
    rng = np.random.default_rng(7)
    for n in (1, 2, 3):
        for _ in range(5):
            w = list(rng.uniform(-1e6, 1e6, n))
            assert relative_error(kernel(model, n)(*w), reference(model, w)) < 1e-9


@pytest.mark.parametrize("scale", [1e3, 1e6])
def test_frequencies_up_to_1e6(scale: float) -> None:
    model = parse_model("D(y,2) + 0.2*D(y) + y + 0.3*y**2*D(y) + 0.5*y**3 = u")
    triples = [[scale, scale, -scale], [scale, -scale + 0.5, 0.25], [0.7 * scale, 0.1, -3.0]]
    for w in triples:
        assert relative_error(kernel(model, 3)(*w), reference(model, w)) < 1e-10
    assert relative_error(kernel(model, 1)(scale), reference(model, [scale])) < 1e-14
