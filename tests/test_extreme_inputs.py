"""No false sentence at the edges (huge coefficients, poles, pole clusters,
mixed timebases, exit codes).  Every expected value comes from a closed form, mpmath or
an exact scaling law, never from the code's own output."""

from __future__ import annotations

import json
import math

import pytest
from conftest import run

ZETA = 0.1
PEAK = 1.0 / (2 * ZETA * math.sqrt(1 - ZETA ** 2))  # ||H1|| of 1/(s^2 + 0.2 s + 1)



def _cubic_radius(c3: float) -> float:
    """Closed form of the pure-cubic majorant X = v r + v c3 X^3: r* = 2 / (3 v sqrt(3 v c3))."""
    return 2.0 / (3.0 * PEAK * math.sqrt(3.0 * PEAK * c3))


@pytest.mark.parametrize("s", [1e-150, 1e-20, 1e-3, 0.3, 3.7, 1e5, 1e9, 1e14,
                               math.sqrt(5e27 / 0.5), 1e30, 1e100, 1e150])
def test_radius_scales_exactly(s: float) -> None:
    """r*(c3 s^2) = r*(c3) / s, at the interval level, for every magnitude."""
    from gfrf.bounds.majorant import majorant, plant_radius
    from gfrf.model.equation import parse_model

    c3 = 0.5 * s * s
    rad = plant_radius(majorant(parse_model(f"D(y,2) + 0.2*D(y) + y + {c3!r}*y**3 = u")))
    assert rad.proof == "interval"
    # r* sits 1e-9 relative below the branch point (certify's margin)
    assert rad.value * s == pytest.approx(_cubic_radius(0.5), rel=3e-9)
    assert rad.certified_below <= _cubic_radius(c3)
    assert rad.certified_below == pytest.approx(_cubic_radius(c3), rel=3e-9)


