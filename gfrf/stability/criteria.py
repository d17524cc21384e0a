"""The entry points of the stability criteria: which theorem applies, and margins.

:func:`verdict` applies Theorem 2 (:func:`gfrf.stability.theorem2.theorem2`) when the
model file has a controller and Theorem 1 (:func:`gfrf.stability.theorem1.theorem1`)
otherwise, and returns a :class:`gfrf.stability.verdicts.Verdict`.
:func:`parameter_margin` bisects a model-file parameter for the boundary of a certified
``stable`` verdict (a :class:`Margin`).
"""

from __future__ import annotations

from dataclasses import dataclass

from gfrf._results import Result, markdown_table, short_repr
from gfrf.errors import ArgumentError
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile, model_from_dict, resolve_model
from gfrf.stability.theorem1 import theorem1
from gfrf.stability.theorem2 import theorem2
from gfrf.stability.verdicts import Verdict

__all__ = ["verdict", "Margin", "parameter_margin"]


def verdict(model: ModelFile | Model, order: int = 5, amplitude: float = 1.0,
            with_norms: bool = True, proof: str = "interval", *,
            norms: str | None = None) -> Verdict:
    """Theorem 2 when the model file has a controller, Theorem 1 otherwise.

    Parameters
    ----------
    model : ModelFile or Model
        A loaded model file (plant and optional controller) or a bare plant model.
    order : int
        Highest kernel order whose norms are computed and reported.
    amplitude : float
        Input amplitude r at which the series is tested (the paper's r = 1).
    with_norms : bool
        False is ``norms="none"`` (sweeps and margins).
    proof : {"interval", "float", "none"}
        Level of proof, default ``"interval"`` (see :func:`theorem1`).
    norms : {"none", "fast", "tight"}, optional
        Tightness of the ||H_n|| brackets, default ``"fast"`` (see :func:`theorem1`);
        the verdict and r* do not depend on it.

    Returns
    -------
    Verdict
    """
    if isinstance(model, Model):
        return theorem1(model, order, amplitude, with_norms, proof, norms=norms)
    model = resolve_model(model)
    if model.controller is not None:
        return theorem2(model, order, amplitude, with_norms, proof, norms=norms)
    return theorem1(model.plant, order, amplitude, with_norms, proof, norms=norms)


@dataclass(frozen=True, kw_only=True)
class Margin(Result):
    """Smallest (or largest) parameter value for which the certified verdict is ``stable``.

    Attributes
    ----------
    parameter : str
    value : float
        The boundary found by bisection (relative width ``tolerance``).
    direction : str
        ``"above"``: stable for parameter > value (e.g. damping); ``"below"`` otherwise.
    amplitude : float
    current : float
        The model file's own value.
    tolerance : float
    """

    parameter: str
    value: float
    direction: str
    amplitude: float
    current: float
    tolerance: float

    def __repr__(self) -> str:
        return short_repr(self, "parameter", "value", "direction", "amplitude")

    def _repr_markdown_(self) -> str:
        return markdown_table(("parameter", "boundary", "stable", "file value", "amplitude r"),
                              [(self.parameter, self.value, f"{self.direction} the boundary",
                                self.current, self.amplitude)])


def parameter_margin(model_file: ModelFile, parameter: str, amplitude: float = 1.0,
                     tolerance: float = 1e-6) -> Margin:
    """Boundary value of a model-file parameter for a certified ``stable`` verdict.

    The verdict is assumed monotone in the parameter near the boundary (true for the
    damping of the pendulum: r* increases with rho).  The nearest change of verdict is
    searched by scaling the file value up and down by powers of 2, then bisected, with
    the model rebuilt from the file each time; norms are not bracketed (majorant only).
    ``direction`` says whether the certified side lies above or below the boundary.

    Parameters
    ----------
    model_file : ModelFile
        Loaded from a TOML file (its ``path`` is re-read).
    parameter : str
        A key of the file's ``[parameters]`` table.
    amplitude : float
    tolerance : float
        Relative width of the final bracket.

    Returns
    -------
    Margin
    """
    if parameter not in model_file.parameters:
        raise ArgumentError(f"{parameter!r} is not a parameter of {model_file.name!r}; "
                            f"parameters: {', '.join(sorted(model_file.parameters))}")
    if not model_file.path:
        raise ArgumentError("parameter margins need a model file (its path is re-read)")
    from gfrf.model.modelfile import read_table

    data = read_table(model_file.path)
    current = model_file.parameters[parameter]

    def passes(value: float) -> bool:
        changed = {**data, "parameters": {**data.get("parameters", {}), parameter: value}}
        mf = model_from_dict(changed, path=model_file.path)
        return verdict(mf, 1, amplitude, with_norms=False).verdict == "stable"

    if current == 0:
        raise ArgumentError(f"{parameter!r} is 0 in the file: the margin search scales it by "
                            "powers of 2, give a nonzero value")
    ok_now = passes(current)
    bracket = None
    for k in range(1, 61):  # the nearest change of verdict, scaling up or down by 2^k
        for probe, previous in ((current * 2.0**k, current * 2.0 ** (k - 1)),
                                (current / 2.0**k, current / 2.0 ** (k - 1))):
            if passes(probe) != ok_now:
                bracket = sorted((previous, probe))
                break
        if bracket:
            break
    else:
        raise ArgumentError(f"no change of verdict found when scaling {parameter!r} by up "
                            "to 2^60 either way")
    lo, hi = bracket
    good_high = passes(hi)
    while abs(hi - lo) > tolerance * max(abs(lo), abs(hi)):
        mid = 0.5 * (lo + hi)
        if passes(mid) == good_high:
            hi = mid
        else:
            lo = mid
    return Margin(parameter=parameter, value=hi if good_high else lo,
                  direction="above" if good_high else "below", amplitude=float(amplitude),
                  current=current, tolerance=tolerance)
