"""Model files: one TOML file per system, holding a plant and optionally a controller.

The smallest valid file is one line, ``equation = "D(y,2) + 2*D(y) + y = u"`` (plus
``sample_time = 0.1`` for a discrete model).  Every other key is optional:

=================== =====================================================================
key                 meaning
=================== =====================================================================
equation            the model equation (see :func:`gfrf.model.equation.parse_model`)
sample_time         sample time in s; makes the model discrete-time (NARX)
truncation          Taylor order for ``sin``/``cos``/... terms (the polynomial model)
physical_equation   untruncated equation kept for simulation when ``equation`` is the
                    already-truncated polynomial (e.g. a paper's printed coefficients)
output, input       signal names (default ``y``, ``u``)
parameters          table of named constants used in the equations
name, source,       free text: a title, the paper equation it comes from, a description
description
kind                ``"ode"`` (default), or ``"parametric"`` for the time-varying
                    pendulum handled by :mod:`gfrf.periodic` (refused here)
paper               table of values printed in the paper, quoted by reports only
controller          table: ``num``/``den`` (transfer function, highest power first, as
                    :func:`control.tf`; entries may be parameter expressions) or
                    ``equation`` (a polynomial controller whose input is the plant
                    output and whose output is the plant input); ``feedback`` = -1
                    (default, u = C(r - y)) or +1; ``name``, ``source``, ``description``;
                    ``sample_time`` (a discrete controller: it must equal the plant's, a
                    continuous controller on a discrete plant or the reverse is refused)
=================== =====================================================================
"""

from __future__ import annotations

import math
import os
import re
import stat
import tomllib
from dataclasses import dataclass, field, replace
from fractions import Fraction
from pathlib import Path
from typing import Any

import sympy as sp

from gfrf._data import MODELS_DIR
from gfrf._results import Result
from gfrf.errors import ModelError
from gfrf.model.equation import Model, parse_model
from gfrf.model.exact import as_fraction
from gfrf.model.limits import quote
from gfrf.model.numbers import MAX_PARAMETERS, exact_number, parse_number
from gfrf.model.numbers import parameter_table as _parameters

__all__ = ["Controller", "ModelFile", "load_model", "model_from_dict", "read_table",
           "MAX_FILE_BYTES", "MAX_PARAMETERS", "MAX_CONTROLLER_COEFFICIENTS", "parse_number",
           "as_plant", "resolve_model", "looks_like_path", "bundled_or_path", "MODEL_TYPES"]

#: Largest model file accepted, in bytes (checked before reading it).
MAX_FILE_BYTES = 256 * 1024
#: Most entries of a controller's ``num`` or ``den``.
MAX_CONTROLLER_COEFFICIENTS = 64

_TOP_KEYS = {"equation", "sample_time", "truncation", "physical_equation", "output", "input",
             "parameters", "name", "source", "description", "kind", "paper", "controller"}
_CONTROLLER_KEYS = {"num", "den", "equation", "feedback", "name", "source", "description",
                    "parameters", "sample_time"}


