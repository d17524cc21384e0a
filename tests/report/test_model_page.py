"""Model pages: the sentence beside the linear-versus-nonlinear table follows its rows."""

from __future__ import annotations

import pytest

from gfrf.report.model_page import growth_sentence


def _rows(power: int, relative_power: int) -> list[dict[str, float]]:
    """Rows of a difference c a^power and a relative difference c' a^relative_power."""
    return [{"angle_deg": a, "max_abs_error": 4e-8 * a**power,
             "relative_error": 2e-6 * a**relative_power} for a in (5.0, 10.0, 15.0)]


def test_a_cubic_difference_is_called_cubic() -> None:
    assert growth_sentence(_rows(3, 2)) == (
        "the difference grows like angle^3 (relative to the response: angle^2), the size "
        "of the neglected cubic terms.")


@pytest.mark.parametrize(("power", "relative", "size"), [(2, 1, "quadratic"),
                                                          (5, 4, "degree-5")])
def test_the_powers_follow_the_numbers(power: int, relative: int, size: str) -> None:
    text = growth_sentence(_rows(power, relative))
    assert f"like angle^{power} (relative to the response: angle^{relative})" in text
    assert f"the neglected {size} terms" in text


def test_the_cart_pole_rows_of_the_report_grow_like_the_cube() -> None:
    # the rows printed in reports/models/cartpole.md (5, 10, 15 degrees)
    rows = [{"angle_deg": 5.0, "max_abs_error": 4.7681e-06, "relative_error": 5.46384e-05},
            {"angle_deg": 10.0, "max_abs_error": 3.8567e-05, "relative_error": 0.000220973},
            {"angle_deg": 15.0, "max_abs_error": 0.000132609, "relative_error": 0.000506529}]
    assert "grows like angle^3 (relative to the response: angle^2)" in growth_sentence(rows)
