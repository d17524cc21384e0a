"""Everything a report says about one model file, computed once per run.

:func:`analyse` loads a model file and runs the verdict (Theorem 1 or 2, with norm
brackets), the simulations of :func:`gfrf.sim.validation.validate` around the margin r*,
the time responses drawn in the figures, and for each ``[parameters]`` entry a scan of
the verdict at r = 1 over a bracket around its value with, where the verdict turns
``stable`` above a boundary, the certified boundary of
:func:`gfrf.stability.criteria.parameter_margin`.  The result is cached per (path, quick),
so the per-model page and the paper page quote the same objects.

The simulations use the polynomial (truncated) equation, the object the verdict
speaks about, with fixed seeds.  ``quick`` shortens horizons and lowers the highest
norm order (for tests and CI), and bisects parameter margins to a coarser tolerance.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from gfrf._data import MODELS_DIR
from gfrf.errors import GfrfError
from gfrf.model.modelfile import ModelFile, load_model
from gfrf.model.template import ModelTemplate, model_template
from gfrf.sim.integrate import SimulationResult
from gfrf.sim.simulation import simulate
from gfrf.sim.system import build_system
from gfrf.sim.validation import ValidationResult, resonance, validate
from gfrf.stability.criteria import Margin, parameter_margin, verdict
from gfrf.stability.verdicts import Verdict

__all__ = ["MODELS_DIR", "MARGIN_OCTAVES", "ModelAnalysis", "ParameterScan", "Response",
           "analyse", "scan_parameter", "settings"]

#: Half-width of a parameter's margin bracket in octaves: file value * 2^-6 .. 2^6.
MARGIN_OCTAVES = 6

#: The bundled model files (``models/`` beside the package).


@dataclass(frozen=True)
class Response:
    """One time response drawn in a simulation figure."""

    label: str
    signal: str
    amplitude: float
    initial_angle_deg: float
    result: SimulationResult


@dataclass(frozen=True)
class ParameterScan:
    """The verdict at r = 1 along one ``[parameters]`` entry, and its certified margin.

    Attributes
    ----------
    parameter : str
    current : float
        The model file's value.
    values : tuple of float
        The bracket grid, ``current * 2^k`` for ``|k| <= MARGIN_OCTAVES`` (empty for a
        non-positive value).
    stable : tuple of bool
        Whether the verdict at each grid value is ``stable`` (an invalid point is not).
    margin : Margin or None
        The boundary of :func:`gfrf.stability.criteria.parameter_margin`, when the verdict along
        the grid is monotone with ``stable`` above one boundary.
    note : str
        Why there is no margin (empty when there is one).
    """

    parameter: str
    current: float
    values: tuple[float, ...]
    stable: tuple[bool, ...]
    margin: Margin | None
    note: str


@dataclass(frozen=True)
class ModelAnalysis:
    """Verdict, validation trials and figure responses of one model file.

    Attributes
    ----------
    path : str
        Model file as given (relative paths are kept for the printed commands).
    model_file : ModelFile
    verdict : Verdict
        At the paper's amplitude r = 1, with norm brackets up to ``order``.
    order : int
    resonance : float
        Drive frequency (rad/s) of :func:`gfrf.sim.validation.resonance`: the exact peak
        of |H1| (the witness of ||H1||), or a grid argmax where |H1| has no finite peak.
    trial_scale : float
        The amplitude the trials are multiples of: r* when positive, else the
        uncertified root-test estimate (``trial_scale_certified`` False), else 0.
    trial_scale_certified : bool
    validation : ValidationResult or None
    responses : tuple of Response
    t_end : float
        Horizon (s) of every simulation.
    margins : tuple of ParameterScan
        One per ``[parameters]`` entry, in file order.
    """

    path: str
    model_file: ModelFile
    verdict: Verdict
    order: int
    resonance: float
    trial_scale: float
    trial_scale_certified: bool
    validation: ValidationResult | None
    responses: tuple[Response, ...] = field(default=())
    t_end: float = 0.0
    margins: tuple[ParameterScan, ...] = field(default=())

    @property
    def stem(self) -> str:
        """File name without ``.toml`` (the page name)."""
        return Path(self.path).stem

    @property
    def closed(self) -> bool:
        """True when the model file has a controller (Theorem 2)."""
        return self.model_file.controller is not None


def settings(quick: bool) -> dict[str, float]:
    """Norm order, simulation horizon and margin tolerance of the full and quick setting.

    Parameters
    ----------
    quick : bool
        The quick setting (tests) instead of the full one.

    Returns
    -------
    dict of str to float
        ``order``, ``t_end`` (s) and ``margin_tolerance``.
    """
    return ({"order": 3, "t_end": 20.0, "margin_tolerance": 1e-2} if quick else
            {"order": 5, "t_end": 100.0, "margin_tolerance": 1e-6})


@lru_cache(maxsize=32)
def analyse(path: str, quick: bool = False) -> ModelAnalysis:
    """Verdict, trials and responses for the model file at ``path`` (cached).

    Parameters
    ----------
    path : str
        A GFRF model file (``kind = "ode"``).
    quick : bool
        Reduced setting (norm order 3, 20 s horizons).

    Returns
    -------
    ModelAnalysis
    """
    mf = load_model(path)
    cfg = settings(quick)
    order, t_end = int(cfg["order"]), cfg["t_end"]
    v = verdict(mf, order, 1.0, norms="tight")  # a report page shows the tightest brackets
    w_r = resonance(mf.plant)
    if v.radius > 0 and math.isfinite(v.radius):
        scale, certified = v.radius, True
    elif v.radius_estimate:
        scale, certified = v.radius_estimate, False
    else:
        scale, certified = 0.0, False
    validation = None
    if scale > 0:
        # r*/2, 2 r* and the paper's test amplitude r = 1 (as a multiple of the scale).
        factors = tuple(sorted({0.5, 2.0, 1.0 / scale}))
        validation = validate(mf, scale, factors=factors, t_end=t_end, seed=0)
    responses = _responses(mf, scale, w_r, t_end)
    margins: tuple[ParameterScan, ...] = ()
    if mf.parameters:
        data = tomllib.loads(Path(mf.path).read_text(encoding="utf-8"))
        free = [n for n, value in data["parameters"].items() if not isinstance(value, str)]
        template = model_template(data, free, mf.path)
        margins = tuple(scan_parameter(mf, template, name, cfg["margin_tolerance"])
                        if name in free else
                        ParameterScan(name, mf.parameters[name], (), (), None,
                                      "defined by an expression of other parameters")
                        for name in mf.parameters)
    return ModelAnalysis(path=path,
                         model_file=mf,
                         verdict=v,
                         order=order,
                         resonance=w_r,
                         trial_scale=scale,
                         trial_scale_certified=certified,
                         validation=validation,
                         responses=responses,
                         t_end=t_end,
                         margins=margins)


def scan_parameter(mf: ModelFile, template: ModelTemplate, name: str,
                   tolerance: float) -> ParameterScan:
    """Scan the verdict at r = 1 along ``name`` and certify its boundary when monotone.

    Parameters
    ----------
    mf : ModelFile
        Loaded from a file (its ``path`` is re-read by the bisection).
    template : ModelTemplate
        The sweep template of the file over its numeric ``[parameters]`` (the scan's
        points; parameters given as expressions follow them).
    name : str
        A key of the file's ``[parameters]``.
    tolerance : float
        Relative bracket width of the :func:`gfrf.stability.criteria.parameter_margin` bisection.

    Returns
    -------
    ParameterScan
        With a margin only when the verdict along the bracket grid changes exactly once
        (``parameter_margin`` finds that boundary from the file value by doubling and
        halving, on the same grid, and says on which side the verdict is stable).
    """
    current = mf.parameters[name]
    if current <= 0:
        return ParameterScan(name, current, (), (), None,
                             f"file value {current:g} is not positive: no geometric bracket")
    values = tuple(current * 2.0 ** k for k in range(-MARGIN_OCTAVES, MARGIN_OCTAVES + 1))
    stable = tuple(_stable(template, {**mf.parameters, name: value}) for value in values)
    changes = [i for i in range(len(stable) - 1) if stable[i] != stable[i + 1]]
    where = f"[{values[0]:.4g}, {values[-1]:.4g}]"
    if not changes:
        kind = "stable" if stable[0] else "not stable"
        note = f"no boundary in {where}: the verdict is {kind} throughout"
    elif len(changes) > 1:
        note = f"the verdict is not monotone in {name} over {where} ({len(changes)} changes)"
    else:
        return ParameterScan(name, current, values, stable,
                             parameter_margin(mf, name, 1.0, tolerance), "")
    return ParameterScan(name, current, values, stable, None, note)


def _stable(template: ModelTemplate, values: dict[str, float]) -> bool:
    """Whether the verdict at r = 1 (majorant only) is ``stable``; an invalid point is not."""
    try:
        point = template.instantiate(values)
    except GfrfError:
        return False
    return verdict(point, 1, 1.0, with_norms=False).verdict == "stable"


def _responses(mf: ModelFile, scale: float, w_r: float, t_end: float) -> tuple[Response, ...]:
    """Responses for the figure: initial angles in closed loop, sines at r*/2 and 2 r*."""
    closed = mf.controller is not None
    system = build_system(mf, closed_loop=closed, equation="polynomial")
    t_eval = None if mf.plant.is_discrete else np.linspace(0.0, t_end, 1001)
    out = []
    if closed:
        for angle in (5.0, 10.0, 15.0):
            res = simulate(system, None, t_end=t_end, initial=[math.radians(angle), 0.0],
                           t_eval=t_eval, rtol=1e-8, atol=1e-11, blowup=1e3)
            out.append(Response(f"initial angle {angle:g} deg, r = 0", "0", 0.0, angle, res))
        return tuple(out)
    for factor in (0.5, 2.0):
        a = factor * scale
        signal = f"{a:.6g}*sin({w_r:.6g}*t)"
        res = simulate(system, signal, t_end=t_end, t_eval=t_eval, rtol=1e-8, atol=1e-11,
                       blowup=1e3)
        out.append(Response(f"u = {a:.4g} sin({w_r:.4g} t) ({factor:g} r*)", signal, a, 0.0,
                            res))
    return tuple(out)
