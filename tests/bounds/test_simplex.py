"""gfrf.bounds.simplex.nelder_mead against scipy's Nelder-Mead and closed-form minima."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize, rosen

from gfrf.bounds.simplex import nelder_mead
from gfrf.errors import ArgumentError

ROOT = Path(__file__).resolve().parents[2]
TIGHT = {"xatol": 1e-12, "fatol": 1e-14}


def _scipy(fun, x0, **options):
    return minimize(fun, x0, method="Nelder-Mead", options=options)


def _quadratic():
    a = np.array([[3.0, 1.0, 0.0], [1.0, 2.0, 0.5], [0.0, 0.5, 1.0]])
    b = np.array([1.0, -2.0, 0.5])
    return (lambda x: float(0.5 * x @ a @ x - b @ x)), np.linalg.solve(a, b)


@pytest.mark.parametrize("x0", [np.array([-1.2, 1.0]), np.array([1.3, 0.7, 0.8, 1.9, 1.2])],
                         ids=["rosenbrock-2d", "rosenbrock-5d"])
def test_rosenbrock_agrees_with_scipy_and_reaches_the_minimum(x0):
    options = {**TIGHT, "maxiter": 400 * x0.size, "maxfev": 800 * x0.size}
    ref = _scipy(rosen, x0, **options)
    res = nelder_mead(rosen, x0, **options)
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8
    assert abs(res.fun - ref.fun) <= 1e-8
    assert (res.nfev, res.nit, res.converged) == (ref.nfev, ref.nit, ref.success)
    assert res.converged
    np.testing.assert_allclose(res.x, np.ones(x0.size), atol=1e-5)  # the minimum is (1, .., 1)


def test_quadratic_agrees_with_scipy_and_the_linear_solve():
    fun, xstar = _quadratic()
    options = {**TIGHT, "maxiter": 5000, "maxfev": 5000}
    ref = _scipy(fun, np.zeros(3), **options)
    res = nelder_mead(fun, np.zeros(3), **options)
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8
    assert res.nfev == ref.nfev
    np.testing.assert_allclose(res.x, xstar, atol=1e-6)


def test_default_options_match_scipy():
    x0 = np.array([0.0, 2.0, -1.0])  # a zero coordinate: the 0.00025 vertex of the default
    ref = _scipy(rosen, x0)
    res = nelder_mead(rosen, x0)
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8
    assert (res.nfev, res.nit) == (ref.nfev, ref.nit)


def test_initial_simplex_is_honoured():
    x0 = np.zeros(2)
    simplex = np.array([[-2.0, 2.0], [-1.5, 2.0], [-2.0, 2.6]])
    ref = _scipy(rosen, x0, initial_simplex=simplex, **TIGHT)
    res = nelder_mead(rosen, x0, initial_simplex=simplex, **TIGHT)
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8
    assert res.nfev == ref.nfev
    default = nelder_mead(rosen, x0, **TIGHT)
    assert default.nfev != res.nfev  # the simplex, not x0, started the search


@pytest.mark.parametrize("maxfev", [1, 3, 4, 137])
def test_maxfev_stops_where_scipy_stops(maxfev):
    x0 = np.array([1.3, 0.7, 0.8, 1.9, 1.2])
    ref = _scipy(rosen, x0, maxfev=maxfev)
    res = nelder_mead(rosen, x0, maxfev=maxfev)
    assert res.nfev == ref.nfev == maxfev
    assert not res.converged
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8


def test_maxiter_stops_where_scipy_stops():
    ref = _scipy(rosen, np.zeros(3), maxiter=50)
    res = nelder_mead(rosen, np.zeros(3), maxiter=50)
    assert res.nit == ref.nit == 50 and not res.converged
    assert np.max(np.abs(res.x - ref.x)) <= 1e-8


def test_nan_values_sort_last_and_fun_is_the_value_at_x():
    def fun(x):
        return float("nan") if x[0] > 2.0 else float((x[0] - 1.0) ** 2 + x[1] ** 2)

    simplex = np.array([[3.0, 0.5], [0.0, 0.5], [0.5, -0.5]])
    res = nelder_mead(fun, np.zeros(2), initial_simplex=simplex, **TIGHT)
    assert res.fun == fun(res.x)
    np.testing.assert_allclose(res.x, [1.0, 0.0], atol=1e-6)


@pytest.mark.parametrize("kwargs", [
    {"x0": np.array([np.nan, 1.0])},
    {"x0": np.zeros((2, 2))},
    {"x0": np.zeros(2), "initial_simplex": np.zeros((2, 2))},
    {"x0": np.zeros(2), "maxfev": 0},
    {"x0": np.zeros(2), "maxiter": -1},
])
def test_bad_arguments_are_refused(kwargs):
    with pytest.raises(ArgumentError, match="nelder_mead"):
        nelder_mead(rosen, **kwargs)


def test_gfrf_norm_does_not_import_scipy_optimize():
    script = ("import contextlib, io, json, sys\n"
              "from gfrf.cli import main\n"
              "with contextlib.redirect_stdout(io.StringIO()):\n"
              "    code = main(['norm', 'models/hanging_pendulum.toml', '--order', '3'])\n"
              "print(json.dumps([code, [m for m in ('scipy.optimize', 'control', 'matplotlib',"
              " 'numba', 'numpy.f2py') if m in sys.modules]]))\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert json.loads(out.stdout.strip().splitlines()[-1]) == [0, []]
