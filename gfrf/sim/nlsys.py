"""A model file as a python-control ``NonlinearIOSystem``, for python-control simulations.

:func:`to_nlsys` wraps the state form that :func:`gfrf.sim.system.build_system`
generates (the same right-hand side :func:`gfrf.simulate` integrates), so
``control.input_output_response`` and :func:`gfrf.simulate` solve the same equations.

Continuous models give a continuous system with states y, y', ..., y^(n-1) (then the
controller's states) and the plant input u (open loop) or the reference r (closed loop)
as input.  A NARX model gives a discrete system (``dt`` = its sample time) whose state
holds the past outputs (then, in a loop, the past controller outputs) and the past
inputs it reads; its output has a direct feedthrough when y[k] depends on u[k].

Examples
--------
>>> import numpy as np, control
>>> from gfrf.model.equation import parse_model
>>> sys = to_nlsys(parse_model("D(y) + y + y**3 = u"))
>>> sys.ninputs, sys.noutputs, sys.nstates
(1, 1, 1)
>>> float(sys.dynamics(0.0, np.array([1.0]), np.array([2.0])))  # -y - y^3 + u
0.0
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from gfrf.errors import ModelError

if TYPE_CHECKING:
    import control

    from gfrf.model.equation import Model
    from gfrf.model.modelfile import ModelFile
    from gfrf.sim.integrate import OdeSystem

__all__ = ["to_nlsys"]


def to_nlsys(model: Model | ModelFile, closed_loop: bool = False, *,
             equation: str = "physical", name: str | None = None
             ) -> control.NonlinearIOSystem:
    """The model as a ``control.NonlinearIOSystem`` (plant, or closed loop).

    Parameters
    ----------
    model : Model or ModelFile
        A model (:func:`gfrf.parse_model`) or a loaded model file
        (:func:`gfrf.load_model`; needed for ``closed_loop``).
    closed_loop : bool, optional
        Close the loop with the model file's controller, ``u = C(r + feedback*y)``;
        the input is then the reference r and the outputs are y and the plant input u.
    equation : {"physical", "polynomial"}
        The untruncated equation of the file (when it has one) or the truncated
        polynomial model the GFRFs describe, as in :func:`gfrf.simulate`.
    name : str, optional
        The system's name (default: the model file's name, else python-control's).

    Returns
    -------
    control.NonlinearIOSystem
        Continuous (``dt=0``), or discrete with ``dt`` = the sample time for NARX.
        Input named after the model's input (``r`` in closed loop); outputs the model's
        output (and its input in closed loop).  The ``params`` argument is ignored.

    Raises
    ------
    ModelError
        A continuous model that reads derivatives of its input, or a loop whose
        controller is improper (it reads derivatives of the reference): python-control
        gives the system its input only; a closed loop without a controller; the errors
        of :func:`gfrf.sim.system.build_system`.

    Examples
    --------
    >>> import gfrf
    >>> sys = gfrf.to_nlsys(gfrf.parse_model("D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"))
    >>> sys.state_labels
    ['y', 'D(y,1)']
    """
    import control

    from gfrf.model.equation import Model
    from gfrf.model.modelfile import ModelFile, as_plant, resolve_model
    from gfrf.sim.system import build_system

    source = model if isinstance(model, Model) else resolve_model(model)
    plant = as_plant(source)
    system = build_system(source, closed_loop=closed_loop, equation=equation)
    inputs = ["r"] if closed_loop else [plant.input]
    outputs = [plant.output] + ([plant.input] if closed_loop else [])
    if name is None and isinstance(source, ModelFile) and source.name:
        name = source.name
    kwargs: dict[str, Any] = {"inputs": inputs, "outputs": outputs, "name": name}
    if system.discrete:
        update, output, states = _discrete(system, plant.output, closed_loop)
        return control.nlsys(update, output, states=states, dt=system.sample_time,
                             **kwargs)
    if system.n_inputs > 1:
        what = ("the closed loop u = C(r - y) with an improper controller reads derivatives "
                "of the reference r" if closed_loop else
                f"the model reads derivatives of its input (D({plant.input},k))")
        raise ModelError(f"{what}; a python-control system gets the input only: no "
                         f"NonlinearIOSystem")
    update, output = _continuous(system, closed_loop)
    y = plant.output
    states = [y] + [f"D({y},{k})" for k in range(1, system.order)]
    states += [f"xc{i}" for i in range(system.n_states - system.order)]
    return control.nlsys(update, output, states=states, **kwargs)


Function = Callable[[float, np.ndarray, np.ndarray, Any], np.ndarray]


def _continuous(system: OdeSystem, closed_loop: bool) -> tuple[Function, Function]:
    """``updfcn`` and ``outfcn`` of a continuous system from its generated ``rhs``."""
    rhs, plant_input = system.function("rhs"), system.function("plant_input")

    def rates(x: np.ndarray, u: np.ndarray) -> np.ndarray:
        out = np.empty(system.n_states)
        try:
            rhs(np.asarray(x, dtype=float), [float(u[0])], out)
        except ZeroDivisionError:  # the implicit loop's coefficient vanished
            out[:] = np.nan
        return out

    def update(t: float, x: np.ndarray, u: np.ndarray, params: Any = None) -> np.ndarray:
        return rates(x, np.atleast_1d(u))

    def output(t: float, x: np.ndarray, u: np.ndarray, params: Any = None) -> np.ndarray:
        if not closed_loop:
            return np.array([x[0]])
        u = np.atleast_1d(u)
        dz = rates(x, u)
        return np.array([x[0], plant_input(np.asarray(x, dtype=float), [float(u[0])], dz)])

    return update, output


def _discrete(system: OdeSystem, y: str, closed_loop: bool
              ) -> tuple[Function, Function, list[str]]:
    """``updfcn``, ``outfcn`` and state names of a NARX recursion.

    The generated state (y[k-1..k-a], then in a loop w[k-1..k-b]) is followed by the
    input lags u[k-1..k-q] (r in a loop) that ``rhs`` reads.
    """
    rhs, plant_input = system.function("rhs"), system.function("plant_input")
    n, a, lags = system.n_states, system.order, system.n_inputs - 1
    width = 2 if closed_loop else 1
    v_name = "r" if closed_loop else "u"
    states = [f"{y}[k-{i}]" for i in range(1, a + 1)]
    states += [f"w[k-{i}]" for i in range(1, n - a + 1)]
    states += [f"{v_name}[k-{i}]" for i in range(1, lags + 1)]

    def step(x: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, list[float], np.ndarray]:
        x = np.asarray(x, dtype=float)
        v = [float(np.atleast_1d(u)[0]), *x[n:]]
        out = np.empty(width)
        rhs(x[:n], v, out)
        return x, v, out

    def update(t: float, x: np.ndarray, u: np.ndarray, params: Any = None) -> np.ndarray:
        x, v, out = step(x, u)
        z = x[:n]
        y_part = np.concatenate((out[:1], z[:a][:-1])) if a else z[:0]
        w_part = np.concatenate((out[1:], z[a:][:-1])) if n > a else z[:0]
        return np.concatenate((y_part, w_part, v[:lags]))

    def output(t: float, x: np.ndarray, u: np.ndarray, params: Any = None) -> np.ndarray:
        x, v, out = step(x, u)
        if not closed_loop:
            return out[:1].copy()
        return np.array([out[0], plant_input(x[:n], v, out)])

    return update, output, states
