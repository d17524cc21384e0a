"""The identified model as a model file: its TOML text, read back, written atomically.

:func:`model_file_text` writes an :class:`~gfrf.identify.fit.Identification` as a model
file (``source`` names the data and the fit settings) that ``gfrf verdict`` and
``gfrf report`` read like any other, and checks that it reads back to the identified
terms; :func:`load_text` reads such a text, :func:`write_atomic` saves it.
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

from gfrf.errors import ModelError
from gfrf.identify.fit import Identification
from gfrf.model.modelfile import ModelFile, model_from_dict

__all__ = ["model_file_text", "load_text", "write_atomic"]


def _toml_string(text: str) -> str:
    """A TOML basic string of ``text``; lone surrogates (the undecodable bytes of a file
    name, as Python passes them) become visible ``\\xNN`` text, which TOML accepts."""
    return json.dumps(re.sub("[\ud800-\udfff]", _surrogate, text), ensure_ascii=True)


def _surrogate(match: re.Match[str]) -> str:
    code = ord(match.group())
    return f"\\x{code - 0xdc00:02x}" if 0xdc80 <= code <= 0xdcff else f"\\u{code:04x}"


def model_file_text(result: Identification, data: str, name: str = "",
                    description: str = "") -> str:
    """The model file (TOML) of an identification; ``source`` names the data and settings.

    The text is read back before it is returned: its model must have exactly the
    identified terms (same lags, same coefficients), else :class:`ModelError`.

    Parameters
    ----------
    result : Identification
        The identification.
    data : str
        The CSV file's path, as the user gave it (in ``source`` and the default name).
    name : str, optional
        The model's name; empty: "NARX identified from" the data file's name.
    description : str, optional
        Text put before the generated description.

    Returns
    -------
    str
        The TOML text.
    """
    m = result.model
    how = (f"FROLS as in sysidentpy {result.sysidentpy_version}" if result.sysidentpy_version
           else "FROLS")
    source = (f"gfrf identify {data} --output {m.output} --input {m.input} --sample-time "
              f"{m.sample_time!r} {result.settings_text()} ({how}): {result.quality_text()}")
    lines = ["# Identified from measured data by `gfrf identify` (FROLS); "
             "coefficients rounded to 10 significant digits.",
             f"name = {_toml_string(name or 'NARX identified from ' + Path(data).name)}",
             f"equation = {_toml_string(m.text)}",
             f"sample_time = {m.sample_time!r}"]
    if m.output != "y" or m.input != "u":
        lines += [f"output = {_toml_string(m.output)}", f"input = {_toml_string(m.input)}"]
    lines.append(f"source = {_toml_string(source)}")
    adequacy = (f"Validation: {'adequate' if result.adequate else 'NOT ADEQUATE'} ("
                f"{result.validation.reason})." if result.validation else "")
    about = " ".join([description, result.operating_text() + ".", result.noise_text() + ".",
                      adequacy, *result.notes]).strip()
    lines.append(f"description = {_toml_string(about)}")
    text = "\n".join(lines) + "\n"
    reread = model_from_dict(tomllib.loads(text)).plant
    if reread.terms != m.terms:  # Term equality includes the coefficient
        raise ModelError(f"the model file does not reproduce the identified model: "
                         f"{reread.equation()} != {m.equation()}")
    return text


def load_text(text: str, path: str) -> ModelFile:
    """The ModelFile of a model file text (as ``load_model`` would read it from ``path``).

    Parameters
    ----------
    text : str
        The TOML text of a model file.
    path : str
        The path the file is (or will be) at.

    Returns
    -------
    ModelFile
        The model file.
    """
    return model_from_dict(tomllib.loads(text), path=path)


def write_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically: :func:`gfrf._atomic.atomic_write_text`.

    Parameters
    ----------
    path : str or path-like
        The model file.
    text : str
        Its content.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from gfrf._atomic import atomic_write_text

    return atomic_write_text(path, text)
