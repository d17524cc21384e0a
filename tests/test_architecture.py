"""The folder tree reads like the architecture: no import cycles between gfrf modules
(lazy imports inside functions included), and no module shadows a public function."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import gfrf

PACKAGE = Path(gfrf.__file__).resolve().parent


def _imports() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for path in PACKAGE.rglob("*.py"):
        name = ".".join(("gfrf", *path.relative_to(PACKAGE).with_suffix("").parts))
        name = name.removesuffix(".__init__")
        deps: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gfrf"):
                deps.add(node.module or "")
            elif isinstance(node, ast.Import):
                deps.update(a.name for a in node.names if a.name.startswith("gfrf"))
        graph[name] = deps - {name}
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of the graph (depth-first search), or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for dep in sorted(graph.get(node, ())):
            if dep not in graph:
                continue
            if state.get(dep) == 1:
                return [*stack[stack.index(dep):], dep]
            if dep not in state and (found := visit(dep)):
                return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_no_import_cycles() -> None:
    graph = _imports()
    # The package's lazy re-export table is not a dependency of its submodules.
    graph["gfrf"] = set()
    assert _cycle(graph) is None, " -> ".join(_cycle(graph) or [])


def test_the_cycle_finder_finds_cycles() -> None:
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


def test_no_module_shadows_a_public_name() -> None:
    modules = {path.stem for path in PACKAGE.glob("*.py")} | \
        {path.name for path in PACKAGE.iterdir() if path.is_dir()}
    assert not modules & set(gfrf.__all__)


# --- the tree is the architecture ----------------------------------------------------------

#: Most modules directly under gfrf/ (the public face and the small shared helpers).
MAX_TOP_LEVEL_MODULES = 8
#: Longest module, in lines: a file to read in one sitting.
MAX_MODULE_LINES = 600


def _subpackages() -> set[str]:
    return {f"gfrf.{p.name}" for p in PACKAGE.iterdir()
            if p.is_dir() and (p / "__init__.py").is_file()}


def _contracts() -> list[dict]:
    import tomllib

    with open(PACKAGE.parent / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["tool"]["importlinter"]["contracts"]


def test_few_modules_at_the_top_and_none_too_long() -> None:
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= MAX_TOP_LEVEL_MODULES, top
    long = {str(p.relative_to(PACKAGE)): n for p in PACKAGE.rglob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES}
    assert not long, long


def test_every_subpackage_sits_in_the_layers_contract() -> None:
    """A new subpackage cannot escape the layers: it must be placed in the contract."""
    layers = next(c for c in _contracts() if c["type"] == "layers")["layers"]
    placed = {name.strip() for layer in layers for name in layer.replace(":", "|").split("|")}
    assert placed == _subpackages()


def test_the_layers_run_model_to_cli_in_pipeline_order() -> None:
    layers = next(c for c in _contracts() if c["type"] == "layers")["layers"]
    order = [layer.split("|")[0].strip() for layer in layers]
    pipeline = ["gfrf.cli", "gfrf.report", "gfrf.papers", "gfrf.sim", "gfrf.stability",
                "gfrf.bounds", "gfrf.kernels", "gfrf.model"]
    assert order == pipeline


def test_each_subpackage_says_what_it_owns_and_may_import() -> None:
    for name in sorted(_subpackages()):
        doc = importlib.import_module(name).__doc__ or ""
        assert len(doc.splitlines()) >= 3, name
        assert "import" in doc.lower(), f"{name}: its docstring does not say what it may import"


def test_the_layer_checker_catches_an_import_up_the_layers(tmp_path: Path) -> None:
    """The contract is live: a kernels module importing the stability stage is refused."""
    import shutil
    import subprocess
    import sys

    copy = tmp_path / "gfrf"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(PACKAGE.parent / "pyproject.toml", tmp_path / "pyproject.toml")
    (copy / "kernels" / "upward.py").write_text("from gfrf.stability import loops\n")
    linter = Path(sys.executable).parent / "lint-imports"
    env = {"PYTHONPATH": str(tmp_path), "PATH": "/usr/bin:/bin"}
    ok = subprocess.run([str(linter)], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert "BROKEN" in ok.stdout and "gfrf.kernels.upward -> gfrf.stability" in ok.stdout
    assert ok.returncode != 0


#: Most positional arguments a call of a gfrf class may pass (beyond: by keyword).
MAX_POSITIONAL_ARGUMENTS = 6


def _long_positional_calls(source: str, classes: set[str]) -> list[tuple[int, str]]:
    """``(line, class)`` of the calls of ``classes`` with too many positional arguments."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call) and len(node.args) > MAX_POSITIONAL_ARGUMENTS:
            name = getattr(node.func, "id", getattr(node.func, "attr", None))
            if name in classes:
                found.append((node.lineno, name))
    return found


def test_classes_with_many_fields_are_built_by_keyword() -> None:
    sources = {p: p.read_text(encoding="utf-8") for p in PACKAGE.rglob("*.py")}
    classes = {n.name for s in sources.values() for n in ast.walk(ast.parse(s))
               if isinstance(n, ast.ClassDef)}
    long = {f"{p.relative_to(PACKAGE)}:{line}": name for p, s in sources.items()
            for line, name in _long_positional_calls(s, classes)}
    assert not long, long


def test_the_positional_call_finder_finds_one() -> None:
    assert _long_positional_calls("R(1, 2, 3, 4, 5, 6, 7)\nR(1, b=2)", {"R"}) == [(1, "R")]
