"""Tests of gfrf.identify: the exact sysidentpy converter, FROLS identification, the CLI.

References are independent of gfrf's kernel recursion: the closed-form H1 and H2 of
a NARX model (Peyton Jones and Billings) written out below with numpy, sysidentpy's
own free-run prediction, and least-squares covariance for the tolerance of noisy fits.
"""

from __future__ import annotations

import json
import math
import tomllib
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from gfrf.cli import main
from gfrf.errors import ArgumentError, ModelError
from gfrf.identify import example as ex
from gfrf.identify.data import read_csv
from gfrf.identify.fit import free_run, identify, same_terms
from gfrf.identify.narx import from_sysidentpy
from gfrf.identify.output import model_file_text, write_atomic
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model

pytest.importorskip("sysidentpy")

T = 0.1
# y[k] = sum theta * monomial; keys: (output lags, input lags).
CROSS = {((1,), ()): 0.5, ((2,), ()): -0.1, ((), (1,)): 0.8, ((), (2,)): 0.3,
         ((1,), (1,)): 0.2, ((), (1, 1)): -0.1}
CUBIC = {((1,), ()): 0.6, ((2,), ()): -0.2, ((), (1,)): 0.5, ((), (1, 2)): 0.15,
         ((1, 1, 1), ()): -0.05}


def _simulate(theta: dict, u: np.ndarray, noise: np.ndarray) -> np.ndarray:
    """Direct recursion y[k] = sum theta * monomial + noise[k] (reference simulator)."""
    y = np.zeros(u.size)
    for k in range(2, u.size):
        total = noise[k]
        for (ylags, ulags), c in theta.items():
            term = c
            for lag in ylags:
                term *= y[k - lag]
            for lag in ulags:
                term *= u[k - lag]
            total += term
        y[k] = total
    return y


def _h1(theta: dict, w: np.ndarray) -> np.ndarray:
    q = np.exp(-1j * np.asarray(w) * T)
    a = 1 - sum(c * q**ys[0] for (ys, us), c in theta.items() if len(ys) == 1 and not us)
    b = sum(c * q**us[0] for (ys, us), c in theta.items() if not ys and len(us) == 1)
    return b / a


def _h2(theta: dict, w1: np.ndarray, w2: np.ndarray) -> np.ndarray:
    """Closed-form symmetric H2 of a NARX model (degree-2 terms only contribute)."""
    q1, q2 = np.exp(-1j * w1 * T), np.exp(-1j * w2 * T)
    g1, g2 = _h1(theta, w1), _h1(theta, w2)
    num = np.zeros(np.broadcast(w1, w2).shape, dtype=complex)
    for (ys, us), c in theta.items():
        if len(ys) + len(us) != 2:
            continue
        if len(us) == 2:
            num += c * (q1**us[0] * q2**us[1] + q1**us[1] * q2**us[0]) / 2
        elif len(ys) == 1:
            num += c * (g1 * q1**ys[0] * q2**us[0] + g2 * q2**ys[0] * q1**us[0]) / 2
        else:
            num += c * g1 * g2 * (q1**ys[0] * q2**ys[1] + q1**ys[1] * q2**ys[0]) / 2
    q12 = q1 * q2
    den = 1 - sum(c * q12**ys[0] for (ys, us), c in theta.items() if len(ys) == 1 and not us)
    return num / den


def _text(theta: dict) -> str:
    parts = []
    for (ys, us), c in theta.items():
        factors = [f"y[k-{lag}]" for lag in ys] + [f"u[k-{lag}]" for lag in us]
        parts.append(f"({c!r})*" + "*".join(factors))
    return "y[k] = " + " + ".join(parts)


def _codes(theta: dict, width: int) -> tuple[np.ndarray, np.ndarray]:
    rows, values = [], []
    for (ys, us), c in theta.items():
        row = [1000 + lag for lag in ys] + [2000 + lag for lag in us]
        rows.append(row + [0] * (width - len(row)))
        values.append([c])
    return np.array(rows), np.array(values)


def _as_theta(model) -> dict:
    lead = next(t.coefficient for t in model.terms if t.y_orders == (0,) and not t.u_orders)
    return {(t.y_orders, t.u_orders): -t.coefficient / lead for t in model.terms
            if not (t.y_orders == (0,) and not t.u_orders)}


W = np.array([0.0, 0.7, 3.1, 11.0, 25.0, 31.4])
W1, W2 = np.meshgrid(np.linspace(-31, 31, 9), np.linspace(-31, 31, 9))


