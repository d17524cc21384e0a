"""Volterra prediction of the steady-state output for multi-tone inputs.

For an input ``u(t) = sum_k A_k cos(w_k t + phi_k)`` (w in rad/s) write u as a sum of
phasors ``c e^{j w t}`` over the 2K signed tones (c = A/2 e^{+-j phi}).  The n-th order
Volterra term of the steady state is

    y_n(t) = sum over n-tuples of signed tones  H_n(w_1..w_n) c_1...c_n e^{j (w_1+..+w_n) t},

so the prediction of order N collects, for every harmonic and intermodulation
frequency Omega = w_1 + ... + w_n, the complex amplitude Y(Omega) with n <= N.
:func:`predict` returns those components (amplitude and phase of
``|2Y| cos(Omega t + arg Y)``, per-order contributions kept).

Where the prediction is meaningful.  The amplitude of a multi-tone input is the sum
of the tone amplitudes ``sum_k |A_k|``, the sup of |u(t)| over t and over the tones'
phases (:func:`input_amplitude`).
The series converges for amplitudes below the radius r* of the certified majorant
series (:func:`series_radius`, the r* of ``gfrf verdict``); at or beyond r* nothing is
known and a truncated sum can be off by orders of magnitude, so :func:`predict`
refuses (:class:`BeyondRadiusError`) unless ``force=True``, which labels the result
with a ``warning``.  A steady state needs a stable linear part: a plant with a pole
of A on or beyond the stability boundary (decided exactly, :func:`gfrf.bounds.norms.linear_poles`;
e.g. the open-loop cart-pole) has none that the input settles to, and :func:`predict`
and :func:`gfrf.sim.truncation.select_order` refuse it first (:class:`NoSteadyStateError`;
``force=True`` again predicts with a warning).  Limits are checked before any work: the
order against :data:`gfrf.kernels.recursion.MAX_KERNEL_ORDER` and the number of
intermodulation products against :data:`MAX_PRODUCTS`; a non-finite component is
refused, never returned.

The check of the prediction against the simulated steady state, and the choice of the
truncation order, are in :mod:`gfrf.sim.truncation`.

Examples
--------
>>> from gfrf.model.equation import parse_model
>>> lin = parse_model("D(y) + y = u")
>>> p = predict(lin, [(2.0, 1.0, 0.0)], order=1)
>>> c = p.components[0]
>>> round(c.amplitude, 6) == round(2.0 / 2 ** 0.5, 6), round(c.phase, 6)
(True, -0.785398)
"""

from __future__ import annotations

import cmath
import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf._results import PROOF_WORDS, Result, proof_word, short_repr
from gfrf.errors import ArgumentError
from gfrf.kernels.recursion import check_order, generator, kernel
from gfrf.model.equation import Model
from gfrf.model.signals import Tone

__all__ = ["Component", "VolterraPrediction", "BeyondRadiusError", "NoSteadyStateError",
           "predict",
           "input_amplitude", "series_radius", "PROOF_WORDS", "intermodulation_count",
           "MAX_PRODUCTS"]

#: Largest number of intermodulation products (multisets of signed tones, summed over
#: the orders with a structurally non-zero kernel) that :func:`predict` evaluates.
#: Checked before any kernel is built; at the limit a prediction takes a few seconds
#: and a few hundred MB.
MAX_PRODUCTS = 500_000
#: Multisets evaluated per vectorised chunk (bounds the temporaries of the kernels).
_CHUNK = 20_000


@dataclass(frozen=True, kw_only=True)
class Component(Result):
    """One output frequency of a prediction: ``amplitude * cos(omega t + phase)``.

    ``omega`` in rad/s; ``by_order`` maps n to the complex phasor contributed by H_n
    (the full phasor is ``value``, y = 2 Re(value e^{j omega t}) for omega > 0;
    :meth:`to_dict` gives it as ``amplitude`` and ``phase``).
    """

    _exclude = ("value",)
    _order = ("omega", "frequency_hz", "amplitude", "phase", "by_order")

    omega: float
    value: complex
    by_order: dict[int, complex]

    @property
    def amplitude(self) -> float:
        """Amplitude of the real cosine (|Y| at omega = 0, else 2|Y|)."""
        return abs(self.value) * (1.0 if self.omega == 0 else 2.0)

    @property
    def phase(self) -> float:
        """Phase in rad of the cosine."""
        return float(np.angle(self.value))

    def _computed(self) -> dict[str, Any]:
        return {"frequency_hz": self.omega / (2 * math.pi), "amplitude": self.amplitude,
                "phase": self.phase,
                "by_order": {str(n): abs(v) * (1 if self.omega == 0 else 2)
                             for n, v in self.by_order.items()}}


