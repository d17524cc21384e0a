"""The Python API of the package: ModelFile everywhere, python-control interop,
short reprs, JSON-ready results, ``gfrf.simulate`` that stays a function."""

from __future__ import annotations

import cmath
import json
import math
import os
import pydoc
import subprocess
import sys
from pathlib import Path

import control
import numpy as np
import pytest

import gfrf
from gfrf.model.modelfile import model_from_dict

MODELS = Path(__file__).resolve().parent.parent / "models"
DUFFING = MODELS / "duffing.toml"
NARX = MODELS / "narx_example.toml"


def h1_duffing(w: float) -> complex:
    """H1 of y'' + 0.2 y' + y + 0.5 y^3 = u at s = j w."""
    return 1 / (1 - w * w + 0.2j * w)


def test_simulate_stays_a_function_after_the_simulation_module_is_imported() -> None:
    script = (
        "import gfrf, gfrf.sim.validation\n"  # imports the simulation module first
        "r1 = gfrf.simulate(gfrf.parse_model('D(y) + y = u'), 'step(t)', t_end=1.0)\n"
        "import gfrf.sim.volterra, gfrf.sim.truncation, gfrf.report.analysis\n"
        "r2 = gfrf.simulate(gfrf.parse_model('D(y) + y = u'), 'step(t)', t_end=1.0)\n"
        "print(callable(gfrf.simulate), r1.y[-1] == r2.y[-1])\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["True", "True"]


def test_kernel_takes_a_model_file() -> None:
    mf = gfrf.load_model(DUFFING)
    h3 = complex(gfrf.kernel(mf, 3)(1.0, 1.0, -1.0))
    # symmetric H3(w1, w2, w3) = -0.5 H1(w1) H1(w2) H1(w3) H1(w1 + w2 + w3)
    expected = -0.5 * h1_duffing(1.0) ** 2 * h1_duffing(-1.0) * h1_duffing(1.0)
    assert h3 == pytest.approx(expected, rel=1e-12)
    assert gfrf.kernel is gfrf.kernel  # loaded once


def test_every_plant_function_takes_a_model_file() -> None:
    mf = gfrf.load_model(DUFFING)
    zeta = 0.1  # ||H1|| of a damped oscillator: 1 / (2 zeta sqrt(1 - zeta^2))
    assert gfrf.h1_norm(mf).upper == pytest.approx(1 / (2 * zeta * math.sqrt(1 - zeta ** 2)),
                                                   rel=1e-9)
    assert gfrf.kernel_norm(mf, 1).upper == pytest.approx(gfrf.h1_norm(mf.plant).upper)
    assert gfrf.probe_kernel(mf, [1.0]) == pytest.approx(h1_duffing(1.0), rel=1e-9)
    prediction = gfrf.predict(mf, [(0.001, 1.0, 0.0)], 1)
    assert prediction.component(1.0).amplitude == pytest.approx(0.001 * abs(h1_duffing(1.0)),
                                                                rel=1e-9)
    assert gfrf.verdict(mf, 2).radius == gfrf.verdict(mf.plant, 2).radius


def test_a_path_string_is_the_model_file() -> None:
    assert gfrf.kernel(str(DUFFING), 1)(0.7) == gfrf.kernel(gfrf.load_model(DUFFING), 1)(0.7)
    with pytest.raises(TypeError, match="an equation string"):
        gfrf.kernel(1.5, 1)


def test_linear_part_continuous() -> None:
    h1 = gfrf.linear_part(gfrf.load_model(DUFFING))
    assert isinstance(h1, control.TransferFunction) and h1.dt in (0, None)
    for w in (0.0, 0.7, 1.0, 3.0):
        assert complex(h1(1j * w)) == pytest.approx(h1_duffing(w), rel=1e-12, abs=1e-15)


def test_linear_part_narx_is_discrete_with_dt() -> None:
    mf = gfrf.load_model(NARX)  # y[k] = 0.5 y[k-1] + u[k-1] + ...: H1(q) = q / (1 - 0.5 q)
    h1 = gfrf.linear_part(mf)
    assert h1.dt == pytest.approx(0.1)
    for w in (0.3, 2.0, 10.0):
        q = cmath.exp(-1j * w * 0.1)
        assert complex(h1(1 / q)) == pytest.approx(q / (1 - 0.5 * q), rel=1e-12)
        assert complex(h1(1 / q)) == pytest.approx(complex(gfrf.kernel(mf, 1)(w)), rel=1e-12)


UNSTABLE_PLANT = "D(y,2) + D(y) - y + 0.1*y**3 = u"  # stabilised by u = -3 y


def test_verdict_with_a_python_control_controller() -> None:
    plant = gfrf.parse_model(UNSTABLE_PLANT)
    from_file = gfrf.verdict(model_from_dict({"equation": UNSTABLE_PLANT,
                                              "controller": {"num": [3], "den": [1]}}), 3)
    with_tf = gfrf.verdict(plant, 3, controller=control.tf([3], [1]))
    with_ss = gfrf.verdict(plant, 3, controller=control.ss([], [], [], [[3]]))
    assert with_tf.theorem == with_ss.theorem == from_file.theorem == 2
    assert with_tf.radius == from_file.radius == with_ss.radius
    assert with_tf.verdict == from_file.verdict
    # closed loop s^2 + s + 2: stable; with positive feedback s^2 + s - 4: unstable
    linear = next(c for c in with_tf.conditions if c.name.startswith("linear"))
    assert linear.passed is True
    positive = gfrf.verdict(plant, 3, controller=control.tf([3], [1]), feedback=1)
    assert positive.verdict == "unstable"
    with pytest.raises(gfrf.ArgumentError, match="TransferFunction"):
        gfrf.verdict(plant, controller=[3, 1])


def test_all_lists_the_public_api_and_help_shows_it() -> None:
    for name in gfrf.__all__:
        assert getattr(gfrf, name) is not None
    assert {"simulate", "kernel", "verdict", "linear_part", "load_model", "Verdict",
            "SweepResult", "Margin"} <= set(gfrf.__all__)
    assert set(gfrf.__all__) <= set(dir(gfrf))
    text = pydoc.render_doc(gfrf)
    assert "linear_part" in text and "load_model" in text


def _results() -> dict[str, object]:
    from gfrf.sweep.run import parse_axis, sweep

    mf = gfrf.load_model(DUFFING)
    data = {"equation": "D(y,2) + c*D(y) + y + 0.5*y**3 = u", "parameters": {"c": 0.2}}
    cartpole = gfrf.load_model(MODELS / "cartpole.toml")
    return {
        "verdict": gfrf.verdict(mf, 2),
        "bound": gfrf.h1_norm(mf),
        "closed_loop": gfrf.closed_loop(cartpole),
        "prediction": gfrf.predict(mf, [(0.001, 1.0, 0.0)], 3),
        "simulation": gfrf.simulate(mf, "0.01*sin(t)", t_end=1.0),
        "sweep": sweep(data, [parse_axis("c=0.1:0.4:2")], what="radius"),
    }


def test_results_have_short_reprs_and_json_dicts() -> None:
    results = _results()
    for name, result in results.items():
        text = repr(result)
        assert "\n" not in text and len(text) < 160, (name, text)
        assert text.startswith(type(result).__name__ + "("), text
        json.dumps(result.to_dict())  # complex values and numpy arrays included
    loop = results["closed_loop"]
    poles = json.loads(json.dumps(loop.to_dict()))["poles"]
    expected = sorted(np.roots(loop.characteristic), key=lambda p: (p.real, p.imag))
    got = sorted((complex(p["re"], p["im"]) for p in poles), key=lambda p: (p.real, p.imag))
    assert got == pytest.approx(expected, rel=1e-12)
    damping = json.loads(json.dumps(results["verdict"].to_dict()))
    linear = next(c for c in damping["conditions"] if c["name"].startswith("linear"))
    # the poles of s^2 + 0.2 s + 1: -0.1 +- j sqrt(0.99)
    assert sorted(p["im"] for p in linear["value"]) == pytest.approx(
        [-math.sqrt(0.99), math.sqrt(0.99)], rel=1e-12)


def h1_duffing_s(s: complex) -> complex:
    """H1 of the Duffing oscillator at complex s: 1 / (s^2 + 0.2 s + 1)."""
    return 1 / (s * s + 0.2 * s + 1)


def test_kernel_at_complex_s_matches_the_closed_form() -> None:
    mf = gfrf.load_model(DUFFING)
    h1, h3 = gfrf.kernel(mf, 1), gfrf.kernel(mf, 3)
    points = [-0.5 + 2j, 0.3 - 0.7j, 2.0 + 0j, -0.1 + 0.99j]
    for s in points:
        assert complex(h1.at_s(s)) == pytest.approx(h1_duffing_s(s), rel=1e-13)
    got = h1.at_s(np.array(points))
    assert got.shape == (4,)
    assert got == pytest.approx([h1_duffing_s(s) for s in points], rel=1e-13)
    s1, s2, s3 = 0.2 + 1j, -0.3 + 0.5j, 0.1 - 2j
    expected = -0.5 * h1_duffing_s(s1) * h1_duffing_s(s2) * h1_duffing_s(s3) \
        * h1_duffing_s(s1 + s2 + s3)
    assert complex(h3.at_s(s1, s2, s3)) == pytest.approx(expected, rel=1e-12)
    # on the imaginary axis it is the rad/s evaluation
    assert complex(h3.at_s(1j, 1j, -0.5j)) == complex(h3(1.0, 1.0, -0.5))
    with pytest.raises(gfrf.ArgumentError, match="3 values of s"):
        h3.at_s(1j)
    with pytest.raises(gfrf.ArgumentError, match="finite"):
        h1.at_s(complex("nan"))
    with pytest.raises(gfrf.ArgumentError, match="complex"):
        h1.at_s("1j")


def test_narx_kernel_at_s_uses_the_backward_shift() -> None:
    h1 = gfrf.kernel(gfrf.load_model(NARX), 1)  # H1(q) = q / (1 - 0.5 q), q = exp(-0.1 s)
    for s in (0.3 + 2j, -1.0 + 0.5j):
        q = cmath.exp(-0.1 * s)
        assert complex(h1.at_s(s)) == pytest.approx(q / (1 - 0.5 * q), rel=1e-13)


def test_to_nlsys_matches_simulate_on_the_same_input() -> None:
    mf = gfrf.load_model(DUFFING)
    sys = gfrf.to_nlsys(mf)
    assert isinstance(sys, control.NonlinearIOSystem) and sys.isctime()
    assert (sys.input_labels, sys.output_labels) == (["u"], ["y"])
    t = np.linspace(0.0, 20.0, 40001)  # python-control interpolates u linearly: error ~h^2
    response = control.input_output_response(sys, t, 0.5 * np.sin(1.3 * t), X0=[0.1, 0.0],
                                             solve_ivp_kwargs={"rtol": 1e-10, "atol": 1e-12})
    ours = gfrf.simulate(mf, "0.5*sin(1.3*t)", t_end=20.0, t_eval=t, initial=[0.1, 0.0],
                         rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(ours.y)) > 1.0  # the cubic term matters
    assert np.max(np.abs(response.outputs - ours.y)) < 1e-6


def test_to_nlsys_closed_loop_with_a_dynamic_controller() -> None:
    # y'' + y' - y + 0.1 y^3 = u, u = (4 s + 4)/(s + 2) [r - y]: linear closed loop
    # s^3 + 3 s^2 + 5 s + 2, stable
    mf = model_from_dict({"equation": UNSTABLE_PLANT,
                          "controller": {"num": [4, 4], "den": [1, 2]}})
    sys = gfrf.to_nlsys(mf, closed_loop=True)
    assert (sys.input_labels, sys.output_labels, sys.nstates) == (["r"], ["y", "u"], 3)
    t = np.linspace(0.0, 10.0, 20001)
    response = control.input_output_response(sys, t, 0.2 * np.sin(t),
                                             solve_ivp_kwargs={"rtol": 1e-10, "atol": 1e-12})
    ours = gfrf.simulate(mf, "0.2*sin(t)", t_end=10.0, t_eval=t, closed_loop=True,
                         rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(response.outputs[0] - ours.y)) < 1e-6
    assert np.max(np.abs(response.outputs[1] - ours.u)) < 1e-5
    # the linearisation at 0 is python-control's feedback of the linear parts
    linear = control.feedback(gfrf.linear_part(mf), control.tf([4, 4], [1, 2]))
    assert sorted(np.linalg.eigvals(sys.linearize([0, 0, 0], [0]).A), key=np.imag) == \
        pytest.approx(sorted(linear.poles(), key=np.imag), rel=1e-9)


def test_to_nlsys_narx_is_discrete_and_matches_the_recursion() -> None:
    mf = gfrf.load_model(NARX)
    sys = gfrf.to_nlsys(mf)
    assert sys.dt == pytest.approx(0.1) and sys.nstates == 3  # y[k-1], u[k-1], u[k-2]
    ours = gfrf.simulate(mf, "0.3*sin(2*t) + 0.5", t_end=5.0)
    response = control.input_output_response(sys, ours.t, 0.3 * np.sin(2 * ours.t) + 0.5)
    assert np.max(np.abs(response.outputs - ours.y)) < 1e-12
    # independent recursion y[k] = 0.5 y[k-1] - 0.2 y[k-1]^2 u[k-2] + u[k-1]
    u = 0.3 * np.sin(2 * ours.t) + 0.5
    y = np.zeros_like(u)
    for k in range(1, u.size):
        y[k] = 0.5 * y[k - 1] + u[k - 1] - (0.2 * y[k - 1] ** 2 * u[k - 2] if k >= 2 else 0)
    assert response.outputs == pytest.approx(y, abs=1e-12)
    # in a loop with u = C(r - y) = 0.3 (r - y): outputs y and u, the recursion's own
    loop = model_from_dict({"equation": "y[k] = 0.5*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]",
                            "sample_time": 0.1, "controller": {"num": [0.3], "den": [1]}})
    closed = gfrf.simulate(loop, "0.3*sin(2*t)", t_end=5.0, closed_loop=True)
    response = control.input_output_response(gfrf.to_nlsys(loop, closed_loop=True),
                                             closed.t, 0.3 * np.sin(2 * closed.t))
    r = 0.3 * np.sin(2 * closed.t)
    assert np.max(np.abs(response.outputs[1] - 0.3 * (r - response.outputs[0]))) < 1e-12
    assert np.max(np.abs(response.outputs[0] - closed.y)) < 1e-12


def test_to_nlsys_refusals() -> None:
    with pytest.raises(gfrf.ModelError, match="controller"):
        gfrf.to_nlsys(gfrf.load_model(DUFFING), closed_loop=True)
    with pytest.raises(gfrf.ModelError, match="derivatives"):
        gfrf.to_nlsys(gfrf.parse_model("D(y) + y = D(u) + u"))
    with pytest.raises(TypeError, match="a Model or a ModelFile"):
        gfrf.to_nlsys(1.5)


def test_markdown_of_the_results_shows_the_key_numbers() -> None:
    mf = gfrf.load_model(DUFFING)
    v = gfrf.verdict(mf, 3)
    text = v._repr_markdown_()
    assert text.startswith(f"**Theorem 1: {v.verdict}**")
    assert f"| {v.radius:.6g} |" in text
    zeta = 0.1  # ||H1|| = 1 / (2 zeta sqrt(1 - zeta^2)) = 5.02519 in the norm table
    assert f"| 1 | {1 / (2 * zeta * math.sqrt(1 - zeta ** 2)):.6g} |" in text
    assert "sum \\|\\|H_n\\|\\| r^n" in text  # pipes in cells are escaped
    assert all(line.count("|") >= 3 for line in text.splitlines() if line.startswith("|"))

    run = gfrf.simulate(gfrf.parse_model("D(y) + y = u"), "step(t)", t_end=2.0, rtol=1e-11,
                        atol=1e-13)
    row = run._repr_markdown_().splitlines()[2].split(" | ")
    assert row[0] == "| ok" and row[2] == "2" and row[3] == "2001"
    assert float(row[4]) == pytest.approx(1 - math.exp(-2.0), rel=1e-6)  # max |y| = y(2)
    assert float(row[5]) == pytest.approx(1 - math.exp(-2.0), rel=1e-6)

    from gfrf.stability.criteria import Margin

    margin = Margin(parameter="rho", value=0.25, direction="above", amplitude=1.0, current=0.8,
                    tolerance=1e-6)._repr_markdown_()
    assert "| rho | 0.25 | above the boundary | 0.8 | 1 |" in margin


def test_plots_return_labelled_figures_without_pyplot() -> None:
    from matplotlib.figure import Figure

    mf = gfrf.load_model(DUFFING)
    run = gfrf.simulate(mf, "0.5*sin(1.3*t)", t_end=5.0)
    figure = run.plot()
    assert isinstance(figure, Figure)
    y_axes, u_axes = figure.axes
    assert (y_axes.get_ylabel(), u_axes.get_ylabel(), u_axes.get_xlabel()) == \
        ("output y", "input u", "t (s)")
    assert np.array_equal(y_axes.lines[0].get_ydata(), run.y)
    assert np.allclose(u_axes.lines[0].get_ydata(), 0.5 * np.sin(1.3 * run.t), atol=1e-15)

    v = gfrf.verdict(mf, 5)
    norms, radii = v.plot().axes
    assert norms.get_xlabel() == radii.get_xlabel() == "order n"
    assert norms.get_ylabel() and radii.get_ylabel() == "amplitude r"
    assert [float(y) for y in norms.lines[0].get_ydata()] == \
        [row["majorant"] for row in v.series if row["majorant"] > 0]  # H2, H4 vanish
    levels = {float(line.get_ydata()[0]) for line in radii.lines[1:]}
    assert {v.radius, v.amplitude} <= levels
    script = ("import gfrf\nm = gfrf.parse_model('D(y) + y = u')\n"
              "gfrf.simulate(m, 'step(t)', t_end=1.0).plot()\n"
              "import sys; print('matplotlib.pyplot' in sys.modules)\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=300, env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["False"]


def test_bound_markdown_shows_the_bracket_and_its_proof() -> None:
    import gfrf

    b = gfrf.h1_norm(gfrf.parse_model("D(y,2) + 0.2*D(y) + y = u"))
    text = b._repr_markdown_()
    exact = 1.0 / (0.2 * (1.0 - 0.01) ** 0.5)  # 1/(c sqrt(k - c^2/4))
    assert text.count("\n") == 2 and "interval" in text
    assert f"{exact:.6g}"[:6] in text


def _threshold_routes(plant_text: str, num: list[float], den: list[float], feedback: int = -1,
                      **kwargs: object) -> tuple[gfrf.Threshold, gfrf.Threshold]:
    """The threshold of one loop given by a python-control controller and by a model
    file's [controller] table."""
    plant = gfrf.parse_model(plant_text)
    with_tf = gfrf.threshold(plant, controller=control.tf(num, den), feedback=feedback,
                             **kwargs)
    from_file = gfrf.threshold(model_from_dict(
        {"equation": plant_text,
         "controller": {"num": num, "den": den, "feedback": feedback}}), **kwargs)
    return with_tf, from_file


def test_threshold_with_a_python_control_controller() -> None:
    plant = "D(y) + y + y**3 = u"
    with_tf, from_file = _threshold_routes(plant, [2], [1])
    assert with_tf.to_dict() == from_file.to_dict()
    assert with_tf.lower == math.inf  # y' = -3y - y^3 + 2r: bounded for every bounded r
    # positive feedback: y' = y - y^3 + 2r, the pole s = 1 (python-control's loop agrees)
    pos_tf, pos_file = _threshold_routes(plant, [2], [1], feedback=1)
    loop = control.feedback(control.tf([2], [1]) * control.tf([1], [1, 1]), sign=1)
    assert max(p.real for p in loop.poles()) > 0
    assert pos_tf.to_dict() == pos_file.to_dict()
    assert pos_tf.lower == pos_tf.upper == 0
    with pytest.raises(gfrf.ArgumentError, match="TransferFunction"):
        gfrf.threshold(gfrf.parse_model(plant), controller=[2, 1])


@pytest.mark.slow
def test_threshold_of_a_pi_loop_is_the_model_files() -> None:
    with_tf, from_file = _threshold_routes("D(y) + y - 0.5*y**3 = u", [1, 0.5], [1, 0])
    assert with_tf.to_dict() == from_file.to_dict()
    assert 0 < with_tf.lower < with_tf.upper < math.inf
