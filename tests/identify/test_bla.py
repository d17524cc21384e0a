"""The best linear approximation: exact on a linear system, its noise level against the noise
put in, its distortion level against the one the model's H3 predicts, and the detection."""

from __future__ import annotations

import math

import numpy as np
import pytest
from multisine_truth import distortion_variance, measure, narx_model, oscillator_model
from scipy.signal import lfilter

from gfrf.identify.bla import best_linear_approximation
from gfrf.identify.measured import periodic, spectra
from gfrf.identify.multisine import multisine

B, A = [0.0, 0.5, 0.3], [1.0, -0.6, 0.2]  # the linear part of the NARX truth


def _h1(omega: np.ndarray, t: float) -> np.ndarray:
    q = np.exp(-1j * omega * t)
    return np.polyval(B[::-1], q) / np.polyval(A[::-1], q)


def _linear(design, noise: float, seed: int = 0, y_offset: float = 0.0):
    y = np.stack([lfilter(B, A, u) for u in design.u])
    sigma = noise * float(np.std(y))
    y = y + y_offset + sigma * np.random.default_rng(seed).standard_normal(y.shape)
    rows, samples = design.u.shape
    t = np.tile(np.arange(samples) * design.sample_time, rows)
    return periodic(t, design.u.ravel(), y.ravel(), np.arange(rows) * samples,
                    design.period, 1), sigma


def _bla(measured):
    return best_linear_approximation(spectra(measured.u), spectra(measured.y),
                                     measured.period, measured.sample_time)


def test_a_linear_system_without_noise_gives_h1_exactly_and_no_distortion() -> None:
    design = multisine(512, 0.1, realisations=3, periods=3, rms=1.0, seed=2)
    measured, _ = _linear(design, 0.0)
    bla = _bla(measured)
    assert bla.lines.tolist() == list(design.lines)
    h1 = _h1(bla.omega, 0.1)
    assert np.max(np.abs(bla.bla - h1) / np.abs(h1)) < 1e-6  # the 2nd period: transient gone
    assert np.max(bla.bla_std) < 1e-6 * np.min(np.abs(h1))
    assert bla.detection["even_detected"] is False and bla.detection["odd_detected"] is False


def test_noise_level_matches_the_noise_put_in_and_the_errors_are_within_three_sigma() -> None:
    # with the std estimated from M realisations, |error / std|^2 is F(2, 2(M - 1)):
    # P(> 9) = (1 + 9 / (M - 1))^-(M - 1) = 0.2 % at M = 10
    design = multisine(1024, 0.1, realisations=10, periods=4, rms=1.0, seed=3)
    measured, sigma = _linear(design, 0.1, seed=8)
    bla = _bla(measured)
    amplitude = design.rms / math.sqrt(2 * len(design.lines))
    # the DFT line of white noise (scaled 1/N) has variance sigma^2 / N; M P periods averaged
    expected = sigma / math.sqrt(1024) / math.sqrt(10 * 3) / amplitude
    assert math.sqrt(np.mean(bla.noise_std ** 2)) == pytest.approx(expected, rel=0.1)
    z = np.abs(bla.bla - _h1(bla.omega, 0.1)) / bla.bla_std
    assert np.mean(z <= 3) >= 0.99
    # a linear system: the realisation spread is noise only
    assert np.mean(bla.distortion_std ** 2) / 10 < 0.3 * np.mean(bla.noise_std ** 2)


def test_excited_lines_of_a_users_multisine_full_grid_uneven_amplitudes_and_offsets() -> None:
    # not gfrf's generator: every line 1..60, amplitudes falling 30 dB, one realisation
    n, t = 600, 0.1
    rng = np.random.default_rng(11)
    lines = np.arange(1, 61)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[lines] = np.logspace(0, -1.5, lines.size) * np.exp(2j * np.pi * rng.random(60))
    one = np.fft.irfft(spectrum * n, n) + 0.7  # an input offset
    u = np.tile(one, 4)
    y = lfilter(B, A, u) - 2.0 + 1e-4 * rng.standard_normal(u.size)
    measured = periodic(np.arange(u.size) * t, u, y, np.array([0]), n, 1)
    bla = _bla(measured)
    assert bla.lines.tolist() == lines.tolist()
    z = np.abs(bla.bla - _h1(bla.omega, t)) / bla.bla_std
    assert np.mean(z <= 3) >= 0.95
    assert bla.detection["odd_lines"] + bla.detection["even_lines"] == n // 2 - 1 - 60


