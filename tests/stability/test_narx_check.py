"""Re-checking a NARX invariant box or paving file: accepted as written, refused when
perturbed (exit 1) or malformed / for another model (exit 2).

Each perturbation is refused for a reason the test establishes on its own: a state that
the recursion reaches from rest with |u| <= U, simulated here from the model's equation
(not from gfrf's state form), lies outside the perturbed set, so no sound check may
accept it.
"""

from __future__ import annotations

import copy
import json
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import MODELS

from gfrf.cli import main
from gfrf.model.modelfile import resolve_model
from gfrf.stability.narx_check import MAX_DIGITS, MAX_PAVING_CELLS
from gfrf.stability.narx_paving import paving_certificate
from gfrf.stability.polysys import state_form

NARX = str(MODELS / "narx_example.toml")
IDENTIFIED = str(MODELS / "identified_example.toml")


def _narx_states(u: np.ndarray) -> np.ndarray:
    """States (y[k-1], u[k-1], u[k-2]) of y[k] = 0.5y[k-1] - 0.2y[k-1]^2 u[k-2] + u[k-1],
    from rest (two samples of zero input and output before u)."""
    u = np.r_[0.0, 0.0, u]
    y = np.zeros(len(u))
    for k in range(2, len(u)):
        y[k] = 0.5 * y[k - 1] - 0.2 * y[k - 1] ** 2 * u[k - 2] + u[k - 1]
    return np.array([[y[k - 1], u[k - 1], u[k - 2]] for k in range(2, len(u))])


def _identified_states(u: np.ndarray) -> np.ndarray:
    """States (y[k-1], y[k-2], u[k-1], u[k-2]) of the identified example's equation,
    from rest."""
    u = np.r_[0.0, 0.0, u]
    y = np.zeros(len(u))
    for k in range(2, len(u)):
        y1, y2, u1, u2 = y[k - 1], y[k - 2], u[k - 1], u[k - 2]
        y[k] = (0.5951575491 * y1 - 0.1979410468 * y2 + 0.4991094922 * u1
                + 0.3025633491 * u2 + 0.1508917809 * y1 * u1 - 0.100037633 * u1**2
                - 0.04852880773 * y1**3)
        if abs(y[k]) > 1e6:
            return np.array([[y[j - 1], y[j - 2], u[j - 1], u[j - 2]] for j in range(2, k + 1)])
    return np.array([[y[k - 1], y[k - 2], u[k - 1], u[k - 2]] for k in range(2, len(u))])


def _inputs(U: float, seed: int) -> list[np.ndarray]:
    """Bang-bang, random-level, constant and square-wave inputs with sup|u| <= U."""
    rng = np.random.default_rng(seed)
    out = [U * rng.choice([-1.0, 1.0], size=300) for _ in range(20)]
    out += [U * rng.uniform(-1, 1, size=300) for _ in range(10)]
    out += [np.full(300, U), np.full(300, -U)]
    out += [U * np.sign(np.sin(np.arange(300) * np.pi / p + 0.1)) for p in (1, 2, 3, 5)]
    return out


def _coords(cert: dict[str, Any], states: np.ndarray) -> np.ndarray:
    """s = T(x) at float states, T read from the file."""
    out = np.zeros((len(states), len(cert["T"])))
    for i, table in enumerate(cert["T"]):
        for key, c in table.items():
            e = [int(x) for x in key.split(",")][:-1]  # T does not depend on v
            out[:, i] += float(Fraction(c)) * np.prod(states ** np.array(e), axis=1)
    return out


