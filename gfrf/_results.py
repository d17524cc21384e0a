"""Shared helpers of the result objects: a short ``repr`` and JSON-ready values.

>>> from dataclasses import dataclass
>>> @dataclass
... class R:
...     radius: float
...     poles: tuple
...     def __repr__(self) -> str:
...         return short_repr(self, "radius")
>>> R(0.125, (-1 + 2j,))
R(radius=0.125)
>>> plain({"poles": (complex(-1, 2),)})
{'poles': [{'re': -1.0, 'im': 2.0}]}
"""

from __future__ import annotations

from typing import Any

__all__ = ["short_repr", "plain"]


def _value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str) and len(value) > 40:
        return repr(value[:37] + "...")
    return repr(value)


def short_repr(obj: object, *fields: str, **extra: Any) -> str:
    """``Type(field=value, ...)`` of the named attributes and ``extra`` values (floats 6 digits)."""
    items = [(name, getattr(obj, name)) for name in fields] + list(extra.items())
    return f"{type(obj).__name__}({', '.join(f'{k}={_value(v)}' for k, v in items)})"


def plain(value: Any) -> Any:
    """``value`` with complex numbers as ``{"re", "im"}``, numpy values as Python ones and
    tuples as lists, so that :func:`json.dumps` accepts it (floats are kept, infinities
    included)."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return plain(value.tolist())
    if isinstance(value, complex):
        return {"re": float(value.real), "im": float(value.imag)}
    return value
