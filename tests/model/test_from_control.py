"""Models from python-control objects: gfrf.from_tf, gfrf.from_nlsys, parse_model's type check.

References: python-control's own evaluation of the transfer function (H1), closed forms
of H3 for a cubic feedback and a cubic series nonlinearity, and python-control's
``input_output_response`` of the original nlsys against gfrf.simulate of the recovered
model.
"""

from __future__ import annotations

import math
import re

import control
import numpy as np
import pytest

import gfrf
from gfrf.errors import ArgumentError, ModelError
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import ModelTypeError

W = np.array([0.3, 1.1, 2.7])


def test_from_tf_feedback_kernels() -> None:
    G = control.tf([2, 1], [1, 0.4, 1.5])
    m = gfrf.from_tf(G, {3: 0.5})
    g = np.array([complex(G(1j * w)) for w in W])
    # y = G (u - 0.5 y^3): H1 = G, H3 = -0.5 G(s1+s2+s3) G(s1) G(s2) G(s3)
    assert np.allclose(kernel(m, 1)(W), g, rtol=1e-12)
    w1, w2, w3 = 0.3, 1.1, -2.7
    gsum = complex(G(1j * (w1 + w2 + w3)))
    expected = -0.5 * gsum * np.prod([complex(G(1j * w)) for w in (w1, w2, w3)])
    assert complex(kernel(m, 3)(w1, w2, w3)) == pytest.approx(expected, rel=1e-12)


def test_from_tf_series_kernels() -> None:
    G = control.tf([1], [1, 0.2, 1])
    m = gfrf.from_tf(G, {1: 1.0, 3: 0.1}, connection="series")
    w = (0.4, -1.3, 0.9)
    # y = G (u + 0.1 u^3): H3 = 0.1 G(s1 + s2 + s3), H2 = 0
    assert complex(kernel(m, 3)(*w)) == pytest.approx(0.1 * complex(G(1j * sum(w))), rel=1e-12)
    assert kernel(m, 2).is_zero


def test_from_tf_discrete() -> None:
    G = control.tf([0.5], [1, -0.5], dt=0.1)
    m = gfrf.from_tf(G, {2: 0.2})
    assert m.sample_time == 0.1
    g = np.array([complex(G(np.exp(1j * w * 0.1))) for w in W])
    assert np.allclose(kernel(m, 1)(W), g, rtol=1e-12)


@pytest.mark.parametrize(("G", "nonlinearity", "message"), [
    (control.tf([1, 0, 0], [1, 1]), {3: 1}, "improper"),
    (control.tf([1], [1, 1]), {0: 1, 3: 1}, "constant term"),
    (control.tf([1], [1, 1]), "y**3", "nonlinearity must be"),
    (control.tf([1], [1, 1], True), {3: 1}, "dt=True"),
    ("not a tf", {3: 1}, "SISO control.TransferFunction"),
])
def test_from_tf_refusals(G, nonlinearity, message: str) -> None:
    with pytest.raises(ArgumentError, match=message):
        gfrf.from_tf(G, nonlinearity)


def test_from_nlsys_round_trip_and_simulation() -> None:
    def update(t, x, u, params):
        # an equilibrium at x = (1, 0), u = 2: the deviations obey
        # y'' + 0.3 y' + 4 y + 3 y^2 + y^3 - 0.5 y u = u
        y = x[0] - 1
        return [x[1], -0.3 * x[1] - 4 * y - 3 * y ** 2 - y ** 3 + 0.5 * y * (u[0] - 2)
                + (u[0] - 2)]

    sys = control.nlsys(update, lambda t, x, u, params: x[0], inputs=1, outputs=1, states=2)
    m = gfrf.from_nlsys(sys, [1.0, 0.0], 2.0, order=3)
    expected = gfrf.parse_model("D(y,2) + 0.3*D(y) + 4*y + 3*y**2 + y**3 - 0.5*y*u = u")
    assert sorted(m.terms) == sorted(expected.terms)
    # free response from x = (1.4, 0) at the constant input u0 = 2 (python-control
    # interpolates an input linearly between samples: a constant one is exact)
    t = np.linspace(0, 10, 201)
    ref = control.input_output_response(sys, t, np.full_like(t, 2.0), X0=[1.4, 0.0],
                                        solve_ivp_kwargs={"rtol": 1e-11, "atol": 1e-12})
    ours = gfrf.simulate(m, None, t_end=10, t_eval=t, initial=[0.4, 0.0], rtol=1e-11,
                         atol=1e-12)
    assert np.max(np.abs(ours.y + 1 - ref.outputs)) < 1e-8


def test_from_nlsys_of_to_nlsys() -> None:
    m = gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 - 0.1*y*D(y)*u = u")
    back = gfrf.from_nlsys(gfrf.to_nlsys(m), [0, 0], 0, order=3)
    assert sorted(back.terms) == sorted(m.terms)


def _sys(update, output=lambda t, x, u, p: x[0], states=2):
    return control.nlsys(update, output, inputs=1, outputs=1, states=states)


@pytest.mark.parametrize(("sys", "x0", "message"), [
    (_sys(lambda t, x, u, p: [x[1], -np.sin(x[0]) - 0.1 * x[1] + u[0]]), [0, 0],
     "not a polynomial of total degree 3"),
    (_sys(lambda t, x, u, p: [x[1], -x[0] - 0.1 * x[1] + u[0]]), [1, 0], "not an equilibrium"),
    (_sys(lambda t, x, u, p: [x[1] + x[0], -x[0] + u[0]]), [0, 0], "chain of integrators"),
    (_sys(lambda t, x, u, p: [x[1], -x[0] + u[0]], lambda t, x, u, p: x[1]), [0, 0],
     "output y = x[0]"),
    (_sys(lambda t, x, u, p: [x[1], -x[0] + u[0] / 0]), [0, 0], "not finite"),
    (_sys(lambda t, x, u, p: [x[1], math.log(-1.0)]), [0, 0], "failed at x = [0.0, 0.0]"),
    (control.tf([1], [1, 1]), [0], "for a transfer function use gfrf.from_tf"),
])
def test_from_nlsys_refusals(sys, x0, message: str) -> None:
    with np.errstate(all="ignore"), pytest.raises(ModelError, match=re.escape(message)):
        gfrf.from_nlsys(sys, x0, 0.0, order=3)


def test_parse_model_type_check_points_to_the_constructors() -> None:
    with pytest.raises(ModelTypeError, match="gfrf.from_tf.*gfrf.from_nlsys"):
        gfrf.parse_model(control.tf([1], [1, 1]))
    with pytest.raises(TypeError, match="takes the equation as a str"):
        gfrf.parse_model(3)

