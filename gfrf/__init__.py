"""gfrf: stability of polynomial nonlinear systems from their generalized frequency responses.

Angular frequency is in rad/s everywhere: ``H(w)`` evaluates the kernel at s = j*w
(see :class:`gfrf.kernels.recursion.Kernel` for values at complex s).  The public API
(:data:`__all__`) is re-exported here and loaded on first use (so ``import gfrf``
stays cheap); every function that takes a model takes a :class:`Model` or what
:func:`load_model` returns (a :class:`ModelFile`, whose plant is used):

>>> import gfrf
>>> m = gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
>>> abs(complex(gfrf.kernel(m, 1)(0.0)))
1.0

Models
    parse_model, load_model, Model, ModelFile; from_tf (a transfer function with a
    polynomial feedback or series nonlinearity), from_nlsys (a polynomial
    ``control.nlsys`` about an equilibrium)
Kernels and norms
    kernel, Kernel, h1_norm, kernel_norm, Bound, probe_kernel, linear_part
    (H1 as a ``control.TransferFunction``)
Stability
    verdict (Theorem 1, or 2 with the file's controller or ``controller=`` a
    python-control system), Verdict, parameter_margin, Margin, closed_loop, ClosedLoop
Time and frequency domain
    simulate, SimulationResult, build_system, predict, VolterraPrediction,
    to_nlsys (the plant or closed loop as a ``control.NonlinearIOSystem``), ofrf, OFRF
    (the output at one frequency as a polynomial in a parameter, and the NOFRFs)
Measurements without a model
    multisine, Multisine (odd random-phase multisine designs), estimate_gfrf, Estimate
    (the best linear approximation with its noise and distortion levels, nonparametric
    H2 and H3 from periodic data)
Beyond the series radius
    frc (frequency response curve by harmonic balance and continuation: stable and
    unstable branches, folds, backbone), FrequencyResponseCurve
Sweeps
    :mod:`gfrf.sweep.run` (``gfrf.sweep.run.sweep``), SweepResult
Errors
    GfrfError and its subclasses ModelError, ArgumentError, ConvergenceError

Result objects have a short ``repr`` and a ``to_dict()`` that :func:`json.dumps`
accepts; Verdict, Margin, SimulationResult, VolterraPrediction, OFRF and ClosedLoop
show as Markdown tables in notebooks, Model, ModelFile and Kernel as LaTeX; and
``Verdict.plot()`` (norm series with r*), ``SimulationResult.plot()`` (y and u against
t), ``Kernel.plot()`` (Bode of H1, |H2| map, slices of Hn), ``VolterraPrediction.plot()``
(the predicted spectrum, with a simulation's FFT) and ``OFRF.plot()`` return a
matplotlib Figure made without pyplot.

The package is laid out as its pipeline, one subpackage per stage, each importing only
the stages before it (``import-linter`` holds this in ``make test``):
:mod:`gfrf.model` (text -> Model) -> :mod:`gfrf.kernels` (H1..Hn) -> :mod:`gfrf.bounds`
(norms and majorants with their proofs) -> :mod:`gfrf.stability` (Theorems 1 and 2,
verdicts) -> :mod:`gfrf.sim` (simulation, Volterra prediction, validation) ->
:mod:`gfrf.papers`, :mod:`gfrf.sweep`, :mod:`gfrf.identify` -> :mod:`gfrf.report`,
:mod:`gfrf.bench` -> :mod:`gfrf.cli`; :mod:`gfrf.periodic` (the parametrically excited
pendulum) stands apart from the GFRF stack.
"""

from __future__ import annotations

import importlib
from typing import Any

from gfrf.errors import (
    ArgumentError,
    ConvergenceError,
    GfrfError,
    ModelError,
)

#: Public names re-exported as they are, and their modules.
_LAZY = {
    "Model": "gfrf.model.equation", "parse_model": "gfrf.model.equation",
    "ModelFile": "gfrf.model.modelfile", "load_model": "gfrf.model.modelfile",
    "Kernel": "gfrf.kernels.recursion",
    "Bound": "gfrf.bounds.norms",
    "Verdict": "gfrf.stability.verdicts", "Margin": "gfrf.stability.criteria",
    "parameter_margin": "gfrf.stability.criteria",
    "ClosedLoop": "gfrf.stability.loops", "closed_loop": "gfrf.stability.loops",
    "SimulationResult": "gfrf.sim.simulation", "build_system": "gfrf.sim.system",
    "simulate": "gfrf.sim.simulation",
    "VolterraPrediction": "gfrf.sim.volterra",
    "SweepResult": "gfrf.sweep.run",
    "from_sysidentpy": "gfrf.identify.narx",
    "multisine": "gfrf.identify.multisine", "Multisine": "gfrf.identify.multisine",
    "estimate_gfrf": "gfrf.identify.nonparametric", "Estimate": "gfrf.identify.nonparametric",
    "linear_part": "gfrf._api", "verdict": "gfrf._api",
    "to_nlsys": "gfrf.sim.nlsys",
    "ofrf": "gfrf.sim.ofrf", "OFRF": "gfrf.sim.ofrf",
    "from_tf": "gfrf.model.from_control", "from_nlsys": "gfrf.model.from_control",
    "check_certificate": "gfrf.stability.sos_check",
    "threshold": "gfrf._api", "Threshold": "gfrf.twosided.threshold",
    "FrequencyResponseCurve": "gfrf.harmonic.curve",
}
#: Functions of a plant model re-exported so that they also take a ModelFile.
_PLANT = {
    "kernel": "gfrf.kernels.recursion", "h1_norm": "gfrf.bounds.norms",
    "kernel_norm": "gfrf.bounds.norms",
    "predict": "gfrf.sim.volterra", "probe_kernel": "gfrf.kernels.probing",
    "frc": "gfrf.harmonic.curve",
}

__all__ = [
    "ArgumentError",
    "ConvergenceError",
    "GfrfError",
    "ModelError",
    *sorted({*_LAZY, *_PLANT}),
]

__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    if name in _PLANT:
        from gfrf._api import plant_function

        value = plant_function(_PLANT[name], name)
    elif name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
    else:
        raise AttributeError(f"module 'gfrf' has no attribute {name!r}")
    globals()[name] = value  # loaded once; gfrf.kernel is gfrf.kernel
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