def test_closed_form_reference_agrees_with_gfrf_kernels():
    model = parse_model(_text(CROSS), sample_time=T)
    assert np.allclose(kernel(model, 1)(W), _h1(CROSS, W), rtol=1e-12, atol=1e-14)
    assert np.allclose(kernel(model, 2)(W1, W2), _h2(CROSS, W1, W2), rtol=1e-12, atol=1e-14)


# ----------------------------------------------------------------- the converter

@pytest.mark.parametrize("theta", [CROSS, CUBIC])
def test_converter_round_trips_exactly(theta):
    codes, values = _codes(theta, 3)
    converted = from_sysidentpy(SimpleNamespace(final_model=codes, theta=values), T)
    written = parse_model(_text(theta), sample_time=T)
    assert converted.terms == written.terms  # same lags and bit-identical coefficients
    reread = parse_model(converted.text, sample_time=T)
    assert reread.terms == converted.terms
    for n, args in ((1, (W,)), (2, (W1, W2)), (3, (W[:3], W[1:4], W[2:5]))):
        a, b = kernel(converted, n)(*args), kernel(written, n)(*args)
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, np.max(np.abs(b)))


def test_converter_on_a_sysidentpy_model_with_known_theta_matches_its_prediction():
    from sysidentpy.basis_function import Polynomial
    from sysidentpy.model_structure_selection import FROLS
    from sysidentpy.parameter_estimation import LeastSquares

    rng = np.random.default_rng(3)
    u = rng.uniform(-1, 1, 400)
    y = _simulate(CROSS, u, np.zeros(u.size))
    fitted = FROLS(ylag=2, xlag=2, n_terms=6, order_selection=False,
                   estimator=LeastSquares(), basis_function=Polynomial(degree=2))
    fitted.fit(X=u[:, None], y=y[:, None])
    codes, values = _codes(CROSS, 2)
    fitted.final_model, fitted.theta = codes, values  # a model with known theta
    model = from_sysidentpy(fitted, T)
    assert model.terms == parse_model(_text(CROSS), sample_time=T).terms
    u_new = rng.uniform(-1, 1, 300)
    y_new = _simulate(CROSS, u_new, np.zeros(u_new.size))
    expected = fitted.predict(X=u_new[:, None], y=y_new[:2, None]).ravel()
    ours, blowup = free_run(model, u_new, y_new[:2])
    assert blowup is None
    assert np.max(np.abs(ours - expected)) <= 1e-12
    assert np.max(np.abs(ours - y_new)) <= 1e-12


@pytest.mark.parametrize("codes, theta, message", [
    ([[1001, 0], [0, 0], [2001, 0]], [0.5, 0.1, 1.0], "constant term"),
    ([[1001, 0], [3001, 0]], [0.5, 1.0], "one input"),
    ([[1001, 0], [1001, 0], [2001, 0]], [0.5, 0.1, 1.0], "same monomial"),
    ([[1001, 0], [1002, 1001]], [0.5, 0.1], "no input term"),
    ([[1000, 0], [2001, 0]], [0.5, 1.0], "implicit"),
    ([[1001, 0], [2001, 0]], [0.5], "theta has 1 entries for 2"),
    ([[1001, 0], [2001, 0]], [np.nan, 1.0], "not finite"),
    ([[1001, 0], [2001.5, 0]], [0.5, 1.0], "integer"),
    ([[1001, 0], [2099, 0]], [0.5, 1.0], "lag 99"),
])
def test_converter_refuses_what_gfrf_cannot_represent(codes, theta, message):
    with pytest.raises(ModelError, match=message):
        from_sysidentpy(SimpleNamespace(final_model=np.array(codes), theta=np.array(theta)), T)


def test_converter_refuses_non_polynomial_bases_miso_and_unfitted_models():
    from sysidentpy.basis_function import Fourier, Polynomial

    codes, values = _codes(CROSS, 2)
    with pytest.raises(ModelError, match="Fourier basis"):
        from_sysidentpy(SimpleNamespace(final_model=codes, theta=values,
                                        basis_function=Fourier(degree=2)), T)
    with pytest.raises(ModelError, match="2 inputs"):
        from_sysidentpy(SimpleNamespace(final_model=codes, theta=values, n_inputs=2,
                                        basis_function=Polynomial()), T)
    with pytest.raises(ModelError, match="call fit first"):
        from_sysidentpy(SimpleNamespace(final_model=None, theta=None), T)
    with pytest.raises(ModelError, match="sample_time"):
        from_sysidentpy(SimpleNamespace(final_model=codes, theta=values), 0.0)