@dataclass(frozen=True, kw_only=True)
class VolterraPrediction(Result):
    """The order-N Volterra steady state of a multi-tone input (see module docstring).

    ``amplitude`` is the input amplitude the series is judged by: the sum of the tone
    amplitudes, the sup of |u(t)| over t and the tones' phases.  ``radius`` is r* of the
    series, of the kind ``radius_proof`` names (:data:`PROOF_WORDS`); ``warning`` is set
    when the prediction was forced without a steady state (unstable linear part) or at an
    amplitude at or beyond r*, where the series is not known to converge.
    """

    _order = ("tones", "order", "amplitude", "radius", "radius_certified", "radius_proof",
              "warning", "components")

    tones: tuple[Tone, ...]
    order: int
    components: tuple[Component, ...]
    amplitude: float = 0.0
    radius: float = math.inf
    radius_proof: str = "interval"
    warning: str | None = None

    @property
    def radius_certified(self) -> bool:
        """True unless r* is only an estimate."""
        return self.radius_proof != "none"

    def component(self, omega: float) -> Component | None:
        """The component at angular frequency ``omega`` (rad/s), None if absent.

        Parameters
        ----------
        omega : float
            Angular frequency in rad/s (matched within a relative 1e-9).

        Returns
        -------
        Component or None
            The component, or None.
        """
        for c in self.components:
            if abs(c.omega - omega) <= 1e-9 * max(1.0, abs(omega)):
                return c
        return None

    def waveform(self, t: Any, derivative: int = 0) -> np.ndarray:
        """The predicted steady state (or its time derivative) at times ``t`` in seconds.

        Parameters
        ----------
        t : array_like
            Times in s.
        derivative : int, optional
            Order of the time derivative, 0 for y itself.

        Returns
        -------
        numpy.ndarray
            Float values, the shape of ``t``.
        """
        t = np.asarray(t, dtype=float)
        y = np.zeros_like(t)
        for c in self.components:
            factor = 1.0 if c.omega == 0 else 2.0
            y += factor * np.real(c.value * (1j * c.omega) ** derivative
                                  * np.exp(1j * c.omega * t))
        return y

    def __repr__(self) -> str:
        return short_repr(self, "order", "amplitude", "radius",
                          components=len(self.components))

    def _repr_markdown_(self) -> str:
        from gfrf.sim.views import prediction_markdown

        return prediction_markdown(self)

    def plot(self, simulated: Any = None) -> Any:
        """The predicted spectrum as stems (rad/s), with the FFT of ``simulated`` (a
        :class:`gfrf.sim.simulation.SimulationResult` or ``(t, y)``) behind it; returns a
        matplotlib Figure made without pyplot (:func:`gfrf.sim.views.prediction_figure`).

        Parameters
        ----------
        simulated : SimulationResult or tuple of array_like, optional
            A simulation, or ``(t, y)`` in s, drawn behind the prediction; None: the
            prediction only.

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from gfrf.sim.views import prediction_figure

        return prediction_figure(self, simulated)

    def _computed(self) -> dict[str, Any]:
        return {"radius_certified": self.radius_certified}


class BeyondRadiusError(ArgumentError):
    """The input amplitude is at or beyond the radius r* of the Volterra series.

    Attributes
    ----------
    amplitude : float
        Sum of the tone amplitudes (the sup of |u| over t and the phases).
    radius : float
        r* of the series.
    """

    def __init__(self, message: str, amplitude: float, radius: float) -> None:
        super().__init__(message)
        self.amplitude = amplitude
        self.radius = radius


class NoSteadyStateError(ArgumentError):
    """The linear part of the model is not asymptotically stable: no steady state exists."""


def _steady_state_problem(model: Model) -> str | None:
    """Why ``model`` has no steady state (a pole of A on or beyond the boundary), or None."""
    from gfrf.bounds.exact import format_roots
    from gfrf.bounds.norms import linear_poles

    report = linear_poles(model)
    if report.stable:
        return None
    name = "z" if model.is_discrete else "s"
    if report.outside:
        region = "|z| > 1" if model.is_discrete else "Re s > 0"
        bad = [complex(r) for r in report.roots
               if (abs(r) > 1 if model.is_discrete else r.real > 0)]
        return (f"the linear part is unstable (pole {format_roots(bad, name)}, {region}): no "
                f"steady state exists (the response to a tone grows)")
    return (f"the linear part has a pole on the stability boundary at "
            f"{format_roots(report.boundary, name)}: no steady state exists (free "
            f"oscillations do not decay)")


def _check_tones(tones: Any) -> tuple[Tone, ...]:
    """Tones as (A, omega, phi) floats; text is read as ``gfrf predict --input`` reads it."""
    if isinstance(tones, str):
        from gfrf.model.signals import parse_input

        parsed = parse_input(tones).tones
        if not parsed:
            raise ArgumentError(f"input {tones!r} is not a sum of sinusoids "
                                f"A*sin(w*t + p) / A*cos(w*t + p)")
        tones = parsed
    try:
        out = tuple((float(a), float(w), float(p)) for a, w, p in tones)
    except (TypeError, ValueError):
        raise ArgumentError("tones must be (amplitude, omega rad/s, phase rad) triples") \
            from None
    if not out or not all(math.isfinite(x) for tone in out for x in tone):
        raise ArgumentError(f"need at least one finite tone, got {tones!r}")
    if any(w <= 0 for _, w, _ in out):
        raise ArgumentError("tone angular frequencies must be positive (rad/s)")
    return out


def input_amplitude(tones: Any) -> float:
    """Amplitude of a sum of tones: ``sum_k |A_k|``, the sup of |u(t)| over t and phases.

    It bounds sup_t |u(t)| for the given phases and equals it when the tones can line
    up (e.g. incommensurate frequencies); it is the amplitude r at which the series
    sum_n ||H_n|| r^n bounds the output (|sum of the phasors| <= sum_k |A_k|).

    Parameters
    ----------
    tones : str or sequence of tuple
        ``(A, omega, phi)`` per tone (omega in rad/s, phi in rad), or input text such as
        ``"0.1*cos(2*t) + 0.05*sin(3*t)"``.

    Returns
    -------
    float
        ``sum_k |A_k|``.
    """
    return float(sum(abs(a) for a, _, _ in _check_tones(tones)))


def series_radius(model: Model) -> tuple[float, float, str]:
    """(r*, certified_below, proof) of the Volterra series of ``model``: the radius of the
    norm series that ``gfrf verdict`` reports (:func:`gfrf.bounds.majorant.plant_radius`), so the
    series converges for every input amplitude below ``certified_below`` (within 1e-10
    of r*).  ``proof`` is ``"interval"`` (proven), ``"float"`` or ``"none"`` (estimate).

    Parameters
    ----------
    model : Model
        The plant model.

    Returns
    -------
    tuple of (float, float, str)
        r*, the amplitude below which convergence is certified, and the proof level.
    """
    from gfrf.bounds.majorant import majorant, plant_radius

    rad = plant_radius(majorant(model))
    return rad.value, rad.certified_below, rad.proof


def intermodulation_count(model: Model, n_tones: int, order: int) -> int:
    """Number of intermodulation products :func:`predict` evaluates.

    One product per multiset of n of the 2 ``n_tones`` signed tones, for every order
    n <= ``order`` whose kernel is not structurally zero: ``sum_n C(2K + n - 1, n)``.

    Parameters
    ----------
    model : Model
        The plant model.
    n_tones : int
        Number of tones K of the input.
    order : int
        Highest order of the truncated series.

    Returns
    -------
    int
        The number of products.
    """
    gen = generator(model)
    return sum(math.comb(2 * n_tones + n - 1, n) for n in range(1, order + 1)
               if gen.structurally_nonzero(n))


def _multisets(size: int, n: int) -> Iterator[np.ndarray]:
    """Sorted index n-tuples of range(size) (multisets), in chunks of :data:`_CHUNK` rows."""
    source = itertools.combinations_with_replacement(range(size), n)
    while chunk := list(itertools.islice(source, _CHUNK)):
        yield np.array(chunk, dtype=np.int64).reshape(len(chunk), n)


def predict(model: Model, tones: Any, order: int, *, force: bool = False
            ) -> VolterraPrediction:
    """Volterra prediction of order ``order`` of the steady state for ``tones``.

    The symmetric kernel takes the same value on every ordering of a tuple of tones, so
    each multiset of tones is evaluated once with its multiplicity n! / prod m_i!, in
    chunks (memory bounded by the number of output frequencies).

    Parameters
    ----------
    model : Model
        A polynomial model with a stable linear part.
    tones : sequence of (A, omega, phi), or str
        Input ``sum A cos(omega t + phi)``, omega in rad/s, phi in rad, or its text as
        ``gfrf predict --input`` takes it (``"0.01*sin(1.565*t)"``).  Its amplitude is
        ``sum |A|`` (:func:`input_amplitude`).
    order : int
        Highest kernel order N, 1 <= N <= :data:`gfrf.kernels.recursion.MAX_KERNEL_ORDER`.
    force : bool, optional
        Predict even without a steady state (unstable linear part) or at an amplitude
        at or beyond the series radius r*; the result then carries a ``warning``.

    Returns
    -------
    VolterraPrediction
        Components at every frequency ``Omega >= 0`` reached by n <= N tones.

    Raises
    ------
    NoSteadyStateError
        The linear part has a pole on or beyond the stability boundary (no steady state
        exists) and ``force`` is False.
    BeyondRadiusError
        The amplitude is at or beyond r* (the series is not known to converge there;
        the truncated sum can be off by orders of magnitude) and ``force`` is False.
    ArgumentError
        Bad tones or order, more than :data:`MAX_PRODUCTS` intermodulation products,
        or a non-finite predicted component.
    """
    tones = _check_tones(tones)
    check_order(order)
    count = intermodulation_count(model, len(tones), order)
    if count > MAX_PRODUCTS:
        raise ArgumentError(f"{len(tones)} tones to order {order} give {count} "
                            f"intermodulation products, above MAX_PRODUCTS = {MAX_PRODUCTS} "
                            f"(gfrf.sim.volterra): use fewer tones or a lower order")
    amplitude = input_amplitude(tones)
    cautions: list[str] = []
    problem = _steady_state_problem(model)
    if problem is not None:
        if not force:
            raise NoSteadyStateError(problem)
        cautions.append(problem)
    r_star, inside, proof = series_radius(model)
    if amplitude >= inside:
        kind = proof_word(proof)
        warning = (f"input amplitude {amplitude:.6g} (sum of the tone amplitudes, the peak |u| "
                   f"over all phases) is at or beyond the {kind} radius r* = {r_star:.6g} of "
                   f"the Volterra series: the series is not known to converge and the "
                   f"prediction may be meaningless")
        if not force:
            raise BeyondRadiusError(warning, amplitude, r_star)
        cautions.append(warning)
    omegas = np.array([s * w for _, w, _ in tones for s in (1, -1)])
    phasors = np.array([a / 2 * np.exp(s * 1j * p) for a, _, p in tones for s in (1, -1)])
    table: dict[float, dict[int, complex]] = {}
    keys: dict[float, float] = {}
    for n in range(1, order + 1):
        k = kernel(model, n)
        if k.is_zero:
            continue
        for idx in _multisets(omegas.size, n):
            run = np.ones(idx.shape)
            for j in range(1, n):
                run[:, j] = np.where(idx[:, j] == idx[:, j - 1], run[:, j - 1] + 1, 1)
            weight = math.factorial(n) / np.prod(run, axis=1)
            w = omegas[idx]
            total = w.sum(axis=1)
            keep = total >= -1e-12
            if not keep.any():
                continue
            idx, w, total, weight = idx[keep], w[keep], total[keep], weight[keep]
            with np.errstate(over="ignore", invalid="ignore"):  # checked below
                values = weight * k(*w.T) * np.prod(phasors[idx], axis=1)
            rounded, first, inverse = np.unique(np.round(total, 9), return_index=True,
                                                return_inverse=True)
            sums = (np.bincount(inverse, values.real, rounded.size)
                    + 1j * np.bincount(inverse, values.imag, rounded.size))
            for key, start, value in zip(rounded.tolist(), first.tolist(), sums.tolist(),
                                         strict=True):
                keys.setdefault(key, max(float(total[start]), 0.0))
                row = table.setdefault(key, {})
                row[n] = row.get(n, 0j) + value
    comps = tuple(Component(omega=keys[key], value=sum(row.values()), by_order=row)
                  for key, row in sorted(table.items()))
    bad = [c.omega for c in comps if not cmath.isfinite(c.value)]
    if bad:
        raise ArgumentError(f"the prediction is not finite (overflow) at omega = {bad[0]:.6g} "
                            f"rad/s for input amplitude {amplitude:.6g}")
    return VolterraPrediction(tones=tones,
                              order=order,
                              components=comps,
                              amplitude=amplitude,
                              radius=r_star,
                              radius_proof=proof,
                              warning="; ".join(cautions) or None)
