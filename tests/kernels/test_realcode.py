"""The recursion step written on real and imaginary parts equals the symbolic numerator."""

from __future__ import annotations

import cmath
import itertools

import numpy as np
import pytest
import sympy as sp

from gfrf.kernels.probing import probe_kernel
from gfrf.kernels.realcode import grouped_numerator, real_step_lines
from gfrf.kernels.recursion import generator, kernel
from gfrf.model.equation import parse_model

MODELS = [
    # every term type of the cart-pole: cubic, y*y'^2, y^2*y'', y^2*u
    "D(y,2) + 0.2*D(y) + y + 11.2*y**3 + 0.15*y**2*D(y,2) + 0.15*y*D(y)**2 - 19.7*y**2*u = u",
    "D(y,2) + 0.3*D(y) + y + 0.4*D(y)**2*D(u) - 0.7*y*u**2 = u",  # an even order, inputs' D
    "y[k] = 0.6*y[k-1] - 0.2*y[k-2] + 0.5*u[k-1] + 0.15*y[k-1]*u[k-1] - 0.1*u[k-1]**2 "
    "- 0.05*y[k-1]**3",
]


def _model(text: str) -> object:
    return parse_model(text, sample_time=0.1 if "[k]" in text else None)


def _run(gen: object, m: int, symmetric: bool, values: dict[str, complex]) -> complex:
    """The generated lines run as plain Python on the given argument values."""
    arguments, lines, numerator = real_step_lines(gen, m, symmetric)
    namespace = {name: values[name] for name in arguments}
    exec("\n".join([*lines, f"_result = {numerator}"]), namespace)
    return complex(namespace["_result"])


@pytest.mark.parametrize("text", MODELS)
@pytest.mark.parametrize("symmetric", [True, False])
def test_the_real_code_is_the_numerator(text: str, symmetric: bool) -> None:
    gen = generator(_model(text))
    rng = np.random.default_rng(5)
    for m in range(1, 6):
        plan = gen.plan(m, symmetric)
        if plan.is_zero:
            continue
        w = rng.uniform(-3.0, 3.0, m)
        h = rng.standard_normal(len(plan.placeholders)) \
            + 1j * rng.standard_normal(len(plan.placeholders))
        variables = gen.variables(m)
        if gen.model.is_discrete:  # the q_i themselves
            x = [cmath.exp(-0.1j * wi) for wi in w]
            values = {str(v): xi for v, xi in zip(variables, x, strict=True)}
        else:  # the real w_i; the numerator is in s_i = j*w_i
            x = [1j * wi for wi in w]
            values = {str(v): float(wi) for v, wi in zip(variables, w, strict=True)}
        values |= {str(p): complex(hi) for p, hi in zip(plan.placeholders, h, strict=True)}
        exact = complex(plan.numerator.xreplace(
            {**dict(zip(variables, x, strict=True)),
             **dict(zip(plan.placeholders, (sp.sympify(complex(c)) for c in h),
                        strict=True))}).evalf(30))
        got = _run(gen, m, symmetric, values)
        assert abs(got - exact) <= 1e-13 * max(abs(exact), 1.0), (m, got, exact)


@pytest.mark.parametrize("text", MODELS)
def test_the_compiled_kernel_agrees_with_harmonic_probing(text: str) -> None:
    pytest.importorskip("numba")
    model = _model(text)
    rng = np.random.default_rng(6)
    for n in (2, 3):
        k = kernel(model, n)
        if k.is_zero:
            continue
        f = k.compiled()
        for w in itertools.islice(rng.uniform(-4.0, 4.0, (50, n)), 8):
            reference = probe_kernel(model, list(w))
            value = complex(f(*w))
            assert abs(value - reference) <= 1e-12 * abs(reference), (n, w)


@pytest.mark.parametrize("text", MODELS)
def test_grouped_numerator_is_the_same_polynomial(text: str) -> None:
    gen = generator(_model(text))
    for m in range(2, 6):
        plan = gen.plan(m, True)
        grouped = grouped_numerator(plan.numerator, plan.placeholders)
        assert sp.expand(grouped - plan.numerator) == 0, m
        # one term per distinct product of lower-order kernels
        products = {sp.Mul(*(f for f in sp.Mul.make_args(t) if f in plan.placeholders
                             or f.free_symbols & set(plan.placeholders)))
                    for t in sp.Add.make_args(plan.numerator)} - {sp.Integer(0)}
        assert len(sp.Add.make_args(grouped)) == len(products) or plan.is_zero, m