def test_converter_drops_the_noise_model_with_a_note():
    codes, values = _codes(CROSS, 2)
    fitted = SimpleNamespace(final_model=codes, theta=values, elag=2,
                             estimator=SimpleNamespace(unbiased=True))
    with pytest.warns(UserWarning, match="noise model .* dropped"):
        model = from_sysidentpy(fitted, T)
    assert model.terms == parse_model(_text(CROSS), sample_time=T).terms


# ------------------------------------------------------------ identification

def _contains_true_terms(model, theta: dict) -> bool:
    return set(theta) <= set(_as_theta(model))


def test_noise_free_identification_recovers_the_cross_term_model_exactly():
    rng = np.random.default_rng(5)
    u = rng.uniform(-1, 1, 1500)
    y = _simulate(CROSS, u, np.zeros(u.size))
    result = identify(y, u, T, degree=2)
    assert _contains_true_terms(result.model, CROSS)
    identified = result.model
    assert np.max(np.abs(kernel(identified, 1)(W) - _h1(CROSS, W))) < 1e-9
    assert np.max(np.abs(kernel(identified, 2)(W1, W2) - _h2(CROSS, W1, W2))) < 1e-9
    assert result.free_run_error < 1e-9
    assert result.n_train == 1125


def _regressor_matrix(theta_keys, y, u, lag):
    columns = []
    for ys, us in theta_keys:
        col = np.ones(y.size - lag)
        for l_ in ys:
            col = col * y[lag - l_:y.size - l_]
        for l_ in us:
            col = col * u[lag - l_:u.size - l_]
        columns.append(col)
    return np.column_stack(columns)


def _kernel_sigma(f, theta: dict, cov: np.ndarray, keys: list) -> np.ndarray:
    """Linearised standard deviation of |f(theta_hat) - f(theta)| from cov of theta_hat."""
    base = np.ravel(f(theta))
    jac = []
    for key in keys:
        step = 1e-7
        moved = dict(theta)
        moved[key] = moved.get(key, 0.0) + step
        jac.append((np.ravel(f(moved)) - base) / step)
    jac = np.array(jac)  # (p, points)
    var = (np.einsum("ip,ij,jp->p", jac.real, cov, jac.real)
           + np.einsum("ip,ij,jp->p", jac.imag, cov, jac.imag))
    return np.sqrt(var)


@pytest.mark.parametrize("theta, sigma, seed", [(CROSS, 0.02, 7), (CUBIC, 0.02, 8)])
def test_noisy_identification_kernels_within_the_noise_tolerance(theta, sigma, seed):
    """Equation noise e ~ N(0, sigma^2): LS is unbiased with covariance sigma^2 (Psi'Psi)^-1."""
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1, 1, 3000)
    y = _simulate(theta, u, sigma * rng.standard_normal(u.size))
    result = identify(y, u, T)
    assert _contains_true_terms(result.model, theta)
    got = _as_theta(result.model)
    keys = list(got)
    psi = _regressor_matrix(keys, y[:result.n_train], u[:result.n_train], 2)
    cov = sigma**2 * np.linalg.inv(psi.T @ psi)
    true_full = {k: theta.get(k, 0.0) for k in keys}
    errors = np.abs(np.array([got[k] - true_full[k] for k in keys]))
    assert np.all(errors <= 6 * np.sqrt(np.diag(cov)))  # parameters within 6 sigma
    for n, f, args in ((1, lambda th: _h1(th, W), (W,)),
                       (2, lambda th: _h2(th, W1, W2), (W1, W2))):
        tol = 6 * _kernel_sigma(f, true_full, cov, keys) + 1e-10
        diff = np.abs(kernel(result.model, n)(*args) - f(theta))
        assert np.all(diff <= tol.reshape(diff.shape)), (n, np.max(diff / tol))
    assert result.free_run_error < 0.2


