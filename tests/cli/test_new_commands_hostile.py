"""Hostile input to ``gfrf threshold``, ``gfrf certificate check`` and ``gfrf frc``.

A hostile model name stays inert in ``threshold``'s text; a certificate file that is
nested too deeply, holds a huge JSON integer or a costly Gram matrix is refused with one
line and exit 2 (or refused by an exact test in bounded time), never a traceback, and a
Gram matrix that is not positive semidefinite is never accepted.
"""

from __future__ import annotations

import json
import random
import re
import sys
from fractions import Fraction
from pathlib import Path

import pytest
from costly_certificates import padded_square

from gfrf.cli import main
from gfrf.stability.sos_check import is_psd

sys.path.insert(0, str(Path(__file__).parent))
from test_hostile_names import RAW, _check_text, _model, drawn  # noqa: F401

CUBIC_DAMPING = "D(y,2) + 0.2*D(y) + y - 0.3*D(y)**3 = u"


def test_threshold_text_keeps_a_hostile_name_inert(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture) -> None:
    model = str(_model(tmp_path))
    assert main(["threshold", model, "--order", "3"]) == 0
    out, err = capsys.readouterr()
    assert not RAW.search(out + err)
    assert not any(line.startswith("verdict: stable") for line in out.splitlines())
    assert "\\r\\nverdict: stable" in out


