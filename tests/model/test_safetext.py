"""Text a model carries is data on a terminal and in a report."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import pytest

from gfrf.cli import main
from gfrf.errors import ModelError
from gfrf.model.modelfile import load_model
from gfrf.model.safetext import markdown_text, printable

UNSTABLE = "D(y,2) - 0.2*D(y) + y + 0.5*y**3 = u"
SPOOF = "x\u001b[2K\r\nverdict: stable\n\u001b]0;owned\u0007\u202eevil\u001b[8m"


def run(capsys: pytest.CaptureFixture, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _model(tmp_path: Path, name: str, **extra: str) -> Path:
    path = tmp_path / "m.toml"
    lines = [f"name = {json.dumps(name)}", f"equation = {json.dumps(UNSTABLE)}"]
    lines += [f"{k} = {json.dumps(v)}" for k, v in extra.items()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _clean(text: str) -> None:
    assert "\x1b" not in text and "\r" not in text and "\x07" not in text
    assert "\u202e" not in text
    assert not any(line.startswith("verdict: stable") for line in text.splitlines())


@pytest.mark.parametrize("command", [["verdict"], ["show"],
                                     ["simulate", "--input", "0.1*sin(t)", "--t-end", "1"]])
def test_a_model_name_cannot_spoof_a_verdict(tmp_path: Path, capsys: pytest.CaptureFixture,
                                             command: list[str]) -> None:
    path = _model(tmp_path, SPOOF, description="line one\n\u001b[31mred", source="\u009b2J")
    code, out, err = run(capsys, command[0], str(path), *command[1:])
    _clean(out)
    _clean(err)
    assert "x\\x1b[2K\\r\\nverdict: stable" in out  # shown, escaped
    if command == ["verdict"]:
        assert code == 1 and "unstable" in out


def test_json_keeps_the_text_as_data(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = _model(tmp_path, SPOOF)
    code, out, _ = run(capsys, "verdict", str(path), "--json")
    assert "\x1b" not in out  # json.dumps escapes it
    assert json.loads(out)["model"] == SPOOF


def test_error_and_warning_lines_escape_user_text(tmp_path: Path,
                                                  capsys: pytest.CaptureFixture) -> None:
    code, out, err = run(capsys, "verdict", str(tmp_path / "no\u001b]0;t\u0007such\n.toml"))
    assert code == 2 and err.count("\n") == 1
    _clean(err)


def test_printable_and_markdown_text() -> None:
    assert printable("a\u001b[2Kb\u009b\u2066c\u2028") == "a\\x1b[2Kb\\x9b\\u2066c\\u2028"
    assert printable("é ü 漢字 Ω") == "é ü 漢字 Ω"  # printable text is untouched
    md = markdown_text("<script>alert(2)</script>\n# heading [x](javascript:alert(3))")
    assert "<" not in md and "\n" not in md and "](" not in md
    assert md.startswith("&lt;script&gt;") and "\\# heading" in md


def test_reports_escape_user_text(tmp_path: Path) -> None:
    from gfrf.report._format import header
    from gfrf.report.model_facts import compute
    from gfrf.report.model_page import _model_section

    path = _model(tmp_path, "<img src=x onerror=alert(1)>\n# Injected",
                  description="<script>alert(2)</script>", source="[x](javascript:alert(3))")
    path.write_text(path.read_text(encoding="utf-8").replace(
        UNSTABLE, "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"), encoding="utf-8")
    facts = compute(str(path), tmp_path / "report", True)
    text = "\n".join(_model_section(facts))
    assert "<script" not in text and "](javascript" not in text
    assert "&lt;script&gt;" in text
    # the page's title is the escaped name (model_page.render: header(markdown_text(name)))
    title = header(markdown_text(facts.name), ["a", "b", "c"], "x")
    assert "\n# Injected" not in title and "<img" not in title


# --- §9: special files as model paths ------------------------------------------------------

def test_a_directory_is_not_a_model_file(tmp_path: Path) -> None:
    with pytest.raises(ModelError, match="not a regular file"):
        load_model(tmp_path)


def test_a_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    fifo = tmp_path / "m.toml"
    os.mkfifo(fifo)
    result: list[BaseException | None] = []

    def load() -> None:
        try:
            load_model(fifo)
        except BaseException as exc:
            result.append(exc)
        else:
            result.append(None)

    thread = threading.Thread(target=load, daemon=True)
    thread.start()
    thread.join(10)
    if thread.is_alive():  # unblock the old code's open() so that the thread ends
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        thread.join(10)
        pytest.fail("loading a FIFO blocked")
    assert isinstance(result[0], ModelError) and "not a regular file" in str(result[0])


def test_a_link_to_a_device_is_refused(tmp_path: Path) -> None:
    link = tmp_path / "m.toml"
    link.symlink_to("/dev/zero")
    with pytest.raises(ModelError, match="not a regular file"):
        load_model(link)


def test_a_utf8_bom_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbfequation = \"D(y) + y = u\"\n")
    assert load_model(path).plant.text.strip() == "D(y) + y = u"
