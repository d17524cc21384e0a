"""The radius r* of an identified model, with its spread over the parameter uncertainty.

An identified model's r* (Theorem 1's radius, proven for that model) estimates the
system's with the error of the coefficients.  :func:`radius_spread` draws
:data:`DRAWS` coefficient vectors from the normal distribution of the least-squares
estimate (mean the estimate, covariance ``s^2 (Psi^T Psi)^-1``, a fixed seed: the same
numbers on every run), computes r* of each, and reports the :data:`QUANTILE` and
``1 - QUANTILE`` quantiles.  :func:`gfrf.identify.trust.identified_verdict` states
``stable`` only below the lower end, ``low``: the smaller of that quantile and the
model's own proven r*.  The spread is an estimate (a sampled distribution), not a proof.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gfrf._results import Result, short_repr
from gfrf.errors import GfrfError
from gfrf.model.equation import Model

__all__ = ["RadiusSpread", "radius", "radius_spread", "DRAWS", "QUANTILE", "SEED", "MAX_TERMS"]

Key = tuple[tuple[int, ...], tuple[int, ...]]
#: Coefficient vectors drawn.
DRAWS = 40
#: The lower end's quantile of the drawn radii.
QUANTILE = 0.05
#: Seed of the draws.
SEED = 0
#: Largest model whose r* is drawn (r* of a larger one is computed once).
MAX_TERMS = 40


@dataclass(frozen=True, kw_only=True)
class RadiusSpread(Result):
    """r* of the identified (pruned) model and of the full one, with the spread.

    Attributes
    ----------
    radius : float
        r* of the identified model (Theorem 1, proven for that model).
    full : float or None
        r* of the full model (every term the criterion chose), None when not pruned.
    low, high : float
        The :data:`QUANTILE` and ``1 - QUANTILE`` quantiles of r* over the draws;
        ``low`` is at most ``radius``.
    draws : int
        Coefficient vectors drawn (0: no covariance, ``low = high = radius``).
    kind : str
        ``"estimate"``: the quantiles are of a sampled distribution.
    """

    radius: float
    full: float | None
    low: float
    high: float
    draws: int
    kind: str = "estimate"



    def __repr__(self) -> str:
        return short_repr(self, "radius", "low", "high")

    def text(self) -> str:
        """One line for the text output."""
        full = f"; with every term r* = {self.full:.6g}" if self.full is not None else ""
        if not self.draws:
            return f"radius: identified r* = {self.radius:.6g}{full}"
        return (f"radius: identified r* = {self.radius:.6g} (proven for this model){full}; "
                f"over the coefficients' uncertainty ({self.draws} draws from the least-"
                f"squares covariance, an estimate) r* is {self.low:.6g} to {self.high:.6g} "
                f"({QUANTILE:.0%} to {1 - QUANTILE:.0%}); a verdict uses {self.low:.6g}")


def radius(model: Model, proof: str = "interval") -> float:
    """Theorem 1's r* of ``model`` (inf for a linear model).

    Parameters
    ----------
    model : Model
        A NARX model.
    proof : {"interval", "float"}
        Proof level of r*.
    """
    from gfrf.stability.theorem1 import theorem1

    return float(theorem1(model, 1, 1.0, with_norms=False, proof=proof).radius)


def radius_spread(model: Model, keys: list[Key], theta: np.ndarray, cov: np.ndarray,
                  build: Callable[[dict[Key, float]], Model], full: float | None = None,
                  draws: int = DRAWS) -> RadiusSpread:
    """r* of ``model`` and its quantiles over ``draws`` coefficient vectors.

    Parameters
    ----------
    model : Model
        The identified model.
    keys, theta, cov : list, numpy.ndarray, numpy.ndarray
        The monomials, their estimate and its covariance (in the coordinates of the fit).
    build : callable
        The model of a coefficient dict (the same steps as the identified model: operating
        point, rounding); it may raise :class:`~gfrf.errors.GfrfError` for a draw without
        an equilibrium, which is then skipped.
    full : float, optional
        r* of the full model, reported alongside.
    draws : int
        Coefficient vectors drawn (0: none; none either for a model of more than
        :data:`MAX_TERMS` terms).
    """
    point = radius(model)
    values = []
    if draws and len(keys) <= MAX_TERMS and np.all(np.isfinite(cov)):
        rng = np.random.default_rng(SEED)
        w, v = np.linalg.eigh((cov + cov.T) / 2)
        root = v * np.sqrt(np.maximum(w, 0.0))
        for z in rng.standard_normal((draws, len(keys))):
            sample = theta + root @ z
            try:
                drawn = build({k: float(c) for k, c in zip(keys, sample, strict=True)})
            except GfrfError:
                continue
            values.append(radius(drawn, proof="float"))
    if not values:
        return RadiusSpread(radius=point, full=full, low=point, high=point, draws=0)
    low, high = (float(np.quantile(values, q, method="inverted_cdf"))
                 for q in (QUANTILE, 1 - QUANTILE))
    low = min(low, point)
    return RadiusSpread(radius=point, full=full, low=low if math.isfinite(low) else point,
                        high=high, draws=len(values))
