"""The notebook-facing functions of :mod:`gfrf` that add to the modules' own functions.

Every function of the package API that analyses a plant accepts either a
:class:`gfrf.model.equation.Model` or what :func:`gfrf.load_model` returns (a
:class:`gfrf.model.modelfile.ModelFile`, whose plant is then used); python-control
interoperates both ways: :func:`linear_part` gives H1 as a
``control.TransferFunction``, and :func:`verdict` and :func:`threshold` take a
python-control controller.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from gfrf.errors import ArgumentError
from gfrf.model.modelfile import as_plant

if TYPE_CHECKING:
    import control

    from gfrf.model.equation import Model
    from gfrf.model.modelfile import ModelFile
    from gfrf.stability.verdicts import Verdict
    from gfrf.twosided.threshold import Threshold

__all__ = ["plant_function", "linear_part", "verdict", "threshold"]


def plant_function(module: str, name: str) -> Callable[..., Any]:
    """``module.name`` with its first argument passed through :func:`as_plant`.

    Parameters
    ----------
    module : str
        The module's dotted name.
    name : str
        The function's name in it.

    Returns
    -------
    callable
        The wrapped function, its docstring extended.
    """
    target = getattr(importlib.import_module(module), name)

    @functools.wraps(target)
    def call(model: Model | ModelFile, *args: Any, **kwargs: Any) -> Any:
        return target(as_plant(model), *args, **kwargs)

    call.__doc__ = (f"{target.__doc__ or ''}\n\n    The model may also be a ModelFile "
                    f"(:func:`gfrf.load_model`): its plant is used.\n")
    return call


def linear_part(model: Model | ModelFile) -> control.TransferFunction:
    """H1 of the plant as a python-control transfer function.

    Continuous models give ``H1(s)``; discrete (NARX) models a discrete transfer
    function in ``z`` with ``dt`` = the sample time (the GFRFs' ``q`` is ``1/z``).

    Parameters
    ----------
    model : Model or ModelFile

    Returns
    -------
    control.TransferFunction

    Examples
    --------
    >>> import gfrf
    >>> h1 = gfrf.linear_part(gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    >>> [float(c) for c in h1.den[0][0]]
    [1.0, 0.2, 1.0]
    """
    from gfrf.stability.loops import linear_plant

    return linear_plant(as_plant(model))


def _controller(controller: Any, feedback: int, plant: Any) -> Any:
    """A :class:`gfrf.model.modelfile.Controller` from a SISO python-control system with
    the timebase of ``plant`` (ArgumentError naming both dt's otherwise)."""
    import control
    import numpy as np

    from gfrf.model.modelfile import Controller

    if isinstance(controller, control.StateSpace):
        controller = control.ss2tf(controller)
    if not isinstance(controller, control.TransferFunction):
        raise ArgumentError(f"controller must be a control.TransferFunction or StateSpace, "
                            f"got {type(controller).__name__}")
    if controller.ninputs != 1 or controller.noutputs != 1:
        raise ArgumentError("controller must be single-input single-output")
    plant_dt = plant.sample_time if plant.is_discrete else 0
    dt = controller.dt
    if dt is not None and not (dt == plant_dt or (dt is True and plant_dt)):
        raise ArgumentError(f"mixed timebases: the controller has dt = {dt!r} and the plant "
                            f"dt = {plant_dt!r} (0: continuous-time); python-control refuses "
                            "to connect them: give a controller of the plant's timebase")
    if feedback not in (-1, 1):
        raise ArgumentError(f"feedback must be -1 (negative) or +1, got {feedback!r}")
    num, den = (np.atleast_1d(np.asarray(c[0][0], dtype=float)) for c in
                (controller.num, controller.den))
    if not (np.all(np.isfinite(num)) and np.all(np.isfinite(den))) or not np.any(den):
        raise ArgumentError("controller coefficients must be finite with a non-zero "
                            "denominator")
    return Controller(num=tuple(float(c) for c in num), den=tuple(float(c) for c in den),
                      feedback=feedback, name="python-control controller")


def verdict(model: Model | ModelFile, order: int = 5, amplitude: float = 1.0,
            with_norms: bool = True, *, controller: Any = None,
            feedback: int = -1, proof: str = "interval", norms: str | None = None) -> Verdict:
    """Theorem 2 with a controller (the file's or ``controller``), Theorem 1 otherwise.

    Parameters
    ----------
    model : Model or ModelFile
        The plant, or a loaded model file (plant and optional controller).
    order : int
        Highest kernel order whose norms are computed and reported.
    amplitude : float
        Input amplitude r at which the series is tested.
    with_norms : bool
        Compute the lower bounds of the norms (slower).
    controller : control.TransferFunction or control.StateSpace, optional
        A linear SISO controller C(s) in the loop ``u = C(r + feedback*y)``; it
        replaces the model file's controller.
    feedback : {-1, 1}
        Sign of the feedback of ``controller`` (default negative).
    proof : {"interval", "float", "none"}
        Level of proof (default ``"interval"``), see :func:`gfrf.stability.theorem1.theorem1`.
    norms : {"none", "fast", "tight"}, optional
        Tightness of the ||H_n|| brackets, default ``"fast"``, as
        :func:`gfrf.stability.criteria.verdict`; the verdict and r* do not depend on it.

    Returns
    -------
    Verdict
    """
    from dataclasses import replace

    from gfrf.model.equation import Model
    from gfrf.model.modelfile import resolve_model
    from gfrf.stability.criteria import verdict as criteria_verdict

    if controller is not None:
        base = resolve_model(model)
        model = replace(base, controller=_controller(controller, feedback, base.plant))
    elif not isinstance(model, Model):
        model = resolve_model(model)
    return criteria_verdict(model, order, amplitude, with_norms, proof, norms=norms)


def threshold(model: Model | ModelFile, *, controller: Any = None, feedback: int = -1,
              order: int = 5, prove: bool = True,
              progress: Callable[[int, int], None] | None = None) -> Threshold:
    """Stable below ``lower`` (proven), unstable at ``upper`` (a witness), unknown between;
    in closed loop with the file's controller or ``controller``.

    :func:`gfrf.twosided.threshold.threshold` with a python-control controller: the loop
    ``u = C(r + feedback*y)`` is the one a model file with that ``[controller]`` (``num``,
    ``den``, ``feedback``) describes, and gives the same numbers.

    Parameters
    ----------
    model : Model or ModelFile
        The plant, or a loaded model file (plant and optional controller).
    controller : control.TransferFunction or control.StateSpace, optional
        A linear SISO controller C(s) of the plant's timebase; it replaces the model
        file's controller. Amplitudes are then those of the reference r.
    feedback : {-1, 1}
        Sign of the feedback of ``controller`` (default negative: ``u = C(r - y)``).
    order : int
        Order of the norms of the verdict behind Theorem 1's (2's) r*.
    prove : bool
        Enclose the witness's escape in ball arithmetic (``upper_proof`` ``"interval"``
        when it succeeds).
    progress : callable, optional
        ``progress(done, total)`` during the falsifier's search.

    Returns
    -------
    Threshold

    Examples
    --------
    >>> import control, gfrf
    >>> plant = gfrf.parse_model("D(y) + y + y**3 = u")
    >>> gfrf.threshold(plant, controller=control.tf([2], [1])).lower
    inf
    >>> gfrf.threshold(plant, controller=control.tf([2], [1]), feedback=1).upper
    0.0
    """
    from dataclasses import replace

    from gfrf.model.modelfile import resolve_model
    from gfrf.twosided.threshold import threshold as twosided_threshold

    if controller is not None:
        base = resolve_model(model)
        model = replace(base, controller=_controller(controller, feedback, base.plant))
    return twosided_threshold(model, order=order, prove=prove, progress=progress)
