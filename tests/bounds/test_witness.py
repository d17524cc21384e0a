"""Proven witness points: |H_n| at the lower end's frequency vector in ball arithmetic.

References are mpmath at 50 digits on closed forms written from the model's
coefficients as written (``0.41`` is 41/100, not its double): Duffing-type and hanging
pendulum H3 = -c3 H1(s1) H1(s2) H1(s3) / A(s1+s2+s3), and the NARX example's H3.
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import mpmath as mp
import pytest

from gfrf.bounds.norms import kernel_norm
from gfrf.bounds.witness import kernel_ball, witness_bound
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import Model, parse_model
from gfrf.model.modelfile import load_model

MODELS = Path(__file__).resolve().parents[2] / "models"
BUNDLED = sorted(p for p in MODELS.glob("*.toml") if p.stem != "parametric_pendulum")
POINT = (1.565, 1.5, -0.7)


def _ends(x: object) -> tuple[Fraction, Fraction]:
    """Exact ends of an Arb ball (no rounding)."""
    def exact(v: object) -> Fraction:
        man, exp = v.mid().man_exp()  # type: ignore[attr-defined]
        return Fraction(int(man)) * Fraction(2) ** int(exp)

    mid, rad = exact(x), exact(x.rad())  # type: ignore[attr-defined]
    return mid - rad, mid + rad


def _contains(ball: object, value: mp.mpc) -> bool:
    """Whether the acb ball contains the mpmath complex value (compared exactly)."""
    re_lo, re_hi = _ends(ball.real)  # type: ignore[attr-defined]
    im_lo, im_hi = _ends(ball.imag)  # type: ignore[attr-defined]
    with mp.workdps(80):
        def within(lo: Fraction, v: mp.mpf, hi: Fraction) -> bool:
            return (mp.mpf(lo.numerator) / lo.denominator <= v
                    <= mp.mpf(hi.numerator) / hi.denominator)

        return within(re_lo, mp.re(value), re_hi) and within(im_lo, mp.im(value), im_hi)


def _mp(value: Fraction | float) -> mp.mpf:
    """A Fraction or a float exactly as an mpmath number (at the working precision)."""
    value = Fraction(value)
    return mp.mpf(value.numerator) / value.denominator


def _cubic_h3(model: Model, w: tuple[float, ...], c3: mp.mpf | None = None,
              binary: bool = False) -> mp.mpc:
    """-c3 H1(s1)H1(s2)H1(s3)/A(s1+s2+s3), H1 = -B/A, at 50 digits from the coefficients as
    written (``binary``: from their doubles)."""
    def value(t: object) -> mp.mpf:
        return _mp(t.coefficient if binary else t.exact)  # type: ignore[attr-defined]

    with mp.workdps(50):
        linear = [(value(t), t.y_orders[0]) for t in model.terms if t.is_linear_output]
        gain = next(value(t) for t in model.terms if t.y_orders == ())
        if c3 is None:
            c3 = next(value(t) for t in model.terms if t.y_orders == (0, 0, 0))

        def a(s: mp.mpc) -> mp.mpc:
            return sum(c * s ** k for c, k in linear)

        s = [mp.mpc(0, x) for x in w]
        h1 = [-gain / a(x) for x in s]
        return -c3 * h1[0] * h1[1] * h1[2] / a(s[0] + s[1] + s[2])


@pytest.mark.parametrize("text", ["D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u",
                                  "models/hanging_pendulum.toml"])
def test_h3_ball_contains_mpmath_closed_form(text: str) -> None:
    model = (load_model(MODELS.parent / text).plant if text.endswith(".toml")
             else parse_model(text))
    for w in (POINT, (1.565, 1.565, -1.565), (0.0, 2.0, -3.25)):
        ball = kernel_ball(model, 3, w)
        assert _contains(ball, _cubic_h3(model, w))
        lo, hi = _ends(ball.real)
        assert hi - lo <= abs(hi) * Fraction(1, 10**30)  # 128 bits: a tight ball


def test_ball_is_of_the_written_coefficients_not_their_doubles() -> None:
    """The pendulum's g/6L as written is 49/120, not its double 0.4083333333333333."""
    model = load_model(MODELS / "hanging_pendulum.toml").plant
    ball = kernel_ball(model, 3, POINT)
    assert _contains(ball, _cubic_h3(model, POINT))
    with mp.workdps(50):
        assert _contains(ball, _cubic_h3(model, POINT, c3=-mp.mpf(49) / 120))
        assert not _contains(ball, _cubic_h3(model, POINT, binary=True))


