"""One rule for a model argument (gfrf.model.modelfile.resolve_model), used by the CLI and
by every public function that takes a model."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import MODELS, run

import gfrf
from gfrf.errors import ModelError
from gfrf.model.modelfile import looks_like_path, resolve_model

DUFFING = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


@pytest.mark.parametrize("text", ["models/duffing.tom", "duffing", "models/duffing",
                                  "no-such_file.txt", "~/model.toml"])
def test_a_missing_file_name_is_no_such_file_not_a_parse_error(text: str, tmp_path: Path,
                                                                monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ModelError, match="does not exist"):
        resolve_model(text)


@pytest.mark.parametrize("text", ["models/duffing.tom", "duffing"])
def test_the_cli_says_no_such_file(text: str, capsys, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, "verdict", text)
    assert code == 2 and "does not exist (no such file)" in err and err.count("\n") == 1


@pytest.mark.parametrize(("text", "path"), [(DUFFING, False), ("D(y) + y", False),
                                            ("y[k] = 0.5*y[k-1] + u[k-1]", False),
                                            ("a.toml", True), ("x", True)])
def test_equations_and_paths_are_told_apart(text: str, path: bool) -> None:
    assert looks_like_path(text) is path


def test_every_form_gives_the_same_model() -> None:
    file = MODELS / "duffing.toml"
    loaded = gfrf.load_model(file)
    forms = [str(file), file, loaded, loaded.plant, DUFFING]
    equations = {resolve_model(form).plant.equation() for form in forms}
    assert len(equations) == 1


@pytest.mark.parametrize("call", [
    lambda m: gfrf.verdict(m, 2, with_norms=False), lambda m: gfrf.kernel(m, 1),
    lambda m: gfrf.linear_part(m), lambda m: gfrf.threshold(m, order=2),
    lambda m: gfrf.to_nlsys(m), lambda m: gfrf.simulate(m, "0", t_end=0.1),
    lambda m: gfrf.ofrf(m, "c", "0.01*cos(t)", 1.0, 2)],
    ids=["verdict", "kernel", "linear_part", "threshold", "to_nlsys", "simulate", "ofrf"])
@pytest.mark.parametrize("bad", [3, 2.5, None, b"D(y) + y = u", ["models/duffing.toml"]],
                         ids=["int", "float", "None", "bytes", "list"])
def test_anything_else_is_a_type_error_naming_the_accepted_types(call, bad) -> None:
    with pytest.raises(TypeError, match="a model file path .*an equation string"):
        call(bad)


def test_the_public_functions_take_what_load_model_returns(tmp_path: Path) -> None:
    """The README's promise: a ModelFile works wherever a model is taken (ofrf included,
    with the parameter kept as a symbol)."""
    path = tmp_path / "damper.toml"
    path.write_text('equation = "D(y,2) + 0.1*D(y) + y + c*D(y)**3 = u"\n'
                    "[parameters]\nc = 3.2\n")
    loaded = gfrf.load_model(path)
    by_file = gfrf.ofrf(loaded, "c", "0.005*cos(0.995*t)", 0.995, 3)
    by_path = gfrf.ofrf(str(path), "c", "0.005*cos(0.995*t)", 0.995, 3)
    assert by_file(3.2) == by_path(3.2)
    # an equation string: H1 of 1/(s^2 + 0.2 s + 1) at w = 1 is -5j (closed form)
    assert gfrf.kernel(DUFFING, 1)(1.0) == pytest.approx(-5j, rel=1e-12)
    assert gfrf.threshold(DUFFING, order=3).lower == float("inf")


def test_a_bundled_model_is_found_by_its_name_from_any_directory(tmp_path, monkeypatch):
    from gfrf._data import MODELS_DIR

    monkeypatch.chdir(tmp_path)
    for name in ("duffing.toml", "models/duffing.toml"):
        assert resolve_model(name).path == str(MODELS_DIR / "duffing.toml")
    with pytest.raises(ModelError, match="no such file"):
        resolve_model("duffing.tom")
    with pytest.raises(ModelError, match=r"\); the bundled model is models/duffing.toml"):
        resolve_model("duffing")
    (tmp_path / "duffing.toml").write_text(
        'name = "mine"\nequation = "D(y) + y + y**3 = u"\n')  # a file that exists wins
    assert resolve_model("duffing.toml").name == "mine"
