"""Periodic solutions of the parametrically excited inverted pendulum.

Independent of the GFRF core.  Equation (3)/(4) of Zhang, Zhen & Li (2019),
``x'' + (delta + eps cos t) g(x) = 0`` with dimensionless time (excitation angular
frequency 1), ``g = sin`` or ``x - x**3/6``.  ``amplitude`` means ``x(0)`` of the
orbit with ``x'(0) = 0``, except on the upper side of the ``1/4`` tongue
(``side="upper"``), where it is the turning point ``x(pi)`` of the orbit with ``x(0) = 0``.

Modules, one idea each:

* :mod:`~gfrf.periodic.equation` -- parameters, physical mapping, model file;
* :mod:`~gfrf.periodic.floquet` -- monodromy, Floquet multipliers, Mathieu curves;
* :mod:`~gfrf.periodic.shooting` -- exact nonlinear orbits and transition values;
* :mod:`~gfrf.periodic.spectral` -- transition orbits by Fourier collocation (the fast
  exact path behind :func:`transition_delta`, checked by shooting);
* :mod:`~gfrf.periodic.fourier` -- cosine-series arithmetic on coefficient arrays;
* :mod:`~gfrf.periodic.perturbation`, :mod:`~gfrf.periodic.homotopy`,
  :mod:`~gfrf.periodic.energy`, :mod:`~gfrf.periodic.averaging` -- the four methods;
* :mod:`~gfrf.periodic.compare` -- errors against the ground truth;
* :mod:`~gfrf.periodic.formulas` -- the formula-by-formula check of the paper.

May import: :mod:`gfrf.errors` only; it and the GFRF stack (model ... sim) never import
each other (an import-linter contract in pyproject.toml).
"""

from gfrf.periodic.compare import (
    METHODS,
    compare_periodic,
    method_transition,
    transition_curve,
)
from gfrf.periodic.equation import load_model, physical_to_dimensionless
from gfrf.periodic.floquet import floquet_multipliers, mathieu_transition
from gfrf.periodic.shooting import orbit_at_delta, transition_delta

__all__ = [
    "METHODS",
    "compare_periodic",
    "floquet_multipliers",
    "load_model",
    "mathieu_transition",
    "method_transition",
    "orbit_at_delta",
    "physical_to_dimensionless",
    "transition_curve",
    "transition_delta",
]
