"""Model file, physical mapping and range warnings."""

from fractions import Fraction

import pytest

from gfrf.errors import ArgumentError, ModelError
from gfrf.periodic.equation import (
    check_paper_range,
    load_model,
    parse_branch,
    physical_to_dimensionless,
    sin_taylor_coefficients,
)


def test_model_file_maps_to_paper_parameters():
    m = load_model()
    assert m.truncation == 3
    assert m.eps == pytest.approx(m.A / m.L)
    assert m.delta == pytest.approx(-m.g / (m.L * m.omega**2))
    assert -1 < m.delta < 0 < m.eps < 1


def test_non_parametric_file_refused(tmp_path):
    p = tmp_path / "x.toml"
    p.write_text('kind = "polynomial"\n')
    with pytest.raises(ModelError, match="not a parametric"):
        load_model(p)


def test_mapping_and_taylor():
    assert physical_to_dimensionless(2.0, 0.5, 10.0, 9.8) == pytest.approx((0.25, -0.049))
    assert sin_taylor_coefficients(5) == {1: 1, 3: Fraction(-1, 6), 5: Fraction(1, 120)}
    with pytest.raises(ArgumentError):
        sin_taylor_coefficients(4)


def test_branch_labels_and_warnings():
    assert parse_branch(0.25) == "1/4" and parse_branch("0") == "0"
    with pytest.raises(ArgumentError, match="branch"):
        parse_branch("1/2")
    with pytest.warns(UserWarning, match="eps"):
        check_paper_range(1.5)
    with pytest.warns(UserWarning, match="delta"):
        check_paper_range(0.5, 0.2)