def test_radius_power_of_four_bitwise() -> None:
    """A coefficient scaled by 4^k gives r* exactly 2^-k times the old one (the scaled
    coefficient written exactly: 0.5 times powers 4**15 and 4**(k mod 15))."""
    from gfrf.bounds.majorant import majorant, plant_radius
    from gfrf.model.equation import parse_model

    base = plant_radius(majorant(parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")))
    for k in (-60, -7, 3, 45, 90):
        op = "*" if k > 0 else "/"
        c3 = "0.5" + f"{op}4**15" * (abs(k) // 15) + f"{op}4**{abs(k) % 15}"
        rad = plant_radius(majorant(parse_model(f"D(y,2) + 0.2*D(y) + y + {c3}*y**3 = u")))
        assert rad.value == math.ldexp(base.value, -k)
        assert rad.certified_below == math.ldexp(base.certified_below, -k)


def test_verdict_huge_cubic_is_stable(capsys: pytest.CaptureFixture[str]) -> None:
    """the true radius 4.832e-16 > r = 1e-16."""
    code, out, _ = run(capsys, "verdict", "D(y,2) + 0.2*D(y) + y + 5e27*y**3 = u",
                       "--amplitude", "1e-16", "--order", "3", "--json")
    data = json.loads(out)
    assert code == 0 and data["verdict"] == "stable"
    assert data["radius"] == pytest.approx(_cubic_radius(5e27), rel=3e-9)
    assert data["radius_proof"] == "interval"


def test_kernel_far_out_prints_zero(capsys: pytest.CaptureFixture[str]) -> None:
    """|H3| at 1e308 underflows (mpmath: H3 ~ 1/w^6); printed 0, never nan."""
    import mpmath

    code, out, _ = run(capsys, "kernel", "models/hanging_pendulum.toml", "--order", "3",
                       "--at", "1e308,1e308,-1e308", "--json")
    data = json.loads(out)
    assert code == 0 and data["abs"] == 0.0 and data["re"] == 0.0 and data["im"] == 0.0
    assert mpmath.mpf(data["abs_decimal"]) < mpmath.mpf("1e-2000")
    assert "nan" not in out.lower()


@pytest.mark.parametrize(("order", "at", "block"), [(3, "1,1,-1", [1]), (1, "1", [1]),
                                                    (3, "0.25,0.25,0.5", [1, 2, 3]),
                                                    (2, "-1,3", [1])])
def test_kernel_at_pole_names_it(capsys: pytest.CaptureFixture[str], order: int, at: str,
                                 block: list[int]) -> None:
    """at a pole of 1/A (A = s^2 + 1: s = +-j) the command says so, exit 1."""
    code, out, _ = run(capsys, "kernel", "D(y,2) + y + 0.5*y**3 + 0.1*y**2 = u",
                       "--order", str(order), "--at", at, "--json")
    data = json.loads(out)
    assert code == 1
    assert data["pole"]["block"] == block and abs(data["pole"]["omega"]) == 1.0
    assert "nan" not in out.lower() and "null" not in out and "inf" not in out.lower()
    code, out, _ = run(capsys, "kernel", "D(y,2) + y + 0.5*y**3 + 0.1*y**2 = u",
                       "--order", str(order), "--at", at)
    assert code == 1 and "pole" in out and "nan" not in out.lower()


def _cluster(zeta: float, k: int) -> list[float]:
    """Float coefficients of (s^2 + 2 zeta s + 1)^k, highest power first."""
    import numpy as np

    den = np.array([1.0])
    for _ in range(k):
        den = np.polymul(den, [1.0, 2 * zeta, 1.0])
    return [float(c) for c in den]


@pytest.mark.parametrize("k", [2, 3])
@pytest.mark.parametrize("zeta", [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8])
def test_float_level_lower_end_is_evaluated(zeta: float, k: int) -> None:
    """on pole clusters the float path may refuse its upper end, but its lower
    end is a value of |H1| at an evaluated point: <= the 60-digit sup, never inf."""
    from mp_reference import mp_sup

    from gfrf.bounds.rational import rational_sup

    den = _cluster(zeta, k)
    floated = rational_sup([1.0], den, proof="float")
    proven = rational_sup([1.0], den, proof="interval")
    if "pole on the imaginary axis" in proven.reason:  # the rounded floats of k = 3,
        assert floated.lower == math.inf == proven.lower  # zeta = 1e-8: a root at s = j
        return
    ref = mp_sup([1.0], den)
    assert proven.lower <= ref <= proven.upper
    assert math.isfinite(floated.lower) and math.isfinite(floated.omega)
    assert floated.lower <= ref * (1 + 1e-15)
    assert floated.lower > 0.0
    if k == 2:  # a double cluster stays resolvable: the witness sits at its peak
        assert floated.lower >= 0.99 * float(ref)
    if math.isfinite(floated.upper):
        assert abs(floated.upper / float(ref) - 1) <= 1e-8


def test_norm_float_cluster_json(capsys: pytest.CaptureFixture[str]) -> None:
    """lower end 250000.25 (mpmath), never inf, no nan witness."""
    from mp_reference import mp_sup

    model = ("D(y,4) + 0.004*D(y,3) + 2.000004*D(y,2) + 0.004*D(y) + 1.0*y "
             "+ 0.1*y**3 = u")
    code, out, _ = run(capsys, "norm", model, "--order", "1", "--proof", "float", "--json")
    bound = json.loads(out)
    ref = float(mp_sup([1.0], [1.0, 0.004, 2.000004, 0.004, 1.0]))
    assert bound["lower"] <= ref and bound["lower"] == pytest.approx(ref, rel=1e-6)
    assert "nan" not in out.lower()
    code, out, _ = run(capsys, "verdict", model, "--order", "3", "--proof", "float",
                       "--amplitude", "1e-8")
    assert "diverges" not in out and "certifies no input amplitude r > 0" in out


@pytest.mark.parametrize("coefficient", ["tan(pi/2)", "tan(-3*pi/2)", "tan(2*atan(1))",
                                         "1/cos(pi/2)", "1/sin(pi)", "1/tan(pi)"])
def test_coefficient_at_a_pole_is_an_error(coefficient: str) -> None:
    """sympy's exact value is zoo (tan(pi/2)) or the divisor is exactly 0."""
    import sympy as sp

    from gfrf.errors import ModelError
    from gfrf.model.equation import parse_model

    with pytest.raises(ModelError):
        parse_model(f"D(y,2) + D(y) + y + {coefficient}*y**3 = u")
    with pytest.raises(ModelError):
        parse_model(f"D(y,2) + D(y) + y + y**3/({coefficient.replace('1/', '')}) = u")
    assert sp.tan(sp.pi / 2) == sp.zoo and sp.cos(sp.pi / 2) == 0  # the exact facts


@pytest.mark.parametrize(("coefficient", "value"), [("tan(pi/4)", 1.0), ("cos(pi/3)", 0.5),
                                                    ("tan(1.5707963267948966)",
                                                     1.633123935319537e16)])
def test_coefficient_near_a_pole_is_a_number(coefficient: str, value: float) -> None:
    """A float argument is not pi/2: tan(fl(pi/2)) = 1/cos(fl(pi/2)) is a finite number."""
    from gfrf.model.equation import parse_model

    model = parse_model(f"D(y,2) + D(y) + y + {coefficient}*y**3 = u")
    (term,) = model.nonlinear_terms
    assert term.coefficient == pytest.approx(value, rel=1e-12)


def test_parameter_at_a_pole_is_an_error(tmp_path: object, capsys: pytest.CaptureFixture[str]
                                         ) -> None:
    """In a model file: a parameter tan(pi/2) is refused, exit 2."""
    from pathlib import Path

    path = Path(str(tmp_path)) / "m.toml"
    path.write_text('equation = "D(y,2) + c*D(y) + y + 0.5*y**3 = u"\n'
                    '[parameters]\nc = "tan(pi/2)"\n')
    code, _, err = run(capsys, "show", str(path))
    assert code == 2 and "pole" in err


@pytest.mark.parametrize("dt", [0.1, True])
def test_api_refuses_a_discrete_controller_on_a_continuous_plant(dt: object) -> None:
    """python-control itself refuses to connect these; so does gfrf."""
    import control

    import gfrf
    from gfrf.errors import ArgumentError

    plant = gfrf.load_model("models/duffing.toml")
    controller = control.tf([1], [1, -0.5], dt)
    with pytest.raises(ValueError):  # the independent reference
        control.feedback(gfrf.linear_part(plant), controller)
    with pytest.raises(ArgumentError, match=r"dt = (0\.1|True).*dt = 0"):
        gfrf.verdict(plant, order=2, controller=controller)


@pytest.mark.parametrize(("top", "controller", "words"), [
    ("", "sample_time = 0.1\n", ["discrete-time (dt = 0.1 s)", "continuous-time (dt = 0)"]),
    ("sample_time = 0.1\n", "sample_time = 0\n",
     ["continuous-time (dt = 0)", "discrete-time (dt = 0.1 s)"]),
    ("sample_time = 0.1\n", "sample_time = 0.2\n", ["dt = 0.2 s", "dt = 0.1 s"])])
def test_model_file_refuses_mixed_timebases(tmp_path: object, capsys: pytest.CaptureFixture[str],
                                            top: str, controller: str, words: list[str]) -> None:
    """In model files: a [controller] sample_time that differs from the plant's
    (``sample_time = 0`` marks a continuous controller; without it, the plant's timebase)."""
    from pathlib import Path

    equation = ("y[k] - 0.5*y[k-1] + 0.1*y[k-1]**3 = u[k-1]" if top else
                "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    path = Path(str(tmp_path)) / "m.toml"
    path.write_text(f'equation = "{equation}"\n{top}[controller]\nnum = [0.1]\n'
                    f'den = [1, -0.5]\n{controller}')
    code, _, err = run(capsys, "verdict", str(path), "--order", "2")
    assert code == 2 and "mixed timebases" in err
    assert all(w in err for w in words)


def test_sweep_with_no_successful_point_exits_1(tmp_path: object,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    """every grid point fails (log of a negative parameter): exit 1, the cause named
    (not 'invalid model' for every failure)."""
    from pathlib import Path

    path = Path(str(tmp_path)) / "m.toml"
    path.write_text('equation = "D(y,2) + 0.2*D(y) + y + log(c)*y**3 = u"\n'
                    '[parameters]\nc = 2\n')
    code, out, err = run(capsys, "sweep", str(path), "--param", "c=-2:-1:3")
    assert code == 1
    assert "no grid point succeeded" in err and "not a real number" in err
    assert "3 of 3 point(s) failed" in err and "failed" not in out  # said once
    code, out, err = run(capsys, "sweep", str(path), "--param", "c=1:2:2")
    assert code == 0 and "failed" not in out


def test_norm_of_unstable_linear_part_says_l_infinity(capsys: pytest.CaptureFixture[str]
                                                       ) -> None:
    """A = s^2 - 0.2 s + 1 is unstable; the bracket is of the L-infinity norm."""
    code, out, _ = run(capsys, "norm", "D(y,2) - 0.2*D(y) + y + 0.5*y**3 = u", "--order", "3")
    bracket = next(line for line in out.splitlines() if "||H3|| in" in line)
    assert code == 1 and "L-infinity" in bracket and "not H-infinity" in bracket
    code, out, _ = run(capsys, "norm", "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u", "--order", "3")
    assert code == 0 and "L-infinity" not in out


def _loop_file(tmp_path: object, k: float) -> str:
    from pathlib import Path

    path = Path(str(tmp_path)) / f"loop_{k:g}.toml"
    path.write_text('name = "Duffing in a loop"\n'
                    'equation = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"\n'
                    f"[controller]\nnum = [{k!r}]\nden = [1]\n")
    return str(path)


@pytest.mark.parametrize("k", [0.001, 0.3, 4.0])
def test_theorem2_prints_the_loop_and_its_upper_bound(tmp_path: object, k: float,
                                                      capsys: pytest.CaptureFixture[str]
                                                      ) -> None:
    """the loop u = C(r - y) in the header; the loop's proven upper radius in units
    of r is the fold of (1 + k) y + y^3/2 = k r: |r| = 2 sqrt(2) (1 + k)^1.5 / (3 sqrt(3) k),
    and r* (units of r) lies below it; the plant's 0.544 is labelled the plant's."""
    if k == 0.001:  # the text once
        code, out, _ = run(capsys, "verdict", _loop_file(tmp_path, k), "--order", "3")
        assert "loop: u = C(r - y), C(s) = 0.001" in out.splitlines()[1]
        assert "loop radius_upper" in out and "(units of the reference r)" in out
    fold = 2 * math.sqrt(2) * (1 + k) ** 1.5 / (3 * math.sqrt(3) * k)
    code, out, _ = run(capsys, "verdict", _loop_file(tmp_path, k), "--order", "3", "--json")
    data = json.loads(out)
    assert data["loop_radius_upper"] == pytest.approx(fold, rel=1e-9)
    assert data["loop"].startswith("u = C(r - y)")
    assert data["radius"] <= data["loop_radius_upper"]
    assert "plant's own" in data["estimate_of"] and "units of u" in data["estimate_of"]
    assert data["radius_upper"] == pytest.approx(2 * math.sqrt(2) / (3 * math.sqrt(3)),
                                                 rel=1e-9)  # the plant's: k -> u


def test_theorem2_plot_log_axis_labelled_legend_off_data(tmp_path: object) -> None:
    """Verdict.plot for Theorem 2: log amplitude axis, every line labelled with
    its units, legends outside the axes."""
    import gfrf

    v = gfrf.verdict(gfrf.load_model(_loop_file(tmp_path, 0.001)), order=3)
    figure = v.plot()
    figure.canvas.draw()
    left, right = figure.axes[:2]
    assert right.get_yscale() == "log"
    labels = [line.get_label() for line in right.get_lines()]
    assert all(not label.startswith("_") for label in labels)
    assert any("plant true radius" in x and "units of u" in x for x in labels)
    assert any("loop r*" in x and "units of r" in x for x in labels)
    for ax in (left, right):
        legend = ax.get_legend().get_window_extent()
        assert legend.x0 >= ax.get_window_extent().x1  # beside the axes, not on the data


def test_resonance_is_the_exact_peak_of_h1() -> None:
    """eq (2), rho = 0.8: A = s^2 + 0.05 s + 2.45 peaks at sqrt(2.45 - 0.05^2 / 2)
    = 1.564848 rad/s, not at the grid point 1.563148 the reports called the resonance."""
    import gfrf
    from gfrf.sim.validation import resonance, resonance_label

    plant = gfrf.load_model("models/hanging_pendulum_eq2.toml").plant
    exact = math.sqrt(2.45 - 0.05 ** 2 / 2)
    assert resonance(plant) == pytest.approx(exact, rel=1e-12)
    assert abs(resonance(plant) - 1.563148) > 1e-3
    assert "exact peak" in resonance_label(plant)
    # no finite peak (|H1| maximal at w = 0): the grid value, named as such
    narx = gfrf.load_model("models/narx_example.toml").plant
    assert "grid" in resonance_label(narx)


@pytest.mark.parametrize("s", [1e-20, 1e14, 1e100])
def test_upper_and_estimate_scale_too(s: float, capsys: pytest.CaptureFixture[str]) -> None:
    """radius_upper (the static fold of y + c3 y^3 = u: |u| = (2/3) / sqrt(3 c3))
    and the estimate follow r*(c3 s^2) = r*(c3) / s; no overflow warning."""
    import warnings

    c3 = 0.5 * s * s
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, out, _ = run(capsys, "verdict", f"D(y,2) + 0.2*D(y) + y + {c3!r}*y**3 = u",
                           "--amplitude", f"{0.01 / s!r}", "--order", "3", "--json")
    data = json.loads(out)
    assert code == 0 and data["verdict"] == "stable"
    assert data["radius_upper"] == pytest.approx((2 / 3) / math.sqrt(3 * c3), rel=1e-12)
    assert data["radius_upper"] >= (2 / 3) / math.sqrt(3 * c3) * (1 - 1e-15)
    _, base, _ = run(capsys, "verdict", "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u",
                     "--amplitude", "0.01", "--order", "3", "--json")
    assert data["radius_estimate"] * s == pytest.approx(json.loads(base)["radius_estimate"],
                                                        rel=1e-6)


def _loop_closed_form(lam: float, c3: float) -> float:
    """r* of the loop majorant X = v lam E + g X^3, E = rho r + rho g X^3 (g = v c3, v = ||H1||,
    rho = sup|A / (A + lam)| by mpmath): with a = v lam rho / (1 + v lam rho) the fold of
    r = (X (1 - a) - g X^3) / a is at X^2 = (1 - a) / (3 g), r* = 2 (1 - a) X / (3 a)."""
    import mpmath as mp

    with mp.workdps(30):
        def minus_s(w: mp.mpf) -> mp.mpf:
            a_jw = (1 - w ** 2) + 0.2j * w
            return -abs(a_jw / (a_jw + lam))

        w0 = min((mp.mpf(i) / 1000 for i in range(500, 1500)), key=minus_s)
        rho = -minus_s(mp.findroot(lambda w: mp.diff(minus_s, w), w0))
        g = PEAK * c3
        a = PEAK * lam * rho / (1 + PEAK * lam * rho)
        x = mp.sqrt((1 - a) / (3 * g))
        return float(2 * (1 - a) * x / (3 * a))


def test_loop_radius_scales_exactly(tmp_path: object) -> None:
    """For Theorem 2: under y -> s y (u, r alike) the loop's r* is r*(c3) / s too
    (the 5e27 loop gave 1.29e-14, 37x below 4.81e-13, before the loop was rescaled)."""
    from pathlib import Path

    import gfrf

    def loop_radius(c3: float) -> float:
        path = Path(str(tmp_path)) / "loop.toml"
        path.write_text(f'equation = "D(y,2) + 0.2*D(y) + y + {c3!r}*y**3 = u"\n'
                        "[controller]\nnum = [0.001]\nden = [1]\n")
        return gfrf.verdict(gfrf.load_model(str(path)), order=2, amplitude=1e-30,
                            with_norms=False).radius

    base = loop_radius(0.5)
    assert base == pytest.approx(_loop_closed_form(0.001, 0.5), rel=3e-9)
    for s in (1e-10, 1e14, 1e100):
        assert loop_radius(0.5 * s * s) * s == pytest.approx(base, rel=3e-9)
