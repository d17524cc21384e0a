"""Property tests: random polynomial models, recursion versus harmonic probing.

Models have a stable second-order linear part, a linear input part b0 u + b1 D(u),
and one to four random nonlinear terms of every kind (pure output, cross, pure
input) of degree 2 or 3 with derivative orders up to 2.  Their symmetric kernels
from the recursion (:func:`gfrf.kernels.recursion.kernel`) must agree with harmonic probing
(:func:`gfrf.kernels.probing.probe_kernel`, an independent algorithm) to 1e-10 relative, and
be invariant under permutation of their arguments.
"""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.recursion import kernel
from gfrf.model.equation import parse_model

SETTINGS = settings(max_examples=60, deadline=None)


def _factor(signal: str, order: int) -> str:
    return signal if order == 0 else f"D({signal},{order})"


@st.composite
def models(draw: st.DrawFn) -> object:
    """A random polynomial model text with a stable linear part, parsed."""
    # A(s) = s^2 + a1 s + a0 with a1, a0 > 0 is Hurwitz.
    a1 = draw(st.floats(0.1, 3.0))
    a0 = draw(st.floats(0.2, 4.0))
    b0 = draw(st.floats(0.5, 2.0))
    b1 = draw(st.sampled_from([0.0, 0.3]))
    terms = []
    for _ in range(draw(st.integers(1, 4))):
        degree = draw(st.integers(2, 3))
        n_y = draw(st.integers(0, degree))
        factors = [_factor("y", draw(st.integers(0, 2))) for _ in range(n_y)]
        factors += [_factor("u", draw(st.integers(0, 2))) for _ in range(degree - n_y)]
        coefficient = draw(st.floats(-1.0, 1.0).filter(lambda c: abs(c) > 0.05))
        terms.append(f"{coefficient!r}*" + "*".join(factors))
    text = (f"D(y,2) + {a1!r}*D(y) + {a0!r}*y + " + " + ".join(terms)
            + f" = {b0!r}*u + {b1!r}*D(u)")
    return parse_model(text)


def _frequencies(seed: int, n: int) -> list[float]:
    """Generic (incommensurate) angular frequencies in rad/s, as probing requires."""
    return list(np.random.default_rng(seed).uniform(-3.0, 3.0, n))


def _close(a: complex, b: complex, rel: float) -> bool:
    scale = max(abs(a), abs(b))
    return abs(a - b) <= rel * scale or scale < 1e-300


@SETTINGS
@given(models(), st.integers(1, 4), st.integers(0, 2**32 - 1))
def test_recursion_agrees_with_harmonic_probing(model: object, n: int, seed: int) -> None:
    w = _frequencies(seed, n)
    value = complex(kernel(model, n)(*w))
    assert _close(value, probe_kernel(model, w), 1e-10), (model.equation(), w)


@SETTINGS
@given(models(), st.integers(2, 4), st.integers(0, 2**32 - 1))
def test_symmetric_kernel_is_permutation_invariant(model: object, n: int, seed: int) -> None:
    w = _frequencies(seed, n)
    k = kernel(model, n)
    reference = complex(k(*w))
    for perm in itertools.permutations(w):
        assert _close(complex(k(*perm)), reference, 1e-12)


@SETTINGS
@given(models(), st.integers(0, 2**32 - 1))
def test_asymmetric_kernel_symmetrises_to_the_symmetric_one(model: object, seed: int) -> None:
    w = _frequencies(seed, 3)
    asym = kernel(model, 3, symmetric=False)
    mean = sum(complex(asym(*p)) for p in itertools.permutations(w)) / 6
    assert _close(mean, complex(kernel(model, 3)(*w)), 1e-10)
