"""Multisine designs: the grid, the amplitude, the periods, and the lines a design isolates."""

from __future__ import annotations

import itertools
import math
from collections import Counter

import numpy as np
import pytest

from gfrf.errors import ArgumentError
from gfrf.identify.multisine import combination_lines, multisine


def test_random_odd_grid_leaves_one_odd_line_in_three_and_every_even_line_free() -> None:
    design = multisine(1024, 0.01, realisations=2, periods=3, rms=0.7, seed=4)
    lines = np.array(design.lines)
    assert np.all(lines % 2 == 1)
    odd = np.arange(1, 1024 // 8 + 1, 2)
    for start in range(0, odd.size - 2, 3):
        assert np.sum(np.isin(odd[start:start + 3], lines)) == 2
    spectrum = np.fft.rfft(design.u[0, :1024]) / 1024
    excited = np.flatnonzero(np.abs(spectrum) > 1e-9)
    assert excited.tolist() == lines.tolist()
    # flat amplitude, the RMS asked for, the same samples in every period
    assert np.allclose(np.abs(spectrum[lines]), np.abs(spectrum[lines[0]]))
    assert np.std(design.u[1]) == pytest.approx(0.7, rel=1e-12)
    assert np.allclose(design.u[:, :1024], design.u[:, 1024:2048])
    # new phases in every realisation, the same bytes for the same seed
    assert not np.allclose(design.u[0], design.u[1])
    assert np.array_equal(design.u, multisine(1024, 0.01, realisations=2, periods=3, rms=0.7,
                                              seed=4).u)


def test_levels_scale_the_realisations() -> None:
    design = multisine(256, 0.1, realisations=3, periods=1, rms=2.0, levels=(1.0, 0.25))
    assert design.u.shape == (6, 256)
    assert np.std(design.u[:3], axis=1) == pytest.approx([2.0] * 3)
    assert np.std(design.u[3:], axis=1) == pytest.approx([0.5] * 3)


def _reach(lines: tuple[int, ...], n: int) -> Counter[int]:
    """Every combination of one to three signed excited lines (no x, -x pair in a
    triple or pair), counted on the folded output line."""
    signed = list(lines) + [-k for k in lines]
    reach: Counter[int] = Counter()
    for order in (1, 2, 3):
        for combo in itertools.combinations_with_replacement(signed, order):
            if any(-x in combo for x in combo):
                continue
            s = abs(sum(combo)) % n
            s = min(s, n - s)
            if sum(combo) > 0 or order == 1 and combo[0] > 0:
                reach[s] += 1
    return reach


def test_isolating_grid_gives_every_combination_a_line_of_its_own() -> None:
    design = multisine(2048, 0.05, grid="isolating", realisations=1, periods=1)
    reach = _reach(design.lines, 2048)
    assert max(reach.values()) == 1
    assert max(reach) < 1024
    isolated = design.isolated()
    pairs = len(design.lines) * (len(design.lines) + 1) // 2 + math.comb(len(design.lines), 2)
    assert len(isolated[2]) == pairs
    for order in (2, 3):
        for c in isolated[order]:
            assert sum(c.factors) == c.line and len(c.factors) == order
            assert c.count == math.factorial(order) // math.prod(
                math.factorial(v) for v in Counter(c.factors).values())


def test_a_line_reached_twice_is_not_isolated() -> None:
    # 1 + 5 = 6 = 3 + 3: line 6 has two second-order combinations; 3 + 5 + 5 = 13 alone
    iso = combination_lines((1, 3, 5), 64)
    assert 6 not in [c.line for c in iso[2]]
    assert 13 in [c.line for c in iso[3]]
    # lines 1 + 1 + 1 = 3 falls on an excited line: not an H3 line
    assert 3 not in [c.line for c in iso[3]]


@pytest.mark.parametrize("kwargs, match", [
    ({"period": 8}, "at least 16"), ({"sample_time": -1.0}, "sample_time"),
    ({"grid": "even"}, "grid"), ({"rms": float("nan")}, "rms"),
    ({"levels": (1.0, 1.0)}, "levels"), ({"levels": (2.0,)}, "levels"),
    ({"realisations": 1000, "periods": 1000}, "above the limit"),
    ({"max_line": 600}, "max_line")])
def test_bad_designs_are_refused_before_any_work(kwargs: dict, match: str) -> None:
    args = {"period": 1024, "sample_time": 0.1} | kwargs
    with pytest.raises(ArgumentError, match=match):
        multisine(args.pop("period"), args.pop("sample_time"), **args)


def test_plot_shows_the_excited_lines() -> None:
    figure = multisine(256, 0.1).plot()
    ax = figure.axes[0]
    assert "rad/s" in ax.get_xlabel() and "dB" in ax.get_ylabel()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["other lines (drawn 100 dB below the top when lower)", "excited lines"]