@dataclass(frozen=True, kw_only=True)
class Controller(Result):
    """A controller from a model file: linear transfer function or polynomial model.

    Attributes
    ----------
    num, den : tuple of float or None
        Transfer-function coefficients, highest power of s first (``control.tf`` order).
    model : Model or None
        Polynomial controller; its input is the plant output, its output the plant input.
    feedback : int
        -1 for negative feedback ``u = C(r - y)`` (default), +1 for ``u = C(r + y)``.
    name, source, description : str
        Free text.
    written : tuple, optional
        ``(num, den, exact num, exact den)``: the doubles and the exact values written in
        the model file (see :meth:`exact_tf`).

    :meth:`to_dict` gives ``model`` as its ``equation`` and leaves out ``description``
    (free prose).
    """

    _exclude = ("model", "description", "written")
    _order = ("name", "source", "feedback", "num", "den", "equation")

    num: tuple[float, ...] | None = None
    den: tuple[float, ...] | None = None
    model: Model | None = None
    feedback: int = -1
    name: str = ""
    source: str = ""
    description: str = ""
    written: tuple[tuple[float, ...], tuple[float, ...], tuple[Fraction | None, ...],
                   tuple[Fraction | None, ...]] | None = field(default=None, repr=False,
                                                               compare=False)

    @property
    def is_linear(self) -> bool:
        """True for a transfer-function controller."""
        return self.model is None

    def exact_tf(self) -> tuple[tuple[Fraction | None, ...], tuple[Fraction | None, ...]]:
        """``num`` and ``den`` as the exact rationals written in the model file (None for
        an irrational entry); the doubles' own values when they were not written as text
        or were changed since (a python-control controller: its doubles are the model).

        Returns
        -------
        tuple
            ``(num, den)``, highest power first.
        """
        num, den = self.num or (), self.den or ()
        w = self.written
        if w is None or (w[0], w[1]) != (num, den):
            return tuple(Fraction(c) for c in num), tuple(Fraction(c) for c in den)
        return w[2], w[3]

    def _computed(self) -> dict[str, Any]:
        return {"num": list(self.num) if self.num else None,
                "den": list(self.den) if self.den else None,
                "equation": self.model.equation() if self.model else None}


@dataclass(frozen=True, kw_only=True)
class ModelFile(Result):
    """The contents of a model file: the plant, its controller and metadata.

    :meth:`to_dict` leaves out ``description`` (free prose) and ``paper`` (the paper's
    reference values, read by the report).
    """

    _exclude = ("description", "paper")
    _order = ("name", "source", "path", "parameters", "plant", "controller")

    plant: Model
    name: str = ""
    source: str = ""
    description: str = ""
    path: str = ""
    parameters: dict[str, float] = field(default_factory=dict)
    controller: Controller | None = None
    paper: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        extra = ", controller" if self.controller is not None else ""
        return f"ModelFile({self.name or self.path!r}, {self.plant.equation()!r}{extra})"

    def _repr_latex_(self) -> str:
        return self.plant._repr_latex_()


def load_model(path: str | Path) -> ModelFile:
    """Read a TOML model file.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    ModelFile

    Raises
    ------
    ModelError
        Missing file, invalid TOML, unknown key, or an invalid equation; the message
        names the file and the key.
    """
    p = Path(path)
    data = read_table(p)
    try:
        return model_from_dict(data, path=str(p))
    except ModelError as exc:
        message = str(exc)
        raise ModelError(message if message.startswith(str(p)) else f"{p}: {message}") from None


def read_table(path: str | Path) -> dict[str, Any]:
    """The TOML table of a model file, read within :data:`MAX_FILE_BYTES`.

    Parameters
    ----------
    path : str or Path
        The model file.

    Returns
    -------
    dict
        The parsed table.

    Raises
    ------
    ModelError
        Missing or oversized file, invalid TOML or UTF-8, nesting too deep to read.
    """
    p = Path(path)
    data = _read_regular(p)
    try:
        return tomllib.loads(data.decode("utf-8-sig"))  # a UTF-8 byte order mark is fine
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ModelError(f"{p}: not valid TOML: {exc}") from None
    except RecursionError:
        raise ModelError(f"{p}: not readable TOML: arrays or tables nested too deep") \
            from None


def _kind(mode: int) -> str:
    return ("a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode)
            else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
            else "a socket" if stat.S_ISSOCK(mode) else "not a regular file")


