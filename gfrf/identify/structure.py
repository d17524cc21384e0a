"""Lags the held-out data agree with, when the criterion's lags are suspect.

A one-step information criterion compares lags by how well they predict the next
sample.  With output noise the equation error is coloured, and extra output lags
predict the noise: on a lightly damped system sampled fast the criterion takes the
largest lag searched.  :func:`revise_lags` checks that choice on the held-out data:

- when the chosen lags fail validation, at most :data:`RETRIES` other lags are tried,
  in the criterion's order, with the largest degree compared (the grow and prune steps
  then choose the terms), and the first adequate model is kept;
- when the chosen model is adequate but its noise model is output error (extended least
  squares could not whiten the residuals: the criterion's residuals were coloured), or
  its r* spreads wide over the coefficients' uncertainty (the lower end below
  :data:`WIDE_SPREAD` times r*), the next smaller lags are tried and kept when adequate
  with a held-out free run within :data:`~gfrf.identify.prune.TOLERANCE` (in quadrature)
  of the chosen one's (and, for a wide spread, a higher lower end): an extra lag that
  the free run does not need is a pole and a zero that nearly cancel, which widen the
  spread of r*.

The work is a count: at most :data:`RETRIES` more identifications.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from gfrf.identify.prune import TOLERANCE
from gfrf.identify.result import Identification

__all__ = ["revise_lags", "RETRIES", "WIDE_SPREAD"]

#: Most identifications with other lags.
RETRIES = 2
#: An adequate model whose r* has its lower end below this fraction of r* is tried with
#: fewer lags (the spread of the data sets whose lags were right is within a few %).
WIDE_SPREAD = 0.9


def revise_lags(first: Identification, run: Callable[[int, int], Identification],
                criterion: str) -> Identification:
    """The identification with the lags the held-out data agree with.

    Parameters
    ----------
    first : Identification
        The identification with the criterion's lags and degree (its ``structure``
        table compares them).
    run : callable
        ``run(lag, degree)`` identifies with ``ylag = ulag = lag`` and that degree.
    criterion : str
        The criterion's key in the ``structure`` rows.

    Returns
    -------
    Identification
        ``first``, or a revised one whose ``structure`` marks its lags as chosen and
        whose last note says why.
    """
    if not first.structure:
        return first

    def adequate(result: Identification) -> bool:
        return result.validation is not None and result.validation.adequate

    table = sorted(first.structure, key=lambda r: r[criterion])
    top = max(r["degree"] for r in table)
    lag = first.settings["ylag"]
    said = (f"the criterion's structure (--ylag {lag} --ulag {first.settings['ulag']} "
            f"--degree {first.settings['degree']})")
    def low(result: Identification) -> float:
        return -1.0 if result.radius is None else result.radius.low

    wide = first.radius is not None and low(first) < WIDE_SPREAD * first.radius.radius
    if adequate(first):
        others = [lag - 1] if (first.noise_model == "output error" or wide) and lag > 1 \
            else []
    else:
        others = list(dict.fromkeys(r["ylag"] for r in table if r["ylag"] != lag))
    for other in others[:RETRIES]:
        retry = run(other, top)
        if not adequate(retry):
            continue
        if adequate(first):
            if retry.free_run_error**2 > first.free_run_error**2 + TOLERANCE**2 or (
                    first.noise_model != "output error" and low(retry) <= low(first)):
                return first
            why = ("fitted an output-error model" if first.noise_model == "output error"
                   else f"has r* spread down to {low(first):.6g} over its coefficients' "
                        f"uncertainty")
            note = (f"{said} {why}: --ylag {other} --ulag {other} "
                    f"--degree {top} reproduces the held-out data as well, with fewer lags")
        else:
            note = f"{said} failed validation: --ylag {other} --ulag {other} --degree {top} passed"
        rows = tuple({**r, "chosen": (r["ylag"], r["degree"]) == (other, top)}
                     for r in first.structure)
        return replace(retry, structure=rows, notes=(*retry.notes, note))
    return first
