"""Shooting: periodic orbits of eqs (3)/(4) and their linear (Mathieu) limit."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gfrf.errors import ConvergenceError
from gfrf.periodic.floquet import linear_orbit_shape, mathieu_transition
from gfrf.periodic.shooting import orbit_at_delta, transition_delta, transition_zero_eps


def _ode_check(orbit, g):
    """Integrate independently (LSODA) over one period; return periodicity defect."""
    T = orbit.period
    sol = solve_ivp(lambda t, y: [y[1], -(orbit.delta + orbit.eps * np.cos(t)) * g(y[0])],
                    (0, T), [orbit.amplitude, 0.0], method="LSODA", rtol=1e-11, atol=1e-13)
    return abs(sol.y[0, -1] - orbit.amplitude) + abs(sol.y[1, -1])


@pytest.mark.parametrize("branch", ["0", "1/4"])
@pytest.mark.parametrize("trunc,g", [(3, lambda x: x - x**3 / 6), (None, np.sin)])
def test_orbit_is_periodic_solution(branch, trunc, g):
    orbit = transition_delta(0.2, 0.8, branch, trunc)
    assert orbit.shooting_residual < 1e-10
    assert orbit.period_residual < 1e-8
    assert _ode_check(orbit, g) < 1e-6


@pytest.mark.parametrize("branch", ["0", "1/4"])
def test_small_amplitude_limit_is_mathieu(branch):
    eps = 0.3
    orbit = transition_delta(eps, 1e-4, branch)
    assert orbit.delta == pytest.approx(float(mathieu_transition(eps, branch)), abs=1e-8)
    t = np.linspace(0, orbit.period, 40)
    assert np.max(np.abs(orbit.evaluate(t) / orbit.amplitude
                         - linear_orbit_shape(eps, branch, t))) < 1e-6
    # on a transition curve both multipliers are 1 (branch 0: period 2 pi; 1/4: 4 pi)
    assert np.allclose(orbit.multipliers, 1.0, atol=1e-3)


def test_nonlinear_shift_is_quadratic_in_amplitude():
    # delta(a) - delta_lin ~ C a^2: halving a divides the shift by ~4
    d = [transition_delta(0.1, a, "1/4").delta - float(mathieu_transition(0.1, "1/4"))
         for a in (0.2, 0.1)]
    assert d[0] / d[1] == pytest.approx(4.0, rel=0.02)


def test_orbit_at_delta_recovers_amplitude():
    orbit = transition_delta(0.2, 0.6, "1/4")
    again = orbit_at_delta(0.2, orbit.delta, 0.5, "1/4")
    assert again.amplitude == pytest.approx(0.6, abs=1e-9)


def test_no_orbit_raises_with_residual():
    # 1/4 branch: delta below the linear curve has no small orbit (softening spring)
    with pytest.raises(ConvergenceError, match="residual"):
        orbit_at_delta(0.2, float(mathieu_transition(0.2, "1/4")) - 0.05, 0.1, "1/4")


def test_truncated_and_full_agree_for_small_amplitude():
    a = 0.1
    d3 = transition_delta(0.2, a, "0", 3).delta
    dfull = transition_delta(0.2, a, "0", None).delta
    assert abs(d3 - dfull) < 1e-6


def test_nonlinear_quarter_curve_reaches_delta_zero():
    eps0 = transition_zero_eps(0.5)

    def x_at_pi(e: float) -> float:
        # independent integration of eq (4) at delta = 0 from x(0) = 0.5, x'(0) = 0: the
        # 4 pi-periodic orbit of the 1/4 branch is even with x(pi) = 0
        sol = solve_ivp(lambda t, y: [y[1], -e * np.cos(t) * (y[0] - y[0] ** 3 / 6)],
                        (0, np.pi), [0.5, 0.0], method="LSODA", rtol=1e-12, atol=1e-14)
        return sol.y[0, -1]

    slope = (x_at_pi(eps0 + 1e-4) - x_at_pi(eps0 - 1e-4)) / 2e-4
    assert abs(x_at_pi(eps0) / slope) < 1e-9  # eps0 is a root to about 1e-9
    assert eps0 > 0.4540231668  # beyond the linear (small-amplitude) crossing