def _read_regular(p: Path) -> bytes:
    """The bytes of the regular file ``p`` (links followed), within MAX_FILE_BYTES.

    A directory, FIFO, device or socket is refused from :func:`os.stat` before it is
    opened (reading a FIFO would block, a device may never end), and the opened file is
    checked again (non-blocking open, then :func:`os.fstat`).
    """
    try:
        st = os.stat(p)
    except FileNotFoundError:
        hint = ""
        if p.suffix != ".toml" and p.parent in (Path("."), Path("models")) and (
                MODELS_DIR / f"{p.name}.toml").is_file():
            hint = f"; the bundled model is models/{p.name}.toml"
        raise ModelError(f"model file {quote(str(p))} does not exist (no such file){hint}"
                         ) from None
    except OSError as exc:
        raise ModelError(f"model file {quote(str(p))}: {exc.strerror}") from None
    if not stat.S_ISREG(st.st_mode):
        raise ModelError(f"model file {quote(str(p))} is not a regular file "
                         f"({_kind(st.st_mode)})")
    if st.st_size > MAX_FILE_BYTES:
        raise ModelError(f"{p}: {st.st_size} bytes, more than the limit MAX_FILE_BYTES = "
                         f"{MAX_FILE_BYTES}")
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise ModelError(f"model file {quote(str(p))}: {exc.strerror}") from None
    with os.fdopen(fd, "rb") as f:
        mode = os.fstat(f.fileno()).st_mode
        if not stat.S_ISREG(mode):
            raise ModelError(f"model file {quote(str(p))} is not a regular file "
                             f"({_kind(mode)})")
        data = f.read(MAX_FILE_BYTES + 1)
    if len(data) > MAX_FILE_BYTES:
        raise ModelError(f"{p}: more than the limit MAX_FILE_BYTES = {MAX_FILE_BYTES} bytes")
    return data


def _text(data: dict[str, Any], key: str, where: str = "") -> str:
    value = data.get(key, "")
    if not isinstance(value, str):
        raise ModelError(f"{where}{key} must be a string, got {value!r}")
    return value


def model_from_dict(data: dict[str, Any], path: str = "") -> ModelFile:
    """Build a :class:`ModelFile` from the parsed TOML table ``data``.

    Parameters
    ----------
    data : dict
        The parsed TOML table.
    path : str, optional
        The file it came from (the default name is its stem); empty for none.

    Returns
    -------
    ModelFile
        The model file.
    """
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise ModelError(f"unknown model file key(s) {', '.join(map(repr, unknown))}; "
                         f"allowed: {', '.join(sorted(_TOP_KEYS))}")
    kind = data.get("kind", "ode")
    if kind == "parametric":
        raise ModelError("this is a parametrically excited (time-varying) model: it has no "
                         "GFRFs; use 'gfrf transition' / 'gfrf periodic' (gfrf.periodic)")
    if kind != "ode":
        raise ModelError(f"kind must be 'ode' or 'parametric', got {kind!r}")
    if "equation" not in data:
        raise ModelError("missing key 'equation'")
    exact: dict[str, sp.Expr] = {}
    parameters = _parameters(data.get("parameters"), "parameters", exact)
    sample_time = data.get("sample_time")
    if sample_time is not None:
        sample_time = parse_number(sample_time, "sample_time", parameters)
    common = {"truncation": data.get("truncation"), "parameters": parameters,
              "output": data.get("output", "y"), "input": data.get("input", "u")}
    plant = parse_model(_text(data, "equation"), sample_time=sample_time,
                        exact_parameters=exact, **common)
    if "physical_equation" in data:
        # Only the untruncated expression is kept; the truncation merely validates it.
        physical = parse_model(_text(data, "physical_equation"), sample_time=sample_time,
                               exact=False,
                               **{**common, "truncation": common["truncation"] or 3})
        plant = replace(plant, physical=physical.physical)
    controller = _controller(data.get("controller"), parameters, plant, exact)
    paper = data.get("paper", {})
    if not isinstance(paper, dict):
        raise ModelError("paper must be a table")
    return ModelFile(plant=plant, name=_text(data, "name") or Path(path).stem,
                     source=_text(data, "source"), description=_text(data, "description"),
                     path=path, parameters=parameters, controller=controller, paper=paper)