def test_narx_h3_ball_contains_mpmath_closed_form() -> None:
    """y[k] = 0.5 y[k-1] - 0.2 y[k-1]^2 u[k-2] + u[k-1]: H1 = q / (1 - 0.5 q), and
    H3 = -(0.2 / 3) sum_i q_i^2 prod_{j != i} q_j H1(q_j) / (1 - 0.5 q1 q2 q3)."""
    model = load_model(MODELS / "narx_example.toml").plant
    with mp.workdps(50):
        q = [mp.exp(mp.mpc(0, -mp.mpf(x) * mp.mpf(0.1))) for x in POINT]

        def h1(z: mp.mpc) -> mp.mpc:
            return z / (1 - mp.mpf(0.5) * z)

        total = sum(q[i] ** 2 * mp.fprod(q[j] * h1(q[j]) for j in range(3) if j != i)
                    for i in range(3))
        h3 = -mp.mpf(2) / 10 / 3 * total / (1 - mp.mpf(0.5) * q[0] * q[1] * q[2])
    assert _contains(kernel_ball(model, 3, POINT), h3)


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_witness_lower_end_is_proven_on_every_bundled_model(path: Path) -> None:
    """Order 3 (order 2 where H3 vanishes): the lower end is interval, below the upper."""
    model = load_model(path).plant
    n = 3 if not kernel(model, 3).is_zero else 2
    b = kernel_norm(model, n, max_boxes=0)
    assert b.lower_proof == "interval" and b.upper_proof == "interval"
    assert 0 < b.lower <= b.upper
    assert b.to_dict()["lower_proof"] == "interval"
    w = witness_bound(model, n, b.argmax)
    assert w.lower == b.lower and w.relative_width < 1e-14
    # the double-precision value agrees to rounding (it may lie a few ulps outside)
    assert abs(complex(kernel(model, n)(*b.argmax))) == pytest.approx(w.lower, rel=1e-13)


def test_cli_json_says_interval(capsys: pytest.CaptureFixture[str]) -> None:
    from gfrf.cli import main

    assert main(["norm", str(MODELS / "duffing.toml"), "--order", "3", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["proof"] == data["lower_proof"] == data["upper_proof"] == "interval"
    assert main(["norm", str(MODELS / "duffing.toml"), "--order", "3"]) == 0
    assert capsys.readouterr().out.splitlines()[1].endswith("proven")


def test_wide_ball_keeps_the_float_value(monkeypatch: pytest.MonkeyPatch) -> None:
    """A witness ball wider than 1e-10 relative: the float value stays, labelled."""
    import gfrf.bounds.witness

    model = parse_model("D(y,2) + 0.05*D(y) + 2.45*y - 0.41*y**3 = u")
    proven = kernel_norm(model, 3)
    monkeypatch.setattr(gfrf.bounds.witness, "witness_bound",
                        lambda *a: gfrf.bounds.witness.WitnessBound(0.5, 2e4, 1.0, 512))
    b = kernel_norm(model, 3)
    assert (b.lower_proof, b.proof, b.upper_proof) == ("float", "float", "interval")
    assert proven.lower <= b.lower <= proven.upper  # the float value, not the ball's end
    assert any("stays a float value" in note for note in b.notes)
