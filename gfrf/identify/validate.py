"""Is an identified model adequate?  Hold-out free-run error and Billings-Voon correlation tests.

A polynomial NARMAX model is judged on data not used to fit it (the held-out end of
the record) by two kinds of evidence:

* the free-run root relative squared error (the model simulated from the input
  alone, :func:`gfrf.identify.fit.free_run`) above the noise floor (the RRSE even the
  true system scores against noisy data, :mod:`gfrf.identify.floor`),
  ``sqrt(free^2 - floor^2)``, must be below :data:`FREE_RUN_LIMIT`, and the floor below
  :data:`MAX_NOISE_FLOOR`;
* the model-validity correlation tests of Billings and Voon (1986) on the one-step
  residuals ``e`` (with the NARMAX noise model, when there is one) must pass:
  ``phi_ee(tau) = delta(tau)``, ``phi_ue(tau) = 0``, ``phi_u2'e(tau) = 0``,
  ``phi_u2'e2(tau) = 0`` and ``phi_e(eu)(tau) = 0``, each inside the 95 % band
  ``1.96/sqrt(N)``.  A white residual still leaves about 5 % of the values outside
  the band by chance: a test passes when at most :func:`allowed_outside` of its
  :data:`LAGS` values are outside, the count a white residual stays within with
  probability ``0.99**(1/5)`` (so that it passes all five with probability 0.99), and
  none is beyond twice the band (``3.92/sqrt(N)``, which a white
  residual reaches with probability below 1e-4 per value).

:func:`correlation_tests` computes the tests and :func:`judge` sums everything up
as a :class:`Validation` (``adequate`` with its ``reason``).  One exception: a model
whose free run reproduces the held-out data to :data:`PRECISE_FIT` (1 % of the output)
beyond the noise floor is adequate whatever its correlation tests say, since such
residuals are noise plus the fit's own small structural error (a continuous system
fitted by a NARX model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gfrf._results import Result

__all__ = ["Validation", "CorrelationTest", "correlation_tests", "judge", "allowed_outside",
           "model_error", "FREE_RUN_LIMIT", "PRECISE_FIT", "MAX_NOISE_FLOOR", "LAGS"]

#: Largest model error (the held-out free-run RRSE above the noise floor) of an adequate
#: model: below the 0.1 a user can rely on, with a margin for the spread of the error
#: between two held-out records.
FREE_RUN_LIMIT = 0.08
#: Model error (held-out free-run RRSE above the noise floor) below which failed
#: correlation tests do not make a model inadequate: the residuals of a model that
#: reproduces unseen data to 1 % beyond the noise are noise plus its own small structural
#: error (a continuous system fitted by a NARX model), which the whiteness tests detect
#: when the noise is small, not unmodelled dynamics that would bias the kernels.
PRECISE_FIT = 0.01
#: Largest noise floor (RRSE) at which a model can be judged: above it the noise hides a
#: model error of the size :data:`FREE_RUN_LIMIT` allows.
MAX_NOISE_FLOOR = 0.3
#: Lags of each correlation test (0..LAGS, or 1..LAGS for the autocorrelation).
LAGS = 20
#: Probability with which a white residual passes all five tests, and one of them.
FAMILY_PASS_PROBABILITY = 0.99
_PASS_PROBABILITY = FAMILY_PASS_PROBABILITY ** (1 / 5)


def allowed_outside(count: int, level: float = 0.05) -> int:
    """Values of ``count`` allowed outside a band that white noise leaves with probability
    ``level``: the smallest k with ``P(Binomial(count, level) <= k) >= 0.99**(1/5)``
    (each of the five tests at this level: a white residual passes all with probability
    0.99).

    Parameters
    ----------
    count : int
        Number of values tested.
    level : float, optional
        The probability that one value of white noise leaves the band.

    Returns
    -------
    int
        k.

    Examples
    --------
    >>> allowed_outside(20), allowed_outside(21)
    (5, 5)
    """
    total = 0.0
    for k in range(count + 1):
        total += math.comb(count, k) * level**k * (1 - level) ** (count - k)
        if total >= _PASS_PROBABILITY:
            return k
    return count


@dataclass(frozen=True, kw_only=True)
class CorrelationTest(Result):
    """One Billings-Voon correlation test.

    Attributes
    ----------
    name : str
        ``phi_ee``, ``phi_ue``, ``phi_u2e``, ``phi_u2e2`` or ``phi_e_eu``; not in
        :meth:`to_dict` (it is the key of the test in :meth:`Validation.to_dict`).
    first_lag : int
        The lag of ``values[0]``.
    values : tuple of float
        The normalised correlation at each lag.
    band : float
        The 95 % band ``1.96/sqrt(N)``.
    outside, allowed : int
        Values outside the band, and how many a pass allows.
    """

    _exclude = ("name",)
    _order = ("passed", "outside", "allowed", "band", "max_abs", "first_lag", "values")

    name: str
    first_lag: int
    values: tuple[float, ...]
    band: float
    outside: int
    allowed: int

    @property
    def passed(self) -> bool:
        """True when at most ``allowed`` values are outside the band and none beyond
        twice the band."""
        return self.outside <= self.allowed and \
            all(abs(v) <= 2 * self.band for v in self.values)

    def _computed(self) -> dict[str, Any]:
        return {"passed": self.passed, "max_abs": max(abs(v) for v in self.values)}


def _corr(a: np.ndarray, b: np.ndarray, lags: range) -> list[float]:
    """Normalised cross-correlation sum a(k-tau) b(k) / sqrt(sum a^2 sum b^2), a, b centred."""
    a = a - np.mean(a)
    b = b - np.mean(b)
    scale = math.sqrt(float(np.dot(a, a)) * float(np.dot(b, b)))
    n = a.size
    if scale == 0.0:
        return [math.inf if tau else 0.0 for tau in lags]
    return [float(np.dot(a[:n - tau], b[tau:])) / scale for tau in lags]


def correlation_tests(e: np.ndarray, u: np.ndarray, lags: int = LAGS, floor: float = 0.0
                      ) -> tuple[CorrelationTest, ...]:
    """The five Billings-Voon tests of residuals ``e`` against input ``u`` (same length).

    A residual whose root mean square is at most ``floor`` (an exact fit of noise-free
    data: rounding errors, whose correlations mean nothing) passes every test with all
    values 0; a constant non-zero residual fails them.

    Parameters
    ----------
    e : numpy.ndarray
        The residuals.
    u : numpy.ndarray
        The input samples, as many.
    lags : int, optional
        Largest lag of the correlations.
    floor : float, optional
        The root mean square at or below which the residual counts as zero.

    Returns
    -------
    tuple of CorrelationTest
        The five tests.
    """
    e = np.asarray(e, dtype=float)
    u = np.asarray(u, dtype=float)
    n = e.size
    band = 1.96 / math.sqrt(n)
    if math.sqrt(float(np.mean(e**2))) <= floor:
        zero = {"phi_ee": 1, "phi_ue": 0, "phi_u2e": 0, "phi_u2e2": 0, "phi_e_eu": 0}
        return tuple(CorrelationTest(name=name, first_lag=first,
                                     values=(0.0,) * (lags + 1 - first), band=band, outside=0,
                                     allowed=allowed_outside(lags + 1 - first))
                     for name, first in zero.items())
    u2 = u**2
    e2 = e**2
    eu = np.r_[0.0, (e * u)[:-1]]  # e(k-1) u(k-1), so that lag tau is e(k-1-tau) u(k-1-tau)
    series = {"phi_ee": (e, e, 1), "phi_ue": (u, e, 0), "phi_u2e": (u2, e, 0),
              "phi_u2e2": (u2, e2, 0), "phi_e_eu": (eu, e, 0)}
    tests = []
    for name, (a, b, first) in series.items():
        values = _corr(a, b, range(first, lags + 1))
        outside = sum(1 for v in values if not abs(v) <= band)
        tests.append(CorrelationTest(name=name, first_lag=first, values=tuple(values), band=band,
                                     outside=outside, allowed=allowed_outside(len(values))))
    return tuple(tests)


@dataclass(frozen=True, kw_only=True)
class Validation(Result):
    """The verdict on a model's adequacy, from held-out data.

    Attributes
    ----------
    free_run_error : float
        Held-out free-run RRSE (``inf`` after a blow-up).
    free_run_limit : float
        :data:`FREE_RUN_LIMIT`.
    one_step_error : float
        Held-out one-step RRSE (with the noise model, if any).
    held_out : int
        Held-out samples.
    tests : tuple of CorrelationTest
    adequate : bool
    reason : str
    noise_floor : float
        The RRSE of the measurement noise in the held-out part (an estimate).
    noise_floor_method : str
        ``"periods"``, ``"rich model"`` or ``"none"`` (see
        :func:`gfrf.identify.floor.noise_floor`).
    """

    _keys = {"held_out": "held_out_samples"}
    _order = ("free_run_error", "free_run_limit", "free_run_passed", "noise_floor",
              "noise_floor_method", "noise_floor_kind", "model_error", "one_step_error",
              "held_out_samples", "tests", "adequate", "reason")

    free_run_error: float
    free_run_limit: float
    one_step_error: float
    held_out: int
    tests: tuple[CorrelationTest, ...]
    adequate: bool
    reason: str
    noise_floor: float = 0.0
    noise_floor_method: str = "none"

    @property
    def model_error(self) -> float:
        """The held-out free-run RRSE above the noise floor."""
        return model_error(self.free_run_error, self.noise_floor)

    @property
    def free_run_passed(self) -> bool:
        """True when the model error is below the limit and the floor below its own."""
        return self.model_error < self.free_run_limit and self.noise_floor < MAX_NOISE_FLOOR

    def _computed(self) -> dict[str, Any]:
        return {"free_run_passed": self.free_run_passed, "noise_floor_kind": "estimate",
                "model_error": self.model_error,
                "tests": {t.name: t for t in self.tests}}

    def text(self) -> list[str]:
        """Lines for the text output."""
        run = "passed" if self.free_run_passed else "FAILED"
        lines = [f"validation on the held-out last {self.held_out} samples:",
                 f"  noise floor {self.noise_floor:.4g} (RRSE of the measurement noise, "
                 f"estimated from the {self.noise_floor_method}; limit {MAX_NOISE_FLOOR:g})",
                 f"  free-run RRSE {self.free_run_error:.4g}: model error above the floor "
                 f"{self.model_error:.4g} (limit {self.free_run_limit:g}): {run}"]
        for t in self.tests:
            lines.append(f"  {t.name:9s} {t.outside:2d} of {len(t.values)} lags outside "
                         f"+-{t.band:.3g} (allowed {t.allowed}), max |phi| "
                         f"{max(abs(v) for v in t.values):.3g}: "
                         f"{'passed' if t.passed else 'FAILED'}")
        lines.append(f"adequate: {'yes' if self.adequate else 'no'} ({self.reason})")
        return lines


def judge(free_run_error: float, one_step_error: float, residual: np.ndarray,
          u: np.ndarray, blowup: int | None = None, floor: float = 0.0,
          noise_floor: float = 0.0, noise_floor_method: str = "none") -> Validation:
    """Sum up the held-out evidence (``floor`` as in :func:`correlation_tests`).

    The model error is the part of the free-run RRSE above the ``noise_floor`` (an RRSE,
    :func:`gfrf.identify.floor.noise_floor`): ``sqrt(free^2 - floor^2)``.  Adequate when
    the free run did not blow up, the noise floor is below :data:`MAX_NOISE_FLOOR`, the
    model error is below :data:`FREE_RUN_LIMIT`, and every correlation test passes or
    the model error is below :data:`PRECISE_FIT`.

    Parameters
    ----------
    free_run_error, one_step_error : float
        Held-out free-run and one-step RRSE.
    residual : numpy.ndarray
        Held-out one-step residuals.
    u : numpy.ndarray
        Held-out input, aligned with ``residual``.
    blowup : int, optional
        Held-out sample at which the free run blew up.
    floor : float
        Residuals of root mean square at most this are an exact fit.
    noise_floor : float
        The noise floor as an RRSE (:func:`gfrf.identify.floor.noise_floor`).
    noise_floor_method : str
        How it was estimated.
    """
    tests = correlation_tests(residual, u, floor=floor)
    failed = [t.name for t in tests if not t.passed]
    excess = model_error(free_run_error, noise_floor)
    above = (f"model error {excess:.4g} (held-out free-run RRSE {free_run_error:.4g} above "
             f"the noise floor {noise_floor:.4g})")
    if blowup is not None:
        reason = f"the free run blew up at held-out sample {blowup}"
    elif not noise_floor < MAX_NOISE_FLOOR:
        reason = (f"the noise floor {noise_floor:.4g} is not below {MAX_NOISE_FLOOR:g}: the "
                  f"noise hides model errors of the size the limit {FREE_RUN_LIMIT:g} allows")
    elif not excess < FREE_RUN_LIMIT:
        reason = (f"{above} is not below {FREE_RUN_LIMIT:g}: the model does not reproduce "
                  f"the data")
    elif failed and excess < PRECISE_FIT:
        reason = (f"{above} < {PRECISE_FIT:g}: the model reproduces unseen data to 1 % "
                  f"of the output beyond the noise, so the failed correlation tests "
                  f"({', '.join(failed)}) show its small structural error, not missing "
                  f"dynamics")
    elif failed:
        reason = (f"correlation tests failed ({', '.join(failed)}): the residuals are not "
                  f"white and independent of the input, so the model misses dynamics or "
                  f"noise structure")
    else:
        exact = " (residuals at rounding level: an exact fit)" if not any(
            any(t.values) for t in tests) else ""
        reason = (f"{above} < {FREE_RUN_LIMIT:g} and all {len(tests)} correlation tests "
                  f"passed{exact}")
    adequate = blowup is None and noise_floor < MAX_NOISE_FLOOR and excess < FREE_RUN_LIMIT \
        and (not failed or excess < PRECISE_FIT)
    return Validation(free_run_error=free_run_error, free_run_limit=FREE_RUN_LIMIT,
                      one_step_error=one_step_error, held_out=int(residual.size), tests=tests,
                      adequate=adequate, reason=reason, noise_floor=noise_floor,
                      noise_floor_method=noise_floor_method)


def model_error(free_run_error: float, noise_floor: float) -> float:
    """The part of a free-run RRSE above the noise floor, ``sqrt(free^2 - floor^2)``
    (0 when the free run is at or below the floor; inf after a blow-up).

    Parameters
    ----------
    free_run_error : float
        Held-out free-run RRSE.
    noise_floor : float
        The noise floor as an RRSE.
    """
    if not math.isfinite(free_run_error):
        return math.inf
    return math.sqrt(max(0.0, free_run_error**2 - noise_floor**2))
