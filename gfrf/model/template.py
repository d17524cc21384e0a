"""Model templates: the symbolic work of a parameter sweep, done once per model structure.

A sweep changes only the values of some ``[parameters]`` (or ``controller.parameters``)
of a model file; the terms that exist, their derivative orders (or lags of a NARX
model) and the truncation are the same at every point.  :func:`model_template` parses
the equation once with the swept parameters left as symbols, Taylor-truncates it, and
keeps each term's coefficient (and each controller ``num``/``den`` entry, or each
coefficient of a polynomial controller's equation) as a formula in the swept
parameters, printed to Python source.  :meth:`ModelTemplate.instantiate` evaluates
those formulas (plain float arithmetic, ~10 us) and assembles the
:class:`~gfrf.model.modelfile.ModelFile` of one grid point without touching sympy, so only
numeric work is shipped to sweep workers.  The template pickles as text and
recompiles its formulas on first use in each process.

The instantiated plant (and polynomial controller) has ``physical = None``: it serves
the GFRF criteria and simulations of the polynomial model.  The one structure a
template cannot cover, a ``sample_time`` that depends on a swept parameter, raises
:class:`TemplateUnsupported`; :func:`rebuild` (a full parse per point) covers it.
A grid point's coefficients are the doubles its formulas evaluate to: they carry no
written decimal values (:attr:`gfrf.model.equation.Term.exact` is the double's own value),
so a proof at a grid point is about the model with those doubles.

Examples
--------
>>> data = {"equation": "D(y,2) + c*D(y) + y + 0.5*y**3 = u", "parameters": {"c": 0.2}}
>>> t = model_template(data, ["c"])
>>> t.instantiate({"c": 0.4}).plant.linear_output[1]
0.4
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import sympy as sp

from gfrf.errors import ArgumentError, ModelError
from gfrf.model.equation import Model, Term, coefficient_formulas
from gfrf.model.expr import UnknownNames, parse_expression
from gfrf.model.limits import Parsed, quote
from gfrf.model.modelfile import ModelFile, model_from_dict

__all__ = ["ModelTemplate", "TemplateUnsupported", "model_template", "rebuild",
           "parameter_names"]

#: Coefficient structure of one equation: (y_orders, u_orders) per coefficient formula.
Structure = tuple[tuple[tuple[int, ...], tuple[int, ...]], ...]


class TemplateUnsupported(ArgumentError):
    """The model file is valid but its swept structure is outside the template path."""


def parameter_names(data: Mapping[str, Any]) -> dict[str, str]:
    """Sweepable parameter names of a model-file table, mapped to their table.

    Returns ``{name: "parameters"}`` for the top-level table and
    ``{name: "controller.parameters"}`` for the controller's own table.

    Parameters
    ----------
    data : mapping
        The parsed TOML table of a model file.

    Returns
    -------
    dict of str to str
        ``{name: table}``.
    """
    names = {name: "parameters" for name in (data.get("parameters") or {})}
    controller = data.get("controller") or {}
    if isinstance(controller, dict):
        names.update({name: "controller.parameters"
                      for name in (controller.get("parameters") or {})})
    return names


def rebuild(data: Mapping[str, Any], values: Mapping[str, float], path: str = "") -> ModelFile:
    """The model file ``data`` with some parameter values replaced (full parse, slow path).

    Parameters
    ----------
    data : mapping
        The parsed TOML table of a model file.
    values : mapping of str to float
        New values of parameters of ``data``'s parameter tables.
    path : str, optional
        The file it came from; empty for none.

    Returns
    -------
    ModelFile
        The model file at the new values.
    """
    where = parameter_names(data)
    changed: dict[str, Any] = dict(data)
    top = dict(data.get("parameters") or {})
    controller = dict(data.get("controller") or {})
    own = dict(controller.get("parameters") or {})
    for name, value in values.items():
        if where.get(name) == "parameters":
            top[name] = value
        elif where.get(name) == "controller.parameters":
            own[name] = value
        else:
            raise ArgumentError(_unknown(name, where))
    if top:
        changed["parameters"] = top
    if controller:
        changed["controller"] = {**controller, "parameters": own} if own else controller
    return model_from_dict(changed, path=path)


def _unknown(name: str, where: Mapping[str, str]) -> str:
    known = ", ".join(sorted(where)) or "none"
    return f"unknown parameter {name!r}; the model file's parameters are: {known}"


@dataclass
class ModelTemplate:
    """Coefficient formulas of a model file in its swept parameters.

    Attributes
    ----------
    names : tuple of str
        The swept parameters, in argument order.
    base : ModelFile
        The model file at its own parameter values (fully validated).
    structure : tuple of (y_orders, u_orders)
        One entry per plant coefficient formula.
    source : str
        Python source of ``lambda _p0, _p1, ...: (plant coefficients, controller numbers)``,
        the controller numbers being ``num`` then ``den`` of a transfer function, or
        the coefficients of a polynomial controller in ``controller_structure`` order.
    n_num : int
        Length of a transfer-function controller's ``num`` (0 otherwise).
    controller_structure : tuple of (y_orders, u_orders)
        One entry per coefficient of a polynomial controller (its output is the plant
        input); empty otherwise.
    """

    names: tuple[str, ...]
    base: ModelFile
    structure: Structure
    source: str
    n_num: int
    controller_structure: Structure = ()
    _function: Callable[..., tuple[float, ...]] | None = field(default=None, repr=False)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_function": None}

    def _formulas(self) -> Callable[..., tuple[float, ...]]:
        if self._function is None:
            self._function = eval(self.source, {"math": math})
        return self._function

    def instantiate(self, values: Mapping[str, float]) -> ModelFile:
        """The model file at ``values`` of the swept parameters (numeric work only).

        Parameters
        ----------
        values : mapping of str to float
            Values of the swept parameters.

        Returns
        -------
        ModelFile
            The model file at ``values``.

        Raises
        ------
        ModelError
            A coefficient is not finite, or a vanishing coefficient removes the linear
            output term, the input or the output (the message names the point).
        """
        args = [float(values[n]) for n in self.names]
        try:
            numbers = self._formulas()(*args)
        except (ZeroDivisionError, ValueError, OverflowError) as exc:
            raise ModelError(f"{self._where(values)}: {exc}") from None
        plant = self.base.plant
        terms = self._terms(plant, self.structure, numbers, values)
        self._check(plant, terms, values, "the equation")
        model = replace(plant, terms=terms, physical=None)
        controller = self.base.controller
        rest = numbers[len(self.structure):]
        if controller is not None and controller.model is not None:
            law = controller.model
            law_terms = self._terms(law, self.controller_structure, rest, values)
            self._check(law, law_terms, values, "the controller equation")
            controller = replace(controller, model=replace(law, terms=law_terms,
                                                           physical=None))
        elif controller is not None:
            num, den = rest[:self.n_num], rest[self.n_num:]
            if not any(den):
                raise ModelError(f"{self._where(values)}: controller.den is zero")
            controller = replace(controller, num=tuple(num), den=tuple(den))
        return replace(self.base, plant=model, controller=controller,
                       parameters={**self.base.parameters, **dict(zip(self.names, args,
                                                                       strict=True))})

    def _terms(self, model: Model, structure: Structure, numbers: Sequence[float],
               values: Mapping[str, float]) -> tuple[Term, ...]:
        """The non-zero terms of ``model`` with the coefficients ``numbers``."""
        terms = []
        for (y_orders, u_orders), c in zip(structure, numbers, strict=False):
            if not math.isfinite(c):
                raise ModelError(f"{self._where(values)}: coefficient of "
                                 f"{Term(y_orders, u_orders, 1.0, model.output, model.input)} "
                                 f"is not finite")
            if c != 0.0:
                terms.append(Term(y_orders, u_orders, float(c), model.output, model.input,
                                  model.is_discrete))
        return tuple(sorted(terms))

    def _where(self, values: Mapping[str, float]) -> str:
        return "at " + ", ".join(f"{n} = {values[n]:g}" for n in self.names)

    def _check(self, model: Model, terms: Sequence[Term], values: Mapping[str, float],
               what: str) -> None:
        if not any(t.is_linear_output for t in terms):
            raise ModelError(f"{self._where(values)}: no linear term in the output "
                             f"{model.output!r}: H1 is undefined")
        if not any(t.u_orders for t in terms):
            raise ModelError(f"{self._where(values)}: {what} has no input {model.input!r}")


def _symbolic(value: Any, values: Mapping[str, Parsed], key: str) -> Parsed:
    """A TOML number or expression text as a parsed expression in ``values`` (by
    :mod:`gfrf.model.expr`; every name is a :class:`Parsed` that carries its degree and size in
    the swept parameters, so a chain of parameter definitions cannot grow an expression
    without bound)."""
    if not isinstance(value, str):
        return Parsed(sp.Float(value), 0, False)
    try:
        return parse_expression(value, names=values)
    except UnknownNames as exc:
        raise ModelError(f"{key}: {quote(value)} uses unknown symbol(s) "
                         f"{', '.join(exc.names)}") from None
    except ModelError as exc:
        raise ModelError(f"{key}: {exc}") from None


def _symbolic_table(table: Mapping[str, Any] | None, swept: Mapping[str, Parsed],
                    known: dict[str, Parsed], where: str) -> dict[str, Parsed]:
    values = dict(known)
    for name, value in (table or {}).items():
        values[name] = swept[name] if name in swept else \
            _symbolic(value, values, f"{where}.{name}")
    return values


def _coefficients(text: str, model: Model, values: dict[str, Parsed]) -> dict[tuple, sp.Expr]:
    """Coefficient formulas {(y_orders, u_orders): expr} of the equation ``text`` of
    ``model`` (its signals, truncation and time base), parameters as in ``values``."""
    return coefficient_formulas(text, output=model.output, input=model.input,
                                discrete=model.is_discrete, truncation=model.truncation,
                                symbols=values)


def _exact(expr: sp.Expr) -> sp.Expr:
    """Floats as exact binary fractions, so the printed source loses no digit."""
    return expr.xreplace({f: sp.Rational(f) for f in expr.atoms(sp.Float)})


def model_template(data: Mapping[str, Any], names: Sequence[str], path: str = "") -> ModelTemplate:
    """Build the template of the model-file table ``data`` for sweeping ``names``.

    Parameters
    ----------
    data : mapping
        The parsed TOML table of a model file.
    names : sequence of str
        Parameters to sweep: keys of ``[parameters]`` or of ``controller.parameters``.
    path : str
        The file, for messages.

    Returns
    -------
    ModelTemplate

    Raises
    ------
    ArgumentError
        An unknown parameter name.
    TemplateUnsupported
        A structure this fast path does not cover (a ``sample_time`` depending on a
        swept parameter): use :func:`rebuild` per point instead.
    ModelError
        The model file itself is invalid.
    """
    where = parameter_names(data)
    for name in names:
        if name not in where:
            raise ArgumentError(_unknown(name, where))
    base = model_from_dict(dict(data), path=path)
    # Internal argument names _p0, _p1, ...: no user-written name reaches the source.
    swept = {n: Parsed(sp.Symbol(f"_p{i}", real=True), 1, False, 1, True)
             for i, n in enumerate(names)}
    try:
        values = _symbolic_table(data.get("parameters"), swept, {}, "parameters")
        step = data.get("sample_time")
        if isinstance(step, str) and _symbolic(step, values, "sample_time").expr.free_symbols:
            raise TemplateUnsupported("sweep templates need a sample_time independent of the "
                                      "swept parameters")
        formulas = _coefficients(data["equation"], base.plant, values)
        exprs = list(formulas.values())
        n_num = 0
        law: dict[tuple, sp.Expr] = {}
        if base.controller is not None:
            controller = data["controller"]
            own = _symbolic_table(controller.get("parameters"), swept, values,
                                  "controller.parameters")
            if base.controller.model is not None:
                law = _coefficients(controller["equation"], base.controller.model, own)
                exprs += list(law.values())
            else:
                num = [_symbolic(v, own, "controller.num").expr
                       for v in controller.get("num", [1])]
                den = [_symbolic(v, own, "controller.den").expr
                       for v in controller.get("den", [1])]
                exprs += num + den
                n_num = len(num)
    except ModelError as exc:
        # The file is valid (parsed above with numbers); only the symbolic form in the
        # swept parameters exceeds a limit of gfrf.model.limits: each point is parsed in full.
        raise TemplateUnsupported(f"its form in the swept parameters exceeds a parser "
                                  f"limit: {exc}") from None
    body = ", ".join(sp.pycode(_exact(e)) for e in exprs)
    arguments = ", ".join(f"_p{i}" for i in range(len(names)))
    source = f"lambda {arguments or '*_'}: ({body},)"
    return ModelTemplate(tuple(names), base, tuple(formulas), source, n_num, tuple(law))
