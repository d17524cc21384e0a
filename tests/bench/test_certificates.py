"""The certificate-search benchmark section: its rows and the ratio targets."""

import pytest


@pytest.mark.slow
def test_quick_certificate_section_meets_the_ratio_target() -> None:
    from gfrf.bench import SECTION_MODULES
    from gfrf.bench.certificates import run

    assert "gfrf.bench.certificates" in SECTION_MODULES
    section = run(quick=True)
    rows = {r[0]: r for r in section.rows}
    cartpole = "cartpole_reduced (input d = C r; whole threshold)"
    assert set(rows) == {"third-order plant", "PI loop", "cubic damping", cartpole,
                         "narx_example"}
    # the reduced cart-pole loop: the polygon's radius within 1.3x of the breakdown witness
    assert 1.0 <= float(rows[cartpole][4]) <= 1.3
    third = rows["third-order plant"]
    # the degree-4 search beats the quadratic baseline and is within 2x of the escape
    assert float(third[3]) > float(third[7])
    assert float(third[4]) <= 2.0
    assert float(rows["PI loop"][3]) > 0
    # the NARX example: the box-then-paving radius within 1.3x of the witnessed escape
    assert 1.0 <= float(rows["narx_example"][4]) <= 1.3
    assert "| third-order plant |" in section.to_markdown()
