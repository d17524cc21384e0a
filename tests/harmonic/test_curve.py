"""Frequency response curves against long simulations, slow sweeps, the Volterra series
and the exact period of the free Duffing oscillator."""

from __future__ import annotations

import functools
import json
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

import gfrf
from gfrf.errors import ArgumentError
from gfrf.harmonic.curve import frc
from gfrf.model.equation import parse_model
from gfrf.sim.volterra import predict, series_radius

HARDENING = ("D(y,2) + 0.1*D(y) + y + 0.3*y**3 = u", 0.3, 0.3)
SOFTENING = ("D(y,2) + 0.1*D(y) + y - 0.3*y**3 = u", -0.3, 0.05)


@functools.cache
def _curve(text: str, forcing: float):
    return frc(parse_model(text), forcing, (0.5, 2.0))


def _duffing(cubic: float, forcing: float, omega: float):
    return lambda t, z: [z[1], forcing * math.cos(omega * t) - 0.1 * z[1] - z[0]
                         - cubic * z[0] ** 3]


def _first_harmonic(sol, omega: float, start: float) -> complex:
    """a1 - j b1 of y over the period from ``start`` (256 samples of the dense output)."""
    n = 256
    t = start + 2 * math.pi / omega * np.arange(n) / n
    return complex(np.exp(-1j * omega * t) @ sol.sol(t)[0] * 2 / n)


def _settled(cubic: float, forcing: float, omega: float, y0: float, v0: float,
             seconds: float = 250.0) -> complex:
    """The first harmonic after ``seconds`` of DOP853 (rtol 1e-12) from (y0, v0)."""
    period = 2 * math.pi / omega
    periods = int(seconds / period) + 1
    sol = solve_ivp(_duffing(cubic, forcing, omega), (0.0, periods * period), [y0, v0],
                    method="DOP853", rtol=1e-12, atol=1e-13, dense_output=True)
    return _first_harmonic(sol, omega, (periods - 1) * period)


