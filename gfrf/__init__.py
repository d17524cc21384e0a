"""gfrf: stability of polynomial nonlinear systems from their generalized frequency responses.

Angular frequency is in rad/s everywhere: ``H(w)`` evaluates the kernel at s = j*w
(see :class:`gfrf.kernels.Kernel` for values at complex s).  The public API
(:data:`__all__`) is re-exported here and loaded on first use (so ``import gfrf``
stays cheap); every function that takes a model takes a :class:`Model` or what
:func:`load_model` returns (a :class:`ModelFile`, whose plant is used):

>>> import gfrf
>>> m = gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
>>> abs(complex(gfrf.kernel(m, 1)(0.0)))
1.0

Models
    parse_model, load_model, Model, ModelFile
Kernels and norms
    kernel, Kernel, h1_norm, kernel_norm, Bound, probe_kernel, linear_part
    (H1 as a ``control.TransferFunction``)
Stability
    verdict (Theorem 1, or 2 with the file's controller or ``controller=`` a
    python-control system), Verdict, parameter_margin, Margin, closed_loop, ClosedLoop
Time and frequency domain
    simulate, SimulationResult, build_system, predict, VolterraPrediction,
    to_nlsys (the plant or closed loop as a ``control.NonlinearIOSystem``)
Sweeps
    :mod:`gfrf.sweep` (``gfrf.sweep.sweep``), SweepResult
Errors
    GfrfError and its subclasses ModelError, ArgumentError, ConvergenceError,
    InstabilityError

Result objects have a short ``repr`` and a ``to_dict()`` that :func:`json.dumps`
accepts; Verdict, Margin and SimulationResult show as Markdown tables in notebooks,
and ``Verdict.plot()`` (norm series with r*) and ``SimulationResult.plot()`` (y and u
against t) return a matplotlib Figure.  Modules: :mod:`gfrf.model`,
:mod:`gfrf.modelfile`, :mod:`gfrf.kernels`, :mod:`gfrf.norms`, :mod:`gfrf.criteria`,
:mod:`gfrf.loops`, :mod:`gfrf.simulation`, :mod:`gfrf.nlsys`,
:mod:`gfrf.volterra`, :mod:`gfrf.sweep`, :mod:`gfrf.periodic` (the parametrically
excited pendulum).
"""

from __future__ import annotations

import importlib
from typing import Any

from gfrf.errors import (
    ArgumentError,
    ConvergenceError,
    GfrfError,
    InstabilityError,
    ModelError,
)

#: Public names re-exported as they are, and their modules.
_LAZY = {
    "Model": "gfrf.model", "parse_model": "gfrf.model",
    "ModelFile": "gfrf.modelfile", "load_model": "gfrf.modelfile",
    "Kernel": "gfrf.kernels",
    "Bound": "gfrf.norms",
    "Verdict": "gfrf.criteria", "Margin": "gfrf.criteria",
    "parameter_margin": "gfrf.criteria",
    "ClosedLoop": "gfrf.loops", "closed_loop": "gfrf.loops",
    "SimulationResult": "gfrf.simulation", "build_system": "gfrf.simulation",
    "simulate": "gfrf.simulation",
    "VolterraPrediction": "gfrf.volterra",
    "SweepResult": "gfrf.sweep",
    "from_sysidentpy": "gfrf.identify",
    "linear_part": "gfrf._api", "verdict": "gfrf._api",
    "to_nlsys": "gfrf.nlsys",
}
#: Functions of a plant model re-exported so that they also take a ModelFile.
_PLANT = {
    "kernel": "gfrf.kernels", "h1_norm": "gfrf.norms", "kernel_norm": "gfrf.norms",
    "predict": "gfrf.volterra", "probe_kernel": "gfrf.probing",
}

__all__ = [
    "ArgumentError",
    "ConvergenceError",
    "GfrfError",
    "InstabilityError",
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
