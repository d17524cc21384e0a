"""The invariant paving of a NARX recursion: the exact check refusing tampered
certificates, and simulated bounded inputs below the radius staying inside the bound."""

from __future__ import annotations

import copy
import itertools
from fractions import Fraction

import numpy as np
import pytest
from conftest import MODELS

from gfrf.model.modelfile import resolve_model
from gfrf.stability.narx_paving import check_paving, paving_certificate
from gfrf.stability.polysys import state_form


@pytest.fixture(scope="module")
def paving():
    system = state_form(resolve_model(MODELS / "identified_example_true.toml"))
    # 1.6: below the invariant box's radius of this model (the search starts above it)
    return system, paving_certificate(system, 1.6)


def test_the_exact_check_passes_the_found_paving_and_refuses_tampering(paving):
    system, res = paving
    assert res is not None and res.radius > 1.6
    assert check_paving(system, res.certificate) == ""
    bigger = copy.deepcopy(res.certificate)
    bigger["U"] = str(Fraction(bigger["U"]) * Fraction(3, 2))
    assert check_paving(system, bigger) != ""
    # drop the outermost cell of the first output coordinate: its neighbours map into it
    holed = copy.deepcopy(res.certificate)
    holed["cells"].remove(max(holed["cells"], key=lambda c: c[0]))
    assert "leaves" in check_paving(system, holed)
    no_rest = copy.deepcopy(res.certificate)
    half = no_rest["N"] // 2
    no_rest["cells"] = [c for c in no_rest["cells"] if abs(c[0] - half) > 2]
    assert check_paving(system, no_rest) != ""
    moved = copy.deepcopy(res.certificate)
    moved["R"][0] = str(Fraction(moved["R"][0]) / 2)
    assert check_paving(system, moved) != ""


def _identified_true(u: np.ndarray) -> np.ndarray:
    m, N = u.shape
    y = np.zeros((m, N))
    for k in range(2, N):
        y1, y2, u1, u2 = y[:, k - 1], y[:, k - 2], u[:, k - 1], u[:, k - 2]
        y[:, k] = (0.6 * y1 - 0.2 * y2 + 0.5 * u1 + 0.3 * u2 + 0.15 * y1 * u1
                   - 0.1 * u1**2 - 0.05 * y1**3)
    return y


def test_bounded_inputs_below_the_paving_radius_stay_inside_the_bound(paving):
    _, res = paving
    U, N = res.radius, 300
    rng = np.random.default_rng(5)
    t = np.arange(N)
    rows = [U * rng.choice([-1.0, 1.0], size=(300, N)), U * rng.uniform(-1, 1, size=(300, N))]
    for w in np.linspace(0.05, np.pi, 40):
        rows += [U * np.cos(w * t)[None, :], U * np.sign(np.cos(w * t) + 1e-12)[None, :]]
    rows += [U * (-1.0) ** (t // p)[None, :] for p in range(1, 9)]
    signs = np.array(list(itertools.product([-1.0, 1.0], repeat=12)))
    rows.append(U * np.hstack([signs, np.repeat(signs[:, -1:], N - 12, axis=1)]))
    y = _identified_true(np.vstack(rows))
    assert np.all(np.isfinite(y)) and np.max(np.abs(y)) <= res.bound
