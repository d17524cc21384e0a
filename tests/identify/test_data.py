"""Data checks that follow the scale of the data, and a subnormal sample time."""

from __future__ import annotations

import numpy as np
import pytest

from gfrf.errors import ArgumentError, ModelError
from gfrf.identify.data import _check_data, _check_sample_time
from gfrf.model.equation import parse_model


def test_a_tiny_record_is_not_called_constant() -> None:
    rng = np.random.default_rng(0)
    y, u = rng.standard_normal(200) * 1e-300, rng.standard_normal(200) * 1e-300
    with pytest.raises(ArgumentError) as info:
        _check_data(y, u, 2)
    assert "constant" not in str(info.value) and "underflow" in str(info.value)


def test_a_constant_record_is_still_constant() -> None:
    with pytest.raises(ArgumentError, match="constant"):
        _check_data(np.full(100, 3.0), np.linspace(0, 1, 100), 2)


@pytest.mark.parametrize("value", [1e-310, 5e-324, 0.0, -1.0])
def test_a_subnormal_sample_time_is_refused(value: float) -> None:
    with pytest.raises(ModelError, match="normal"):
        _check_sample_time(value)
    with pytest.raises(ModelError, match="normal"):
        parse_model("y[k] - 0.5*y[k-1] = u[k-1]", sample_time=value)