def test_identification_settings_are_checked_before_fitting():
    y = np.zeros(100)
    with pytest.raises(ArgumentError, match="too few"):
        identify(y, y, T, ylag=4, ulag=4, degree=3)
    with pytest.raises(ArgumentError, match="criterion"):
        identify(y, y, T, criterion="magic")
    with pytest.raises(ArgumentError, match="holdout"):
        identify(y, y, T, holdout=0.9)
    with pytest.raises(ArgumentError, match="candidate terms, above the limit"):
        identify(np.zeros(10**5), np.zeros(10**5), T, ylag=10, ulag=10, degree=4)
    with pytest.raises(ArgumentError, match="non-finite"):
        identify(np.r_[y[:-1], np.inf], y, T)
    with pytest.raises(ArgumentError, match="samples"):
        identify(y, y[:50], T)


def test_identify_runs_without_sysidentpy(monkeypatch, tmp_path, capsys):
    import sys

    for name in [m for m in sys.modules if m.startswith("sysidentpy")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "sysidentpy", None)  # any import of it fails
    rng = np.random.default_rng(1)
    u = rng.uniform(-1, 1, 600)
    y = _simulate(CROSS, u, np.zeros(u.size))
    assert _contains_true_terms(identify(y, u, T).model, CROSS)
    path = tmp_path / "d.csv"
    rows = [f"{float(a)!r},{float(b)!r}" for a, b in zip(u, y, strict=True)]
    path.write_text("u,y\n" + "\n".join(rows) + "\n", encoding="utf-8")
    assert main(["identify", str(path), "--sample-time", "0.1", "--order", "1"]) in (0, 1)
    assert "identified from" in capsys.readouterr().out


# --------------------------------------------------------- files and the CLI

def _csv(tmp_path, y, u, name="data.csv"):
    path = tmp_path / name
    rows = ["t,u,y"] + [f"{k * T:g},{float(a)!r},{float(b)!r}"
                        for k, (a, b) in enumerate(zip(u, y, strict=True))]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_cli_identify_writes_a_model_file_that_verdict_reads(tmp_path, capsys):
    rng = np.random.default_rng(11)
    u = rng.uniform(-1, 1, 800)
    y = _simulate(CROSS, u, np.zeros(u.size))
    data = _csv(tmp_path, y, u)
    out = tmp_path / "model.toml"
    code = main(["identify", str(data), "--sample-time", "0.1", "--degree", "2",
                 "--out", str(out), "--order", "3", "--json"])
    payload = json.loads(capsys.readouterr().out)
    assert code in (0, 1)
    assert payload["verdict"]["verdict"] in ("stable", "inconclusive")
    mf = load_model(out)
    assert set(CROSS) <= set(_as_theta(mf.plant))
    assert np.max(np.abs(kernel(mf.plant, 1)(W) - _h1(CROSS, W))) < 1e-9
    source = tomllib.loads(out.read_text(encoding="utf-8"))["source"]
    assert str(data) in source and "--degree 2" in source and "free-run RRSE" in source
    assert payload["identification"]["free_run_error"] < 1e-9
    assert not list(tmp_path.glob(".model.toml.*"))  # no temporary file left behind
    code = main(["verdict", str(out), "--order", "3", "--json"])
    assert json.loads(capsys.readouterr().out)["verdict"] == payload["verdict"]["verdict"]


