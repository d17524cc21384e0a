"""Amplitudes near the float range: the majorant terms overflow to inf, never a crash."""

import math

from gfrf.cli import main
from gfrf.model.modelfile import load_model
from gfrf.stability.criteria import verdict


def test_verdict_at_largest_amplitude_is_inconclusive_with_inf_terms():
    # Duffing: M_1 = ||H1|| = 5.03 (closed form 1/(0.2*sqrt(1 - 0.01))), so M_1 * 1e308
    # overflows; H2 = 0 gives a zero term, not 0*inf = NaN.  r* < 1e308: not proven.
    v = verdict(load_model("models/duffing.toml"), 3, 1e308, with_norms=False)
    terms = [row["majorant_term"] for row in v.series]
    assert v.verdict == "inconclusive"
    assert terms[0] == math.inf and terms[1] == 0.0 and terms[2] == math.inf
    assert not any(math.isnan(t) for t in terms)


def test_cli_verdict_at_largest_amplitude(capsys):
    code = main(["verdict", "models/duffing.toml", "--amplitude", "1e308", "--order", "3"])
    out = capsys.readouterr().out
    assert code == 1 and "verdict: inconclusive" in out and "term = inf" in out
    assert "nan" not in out.lower()
