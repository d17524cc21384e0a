"""The result objects' ``to_dict`` drops no field silently.

Every dataclass of the package with a ``to_dict`` (the source of ``--json``) either
derives it from the fields (:class:`gfrf._results.Result`: a field is left out only when
it is in the class's ``_exclude`` and its docstring says why), or, where the hand-written
view is a documented contract not yet derived, reads every field (``self.<field>`` in the
method's source) but those listed in :data:`DROPPED` with the reason.  Every result
class (a :class:`~gfrf._results.Result` or a dataclass named ``*Result``) is frozen and
built by keyword.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import pkgutil
import textwrap

import pytest

import gfrf
from gfrf._results import Result

#: Fields that a hand-written ``to_dict`` leaves out, and why (class -> field -> reason).
DROPPED: dict[str, dict[str, str]] = {
    "gfrf.identify.nonparametric.Estimate": {
        "model_values": "an identified model's kernels at the lines: the plot's data"},
    "gfrf.sim.integrate.SimulationResult": {
        "states": "the state trajectory: array data (y and u are summarised)"},
    "gfrf.twosided.threshold.Threshold": {
        "sos": "the SOS search object behind the sos certificate, which is in the lower side",
        "certificate_file": "the headline certificate's file, written by --certificate-out",
        "d_witness": "an improper loop's escaping plant-input signal: given as the witness"},
}


def _result_classes() -> list[type]:
    found = []
    for info in pkgutil.walk_packages(gfrf.__path__, "gfrf."):
        module = importlib.import_module(info.name)
        for obj in vars(module).values():
            if (inspect.isclass(obj) and obj.__module__ == info.name
                    and dataclasses.is_dataclass(obj) and hasattr(obj, "to_dict")):
                found.append(obj)
    return found


CLASSES = _result_classes()


def _name(cls: type) -> str:
    return f"{cls.__module__}.{cls.__qualname__}"


def _read(method: object) -> set[str]:
    """Attribute names read as ``self.<name>`` in ``method``'s source, and its string
    constants (the keys it writes; all fields when it calls ``asdict(self)``)."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(method)))  # type: ignore[arg-type]
    names = {node.attr for node in ast.walk(tree) if isinstance(node, ast.Attribute)
             and isinstance(node.value, ast.Name) and node.value.id == "self"}
    names |= {node.value for node in ast.walk(tree)  # keys, getattr(self, "name")
              if isinstance(node, ast.Constant) and isinstance(node.value, str)}
    if any(isinstance(node, ast.Call) and getattr(node.func, "id", "") == "asdict"
           for node in ast.walk(tree)):
        names.add("*")
    return names


def test_the_field_check_finds_the_result_classes() -> None:
    names = {_name(c) for c in CLASSES}
    assert {"gfrf.stability.verdicts.Verdict", "gfrf.bounds.norms.Bound",
            "gfrf.periodic.compare.TransitionResult"} <= names
    assert set(DROPPED) <= names
    derived = {_name(c) for c in CLASSES if issubclass(c, Result) and "to_dict" not in vars(c)}
    assert not set(DROPPED) & derived  # a derived to_dict states its exclusions itself


@pytest.mark.parametrize("cls", CLASSES, ids=_name)
def test_every_field_is_in_to_dict_or_excluded_for_a_stated_reason(cls: type) -> None:
    names = [f.name for f in dataclasses.fields(cls)]
    if issubclass(cls, Result) and "to_dict" not in vars(cls):
        assert set(cls._exclude) <= set(names)
        assert set(cls._keys) <= set(names)
        doc = cls.__doc__ or ""
        for name in cls._exclude:
            assert name in doc and "to_dict" in doc, f"{_name(cls)}: say why {name} is left out"
        return
    method = next(vars(k)["to_dict"] for k in cls.__mro__ if "to_dict" in vars(k))
    read = _read(method)
    dropped = DROPPED.get(_name(cls), {})
    assert set(dropped) <= set(names)
    assert not set(dropped) & read, f"{_name(cls)}: DROPPED lists a field to_dict reads"
    missing = [n for n in names if n not in read and n not in dropped and "*" not in read]
    assert not missing, f"{_name(cls)}.to_dict drops {missing}"


def test_derived_to_dict_keeps_contract_names_and_order() -> None:
    @dataclasses.dataclass(frozen=True, kw_only=True, repr=False)
    class Bracket(Result):
        """A bracket (``scratch`` is working data, left out)."""

        _exclude = ("scratch",)
        _keys = {"low": "lower"}
        _order = ("gap", "lower")
        low: float
        upper: float
        where: complex = 0j
        scratch: tuple[float, ...] = ()
        _memo: dict[str, float] = dataclasses.field(default_factory=dict)

        def _computed(self) -> dict[str, object]:
            return {"gap": self.upper - self.low, "where": [self.where.real, self.where.imag]}

    d = Bracket(low=1.0, upper=3.0, where=2 + 1j, scratch=(4.0,), _memo={"x": 1.0}).to_dict()
    assert list(d) == ["gap", "lower", "upper", "where"]
    assert d == {"gap": 2.0, "lower": 1.0, "upper": 3.0, "where": [2.0, 1.0]}


def _result_dataclasses() -> list[type]:
    """Every dataclass of the package that is a :class:`Result` or is named ``*Result``."""
    found = []
    for info in pkgutil.walk_packages(gfrf.__path__, "gfrf."):
        for obj in vars(importlib.import_module(info.name)).values():
            if (inspect.isclass(obj) and obj.__module__ == info.name
                    and dataclasses.is_dataclass(obj)
                    and (issubclass(obj, Result) or obj.__name__.endswith("Result"))):
                found.append(obj)
    return found


@pytest.mark.parametrize("cls", _result_dataclasses(), ids=_name)
def test_result_classes_are_frozen_and_built_by_keyword(cls: type) -> None:
    assert cls.__dataclass_params__.frozen, f"{_name(cls)} is not frozen"  # type: ignore[attr-defined]
    positional = [f.name for f in dataclasses.fields(cls) if f.init and not f.kw_only]
    assert not positional, f"{_name(cls)}: fields passed by position {positional}"
