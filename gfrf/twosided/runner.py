"""Escape tests of one system: the fast path (fixed-step RK4), the DOP853 checks, NARX.

:class:`EscapeRunner` answers "does the response from rest to this input escape?" for
sums of tones (:meth:`EscapeRunner.escapes`) and for switching feedback runs
(:meth:`EscapeRunner.switch`), and confirms a candidate witness under scipy's DOP853 at
two tolerances (:meth:`EscapeRunner.confirm`, :meth:`EscapeRunner.confirm_switching`).
Escape is any state beyond its level (:func:`gfrf.twosided.escape.escape_levels`) or in
the certified escape region of an oscillator, or a non-finite state.  Every run is
counted (``runs``); the horizon and the step follow from the linear part, never the
clock.  A closed loop's input is the reference r of u = C(r - y); an improper
controller reads r', r'', which a tone gives exactly.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from gfrf.model.equation import Model
from gfrf.twosided.escape import EscapeRegion, escape_levels, escape_region
from gfrf.twosided.witness import Chirp, Tone, tones_text

__all__ = ["EscapeRunner", "T_MAX", "TIME_CONSTANTS", "PERIODS", "SAMPLES", "MAX_RUN_STEPS",
           "CHECK_RTOLS", "TIME_AGREEMENT"]

#: Longest horizon in seconds (continuous models).
T_MAX = 400.0
#: Horizon: this many time constants of the slowest linear mode ...
TIME_CONSTANTS = 40.0
#: ... and at least this many periods of the slowest linear mode.
PERIODS = 10.0
#: NARX horizon in samples: at least, at most.
SAMPLES = (500, 2000)
#: RK4 steps of one run at most: a stiff model's horizon is shortened to fit (stated).
MAX_RUN_STEPS = 200_000
#: The two DOP853 tolerances of the witness check (rtol; atol = rtol * 1e-3).
CHECK_RTOLS = (1e-9, 1e-11)
#: Relative agreement of the two escape times.
TIME_AGREEMENT = 0.01


class EscapeRunner:
    """Escape tests of one system on the fast path (fixed step) or the NARX recursion.

    Parameters
    ----------
    system : OdeSystem
        The generated state form (:func:`gfrf.sim.system.build_system`, polynomial
        equation; a closed loop's input is the reference and its derivatives).
    model : Model
        The plant: its scale gives the escape levels and, for an oscillator, the region.
    top_omega : float
        The highest input frequency (rad/s) to be run: the RK4 step resolves it.
    """

    def __init__(self, system: Any, model: Model, top_omega: float):
        self.system = system
        self.model = model
        self.runs = 0
        self.notes: list[str] = []
        ev = np.asarray(self.system.linear_eigenvalues, dtype=complex)
        self.levels = escape_levels(model, ev, system.n_states)
        self.discrete = self.system.discrete
        self.module = self.bang = None
        if self.discrete:
            mod = float(np.max(np.abs(ev))) if ev.size else 0.0
            decay = -math.log(mod) if 0 < mod < 1 else 1.0
            n = int(min(SAMPLES[1], max(SAMPLES[0], math.ceil(TIME_CONSTANTS / decay))))
            self.t_end = n * float(self.system.sample_time)
            self.samples = n
            return
        nonzero = np.abs(ev[np.abs(ev) > 0])
        slow = float(np.min(np.abs(ev.real))) if ev.size else 1.0
        fast = float(np.max(np.abs(ev))) if ev.size else 1.0
        period = 2 * math.pi / float(nonzero.min()) if nonzero.size else 2 * math.pi
        self.t_end = float(min(T_MAX, max(PERIODS * period,
                                          TIME_CONSTANTS / max(slow, 1e-12))))
        h = min(0.5 / max(fast, 1e-12), 2 * math.pi / top_omega / 40)
        if self.t_end / h > MAX_RUN_STEPS:
            self.notes.append(f"horizon shortened from {self.t_end:.4g} s to fit MAX_RUN_STEPS "
                              f"= {MAX_RUN_STEPS} RK4 steps of {h:.3g} s")
            self.t_end = MAX_RUN_STEPS * h
        self.steps = max(1, int(math.ceil(self.t_end / h)))
        self.h = self.t_end / self.steps
        self.orders = []
        for name in self.system.input_names:
            head, _, k = name.rpartition("__")
            self.orders.append(int(k) if k.isdigit() and head else 0)
        from gfrf.sim.fastsim import compile_system, numba_available

        if numba_available():
            self.module = compile_system(self.system)[0]
            if all(k == 0 for k in self.orders):
                from gfrf.twosided.switching import switching_module

                self.bang = switching_module(self.system)

    def region(self, amplitude: float) -> EscapeRegion | None:
        """The certified escape region of an open-loop oscillator at this input size.

        Parameters
        ----------
        amplitude : float
            The input bound sup|u|.

        Returns
        -------
        EscapeRegion or None
            None for NARX models, closed loops and models not of second order.
        """
        if self.discrete or self.system.closed_loop or self.system.n_states != 2:
            return None
        return escape_region(self.model, amplitude)

    def _escaped_states(self, Z: np.ndarray, region: EscapeRegion | None) -> bool:
        with np.errstate(invalid="ignore"):
            if not np.all(np.abs(Z) < self.levels):
                return True
            if region is not None:
                y, p = Z[:, 0], Z[:, 1]
                return bool(np.any((y >= region.y_plus) & (p >= 0))
                            or np.any((y <= -region.y_minus) & (p <= 0)))
        return False

    def escapes(self, tones: list[Tone], refine: int = 1) -> bool:
        """True if the response from rest to ``tones`` escapes (fast path).

        Parameters
        ----------
        tones : list of (A, omega, phi)
            The input u = sum A cos(omega t + phi).
        refine : int, optional
            Divide the RK4 step by this (a second run at half the step checks the first).

        Returns
        -------
        bool
        """
        self.runs += 1
        region = self.region(sum(abs(a) for a, _, _ in tones))
        if self.discrete or self.module is None:
            return self._simulate(tones, 1e-7, region) is not None
        steps, h = self.steps * refine, self.h / refine
        t = np.arange(2 * steps + 1) * (0.5 * h)
        V = np.zeros((t.size, len(self.orders)))
        for a, w, p in tones:
            for j, k in enumerate(self.orders):
                V[:, j] += a * w**k * np.cos(w * t + p + k * math.pi / 2)
        return self._fast(V, steps, h, region)

    def _fast(self, V: np.ndarray, steps: int, h: float, region: EscapeRegion | None) -> bool:
        """Escape of the fixed-step RK4 run from rest with inputs V at the half steps."""
        from gfrf.sim.fastsim import _rk4

        assert self.module is not None  # callers run the fast path only where it compiled
        z0 = np.zeros(self.system.n_states)
        with np.errstate(all="ignore"):
            Z, _, _, done = _rk4(self.module, z0, seg_n=np.array([steps], dtype=np.int64),
                                 seg_h=np.array([h]), V=V, VL=V[-1:].copy(), steps=steps,
                                 blowup=float(self.levels[0]))
        return self._escaped_states(Z[:done + 1], region)

    @property
    def chirps(self) -> bool:
        """Chirps run here: a continuous system on the fast path reading u, u', u'' at most."""
        return not self.discrete and self.module is not None and max(self.orders) <= 2

    def escapes_chirp(self, chirp: Chirp, refine: int = 1) -> bool:
        """True if the response from rest to ``chirp`` escapes within its duration.

        Parameters
        ----------
        chirp : Chirp
            The input (only where :attr:`chirps`).
        refine : int, optional
            Divide the RK4 step by this.

        Returns
        -------
        bool
        """
        self.runs += 1
        h = self.h / refine
        steps = max(1, int(math.ceil(min(chirp.duration, self.t_end) / h)))
        V = chirp.values(np.arange(2 * steps + 1) * (0.5 * h), self.orders)
        return self._fast(V, steps, h, self.region(chirp.amplitude))

    def confirm_chirp(self, chirp: Chirp) -> float | None:
        """Escape time of ``chirp`` if the fast path at two steps and DOP853 at both
        :data:`CHECK_RTOLS` agree that it escapes (times within :data:`TIME_AGREEMENT`).

        Parameters
        ----------
        chirp : Chirp
            The candidate witness.

        Returns
        -------
        float or None
            The escape time (s) at the tighter tolerance; None when a check disagrees.
        """
        from gfrf.twosided.switching import dop853_escape

        if not (self.escapes_chirp(chirp) and self.escapes_chirp(chirp, refine=2)):
            return None
        orders = self.orders

        def values(t: float, v: np.ndarray) -> None:
            v[:] = chirp.values(np.array([t]), orders)[0]

        region = self.region(chirp.amplitude)
        self.runs += len(CHECK_RTOLS)
        return self._agreeing([dop853_escape(self.system, values,
                                             [0.0, min(chirp.duration, self.t_end)],
                                             self.levels, rtol, region)
                               for rtol in CHECK_RTOLS])

    def switch(self, c: Any, amplitude: float, first_sign: int = 1) -> Any:
        """The feedback run u = U sign(c . z) from rest.

        Parameters
        ----------
        c : numpy.ndarray or str
            The switching function's coefficients on the state; for a NARX model the
            name of a sign rule of :mod:`gfrf.twosided.narx_signs`.
        amplitude : float
            U.
        first_sign : int, optional
            The sign of u where c . z = 0 at the start.

        Returns
        -------
        SwitchRun
            ``escaped``, ``t_escape``, ``first_sign``, ``switch_times``
            (:class:`gfrf.twosided.switching.SwitchRun`).
        """
        from gfrf.twosided.switching import run_switching

        self.runs += 1
        if self.discrete:
            from gfrf.twosided.narx_signs import run_signs

            return run_signs(self.system, c, amplitude, self.samples, float(self.levels[0]))
        region = self.region(amplitude)
        return run_switching(self.bang, self.system.n_states, c=c,  # type: ignore[arg-type]
                             amplitude=amplitude, first_sign=first_sign, h=self.h,
                             steps=self.steps, level=self.levels,
                             region=region.flags() if region is not None else (0.0, 0.0, 0.0))

    def _simulate(self, tones: list[Tone], rtol: float, region: EscapeRegion | None
                  ) -> float | None:
        """Escape time of ``tones`` (scipy DOP853, or the NARX recursion), or None."""
        if self.discrete:
            from gfrf.sim.simulation import simulate

            with warnings.catch_warnings():  # "expect growth": escaping is looked for
                warnings.simplefilter("ignore", UserWarning)
                res = simulate(self.system, tones_text(tones), t_end=self.t_end,
                               method="dop853", rtol=rtol, atol=rtol * 1e-3,
                               blowup=float(self.levels[0]), n_out=2)
            return res.blowup_time if res.status == "blowup" else None
        from gfrf.twosided.switching import dop853_escape

        orders = self.orders

        def values(t: float, v: np.ndarray) -> None:
            v[:] = 0.0
            for a, w, p in tones:
                for j, k in enumerate(orders):
                    v[j] += a * w**k * math.cos(w * t + p + k * math.pi / 2)

        return dop853_escape(self.system, values, [0.0, self.t_end], self.levels, rtol,
                             region)

    def confirm(self, tones: list[Tone]) -> float | None:
        """Escape time of ``tones`` if the independent checks agree that it escapes.

        The fast path at the step and at half of it, then DOP853 at both
        :data:`CHECK_RTOLS` with escape times within :data:`TIME_AGREEMENT`.

        Parameters
        ----------
        tones : list of (A, omega, phi)
            The candidate witness.

        Returns
        -------
        float or None
            The escape time (s) at the tighter tolerance; None when a check disagrees.
        """
        region = self.region(sum(abs(a) for a, _, _ in tones))
        if self.discrete:
            self.runs += 1
            return self._simulate(tones, 1e-9, region)
        if not (self.escapes(tones) and self.escapes(tones, refine=2)):
            return None
        return self._agreeing([self._simulate(tones, rtol, region) for rtol in CHECK_RTOLS])

    def confirm_switching(self, amplitude: float, first_sign: int, times: list[float]
                          ) -> float | None:
        """Escape time of a switching input replayed open loop by DOP853 at both tolerances.

        Parameters
        ----------
        amplitude : float
            U.
        first_sign : int
            u = first_sign * U on [0, t1).
        times : list of float
            The switch times (s), each an integration boundary.

        Returns
        -------
        float or None
            The escape time (s); None when a run does not escape or the times disagree.
        """
        from gfrf.twosided.switching import replay

        if self.discrete:
            from gfrf.twosided.narx_signs import replay_signs

            self.runs += 1
            return replay_signs(self.system, amplitude, first_sign, times, self.samples,
                                float(self.levels[0]))
        region = self.region(amplitude)
        self.runs += len(CHECK_RTOLS)
        return self._agreeing([replay(self.system, amplitude, first_sign=first_sign,
                                      switch_times=times, t_end=self.t_end, level=self.levels,
                                      rtol=rtol, region=region) for rtol in CHECK_RTOLS])

    @staticmethod
    def _agreeing(times: list[float | None]) -> float | None:
        if any(t is None for t in times):
            return None
        ts = [float(t) for t in times if t is not None]
        if abs(ts[0] - ts[-1]) > TIME_AGREEMENT * max(ts):
            return None
        return ts[-1]