@pytest.mark.parametrize("text, words", [
    ('{"format": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply"),
    ('{"format": "gfrf-sos-certificate", "c": 1' + "0" * 1_000_000 + "}", "digits"),
    ('{"format": ', "not JSON"),
])
def test_certificate_check_refuses_a_hostile_file_in_one_line(
        text: str, words: str, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "cert.json"
    path.write_text(text)
    assert main(["certificate", "check", CUBIC_DAMPING, str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and words in err
    assert "Traceback" not in err


def test_certificate_check_refuses_an_oversized_file(tmp_path: Path,
                                                     capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "cert.json"
    path.write_text('{"format": "' + "1" * 3_000_000 + '"}')
    assert main(["certificate", "check", CUBIC_DAMPING, str(path)]) == 2
    assert "MAX_FILE_BYTES" in capsys.readouterr().err


def _integer_matrix(rows: list[list[int]]) -> list[list[Fraction]]:
    return [[Fraction(x) for x in row] for row in rows]


def test_exact_psd_test_agrees_with_constructed_truths() -> None:
    """B B^T is PSD (singular when B has fewer columns than rows); subtracting a tiny
    multiple of z z^T, z in its null space, makes z^T Q z < 0: not PSD."""
    rng = random.Random(7)
    for n, rank in ((1, 1), (3, 1), (5, 3), (8, 8), (12, 5)):
        B = [[rng.randint(-9, 9) for _ in range(rank)] for _ in range(n)]
        Q = _integer_matrix([[sum(B[i][k] * B[j][k] for k in range(rank)) for j in range(n)]
                             for i in range(n)])
        assert is_psd(Q)
        if rank < n:  # a null vector: rank + 1 rows of B are dependent
            import sympy

            z = sympy.Matrix(B).T.nullspace()[0]
            z = [Fraction(int(sympy.fraction(v)[0]), int(sympy.fraction(v)[1])) for v in z]
            bad = [[Q[i][j] - Fraction(1, 10**30) * z[i] * z[j] for j in range(n)]
                   for i in range(n)]
            assert not is_psd(bad)
        neg = [row[:] for row in Q]
        neg[0][0] -= sum(abs(x) for row in Q for x in row) + 1
        assert not is_psd(neg)
    assert not is_psd(_integer_matrix([[1, 2], [3, 4]]))  # not symmetric
    assert is_psd([])


def test_exact_psd_test_is_fast_on_a_hostile_gram_matrix() -> None:
    """A 60 x 60 Gram matrix of 100-digit entries (a diagonally dominant one, PSD): the
    elimination with fractions took minutes; the characteristic polynomial is exact and
    fast, so a certificate of that size is checked, not hung on."""
    rng = random.Random(3)
    n = 60
    Q = [[Fraction(rng.randrange(10**99, 10**100)) for _ in range(n)] for _ in range(n)]
    for i in range(n):
        for j in range(i):
            Q[i][j] = Q[j][i]
        Q[i][i] = Fraction(10**103)
    assert is_psd(Q)
    Q[5][5] = Fraction(0)  # a zero pivot beside non-zero entries: indefinite
    assert not is_psd(Q)


def _strict(token: str) -> None:
    raise AssertionError(f"the non-JSON token {token}")


def test_every_new_json_output_is_strict(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    code = main(["frc", "models/duffing.toml", "--amplitude", "0.3", "--omega", "0.5:2",
                 "--max-points", "40", "--json"])
    assert code in (0, 1)
    json.loads(capsys.readouterr().out, parse_constant=_strict)


@pytest.mark.parametrize("argv, words", [
    (["--amplitude", "1e-320"], "amplitude"),
    (["--step", "1e-320"], "step"),
    (["--vary", "amplitude", "--amplitude", "0:1e-320", "--omega", "1"], "amplitude"),
])
def test_frc_refuses_subnormal_numbers(argv: list[str], words: str,
                                       capsys: pytest.CaptureFixture) -> None:
    base = ["frc", "models/duffing.toml", "--amplitude", "0.3", "--omega", "0.5:2"]
    assert main([*base, *argv]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and re.search(words, err)


@pytest.mark.parametrize("argv, words", [
    (["--sample-time", "1e-320"], "SAMPLE_TIME_LIMITS"),
    (["--sample-time", "1e308"], "SAMPLE_TIME_LIMITS"),
    (["--rms", "1e308"], "RMS_LIMITS"),
    (["--rms", "1e-320"], "RMS_LIMITS"),
    (["--seed", "-1"], "seed"),
    (["--levels", "1,1e-320"], "MIN_LEVEL"),
])
def test_multisine_refuses_values_whose_signal_leaves_the_float_range(
        argv: list[str], words: str, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "m.csv"
    code = main(["multisine", "--period", "256", "--sample-time", "0.01", "--out", str(out),
                 *argv])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err
    assert not out.exists()


def test_frc_and_estimate_figures_and_json_keep_a_hostile_name_inert(
        tmp_path: Path, capsys: pytest.CaptureFixture, drawn: list[str]) -> None:  # noqa: F811
    model = str(_model(tmp_path))
    commands = [["frc", model, "--amplitude", "0.3", "--omega", "0.5:2", "--max-points", "40",
                 "--plot", str(tmp_path / "frc.png")],
                ["estimate", "models/multisine_example.csv", "--period", "512",
                 "--skip-periods", "1", "--model", model, "--plot", str(tmp_path / "e.png")]]
    for argv in commands:
        assert main(argv) in (0, 1)
        out, err = capsys.readouterr()
        _check_text(out + err, argv[0])
        assert main([*argv, "--json"]) in (0, 1)
        out, err = capsys.readouterr()
        json.loads(out, parse_constant=_strict)
        assert not RAW.search(out + err)
    assert drawn
    for t in drawn:
        _check_text(t, "figure")


def test_certificate_check_refuses_a_costly_global_certificate_quickly(
        tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A global certificate whose V = |x|^2 + (sum of 120 monomials)^2 is a true SOS
    identity for sigma_V, but makes G^2 tens of millions of products (it ran for minutes):
    it is refused by a count, before the product."""

    model = "D(y,4) + 2*D(y,3) + 3*D(y,2) + 2*D(y) + y + 0.1*y**3 = u"
    V, basis = padded_square()
    cert = {"format": "gfrf-sos-certificate", "version": 1, "kind": "global-continuous",
            "states": ["y", "D(y,1)", "D(y,2)", "D(y,3)"],
            "V": [[list(k), str(c)] for k, c in V.items()], "gamma": "1", "alpha": "1",
            "multipliers": {"sigma": {"basis": [[0] * 5], "Q": [["1"]]},
                            "sigma_V": {"basis": basis, "Q": [["1"] * 120] * 120}}}
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(cert))
    assert main(["certificate", "check", model, str(path), "--json"]) == 1
    payload = json.loads(capsys.readouterr().out)
    assert payload["valid"] is False and "MAX_PRODUCT_WORK" in payload["reason"]


@pytest.mark.parametrize("column, value, words", [
    ("y", "1e308", "MAX_ABS_VALUE"),  # its spectrum overflowed: NaN (null) estimates
    ("t", "subnormal", "SAMPLE_TIME_LIMITS"),  # lines at inf rad/s
])
def test_estimate_refuses_data_whose_spectra_leave_the_float_range(
        column: str, value: str, words: str, tmp_path: Path,
        capsys: pytest.CaptureFixture) -> None:
    lines = Path("models/multisine_example.csv").read_text().splitlines()
    rows = [line.split(",") for line in lines[1:]]
    for i, row in enumerate(rows):
        if column == "y":
            row[2] = value
        else:
            row[0] = repr(i * 1e-320)
    path = tmp_path / "data.csv"
    path.write_text("\n".join([lines[0], *(",".join(r) for r in rows)]) + "\n")
    assert main(["estimate", str(path), "--period", "512", "--skip-periods", "1",
                 "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and words in err


@pytest.mark.parametrize("version", [2, 0, "1", True, None, 1.0])
def test_certificate_check_refuses_an_unknown_version(
        version: object, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    cert: dict[str, object] = {"format": "gfrf-sos-certificate", "kind": "local-continuous",
                               "states": ["y", "D(y,1)"]}
    if version is not None:
        cert["version"] = version
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(cert))
    assert main(["certificate", "check", CUBIC_DAMPING, str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1 and "version" in err
