"""The README's worked examples are real output: every ``$ gfrf ...`` line in a ``text``
block is run and its printed lines compared with the README's, where a line ``...``
stands for any number of lines.  Commands piped to other programs or marked slow
(``# slow``) are skipped.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from gfrf.cli import main

ROOT = Path(__file__).resolve().parent.parent
BLOCK = re.compile(r"```text\n(.*?)```", re.DOTALL)


def _examples() -> list[tuple[str, list[str]]]:
    examples: list[tuple[str, list[str]]] = []
    for block in BLOCK.findall((ROOT / "README.md").read_text(encoding="utf-8")):
        for line in block.splitlines():
            if line.startswith("$ gfrf "):
                examples.append((line[2:], []))
            elif examples and line.strip():
                examples[-1][1].append(line)
    return [(cmd, out) for cmd, out in examples if "|" not in cmd and "# slow" not in cmd]


def _matches(expected: list[str], actual: list[str]) -> bool:
    """Line-by-line equality, a ``...`` line matching any run of lines."""
    if not expected:
        return not actual
    if expected[0].strip() == "...":
        return any(_matches(expected[1:], actual[i:]) for i in range(len(actual) + 1))
    return bool(actual) and expected[0].rstrip() == actual[0].rstrip() \
        and _matches(expected[1:], actual[1:])


@pytest.mark.parametrize(("command", "expected"), _examples(),
                         ids=[c for c, _ in _examples()])
def test_readme_example_is_real_output(command: str, expected: list[str], monkeypatch,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(ROOT)
    argv = shlex.split(command.split("  #")[0])[1:]
    try:
        main(argv)
    except SystemExit:
        pass
    actual = [line for line in capsys.readouterr().out.splitlines() if line.strip()]
    assert _matches(expected, actual), "\n".join(["README:", *expected, "actual:", *actual])
