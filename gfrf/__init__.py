"""gfrf: stability of polynomial nonlinear systems from their generalized frequency responses.

Angular frequency is in rad/s everywhere.  The public API is re-exported here and
loaded on first use (so ``import gfrf`` stays cheap):

>>> import gfrf
>>> m = gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u")
>>> abs(complex(gfrf.kernel(m, 1)(0.0)))
1.0

Modules: :mod:`gfrf.model` (text → Model), :mod:`gfrf.modelfile` (TOML files),
:mod:`gfrf.kernels` (the GFRF recursion), :mod:`gfrf.norms`, :mod:`gfrf.criteria`
(Theorems 1 and 2, the radius r*), :mod:`gfrf.loops`, :mod:`gfrf.simulate`,
:mod:`gfrf.volterra`, :mod:`gfrf.periodic` (the parametrically excited pendulum).
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

_LAZY = {
    "Model": "gfrf.model", "parse_model": "gfrf.model",
    "ModelFile": "gfrf.modelfile", "load_model": "gfrf.modelfile",
    "Kernel": "gfrf.kernels", "kernel": "gfrf.kernels",
    "Bound": "gfrf.norms", "h1_norm": "gfrf.norms", "kernel_norm": "gfrf.norms",
    "Verdict": "gfrf.criteria", "verdict": "gfrf.criteria",
    "ClosedLoop": "gfrf.loops", "closed_loop": "gfrf.loops",
    "SimulationResult": "gfrf.simulate", "build_system": "gfrf.simulate",
    "simulate": "gfrf.simulate",
    "predict": "gfrf.volterra",
    "probe_kernel": "gfrf.probing",
    "from_sysidentpy": "gfrf.identify",
}

__all__ = [
    "ArgumentError",
    "ConvergenceError",
    "GfrfError",
    "InstabilityError",
    "ModelError",
    *sorted(_LAZY),
]

__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'gfrf' has no attribute {name!r}")
