"""Volterra prediction of the steady-state output for multi-tone inputs, and its check.

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
and :func:`select_order` refuse it first (:class:`NoSteadyStateError`; ``force=True``
again predicts with a warning).  Limits are checked before any work: the order against
:data:`gfrf.kernels.recursion.MAX_KERNEL_ORDER` and the number of intermodulation products
against :data:`MAX_PRODUCTS`; a non-finite component is refused, never returned.

The independent check is the simulated steady state: for commensurate tones
(w_k = m_k w_0) the steady state is periodic with period 2 pi / w_0, found here by
Newton shooting on the period map (DOP853 at rtol 1e-12), so no transient has to
decay, and its FFT over exactly one period is exact for the harmonics m w_0.
The truncation error of the order-N prediction falls like A^(N+1), or like A^(N+2)
when H_{N+1} vanishes (odd systems such as the pendulum): :func:`error_vs_amplitude`
measures it, :func:`figure_error_vs_amplitude` draws it.

:func:`select_order` picks the smallest N whose truncation bound
``sum_{n>N} sup|H_n| (sum_k A_k)^n`` (upper bounds of :func:`gfrf.bounds.norms.kernel_norm`)
is below a tolerance; since |sum c_i| <= sum_k A_k this bounds the sup-norm error of
the steady state while the series converges.

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
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from gfrf._results import short_repr
from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.kernels.recursion import MAX_KERNEL_ORDER, generator, kernel
from gfrf.model.equation import Model
from gfrf.model.signals import Tone, tones_input
from gfrf.sim.integrate import MAX_RHS_EVALUATIONS, OdeSystem, input_values
from gfrf.sim.simulation import build_system

__all__ = ["Component", "VolterraPrediction", "BeyondRadiusError", "NoSteadyStateError",
           "predict",
           "input_amplitude", "series_radius", "PROOF_WORDS", "intermodulation_count",
           "MAX_PRODUCTS",
           "SteadyState", "steady_state", "compare", "error_vs_amplitude",
           "figure_error_vs_amplitude", "OrderChoice", "select_order", "base_frequency"]

#: Largest number of intermodulation products (multisets of signed tones, summed over
#: the orders with a structurally non-zero kernel) that :func:`predict` evaluates.
#: Checked before any kernel is built; at the limit a prediction takes a few seconds
#: and a few hundred MB.
MAX_PRODUCTS = 500_000
#: Multisets evaluated per vectorised chunk (bounds the temporaries of the kernels).
_CHUNK = 20_000


@dataclass(frozen=True)
class Component:
    """One output frequency of a prediction: ``amplitude * cos(omega t + phase)``.

    ``omega`` in rad/s; ``by_order`` maps n to the complex phasor contributed by H_n
    (the full phasor is ``value``, y = 2 Re(value e^{j omega t}) for omega > 0).
    """

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

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready row."""
        return {"omega": self.omega, "frequency_hz": self.omega / (2 * math.pi),
                "amplitude": self.amplitude, "phase": self.phase,
                "by_order": {str(n): abs(v) * (1 if self.omega == 0 else 2)
                             for n, v in self.by_order.items()}}


