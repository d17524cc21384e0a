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
    # gfrf's exact transition values agree with the independent brentq + DOP853 reference,
    # and the fair baselines (brentq + solve_ivp) are in the table beside them
    exact = [r for r in section.rows if str(r[0]).startswith("exact transition")]
    assert any("brentq + solve_ivp RK45" in str(r[1]) for r in exact)
    ours = [r for r in exact if str(r[1]).startswith("gfrf")]
    assert len(ours) == 3
    assert all(float(r[4]) < 1e-10 for r in ours)
    # the exact transition value is at least level with brentq + solve_ivp RK45
    # (rtol 1e-10, atol 1e-12) in time, at no worse accuracy (measured in the same run;
    # the margin today is about 30x)
    value = [r for r in exact if str(r[0]).startswith("exact transition value")]
    rk45 = next(r for r in value if r[1] == "brentq + solve_ivp RK45, rtol 1e-10, atol 1e-12")
    assert float(value[0][3]) <= float(rk45[3])
    assert float(value[0][4]) <= float(rk45[4])
