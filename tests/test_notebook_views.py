"""Notebook habits: short reprs, LaTeX and Markdown views, VolterraPrediction.plot,
one signature per function (gfrf.verdict's norms=, gfrf.predict's input text)."""

from __future__ import annotations

import numpy as np
import pytest

import gfrf

DUFFING = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


def test_short_reprs() -> None:
    m = gfrf.parse_model(DUFFING)
    mf = gfrf.load_model("models/cartpole.toml")
    objects = [m, mf, gfrf.kernel(m, 3), gfrf.closed_loop(mf),
               gfrf.predict(m, "0.02*cos(1.0*t)", 3)]
    for obj in objects:
        text = repr(obj)
        assert len(text) < 300 and "Term(" not in text, text
    assert repr(m) == "Model('0.5*y**3 + y + 0.2*D(y) + D(y,2) - u = 0')"
    assert repr(gfrf.kernel(m, 1)) == f"Kernel(H1 of {DUFFING!r})"


def test_latex_of_models_and_kernels() -> None:
    m = gfrf.parse_model(DUFFING)
    assert m._repr_latex_() == r"$- u + 0.5 y^{3} + y + 0.2 \dot{y} + \ddot{y} = 0$"
    narx = gfrf.load_model("models/narx_example.toml")
    assert "y_{k-1}^{2}" in narx._repr_latex_()
    assert gfrf.kernel(m, 1)._repr_latex_().startswith("$H_{1} = ")


def test_prediction_markdown_and_plot_against_simulation() -> None:
    m = gfrf.parse_model(DUFFING)
    p = gfrf.predict(m, "0.02*sin(1.0*t)", 3)
    table = p._repr_markdown_()
    assert "| 1 | 0.100018 |" in table and "| 3 | 1.55812e-05 |" in table
    r = gfrf.simulate(m, "0.02*sin(1.0*t)", t_end=300, n_out=6001)
    fig = p.plot(r)
    ax = fig.axes[0]
    spectrum = ax.lines[0]   # the simulated FFT, drawn first
    w, a = spectrum.get_xdata(), spectrum.get_ydata()
    # the simulated spectrum peaks at the predicted fundamental, with its amplitude
    # (Hann window, 20 whole periods: the bin sits on omega = 1)
    assert w[np.argmax(a)] == pytest.approx(1.0, abs=0.05)
    assert a.max() == pytest.approx(p.component(1.0).amplitude, rel=0.02)


def test_ofrf_markdown_and_plot() -> None:
    data = {"equation": "D(y,2) + 0.2*D(y) + y + c*y**3 = u", "parameters": {"c": 0.5}}
    o = gfrf.ofrf(data, "c", "0.02*cos(t)", 1.0, 3)
    assert "| 0 | 0 | -0.1 |" in o._repr_markdown_()
    assert len(o.plot().axes[0].lines) == 2


def test_one_signature_per_function() -> None:
    m = gfrf.parse_model(DUFFING)
    # gfrf.verdict takes norms= as gfrf.stability.criteria.verdict does
    v = gfrf.verdict(m, order=3, norms="none")
    assert v.norms == ()
    # gfrf.predict takes the text of gfrf predict --input
    text = gfrf.predict(m, "0.02*sin(1.0*t)", 3)
    tones = gfrf.predict(m, [(0.02, 1.0, -np.pi / 2)], 3)
    assert [c.value for c in text.components] == pytest.approx(
        [c.value for c in tones.components], rel=1e-12)
    with pytest.raises(gfrf.ArgumentError, match="not a sum of sinusoids"):
        gfrf.predict(m, "step(t)", 3)
