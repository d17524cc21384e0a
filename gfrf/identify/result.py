"""The result of :func:`gfrf.identify.fit.identify`: an :class:`Identification`.

The identified process model about its operating point, the noise terms, the fit
settings and the hold-out validation, with their text and JSON forms.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from gfrf._results import Result
from gfrf.identify.operating import SIGNIFICANT_DIGITS
from gfrf.identify.prune import Pruning
from gfrf.identify.spread import RadiusSpread
from gfrf.identify.validate import Validation
from gfrf.model.equation import Model

__all__ = ["Identification"]


@dataclass(frozen=True, kw_only=True, repr=False)
class Identification(Result):
    """A NARMAX model identified from data, with its fit settings, operating point and
    validation.

    ``to_dict`` adds the process terms, ``adequate``, the validation's ``reason`` and the
    significant digits, names ``structure`` ``structure_search``, gives ``full_model`` as
    its text and ``noise`` as ``noise_terms`` (``{term, coefficient}``; the field itself
    is left out).

    Attributes
    ----------
    model : Model
        The process model about the operating point (deviations ``y - y0``,
        ``u - u0``), coefficients rounded to :data:`SIGNIFICANT_DIGITS` digits.
    settings : dict
        ``ylag``, ``ulag``, ``degree``, ``criterion``, ``max_terms``, ``holdout``.
    n_samples, n_train : int
        Samples in the data and in the training part (the rest is held out).
    candidates : int
        Candidate regressors considered (constant excluded).
    regressors : tuple of dict
        Per regressor FROLS selected, in its order: ``codes``, ``theta`` (before the
        move to the operating point and before extended least squares), ``err``.
    free_run_error : float
        Root relative squared error of the free-run simulation on the held-out part
        (``inf`` when the simulation blew up).
    one_step_error : float
        Root relative squared error of one-step-ahead prediction on the held-out part.
    blowup : int or None
        Held-out sample at which the free run blew up, or None.
    notes : tuple of str
        Remarks (criterion at its limit, training window, ...).
    sysidentpy_version : str
        The installed sysidentpy whose FROLS the fit reproduces ("" when not installed;
        identification does not import it).
    operating_point : dict
        ``u0``, ``y0``, ``constant`` (the fitted constant term or None) and ``how``.
    noise : tuple of float
        Coefficients ``c_j`` of the noise terms ``c_j*e[k-j]`` (empty: none fitted).
    validation : Validation or None
        Hold-out validation (free run and correlation tests).
    structure : tuple of dict
        The structures compared when lags and degree were chosen by the criterion.
    n_fit : int
        Training samples in the candidate matrix.
    noise_model : str
        ``"none"``, ``"narmax"`` (the noise terms ``noise``) or ``"output error"``
        (white noise on the output: coefficients minimise the free-run error).
    pruning : Pruning or None
        The backward elimination after the criterion's choice (None: not run).
    full_model : Model or None
        The model with every term the criterion chose, when pruning removed some.
    radius : RadiusSpread or None
        r* of the model, of the full model, and its spread over the coefficients'
        uncertainty (None: not computed).
    """

    model: Model
    settings: dict[str, Any]
    n_samples: int
    n_train: int
    candidates: int
    regressors: tuple[dict[str, Any], ...]
    free_run_error: float
    one_step_error: float
    blowup: int | None = None
    notes: tuple[str, ...] = field(default=())
    sysidentpy_version: str = ""
    operating_point: dict[str, Any] = field(default_factory=dict)
    noise: tuple[float, ...] = field(default=())
    validation: Validation | None = None
    structure: tuple[dict[str, Any], ...] = field(default=())
    n_fit: int = 0
    noise_model: str = "none"
    pruning: Pruning | None = None
    full_model: Model | None = None
    radius: RadiusSpread | None = None

    _exclude = ("noise",)
    _keys = {"structure": "structure_search"}
    _order = ("model", "settings", "n_samples", "n_train", "n_fit", "candidates",
              "regressors", "process_terms", "noise_model", "noise_terms", "operating_point",
              "free_run_error", "one_step_error", "blowup", "notes", "structure_search",
              "validation", "adequate", "reason", "significant_digits", "pruning",
              "full_model", "radius", "sysidentpy_version")

    @property
    def adequate(self) -> bool:
        """True when the hold-out validation passed."""
        return self.validation is not None and self.validation.adequate

    def settings_text(self) -> str:
        """The fit settings as command-line options."""
        s = self.settings
        return (f"--ylag {s['ylag']} --ulag {s['ulag']} --degree {s['degree']} "
                f"--criterion {s['criterion']} --max-terms {s['max_terms']} "
                f"--holdout {s['holdout']:g}")

    def quality_text(self) -> str:
        """One line: terms chosen and the held-out errors."""
        held = self.n_samples - self.n_train
        run = (f"free run blew up at held-out sample {self.blowup}" if self.blowup is not None
               else f"free-run RRSE {self.free_run_error:.4g}")
        return (f"{len(self.regressors)} of {self.candidates} candidate terms "
                f"({self.settings['criterion'].upper()}); on the held-out last {held} of "
                f"{self.n_samples} samples: {run}, one-step RRSE {self.one_step_error:.4g}")

    def operating_text(self) -> str:
        """One line: the operating point the model and its GFRFs are about."""
        op = self.operating_point
        return (f"operating point u0 = {op['u0']:.10g}, y0 = {op['y0']:.10g} ({op['how']}); "
                f"the model, its GFRFs and the verdict are about deviations from it")

    def noise_text(self) -> str:
        """The noise model, or that there is none."""
        if self.noise_model == "output error":
            return ("noise: output error (white noise on the output; the coefficients "
                    "minimise the free-run error on the training part)")
        if not self.noise:
            return "noise terms: none"
        body = " ".join(f"{'-' if c < 0 else '+'} {abs(c):.6g}*e[k-{j}]"
                        for j, c in enumerate(self.noise, start=1))
        return (f"noise terms (extended least squares; not part of the GFRFs): e[k] {body}")

    def _computed(self) -> dict[str, Any]:
        """The terms as text, the noise terms, adequacy and the validation's reason."""
        return {"process_terms": self.model.text,
                "noise_terms": [{"term": f"e[k-{j}]", "coefficient": c}
                                for j, c in enumerate(self.noise, start=1)],
                "adequate": self.adequate,
                "reason": self.validation.reason if self.validation else "not validated",
                "significant_digits": SIGNIFICANT_DIGITS,
                "full_model": self.full_model.text if self.full_model else None}
