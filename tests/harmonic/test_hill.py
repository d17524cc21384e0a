"""Floquet multipliers by Hill's method against closed forms and monodromy matrices."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.harmonic.curve import frc
from gfrf.model.equation import parse_model

DAMPING = 0.1


def _initial_state(point) -> tuple[float, float]:
    """y(0) and y'(0) of the balanced solution."""
    c = point.coefficients
    k = np.arange(1, (c.size - 1) // 2 + 1)
    return float(c[0] + c[1::2].sum()), float(point.omega * (k * c[2::2]).sum())


def _monodromy(cubic: float, forcing: float, omega: float, y0: float, v0: float
               ) -> np.ndarray:
    """Eigenvalues of the monodromy matrix of the Duffing oscillator along the orbit
    through (y0, v0), by DOP853 on the state and its variational equation."""
    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        y, v = z[0], z[1]
        jac = np.array([[0.0, 1.0], [-(1 + 3 * cubic * y * y), -DAMPING]])
        flow = jac @ z[2:].reshape(2, 2)
        return np.concatenate([[v, forcing * math.cos(omega * t) - DAMPING * v - y
                                - cubic * y ** 3], flow.ravel()])

    sol = solve_ivp(rhs, (0.0, 2 * math.pi / omega), [y0, v0, 1, 0, 0, 1], method="DOP853",
                    rtol=1e-12, atol=1e-13)
    return np.linalg.eigvals(sol.y[2:, -1].reshape(2, 2))


def test_a_linear_oscillator_has_the_closed_form_multipliers() -> None:
    """y'' + 0.1 y' + y = u: exponents -0.05 +- j sqrt(1 - 0.0025), rho = exp(lambda T)."""
    curve = frc(parse_model("D(y,2) + 0.1*D(y) + y = u"), 1.0, (0.5, 2.0), backbone=False)
    root = complex(-0.05, math.sqrt(1 - 0.0025))
    for point in curve.points[::10]:
        period = 2 * math.pi / point.omega
        expected = sorted([cmath.exp(root * period), cmath.exp(root.conjugate() * period)],
                          key=lambda z: z.imag)
        got = sorted(point.multipliers, key=lambda z: z.imag)
        assert np.allclose(got, expected, atol=1e-12)
        assert point.stable


@pytest.mark.parametrize(("cubic", "forcing"), [(0.3, 0.3), (-0.3, 0.1)])
def test_hill_multipliers_are_the_monodromy_eigenvalues_on_both_branches(
        cubic: float, forcing: float) -> None:
    """Stable and unstable points of the Duffing curves: the multipliers of Hill's method
    are the eigenvalues of the monodromy matrix integrated along the balanced orbit, and
    the unstable points have one outside the unit circle."""
    curve = frc(parse_model(f"D(y,2) + 0.1*D(y) + y + {cubic}*y**3 = u"), forcing,
                (0.5, 2.0))
    unstable = [p for p in curve.points if not p.stable]
    stable = [p for p in curve.points if p.stable]
    assert len(unstable) >= 10 and len(stable) >= 10
    picks = unstable[len(unstable) // 4::len(unstable) // 3][:3] + stable[::len(stable) // 3]
    for point in picks:
        monodromy = _monodromy(cubic, forcing, point.omega, *_initial_state(point))
        for rho in point.multipliers:
            assert min(abs(rho - m) for m in monodromy) < 1e-6
        assert (max(abs(monodromy)) > 1.0) == (not point.stable)


def test_narx_multipliers_are_the_sampled_monodromy_eigenvalues() -> None:
    """Period of 8 samples: the product of the recursion's Jacobians over one period has
    the eigenvalues of Hill's multipliers (within the truncation of the continuous
    interpolant, 1e-3 relative)."""
    m = parse_model("y[k] = 1.2*y[k-1] - 0.5*y[k-2] - 0.1*y[k-1]**3 + 0.5*u[k-1]",
                    sample_time=1.0)
    w, amp = 2 * math.pi / 8, 0.6
    point = frc(m, (0.05, amp), w, vary="amplitude", harmonics=15).points[-1]
    n = 2000
    y = np.zeros(n)
    u = amp * np.cos(w * np.arange(n))
    for k in range(2, n):
        y[k] = 1.2 * y[k - 1] - 0.5 * y[k - 2] - 0.1 * y[k - 1] ** 3 + 0.5 * u[k - 1]
    product = np.eye(2)
    for k in range(n - 8, n):
        product = np.array([[1.2 - 0.3 * y[k - 1] ** 2, -0.5], [1.0, 0.0]]) @ product
    monodromy = np.linalg.eigvals(product)
    scale = max(abs(monodromy))
    for rho in point.multipliers:
        assert min(abs(rho - mu) for mu in monodromy) < 1e-3 * scale
    assert point.stable


def test_period_doubling_is_where_a_monodromy_multiplier_crosses_minus_one() -> None:
    """y'' + 0.1 y' + (1 + u) y + 0.3 y^3 = u, u = 0.5 cos(w t): the forced orbit loses
    stability to a period doubling near w = 2 (parametric resonance).  Either side of
    each listed point, 0.1 % away, the monodromy matrix integrated along the orbit has its
    smallest multiplier on either side of -1; the multipliers' product is Liouville's
    exp(-0.1 T)."""
    model = parse_model("D(y,2) + 0.1*D(y) + y + y*u + 0.3*y**3 = u")
    curve = frc(model, 0.5, (1.5, 2.5))
    assert len(curve.period_doublings) == 2
    for point in curve.points[::7]:
        product = abs(point.multipliers[0] * point.multipliers[1])
        assert product == pytest.approx(math.exp(-0.1 * 2 * math.pi / point.omega), rel=1e-9)

    def smallest(omega: float) -> float:
        point = frc(model, (0.4, 0.5), omega, vary="amplitude").points[-1]
        y0, v0 = _initial_state(point)

        def rhs(t: float, z: np.ndarray) -> np.ndarray:
            u = 0.5 * math.cos(point.omega * t)
            y, v = z[0], z[1]
            jac = np.array([[0.0, 1.0], [-(1 + u + 0.9 * y * y), -DAMPING]])
            return np.concatenate([[v, u - DAMPING * v - (1 + u) * y - 0.3 * y ** 3],
                                   (jac @ z[2:].reshape(2, 2)).ravel()])

        sol = solve_ivp(rhs, (0.0, 2 * math.pi / point.omega), [y0, v0, 1, 0, 0, 1],
                        method="DOP853", rtol=1e-12, atol=1e-13)
        eig = np.linalg.eigvals(sol.y[2:, -1].reshape(2, 2))
        assert abs(eig.imag).max() < 1e-9
        return float(eig.real.min())

    low, high = (d["omega"] for d in curve.period_doublings)
    assert 1.7 < low < 1.9 < 2.1 < high < 2.3
    assert smallest(low * 0.999) > -1 > smallest(low * 1.001)
    assert smallest(high * 0.999) < -1 < smallest(high * 1.001)
