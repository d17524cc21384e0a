"""Frequency response curves: :func:`frc` and its result, :class:`FrequencyResponseCurve`.

:func:`frc` balances the model with H harmonics (:mod:`.balance`), solves it at the
start of the range by Newton (from H1 times the forcing, or by raising the forcing in
steps when that fails), follows the branch by pseudo-arclength continuation through its
folds (:mod:`.continuation`), decides the stability of every point by Hill's method
(:mod:`.hill`) and adds the backbone of the unforced undamped system (:mod:`.backbone`).
Every number is an ``estimate``: a truncated Fourier series solved in floating point;
the result reports how far the neglected harmonics are from zero (the time-domain
residual above H divided by the linear part there) so the user knows when to raise H.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf._results import Result, markdown_table, new_figure, short_repr
from gfrf.errors import ArgumentError, ConvergenceError
from gfrf.harmonic.backbone import backbone_curve
from gfrf.harmonic.balance import Balance
from gfrf.harmonic.continuation import Point, Tracer, newton_fixed
from gfrf.harmonic.hill import floquet_multipliers
from gfrf.model.equation import Model

__all__ = ["frc", "FrequencyResponseCurve", "CurvePoint", "DEFAULT_HARMONICS",
           "MAX_POINTS"]

#: Harmonics kept by default: odd and even up to the 9th, enough for the textbook
#: Duffing curves to 1e-6 relative (the reported truncation estimate says when not).
DEFAULT_HARMONICS = 9
#: Multipliers within this of the unit circle are not counted stable (an undamped
#: system's are on it, up to rounding).
MARGINAL = 1e-9
#: Frequencies accepted, rad/s (beyond them the powers (j k omega)^l of a model's
#: derivatives leave the float range long before anything physical happens).
OMEGA_LIMITS = (1e-6, 1e6)
#: Largest forcing amplitude accepted.
MAX_AMPLITUDE = 1e6
#: Root-finder iterations locating a period doubling.
PD_ITERATIONS = 30
#: Most points of one continuation.
MAX_POINTS = 20_000
#: Most work of one curve: points times (d (2H + 1))^3, d the output order or largest
#: lag (each point's Hill eigenproblem; 400 points of a Duffing curve with H = 9 are
#: about 2e7 and take about a second).
MAX_WORK = 1_000_000_000


@dataclass(frozen=True, kw_only=True, repr=False)
class CurvePoint(Result):
    """One periodic solution on the curve.

    ``to_dict`` is the contract's point: omega, amplitude, stable and the coefficients as
    :meth:`pairs`; it leaves out ``forcing`` (listed under the curve's ``forcing``),
    ``multipliers`` (their verdict is ``stable``) and ``tail`` (the point's truncation
    estimate: the curve's ``truncation`` is their largest).

    Attributes
    ----------
    omega : float
        Forcing frequency, rad/s.
    forcing : float
        Forcing amplitude A of ``u = A cos(omega t)``.
    coefficients : ndarray
        ``(a0, a1, b1, ..., aH, bH)``.
    stable : bool
        Every Floquet multiplier inside the unit circle (Hill's method).
    multipliers : tuple of complex
        The Floquet multipliers over one forcing period (empty when undefined).
    tail : float
        Estimated amplitude of the neglected harmonics above H.
    """

    omega: float
    forcing: float
    coefficients: np.ndarray
    stable: bool
    multipliers: tuple[complex, ...]
    tail: float

    _exclude = ("forcing", "multipliers", "tail")
    _order = ("omega", "amplitude", "stable", "coefficients")

    @property
    def amplitude(self) -> float:
        """Magnitude of the first harmonic, sqrt(a1^2 + b1^2)."""
        return float(math.hypot(self.coefficients[1], self.coefficients[2]))

    def pairs(self) -> list[list[float]]:
        """``[[a0, 0], [a1, b1], ..., [aH, bH]]``."""
        c = self.coefficients
        return [[float(c[0]), 0.0]] + [[float(c[i]), float(c[i + 1])]
                                       for i in range(1, c.size, 2)]

    def _computed(self) -> dict[str, Any]:
        """The amplitude and the coefficients as pairs."""
        return {"amplitude": self.amplitude, "coefficients": self.pairs()}


@dataclass(frozen=True, kw_only=True, repr=False)
class FrequencyResponseCurve(Result):
    """A branch of periodic steady states under ``u = A cos(omega t)`` (harmonic balance).

    ``to_dict`` is the contract (harmonics, points, folds as omega and amplitude) and the
    extras: ``kind`` (always an estimate), each point's and fold's forcing, the backbone
    as ``{omega, amplitude, peak}``.

    Attributes
    ----------
    equation : str
        The model's equation.
    harmonics : int
        H.
    samples : int
        Time samples per period of the alternating frequency-time scheme.
    vary : str
        ``"omega"`` or ``"amplitude"``: the continuation parameter.
    points : tuple of CurvePoint
        In continuation order.
    folds : tuple of CurvePoint
        Saddle-node points (the tangent's parameter component vanishes).
    fold_sweeps : tuple of str
        For each fold, ``"up"`` when the parameter increased along the branch before it
        (a slow up-sweep on that branch jumps there), else ``"down"``.
    period_doublings : tuple of dict
        ``{omega, forcing, amplitude}`` where a multiplier crosses -1 (located on the
        branch by regula falsi).
    backbone : tuple of (float, float, float)
        (omega, first-harmonic amplitude, peak displacement) of the free oscillations of
        the unforced undamped system; empty when there is none (discrete model, no
        undamped linear resonance, or ``vary="amplitude"``).
    complete : bool
        The branch reached the end of the range.
    residual : float
        Largest residual of the balanced harmonics, relative to the equation's terms.
    truncation : float
        Largest estimated amplitude of the harmonics above H, relative to the
        first-harmonic amplitude at that point.
    notes : tuple of str
        Caveats.
    """

    equation: str
    harmonics: int
    samples: int
    vary: str
    points: tuple[CurvePoint, ...]
    folds: tuple[CurvePoint, ...]
    fold_sweeps: tuple[str, ...] = ()
    period_doublings: tuple[dict[str, float], ...] = ()
    backbone: tuple[tuple[float, float, float], ...] = ()
    complete: bool = True
    residual: float = 0.0
    truncation: float = 0.0
    notes: tuple[str, ...] = field(default_factory=tuple)

    _order = ("harmonics", "points", "folds", "kind", "equation", "vary", "forcing",
              "fold_forcing", "fold_sweeps", "period_doublings", "backbone", "complete",
              "samples")

    def __repr__(self) -> str:
        return short_repr(self, "harmonics", points=len(self.points), folds=len(self.folds),
                          complete=self.complete)

    def _computed(self) -> dict[str, Any]:
        """The folds' omega and amplitude, the kind, the forcings and the backbone."""
        return {"folds": [{"omega": f.omega, "amplitude": f.amplitude} for f in self.folds],
                "kind": "estimate", "forcing": [p.forcing for p in self.points],
                "fold_forcing": [f.forcing for f in self.folds],
                "backbone": [{"omega": w, "amplitude": a, "peak": y}
                             for w, a, y in self.backbone]}

    def summary_rows(self) -> list[tuple[str, Any]]:
        """(quantity, value) rows of the summary."""
        stable = sum(p.stable for p in self.points)
        peak = max(self.points, key=lambda p: p.amplitude)
        rows: list[tuple[str, Any]] = [
            ("harmonics H (samples per period)", f"{self.harmonics} ({self.samples})"),
            ("points (stable / unstable)", f"{len(self.points)} ({stable} / "
                                           f"{len(self.points) - stable})"),
            ("largest first-harmonic amplitude",
             f"{peak.amplitude:.6g} at omega = {peak.omega:.6g} rad/s"),
            ("neglected harmonics above H (estimate, relative)", self.truncation),
            ("balance residual (relative)", self.residual)]
        rows += [(f"fold {i + 1} ({sweep}-sweep jump)",
                  f"omega = {f.omega:.6g} rad/s, A = {f.forcing:.6g}, amplitude {f.amplitude:.6g}")
                 for i, (f, sweep) in enumerate(zip(self.folds, self.fold_sweeps, strict=True))]
        rows += [(f"period doubling {i + 1}", f"omega = {d['omega']:.6g} rad/s, "
                                              f"amplitude {d['amplitude']:.6g}")
                 for i, d in enumerate(self.period_doublings)]
        return rows

    def _repr_markdown_(self) -> str:
        head = (f"**Frequency response curve** (harmonic balance, estimate) of "
                f"`{self.equation}`" + ("" if self.complete else ", **incomplete**"))
        return head + "\n\n" + markdown_table(("quantity", "value"), self.summary_rows())

    def plot(self, ax: Any = None) -> Any:
        """First-harmonic amplitude against omega (or A): stable solid, unstable dashed,
        folds marked, backbone dotted.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Draw into these axes; default a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        if ax is None:
            figure, axes = new_figure(1, 1, (7.0, 4.5))
            ax = axes[0][0]
        else:
            figure = ax.figure
        xs = np.array([p.omega if self.vary == "omega" else p.forcing for p in self.points])
        ys = np.array([p.amplitude for p in self.points])
        stable = np.array([p.stable for p in self.points])
        labelled = {True: False, False: False}
        start = 0
        for i in range(1, len(xs) + 1):
            if i == len(xs) or stable[i] != stable[start]:
                flag = bool(stable[start])
                ax.plot(xs[start:i + 1], ys[start:i + 1], "-" if flag else "--",
                        color="#1c7ed6" if flag else "#e8590c",
                        label=None if labelled[flag] else ("stable" if flag else "unstable"))
                labelled[flag] = True
                start = i
        if self.folds:
            ax.plot([f.omega if self.vary == "omega" else f.forcing for f in self.folds],
                    [f.amplitude for f in self.folds], "ko", label="folds")
        if self.backbone and self.vary == "omega":
            ax.plot([b[0] for b in self.backbone], [b[1] for b in self.backbone], ":",
                    color="#495057", label="backbone")
        ax.set(xlabel="ω (rad/s)" if self.vary == "omega" else "forcing amplitude A",
               ylabel="first-harmonic amplitude",
               title=f"harmonic balance, H = {self.harmonics}")
        ax.legend(fontsize="small")
        return figure


def _check_range(name: str, value: Any, positive: bool) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ArgumentError(f"{name} must be a pair (low, high) of numbers, got "
                            f"{value!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or not lo < hi:
        raise ArgumentError(f"{name} range must be finite with low < high, got {lo!r}:{hi!r}")
    if lo < 0 or (positive and lo == 0):
        raise ArgumentError(f"{name} must be {'positive' if positive else 'non-negative'}, "
                            f"got {lo!r}")
    _check_normal(name, lo)
    _check_normal(name, hi)
    return lo, hi


def _check_normal(name: str, value: float) -> None:
    """Refuse a subnormal number (below 2.2e-308 it has lost its precision)."""
    if 0 < abs(value) < sys.float_info.min:
        raise ArgumentError(f"{name} {value!r} is below the smallest normal float "
                            f"{sys.float_info.min:.3g}")


def _check_number(name: str, value: Any, positive: bool) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or value < 0 or (positive and value == 0):
        raise ArgumentError(f"{name} must be a finite {'positive' if positive else 'non-negative'}"
                            f" number, got {value!r}")
    _check_normal(name, float(value))
    return float(value)


def _first_point(balance: Balance, omega: float, amplitude: float, scale: float) -> Point:
    """The solution at the start: Newton from the linear response, else raising A."""
    point = newton_fixed(balance, balance.linear_guess(omega, amplitude), omega, amplitude,
                         scale)
    steps = 1
    while point is None and steps < 64:
        steps *= 2
        x = np.zeros(balance.size)
        for i in range(1, steps + 1):
            a = amplitude * i / steps
            guess = x if i > 1 else balance.linear_guess(omega, a)
            step = newton_fixed(balance, guess, omega, a, scale)
            if step is None:
                break
            x = step.x
            point = step if i == steps else None
    if point is None:
        raise ConvergenceError(f"harmonic balance found no periodic solution at omega = "
                               f"{omega:.6g} rad/s, A = {amplitude:.6g} (Newton from the "
                               f"linear response and from raising A in up to 64 steps)")
    return point


def _tail(balance: Balance, point: Point) -> tuple[float, float]:
    """(estimated amplitude of harmonics above H, in-band residual) at a point, both
    relative: to the first harmonic and to the largest term of the equation."""
    h, d = balance.harmonics, balance.degree
    count = 2 * (d * h + 1)
    r, biggest = balance.residual_samples(point.x, point.omega, point.amplitude, count)
    spectrum = np.fft.rfft(r) / count * 2.0
    scale = max(float(np.max(biggest)), 1e-300)
    inband = float(np.max(np.abs(spectrum[:h + 1]))) / scale
    neglected = 0.0
    for k in range(h + 1, d * h + 1):
        lin = abs(balance.linear_factor(k, point.omega))
        neglected += (abs(spectrum[k]) / lin) ** 2 if lin > 0 else math.inf
    first = max(math.hypot(point.x[1], point.x[2]), 1e-300)
    return math.sqrt(neglected) / first, inband


def _critical(multipliers: tuple[complex, ...]) -> complex | None:
    """The multiplier of largest modulus when it is finite, non-zero, real and negative."""
    if not multipliers or not all(0 < abs(r) < math.inf for r in multipliers):
        return None
    rho = max(multipliers, key=abs)
    return rho if rho.real < 0 and abs(rho.imag) < 1e-6 * abs(rho) + 1e-9 else None


def _period_doublings(balance: Balance, tracer: Tracer, raw: list[tuple[Point, np.ndarray]],
                      points: list[CurvePoint]) -> list[dict[str, float]]:
    """Where a real negative multiplier crosses -1 between neighbouring points: located
    by regula falsi on the arclength from the first of them (log |rho| = 0), each
    evaluation a corrected point and its Hill multipliers."""
    out = []
    for i, (a, b) in enumerate(zip(points, points[1:], strict=False)):
        ra, rb = _critical(a.multipliers), _critical(b.multipliers)
        if ra is None or rb is None or math.log(abs(ra)) * math.log(abs(rb)) >= 0:
            continue
        start, tangent = raw[i]
        s0, s1 = 0.0, tracer.arclength(start, tangent, raw[i + 1][0])
        f0, f1 = math.log(abs(ra)), math.log(abs(rb))
        best = (start, f0) if abs(f0) < abs(f1) else (raw[i + 1][0], f1)
        for _ in range(PD_ITERATIONS):
            s = (s0 * f1 - s1 * f0) / (f1 - f0)
            got = tracer.correct(start, tangent, s)
            rho = None if got is None else floquet_multipliers(
                balance, got[0].evaluation.partials, got[0].omega)
            crit = None if rho is None else _critical(tuple(complex(r) for r in rho))
            if got is None or crit is None:
                break
            fs = math.log(abs(crit))
            best = (got[0], fs)
            if abs(fs) <= 1e-12:
                break
            if fs * f1 > 0:
                s1, f1 = s, fs
            else:
                s0, f0 = s, fs
        p = best[0]
        out.append({"omega": float(p.omega), "forcing": float(p.amplitude),
                    "amplitude": float(math.hypot(p.x[1], p.x[2]))})
    return out


def frc(model: Model, amplitude: float | tuple[float, float],
        omega: float | tuple[float, float], *, harmonics: int = DEFAULT_HARMONICS,
        vary: str = "omega", step: float = 0.02,
        backbone: bool = True, max_points: int | None = None) -> FrequencyResponseCurve:
    """The frequency response curve of ``model`` under ``u = A cos(omega t)``.

    Parameters
    ----------
    model : Model
        A polynomial model (continuous ODE or discrete NARX).
    amplitude : float or (float, float)
        The forcing amplitude A; a range (low, high) with ``vary="amplitude"``.
    omega : (float, float) or float
        The frequency range in rad/s; one frequency with ``vary="amplitude"``.  A
        discrete model's frequencies must not exceed Nyquist, pi / T.
    harmonics : int, optional
        H, the highest harmonic kept (default :data:`DEFAULT_HARMONICS`).
    vary : {"omega", "amplitude"}
        The continuation parameter.
    step : float, optional
        Largest arclength step in the scaled variables (smaller: denser curve).
    backbone : bool, optional
        Also compute the backbone of the unforced undamped system.
    max_points : int, optional
        Most points; the result is marked incomplete when they run out.  Default 2000
        or fewer, as :data:`MAX_WORK` allows.

    Returns
    -------
    FrequencyResponseCurve

    Raises
    ------
    ArgumentError
        Bad ranges, harmonics, step or point count, or too much work.
    ConvergenceError
        No periodic solution found at the start of the range.
    """
    if vary not in ("omega", "amplitude"):
        raise ArgumentError(f"vary must be 'omega' or 'amplitude', got {vary!r}")
    if vary == "omega":
        lo, hi = _check_range("omega", omega, True)
        forcing = _check_number("amplitude", amplitude, True)
        fixed_omega = lo
    else:
        lo, hi = _check_range("amplitude", amplitude, False)
        fixed_omega = _check_number("omega", omega, True)
        forcing = lo
    step = _check_number("step", step, True)
    balance = Balance(model.terms, harmonics, sample_time=model.sample_time)
    per_point = (max(1, *balance.y_orders) * balance.size) ** 3
    if max_points is None:
        max_points = max(2, min(2000, MAX_WORK // per_point))
    if isinstance(max_points, bool) or not isinstance(max_points, int) \
            or not 2 <= max_points <= MAX_POINTS:
        raise ArgumentError(f"max_points must be an integer from 2 to MAX_POINTS = "
                            f"{MAX_POINTS}, got {max_points!r}")
    if max_points * per_point > MAX_WORK:
        raise ArgumentError(f"{max_points} points with {harmonics} harmonics are "
                            f"{max_points * per_point:.3g} units of work, more than "
                            f"MAX_WORK = {MAX_WORK:.3g}: use fewer harmonics or points")
    for name, value, (low, high) in (("omega", fixed_omega, OMEGA_LIMITS),
                                     ("omega", hi if vary == "omega" else fixed_omega,
                                      OMEGA_LIMITS),
                                     ("amplitude", hi if vary == "amplitude" else forcing,
                                      (0.0, MAX_AMPLITUDE))):
        if not low <= value <= high:
            raise ArgumentError(f"{name} {value!r} is outside [{low:g}, {high:g}] (OMEGA_LIMITS "
                                f"and MAX_AMPLITUDE of gfrf.harmonic.curve)")
    top = hi if vary == "omega" else fixed_omega
    if model.sample_time is not None and top > math.pi / model.sample_time * (1 + 1e-12):
        raise ArgumentError(f"omega {top:.6g} rad/s is above the Nyquist frequency "
                            f"pi/T = {math.pi / model.sample_time:.6g} rad/s of the "
                            f"discrete model")
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _trace(model, balance, vary=vary, lo=lo, hi=hi, fixed_omega=fixed_omega,
                      forcing=forcing, step=step, max_points=max_points, backbone=backbone)


def _trace(model: Model, balance: Balance, vary: str, lo: float, hi: float,
           fixed_omega: float, forcing: float, step: float, max_points: int,
           backbone: bool) -> FrequencyResponseCurve:
    """The work of :func:`frc` once its arguments are checked (overflows are caught as
    non-finite Newton steps, not warned)."""
    harmonics = balance.harmonics
    _, biggest = balance.residual_samples(balance.linear_guess(fixed_omega, forcing or hi),
                                          fixed_omega, forcing or hi, balance.samples)
    term_scale = max(float(np.max(biggest)), 1e-300)
    first = _first_point(balance, fixed_omega, forcing, term_scale)
    grid = np.linspace(lo, hi, 101) if vary == "omega" else np.array([fixed_omega])
    peak = max(math.hypot(*balance.linear_guess(float(w), hi if vary == "amplitude"
                                                else forcing)[1:3]) for w in grid)
    own = max(float(np.max(np.abs(first.x))), 1e-12)
    x_scale = max(own, min(peak, 100 * own)) if math.isfinite(peak) else own
    tracer = Tracer(balance, vary, x_scale, hi - lo, term_scale)
    raw, fold_points, complete = tracer.trace(first, hi, step=step, max_points=max_points,
                                              accept=lambda p: None)
    tails = [_tail(balance, p) for p, _ in raw]
    points = [_curve_point(balance, p, t) for (p, _), (t, _) in zip(raw, tails, strict=True)]
    folds = tuple(_curve_point(balance, f, _tail(balance, f)[0]) for f, _ in fold_points)
    notes = []
    if any(not p.multipliers for p in points):
        notes.append("the leading coefficient of the linearised equation is singular on "
                     "some orbits: their stability is undefined and reported unstable")
    if not complete:
        last = points[-1].omega if vary == "omega" else points[-1].forcing
        notes.append(f"the continuation stopped at {vary} = {last:.6g}, before the end of "
                     f"the range ({len(points)} points): max_points = {max_points} reached, "
                     f"no step converged, or the response grew without bound")
    truncation = max(t for t, _ in tails)
    if truncation > 1e-6:
        notes.append(f"the neglected harmonics above H = {harmonics} are estimated at "
                     f"{truncation:.2g} of the first harmonic: raise the harmonics")
    curve_backbone: tuple[tuple[float, float, float], ...] = ()
    if backbone and model.sample_time is None and vary == "omega":
        top_amp = max(p.amplitude for p in points)
        curve_backbone = backbone_curve(model, harmonics, 1.1 * top_amp)
    return FrequencyResponseCurve(
        equation=model.equation(), harmonics=harmonics, samples=balance.samples, vary=vary,
        points=tuple(points), folds=folds,
        fold_sweeps=tuple("up" if d > 0 else "down" for _, d in fold_points),
        period_doublings=tuple(_period_doublings(balance, tracer, raw, points)),
        backbone=curve_backbone, complete=complete,
        residual=max(r for _, r in tails), truncation=truncation, notes=tuple(notes))


def _curve_point(balance: Balance, point: Point, tail: float) -> CurvePoint:
    rho = floquet_multipliers(balance, point.evaluation.partials, point.omega)
    multipliers = () if rho is None else tuple(complex(r) for r in rho)
    stable = bool(multipliers) and max(abs(r) for r in multipliers) < 1.0 - MARGINAL
    return CurvePoint(omega=float(point.omega), forcing=float(point.amplitude),
                      coefficients=point.x.copy(), stable=stable, multipliers=multipliers,
                      tail=tail)
