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

import json
import math
from dataclasses import dataclass, fields
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal
from typing import Any, ClassVar

__all__ = ["Result", "PROOF_WORDS", "proof_word", "outward_bracket", "short_repr", "plain",
           "json_ready", "dumps", "markdown_table", "new_figure", "subplots", "verdict_markdown",
           "verdict_figure", "simulation_markdown", "simulation_figure"]


#: How a number at each level of proof is called in text: the one mapping of the package
#: (``interval``: proven in exact or ball arithmetic; ``float``: a sound method in floating
#: point; anything else is an estimate).
PROOF_WORDS: dict[str, str] = {"interval": "proven", "float": "certified (float)",
                               "none": "estimate"}


def proof_word(level: str) -> str:
    """The word for a number at proof ``level`` (:data:`PROOF_WORDS`; unknown: estimate).

    Parameters
    ----------
    level : str
        ``"interval"``, ``"float"`` or anything else (an estimate).

    Examples
    --------
    >>> proof_word("interval"), proof_word("float"), proof_word("none")
    ('proven', 'certified (float)', 'estimate')
    """
    return PROOF_WORDS.get(level, "estimate")


def outward_bracket(lower: float, upper: float, most: int = 6
                    ) -> tuple[float, float, int] | None:
    """``(lower, upper, digits)`` of an open bracket rounded outward to the significant
    digits it proves, ``2 + ceil(-log10 gap)`` (lower down, upper up): printed figures
    that do not depend on the last bits of a float; None when the bracket is closed to
    more than ``most`` digits, a point, or has a zero, negative or infinite end.

    Parameters
    ----------
    lower, upper : float
        The ends of the bracket.
    most : int, optional
        Most significant digits printed.

    Returns
    -------
    tuple of (float, float, int) or None
        The rounded ends and the number of digits, or None.

    Examples
    --------
    >>> outward_bracket(0.0111398, 0.0209773)
    (0.0111, 0.021, 3)
    """
    if not (math.isfinite(lower) and math.isfinite(upper) and 0 < lower < upper):
        return None
    digits = 2 + math.ceil(-math.log10((upper - lower) / upper))
    if digits > most:
        return None
    return (float(_round(lower, digits, ROUND_FLOOR)), float(_round(upper, digits, ROUND_CEILING)),
            digits)


def _round(x: float, digits: int, rounding: str) -> Decimal:
    """``x`` (exactly, as a binary number) rounded to ``digits`` significant digits."""
    exact = Decimal(x)
    return exact.quantize(Decimal(1).scaleb(exact.adjusted() - digits + 1), rounding=rounding)


def _value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str) and len(value) > 40:
        return repr(value[:37] + "...")
    return repr(value)


def short_repr(obj: object, *fields: str, **extra: Any) -> str:
    """``Type(field=value, ...)`` of the named attributes and ``extra`` values (floats 6 digits).

    Parameters
    ----------
    obj : object
        The result object.
    *fields : str
        Names of its attributes to show, in order.
    **extra
        Further ``name=value`` pairs shown after them.

    Returns
    -------
    str
        The one-line representation.
    """
    items = [(name, getattr(obj, name)) for name in fields] + list(extra.items())
    return f"{type(obj).__name__}({', '.join(f'{k}={_value(v)}' for k, v in items)})"


def plain(value: Any) -> Any:
    """``value`` with complex numbers as ``{"re", "im"}``, numpy values as Python ones and
    tuples as lists, so that :func:`json.dumps` accepts it (floats are kept, infinities
    included).

    Parameters
    ----------
    value : object
        Nested dicts, lists, tuples, numpy arrays or scalars, complex numbers and plain
        values.

    Returns
    -------
    object
        The same structure of JSON-compatible Python values (dict keys as str).
    """
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return plain(value.tolist())
    if isinstance(value, complex):
        return {"re": float(value.real), "im": float(value.imag)}
    return value


