"""thresholds.md: the page is rendered from its facts; each sentence follows the numbers."""

from __future__ import annotations

from gfrf.report.thresholds import PendulumGap, ThresholdsFacts, render


def _gap(**change: object) -> PendulumGap:
    values: dict[str, object] = dict(stem="hanging_pendulum", theorem=1, radius=0.1, lower=0.4,
                                     upper=0.5, switching=True, upper_proof_words="proven")
    values.update(change)
    return PendulumGap(**values)  # type: ignore[arg-type]


def _page(*gaps: PendulumGap) -> str:
    return render(ThresholdsFacts(rows=[["m", "Theorem 1", 0.1, "-", 0.4, 0.5, "-", 1.0, 0.2]],
                                  gaps=gaps, figure="thresholds.png"))


def test_ratios_and_theorem_follow_the_numbers() -> None:
    page = _page(_gap())
    assert ("- `hanging_pendulum`: Theorem 1 proves 0.1 (sums of tones), the best certificate "
            "0.4 (every input with sup|u| below it), a switching input u = +-U of sup|u| 0.5 "
            "escapes (proven): r*/upper = 20.0% (Theorem 1), lower/upper = 80.0% "
            "(the best proven).") in page
    page = _page(_gap(theorem=2, switching=False, upper=2.0))
    assert "Theorem 2 proves 0.1" in page and "r*/upper = 5.0% (Theorem 2)" in page
    assert "a sum of tones of amplitude 2 escapes" in page


def test_the_best_proven_is_the_larger_radius() -> None:
    # r* above the certificate: lower/upper is no longer the best proven ratio
    page = _page(_gap(radius=0.45))
    assert "(the best proven)" not in page
    assert "lower/upper = 80.0% (below r*, which covers sums of tones only)." in page


def test_layout_without_pendulum_lines() -> None:
    page = _page()
    assert "![three regions](thresholds.png)\n\n\nUnits: r* bounds" in page
    assert page.endswith("not stability.\n") and "{" not in page
