"""Tests of gfrf.model.signals: parsing, derivatives, tones, CSV, bad input."""

import math

import numpy as np
import pytest

from gfrf.errors import ArgumentError
from gfrf.model.signals import parse_input, tones_input


def test_sum_of_tones_value_and_tones():
    u = parse_input("0.1*sin(1.2*t) - 0.3*cos(2*t + 1)")
    t = 0.7
    assert float(u(t)) == pytest.approx(0.1 * math.sin(0.84) - 0.3 * math.cos(2.4))
    (a1, w1, p1), (a2, w2, p2) = u.tones
    # rebuild the signal from the extracted tones: independent of the parser's algebra
    rebuilt = a1 * math.cos(w1 * t + p1) + a2 * math.cos(w2 * t + p2)
    assert rebuilt == pytest.approx(float(u(t)))
    assert {w1, w2} == {1.2, 2.0} and min(a1, a2) == pytest.approx(0.1)


def test_symbolic_derivative():
    u = parse_input("exp(-t)*sin(3*t)", max_derivative=2)
    t = np.array([0.0, 0.4])
    d1 = np.exp(-t) * (3 * np.cos(3 * t) - np.sin(3 * t))
    assert np.allclose(u.derivative(1)(t), d1)
    with pytest.raises(ArgumentError):
        u.derivative(3)


def test_step_is_one_at_jump_and_not_tones():
    u = parse_input("0.5*step(t - 1)")
    assert np.allclose(u([0.0, 1.0, 2.0]), [0.0, 0.5, 0.5])
    assert u.tones is None


def test_tones_input_roundtrip():
    u = tones_input([(0.2, 1.5, 0.3)])
    assert float(u(1.1)) == pytest.approx(0.2 * math.cos(1.5 * 1.1 + 0.3))


def test_csv_input(tmp_path):
    path = tmp_path / "u.csv"
    t = np.linspace(0, 2, 41)
    np.savetxt(path, np.c_[t, 3 * t], delimiter=",", header="t,u", comments="")
    u = parse_input(str(path), max_derivative=1)
    assert float(u(1.234)) == pytest.approx(3 * 1.234)
    assert float(u.derivative(1)(0.5)) == pytest.approx(3.0)
    assert float(u(5.0)) == pytest.approx(6.0)  # held after the recording


@pytest.mark.parametrize("text, word", [("0.5", "not a function of t"), ("x*t", "x"),
                                        ("foo(t)", "foo"), ("sin(", "cannot parse"),
                                        ("", "empty"), ("csv:/nonexistent.csv", "does not exist")])
def test_bad_input(text, word):
    with pytest.raises(ArgumentError, match=word):
        parse_input(text)


@pytest.mark.parametrize("text", ["0,1\n1,2\n2,3\n", "t,u\n0,1\n1,2\n2,3\n",
                                  "# recorded\nt,u\n0,1\n\n1,2\n2,3\n"])
def test_csv_input_with_or_without_header(tmp_path, text):
    path = tmp_path / "u.csv"
    path.write_text(text)
    u = parse_input(f"csv:{path}")
    assert [float(u(t)) for t in (0.0, 1.0, 2.0)] == [1.0, 2.0, 3.0]


@pytest.mark.parametrize("text", ["0,x\n1,2\n2,3\n", "t,u\n0,1\n1,\n2,3\n",
                                  "t,u\n0,1\n1,2,5\n2,3\n", "t,u\n0,1\n1,inf\n2,3\n"])
def test_csv_input_refuses_bad_rows(tmp_path, text):
    path = tmp_path / "u.csv"
    path.write_text(text)
    with pytest.raises(ArgumentError, match="input CSV"):
        parse_input(f"csv:{path}")


def test_csv_input_size_limit(tmp_path, monkeypatch):
    import gfrf.model.signals as signals

    path = tmp_path / "u.csv"
    path.write_text("t,u\n" + "".join(f"{k},{k}\n" for k in range(10)))
    monkeypatch.setattr(signals, "MAX_CSV_BYTES", 20)
    with pytest.raises(ArgumentError, match="above the limit 20"):
        parse_input(f"csv:{path}")
    monkeypatch.setattr(signals, "MAX_CSV_BYTES", 10**6)
    monkeypatch.setattr(signals, "MAX_CSV_ROWS", 5)
    with pytest.raises(ArgumentError, match="more than 5 rows"):
        parse_input(f"csv:{path}")


def test_breakpoints_repeated_calls_are_independent():
    u = parse_input("step(t - 1) - step(2*t - 10)")
    first = u.breakpoints(10.0)
    first[0] = -1.0  # the caller's copy
    assert u.breakpoints(10.0).tolist() == [1.0, 5.0]
    assert u.breakpoints(3.0).tolist() == [1.0]
    assert u.breakpoints(10.0).tolist() == [1.0, 5.0]


def test_time_scale_and_unresolved_parts_are_computed_once_per_end_time(monkeypatch):
    """The simulator asks both for every run of a prepared signal: the sympy walk is
    done once for a given t_end (and again for another one)."""
    from gfrf.model.signals import InputSignal, parse_input

    calls: list[str] = []
    for method in ("_time_scale", "_unresolved_parts"):
        original = getattr(InputSignal, method)

        def counted(self, t_end, _original=original, _name=method):
            calls.append(_name)
            return _original(self, t_end)

        monkeypatch.setattr(InputSignal, method, counted)
    signal = parse_input("0.5*(1 + tanh((t - 1)/0.01)) + 0.02*atan(1/(t - 1))")
    for _ in range(3):
        assert signal.time_scale(5.0) == pytest.approx(0.01)
        parts = signal.unresolved_parts(5.0)
        assert parts == ["1/(t - 1)", "atan(1/(t - 1))"]
        parts.append("changed by the caller")
    assert sorted(calls) == ["_time_scale", "_unresolved_parts"]
    signal.time_scale(6.0)
    assert calls.count("_time_scale") == 2