def _state(point) -> tuple[float, float]:
    c = point.coefficients
    k = np.arange(1, (c.size - 1) // 2 + 1)
    return float(c[0] + c[1::2].sum()), float(point.omega * (k * c[2::2]).sum())


def _check_stable_amplitudes(case: tuple[str, float, float], omegas: tuple[float, ...]
                             ) -> None:
    text, cubic, forcing = case
    curve = _curve(text, forcing)
    stable = [p for p in curve.points if p.stable]
    for w in omegas:
        point = min(stable, key=lambda p: abs(p.omega - w))
        y0, v0 = _state(point)
        # start 0.1 % off the orbit: the simulation must come back to it by itself
        simulated = _settled(cubic, forcing, point.omega, 1.001 * y0, v0)
        assert abs(abs(simulated) - point.amplitude) <= 1e-6 * point.amplitude
        assert abs(simulated - complex(point.coefficients[1], -point.coefficients[2])) \
            <= 1e-6 * point.amplitude


@pytest.mark.parametrize("case", [HARDENING, SOFTENING], ids=["hardening", "softening"])
def test_stable_amplitudes_agree_with_long_simulations(case) -> None:
    _check_stable_amplitudes(case, (1.3,) if case is HARDENING else (0.95,))


@pytest.mark.slow
@pytest.mark.parametrize("case", [HARDENING, SOFTENING], ids=["hardening", "softening"])
def test_stable_amplitudes_agree_with_long_simulations_at_five_frequencies(case) -> None:
    _check_stable_amplitudes(case, (0.6, 0.9, 1.1, 1.3, 1.8))


def _sweep(cubic: float, forcing: float, omegas: np.ndarray, state: list[float],
           settle: int = 60) -> tuple[np.ndarray, list[float]]:
    """Amplitudes of a stepped sweep: each frequency starts where the last one ended
    and runs ``settle`` periods (DOP853, rtol 1e-9); the amplitude is |first harmonic|
    over the last period."""
    out = []
    for w in omegas:
        period = 2 * math.pi / w
        sol = solve_ivp(_duffing(cubic, forcing, w), (0.0, settle * period), state,
                        method="DOP853", rtol=1e-9, atol=1e-11, dense_output=True)
        out.append(abs(_first_harmonic(sol, w, (settle - 1) * period)))
        state = list(sol.y[:, -1])
    return np.array(out), state


def _jump(cubic: float, forcing: float, start: float, stop: float) -> float | None:
    """The frequency where a slow stepped sweep from ``start`` towards ``stop`` jumps:
    1 % steps to bracket the jump, then 0.1 % steps from the last state before it."""
    rest = _sweep(cubic, forcing, np.array([start]), [0.0, 0.0], settle=150)[1]
    coarse = start * (stop / start) ** np.linspace(0, 1, int(abs(math.log(stop / start))
                                                            / 0.01) + 1)
    state = rest
    previous = None
    for w in coarse:
        amp, new_state = _sweep(cubic, forcing, np.array([w]), state)
        if previous is not None and abs(amp[0] - previous) > 0.15 * max(amp[0], previous):
            break
        previous, state, last = amp[0], new_state, w
    else:
        return None
    fine = last * (1 + math.copysign(0.001, stop - start)) ** np.arange(1, 12)
    amps, _ = _sweep(cubic, forcing, fine, state)
    jumps = np.nonzero(np.abs(np.diff(np.concatenate([[previous], amps])))
                       > 0.15 * np.maximum(amps, previous))[0]
    return float(fine[jumps[0]]) if jumps.size else None


@pytest.mark.slow
@pytest.mark.parametrize(("text", "cubic", "forcing"),
                         [HARDENING, ("D(y,2) + 0.1*D(y) + y - 0.3*y**3 = u", -0.3, 0.1)],
                         ids=["hardening", "softening-0.1"])
def test_folds_are_the_jumps_of_slow_sweeps(text: str, cubic: float, forcing: float) -> None:
    """Up- and down-sweeps simulated by DOP853 jump within 0.5 % of the folds."""
    curve = _curve(text, forcing)
    assert len(curve.folds) == 2
    for fold, sweep in zip(curve.folds, curve.fold_sweeps, strict=True):
        start, stop = (fold.omega * 0.85, fold.omega * 1.1) if sweep == "up" else \
            (fold.omega * 1.15, fold.omega * 0.9)
        jump = _jump(cubic, forcing, start, stop)
        assert jump is not None
        assert abs(jump - fold.omega) <= 0.005 * fold.omega, (sweep, jump, fold.omega)


@pytest.mark.slow
def test_the_softening_curve_at_0_05_has_no_fold_and_sweeps_do_not_jump() -> None:
    """y'' + 0.1 y' + y - 0.3 y^3 = 0.05 cos(w t) is single-valued (also by the
    first-order Duffing frequency equation): no fold, and up- and down-sweeps agree."""
    text, cubic, forcing = SOFTENING
    curve = frc(parse_model(text), forcing, (0.5, 1.5))
    assert not curve.folds and all(p.stable for p in curve.points)
    assert _jump(cubic, forcing, 0.8, 1.1) is None
    assert _jump(cubic, forcing, 1.1, 0.8) is None


def test_at_a_fold_the_jacobian_is_singular_and_the_frequency_turns() -> None:
    text, _, forcing = HARDENING
    curve = _curve(text, forcing)
    upper, lower = curve.folds
    assert curve.fold_sweeps == ("up", "down")
    turn = min(range(len(curve.points)), key=lambda i: abs(curve.points[i].omega - upper.omega)
               + abs(curve.points[i].amplitude - upper.amplitude))
    assert max(p.omega for p in curve.points[:turn + 1]) <= upper.omega + 1e-9
    assert min(p.omega for p in curve.points[turn:]) >= lower.omega - 1e-9
    from gfrf.harmonic.balance import Balance

    b = Balance(parse_model(text).terms, curve.harmonics)
    for fold in curve.folds:
        jac = b.evaluate(fold.coefficients, fold.omega, forcing).jac_x
        s = np.linalg.svd(jac, compute_uv=False)
        assert s[-1] < 1e-8 * s[0]
        assert max(abs(r) for r in fold.multipliers) == pytest.approx(1.0, abs=1e-6)


def test_inside_the_series_radius_the_first_harmonic_is_the_volterra_prediction() -> None:
    """At A below r*, predict's first harmonic of order N approaches the balance as N
    grows, within the next order's contribution."""
    model = parse_model(HARDENING[0])
    radius = series_radius(model)[1]
    amp = 0.9 * radius
    for w in (0.5, 0.8, 1.5):
        point = frc(model, (amp / 2, amp), w, vary="amplitude", harmonics=9).points[-1]
        hb = complex(point.coefficients[1], -point.coefficients[2])
        errors = []
        for order in (3, 5, 7):
            volterra = 2 * predict(model, [(amp, w, 0.0)], order).component(w).value
            errors.append(abs(volterra - hb))
        assert errors[0] > errors[1] > errors[2]
        v5 = 2 * predict(model, [(amp, w, 0.0)], 5).component(w).value
        v3 = 2 * predict(model, [(amp, w, 0.0)], 3).component(w).value
        assert errors[1] <= abs(v5 - v3)


def test_the_backbone_is_the_exact_period_of_the_free_oscillator() -> None:
    """Period of y'' + y + 0.3 y^3 = 0 from its turning point Y: 4 int_0^Y dy / sqrt(2(V(Y)
    - V(y))), V = y^2/2 + 0.3 y^4/4."""
    curve = _curve(HARDENING[0], HARDENING[2])
    assert curve.backbone[0] == (pytest.approx(1.0), 0.0, 0.0)
    for omega, _, peak in curve.backbone[10::10]:
        def potential(y: float) -> float:
            return y * y / 2 + 0.3 * y ** 4 / 4

        period = 4 * quad(lambda s, big=peak: big * math.cos(s) / math.sqrt(
            2 * (potential(big) - potential(big * math.sin(s)))), 0, math.pi / 2,
            epsabs=1e-13, epsrel=1e-13)[0]
        assert omega == pytest.approx(2 * math.pi / period, rel=1e-7)


def test_the_result_is_strict_json_with_a_figure_and_markdown() -> None:
    curve = gfrf.frc(gfrf.parse_model(HARDENING[0]), 0.3, (0.5, 2.0))
    data = json.loads(json.dumps(curve.to_dict(), allow_nan=False))
    assert data["harmonics"] == 9 and len(data["points"]) == len(curve.points)
    assert [set(p) for p in data["points"][:1]] == [{"omega", "amplitude", "stable",
                                                     "coefficients"}]
    assert [set(f) for f in data["folds"]] == [{"omega", "amplitude"}] * 2
    assert "fold 1 (up-sweep jump)" in curve._repr_markdown_()
    assert repr(curve).startswith("FrequencyResponseCurve(harmonics=9")
    figure = curve.plot()
    labels = {line.get_label() for line in figure.axes[0].get_lines()}
    assert {"stable", "unstable", "folds", "backbone"} <= labels
    styles = {line.get_label(): line.get_linestyle() for line in figure.axes[0].get_lines()}
    assert styles["stable"] == "-" and styles["unstable"] == "--" and styles["backbone"] == ":"


def test_bad_arguments_are_refused_before_any_work() -> None:
    model = parse_model(HARDENING[0])
    narx = parse_model("y[k] = 0.5*y[k-1] + u[k-1]", sample_time=0.1)
    for kwargs, match in [({"amplitude": 0.3, "omega": (2.0, 1.0)}, "low < high"),
                          ({"amplitude": -0.3, "omega": (1.0, 2.0)}, "amplitude"),
                          ({"amplitude": 0.3, "omega": (0.0, 2.0)}, "positive"),
                          ({"amplitude": 0.3, "omega": (1.0, math.inf)}, "finite"),
                          ({"amplitude": 0.3, "omega": (1.0, 2.0), "vary": "x"}, "vary"),
                          ({"amplitude": 0.3, "omega": (1e-300, 1.0)}, "OMEGA_LIMITS"),
                          ({"amplitude": 0.3, "omega": (1.0, 1e300)}, "OMEGA_LIMITS"),
                          ({"amplitude": 1e300, "omega": (1.0, 2.0)}, "MAX_AMPLITUDE"),
                          ({"amplitude": 0.3, "omega": (1.0, 2.0), "step": 0.0}, "step"),
                          ({"amplitude": 0.3, "omega": (1.0, 2.0), "harmonics": 99,
                            "max_points": 20_000}, "MAX_WORK")]:
        with pytest.raises(ArgumentError, match=match):
            frc(model, **kwargs)
    with pytest.raises(ArgumentError, match="Nyquist"):
        frc(narx, 0.1, (1.0, 40.0))


@pytest.mark.parametrize("omega", [0.6, 1.2])
def test_the_truncation_estimate_is_the_size_of_the_neglected_harmonics(omega: float) -> None:
    """The reported estimate of the harmonics above H is within a factor 2 of their size
    in a 31-harmonic solution, and bounds the error of the first harmonic."""
    model = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    reference = frc(model, (0.5, 1.0), omega, vary="amplitude", harmonics=31).points[-1]
    ref = reference.coefficients
    first = math.hypot(ref[1], ref[2])
    for harmonics in (3, 5):
        point = frc(model, (0.5, 1.0), omega, vary="amplitude",
                    harmonics=harmonics).points[-1]
        neglected = float(np.sqrt(np.sum(ref[2 * harmonics + 1:] ** 2))) / first
        assert neglected / 2 < point.tail < 2 * neglected
        error = math.hypot(point.coefficients[1] - ref[1], point.coefficients[2] - ref[2])
        assert error / first < point.tail


def test_gfrf_frc_takes_a_model_file() -> None:
    """models/duffing.toml is y'' + 0.2 y' + y + 0.5 y^3 = u: at a small forcing the
    first harmonic is H1(jw) A (the cubic's share is of order A^3)."""
    from pathlib import Path

    mf = gfrf.load_model(Path(__file__).resolve().parents[2] / "models" / "duffing.toml")
    point = gfrf.frc(mf, (1e-4, 2e-4), 1.3, vary="amplitude").points[-1]
    h1 = 1 / complex(1 - 1.3 ** 2, 0.2 * 1.3)
    assert complex(point.coefficients[1], -point.coefficients[2]) == pytest.approx(
        2e-4 * h1, rel=1e-6)


def test_a_fold_in_omega_is_a_fold_in_the_forcing_at_that_frequency() -> None:
    """Continued in A at the down-sweep fold frequency, the branch folds at A = 0.3 with
    the same first-harmonic amplitude: the two continuations locate the same point."""
    text, _, forcing = HARDENING
    fold = _curve(text, forcing).folds[1]
    in_a = frc(parse_model(text), (0.05, 0.6), fold.omega, vary="amplitude")
    match = min(in_a.folds, key=lambda f: abs(f.forcing - forcing))
    assert match.forcing == pytest.approx(forcing, rel=1e-8)
    assert match.amplitude == pytest.approx(fold.amplitude, rel=1e-7)


#: A Duffing oscillator sampled at T = 0.1 s (central differences) as a NARX model.
STEP = 0.1
NARX_DUFFING = (f"y[k] = 2*y[k-1] - y[k-2] - {STEP * 0.1}*(y[k-1] - y[k-2]) - {STEP ** 2}*y[k-1]"
                f" - {STEP ** 2 * 0.3}*y[k-1]**3 + {STEP ** 2}*u[k-1]")


def _recursion(omega: float, start: tuple[float, float], samples: int, k0: int = 0
               ) -> np.ndarray:
    """y[k0 - 1], y[k0], ..., of the NARX Duffing under u[k] = 0.3 cos(omega k T)."""
    y = np.empty(samples + 2)
    y[0], y[1] = start
    for j in range(2, samples + 2):
        k = k0 + j - 1
        y[j] = (2 * y[j - 1] - y[j - 2] - STEP * 0.1 * (y[j - 1] - y[j - 2])
                - STEP ** 2 * y[j - 1] - STEP ** 2 * 0.3 * y[j - 1] ** 3
                + STEP ** 2 * 0.3 * math.cos(omega * (k - 1) * STEP))
    return y


def _sampled(point, ks: np.ndarray) -> np.ndarray:
    c = point.coefficients
    h = np.arange(1, (c.size - 1) // 2 + 1)
    phase = point.omega * np.outer(ks * STEP, h)
    return c[0] + np.cos(phase) @ c[1::2] + np.sin(phase) @ c[2::2]


def test_narx_curve_stable_points_attract_and_unstable_points_repel() -> None:
    """The sampled Duffing: a stable point's recursion started 0.1 % off returns to the
    balanced samples (1e-7); an unstable point's, started 1e-9 off, leaves them."""
    curve = frc(parse_model(NARX_DUFFING, sample_time=STEP), 0.3, (0.5, 3.0))
    assert len(curve.folds) == 2 and curve.fold_sweeps == ("up", "down")
    stable = min((p for p in curve.points if p.stable), key=lambda p: abs(p.omega - 1.3))
    start = _sampled(stable, np.array([-1, 0]))
    y = _recursion(stable.omega, (start[0], 1.001 * start[1]), 4000)
    assert np.max(np.abs(y[-100:] - _sampled(stable, np.arange(3901, 4001)))) \
        < 1e-7 * stable.amplitude
    unstable = [p for p in curve.points if not p.stable]
    middle = unstable[len(unstable) // 2]
    start = _sampled(middle, np.array([-1, 0]))
    y = _recursion(middle.omega, (start[0], start[1] + 1e-9), 4000)
    assert np.max(np.abs(y[-100:] - _sampled(middle, np.arange(3901, 4001)))) \
        > 1e-2 * middle.amplitude


def test_narx_folds_are_the_jumps_of_sweeps_of_the_recursion() -> None:
    """Stepped sweeps of the difference equation (0.1 % steps, 100 periods each, from
    the state the last step ended in) jump within 0.5 % of the listed folds."""
    curve = frc(parse_model(NARX_DUFFING, sample_time=STEP), 0.3, (0.5, 3.0))
    for fold, sweep in zip(curve.folds, curve.fold_sweeps, strict=True):
        ratio = 1.001 if sweep == "up" else 1 / 1.001
        omega = fold.omega / ratio ** 15
        state = _sampled(min(curve.points, key=lambda p: abs(p.omega - omega)
                             + (0 if p.stable else 1e9)
                             + abs(p.amplitude - fold.amplitude)), np.array([-1, 0]))
        previous, jump = None, None
        for _ in range(40):
            omega *= ratio
            n = int(100 * 2 * math.pi / omega / STEP)
            y = _recursion(omega, (state[0], state[1]), n)
            amp = np.max(np.abs(y[-int(2 * math.pi / omega / STEP):]))
            if previous is not None and abs(amp - previous) > 0.15 * max(amp, previous):
                jump = omega
                break
            previous, state = amp, (y[-2], y[-1])
        assert jump is not None and abs(jump - fold.omega) <= 0.005 * fold.omega
