"""The verdict on an identified model: stable only below the lower end of its radius's spread.

An identified model's r* is proven for that model, but it estimates the system's with
the error of the coefficients.  :func:`identified_verdict` runs the verdict of the model
file (:func:`gfrf.stability.criteria.verdict`) and keeps a ``stable`` verdict only when
the amplitude is below the lower end of r* over the coefficients' uncertainty
(:attr:`gfrf.identify.spread.RadiusSpread.low`); otherwise the verdict becomes
``inconclusive`` and its summary says why.  A model judged adequate although its
correlation tests failed (its free run is within 1 % of the output beyond the noise:
a small structural error, which the coefficients' covariance does not describe) needs
the amplitude below ``(1 - STRUCTURE_MARGIN)`` times that lower end: a pruned model with
collinear lag-2 terms in place of the true lag-1 ones had r* 6.7 % above the system's.
``gfrf identify``, the report page of the identified example and the Python API all
call it, so they agree.
"""

from __future__ import annotations

from dataclasses import replace

from gfrf.identify.result import Identification
from gfrf.identify.threads import one_blas_thread
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile
from gfrf.stability.criteria import verdict
from gfrf.stability.verdicts import Verdict

__all__ = ["identified_verdict", "with_spread", "STRUCTURE_MARGIN"]

#: Relative margin below the spread's lower end that a ``stable`` verdict needs when the
#: model's correlation tests failed (a structural error the covariance does not cover).
STRUCTURE_MARGIN = 0.1


def with_spread(v: Verdict, result: Identification) -> Verdict:
    """``v`` (the verdict of ``result``'s model) with a ``stable`` kept only when the
    amplitude is below the lower end of r*'s spread.

    Parameters
    ----------
    v : Verdict
        The verdict of the identified model.
    result : Identification
        The identification (its ``radius``; without one, the verdict's own r*).
    """
    low = result.radius.low if result.radius is not None else v.radius
    structural = result.validation is not None and any(
        not t.passed for t in result.validation.tests)
    limit = low * (1 - STRUCTURE_MARGIN) if structural else low
    if v.verdict != "stable" or v.amplitude < limit:
        return v
    why = (f"below {low:.6g}, the lower end of r* over the uncertainty of the identified "
           f"coefficients" if v.amplitude >= low else
           f"below {limit:.6g}, {1 - STRUCTURE_MARGIN:g} x the lower end {low:.6g} of r* over "
           f"the uncertainty of the identified coefficients (its correlation tests failed: a "
           f"small structural error, which that uncertainty does not cover)")
    note = (f"Identified model: r = {v.amplitude:g} is below its r* = {v.radius:.6g} but not "
            f"{why}: the system's r* may be below r, so stability is not claimed. "
            f"For the identified model alone:")
    return replace(v, verdict="inconclusive", summary=f"{note} {v.summary}".strip())


def identified_verdict(result: Identification, model: ModelFile | Model | None = None,
                       order: int = 5, amplitude: float = 1.0) -> Verdict:
    """The verdict of an identified model at ``amplitude``, with the spread's rule.

    Parameters
    ----------
    result : Identification
        What :func:`gfrf.identify.fit.identify` returned.
    model : ModelFile or Model, optional
        The model file written from ``result`` (default: ``result.model``).
    order : int
        Highest kernel order whose norm brackets are reported.
    amplitude : float
        Input amplitude r.

    Returns
    -------
    Verdict
        ``stable`` only when r is below the lower end of r* (:func:`with_spread`).
    """
    with one_blas_thread():  # small complex products: threads only wait for each other
        return with_spread(verdict(result.model if model is None else model, order,
                                   amplitude), result)