def test_cli_identify_text_output_and_bad_input(tmp_path, capsys):
    rng = np.random.default_rng(12)
    u = rng.uniform(-1, 1, 400)
    y = _simulate(CROSS, u, np.zeros(u.size))
    data = _csv(tmp_path, y, u)
    assert main(["identify", str(data), "--sample-time", "0.1", "--degree", "2",
                 "--order", "2"]) in (0, 1)
    text = capsys.readouterr().out
    assert "y[k] = " in text and "free-run RRSE" in text and "verdict:" in text
    assert main(["identify", str(data), "--output", "v", "--sample-time", "0.1"]) == 2
    assert "no column 'v'" in capsys.readouterr().err
    assert main(["identify", str(data), "--sample-time", "0.1", "--out",
                 str(tmp_path / "missing" / "m.toml")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["identify", str(data), "--sample-time", "-1"]) == 2
    assert main(["identify", str(tmp_path / "none.csv"), "--sample-time", "0.1"]) == 2


@pytest.mark.parametrize("content, message", [
    ("u,y\n1,2\n1,abc\n", "line 3, column 'y': 'abc'"),
    ("u,y\n1,2\nnan,1\n", "1 row.* missing .* line 3.*--missing interpolate"),
    ("u,y\n1,2\n", "fewer than two"),
    ("a,b\n1,2\n", "no column 'y'"),
    ("u,y\n1,2\n3\n", "1 row.* missing .* line 3"),
    ("u,y\n1,2\ninf,1\n", "line 3, column 'u': 'inf'"),
])
def test_read_csv_names_the_bad_value(tmp_path, content, message):
    path = tmp_path / "bad.csv"
    path.write_text(content, encoding="utf-8")
    with pytest.raises(ArgumentError, match=message):
        read_csv(path, "y", "u")


def test_write_atomic_is_atomic_and_model_file_text_reproduces_the_model(tmp_path):
    rng = np.random.default_rng(13)
    u = rng.uniform(-1, 1, 600)
    y = _simulate(CUBIC, u, 0.01 * rng.standard_normal(u.size))
    result = identify(y, u, T, output="v", input="w")
    text = model_file_text(result, "data.csv", name='quote " and \\ backslash')
    path = write_atomic(tmp_path / "m.toml", text)
    mf = load_model(path)
    assert mf.plant.terms == result.model.terms
    assert mf.name == 'quote " and \\ backslash'
    assert (mf.plant.output, mf.plant.input) == ("v", "w")
    assert [p.name for p in tmp_path.iterdir()] == ["m.toml"]
    reference = tmp_path / "plain.txt"
    reference.write_text("x", encoding="utf-8")
    assert path.stat().st_mode & 0o777 == reference.stat().st_mode & 0o777


# ----------------------------------------------------------- worked example

def test_worked_example_files_are_consistent_and_close_to_the_truth():
    folder = ex.MODELS_DIR
    csv_path = folder / f"{ex.STEM}.csv"
    assert csv_path.stat().st_size < 200_000
    true = load_model(folder / f"{ex.STEM}_true.toml").plant
    assert true.terms == ex.true_model().terms
    u, y_measured, y_clean = ex.generate()
    y_read, u_read = read_csv(csv_path, "y", "u")
    assert np.max(np.abs(u_read - u)) <= 5e-6 and np.max(np.abs(y_read - y_measured)) <= 5e-6
    identified = load_model(folder / f"{ex.STEM}.toml").plant
    fresh = identify(y_read, u_read, ex.SAMPLE_TIME).model.terms
    # the same monomials; coefficients to 1e-9 relative (BLAS may differ by ulps)
    assert same_terms(identified.terms, fresh)
    truth = _as_theta(true)
    assert set(truth) <= set(_as_theta(identified))
    # Measurement noise v on y: the equation error is v[k] - sum_l a_l v[k-l] + ...,
    # of standard deviation about sigma_v * sqrt(1 + sum a_l^2); LS on noisy regressors
    # is biased by about theta * sigma_v^2 / var(y) (errors in variables).  The kernel
    # tolerance: 6 linearised standard deviations plus that bias, both propagated.
    sigma_eq = ex.NOISE * math.sqrt(1 + 0.6**2 + 0.2**2)
    keys = list(_as_theta(identified))
    n_train = int(round(0.75 * y_read.size))
    psi = _regressor_matrix(keys, y_read[:n_train], u_read[:n_train], 2)
    cov = sigma_eq**2 * np.linalg.inv(psi.T @ psi)
    bias = ex.NOISE**2 / np.var(y_clean)
    full = {k: truth.get(k, 0.0) for k in keys}
    for f in (lambda th: _h1(th, W), lambda th: _h2(th, W1, W2)):
        sd = _kernel_sigma(f, full, cov, keys)
        bias_shift = np.ravel(np.abs(f({k: v * (1 + 3 * bias) for k, v in full.items()})
                                     - f(full)))
        tol = 6 * sd + 3 * bias_shift + 1e-10
        diff = np.ravel(np.abs(f(_as_theta(identified)) - f(truth)))
        assert np.all(diff <= tol), np.max(diff / tol)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.allclose(kernel(identified, 1)(W), _h1(_as_theta(identified), W),
                           rtol=1e-12, atol=1e-14)


def test_the_top_level_name_and_the_package_face():
    import gfrf
    import gfrf.identify

    assert gfrf.from_sysidentpy is from_sysidentpy
    assert gfrf.identify.from_sysidentpy is from_sysidentpy


def test_narx_equation_and_free_run_refuse_models_not_explicit_in_y_k():
    from gfrf.identify.narx import narx_equation

    model = parse_model("2*y[k] = y[k-1] + 3*u[k-1] - u[k-2]**2", sample_time=T)
    assert narx_equation(model) == "y[k] = 0.5*y[k-1] + 1.5*u[k-1] - 0.5*u[k-2]**2"
    assert parse_model(narx_equation(model), sample_time=T).terms == \
        parse_model("y[k] = 0.5*y[k-1] + 1.5*u[k-1] - 0.5*u[k-2]**2", sample_time=T).terms
    u = np.array([0.0, 1.0, 2.0, -1.0])
    y, blowup = free_run(model, u, np.zeros(1))
    assert blowup is None and list(y) == [0.0, 0.0, 1.5, 3.75 - 0.5]
    for bad in (parse_model("y[k] + y[k]**2 = u[k-1]", sample_time=T),
                parse_model("D(y) + y = u")):
        with pytest.raises(ArgumentError, match="explicit"):
            free_run(bad, u, np.zeros(1))
    runaway = parse_model("y[k] = 3*y[k-1] + u[k-1]", sample_time=T)
    y, blowup = free_run(runaway, np.ones(40), np.zeros(1))
    assert blowup is not None and 10 < blowup < 40


def test_a_criterion_at_its_limit_is_noted():
    rng = np.random.default_rng(4)
    u = rng.uniform(-1, 1, 600)
    y = _simulate(CROSS, u, np.zeros(u.size))
    result = identify(y, u, T, degree=2, max_terms=3)
    assert len(result.regressors) == 3
    assert any("larger max_terms" in n for n in result.notes)
    assert "larger max_terms" in model_file_text(result, "d.csv")


def test_report_kernel_errors_against_the_closed_form():
    from gfrf.identify.example import kernel_errors

    other = dict(CROSS)
    other[((1,), ())] = 0.52
    other[((), (1, 1))] = -0.12
    true, moved = (parse_model(_text(th), sample_time=T) for th in (CROSS, other))
    errors = kernel_errors(moved, true, points=100)
    w = np.linspace(0.0, math.pi / T, 100)
    expected_h1 = np.max(np.abs(_h1(other, w) - _h1(CROSS, w))) / np.max(np.abs(_h1(CROSS, w)))
    g = np.linspace(-math.pi / T, math.pi / T, int(math.sqrt(100 * 40)))
    g1, g2 = np.meshgrid(g, g)
    h2 = _h2(CROSS, g1, g2)
    expected_h2 = np.max(np.abs(_h2(other, g1, g2) - h2)) / np.max(np.abs(h2))
    assert errors["H1"] == pytest.approx(expected_h1, rel=1e-9)
    assert errors["H2"] == pytest.approx(expected_h2, rel=1e-9)


@pytest.mark.slow
def test_report_page_shows_both_models(tmp_path):
    from gfrf.report.identified import PAGE, write

    page = write(tmp_path, quick=True)
    text = page.read_text(encoding="utf-8")
    assert page.name == PAGE
    assert "matches this fresh identification: yes" in text
    assert "| true | " in text and "| identified | " in text
    for name in ("identified-example-h1.png", "identified-example-h2.png"):
        assert (tmp_path / name).stat().st_size > 1000 and f"]({name})" in text


def test_same_terms_tolerates_ulps_and_nothing_more():
    """The 1-ulp BLAS difference seen on another CPU passes; a real change does not."""
    from gfrf.model.equation import Term

    a = [Term((1,), (), -0.4995686297675639, discrete=True), Term((), (1,), 0.25, discrete=True)]
    ulp = [Term((1,), (), -0.49956862976756367, discrete=True), a[1]]
    moved = [Term((1,), (), -0.4995686297675639 * (1 + 1e-7), discrete=True), a[1]]
    other = [Term((2,), (), -0.4995686297675639, discrete=True), a[1]]
    assert same_terms(a, ulp) and same_terms(a, a)
    assert not same_terms(a, moved) and not same_terms(a, other) and not same_terms(a, a[:1])


def test_identification_leaves_matplotlib_settings_alone():
    """sysidentpy's first import turns the top and right spines off for every later plot;
    identify() must not pass that on (two report builds differed by it)."""
    code = """
import matplotlib
matplotlib.use("Agg")
import numpy as np
from gfrf.identify import identify
before = {k: str(v) for k, v in matplotlib.rcParams.items()}
u = np.random.default_rng(0).uniform(-1, 1, 400)
y = np.convolve(u, [0.0, 0.5, 0.2])[:400]
identify(y, u, 0.1)
after = {k: str(v) for k, v in matplotlib.rcParams.items()}
print({k: (before[k], after[k]) for k in before if before[k] != after[k]})
"""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "{}"
