"""Kernel pictures: ``Kernel.plot()`` and ``gfrf plot`` (gfrf.kernels.plot, gfrf.cli.plot)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gfrf.cli import main
from gfrf.kernels.plot import frequency_grid
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model

ROOT = Path(__file__).resolve().parents[2]
#: Every bundled GFRF model (parametric_pendulum.toml is the periodic-pendulum format).
MODELS = sorted(p.name for p in (ROOT / "models").glob("*.toml")
                if p.name != "parametric_pendulum.toml")
PNG = b"\x89PNG\r\n\x1a\n"


def _plot(tmp_path: Path, model: str, order: int, *extra: str) -> Path:
    out = tmp_path / f"{Path(model).stem}-{order}.png"
    assert main(["plot", model, "--order", str(order), "--out", str(out), *extra]) == 0
    data = out.read_bytes()
    assert data.startswith(PNG) and len(data) > 5000
    return out


@pytest.mark.parametrize("order", [1, 2, 3])
def test_plot_writes_png_narx_example(order: int, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    _plot(tmp_path, "models/narx_example.toml", order, "--no-mark")


def test_plot_marks_the_norm_sup(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(ROOT)
    out = tmp_path / "h3.svg"
    assert main(["plot", "models/duffing.toml", "--order", "3", "--out", str(out),
                 "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    # closed form: sup |H3| of the Duffing = 0.5 |H1|^4 at the peak of |H1|,
    # |H1|max = 1/(0.2 sqrt(1 - 0.01)), at (-w, w, w) (up to the symmetry)
    h1max = 1 / (0.2 * np.sqrt(1 - 0.01))
    assert payload["sup"] == pytest.approx(0.5 * h1max ** 4, rel=1e-6)
    assert sorted(abs(w) for w in payload["sup_at"]) == pytest.approx([np.sqrt(0.98)] * 3,
                                                                      rel=1e-5)
    assert out.read_text().lstrip().startswith("<?xml")


@pytest.mark.slow
@pytest.mark.parametrize("name", MODELS)
def test_plot_every_bundled_model(name: str, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    for order in (1, 2, 3):
        _plot(tmp_path, f"models/{name}", order)


def test_grid_resolves_a_narrow_resonance() -> None:
    """Damping 0.002 on a range of 10 rad/s: the peak is 2e-4 of the range wide, and the
    Bode grid still finds |H1| = 1/(0.002 sqrt(1 - 1e-6)) to 1e-4."""
    k = kernel(parse_model("D(y,2) + 0.002*D(y) + y = u"), 1)
    w = frequency_grid(k, 10.0, symmetric=False)
    peak = 1 / (0.002 * np.sqrt(1 - 1e-6))
    assert np.max(np.abs(k(w))) == pytest.approx(peak, rel=1e-4)
    # an H2 map grid reaches the ridge w1 + w2 = w0 at its crest (|A(j w0)| = damping)
    k2 = kernel(parse_model("D(y,2) + 0.002*D(y) + y + 0.3*y**2 = u"), 2)
    g = frequency_grid(k2, 10.0, [0.5])
    sums = np.add.outer(g, g)
    assert np.min(np.abs(sums - np.sqrt(1 - 2e-6))) < 2e-4


def test_kernel_plot_api_and_zero_kernel() -> None:
    m = parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
    fig = kernel(m, 1).plot(mark=(0.99,))
    assert len(fig.axes) == 2 and fig.axes[0].get_ylabel() == "magnitude (dB)"
    fig = kernel(m, 2).plot()   # H2 = 0: a figure that says so
    assert "H2 = 0 identically" in fig.axes[0].texts[0].get_text()
    fig = kernel(m, 3).plot(what="phase", fixed=(0.5,))
    assert "omega3 = 0.5" in fig.axes[1].get_title()
    assert repr(kernel(m, 3)) == "Kernel(H3 of 'D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u')"
    assert kernel(m, 1)._repr_latex_().startswith("$H_{1} = ")


@pytest.mark.parametrize(("argv", "message"), [
    (["plot", "models/duffing.toml", "--order", "2", "--out", "x.txt"], "unsupported figure"),
    (["plot", "models/duffing.toml", "--order", "0", "--out", "x.png"], "between 1 and"),
    (["plot", "models/duffing.toml", "--order", "1", "--range", "-1", "--out", "x.png"],
     "range"),
])
def test_plot_bad_input_exit_2(argv: list[str], message: str, capsys, monkeypatch,
                               tmp_path: Path) -> None:
    monkeypatch.chdir(ROOT)
    argv = [a if a not in ("x.txt", "x.png") else str(tmp_path / a) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("gfrf: error:") and message in err
