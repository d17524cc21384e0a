"""The periodic benchmark section runs quickly and meets its targets."""

from gfrf.bench import SECTION_MODULES
from gfrf.bench.periodic import run


def test_quick_bench_section():
    assert "gfrf.bench.periodic" in SECTION_MODULES
    section = run(quick=True)
    targets = [r for r in section.rows if r[5]]
    assert len(targets) == 3
    assert all(r[6] == "yes" for r in targets)
    assert "| transition curve, branch 1/4 | homotopy" in section.to_markdown()