def _check(capsys: pytest.CaptureFixture, model: str, cert: dict[str, Any], folder: Path,
           *extra: str) -> tuple[int, str, str]:
    path = folder / "cert.json"
    path.write_text(json.dumps(cert), encoding="utf-8")
    code = main(["certificate", "check", model, str(path), *extra])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def box_file(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """What ``gfrf threshold narx_example.toml --certificate-out FILE`` writes."""
    path = tmp_path_factory.mktemp("box") / "c.json"
    assert main(["threshold", NARX, "--certificate-out", str(path), "--json"]) == 0
    return json.loads(path.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def paving_file() -> dict[str, Any]:
    """The identified example's headline certificate: its invariant paving (the threshold
    search proper, with the falsifier, runs in the slow test below)."""
    found = paving_certificate(state_form(resolve_model(IDENTIFIED)), 1.69)
    assert found is not None
    return found.certificate


def test_the_written_box_holds_and_contains_simulated_responses(box_file, tmp_path,
                                                                capsys) -> None:
    assert box_file["format"] == "gfrf-narx-box" and box_file["kind"] == "narx-box"
    code, out, _ = _check(capsys, NARX, box_file, tmp_path, "--json")
    payload = json.loads(out)
    U = Fraction(box_file["U"])
    assert code == 0 and payload["valid"] and payload["proof"] == "interval"
    assert payload["radius"] <= U and payload["radius"] > 1.6
    # the escape of this model is proven at 1.7109: a holding certificate stays below it
    assert U < Fraction(17109, 10000)
    # the sampling check agrees with the exact one: every simulated state is in the box
    lo = np.array([float(Fraction(x)) for x in box_file["lo"]])
    hi = np.array([float(Fraction(x)) for x in box_file["hi"]])
    for u in _inputs(float(U), 1):
        s = _coords(box_file, _narx_states(u))
        assert np.all(s >= lo - 1e-12) and np.all(s <= hi + 1e-12)
    # the JSON has the keys of a sum-of-squares check
    model = "D(y,2) + 0.4*D(y) + 2*y + 0.5*y**2*D(y) + 0.8*y**3 = u"
    sos = tmp_path / "sos.json"
    assert main(["threshold", model, "--certificate-out", str(sos)]) == 0
    assert main(["certificate", "check", model, str(sos)]) == 0
    capsys.readouterr()
    assert main(["certificate", "check", model, str(sos), "--json"]) == 0
    assert set(payload) == set(json.loads(capsys.readouterr().out))
    # and each file is bad input for the other model
    assert main(["certificate", "check", model, str(tmp_path / "cert.json")]) == 2
    assert main(["certificate", "check", NARX, str(sos)]) == 2


def test_a_bigger_u_or_a_shrunk_box_is_refused(box_file, tmp_path, capsys) -> None:
    U = float(Fraction(box_file["U"]))
    # bigger U: u[k-1] = 1.25 U is reached, outside the box's [-U, U] for that lag
    big = copy.deepcopy(box_file)
    big["U"] = str(Fraction(box_file["U"]) * Fraction(5, 4))
    assert _coords(big, _narx_states(np.full(10, 1.25 * U)))[:, 1].max() > float(
        Fraction(big["hi"][1]))
    code, out, _ = _check(capsys, NARX, big, tmp_path)
    assert code == 1 and out.startswith("refused: the image of the box leaves it")
    # shrunk box: s_0 below what an input with |u| <= U reaches from rest
    reached = max(_coords(box_file, _narx_states(u))[:, 0].max() for u in _inputs(U, 2))
    small = copy.deepcopy(box_file)
    small["hi"][0] = str(Fraction(0.9 * reached))
    assert 0 < float(Fraction(small["hi"][0])) < reached
    code, out, _ = _check(capsys, NARX, small, tmp_path, "--json")
    assert code == 1 and json.loads(out)["valid"] is False


def test_a_file_for_another_model_is_bad_input(box_file, tmp_path, capsys) -> None:
    # same states, one coefficient changed: the recorded recursion differs
    code, out, err = _check(capsys, "y[k] = 0.4*y[k-1] - 0.2*y[k-1]**2*u[k-2] + u[k-1]",
                            box_file, tmp_path, "--sample-time", "0.1")
    assert code == 2 and out == "" and "another model" in err and len(err.splitlines()) == 1
    # other states
    code, _, err = _check(capsys, IDENTIFIED, box_file, tmp_path)
    assert code == 2 and "another model" in err
    # a continuous-time model
    code, _, err = _check(capsys, "D(y,2) + 0.2*D(y) + y + y**3 = u", box_file, tmp_path)
    assert code == 2 and "another model" in err


@pytest.mark.parametrize("edit, words", [
    (lambda c: c.update(U=1.5), "rational"),
    (lambda c: c.update(U="1" * (MAX_DIGITS + 1) + "/3"), "MAX_DIGITS"),
    (lambda c: c.update(splits=[128, 1, 128, 1]), "MAX_CELLS"),
    (lambda c: c.update(splits=[True, 1, 1, 1]), "splits"),
    (lambda c: c["T"][0].update({"9,0,0,0": "1"}), "degree"),
    (lambda c: c["T"][0].update({"1,0,0": "1"}), "exponent key"),
    (lambda c: c.pop("lo"), "lo"),
    (lambda c: c.update(kind="narx-paving"), "kind"),
])
def test_a_malformed_box_file_is_refused_before_the_work(box_file, edit, words, tmp_path,
                                                         capsys) -> None:
    bad = copy.deepcopy(box_file)
    edit(bad)
    code, out, err = _check(capsys, NARX, bad, tmp_path)
    assert code == 2 and out == "" and words in err and len(err.splitlines()) == 1


def test_the_identified_paving_holds_and_contains_simulated_responses(paving_file, tmp_path,
                                                                      capsys) -> None:
    assert paving_file["format"] == "gfrf-narx-paving"
    code, out, _ = _check(capsys, IDENTIFIED, paving_file, tmp_path, "--json")
    payload = json.loads(out)
    assert code == 0 and payload["kind"] == "narx-paving" and payload["radius"] > 2.5
    cells = {tuple(c) for c in paving_file["cells"]}
    R = np.array([float(Fraction(r)) for r in paving_file["R"]])
    h = 2 * R / paving_file["N"]
    U = float(Fraction(paving_file["U"]))
    visited: dict[tuple[int, ...], int] = {}
    for u in _inputs(U, 3):
        s = _coords(paving_file, _identified_states(u))[:, :2]
        for idx in map(tuple, np.floor((s + R) / h).astype(int).tolist()):
            assert idx in cells
            visited[idx] = visited.get(idx, 0) + 1
    # a visited cell other than the rest cell removed: refused
    rest = tuple(np.floor(R / h).astype(int).tolist())
    gone = next(c for c in sorted(visited) if c != rest)
    bad = copy.deepcopy(paving_file)
    bad["cells"].remove(list(gone))
    code, out, _ = _check(capsys, IDENTIFIED, bad, tmp_path)
    assert code == 1 and "leaves the paving" in out
    # a bigger U: an input with sup|u| <= 1.6 U reaches a state outside the paving
    big = copy.deepcopy(paving_file)
    big["U"] = str(Fraction(paving_file["U"]) * Fraction(8, 5))
    outside = False
    for u in _inputs(1.6 * U, 4):
        s = _coords(paving_file, _identified_states(u))[:, :2]
        idx = np.floor((s + R) / h)
        outside |= any(tuple(i) not in cells for i in idx.astype(np.int64).tolist())
    assert outside
    code, _, _ = _check(capsys, IDENTIFIED, big, tmp_path)
    assert code == 1
    # too many cells for a paving: bad input before the work
    many = copy.deepcopy(paving_file)
    many["cells"] = many["cells"] * (MAX_PAVING_CELLS // len(many["cells"]) + 1)
    code, _, err = _check(capsys, IDENTIFIED, many, tmp_path)
    assert code == 2 and "MAX_PAVING_CELLS" in err
    # a half-width of zero or below: malformed, not a paving that fails to hold
    for R_bad in (["0", "0"], ["-1", "1"]):
        flat = copy.deepcopy(paving_file)
        flat["R"] = R_bad
        code, out, err = _check(capsys, IDENTIFIED, flat, tmp_path)
        assert code == 2 and out == "" and "R must be positive" in err


@pytest.mark.slow
def test_threshold_writes_the_identified_paving_and_it_holds(tmp_path, capsys) -> None:
    path = tmp_path / "c.json"
    assert main(["threshold", IDENTIFIED, "--certificate-out", str(path), "--json"]) == 0
    lower = json.loads(capsys.readouterr().out)["lower"]
    assert json.loads(path.read_text(encoding="utf-8"))["format"] == "gfrf-narx-paving"
    assert main(["certificate", "check", IDENTIFIED, str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["radius"] == lower


def test_a_linear_recursion_box_holds_for_every_amplitude(tmp_path, capsys) -> None:
    """y[k] = 0.5y[k-1] - 0.3y[k-2] + u[k-1] has poles of modulus sqrt(0.3) < 1: bounded
    for every bounded input (the box scales with U), and the file's check says inf."""
    model = "y[k] = 0.5*y[k-1] - 0.3*y[k-2] + u[k-1]"
    path = tmp_path / "c.json"
    assert main(["threshold", model, "--sample-time", "0.1", "--certificate-out", str(path),
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["lower"] == "inf"
    assert main(["certificate", "check", model, "--sample-time", "0.1", str(path),
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["radius"] == "inf"


def test_no_file_is_written_when_lower_has_no_certificate_file(tmp_path, capsys) -> None:
    """A damped hardening oscillator's lower is the energy function's: nothing to write."""
    path = tmp_path / "c.json"
    assert main(["threshold", "D(y,2) + 0.2*D(y) + y + 0.5*y**3 = u", "--certificate-out",
                 str(path)]) == 0
    assert not path.exists() and "no certificate file" in capsys.readouterr().err
