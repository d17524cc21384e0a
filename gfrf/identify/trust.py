"""The verdict on an identified model: stable only below the lower end of its radius's spread.

An identified model's r* is proven for that model, but it estimates the system's with
the error of the coefficients.  :func:`identified_verdict` runs the verdict of the model
file (:func:`gfrf.stability.criteria.verdict`) and keeps a ``stable`` verdict only when
the amplitude is below the lower end of r* over the coefficients' uncertainty
(:attr:`gfrf.identify.spread.RadiusSpread.low`); otherwise the verdict becomes
``inconclusive`` and its summary says why.  ``gfrf identify``, the report page of the
identified example and the Python API all call it, so they agree.
"""

from __future__ import annotations

from dataclasses import replace

from gfrf.identify.result import Identification
from gfrf.identify.threads import one_blas_thread
from gfrf.model.equation import Model
from gfrf.model.modelfile import ModelFile
from gfrf.stability.criteria import verdict
from gfrf.stability.verdicts import Verdict

__all__ = ["identified_verdict", "with_spread"]


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
    if v.verdict != "stable" or v.amplitude < low:
        return v
    note = (f"Identified model: r = {v.amplitude:g} is below its r* = {v.radius:.6g} but not "
            f"below {low:.6g}, the lower end of r* over the uncertainty of the identified "
            f"coefficients: the system's r* may be below r, so stability is not claimed. "
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