def _controller(table: Any, parameters: dict[str, float], plant: Model,
                exact: dict[str, sp.Expr]) -> Controller | None:
    if table is None:
        return None
    if not isinstance(table, dict):
        raise ModelError("controller must be a table")
    unknown = sorted(set(table) - _CONTROLLER_KEYS)
    if unknown:
        raise ModelError(f"unknown controller key(s) {', '.join(map(repr, unknown))}; "
                         f"allowed: {', '.join(sorted(_CONTROLLER_KEYS))}")
    exact = dict(exact)
    values = {**parameters, **_parameters(table.get("parameters"), "controller.parameters",
                                          exact)}
    _check_timebase(table, values, plant)
    feedback = table.get("feedback", -1)
    if feedback not in (-1, 1) or isinstance(feedback, bool):
        raise ModelError(f"controller.feedback must be -1 or +1, got {feedback!r}")
    text = {k: _text(table, k, "controller.") for k in ("name", "source", "description")}
    has_tf = "num" in table or "den" in table
    if has_tf == ("equation" in table):
        raise ModelError("controller needs either num/den (a transfer function) or an "
                         "equation, not both and not neither")
    if has_tf:
        coefficients, written = {}, {}
        for key in ("num", "den"):
            entries = table.get(key, [1])
            if not isinstance(entries, list) or not entries:
                raise ModelError(f"controller.{key} must be a non-empty list of coefficients")
            if len(entries) > MAX_CONTROLLER_COEFFICIENTS:
                raise ModelError(f"controller.{key} has {len(entries)} coefficients, more than "
                                 f"the limit MAX_CONTROLLER_COEFFICIENTS = "
                                 f"{MAX_CONTROLLER_COEFFICIENTS}")
            coefficients[key] = tuple(parse_number(v, f"controller.{key}", values)
                                      for v in entries)
            written[key] = tuple(as_fraction(exact_number(v, exact)) for v in entries)
        if not any(coefficients["den"]):
            raise ModelError("controller.den is zero")
        return Controller(num=coefficients["num"], den=coefficients["den"], feedback=feedback,
                          written=(coefficients["num"], coefficients["den"], written["num"],
                                   written["den"]), **text)
    model = parse_model(table["equation"], sample_time=plant.sample_time, parameters=values,
                        output=plant.input, input=plant.output, exact_parameters=exact)
    return Controller(model=model, feedback=feedback, **text)


def _check_timebase(table: dict[str, Any], values: dict[str, float], plant: Model) -> None:
    """Refuse a controller whose timebase differs from the plant's (as python-control does).

    A controller without ``sample_time`` is read in the plant's timebase (s for an ODE
    plant, z for a NARX plant, as before); ``sample_time = 0`` marks it continuous-time and
    a positive ``sample_time`` discrete-time, and either must then match the plant's.
    """
    given = table.get("sample_time")
    if given is None:
        return
    dt = parse_number(given, "controller.sample_time", values)
    if not (math.isfinite(dt) and dt >= 0):
        raise ModelError(f"controller.sample_time must be 0 (continuous-time) or a positive "
                         f"number of seconds, got {given!r}")
    controller_dt = dt or None
    plant_dt = plant.sample_time
    if controller_dt != plant_dt:
        raise ModelError(f"mixed timebases: the controller is {_timebase(controller_dt)} but "
                         f"the plant is {_timebase(plant_dt)}; give both the same sample_time "
                         "(python-control refuses to connect them too)")


def _timebase(dt: float | None) -> str:
    return "continuous-time (dt = 0)" if dt is None else f"discrete-time (dt = {dt:g} s)"


#: What every public function that takes a model accepts (for messages).
MODEL_TYPES = "a model file path (str or Path), an equation string, a Model or a ModelFile"
#: Characters of a file name: text made only of these (and no ``=``) is a path, never an
#: equation, so ``duffing`` or ``models/duffing.tom`` is "does not exist", not a parse error.
_FILE_NAME = re.compile(r"[\w.\-/\\~:]+")


def looks_like_path(text: str) -> bool:
    """True when ``text`` names a file rather than writes an equation: it ends in
    ``.toml``, or has no ``=`` and is an existing file or made of file-name characters only.

    Parameters
    ----------
    text : str
        A MODEL argument.

    Examples
    --------
    >>> [looks_like_path(t) for t in ("models/duffing.tom", "duffing", "D(y) + y = u")]
    [True, True, False]
    """
    if text.endswith(".toml"):
        return True
    if "=" in text:
        return False
    return _FILE_NAME.fullmatch(text) is not None or _is_file(text)


