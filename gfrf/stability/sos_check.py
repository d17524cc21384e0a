"""Exact re-verification of a sum-of-squares certificate (rational arithmetic only).

A certificate (:mod:`gfrf.stability.sos`) is a polynomial identity

    target(x, v) == sum_blocks  multiplier * constraint  +  z(x, v)^T Q z(x, v)

whose every number is an exact rational, with Gram matrices Q that must be positive
semidefinite.  :func:`check_certificate` rebuilds the target from the model's own state
form (:func:`gfrf.stability.polysys.state_form`), recomputes every product in
:class:`fractions.Fraction` arithmetic, compares the identity coefficient by coefficient
and decides each Gram matrix PSD by the signs of its exact characteristic polynomial:
no floating-point
number takes part, so a solver's tolerance cannot make it pass.

Kinds (``kind`` in the file):

``local-continuous``
    V quadratic, positive definite, or (with ``gamma`` and the multiplier ``sigma_V``)
    V of any degree with V - gamma|x|^2 = sigma_V SOS, gamma > 0 and V(0) < c, so
    {V <= c} is compact and holds the origin; on {V = c}, for |v| <= U:
    -dV/dt >= eps |x|^2 > 0, from  -dV/dt - eps|x|^2 + lambda (V - c) - mu (U^2 - v^2)
    = sigma  (mu, sigma SOS, lambda any polynomial).  So {V <= c} is invariant: every
    solution from rest stays in it.
``local-discrete``
    V quadratic, positive definite; c - V(f(x, v)) - lambda (c - V) - mu (U^2 - v^2)
    - sum_j nu_j (U^2 - x_j^2) = sigma (lambda, mu, nu_j, sigma SOS; x_j the past inputs).
``global-continuous``
    V - g |x|^2 = sigma_V (g > 0: V radially unbounded) and, with dV/dt = W(x) + v G(x),
    -W - a G^2 - a|x|^2 + C = sigma (a > 0): dV/dt <= -a|x|^2 + C + U^2 / (4a) for every
    |v| <= U, so every solution under every bounded input is bounded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

from gfrf._results import Result
from gfrf.stability._rational import read_rational
from gfrf.stability.polysys import (
    Poly,
    PolySystem,
    padd,
    pcompose,
    pdiff,
    pmul,
    pscale,
)

__all__ = ["CheckResult", "CertificateCheck", "check_certificate", "check_dict", "gram_poly",
           "is_psd", "vdot", "FORMAT"]

#: The ``format`` value of a certificate file.
FORMAT = "gfrf-sos-certificate"
KINDS = ("local-continuous", "local-discrete", "global-continuous")
#: The ``version`` of every certificate format gfrf writes; a check refuses any other.
CERTIFICATE_VERSION = 1
#: Largest Gram matrix size a check accepts.
MAX_GRAM = 120
#: Longest text of one rational (or JSON integer) in a certificate.
MAX_RATIONAL_CHARS = 4000
#: Most products of terms in one polynomial product of the global check (a certificate
#: written by gfrf needs a few thousand: V of degree 4, G linear).
MAX_PRODUCT_WORK = 1_000_000
#: Largest n^3 * b of one exact PSD test (n the Gram size, b the bits of the entries of the
#: matrix scaled to integers by their common denominator): the characteristic polynomial's
#: cost grows with it (measured: at most about 4 s CPU; gfrf's own certificates need
#: below 1e7).
MAX_PSD_WORK = 400_000_000
#: Largest b of one exact PSD test (gfrf's own certificates need below 200 bits).
MAX_PSD_BITS = 10_000


class CheckResult(str):
    """Empty string when the certificate holds, else the reason it is refused."""


def q(text: Any) -> Fraction:
    """A rational from its text ``"p/q"`` (or an int), at most :data:`MAX_RATIONAL_CHARS`
    characters (:func:`gfrf.stability._rational.read_rational`)."""
    return read_rational(text, MAX_RATIONAL_CHARS)


def qtext(x: Fraction) -> str:
    """The text of a rational (``"p/q"`` or ``"p"``)."""
    return str(x)


def poly_from(items: Any, nvars: int) -> Poly:
    """A polynomial from ``[[exponents], "p/q"]`` pairs."""
    out: Poly = {}
    if not isinstance(items, list):
        raise ValueError("a polynomial must be a list of [exponents, 'p/q'] pairs")
    for item in items:
        if not (isinstance(item, list) and len(item) == 2 and isinstance(item[0], list)
                and len(item[0]) == nvars and all(isinstance(e, int) and not isinstance(e, bool)
                                                  and 0 <= e <= 12 for e in item[0])):
            raise ValueError(f"bad polynomial term {str(item)[:60]}")
        key = tuple(item[0])
        out[key] = out.get(key, Fraction(0)) + q(item[1])
    return {k: c for k, c in out.items() if c}


def poly_to(p: Poly) -> list[list[Any]]:
    """``[[exponents], "p/q"]`` pairs, sorted."""
    return [[list(k), qtext(c)] for k, c in sorted(p.items())]


def gram_from(block: Any, nvars: int) -> tuple[list[tuple[int, ...]], list[list[Fraction]]]:
    """(basis, Q) of a Gram block ``{"basis": [...], "Q": [[...]]}``."""
    if not isinstance(block, dict):
        raise ValueError("a Gram block must be a table with 'basis' and 'Q'")
    basis = block.get("basis")
    Q = block.get("Q")
    if not (isinstance(basis, list) and isinstance(Q, list) and len(Q) == len(basis)
            and len(basis) <= MAX_GRAM):
        raise ValueError(f"a Gram block needs a basis and a square Q of its size (at most "
                         f"{MAX_GRAM})")
    b = [tuple(e) for e in basis]
    if any(len(e) != nvars or not all(isinstance(x, int) and not isinstance(x, bool)
                                      and 0 <= x <= 6 for x in e) for e in b):
        raise ValueError("a Gram basis monomial has the wrong length or exponents")
    rows = []
    for row in Q:
        if not (isinstance(row, list) and len(row) == len(b)):
            raise ValueError("Q is not square")
        rows.append([q(x) for x in row])
    return b, rows


def gram_to(basis: list[tuple[int, ...]], Q: list[list[Fraction]]) -> dict[str, Any]:
    """The JSON form of a Gram block."""
    return {"basis": [list(e) for e in basis], "Q": [[qtext(x) for x in row] for row in Q]}


def gram_poly(basis: list[tuple[int, ...]], Q: list[list[Fraction]]) -> Poly:
    """z^T Q z.

    Parameters
    ----------
    basis : list of tuple of int
        The monomial vector z, as exponent tuples.
    Q : list of list of Fraction
        The Gram matrix, square of side ``len(basis)``.

    Returns
    -------
    Poly
        The exact polynomial ``z^T Q z``.
    """
    out: Poly = {}
    for i, a in enumerate(basis):
        for j, b in enumerate(basis):
            if Q[i][j]:
                k = tuple(x + y for x, y in zip(a, b, strict=True))
                out[k] = out.get(k, Fraction(0)) + Q[i][j]
    return {k: c for k, c in out.items() if c}


def is_psd(Q: list[list[Fraction]]) -> bool:
    """Exact test: Q symmetric positive semidefinite.

    The characteristic polynomial det(t I - D Q) of the integer matrix D Q (D > 0 the
    common denominator) has only real roots (Q is symmetric); they are all >= 0 exactly
    when its coefficients alternate in sign, zeros allowed (Descartes).  python-flint
    computes it exactly in C, so the cost is polynomial in the size and digits of Q, with
    no growth of intermediate fractions.

    Parameters
    ----------
    Q : list of list of Fraction
        A square matrix of exact rationals.

    Returns
    -------
    bool
        True if ``Q`` is symmetric positive semidefinite (exact test).
    """
    from flint import fmpq, fmpq_mat

    n = len(Q)
    if any(Q[i][j] != Q[j][i] for i in range(n) for j in range(i)):
        return False
    if n == 0:
        return True
    _check_psd_work(Q)
    scaled, _ = fmpq_mat(n, n, [fmpq(x.numerator, x.denominator) for row in Q
                                for x in row]).numer_denom()
    coeffs = scaled.charpoly().coeffs()
    return all((-1) ** (n - k) * c >= 0 for k, c in enumerate(coeffs))


def _short(x: Fraction) -> str:
    """The text of a rational, cut to its first digits when long (one readable line)."""
    text = str(x)
    return text if len(text) <= 60 else f"{text[:30]}... ({len(text)} characters)"


def _check_psd_work(Q: list[list[Fraction]]) -> None:
    """Raise ValueError when the exact PSD test of Q would exceed :data:`MAX_PSD_WORK`
    (the common denominator is built incrementally and abandoned once too long)."""
    n = len(Q)
    limit = min(MAX_PSD_BITS, MAX_PSD_WORK // n**3)
    top = max(max(abs(x.numerator).bit_length() - x.denominator.bit_length() + 1, 0)
              for row in Q for x in row)
    den = 1
    for row in Q:
        for x in row:
            den = math.lcm(den, x.denominator)
            if den.bit_length() + top > limit:
                raise ValueError(f"a {n} x {n} Gram matrix whose entries need more than "
                                 f"{limit} bits over a common denominator: its exact PSD "
                                 f"test is above MAX_PSD_BITS = {MAX_PSD_BITS} or "
                                 f"MAX_PSD_WORK = {MAX_PSD_WORK} (n^3 * bits)")


def vdot(V: Poly, system: PolySystem) -> Poly:
    """dV/dt = grad V . f(x, v) (continuous).

    Parameters
    ----------
    V : Poly
        The Lyapunov candidate, in the variables (x_1, .., x_n, v).
    system : PolySystem
        A continuous-time system x' = f(x, v).

    Returns
    -------
    Poly
        The exact polynomial ``grad V . f(x, v)``.
    """
    return padd(*(pmul(pdiff(V, i), system.f[i]) for i in range(system.n)))


def _var(i: int, nv: int) -> Poly:
    return {tuple(int(j == i) for j in range(nv)): Fraction(1)}


def _norm2(n: int, nv: int) -> Poly:
    return {tuple(2 * int(j == i) for j in range(nv)): Fraction(1) for i in range(n)}


def _quadratic_pd(V: Poly, n: int, nv: int) -> bool:
    """V = x^T P x with P positive definite (exact) and no v."""
    if any(sum(k) != 2 or k[-1] for k in V):
        return False
    P = [[Fraction(0)] * n for _ in range(n)]
    for k, c in V.items():
        idx = [i for i in range(n) for _ in range(k[i])]
        if idx[0] == idx[1]:
            P[idx[0]][idx[0]] = c
        else:
            P[idx[0]][idx[1]] = P[idx[1]][idx[0]] = c / 2
    # positive definite: PSD with every pivot nonzero, i.e. P - 0 PSD and det != 0
    from flint import fmpq, fmpq_mat

    det = fmpq_mat(n, n, [fmpq(x.numerator, x.denominator) for row in P for x in row]).det()
    return det != 0 and is_psd(P)


def _radially_unbounded(cert: dict[str, Any], V: Poly, n: int, nv: int) -> str:
    """Empty when V has no input term and V - gamma |x|^2 == sigma_V (PSD), gamma > 0."""
    if any(k[-1] for k in V):
        return "V depends on the input"
    g = q(cert["gamma"])
    if not g > 0:
        return "gamma must be positive"
    vb, vQ = gram_from(cert["multipliers"]["sigma_V"], nv)
    if not is_psd(vQ):
        return "the Gram matrix of sigma_V is not positive semidefinite (exact charpoly)"
    if padd(V, pscale(_norm2(n, nv), -g), pscale(gram_poly(vb, vQ), Fraction(-1))):
        return "V - gamma |x|^2 differs from its SOS sigma_V"
    return ""


def check_dict(system: PolySystem, cert: dict[str, Any]) -> CheckResult:
    """Re-verify a certificate's identity and Gram matrices exactly.

    Parameters
    ----------
    system : PolySystem
        The model's own state form (never taken from the certificate).
    cert : dict
        The certificate as read from its file.

    Returns
    -------
    CheckResult
        ``""`` when it holds, else the reason.
    """
    try:
        return CheckResult(_check(system, cert))
    except (ValueError, TypeError, KeyError, ZeroDivisionError) as exc:
        return CheckResult(f"malformed certificate: {exc}")


def _check(system: PolySystem, cert: dict[str, Any]) -> str:
    if cert.get("format") != FORMAT:
        return f"not a {FORMAT} file"
    kind = cert.get("kind")
    if kind not in KINDS:
        return f"unknown kind {kind!r}"
    n = system.n
    nv = n + 1
    if list(cert.get("states", [])) != list(system.states):
        return (f"the state map differs from the model's: file {cert.get('states')}, model "
                f"{list(system.states)}")
    if (kind == "local-discrete") != system.discrete:
        return "the certificate's time base differs from the model's"
    V = poly_from(cert["V"], nv)
    m = cert["multipliers"]
    sigma_b, sigma_Q = gram_from(m["sigma"], nv)
    if not is_psd(sigma_Q):
        return "the Gram matrix of sigma is not positive semidefinite (exact charpoly)"
    sigma = gram_poly(sigma_b, sigma_Q)
    if kind == "global-continuous":
        return _check_global(system, cert, V, sigma)
    c, U = q(cert["c"]), q(cert["U"])
    if not (c > 0 and U > 0):
        return "c and U must be positive"
    if kind == "local-discrete" or "gamma" not in cert:
        if not _quadratic_pd(V, n, nv):
            return "V is not a positive definite quadratic form in the state"
    else:
        why = _radially_unbounded(cert, V, n, nv)
        if why:
            return why
        if V.get((0,) * nv, Fraction(0)) >= c:
            return "V(0) >= c: the origin is not inside {V < c}"
    U2 = {(0,) * nv: U * U}
    mu_b, mu_Q = gram_from(m["mu"], nv)
    if not is_psd(mu_Q):
        return "the Gram matrix of mu is not positive semidefinite (exact charpoly)"
    mu = gram_poly(mu_b, mu_Q)
    v2 = pmul(_var(n, nv), _var(n, nv))
    box = padd(U2, pscale(v2, Fraction(-1)))
    if kind == "local-continuous":
        eps = q(cert["epsilon"])
        if not eps > 0:
            return "epsilon must be positive"
        lam = poly_from(m["lambda"], nv)
        work = len(V) * sum(len(p) for p in system.f) + len(lam) * (len(V) + 1)
        if work > MAX_PRODUCT_WORK:
            return (f"V has {len(V)} terms and lambda {len(lam)}: grad V . f and lambda (V - c) "
                    f"are {work} products of terms, above MAX_PRODUCT_WORK = {MAX_PRODUCT_WORK}")
        target = padd(pscale(vdot(V, system), Fraction(-1)), pscale(_norm2(n, nv), -eps),
                      pmul(lam, padd(V, {(0,) * nv: -c})), pscale(pmul(mu, box), Fraction(-1)))
    else:
        lam_b, lam_Q = gram_from(m["lambda"], nv)
        if not is_psd(lam_Q):
            return "the Gram matrix of lambda is not positive semidefinite (exact charpoly)"
        lam = gram_poly(lam_b, lam_Q)
        Vf = pcompose(V, list(system.f), nv)
        target = padd({(0,) * nv: c}, pscale(Vf, Fraction(-1)),
                      pscale(pmul(lam, padd({(0,) * nv: c}, pscale(V, Fraction(-1)))),
                             Fraction(-1)), pscale(pmul(mu, box), Fraction(-1)))
        nus = m.get("nu", [])
        if len(nus) != len(system.bounded_states):
            return "one nu multiplier per past-input state is needed"
        for j, block in zip(system.bounded_states, nus, strict=True):
            nb, nQ = gram_from(block, nv)
            if not is_psd(nQ):
                return "a Gram matrix of nu is not positive semidefinite (exact charpoly)"
            xj2 = pmul(_var(j, nv), _var(j, nv))
            target = padd(target, pscale(pmul(gram_poly(nb, nQ),
                                              padd(U2, pscale(xj2, Fraction(-1)))),
                                         Fraction(-1)))
    diff = padd(target, pscale(sigma, Fraction(-1)))
    if diff:
        k = sorted(diff)[0]
        return f"the identity fails at the monomial {list(k)} (difference {_short(diff[k])})"
    return ""


def _check_global(system: PolySystem, cert: dict[str, Any], V: Poly, sigma: Poly) -> str:
    n = system.n
    nv = n + 1
    if not system.affine_in_input():
        return "the system is not affine in the input"
    a = q(cert["alpha"])
    if not a > 0:
        return "alpha must be positive"
    why = _radially_unbounded(cert, V, n, nv)
    if why:
        return why
    f0 = [{k: c for k, c in p.items() if k[-1] == 0} for p in system.f]
    b = [{k[:-1] + (0,): c for k, c in p.items() if k[-1] == 1} for p in system.f]
    work = len(V) * sum(len(p) for p in system.f)
    if work > MAX_PRODUCT_WORK:
        return (f"V has {len(V)} terms: grad V . f is {work} products of terms, above "
                f"MAX_PRODUCT_WORK = {MAX_PRODUCT_WORK}")
    grads = [pdiff(V, i) for i in range(n)]
    W = padd(*(pmul(grads[i], f0[i]) for i in range(n)))
    G = padd(*(pmul(grads[i], b[i]) for i in range(n)))
    if len(G) ** 2 > MAX_PRODUCT_WORK:
        return (f"G = grad V . b has {len(G)} terms: G^2 is {len(G) ** 2} products of "
                f"terms, above MAX_PRODUCT_WORK = {MAX_PRODUCT_WORK}")
    target = padd(pscale(W, Fraction(-1)), pscale(pmul(G, G), -a), pscale(_norm2(n, nv), -a))
    diff = padd(target, pscale(sigma, Fraction(-1)))
    zero = (0,) * nv
    C = -diff.pop(zero, Fraction(0))  # target + C = sigma: C is free, sigma(0) >= 0
    if diff:
        k = sorted(diff)[0]
        return f"the identity fails at the monomial {list(k)} (difference {_short(diff[k])})"
    if C < 0:
        return "the constant C is negative"
    return ""


#: Largest certificate file read (bytes).
MAX_FILE_BYTES = 2_000_000


@dataclass(frozen=True, kw_only=True, repr=False)
class CertificateCheck(Result):
    """Result of :func:`check_certificate` (``to_dict`` adds ``proof``: ``"interval"``
    when valid, else ``"none"``).

    Attributes
    ----------
    valid : bool
        The certificate holds for this model (re-verified exactly, from scratch).
    reason : str
        Why it was refused (empty when valid).
    kind : str
        The certificate's kind.
    radius : float
        U (every input with sup|v| <= U; ``inf`` for a global certificate), when valid.
    property : str
        What a valid certificate proves.
    state_map : str
        The model's state form the check used.
    """

    valid: bool
    reason: str
    kind: str
    radius: float
    property: str
    state_map: str

    def __repr__(self) -> str:
        return f"CertificateCheck(valid={self.valid}, kind={self.kind!r}, radius={self.radius})"

    def _repr_markdown_(self) -> str:
        return f"**certificate {'holds' if self.valid else 'refused'}**: {self.text()}"

    def _computed(self) -> dict[str, Any]:
        """The radius (``"inf"`` for a global certificate) and the proof level."""
        return {"radius": "inf" if math.isinf(self.radius) else self.radius,
                "proof": "interval" if self.valid else "none"}

    def text(self) -> str:
        """One line: holds (with its radius and property) or refused (with the reason)."""
        if not self.valid:
            return f"refused: {self.reason}"
        what = ("every bounded input" if math.isinf(self.radius)
                else f"every input with sup|v| <= {self.radius:.6g}")
        return (f"holds (exact rational re-check): {self.kind}, {what}; proves {self.property}"
                f"; state map {self.state_map}")


def _json_int(text: str) -> int:
    """A JSON integer, refused above :data:`MAX_RATIONAL_CHARS` digits before conversion."""
    if len(text) > MAX_RATIONAL_CHARS:
        raise ValueError(f"an integer of {len(text)} digits, above MAX_RATIONAL_CHARS = "
                         f"{MAX_RATIONAL_CHARS}")
    return int(text)


def _same_model(system: PolySystem, cert: dict[str, Any]) -> None:
    """Refuse (ArgumentError) a file of an unknown format or kind, or for another model."""
    from gfrf.errors import ArgumentError
    from gfrf.stability.narx_check import FORMATS

    if cert.get("format") != FORMAT:
        raise ArgumentError(f"unknown certificate format {str(cert.get('format'))[:40]!r} "
                            f"(known: {', '.join((FORMAT, *FORMATS))})")
    if cert.get("kind") not in KINDS:
        raise ArgumentError(f"unknown certificate kind {str(cert.get('kind'))[:40]!r} "
                            f"(known: {', '.join(KINDS)})")
    if cert.get("states") != list(system.states) or (
            (cert["kind"] == "local-discrete") != system.discrete):
        raise ArgumentError(f"the certificate is for another model: its states "
                            f"{str(cert.get('states'))[:120]} ({cert['kind']}) differ from "
                            f"the model's {list(system.states)}")


def check_certificate(model: Any, certificate: dict[str, Any] | str | Path) -> CertificateCheck:
    """Re-verify a certificate written by ``gfrf threshold --certificate-out`` from scratch.

    Dispatches on the file's ``format``: a sum-of-squares certificate
    (:data:`FORMAT`) is checked here, an invariant box or paving of a NARX recursion by
    :func:`gfrf.stability.narx_check.check_narx`.

    Parameters
    ----------
    model : ModelFile or Model
        The model the certificate claims to be about (its state form is rebuilt here).
    certificate : dict or str or Path
        The certificate, or the path of its JSON file.

    Returns
    -------
    CertificateCheck

    Raises
    ------
    ArgumentError
        The file is missing, too large, not JSON, of an unknown ``version``, malformed
        above a stated limit, or (a NARX file) recorded for another model.
    """
    import json

    from gfrf.errors import ArgumentError
    from gfrf.stability.polysys import StateFormError, state_form

    if not isinstance(certificate, dict):
        path = Path(certificate)
        if not path.is_file():
            raise ArgumentError(f"certificate file {str(path)[:200]!r} is not a regular file")
        if path.stat().st_size > MAX_FILE_BYTES:
            raise ArgumentError(f"certificate file is above MAX_FILE_BYTES = {MAX_FILE_BYTES} "
                                f"bytes")
        try:
            certificate = json.loads(path.read_text(encoding="utf-8"), parse_int=_json_int)
        except (UnicodeDecodeError, ValueError) as exc:  # JSONDecodeError is a ValueError
            raise ArgumentError(f"certificate file is not JSON: {exc}") from None
        except RecursionError:
            raise ArgumentError("certificate file is not JSON: nested too deeply") from None
        if not isinstance(certificate, dict):
            raise ArgumentError("certificate file must hold a JSON object")
    version = certificate.get("version")
    if type(version) is not int or version != CERTIFICATE_VERSION:
        raise ArgumentError(f"certificate version {str(version)[:40]!r} is unknown: this gfrf "
                            f"reads version {CERTIFICATE_VERSION}")
    from gfrf.stability.implicit_check import FORMAT as IMPLICIT_FORMAT

    if certificate.get("format") == IMPLICIT_FORMAT:
        return _check_implicit(model, certificate)
    try:
        system = state_form(model)
    except StateFormError as exc:
        raise ArgumentError(f"the model has no polynomial state form: {exc}") from None
    from gfrf.stability.narx_check import FORMATS, PROPERTY, check_narx

    if certificate.get("format") in FORMATS:
        kind, why, bound = check_narx(system, certificate)
        return CertificateCheck(valid=not why, reason=why, kind=kind, radius=bound,
                                property="" if why else PROPERTY,
                                state_map=system.map_text())
    _same_model(system, certificate)
    reason = check_dict(system, certificate)
    if reason.startswith("malformed certificate"):
        raise ArgumentError(reason)
    kind = str(certificate.get("kind", ""))[:40]
    radius = math.inf if kind == "global-continuous" else 0.0
    if not reason and kind != "global-continuous":
        U = q(certificate["U"])
        radius = float(U) if Fraction(float(U)) <= U else math.nextafter(float(U), 0.0)
    prop = ("bounded: every solution under every bounded input stays bounded"
            if kind == "global-continuous" else
            "bounded: every solution from rest stays in the invariant set {V <= c}")
    return CertificateCheck(valid=not reason, reason=str(reason), kind=kind,
                            radius=radius if not reason else 0.0,
                            property=prop if not reason else "", state_map=system.map_text())


def _check_implicit(model: Any, certificate: dict[str, Any]) -> CertificateCheck:
    """Re-verify an invariant polygon of an implicit loop (:mod:`gfrf.stability.implicit_check`)."""
    from gfrf.errors import ArgumentError
    from gfrf.stability.implicit import implicit_form
    from gfrf.stability.implicit_check import check_region
    from gfrf.stability.polysys import StateFormError

    try:
        form = implicit_form(model)
    except StateFormError as exc:
        raise ArgumentError(f"the model has no implicit state form: {exc}") from None
    reason = check_region(form, certificate)
    if reason.startswith("malformed certificate"):
        raise ArgumentError(reason)
    radius, level = 0.0, ""
    if not reason:
        U = q(certificate["U"])
        radius = float(U) if Fraction(float(U)) <= U else math.nextafter(float(U), 0.0)
        if certificate.get("level") is not None:
            level = (f" and keeps |D(x)| > {q(certificate['level'])} |D(0)| (the stated "
                     f"breakdown level)")
    return CertificateCheck(valid=not reason, reason=reason, kind=str(certificate["kind"]),
                            radius=radius,
                            property="" if reason else (
                                "bounded: every solution from rest under every input with "
                                f"sup|v| <= U (v = {form.input_name}) stays in the polygon"
                                f"{level}"),
                            state_map=f"D(x) y'' + R(x, v) = 0, x = ({', '.join(form.states)})"
                                      f", v = {form.input_name}")