def json_ready(value: Any) -> Any:
    """``value`` as strict JSON data: the package's one JSON convention.

    Numpy scalars and arrays become Python numbers and lists, tuples lists, complex
    numbers ``{"re": ..., "im": ...}``, dictionary keys strings.  JSON has no infinity
    and no NaN: an infinite float is the string ``"inf"`` (``"-inf"``), a NaN is ``null``
    (a number that is not known; result objects never carry one where a value was
    proven).

    Parameters
    ----------
    value : object
        Nested dicts, lists, tuples, numbers, numpy values and strings.

    Examples
    --------
    >>> json_ready({"r": float("inf"), "x": float("nan"), "z": 1j, 2: (1, -float("inf"))})
    {'r': 'inf', 'x': None, 'z': {'re': 0.0, 'im': 1.0}, '2': [1, '-inf']}
    """
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    if hasattr(value, "tolist") and hasattr(value, "dtype"):  # numpy array or scalar
        return json_ready(value.tolist())
    if isinstance(value, complex):
        return {"re": json_ready(value.real), "im": json_ready(value.imag)}
    if isinstance(value, float):
        if math.isnan(value):
            return None
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
    return value


def dumps(value: Any, *, indent: int | None = 2) -> str:
    """Strict JSON text of ``value`` (:func:`json_ready`, then ``allow_nan=False``): every
    output parses with ``json.loads(text, parse_constant=...)`` raising on
    ``NaN``/``Infinity``.

    Parameters
    ----------
    value : object
        What :func:`json_ready` accepts.
    indent : int, optional
        Indentation (None: one line).

    Examples
    --------
    >>> print(dumps({"lower": float("inf")}, indent=None))
    {"lower": "inf"}
    """
    return json.dumps(json_ready(value), indent=indent, allow_nan=False)


@dataclass(frozen=True, kw_only=True, repr=False)
class Result:
    """The base of result objects: frozen, built by keyword, one ``to_dict``, ``repr`` and
    Markdown view derived from the fields.

    A subclass is declared ``@dataclass(frozen=True, kw_only=True, repr=False)`` (so the
    shared ``__repr__`` stays) and may set two class attributes:

    ``_exclude``
        Fields left out of :meth:`to_dict`, each for a stated reason in the subclass's
        docstring (a large array, a derived object with its own view).  A field whose
        name starts with an underscore is private working data (compiled callables, a
        memo) and never in :meth:`to_dict`.
    ``_headline``
        Fields shown by ``repr`` (default: the first three).
    ``_keys``
        The JSON key of a field whose documented contract names it differently.
    ``_order``
        The JSON keys in the order of the documented contract (keys not listed follow in
        field order).

    and may override :meth:`_computed` for the keys computed from the fields (a relative
    gap, a kind word) or a field's contract form (a complex number as ``[re, im]``).

    >>> @dataclass(frozen=True, kw_only=True, repr=False)
    ... class Radius(Result):
    ...     _exclude = ("samples",)
    ...     value: float
    ...     proof: str
    ...     samples: tuple[float, ...] = ()
    >>> r = Radius(value=float("inf"), proof="interval", samples=(1.0, 2.0))
    >>> r
    Radius(value=inf, proof='interval', samples=(1.0, 2.0))
    >>> r.to_dict()
    {'value': inf, 'proof': 'interval'}
    >>> dumps(r.to_dict(), indent=None)
    '{"value": "inf", "proof": "interval"}'
    """

    _exclude: ClassVar[tuple[str, ...]] = ()
    _headline: ClassVar[tuple[str, ...]] = ()
    _keys: ClassVar[dict[str, str]] = {}
    _order: ClassVar[tuple[str, ...]] = ()

    def to_dict(self) -> dict[str, Any]:
        """The fields (but :attr:`_exclude`) as plain values: nested results as their
        ``to_dict()``, complex numbers ``{"re", "im"}``, numpy values as Python ones;
        then the :meth:`_computed` keys, in :attr:`_order`."""
        out = {self._keys.get(f.name, f.name): _plain_value(getattr(self, f.name))
               for f in fields(self) if f.name not in self._exclude and f.name[0] != "_"}
        out.update({key: _plain_value(value) for key, value in self._computed().items()})
        if self._order:
            out = {**{key: out[key] for key in self._order if key in out}, **out}
        return out

    def _computed(self) -> dict[str, Any]:
        """Keys of :meth:`to_dict` computed from the fields (none here)."""
        return {}

    def __repr__(self) -> str:
        names = self._headline or tuple(f.name for f in fields(self))[:3]
        return short_repr(self, *names)

    def _repr_markdown_(self) -> str:
        rows = [(name, value) for name, value in self.to_dict().items()
                if value is None or isinstance(value, (bool, int, float, str))]
        return f"**{type(self).__name__}**\n\n" + markdown_table(("field", "value"), rows)


