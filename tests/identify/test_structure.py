"""Lags revised on the held-out data: which identifications are tried, which one is kept.

The identifications are stand-ins with the fields the rule reads (validation, noise
model, free-run error, r* with its spread); ``run`` records the lags it is asked for.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

from gfrf.identify.structure import WIDE_SPREAD, revise_lags

TABLE = tuple({"ylag": lag, "ulag": lag, "degree": 3, "bic": -float(lag)}
              for lag in (1, 2, 3))


@dataclass(frozen=True)
class Fake:
    lag: int
    adequate: bool
    free_run_error: float
    low: float | None
    noise_model: str = "narmax"
    structure: tuple[dict[str, Any], ...] = TABLE
    notes: tuple[str, ...] = ()
    settings: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.settings.update(ylag=self.lag, ulag=self.lag, degree=3)

    @property
    def validation(self) -> SimpleNamespace:
        return SimpleNamespace(adequate=self.adequate)

    @property
    def radius(self) -> SimpleNamespace | None:
        return None if self.low is None else SimpleNamespace(radius=1.0, low=self.low)


def _revise(first: Fake, others: dict[int, Fake]) -> tuple[Any, list[int]]:
    asked: list[int] = []

    def run(lag: int, degree: int) -> Fake:
        asked.append(lag)
        return others[lag]

    return revise_lags(first, run, "bic"), asked  # type: ignore[arg-type]


def test_a_wide_spread_tries_one_lag_fewer_and_keeps_it_when_it_is_tighter():
    first = Fake(3, True, 0.0222, 0.66)
    fewer = Fake(2, True, 0.0218, 0.99)
    kept, asked = _revise(first, {2: fewer})
    assert asked == [2] and kept.lag == 2
    assert "spread down to 0.66" in kept.notes[-1]
    assert [r["chosen"] for r in kept.structure] == [False, True, False]


def test_fewer_lags_are_not_kept_when_the_free_run_is_worse_or_the_spread_no_tighter():
    first = Fake(3, True, 0.0222, 0.66)
    worse = Fake(2, True, 0.0222 + 0.02, 0.99)  # beyond the 0.01 tolerance in quadrature
    assert _revise(first, {2: worse})[0] is first
    wider = Fake(2, True, 0.0218, 0.5)
    assert _revise(first, {2: wider})[0] is first
    refused = Fake(2, False, 0.0218, 0.99)
    assert _revise(first, {2: refused})[0] is first


def test_a_narrow_spread_of_an_adequate_model_tries_nothing():
    first = Fake(3, True, 0.0222, WIDE_SPREAD + 0.01)
    kept, asked = _revise(first, {})
    assert kept is first and asked == []
    no_radius = Fake(3, True, 0.0222, None)
    assert _revise(no_radius, {})[1] == []


def test_an_output_error_model_tries_fewer_lags_whatever_its_spread():
    first = Fake(3, True, 0.0222, 0.99, noise_model="output error")
    fewer = Fake(2, True, 0.0225, 0.95)  # a lower end no higher: kept for output error
    kept, asked = _revise(first, {2: fewer})
    assert asked == [2] and kept.lag == 2 and "output-error" in kept.notes[-1]


def test_lags_that_fail_validation_give_way_to_the_criterions_next_ones():
    first = Fake(3, False, 0.2, 0.9)
    kept, asked = _revise(first, {2: Fake(2, False, 0.2, 0.9), 1: Fake(1, True, 0.05, 0.9)})
    assert asked == [2, 1] and kept.lag == 1 and "failed validation" in kept.notes[-1]
