"""Every public function documents its parameters, numpydoc style, as its signature has them.

Public: the names in ``__all__`` of every module of the package (functions, classes and
their public methods).  A ``Parameters`` section must name exactly the parameters of the
signature (``self``/``cls`` aside; ``*args``/``**kwargs`` as written).  Functions without
the section are counted against a ceiling that may only go down (python-control's
``docstrings_test.py`` does the same for its API).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from collections.abc import Callable, Iterator

import pytest

import gfrf

#: Public callables with parameters and no Parameters section (may only go down).
UNDOCUMENTED_CEILING = 0

_HEADER = re.compile(r"^\s*Parameters\s*\n\s*-{3,}\s*$", re.MULTILINE)
_SECTION_END = re.compile(r"^\s*(Returns|Yields|Raises|Warns|See Also|Notes|Examples|References|"
                          r"Attributes|Methods|Other Parameters|Receives|Warnings)\s*\n\s*-{3,}",
                          re.MULTILINE)


def _modules() -> Iterator[object]:
    yield gfrf
    for info in pkgutil.walk_packages(gfrf.__path__, "gfrf."):
        if info.name.rsplit(".", 1)[-1].startswith("_dask"):
            continue
        yield importlib.import_module(info.name)


def public_callables() -> dict[str, Callable]:
    """``qualified name -> callable`` of every public function, class and method."""
    found: dict[str, Callable] = {}
    for module in _modules():
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name, None)
            if obj is None or getattr(obj, "__module__", "").split(".")[0] != "gfrf":
                continue
            if inspect.isfunction(obj):
                found[f"{obj.__module__}.{obj.__qualname__}"] = obj
            elif inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if attr.startswith("_") and attr != "__init__":
                        continue
                    func = member.__func__ if isinstance(member, (classmethod, staticmethod)) \
                        else member
                    if inspect.isfunction(func) and func.__doc__:
                        found[f"{obj.__module__}.{obj.__qualname__}.{attr}"] = func
    return found


def documented(doc: str) -> list[str] | None:
    """Parameter names of the numpydoc ``Parameters`` section, None without one."""
    match = _HEADER.search(doc)
    if match is None:
        return None
    body = doc[match.end():]
    end = _SECTION_END.search(body)
    body = body[:end.start()] if end else body
    lines = [line for line in body.splitlines() if line.strip()]
    if not lines:
        return []
    indent = min(len(line) - len(line.lstrip()) for line in lines)
    names: list[str] = []
    for line in lines:
        if len(line) - len(line.lstrip()) == indent:
            head = line.strip().split(" : ")[0].rstrip(":").strip()
            names += [n.strip() for n in head.split(",") if n.strip()]
    return names


def signature_names(func: Callable) -> list[str]:
    params = list(inspect.signature(func).parameters.values())
    out = []
    for p in params:
        if p.name in ("self", "cls"):
            continue
        prefix = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
        out.append(prefix + p.name)
    return out


def _cases() -> list[tuple[str, Callable]]:
    return sorted(public_callables().items())


@pytest.mark.parametrize(("name", "func"), _cases(), ids=[n for n, _ in _cases()])
def test_documented_parameters_match_the_signature(name: str, func: Callable) -> None:
    names = documented(inspect.getdoc(func) or "")
    if names is None:
        return
    expected = signature_names(func)
    plain = [n.lstrip("*") for n in names]
    assert sorted(plain) == sorted(n.lstrip("*") for n in expected), (
        f"{name}: documents {names}, the signature has {expected}")


def test_undocumented_public_parameters_do_not_grow() -> None:
    missing = [name for name, func in _cases()
               if signature_names(func) and documented(inspect.getdoc(func) or "") is None]
    assert len(missing) <= UNDOCUMENTED_CEILING, "\n".join(missing)


def test_the_parser_reads_numpydoc() -> None:
    doc = """Sum.

    Parameters
    ----------
    a, b : float
        Terms, with a continuation line
        : that is not a name.
    *args : int
    **kwargs
        Passed on.

    Returns
    -------
    c : float
    """
    assert documented(inspect.cleandoc(doc)) == ["a", "b", "*args", "**kwargs"]
    assert documented("No sections.") is None
