"""from_tf / from_nlsys under hostile input: refused before the work, with the
documented error type, never a silent loss (complex coefficients)."""

from __future__ import annotations

import math
import resource
from typing import Any

import numpy as np
import pytest

from gfrf.errors import ArgumentError, ModelError
from gfrf.model import from_control
from gfrf.model.from_control import from_nlsys, from_tf

control = pytest.importorskip("control")


class _ComplexTf:
    """A transfer-function look-alike with a complex denominator (control.tf refuses
    one; its arrays can still hold them)."""

    num = [[np.array([1.0])]]
    den = [[np.array([1.0, 0.2 + 0.5j, 1.0])]]
    ninputs = noutputs = 1
    dt = 0


def test_complex_transfer_function_coefficients_are_refused() -> None:
    G = _ComplexTf()
    with pytest.raises(ArgumentError, match="complex"):
        from_tf(G, {3: 0.5})


def test_complex_nonlinearity_coefficients_are_refused() -> None:
    with pytest.raises(ArgumentError, match="complex"):
        from_tf(control.tf([1.0], [1.0, 0.2, 1.0]), {3: 0.5 + 1j})


def test_a_huge_leibniz_expansion_is_refused_before_it_is_built(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """D^19 (y**15) has p(19, <= 15) = 480 terms per numerator coefficient; 20 of them,
    each of 15 factors, exceed the text limit: refused without expanding."""
    def refuse(*args: object) -> None:
        raise AssertionError("the expansion started before the size check")

    monkeypatch.setattr(from_control, "_power_derivative", refuse)
    G = control.tf([1.0] * 20, [1.0] * 21)
    with pytest.raises(ArgumentError, match="MAX_TERMS|MAX_TEXT_LENGTH"):
        from_tf(G, {15: 0.5})


def test_partition_count_matches_the_expansion() -> None:
    """The a-priori count equals the Leibniz expansion's number of distinct terms."""
    for order, power in [(0, 3), (5, 1), (6, 3), (10, 4), (12, 12)]:
        assert from_control._partitions(order, power) == len(
            from_control._power_derivative("y", power, order))


def test_a_denominator_above_the_derivative_limit_is_refused() -> None:
    with pytest.raises(ArgumentError, match="MAX_DERIVATIVE_ORDER"):
        from_tf(control.tf([1.0], [1.0] * 22), {3: 0.5})


class _Fake:
    """An nlsys look-alike with a chain of ``n`` integrators and a chosen update result."""

    def __init__(self, n: int, update: Any = None, nstates: Any = None) -> None:
        self.nstates = n if nstates is None else nstates
        self.ninputs = self.noutputs = 1
        self.dt = 0
        self._n = n
        self._update = update

    def dynamics(self, t: float, x: np.ndarray, u: np.ndarray) -> Any:
        if self._update is not None:
            return self._update
        return np.r_[x[1:], -x[0] + u[0]] if self._n > 1 else -x + u

    def output(self, t: float, x: np.ndarray, u: np.ndarray) -> Any:
        return x[:1]


def test_the_monomial_limit_is_checked_before_the_list(monkeypatch: pytest.MonkeyPatch) -> None:
    """1,500 states to order 3: C(1504, 3) = 566 million monomials, counted not listed."""
    def refuse(*args: object) -> None:
        raise AssertionError("the monomial list was built before the limit was checked")

    monkeypatch.setattr(from_control.itertools, "combinations_with_replacement", refuse)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with pytest.raises(ModelError, match=str(math.comb(1504, 3))):
        from_nlsys(_Fake(1500), order=3)
    assert (soft, hard) == resource.getrlimit(resource.RLIMIT_AS)


@pytest.mark.parametrize("update", ["abc", {"a": 1}, [1j, 0.0], [[1.0], [2.0, 3.0]],
                                    [0.0, 0.0, 0.0], object()])
def test_hostile_return_values_are_model_errors(update: Any) -> None:
    with pytest.raises(ModelError):
        from_nlsys(_Fake(2, update=update), order=2)


@pytest.mark.parametrize("nstates", ["2", 2.0, None.__class__, True])
def test_hostile_state_counts_are_model_errors(nstates: Any) -> None:
    with pytest.raises(ModelError):
        from_nlsys(_Fake(2, nstates=nstates), order=2)
