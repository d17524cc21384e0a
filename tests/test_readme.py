"""The README's worked examples are real output: every ``$ gfrf ...`` line in a ``text``
block is run and its printed lines compared with the README's, where a line ``...``
stands for any number of lines.  Commands piped to other programs are skipped; those
marked ``# slow`` run in ``make test-slow``.  Each runs in a fresh folder where
``models/`` is the bundled models and every ``toml`` block of the README that starts
with a comment naming a file (``# loop.toml``) is that file, after the commands before
it in the same block that write a file (so ``gfrf certificate check`` reads the file
``--certificate-out`` wrote); nothing lands in the checkout.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from gfrf.cli import main

ROOT = Path(__file__).resolve().parent.parent
BLOCK = re.compile(r"```text\n(.*?)```", re.DOTALL)
#: A ``toml`` block whose first line names the file it is: ``# loop.toml``.
FILE_BLOCK = re.compile(r"```toml\n# ([\w.-]+\.toml)\n(.*?)```", re.DOTALL)


#: Options whose value is a file a command writes.
WRITES = ("--certificate-out", "--out", "--csv", "--plot", "--output")


def _argv(command: str) -> list[str]:
    return shlex.split(command.split("  #")[0])[1:]


def _examples() -> list[tuple[str, list[str], list[str]]]:
    """(command, expected lines, earlier commands of its block that write a file)."""
    examples: list[tuple[str, list[str], list[str]]] = []
    for block in BLOCK.findall((ROOT / "README.md").read_text(encoding="utf-8")):
        writers: list[str] = []
        for line in block.splitlines():
            if line.startswith("$ gfrf "):
                examples.append((line[2:], [], list(writers)))
                if any(option in _argv(line[2:]) for option in WRITES):
                    writers.append(line[2:])
            elif examples and line.strip():
                examples[-1][1].append(line)
    return [example for example in examples if "|" not in example[0]]


def _params() -> list:
    """The examples as pytest parameters, those marked ``# slow`` with the slow mark."""
    return [pytest.param(*example, id=example[0],
                         marks=[pytest.mark.slow] if "# slow" in example[0] else [])
            for example in _examples()]


def _matches(expected: list[str], actual: list[str]) -> bool:
    """Line-by-line equality, a ``...`` line matching any run of lines."""
    if not expected:
        return not actual
    if expected[0].strip() == "...":
        return any(_matches(expected[1:], actual[i:]) for i in range(len(actual) + 1))
    return bool(actual) and expected[0].rstrip() == actual[0].rstrip() \
        and _matches(expected[1:], actual[1:])


def _run(argv: list[str]) -> None:
    try:
        main(argv)
    except SystemExit:
        pass


@pytest.mark.parametrize(("command", "expected", "before"), _params())
def test_readme_example_is_real_output(command: str, expected: list[str], before: list[str],
                                       monkeypatch, tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "models").symlink_to(ROOT / "models")
    for name, text in FILE_BLOCK.findall((ROOT / "README.md").read_text(encoding="utf-8")):
        (tmp_path / name).write_text(text, encoding="utf-8")
    for argv in (*map(_argv, before), _argv(command)):  # the folders the examples write to
        for option, value in zip(argv, argv[1:], strict=False):
            if option in WRITES and not Path(value).is_absolute():
                (tmp_path / value).parent.mkdir(parents=True, exist_ok=True)
    monkeypatch.chdir(tmp_path)
    for earlier in before:
        _run(_argv(earlier))
    capsys.readouterr()
    _run(_argv(command))
    actual = [line for line in capsys.readouterr().out.splitlines() if line.strip()]
    assert _matches(expected, actual), "\n".join(["README:", *expected, "actual:", *actual])