def _is_file(text: str) -> bool:
    try:
        return Path(text).is_file()
    except (OSError, ValueError):  # too long for a file name, or a NUL character
        return False


def bundled_or_path(path: str) -> str:
    """``path``, or the bundled model file it names when no file ``path`` exists.

    A bundled model (:data:`gfrf._data.MODELS_DIR`, installed with the package) is named
    by its file name, alone or under ``models/``: ``duffing.toml`` and
    ``models/duffing.toml`` work from any directory.  A file that exists is always the
    one read; a name without ``.toml`` (``duffing``) names no file (the message of a
    missing file points to the bundled one, :func:`load_model`).

    Parameters
    ----------
    path : str
        A model file path as the user wrote it.

    Returns
    -------
    str
        ``path`` itself, or the bundled file's absolute path.

    Examples
    --------
    >>> bundled_or_path("duffing.toml") == str(MODELS_DIR / "duffing.toml")
    True
    >>> bundled_or_path("duffing")
    'duffing'
    >>> bundled_or_path("models/duffing.tom")
    'models/duffing.tom'
    """
    if _exists(path):
        return path
    given = Path(path)
    if given.parent not in (Path("."), Path("models")) or given.suffix != ".toml":
        return path
    bundled = MODELS_DIR / given.name
    return str(bundled) if bundled.is_file() else path


def _exists(text: str) -> bool:
    try:
        return Path(text).exists()
    except (OSError, ValueError):  # too long for a file name, or a NUL character
        return False


def resolve_model(model: str | os.PathLike[str] | Model | ModelFile, *,
                  sample_time: float | None = None) -> ModelFile:
    """The :class:`ModelFile` of any model argument: the one rule of every function that
    takes a model.

    Parameters
    ----------
    model : str, Path, Model or ModelFile
        A model file path (or a bundled model's name, :func:`bundled_or_path`); an
        equation string (an inline model named ``"inline model"``; text that looks like
        a file name, see :func:`looks_like_path`, is a path); a
        :class:`~gfrf.model.equation.Model` (wrapped); or a ModelFile (returned as is).
    sample_time : float, optional
        Sample time in s of an inline discrete (NARX) equation (a model file sets its own).

    Returns
    -------
    ModelFile

    Raises
    ------
    TypeError
        ``model`` is none of the accepted types (the message names them).
    ModelError
        A missing or invalid file ("does not exist" for a path that names no file), an
        invalid equation, a NARX equation without ``sample_time``, or ``sample_time``
        given with a file.

    Examples
    --------
    >>> resolve_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u").name
    'inline model'
    >>> resolve_model(3)
    Traceback (most recent call last):
    ...
    TypeError: a model is a model file path (str or Path), an equation string, ... not int
    """
    if isinstance(model, ModelFile):
        return model
    if isinstance(model, Model):
        return ModelFile(plant=model)
    if isinstance(model, os.PathLike) or (isinstance(model, str) and looks_like_path(model)):
        if sample_time is not None:
            raise ModelError("sample_time (--sample-time) is for inline equations; a model "
                             "file sets sample_time itself")
        return load_model(bundled_or_path(os.fspath(model)))
    if not isinstance(model, str):
        raise TypeError(f"a model is {MODEL_TYPES}, not {type(model).__name__}")
    data: dict[str, object] = {"equation": model, "name": "inline model"}
    if sample_time is not None:
        data["sample_time"] = sample_time
    elif "[k" in model:
        raise ModelError("a discrete (NARX) equation needs --sample-time (sample_time=)")
    return model_from_dict(data)


def as_plant(model: str | os.PathLike[str] | Model | ModelFile) -> Model:
    """The plant :class:`~gfrf.model.equation.Model` of any model argument
    (:func:`resolve_model`).

    Parameters
    ----------
    model : str, Path, Model or ModelFile
        A model file path, an equation string, a Model or a ModelFile.

    Returns
    -------
    Model
        The plant.

    Raises
    ------
    TypeError
        ``model`` is none of the accepted types.
    """
    if isinstance(model, Model):
        return model
    return resolve_model(model).plant
