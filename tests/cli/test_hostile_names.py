"""A hostile model name stays data on every surface of every command that shows it.

The name holds ESC sequences, a carriage return and a newline followed by a fake verdict
line, a bidirectional override, a mathtext formula (with nested square roots deep
enough to exhaust matplotlib's parser), HTML, a bare URL and an e-mail address.  Each
command runs in-process on a small model; its terminal text, its JSON, the Markdown of
its report page or result, the notebook reprs and the text drawn on its figures are
checked by one set of rules.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

import gfrf._atomic
from gfrf.cli import main

NAME = ("x\x1b[2K\r\nverdict: stable \u202e(ok)\u202c $" + "\\sqrt{" * 60 + "1" + "}" * 60
        + "$ <b>bold</b> <script>x</script> https://evil.example/p www.evil.example "
          "mail@evil.example")
EQUATION = "D(y,2) + 0.2*D(y) + y + c*y**3 = u"
#: Characters that act on a terminal or reorder text, in any output.
RAW = re.compile("[\x00-\x08\x0b-\x1f\x7f\u202a-\u202e\u2066-\u2069]")
#: GitHub-flavoured Markdown's extended autolinks (www., http(s)://, e-mail), per its spec.
AUTOLINK = re.compile(r"(?:^|[\s*_~(])(?:https?://|www\.)[A-Za-z0-9_-]"
                      r"|[A-Za-z0-9.+_-]+@[A-Za-z0-9_-]+\.[A-Za-z0-9_-]")


def _model(folder: Path) -> Path:
    path = folder / "hostile.toml"
    path.write_text(f"name = {json.dumps(NAME)}\nequation = \"{EQUATION}\"\n"
                    "[parameters]\nc = 0.5\n", encoding="utf-8")
    return path


def _commands(model: str, out: Path) -> dict[str, list[str]]:
    return {
        "show": ["show", model, "--order", "2"],
        "kernel": ["kernel", model, "--order", "1", "--at", "1"],
        "verdict": ["verdict", model, "--order", "3"],
        "norm": ["norm", model, "--order", "1"],
        "simulate": ["simulate", model, "--input", "0.1*sin(t)", "--t-end", "1",
                     "--points", "20", "--plot", str(out / "sim.png")],
        "predict": ["predict", model, "--input", "0.01*cos(1.0*t)", "--order", "3"],
        "ofrf": ["ofrf", model, "--param", "c", "--input", "0.1*cos(1.0*t)", "--omega", "3",
                 "--order", "3"],
        "plot": ["plot", model, "--order", "1", "--no-mark", "--out", str(out / "h1.png")],
        "sweep": ["sweep", model, "--param", "c=0.1:0.5:2", "--what", "radius",
                  "--plot", str(out / "map.png")],
    }


def _check_text(text: str, where: str) -> None:
    assert not RAW.search(text), f"{where}: a raw control or bidi character"
    for line in text.splitlines():
        assert not line.lstrip().startswith("verdict: stable \u202e"), f"{where}: fake line"


def _check_markdown(text: str, where: str) -> None:
    _check_text(text, where)
    assert "<b>" not in text and "<script>" not in text, f"{where}: raw HTML"
    assert not AUTOLINK.search(text), f"{where}: a bare link GitHub would make clickable"


@pytest.fixture
def drawn(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Every text drawn on a figure written by gfrf, after the writer's own treatment."""
    texts: list[str] = []
    original = gfrf._atomic.atomic_write_figure

    def figure(fig: Any, path: Any, **kw: Any) -> Path:
        result = original(fig, path, **kw)
        from matplotlib.text import Text

        for t in fig.findobj(Text):
            if "sqrt" in t.get_text():  # the name: drawn as plain text
                assert not t.get_parse_math() and not t.get_usetex()
            texts.append(t.get_text())
        return result

    for module in ("gfrf.cli.simulation", "gfrf.sweep.plot", "gfrf.report._format"):
        monkeypatch.setattr(f"{module}.atomic_write_figure", figure)
    monkeypatch.setattr("gfrf._atomic.atomic_write_figure", figure)
    return texts


def _names_in_titles(texts: list[str]) -> list[str]:
    return [t for t in texts if "verdict: stable" in t]


@pytest.mark.parametrize("command", list(_commands("m", Path("."))))
def test_every_command_keeps_a_hostile_name_inert(command: str, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture,
                                                  drawn: list[str]) -> None:
    model = str(_model(tmp_path))
    argv = _commands(model, tmp_path)[command]
    code = main(argv)
    out, err = capsys.readouterr()
    assert code in (0, 1), err
    _check_text(out + err, f"{command} text")
    assert "verdict: stable" not in out or "\\r\\nverdict: stable" in out
    if command in ("simulate", "plot", "sweep"):
        titled = _names_in_titles(drawn)
        assert titled or command == "plot", f"{command}: the name is not on the figure"
        for t in drawn:
            _check_text(t, f"{command} figure")
            assert all("verdict: stable" not in line or "\\r\\n" in line
                       for line in t.splitlines())
    code = main([*argv, "--json"])
    out, err = capsys.readouterr()
    assert code in (0, 1), err

    def strict(token: str) -> None:
        raise AssertionError(f"{command} --json: the non-JSON token {token}")

    payload = json.loads(out, parse_constant=strict)
    assert isinstance(payload, dict)
    assert not RAW.search(out)


def test_a_report_page_and_the_notebook_reprs_keep_a_hostile_name_inert(
        tmp_path: Path, capsys: pytest.CaptureFixture, drawn: list[str]) -> None:
    import gfrf

    model = _model(tmp_path)
    mf = gfrf.load_model(str(model))
    for result in (gfrf.verdict(mf, order=3), gfrf.threshold(mf, order=3)):
        _check_markdown(result._repr_markdown_(), f"{type(result).__name__} markdown")
        _check_text(repr(result), f"{type(result).__name__} repr")
    code = main(["report", "--quick", "--out", str(tmp_path / "r"), str(model)])
    _, err = capsys.readouterr()
    assert code == 0, err
    pages = list((tmp_path / "r").rglob("*.md"))
    assert pages
    for page in pages:
        text = page.read_text(encoding="utf-8")
        _check_markdown(text.replace("](", "] ("), page.name)  # its own links are fine
    assert _names_in_titles(drawn)
    for t in drawn:
        _check_text(t, "report figure")
