"""The falsifier's witness: an input switched on at t = 0 from rest whose response escapes.

Three kinds, as the JSON ``witness`` of ``gfrf threshold`` gives them: ``"tones"``
(u = sum A cos(omega t + phi), amplitude the sum of the A), ``"switching"``
(u = +-U alternating at recorded switch times, amplitude U = sup|u|) and ``"chirp"``
(:class:`Chirp`: u = A cos(omega_0 t + (omega_1 - omega_0) t^2 / (2 T)) on [0, T],
amplitude A = sup|u|).  For a closed
loop the input is the reference r of the loop u = C(r - y).  :class:`Falsification`
is the result of :func:`gfrf.twosided.falsify.falsify`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gfrf.twosided.escape import EscapeRegion

__all__ = ["Tone", "Chirp", "Falsification", "tones_text", "switching_text", "scaled"]

Tone = tuple[float, float, float]


def tones_text(tones: list[Tone]) -> str:
    """The input u(t) = sum A cos(omega t + phi) as gfrf input text (exact float reprs).

    Parameters
    ----------
    tones : list of tuple of float
        ``(A, omega, phi)`` per tone: amplitude, angular frequency in rad/s, phase in rad.

    Returns
    -------
    str
        ``A*cos(omega*t + phi) + ...``, parsed back exactly by
        :func:`gfrf.model.signals.parse_input`.
    """
    return " + ".join(f"{a!r}*cos({w!r}*t + {p!r})" for a, w, p in tones)


def switching_text(amplitude: float, first_sign: int, switch_times: list[float]) -> str:
    """The switching input in words (all switch times when few, else the first and last).

    Parameters
    ----------
    amplitude : float
        U: the input is +-U.
    first_sign : int
        +1 or -1: u = first_sign * U on [0, t1).
    switch_times : list of float
        The times (s) at which the sign of u alternates.

    Returns
    -------
    str
        One line, e.g. ``u = +0.5 on [0, t1), the sign alternating at each of 3 switch
        times t = 1.2, 3.4, 5.6 s``.
    """
    times = [f"{t:.6g}" for t in switch_times]
    if len(times) > 8:
        times = times[:4] + [f"... ({len(switch_times) - 6} more)"] + times[-2:]
    start = f"u = {'+' if first_sign > 0 else '-'}{amplitude!r} on [0, t1)"
    if not switch_times:
        return f"u = {first_sign * amplitude!r} (constant)"
    if len(switch_times) == 1:
        return f"{start}, the sign switching once at t = {times[0]} s"
    return (f"{start}, the sign alternating at each of {len(switch_times)} switch times t = "
            + ", ".join(times) + " s")


def scaled(shape: list[Tone], amplitude: float) -> list[Tone]:
    """The tones of ``shape`` with every amplitude times ``amplitude``.

    Parameters
    ----------
    shape : list of (A, omega, phi)
        The tones at unit scale.
    amplitude : float
        The factor on every A.

    Returns
    -------
    list of (A, omega, phi)
    """
    return [(a * amplitude, w, p) for a, w, p in shape]


@dataclass(frozen=True)
class Chirp:
    """A linear chirp u = A cos(omega_start t + rate t^2) on [0, duration], switched on at
    t = 0 from rest; ``rate = (omega_end - omega_start) / (2 duration)``, so the
    instantaneous frequency runs linearly from omega_start to omega_end (rad/s).

    Attributes
    ----------
    amplitude : float
        A = sup|u|.
    omega_start, omega_end : float
        Instantaneous angular frequency at t = 0 and at t = duration (rad/s).
    duration : float
        T (s): the input is defined on [0, T]; a witness escapes before T.
    """

    amplitude: float
    omega_start: float
    omega_end: float
    duration: float

    @property
    def rate(self) -> float:
        """(omega_end - omega_start) / (2 duration): the t^2 coefficient of the phase."""
        return (self.omega_end - self.omega_start) / (2.0 * self.duration)

    def text(self) -> str:
        """u(t) as gfrf input text (exact float reprs), for ``gfrf simulate --input``."""
        sign = "-" if self.rate < 0 else "+"
        return (f"{self.amplitude!r}*cos({self.omega_start!r}*t {sign} "
                f"{abs(self.rate)!r}*t**2)")

    def values(self, t: np.ndarray, orders: list[int]) -> np.ndarray:
        """u and the derivatives ``orders`` (each 0, 1 or 2) at the times ``t`` (s).

        Parameters
        ----------
        t : numpy.ndarray
            Times in s.
        orders : list of int
            The derivative orders wanted, one column each (at most 2).

        Returns
        -------
        numpy.ndarray
            Shape (len(t), len(orders)).
        """
        t = np.asarray(t, dtype=float)
        phase = self.omega_start * t + self.rate * t * t
        rate = self.omega_start + 2.0 * self.rate * t  # d phase / dt
        a, c, s = self.amplitude, np.cos(phase), np.sin(phase)
        table = {0: a * c, 1: -a * rate * s, 2: -a * (2.0 * self.rate * s + rate * rate * c)}
        return np.stack([table[k] for k in orders], axis=-1)


@dataclass(frozen=True)
class Falsification:
    """Result of :func:`falsify`.

    Attributes
    ----------
    upper : float or None
        The witness's amplitude: sup|u| = U of a switching input, A of a chirp, the sum
        of the tone amplitudes of a sum of tones; None: no escape up to ``cap``.
    kind : str or None
        ``"switching"``, ``"chirp"`` or ``"tones"``.
    tones : list of (amplitude, omega_rad_s, phase_rad)
        A tone witness u = sum A cos(omega t + phi), switched on at t = 0 from rest.
    first_sign : int
        A switching witness: u = first_sign * U on [0, t1).
    switch_times : list of float
        A switching witness: the times (s) at which the sign of u alternates.
    t_escape : float or None
        Escape time (s) of the witness under DOP853 at the tighter tolerance
        (NARX: of the recursion).
    edge : float or None
        The smallest escaping amplitude the search found (the witness has a margin on it).
    cap : float
        The search cap on the amplitude.
    t_end : float
        The horizon in seconds.
    runs : int
        Simulations run.
    escape : str
        What escape meant, and how the witness was checked.
    region : EscapeRegion or None
        The certified escape region used (oscillators).
    levels : list of float
        Escape level of each state.
    candidates : list of dict
        The edges found per input shape, for reports.
    chirp : Chirp or None
        A chirp witness.
    """

    upper: float | None
    tones: list[Tone]
    t_escape: float | None
    edge: float | None
    cap: float
    t_end: float
    runs: int
    escape: str
    kind: str | None = None
    first_sign: int = 1
    switch_times: list[float] = field(default_factory=list, repr=False)
    region: EscapeRegion | None = field(default=None, repr=False)
    levels: list[float] = field(default_factory=list, repr=False)
    discrete: bool = False
    candidates: list[dict[str, Any]] = field(default_factory=list, repr=False)
    chirp: Chirp | None = None

    def witness(self) -> dict[str, Any] | None:
        """The JSON witness (``kind`` ``"tones"``, ``"switching"`` or ``"chirp"``), or None."""
        if self.upper is None:
            return None
        if self.kind == "chirp" and self.chirp is not None:
            c = self.chirp
            return {"kind": "chirp", "amplitude": c.amplitude, "omega_start": c.omega_start,
                    "omega_end": c.omega_end, "duration": c.duration,
                    "t_escape": self.t_escape}
        if self.kind == "switching":
            return {"kind": "switching", "amplitude": self.upper,
                    "first_sign": self.first_sign, "switch_times": list(self.switch_times),
                    "t_escape": self.t_escape}
        return {"kind": "tones", "tones": [list(t) for t in self.tones],
                "t_escape": self.t_escape}

    def input_text(self, name: str = "u") -> str:
        """The witness input in words.

        Parameters
        ----------
        name : str, optional
            The input's name (``"r"`` for the reference of a closed loop).

        Returns
        -------
        str
        """
        if self.kind == "switching":
            text = switching_text(self.upper or 0.0, self.first_sign, self.switch_times)
            return name + text[1:] if name != "u" else text
        if self.kind == "chirp" and self.chirp is not None:
            c = self.chirp
            return (f"{name} = {c.text()} on [0, {c.duration:.6g}] s (a chirp from "
                    f"{c.omega_start:.6g} to {c.omega_end:.6g} rad/s)")
        return f"{name} = {tones_text(self.tones)}"