@dataclass(frozen=True)
class VolterraPrediction:
    """The order-N Volterra steady state of a multi-tone input (see module docstring).

    ``amplitude`` is the input amplitude the series is judged by: the sum of the tone
    amplitudes, the sup of |u(t)| over t and the tones' phases.  ``radius`` is r* of the
    series, of the kind ``radius_proof`` names (:data:`PROOF_WORDS`); ``warning`` is set
    when the prediction was forced without a steady state (unstable linear part) or at an
    amplitude at or beyond r*, where the series is not known to converge.
    """

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
        """The component at angular frequency ``omega`` (rad/s), None if absent."""
        for c in self.components:
            if abs(c.omega - omega) <= 1e-9 * max(1.0, abs(omega)):
                return c
        return None

    def waveform(self, t: Any, derivative: int = 0) -> np.ndarray:
        """The predicted steady state (or its time derivative) at times ``t`` in seconds."""
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

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {"tones": [list(x) for x in self.tones], "order": self.order,
                "amplitude": self.amplitude, "radius": self.radius,
                "radius_certified": self.radius_certified, "radius_proof": self.radius_proof,
                "warning": self.warning,
                "components": [c.to_dict() for c in self.components]}


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
    """
    return float(sum(abs(a) for a, _, _ in _check_tones(tones)))


#: How each proof level of a radius is named in text.
PROOF_WORDS = {"interval": "proven", "float": "certified (float)", "none": "estimated"}


def series_radius(model: Model) -> tuple[float, float, str]:
    """(r*, certified_below, proof) of the Volterra series of ``model``: the radius of the
    norm series that ``gfrf verdict`` reports (:func:`gfrf.bounds.majorant.plant_radius`), so the
    series converges for every input amplitude below ``certified_below`` (within 1e-10
    of r*).  ``proof`` is ``"interval"`` (proven), ``"float"`` or ``"none"`` (estimate).
    """
    from gfrf.bounds.majorant import majorant, plant_radius

    rad = plant_radius(majorant(model))
    return rad.value, rad.certified_below, rad.proof


def intermodulation_count(model: Model, n_tones: int, order: int) -> int:
    """Number of intermodulation products :func:`predict` evaluates.

    One product per multiset of n of the 2 ``n_tones`` signed tones, for every order
    n <= ``order`` whose kernel is not structurally zero: ``sum_n C(2K + n - 1, n)``.
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
    tones : sequence of (A, omega, phi)
        Input ``sum A cos(omega t + phi)``, omega in rad/s, phi in rad.  Its amplitude
        is ``sum |A|`` (:func:`input_amplitude`).
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
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ArgumentError(f"order must be a positive integer, got {order!r}")
    if order > MAX_KERNEL_ORDER:
        raise ArgumentError(f"order {order} exceeds MAX_KERNEL_ORDER = {MAX_KERNEL_ORDER}")
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
        kind = PROOF_WORDS[proof]
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
    comps = tuple(Component(keys[key], sum(row.values()), row)
                  for key, row in sorted(table.items()))
    bad = [c.omega for c in comps if not cmath.isfinite(c.value)]
    if bad:
        raise ArgumentError(f"the prediction is not finite (overflow) at omega = {bad[0]:.6g} "
                            f"rad/s for input amplitude {amplitude:.6g}")
    return VolterraPrediction(tones, order, comps, amplitude, r_star, proof,
                              "; ".join(cautions) or None)


def _truncate(p: VolterraPrediction, order: int) -> VolterraPrediction:
    """The order-``order`` prediction from the per-order terms of a higher-order one."""
    comps = []
    for c in p.components:
        row = {n: v for n, v in c.by_order.items() if n <= order}
        if row:
            comps.append(Component(c.omega, sum(row.values()), row))
    return VolterraPrediction(p.tones, order, tuple(comps))


