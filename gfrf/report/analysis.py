"""Everything a report says about one model file, computed once per run.

:func:`analyse` loads a model file and runs the verdict (Theorem 1 or 2, with norm
brackets), the simulations of :func:`gfrf.validation.validate` around the margin r*,
and the time responses drawn in the figures.  The result is cached per (path, quick),
so the per-model page and the paper page quote the same objects.

The simulations use the polynomial (truncated) equation, the object the verdict
speaks about, with fixed seeds.  ``quick`` shortens horizons and lowers the highest
norm order (for tests and CI).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from gfrf.criteria import Verdict, verdict
from gfrf.modelfile import ModelFile, load_model
from gfrf.simulate import SimulationResult, build_system, simulate
from gfrf.validation import ValidationResult, resonance, validate

__all__ = ["MODELS_DIR", "ModelAnalysis", "Response", "analyse", "settings"]

#: The bundled model files (``models/`` beside the package).
MODELS_DIR = Path(__file__).resolve().parent.parent.parent / "models"


@dataclass(frozen=True)
class Response:
    """One time response drawn in a simulation figure."""

    label: str
    signal: str
    amplitude: float
    initial_angle_deg: float
    result: SimulationResult


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
        Peak of |H1| (rad/s) on the grid of :func:`gfrf.validation.resonance`.
    trial_scale : float
        The amplitude the trials are multiples of: r* when positive, else the
        uncertified root-test estimate (``trial_scale_certified`` False), else 0.
    trial_scale_certified : bool
    validation : ValidationResult or None
    responses : tuple of Response
    t_end : float
        Horizon (s) of every simulation.
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

    @property
    def stem(self) -> str:
        """File name without ``.toml`` (the page name)."""
        return Path(self.path).stem

    @property
    def closed(self) -> bool:
        """True when the model file has a controller (Theorem 2)."""
        return self.model_file.controller is not None


def settings(quick: bool) -> dict[str, float]:
    """Norm order and simulation horizon of the full and the quick setting."""
    return {"order": 3, "t_end": 20.0} if quick else {"order": 5, "t_end": 100.0}


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
    v = verdict(mf, order, 1.0)
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
    return ModelAnalysis(path, mf, v, order, w_r, scale, certified, validation, responses,
                         t_end)


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
