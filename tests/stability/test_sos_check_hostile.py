"""Costly certificate files: ``gfrf certificate check`` refuses them by a count, in
bounded time, with the limit named (a Gram matrix of long common denominator, a
local certificate whose lambda (V - c) is millions of products)."""

from __future__ import annotations

import itertools
import json
import random
import time
from fractions import Fraction
from pathlib import Path

import pytest
from costly_certificates import padded_square

from gfrf.cli import main

CUBIC_DAMPING = "D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u"
FOURTH_ORDER = "D(y,4) + 2*D(y,3) + 3*D(y,2) + 2*D(y) + y + 0.1*y**3 = u"


def _check(model: str, cert: dict, tmp_path: Path, capsys: pytest.CaptureFixture,
           code: int = 1) -> dict:
    """Check ``cert`` for ``model``: exit ``code`` within 5 s of CPU; the JSON (exit 1) or
    the one error line (exit 2: a malformed file, named on standard error)."""
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(cert))
    t0 = time.process_time()
    assert main(["certificate", "check", model, str(path), "--json"]) == code
    assert time.process_time() - t0 < 5.0
    captured = capsys.readouterr()
    if code == 2:
        assert captured.out == "" and captured.err.count("\n") == 1
        return {"valid": False, "reason": captured.err}
    return json.loads(captured.out)


def test_gram_matrix_with_long_common_denominator_is_refused_by_its_size(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A 10 x 10 Gram matrix whose 55 entries have distinct 1000-digit denominators: its
    common denominator has about 180,000 bits and the exact characteristic polynomial
    ran for seconds (a 20 x 20 one for minutes)."""
    rng = random.Random(3)
    n = 10
    Q = [["0"] * n for _ in range(n)]
    for i in range(n):
        for j in range(i, n):
            d = rng.randrange(10**999, 10**1000)
            Q[i][j] = Q[j][i] = f"{d + 10 if i == j else 1}/{d}"
    basis = [[a, b, 0] for a in range(4) for b in range(4) if a + b <= 3][:n]
    cert = {"format": "gfrf-sos-certificate", "version": 1, "kind": "local-continuous",
            "states": ["y", "D(y,1)"], "V": [[[2, 0, 0], "1"], [[0, 2, 0], "1"]],
            "c": "1", "U": "1/100", "epsilon": "1/100",
            "multipliers": {"sigma": {"basis": basis, "Q": Q},
                            "mu": {"basis": [[0, 0, 0]], "Q": [["1"]]}, "lambda": []}}
    payload = _check(CUBIC_DAMPING, cert, tmp_path, capsys, code=2)
    assert payload["valid"] is False and "MAX_PSD" in payload["reason"]


def test_local_certificate_with_a_huge_lambda_is_refused_by_a_count(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """V = |x|^2 + (sum of 120 monomials)^2 passes the radial check (a true SOS identity
    for sigma_V) with thousands of terms; a lambda of 400 terms makes lambda (V - c)
    millions of exact products (20,000 terms ran for minutes)."""
    V, basis = padded_square()
    lam = [[list(m), "1"] for m in itertools.islice(itertools.product(range(13), repeat=5),
                                                    400)]
    cert = {"format": "gfrf-sos-certificate", "version": 1, "kind": "local-continuous",
            "states": ["y", "D(y,1)", "D(y,2)", "D(y,3)"], "c": "1000", "U": "1",
            "epsilon": "1", "V": [[list(k), str(c)] for k, c in V.items()], "gamma": "1",
            "multipliers": {"sigma": {"basis": [[0] * 5], "Q": [["1"]]},
                            "mu": {"basis": [[0] * 5], "Q": [["1"]]}, "lambda": lam,
                            "sigma_V": {"basis": basis, "Q": [["1"] * 120] * 120}}}
    payload = _check(FOURTH_ORDER, cert, tmp_path, capsys)
    assert payload["valid"] is False and "MAX_PRODUCT_WORK" in payload["reason"]


def test_refusal_of_a_long_rational_stays_one_short_line(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A lambda coefficient of 3,990 digits makes the failing identity's difference a
    number of thousands of digits: the refusal names the monomial and cuts the number."""
    cert = {"format": "gfrf-sos-certificate", "version": 1, "kind": "local-continuous",
            "states": ["y", "D(y,1)"], "V": [[[2, 0, 0], "1"], [[0, 2, 0], "1"]],
            "c": "1", "U": "1/100", "epsilon": "1/100",
            "multipliers": {"sigma": {"basis": [[0, 0, 0]], "Q": [["1"]]},
                            "mu": {"basis": [[0, 0, 0]], "Q": [["1"]]},
                            "lambda": [[[0, 0, 0], "1/" + "9" * 3990]]}}
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(cert))
    assert main(["certificate", "check", CUBIC_DAMPING, str(path)]) == 1
    out = capsys.readouterr().out
    assert len(out.splitlines()) == 1 and "identity fails" in out and len(out) < 300


def test_rationals_are_ascii_digits_only() -> None:
    from gfrf.stability.implicit_check import _q
    from gfrf.stability.sos_check import q

    for parse in (q, _q):
        assert parse("-3/4") == Fraction(-3, 4)
        for text in ("２２０", "٣/4", "1.5", "1e3", True, 0.5):
            with pytest.raises(ValueError):
                parse(text)
