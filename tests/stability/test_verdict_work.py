"""A verdict does only the work it reports: ``norms=none|fast|tight``.

The conclusions (verdict, r*, its proof label, every condition) must not depend on the
bracket level; tighter brackets lie inside the fast ones; the fast level runs no
branch-and-bound; a Theorem 1 verdict never imports python-control.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gfrf.bounds.norms
from gfrf.errors import ArgumentError
from gfrf.model.equation import parse_model
from gfrf.model.modelfile import load_model
from gfrf.stability.criteria import verdict
from gfrf.stability.theorem1 import DEFAULT_NORMS, NORM_LEVELS, theorem1

ROOT = Path(__file__).resolve().parents[2]
MODELS = sorted(p.name for p in (ROOT / "models").glob("*.toml")
                if 'kind = "parametric"' not in p.read_text())
ORDER = 3


def _conclusions(v: object) -> tuple:
    return (v.verdict, v.radius, v.radius_proof, v.radius_certified,  # type: ignore[attr-defined]
            tuple((c.name, c.passed) for c in v.conditions))  # type: ignore[attr-defined]


@pytest.fixture(scope="module")
def by_level() -> dict[str, dict[str, object]]:
    return {name: {level: verdict(load_model(str(ROOT / "models" / name)), ORDER,
                                  norms=level) for level in NORM_LEVELS}
            for name in MODELS}


def test_every_bundled_model_is_covered() -> None:
    assert len(MODELS) >= 10 and "cartpole.toml" in MODELS
    assert "parametric_pendulum.toml" not in MODELS


@pytest.mark.slow  # every bundled model at every norm level
@pytest.mark.parametrize("name", MODELS)
def test_conclusions_do_not_depend_on_the_norm_level(by_level, name: str) -> None:
    none, fast, tight = (by_level[name][level] for level in ("none", "fast", "tight"))
    assert _conclusions(none) == _conclusions(fast) == _conclusions(tight)
    # the series rows carry the same certified majorant at every level
    assert [r["majorant"] for r in none.series] == [r["majorant"] for r in tight.series]


@pytest.mark.slow  # every bundled model at every norm level
@pytest.mark.parametrize("name", MODELS)
def test_tight_brackets_lie_inside_the_fast_ones(by_level, name: str) -> None:
    none, fast, tight = (by_level[name][level] for level in ("none", "fast", "tight"))
    assert none.norms == () and none.radius_estimate is None
    assert [b.order for b in fast.norms] == [b.order for b in tight.norms] == [1, 2, 3]
    for f, t in zip(fast.norms, tight.norms, strict=True):
        # Both lower ends are proven values at witness points; the tight search may settle
        # on a point a few ulps below the fast one, never meaningfully lower.
        assert f.lower <= t.lower * (1 + 1e-12) and t.lower <= t.upper <= f.upper
        if math.isfinite(f.upper):  # the fast upper end is the certified majorant
            assert f.upper == pytest.approx(fast.series[f.order - 1]["majorant"], rel=1e-12)


def test_fast_h1_bracket_contains_the_closed_form() -> None:
    # y'' + c y' + k y = u: sup |1/(k - w^2 + j c w)| = 1 / (c sqrt(k - c^2/4)) (c^2 < 2k)
    c, k = 0.3, 2.0
    v = theorem1(parse_model(f"D(y,2) + {c}*D(y) + {k}*y + 0.5*y**3 = u"), 3, 0.01,
                 norms="fast")
    exact = 1.0 / (c * math.sqrt(k - c * c / 4))
    h1 = v.norms[0]
    assert h1.lower * (1 - 1e-12) <= exact <= h1.upper * (1 + 1e-12)
    # H3 of a pure cubic: |c3| ||H1||^3 sup|1/A| (attained at (w_r, w_r, -w_r))
    h3 = v.norms[2]
    closed = 0.5 * exact ** 4
    assert h3.lower * (1 - 1e-9) <= closed <= h3.upper * (1 + 1e-9)


def test_fast_level_runs_no_branch_and_bound(monkeypatch: pytest.MonkeyPatch) -> None:
    calls = []
    real = gfrf.bounds.norms.branch_and_bound
    monkeypatch.setattr(gfrf.bounds.norms, "branch_and_bound",
                        lambda *a, **k: calls.append(a) or real(*a, **k))
    mf = load_model(str(ROOT / "models" / "cartpole.toml"))
    fast = verdict(mf, 5, norms="fast")
    assert calls == [] and len(fast.norms) == 5
    h5 = fast.norms[4]
    assert 0 < h5.lower <= h5.upper
    verdict(mf, 3, norms="tight")
    assert calls, "the tight level refines the loose brackets by branch-and-bound"


def test_default_level_and_bad_levels() -> None:
    assert DEFAULT_NORMS == "fast" and NORM_LEVELS == ("none", "fast", "tight")
    model = parse_model("D(y,2) + D(y) + 2*y + y**3 = u")
    assert verdict(model, 2, 0.1).norms == verdict(model, 2, 0.1, norms="fast").norms
    assert verdict(model, 2, 0.1, with_norms=False).norms == ()
    with pytest.raises(ArgumentError, match="norms must be one of"):
        verdict(model, 2, 0.1, norms="exact")
    with pytest.raises(ArgumentError, match="contradicts"):
        verdict(model, 2, 0.1, False, norms="tight")


def test_a_verdict_does_not_import_python_control() -> None:
    """Theorems 1 (duffing) and 2 (cartpole), one after the other in one fresh interpreter:
    the modules are checked after each verdict."""
    code = ("import sys; from gfrf.model.modelfile import load_model; "
            "from gfrf.stability.criteria import verdict\n"
            "for name in ('duffing', 'cartpole'):\n"
            "    v = verdict(load_model(f'models/{name}.toml'), 5)\n"
            "    print(name, v.theorem, 'control' in sys.modules, "
            "'scipy.signal' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True).stdout.splitlines()
    assert out == ["duffing 1 False False", "cartpole 2 False False"]


def test_radius_estimate_values_unchanged_by_the_matmul_product() -> None:
    # the truncated bivariate product against a direct double sum (exact reference)
    from gfrf.stability.estimate import _truncated_product

    rng = np.random.default_rng(3)
    n = 6
    p = rng.normal(size=(n, n)) + 1j * rng.normal(size=(n, n))
    f = rng.normal(size=(n, n)) + 1j * rng.normal(size=(n, n))
    direct = np.zeros((n, n), dtype=complex)
    for i in range(n):
        for j in range(n):
            direct[i, j] = sum(p[a, b] * f[i - a, j - b]
                               for a in range(i + 1) for b in range(j + 1))
    assert np.allclose(_truncated_product(p, f), direct, rtol=1e-14, atol=1e-14)