def _plain_value(value: Any) -> Any:
    if isinstance(value, Result) or (hasattr(value, "to_dict") and not isinstance(value, type)):
        return value.to_dict()
    if isinstance(value, (list, tuple)):
        return [_plain_value(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain_value(v) for k, v in value.items()}
    return plain(value)


def _cell(value: Any) -> str:
    """A Markdown table cell: floats to 6 digits, None as an em dash, ``|`` escaped."""
    if value is None:
        text = "—"
    elif isinstance(value, bool):
        text = "yes" if value else "no"
    elif isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = str(value)
    return text.replace("|", "\\|").replace("\n", " ")


def markdown_table(header: tuple[str, ...], rows: list[tuple[Any, ...]]) -> str:
    """A Markdown table (GitHub/Jupyter pipe syntax) of ``rows`` under ``header``.

    Parameters
    ----------
    header : tuple of str
        The column headings.
    rows : list of tuple
        The rows, as long as ``header``; floats are printed with 6 significant digits,
        None as a dash, booleans as yes/no, ``|`` escaped and newlines as spaces.

    Returns
    -------
    str
        The table, without a final newline.

    Examples
    --------
    >>> print(markdown_table(("n", "||H_n||"), [(1, 5.0251890762960), (2, None)]))
    | n | \\|\\|H_n\\|\\| |
    |---|---|
    | 1 | 5.02519 |
    | 2 | — |
    """
    lines = ["| " + " | ".join(_cell(h) for h in header) + " |",
             "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(v) for v in row) + " |" for row in rows]
    return "\n".join(lines)


def new_figure(rows: int, columns: int, size: tuple[float, float]) -> tuple[Any, Any]:
    """A matplotlib ``Figure`` and its axes, made without pyplot (any backend, Agg included;
    no global figure state).  matplotlib is imported here, on first plot only.

    Parameters
    ----------
    rows, columns : int
        Grid of axes.
    size : tuple of float
        Width and height in inches.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.
    numpy.ndarray
        Its axes, always 2-D (``rows`` x ``columns``).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=size, layout="constrained")
    return figure, figure.subplots(rows, columns, squeeze=False)


def subplots(*args: Any, figsize: tuple[float, float] | None = None,
             **kwargs: Any) -> tuple[Any, Any]:
    """``pyplot.subplots`` without pyplot: a ``Figure`` and its axes (``Figure.subplots``
    arguments), bound to no backend and registered nowhere, so the caller's matplotlib
    state (a notebook's backend, its open figures) is untouched and nothing needs closing.

    Parameters
    ----------
    *args
        Rows and columns, as ``Figure.subplots``.
    figsize : tuple of float, optional
        Width and height in inches.
    **kwargs
        Passed to ``Figure.subplots`` (``sharex``, ``squeeze``, ...).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=figsize)
    return figure, figure.subplots(*args, **kwargs)


def verdict_markdown(verdict: Any) -> str:
    """Markdown of a :class:`gfrf.stability.verdicts.Verdict`: r*, r and the bounds, the conditions,
    the norm brackets.

    Parameters
    ----------
    verdict : Verdict
        The verdict.

    Returns
    -------
    str
        The Markdown text.
    """
    kind = (f"certified, {verdict.radius_proof}" if verdict.radius_certified
            else "estimate, not certified")
    held = {True: "yes", False: "no", None: "not established"}
    loop = getattr(verdict, "loop", "")
    rows = ([(f"r* ({kind})", verdict.radius), ("amplitude r", verdict.amplitude),
             ("proven upper bound on the true radius", verdict.radius_upper),
             ("estimate of the true radius (not a proof)", verdict.radius_estimate)]
            if not loop else
            [(f"r* ({kind}), units of the reference r", verdict.radius),
             ("amplitude r (reference)", verdict.amplitude),
             ("loop: proven upper bound on the true radius (units of r)",
              verdict.loop_radius_upper),
             ("plant: proven upper bound on its true radius (units of u)",
              verdict.radius_upper),
             ("plant: estimate of its true radius (units of u; not a proof)",
              verdict.radius_estimate)])
    parts = [f"**Theorem {verdict.theorem}: {verdict.verdict}**"
             + (f" (loop {loop})" if loop else ""),
             markdown_table(("quantity", "value"), rows),
             markdown_table(("condition", "holds"),
                            [(c.name, held[c.passed]) for c in verdict.conditions])]
    if verdict.norms:
        parts.append(markdown_table(("n", "‖H_n‖ lower", "‖H_n‖ upper"),
                                    [(b.order, b.lower, b.upper) for b in verdict.norms]))
    return "\n\n".join(parts)


def verdict_figure(verdict: Any) -> Any:
    """The norm series of a verdict: ||H_n|| and the majorant against n, and the root-test
    radii c_n^(-1/n) of the majorant with r*, r and the radius bounds, on a log amplitude
    axis (r* = 5e-4 is not on the zero line), every line labelled (for Theorem 2 with the
    units it is in: the plant's in units of u, the loop's in units of the reference r),
    the legends beside the axes, off the data.

    Parameters
    ----------
    verdict : Verdict
        The verdict, with its ``series`` rows.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, two panels.
    """
    from matplotlib.ticker import MaxNLocator

    loop = verdict.theorem == 2
    figure, axes = new_figure(1, 2, (12.0, 3.8))
    left, right = axes[0]
    rows = [row for row in verdict.series if row["majorant"] > 0]
    n = [row["order"] for row in rows]
    majorant = [row["majorant"] for row in rows]
    plant = "plant " if loop else ""
    left.semilogy(n, majorant, "o-", label=f"{plant}certified majorant c_n")
    if any(row["lower"] is not None for row in rows):
        left.semilogy(n, [row["upper"] for row in rows], "v", label="‖H_n‖ upper")
        left.semilogy(n, [row["lower"] if row["lower"] else float("nan") for row in rows],
                      "^", label="‖H_n‖ lower")
    left.set(xlabel="order n", ylabel="‖H_n‖ (plant)", title="kernel norms")
    u_units, r_units = (" (units of u)", " (units of r)") if loop else ("", "")
    right.plot(n, [c ** (-1.0 / k) for k, c in zip(n, majorant, strict=True)], "o-",
               label=f"{plant}c_n^(-1/n){u_units}")
    lines = [(verdict.radius, {"color": "#2b8a3e"},
              f"{'loop ' if loop else ''}r* = {verdict.radius:.4g}{r_units}"),
             (verdict.amplitude, {"color": "black", "linestyle": "--"},
              f"r = {verdict.amplitude:.4g}{r_units}")]
    if verdict.radius_upper is not None:
        lines.append((verdict.radius_upper, {"color": "#c92a2a", "linestyle": ":"},
                      f"{plant}true radius <= {verdict.radius_upper:.4g}{u_units}"))
    if getattr(verdict, "loop_radius_upper", None) is not None:
        lines.append((verdict.loop_radius_upper, {"color": "#862e9c", "linestyle": "-."},
                      f"loop true radius <= {verdict.loop_radius_upper:.4g}{r_units}"))
    for value, style, label in lines:
        if 0 < value < float("inf"):
            right.axhline(value, label=label, **style)
        else:  # 0 or inf has no place on a log axis: in the legend only
            right.plot([], [], label=f"{label} (not drawn)", **style)
    right.set_yscale("log")
    right.set(xlabel="order n", ylabel="amplitude" + (" (see units)" if loop else " r"),
              title=f"Theorem {verdict.theorem}: {verdict.verdict}")
    for ax in (left, right):
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  borderaxespad=0.0)
    return figure


def simulation_markdown(result: Any) -> str:
    """Markdown of a :class:`gfrf.sim.integrate.SimulationResult` (no wall time).

    Parameters
    ----------
    result : SimulationResult
        The simulation.

    Returns
    -------
    str
        A one-row Markdown table.
    """
    t_final = float(result.t[-1]) if result.t.size else 0.0
    y_final = float(result.y[-1]) if result.y.size else None
    return markdown_table(("status", "method", "t_final (s)", "samples", "max |y|",
                           "y(t_final)", "blow-up time (s)"),
                          [(result.status, result.method, t_final, int(result.t.size),
                            result.peak, y_final, result.blowup_time)])


def simulation_figure(result: Any) -> Any:
    """y(t) and u(t) of a simulation, stacked, with the blow-up time marked.

    Parameters
    ----------
    result : SimulationResult
        The simulation.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, two stacked panels sharing the time axis.
    """
    figure, axes = new_figure(2, 1, (7.0, 4.5))
    top, bottom = axes[0][0], axes[1][0]
    top.plot(result.t, result.y)
    bottom.plot(result.t, result.u, color="#e8590c")
    top.set(ylabel="output y", title=f"simulation ({result.method}): {result.status}")
    bottom.set(xlabel="t (s)", ylabel="input u")
    if result.blowup_time is not None:
        for ax in (top, bottom):
            ax.axvline(result.blowup_time, color="#c92a2a", linestyle=":")
    top.sharex(bottom)
    return figure
