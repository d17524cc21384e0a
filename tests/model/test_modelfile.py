"""Tests of gfrf.model.modelfile: the bundled models, the minimal file, and file errors."""

from pathlib import Path

import pytest

from gfrf.errors import ModelError
from gfrf.model.modelfile import load_model

MODELS = Path(__file__).resolve().parents[2] / "models"
GFRF_MODELS = [p for p in sorted(MODELS.glob("*.toml")) if "kind = \"parametric\""
               not in p.read_text()]


@pytest.mark.parametrize("path", GFRF_MODELS, ids=lambda p: p.stem)
def test_every_bundled_model_loads(path):
    mf = load_model(path)
    assert mf.name and mf.plant.terms


def test_pendulum_file_derives_the_polynomial_from_sin():
    mf = load_model(MODELS / "hanging_pendulum.toml")
    coefficients = {(t.y_orders, t.u_orders): t.coefficient for t in mf.plant.terms}
    g, L, rho, m = 9.8, 4.0, 0.8, 1.0
    assert coefficients[((1,), ())] == pytest.approx(rho / (m * L**2))
    assert coefficients[((0,), ())] == pytest.approx(g / L)
    assert coefficients[((0, 0, 0), ())] == pytest.approx(-g / (6 * L))


def test_cartpole_file_holds_plant_physical_equation_and_controller():
    mf = load_model(MODELS / "cartpole.toml")
    assert mf.controller.num == (15.6, 379.3, 0.1331)
    assert mf.controller.den == (1.0,)
    assert mf.controller.feedback == -1
    assert "cos" in str(mf.plant.physical)


def test_one_line_file_is_a_valid_model(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text('equation = "D(y,2) + 2*D(y) + y = u"\n')
    assert load_model(f).plant.degree == 1
    g = tmp_path / "d.toml"
    g.write_text('equation = "y[k] = 0.3*y[k-1] + u[k-1]"\nsample_time = 0.5\n')
    assert load_model(g).plant.sample_time == 0.5


@pytest.mark.parametrize("content, fragment", [
    ('equation = "D(y,2) + y = u"\ncolour = "red"\n', "unknown model file key(s) 'colour'"),
    ('name = "no equation"\n', "missing key 'equation'"),
    ('equation = "D(y,2) + y = u\n', "not valid TOML"),
    ('equation = "D(y,2) + y = u"\n[controller]\nnum = [1]\nequation = "u = y"\n',
     "either num/den"),
    ('equation = "D(y,2) + y = u"\n[controller]\nnum = ["k"]\n', "unknown symbol"),
    ('equation = "D(y,2) + y = u"\n[controller]\nnum = [1]\nfeedback = 2\n', "feedback"),
    ('equation = "D(y,2) + y = u"\n[controller]\nnum = [1]\ngain = 2\n',
     "unknown controller key(s) 'gain'"),
    ('equation = "D(y,2) + a*y = u"\n[parameters]\na = "nan"\n', "not finite"),
    ('kind = "parametric"\nequation = "D(x,2) + (d + e*cos(t))*x = 0"\n', "time-varying"),
])
def test_bad_model_files_name_the_problem(tmp_path, content, fragment):
    f = tmp_path / "bad.toml"
    f.write_text(content)
    with pytest.raises(ModelError) as info:
        load_model(f)
    assert fragment in str(info.value)
    assert str(f) in str(info.value)


def test_missing_file():
    with pytest.raises(ModelError, match="does not exist"):
        load_model("no/such/model.toml")
