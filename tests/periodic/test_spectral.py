"""Fourier collocation of transition orbits against independent references.

References: the Mathieu characteristic values as the lowest eigenvalue of the
(symmetrised) Hill matrix in mpmath at 30 digits (small amplitude), and for the
nonlinear orbits one Newton step in ``delta`` on ``x(pi)`` / ``x'(pi)`` from mpmath's
Taylor-series ODE solver at 25 digits, or ``brentq`` on scipy's ``solve_ivp``.
"""

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.periodic.shooting import exact_transition_curve, transition_delta
from gfrf.periodic.spectral import fourier_transition


def _hill_lowest(q: float, kind: str, size: int = 16) -> float:
    """Lowest Mathieu value a_0(q), b_1(q) or a_1(q) from the Hill matrix (DLMF 28.6)."""
    with mp.workdps(30):
        q = mp.mpf(q)
        if kind == "a0":
            diag = [mp.mpf(4 * r * r) for r in range(size)]
            off = [mp.sqrt(2) * q] + [q] * (size - 2)
        else:
            diag = [mp.mpf((2 * r + 1) ** 2) for r in range(size)]
            diag[0] += -q if kind == "b1" else q
            off = [q] * (size - 1)
        m = mp.zeros(size)
        for i in range(size):
            m[i, i] = diag[i]
        for i in range(size - 1):
            m[i, i + 1] = m[i + 1, i] = off[i]
        return float(min(mp.eigsy(m)[0]))


@pytest.mark.parametrize("eps", [0.05, 0.3, 0.5, 0.8])
@pytest.mark.parametrize("branch,kind", [("0", "a0"), ("1/4", "b1")])
def test_small_amplitude_is_hill_value(eps, branch, kind):
    # x(0) = 1e-7: the nonlinear shift C x(0)**2 is below 1e-15
    orbit = fourier_transition(eps, 1e-7, branch)
    assert orbit.delta == pytest.approx(_hill_lowest(2 * eps, kind) / 4, abs=2e-14)


@pytest.mark.parametrize("eps", [0.2, 0.5])
def test_upper_side_is_a1(eps):
    # the upper 1/4 curve for eps is the lower one for -eps: a_1(2 eps)/4
    orbit = fourier_transition(-eps, 1e-7, "1/4")
    assert orbit.delta == pytest.approx(_hill_lowest(2 * eps, "a1") / 4, abs=2e-14)


def _mp_reference(eps: float, amp: float, branch: str, delta: float) -> float:
    """One Newton step in delta on the shooting condition, integrated in mpmath."""
    idx = 1 if branch == "0" else 0
    with mp.workdps(25):
        e, a0 = mp.mpf(eps), mp.mpf(amp)

        def at_pi(d: mp.mpf) -> mp.mpf:
            sol = mp.odefun(lambda t, y: [y[1], -(d + e * mp.cos(t)) * (y[0] - y[0] ** 3 / 6)],
                            0, [a0, mp.mpf(0)])
            return sol(mp.pi)[idx]

        d, h = mp.mpf(delta), mp.mpf("1e-9")
        slope = (at_pi(d + h) - at_pi(d - h)) / (2 * h)
        return float(d - at_pi(d) / slope)


@pytest.mark.parametrize("branch", ["0", "1/4"])
def test_nonlinear_value_against_mpmath(branch):
    eps, amp = 0.5, 0.5
    orbit = transition_delta(eps, amp, branch)
    assert orbit.series is not None  # the collocation value passed its check
    assert abs(orbit.delta - _mp_reference(eps, amp, branch, orbit.delta)) < 1e-14


def _brentq_reference(eps: float, amp: float, branch: str, g, bracket) -> float:
    idx = 1 if branch == "0" else 0

    def at_pi(d: float) -> float:
        sol = solve_ivp(lambda t, y: [y[1], -(d + eps * math.cos(t)) * g(y[0])],
                        (0.0, math.pi), [amp, 0.0], method="DOP853", rtol=1e-13, atol=1e-15)
        return float(sol.y[idx, -1])

    return brentq(at_pi, *bracket, xtol=1e-15)


@pytest.mark.parametrize("branch,bracket", [("0", (-0.2, 0.05)), ("1/4", (0.0, 0.3))])
@pytest.mark.parametrize("eps", [0.1, 0.4])
@pytest.mark.parametrize("trunc,g", [(3, lambda x: x - x**3 / 6), (None, math.sin)])
def test_nonlinear_value_against_solve_ivp(branch, bracket, eps, trunc, g):
    amp = 1.0
    delta = transition_delta(eps, amp, branch, trunc).delta
    assert delta == pytest.approx(_brentq_reference(eps, amp, branch, g, bracket), abs=1e-12)


@pytest.mark.parametrize("eps,amp,trunc,g,bracket", [
    # sin(x), x(0) = 1.5: Newton straight from the linear orbit lands on an orbit with a
    # zero crossing (delta ~ 1.37); the branch-0 orbit (no zero) is near delta = 0.068
    (-0.6, 1.5, None, math.sin, (0.0, 0.2)),
    # eq (4), eps = -2: straight from the linear orbit Newton lands on a positive orbit
    # reaching x ~ 4 (delta ~ -1.92); continuation in x(0) stays near delta = -0.21
    (-2.0, 0.3, 3, lambda x: x - x**3 / 6, (-0.5, 0.0)),
])
def test_continuation_stays_on_the_branch(eps, amp, trunc, g, bracket):
    ref = _brentq_reference(eps, amp, "0", g, bracket)
    orbit = fourier_transition(eps, amp, "0", trunc)
    assert orbit.delta == pytest.approx(ref, abs=1e-12)
    t = np.linspace(0.0, math.pi, 200)
    assert np.all(orbit.evaluate(t) > 0)


def test_orbit_samples_match_integration():
    orbit = fourier_transition(0.4, 0.8, "1/4")
    assert orbit.tail <= 1e-15
    t = np.linspace(0.0, 4 * math.pi, 81)
    sol = solve_ivp(lambda s, y: [y[1], -(orbit.delta + 0.4 * math.cos(s))
                                  * (y[0] - y[0] ** 3 / 6)],
                    (0.0, t[-1]), [0.8, 0.0], method="DOP853", rtol=1e-13, atol=1e-15,
                    t_eval=t)
    assert np.max(np.abs(orbit.evaluate(t) - sol.y[0])) < 1e-10


def test_curve_equals_pointwise_values():
    eps = np.array([0.0, 0.1, 0.25, 0.5])
    curve = exact_transition_curve(eps, 0.5, "1/4")
    point = [transition_delta(float(e), 0.5, "1/4").delta for e in eps]
    assert np.max(np.abs(curve - point)) < 1e-13


def test_check_failure_hands_over_to_shooting():
    # a tolerance below the checking integration's own accuracy: shooting Newton runs
    # (from the collocation value) and reports that it cannot reach it
    with pytest.raises(ConvergenceError, match="residual"):
        transition_delta(0.3, 0.5, "1/4", tol=1e-18)


def test_refusals():
    with pytest.raises(ArgumentError, match="amplitude"):
        fourier_transition(0.2, 0.0, "0")
    with pytest.raises(ArgumentError, match="amplitude"):
        fourier_transition(0.2, math.nan, "0")
    with pytest.raises(ArgumentError, match="eps"):
        fourier_transition(math.inf, 0.5, "0")
    # eq (4) beyond g's zero at sqrt(6): no 1/4-branch orbit is reached from the linear one
    with pytest.raises(ConvergenceError, match="x\\(0\\)"):
        fourier_transition(0.2, 2.8, "1/4")