@pytest.mark.parametrize("system", ["narx", "oscillator"])
def test_distortion_level_matches_the_third_order_contribution_of_the_true_gfrfs(system) -> None:
    t = 0.1 if system == "narx" else 0.05
    design = multisine(1024, t, realisations=8, periods=3, rms=0.3, seed=5,
                       max_line=100 if system == "narx" else 40)
    measured, _ = measure(design, system, noise=0.0, offset=0.3)
    bla = _bla(measured)
    model = narx_model(t) if system == "narx" else oscillator_model()
    true = distortion_variance(model, design)
    ratio = math.sqrt(np.mean(bla.distortion_std ** 2) / np.mean(true))
    assert 0.5 <= ratio <= 2.0
    assert bla.detection["even_detected"] and bla.detection["odd_detected"]


def test_one_realisation_takes_the_distortion_from_the_non_excited_lines() -> None:
    design = multisine(2048, 0.1, realisations=1, periods=3, rms=0.3, seed=6, max_line=150)
    measured, _ = measure(design, "narx", noise=0.001)
    bla = _bla(measured)
    true = distortion_variance(narx_model(0.1), design)
    assert bla.realisations == 1
    ratio = math.sqrt(np.mean(bla.distortion_std ** 2) / np.mean(true))
    assert 0.5 <= ratio <= 2.0


def test_an_even_nonlinearity_is_detected_on_even_lines_only() -> None:
    design = multisine(1024, 0.1, realisations=2, periods=3, rms=0.5, seed=1)
    y = np.stack([lfilter(B, A, u + 0.2 * u ** 2) for u in design.u])
    y += 1e-4 * np.random.default_rng(0).standard_normal(y.shape)
    rows, samples = design.u.shape
    measured = periodic(np.tile(np.arange(samples) * 0.1, rows), design.u.ravel(), y.ravel(),
                        np.arange(rows) * samples, 1024, 1)
    d = _bla(measured).detection
    assert d["even_detected"] is True and d["odd_detected"] is False


def test_plot_is_in_db_against_rad_per_second_with_legends() -> None:
    design = multisine(256, 0.1, realisations=2, periods=3, seed=1)
    figure = _bla(_linear(design, 0.01)[0]).plot()
    left, right = figure.axes
    for ax in (left, right):
        assert "rad/s" in ax.get_xlabel() and "dB" in ax.get_ylabel()
        assert ax.get_legend() is not None
    labels = [t.get_text() for t in left.get_legend().get_texts()]
    assert labels[:4] == ["BLA", "total std (noise + distortion)", "noise std",
                          "distortion std (one realisation)"]


def test_a_grid_drawn_anew_in_each_realisation_keeps_its_lines_out_of_the_detection() -> None:
    # a user's random-odd grid, new left-out lines in every realisation: lines excited in
    # some realisations only are neither BLA lines nor detection lines
    rows = [multisine(512, 0.1, realisations=1, periods=3, seed=s).u[0] for s in range(4)]
    design = multisine(512, 0.1, realisations=4, periods=3, seed=0)
    mixed = type(design)(**{**design.__dict__, "u": np.stack(rows)})
    measured, _ = _linear(mixed, 0.01)
    bla = _bla(measured)
    grids = [set(multisine(512, 0.1, realisations=1, periods=1, seed=s).lines)
             for s in range(4)]
    assert bla.lines.tolist() == sorted(set.intersection(*grids))
    assert bla.partial.tolist() == sorted(set.union(*grids) - set.intersection(*grids))
    assert bla.detection["odd_detected"] is False and bla.detection["even_detected"] is False
    z = np.abs(bla.bla - _h1(bla.omega, 0.1)) / bla.bla_std
    assert np.mean(z <= 3) >= 0.95
