"""r* of a plant with an unstable linear part is not called a proven stability radius."""

from __future__ import annotations

import pytest

from gfrf.cli import main
from gfrf.model.equation import parse_model
from gfrf.stability.criteria import verdict

#: A(s) = s^2 - 0.2 s + 1: poles 0.1 +- 0.995j, in the right half-plane (closed form).
UNSTABLE = "D(y,2) - 0.2*D(y) + y + 0.5*y**3 = u"
STABLE = "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u"


def test_the_radius_of_an_unstable_plant_says_what_it_bounds() -> None:
    v = verdict(parse_model(UNSTABLE), order=3)
    assert v.linear_stable is False
    assert "L-infinity" in v.radius_kind and "no stability radius" in v.radius_kind
    assert "L-infinity" in v.to_dict()["radius_kinds"]["radius"]
    stable = verdict(parse_model(STABLE), order=3)
    assert stable.linear_stable is True and stable.radius_kind == "proven"


def test_gfrf_verdict_does_not_call_it_proven_alone(capsys: pytest.CaptureFixture) -> None:
    assert main(["verdict", UNSTABLE, "--order", "3"]) == 1
    out = capsys.readouterr().out
    line = next(s for s in out.splitlines() if s.startswith("radius (lower bound r*"))
    assert "not H-infinity" in line and "no stability radius" in line
    assert not line.startswith("radius (lower bound r*, proven):")
