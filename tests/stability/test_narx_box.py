"""The invariant-box certificate of a NARX recursion: a closed form, the exact check
refusing tampered certificates, and simulated bounded inputs below the radius."""

from __future__ import annotations

import copy
import itertools
from fractions import Fraction

import numpy as np
import pytest
from conftest import MODELS

from gfrf.model.modelfile import resolve_model
from gfrf.stability.narx_box import box_certificate, check_box
from gfrf.stability.polysys import state_form


def _system(model: str):
    return state_form(resolve_model(model, sample_time=0.1)
                      if "=" in model else resolve_model(MODELS / model))


@pytest.fixture(scope="module")
def narx():
    system = _system("narx_example.toml")
    return system, box_certificate(system)


def test_quadratic_map_radius_is_below_and_near_the_fold():
    # y[k] = y[k-1]^2 + u[k-1]: a constant input U escapes iff U > 1/4 (no fixed point of
    # y^2 + U = y), and for U <= 1/4 the box [-U, fixed point] is invariant: exact 1/4
    res = box_certificate(_system("y[k] = y[k-1]**2 + u[k-1]"))
    assert res is not None
    assert 0.24 < res.radius <= 0.25
    y, U = 0.0, 0.2501
    for _ in range(20000):
        y = y * y + U
    assert y > 10


def test_the_exact_check_passes_the_found_certificate_and_refuses_tampering(narx):
    system, res = narx
    assert res is not None and check_box(system, res.certificate) == ""
    bigger = copy.deepcopy(res.certificate)
    bigger["U"] = str(2 * Fraction(bigger["U"]))
    assert "leaves" in check_box(system, bigger)
    shrunk = copy.deepcopy(res.certificate)
    shrunk["hi"][0] = str(Fraction(shrunk["hi"][0]) / 2)
    assert "leaves" in check_box(system, shrunk)
    bad_inverse = copy.deepcopy(res.certificate)
    key = next(iter(bad_inverse["X"][0]))
    bad_inverse["X"][0][key] = str(Fraction(bad_inverse["X"][0][key]) + Fraction(1, 1000))
    assert "inverse" in check_box(system, bad_inverse)
    assert check_box(system, {"format": "gfrf-narx-box"}) != ""


def test_narx_example_radius_exceeds_the_series_radius(narx):
    _, res = narx
    # Theorem 1's r* of this model is sqrt(5)/4 = 0.559 (the plain lagged box gives it too)
    assert res.radius > 1.5


def _narx_example(u: np.ndarray) -> np.ndarray:
    """y[k] = 0.5 y[k-1] - 0.2 y[k-1]^2 u[k-2] + u[k-1], rows of u are inputs, from rest."""
    m, N = u.shape
    y = np.zeros((m, N))
    for k in range(2, N):
        y[:, k] = 0.5 * y[:, k - 1] - 0.2 * y[:, k - 1] ** 2 * u[:, k - 2] + u[:, k - 1]
    return y


def _inputs(U: float, N: int) -> np.ndarray:
    rng = np.random.default_rng(3)
    t = np.arange(N)
    rows = [U * rng.choice([-1.0, 1.0], size=(200, N)),            # random signs
            U * rng.uniform(-1, 1, size=(200, N))]                   # random levels
    for w in np.linspace(0.05, np.pi, 40):                          # tones and squares
        rows.append(U * np.cos(w * t)[None, :])
        rows.append(U * np.sign(np.cos(w * t) + 1e-12)[None, :])
    for period in range(1, 9):                                       # bang-bang blocks
        rows.append(U * (-1.0) ** (t // period)[None, :])
    # every sign sequence of length 12, then held: the short-horizon worst cases
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=12)))
    rows.append(U * np.hstack([signs, np.repeat(signs[:, -1:], N - 12, axis=1)]))
    return np.vstack(rows)


def test_bounded_inputs_below_the_radius_stay_inside_the_bound(narx):
    _, res = narx
    assert res is not None
    y = _narx_example(_inputs(res.radius, 300))
    assert np.all(np.isfinite(y))
    assert np.max(np.abs(y)) <= res.bound


def test_a_linear_recursion_is_bounded_for_every_bounded_input():
    # y[k] = 0.5 y[k-1] + u[k-1]: |y| <= 2 sup|u| (the l1 norm of 0.5^k), any amplitude
    res = box_certificate(_system("y[k] = 0.5*y[k-1] + u[k-1]"))
    assert res is not None and res.radius == float("inf")


def test_an_unbounded_recursion_gets_no_box():
    # y[k] = y[k-1] + u[k-1] sums the input: unbounded for a constant input of any size
    assert box_certificate(_system("y[k] = y[k-1] + u[k-1]")) is None


def test_sampling_agrees_with_the_exact_check(narx):
    # points of the box x [-U, U] mapped by the recursion in float: inside for the
    # accepted certificate; a violation found for the one with the output box halved
    # (refused exactly)
    from gfrf.stability.narx_box import _poly_from, box_map
    from gfrf.stability.polysys import peval

    system, res = narx
    rng = np.random.default_rng(11)

    def worst(cert: dict) -> float:
        nv = system.n + 1
        g = box_map(system, [_poly_from(p, nv) for p in cert["T"]],
                    [_poly_from(p, nv) for p in cert["X"]])
        U = float(Fraction(cert["U"]))
        lo = np.array([float(Fraction(x)) for x in cert["lo"]] + [-U])
        hi = np.array([float(Fraction(x)) for x in cert["hi"]] + [U])
        pts = lo + (hi - lo) * rng.uniform(size=(20000, nv))
        pts[:1000] = np.where(rng.uniform(size=(1000, nv)) < 0.5, lo, hi)  # corners
        excess = [np.max(np.maximum(peval(p, pts) - hi[i], lo[i] - peval(p, pts)))
                  for i, p in enumerate(g)]
        return float(max(excess))

    assert worst(res.certificate) <= 1e-12
    shrunk = copy.deepcopy(res.certificate)
    shrunk["lo"][0] = str(Fraction(shrunk["lo"][0]) / 2)
    shrunk["hi"][0] = str(Fraction(shrunk["hi"][0]) / 2)
    assert check_box(system, shrunk) != "" and worst(shrunk) > 0