def base_frequency(tones: Any, max_denominator: int = 1000) -> float:
    """Largest w0 (rad/s) of which every tone frequency is an integer multiple.

    Raises
    ------
    ArgumentError
        If the frequencies are not commensurate within ``max_denominator``.
    """
    tones = _check_tones(tones)
    w_ref = tones[0][1]
    ratios = [Fraction(w / w_ref).limit_denominator(max_denominator) for _, w, _ in tones]
    for (_, w, _), r in zip(tones, ratios, strict=True):
        if abs(float(r) * w_ref - w) > 1e-9 * w:
            raise ArgumentError(f"tone frequencies {[t[1] for t in tones]} rad/s are not "
                                f"commensurate: the steady state is not periodic")
    lcm_den = math.lcm(*(r.denominator for r in ratios))
    gcd_num = math.gcd(*(r.numerator * (lcm_den // r.denominator) for r in ratios))
    return w_ref * gcd_num / lcm_den


@dataclass(frozen=True)
class SteadyState:
    """A periodic steady state found by shooting: one period sampled at ``t`` (s)."""

    t: np.ndarray
    y: np.ndarray
    omega0: float
    residual: float
    iterations: int

    def harmonic(self, m: int) -> complex:
        """Phasor Y(m omega0) from the FFT over one period (y = 2 Re(Y e^{j m w0 t}))."""
        return complex(np.fft.rfft(self.y)[m] / self.y.size)


def steady_state(system: OdeSystem, tones: Any, *, samples: int = 256,
                 guess: np.ndarray | None = None, tol: float = 1e-12,
                 max_iter: int = 20, max_evaluations: int = MAX_RHS_EVALUATIONS
                 ) -> SteadyState:
    """Periodic steady state of ``system`` under a commensurate multi-tone input.

    Newton's method on z -> Phi(z) - z, Phi the period map (DOP853, rtol 1e-12),
    with a finite-difference Jacobian.  All integrations together may evaluate the
    right-hand side at most ``max_evaluations`` times (default
    :data:`gfrf.sim.integrate.MAX_RHS_EVALUATIONS`; tones 1000 times apart need about that).

    Raises
    ------
    ConvergenceError
        If the shooting residual does not fall below ``tol`` (times the state size), or
        the work budget is spent first.
    """
    tones = _check_tones(tones)
    w0 = base_frequency(tones)
    period = 2 * math.pi / w0
    signal = tones_input(tones)
    rhs = system.function("rhs")
    count = [0]

    def f(t: float, z: np.ndarray) -> np.ndarray:
        count[0] += 1
        if count[0] > max_evaluations:
            raise ConvergenceError(f"shooting stopped: the period maps of the common period "
                                   f"{period:.6g} s used the work budget max_evaluations = "
                                   f"{max_evaluations} right-hand-side evaluations")
        out = np.empty(system.n_states)
        rhs(z, input_values(signal, 1, np.array([t]))[:, 0], out)
        return out

    def flow(z: np.ndarray, t_eval: np.ndarray | None = None) -> Any:
        return solve_ivp(f, (0.0, period), z, method="DOP853", rtol=1e-12, atol=1e-14,
                         t_eval=t_eval)

    z = np.zeros(system.n_states) if guess is None else np.array(guess, dtype=float)
    scale = 1.0
    for iteration in range(1, max_iter + 1):  # noqa: B007 - reported after the loop
        end = flow(z).y[:, -1]
        g = end - z
        scale = max(1e-300, float(np.max(np.abs(z))), float(np.max(np.abs(end))))
        if np.max(np.abs(g)) <= tol * scale:
            break
        jac = np.empty((z.size, z.size))
        for i in range(z.size):
            dz = np.zeros_like(z)
            dz[i] = 1e-7 * scale
            jac[:, i] = (flow(z + dz).y[:, -1] - z - dz - g) / dz[i]
        z = z - np.linalg.solve(jac, g)
    else:
        raise ConvergenceError(f"shooting did not converge: residual {np.max(np.abs(g)):.3g}")
    t = np.arange(samples) * period / samples
    sol = flow(z, t)
    return SteadyState(t=t, y=sol.y[0], omega0=w0, residual=float(np.max(np.abs(g))),
                       iterations=iteration)


def compare(model: Model, tones: Any, orders: tuple[int, ...] = (1, 3, 5), *,
            samples: int = 256) -> dict[str, Any]:
    """Sup-norm error of each order's prediction against the shot steady state.

    Returns
    -------
    dict
        ``{"errors": {N: max_t |y_sim - y_N|}, "steady_state": SteadyState}``.
    """
    system = build_system(model, equation="polynomial")
    best = predict(model, tones, max(orders))
    guess = np.array([best.waveform(0.0, d) for d in range(system.order)])
    ss = steady_state(system, tones, samples=samples, guess=guess)
    errors = {n: float(np.max(np.abs(ss.y - _truncate(best, n).waveform(ss.t))))
              for n in orders}
    return {"errors": errors, "steady_state": ss}


def error_vs_amplitude(model: Model, omega: float, amplitudes: Any,
                       orders: tuple[int, ...] = (1, 3, 5)) -> dict[str, Any]:
    """Prediction error against amplitude for a sinusoid ``A cos(omega t)`` (rad/s).

    Returns ``{"amplitudes", "errors": {N: [...]}, "slopes": {N: fitted log-log slope}}``.
    """
    amplitudes = np.asarray(amplitudes, dtype=float)
    errors: dict[int, list[float]] = {n: [] for n in orders}
    for a in amplitudes:
        res = compare(model, [(float(a), omega, 0.0)], orders)
        for n in orders:
            errors[n].append(res["errors"][n])
    slopes = {n: float(np.polyfit(np.log(amplitudes), np.log(errors[n]), 1)[0])
              for n in orders}
    return {"omega": omega, "amplitudes": amplitudes.tolist(), "errors": errors,
            "slopes": slopes}


def figure_error_vs_amplitude(out_path: str, model: Model | None = None,
                              omega: float = math.sqrt(2.45),
                              amplitudes: Any = None) -> dict[str, Any]:
    """Write the log-log figure of Volterra error vs input amplitude (1, 3, 5 terms).

    Defaults: the hanging pendulum (rho = 0.8, polynomial model) driven at its H1 peak
    omega = sqrt(2.45) rad/s (0.249 Hz), amplitudes 1e-3 .. 8e-3 N m.

    Returns
    -------
    dict
        The data of :func:`error_vs_amplitude` plus ``"figure": out_path``.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if model is None:
        from pathlib import Path

        from gfrf.model.modelfile import load_model
        model = load_model(Path(__file__).resolve().parent.parent / "models"
                           / "hanging_pendulum.toml").plant
    amplitudes = np.geomspace(1e-3, 8e-3, 6) if amplitudes is None else amplitudes
    data = error_vs_amplitude(model, omega, amplitudes)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for n, errs in data["errors"].items():
        ax.loglog(data["amplitudes"], errs, "o-",
                  label=f"N = {n} (slope {data['slopes'][n]:.2f})")
    ax.set_xlabel("input amplitude A (N m)")
    ax.set_ylabel("max |y_sim - y_N| over a period (rad)")
    ax.set_title(f"Volterra prediction error, sinusoid at {omega:.4g} rad/s")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out_path, dpi=120)
    plt.close(fig)
    return {**data, "figure": str(out_path)}


@dataclass(frozen=True)
class OrderChoice:
    """Result of :func:`select_order`: N, its tail bound and the terms sup|H_n| A^n.

    ``certified`` is False whenever the tail beyond ``max_order`` is extrapolated.
    """

    order: int
    bound: float
    amplitude: float
    tolerance: float
    terms: dict[int, float] = field(default_factory=dict)
    certified: bool = False
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description."""
        return {"order": self.order, "bound": self.bound, "amplitude": self.amplitude,
                "tolerance": self.tolerance, "certified": self.certified, "note": self.note,
                "terms": {str(n): v for n, v in self.terms.items()}}


def select_order(model: Model, amplitude: float, tolerance: float,
                 max_order: int = 7) -> OrderChoice:
    """Smallest N with ``sum_{n>N} sup|H_n| A^n < tolerance`` (upper norm bounds).

    Parameters
    ----------
    amplitude : float
        Peak input amplitude A (for a multi-tone input, the sum of the tone amplitudes).
    tolerance : float
        Allowed sup-norm error of the steady-state output.
    max_order : int
        Highest kernel order whose norm is bounded; the tail beyond it is a geometric
        extrapolation of the last two non-zero terms (then ``certified`` is False).

    Raises
    ------
    NoSteadyStateError
        The linear part has a pole on or beyond the stability boundary.
    BeyondRadiusError
        The amplitude is at or beyond the series radius r* (no truncation bound holds).
    ArgumentError
        Non-positive amplitude or tolerance, or no N <= max_order meets the tolerance.
    """
    from gfrf.bounds.norms import kernel_norm

    if not (amplitude > 0 and tolerance > 0):
        raise ArgumentError("amplitude and tolerance must be positive")
    problem = _steady_state_problem(model)
    if problem is not None:
        raise NoSteadyStateError(problem)
    r_star, inside, _ = series_radius(model)
    if amplitude >= inside:
        raise BeyondRadiusError(f"amplitude {amplitude:.6g} is at or beyond the series radius "
                                f"r* = {r_star:.6g}: no truncation order bounds the error",
                                amplitude, r_star)
    terms = {n: 0.0 if kernel(model, n).is_zero else
             float(kernel_norm(model, n).upper) * amplitude**n for n in range(1, max_order + 1)}
    nonzero = [v for v in terms.values() if v > 0]
    ratio = nonzero[-1] / nonzero[-2] if len(nonzero) >= 2 else 0.0
    beyond = nonzero[-1] * ratio / (1 - ratio) if ratio < 1 else math.inf
    for order in range(1, max_order + 1):
        bound = sum(v for n, v in terms.items() if n > order) + beyond
        if bound < tolerance:
            note = (f"orders <= {max_order} from upper norm bounds, beyond that a geometric "
                    f"extrapolation (ratio {ratio:.3g})")
            return OrderChoice(order, bound, amplitude, tolerance, terms, False, note)
    raise ArgumentError(f"no kernel order <= {max_order} meets tolerance {tolerance:g} at "
                        f"amplitude {amplitude:g} (series ratio {ratio:.3g})")
