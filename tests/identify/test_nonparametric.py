"""Nonparametric H1, H2, H3 against the true GFRFs of a NARX model with a cross term and of a
hardening oscillator, within the standard deviations the estimates report."""

from __future__ import annotations

import numpy as np
import pytest
from multisine_truth import measure, narx_model, oscillator_model

from gfrf.identify.measured import spectra
from gfrf.identify.multisine import multisine
from gfrf.identify.nonparametric import amplitude_levels, estimate_gfrf
from gfrf.kernels.recursion import kernel


def _within(estimate: np.ndarray, std: np.ndarray, true: np.ndarray) -> float:
    return float(np.mean(np.abs(estimate - true) <= 3 * std))


@pytest.mark.parametrize("noise", [0.02, 0.05])
def test_h1_h2_h3_of_a_narx_model_on_an_isolating_grid(noise: float) -> None:
    design = multisine(4096, 0.1, grid="isolating", realisations=4, periods=4, rms=0.3,
                       levels=(1.0, 0.5), seed=3)
    measured, _ = measure(design, "narx", noise=noise, seed=5, offset=-0.4)
    model = narx_model(0.1)
    result = estimate_gfrf(measured)
    assert result.levels == pytest.approx([0.15, 0.3], rel=0.01)
    h1 = kernel(model, 1)(result.h1.omega)
    assert _within(result.h1.value, result.h1.value_std, h1) >= 0.99
    for order, kernel_estimate, informative in ((2, result.h2, 0.2), (3, result.h3, 1.5)):
        true = kernel(model, order)(*kernel_estimate.frequencies.T)
        assert _within(kernel_estimate.value, kernel_estimate.value_std, true) >= 0.95
        # and the estimates say something: their median error is well below |H_n|
        error = np.median(np.abs(kernel_estimate.value - true) / np.abs(true))
        assert error < informative
    assert result.h2.omega.size == 36 and result.h3.omega.size == 146
    # the sums of the frequencies are the output lines
    assert np.allclose(result.h3.frequencies.sum(axis=1), result.h3.omega)


def test_the_bla_at_one_level_is_biased_and_the_extrapolation_removes_the_bias() -> None:
    design = multisine(4096, 0.1, grid="isolating", realisations=4, periods=4, rms=0.3,
                       levels=(1.0, 0.5), seed=3)
    measured, _ = measure(design, "narx", noise=0.02, seed=5)
    result = estimate_gfrf(measured)
    h1 = kernel(narx_model(0.1), 1)(result.bla.omega)
    bla_error = np.abs(result.bla.bla - h1) / result.bla.bla_std
    assert np.median(bla_error) > 5  # H1 + 3 H3(w, w', -w') |U'|^2 + ...: not H1
    assert np.all(np.abs(result.h1.value - h1) <= 3 * result.h1.value_std)


def test_h1_of_a_narx_model_on_a_dense_random_odd_grid() -> None:
    design = multisine(2048, 0.1, realisations=6, periods=4, rms=0.3, levels=(1.0, 0.5),
                       max_line=500, seed=3)
    measured, _ = measure(design, "narx", noise=0.05, seed=2)
    result = estimate_gfrf(measured, model=narx_model(0.1))
    assert result.comparison["h1"]["within"] >= 0.99
    assert result.comparison["h1"]["estimate"] == "h1 (extrapolated)"


def test_h1_of_a_hardening_oscillator_from_sampled_data() -> None:
    design = multisine(1024, 0.05, realisations=6, periods=3, rms=0.3, levels=(1.0, 0.5),
                       max_line=40, seed=2)
    measured, _ = measure(design, "oscillator", noise=0.02, seed=1, offset=0.5)
    model = oscillator_model()
    result = estimate_gfrf(measured, model=model)
    h1 = kernel(model, 1)(result.h1.omega)
    assert _within(result.h1.value, result.h1.value_std, h1) >= 0.99
    assert result.comparison["h1"]["within"] >= 0.99


@pytest.mark.slow
def test_h2_h3_of_a_hardening_oscillator_on_an_isolating_grid() -> None:
    design = multisine(2048, 0.2, grid="isolating", realisations=4, periods=4, rms=0.2,
                       levels=(1.0, 0.5), max_line=200, seed=2)
    measured, _ = measure(design, "oscillator", noise=0.02, seed=4, offset=0.3)
    model = oscillator_model()
    result = estimate_gfrf(measured)
    for k, order in ((result.h1, 1), (result.h2, 2), (result.h3, 3)):
        true = kernel(model, order)(*k.frequencies.T)
        assert _within(k.value, k.value_std, true) >= (0.99 if order == 1 else 0.95)


def test_levels_are_told_apart_and_one_level_gives_no_extrapolation() -> None:
    design = multisine(256, 0.1, realisations=3, periods=3, levels=(1.0, 0.6, 0.3), seed=1)
    measured, _ = measure(design, "narx")
    u = spectra(measured.u)
    groups = amplitude_levels(u, np.array(design.lines))
    assert [g.tolist() for g in groups] == [[6, 7, 8], [3, 4, 5], [0, 1, 2]]
    single = multisine(256, 0.1, realisations=3, periods=3, seed=1)
    result = estimate_gfrf(measure(single, "narx")[0])
    assert result.h1 is None and len(result.levels) == 1


def test_realisations_scaled_to_a_peak_value_are_one_level() -> None:
    # a user's generator: each realisation scaled to max |u| = 0.5, so the RMS values
    # scatter; these are not amplitude levels, and every realisation makes the BLA
    design = multisine(512, 0.1, realisations=6, periods=3, seed=4)
    scaled = design.u * (0.5 / np.max(np.abs(design.u), axis=1, keepdims=True))
    peak = type(design)(**{**design.__dict__, "u": scaled})
    measured, _ = measure(peak, "narx", noise=0.01)
    rms = np.std(scaled, axis=1)
    assert rms.max() > 1.05 * rms.min()
    result = estimate_gfrf(measured)
    assert result.h1 is None and result.bla.realisations == 6
    assert any("without distinct levels" in n for n in result.notes)


def test_the_bla_bias_is_measured_from_two_levels_and_flagged_with_one() -> None:
    design = multisine(4096, 0.1, grid="isolating", realisations=4, periods=4, rms=0.3,
                       levels=(1.0, 0.5), seed=3)
    measured, _ = measure(design, "narx", noise=0.02, seed=5)
    result = estimate_gfrf(measured)
    bias = result.bla_bias
    assert bias["measured"] and bias["levels"] == 2
    # against the true bias: the highest level's BLA minus the model's H1
    h1 = kernel(narx_model(0.1), 1)(result.bla.omega)
    measured_bias = np.array([complex(*z) for z in bias["bias"]])
    true_bias = result.bla.bla - h1
    assert np.all(np.abs(measured_bias - true_bias) <= 3 * np.array(bias["bias_std"]))
    assert bias["significant_lines"] == bias["lines"]  # every line visibly biased
    single = multisine(4096, 0.1, grid="isolating", realisations=4, periods=4, rms=0.3,
                       seed=3)
    one = estimate_gfrf(measure(single, "narx", noise=0.02, seed=5)[0])
    assert not one.bla_bias["measured"] and one.bla_bias["bias"] is None
    assert any("one input level" in n for n in one.notes)
    assert one.to_dict()["bla_bias"]["note"].startswith("one input level")
