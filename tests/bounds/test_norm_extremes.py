"""Edge cases of the kernel-norm brackets: hostile inputs.

Overflowing coefficients, underflowing kernels, float proofs on clustered poles and the
branch-and-bound started without a witness: each gets a sound bracket, no traceback.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
from bounds.test_branch_bound import true_quadratic_max

from gfrf.bounds.branch_bound import branch_and_bound
from gfrf.bounds.norms import kernel_norm
from gfrf.model.equation import parse_model


def test_resonance_at_1e39_rad_s_keeps_the_sound_bracket() -> None:
    """The quadratic oscillator of test_branch_bound scaled to w0 = 1e39 rad/s: its
    derivative polynomials overflow doubles, so the branch-and-bound is skipped (with a
    note) and the proven majorant bracket, which holds the true sup, is returned."""
    m = parse_model("D(y,2) + 2e38*D(y) + 1e78*y + 4e77*y**2 = 1e78*u")
    b = kernel_norm(m, 2)
    true = true_quadratic_max()
    assert b.lower <= true * (1 + 1e-12) and true <= b.upper
    assert any("branch-and-bound skipped" in note for note in b.notes)


def test_underflowing_kernel_gets_a_positive_upper_end() -> None:
    """sup |H_4| is about 2.6e-398 (below the double range): never certified as 0."""
    m = parse_model("D(y,2) + 0.2*D(y) + y + 0.4*y**2 = 1e-100*u")
    for proof in ("interval", "float"):
        b = kernel_norm(m, 4, proof=proof)
        assert b.upper > 0.0 and b.lower >= 0.0


def test_overflowing_majorant_is_explained() -> None:
    b = kernel_norm(parse_model("D(y,2) + 0.2*D(y) + y + 0.4*y**2 = 1e100*u"), 4)
    assert b.upper == math.inf and any("overflows" in note for note in b.notes)


def test_float_proof_lower_end_is_attained_on_clustered_poles() -> None:
    """Two resonances 5e-7 rad/s apart, damping 2e-5: the float |H2| at the maximiser is
    off by ~1e-6 (cancellation in A(j w)); the lower end is the witness proven in balls,
    at most |H2(argmax)| from mpmath at 50 digits, and the upper end is finite."""
    coefficients = ["1", "4e-05", "2.0000010004", "4.000002e-05", "1.000001"]  # as written
    text = ("D(y,4) + 4e-05*D(y,3) + 2.0000010004*D(y,2) + 4.000002e-05*D(y) + 1.000001*y "
            "+ 0.4*y**2 = u")
    b = kernel_norm(parse_model(text), 2, proof="float")
    mp.mp.dps = 50

    def a(w: mp.mpf) -> mp.mpc:
        s = mp.mpc(0, 1) * w
        return sum(mp.mpf(c) * s ** (4 - i) for i, c in enumerate(coefficients))

    w1, w2 = (mp.mpf(x) for x in b.argmax)
    exact = abs(mp.mpf("0.4") / (a(w1) * a(w2) * a(w1 + w2)))
    assert b.lower_proof == "interval"
    assert b.lower <= exact * (1 + mp.mpf(2) ** -52)
    assert math.isfinite(b.upper) and exact <= b.upper


def test_branch_and_bound_without_a_witness_starts_at_the_resonances() -> None:
    """|H3| vanishes at 0 for an input derivative: started there, the tail width used to
    double ~60 times and the whole budget was spent at [1e-23, 1010]."""
    m = parse_model("D(y,2) + 0.2*D(y) + y + 0.4*y**2 = D(u)")
    r = branch_and_bound(m, 3, max_boxes=50_000)
    reference = kernel_norm(m, 3)
    assert r.upper >= reference.lower * (1 - 1e-12)
    assert r.lower <= reference.upper * (1 + 1e-12)
    assert (r.upper - r.lower) <= 1e-4 * r.upper
    assert r.width < 100
    np.testing.assert_allclose(r.lower, reference.lower, rtol=1e-6)
