"""Layer L0: properties of the second-order forward jets (assur.kernels.jet).

A jet carries v, d = dv/ds and dd = d²v/ds² along one path parameter s. For random smooth
compositions of +, −, ×, /, sqrt, expi, abs2, conj, angle (and .real/.imag) on random real and
complex inputs moving along polynomial paths, d and dd must equal central finite differences of
the values (Richardson-extrapolated, so the truncation error is O(h⁴)), and for a few functions
they must equal the derivatives worked out by hand.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from assur.kernels.jet import Jet, abs2, angle, as_jet, cross, dot, expi, sqrt, value, where_valid

N_ELEM = 6          # every example evaluates a batch of this many independent samples
H = 1e-2            # finite-difference step (Richardson: error ~ H⁴·f⁽⁵⁾ + eps·|f|/H²)
RTOL = 2e-7         # relative to the magnitude of the function and its derivatives

# -- random programs ------------------------------------------------------------------------------
# A program is a list of steps; each step appends one new value computed from earlier ones. Every
# operation is guarded so that it stays smooth: denominators are ≥ 1 (1 + x² or 1 + |z|²), square
# roots take ≥ 0.25 arguments, and `angle` is only compared where its argument stays away from 0
# and from the branch cut on the negative real axis (a per-sample mask).
UNARY = ("neg", "sqrt", "expi", "abs2", "conj", "angle", "real", "imag", "recip", "cdiv", "crsub", "cmul")
BINARY = ("add", "sub", "mul", "div")

step_st = st.one_of(
    st.tuples(st.sampled_from(UNARY), st.integers(0, 10**6), st.just(0),
              st.floats(-2.0, 2.0).filter(lambda c: abs(c) > 0.1)),
    st.tuples(st.sampled_from(BINARY), st.integers(0, 10**6), st.integers(0, 10**6), st.just(1.0)),
)
program_st = st.lists(step_st, min_size=1, max_size=7)


def _positive_den(x):
    """1 + |x|² as a jet (real); ≥ 1 so division is smooth."""
    return abs2(x) + 1.0


def run(program, inputs, mask):
    """Evaluate a program on a list of input jets; returns the last value (a jet).

    ``mask`` (bool array) is and-ed in place with the domain guard of `angle`.
    """
    vals = list(inputs)
    for op, i, j, c in program:
        a = vals[i % len(vals)]
        b = vals[j % len(vals)]
        cplx = np.iscomplexobj(a.v)
        if op == "neg":
            r = -a
        elif op == "sqrt":
            r = sqrt(abs2(a) + 0.25)
        elif op == "expi":
            r = expi(a.real if cplx else a)
        elif op == "abs2":
            r = abs2(a)
        elif op == "conj":
            r = a.conj()
        elif op == "angle":
            w = a if cplx else a + 1j * (a * a + 1.0)    # a real value becomes a point in the upper half-plane
            mask &= (np.abs(w.v) > 0.5) & (np.abs(np.angle(w.v)) < 2.6)
            r = angle(w)
        elif op == "real":
            r = a.real
        elif op == "imag":
            r = a.imag if cplx else a * c
        elif op == "recip":
            r = c / _positive_den(a)                       # exercises __rtruediv__ and reciprocal()
        elif op == "cdiv":
            r = a / c                                      # division by a plain constant
        elif op == "crsub":
            r = np.float64(c) - a                          # numpy scalar on the left: __rsub__
        elif op == "cmul":
            r = np.array(c) * a                            # ndarray on the left: __rmul__
        elif op == "add":
            r = a + b
        elif op == "sub":
            r = a - b
        elif op == "mul":
            r = a * b
        elif op == "div":
            r = a / _positive_den(b)                       # Jet / Jet
        else:  # pragma: no cover
            raise AssertionError(op)
        assert isinstance(r, Jet), (op, type(r))
        vals.append(r)
    return vals[-1]


def _paths(seed):
    """Random real and complex inputs x(s) = a + b·s + c·s²/2 (per sample)."""
    rng = np.random.default_rng(seed)
    real = [rng.uniform(-1.5, 1.5, (3, N_ELEM)) for _ in range(2)]
    cplx = [rng.uniform(-1.5, 1.5, (3, N_ELEM)) + 1j * rng.uniform(-1.5, 1.5, (3, N_ELEM)) for _ in range(2)]
    return real + cplx


def _at(paths, s):
    """Order-0 jets of the inputs at s."""
    return [Jet(a + b * s + 0.5 * c * s * s) for a, b, c in paths]


def _bc(x):
    return np.broadcast_to(np.asarray(x), (N_ELEM,))


@settings(max_examples=150, deadline=None)
@given(program=program_st, seed=st.integers(0, 2**32 - 1))
def test_random_composition_matches_central_differences(program, seed):
    paths = _paths(seed)
    mask = np.ones(N_ELEM, dtype=bool)
    jet = run(program, [Jet(a, b, c) for a, b, c in paths], mask)
    f = {}
    for k in (-2, -1, 0, 1, 2):                          # values at s = k·H/2
        f[k] = _bc(run(program, _at(paths, k * H / 2), mask).v)
    # central differences with steps H and H/2, Richardson-extrapolated: error O(H⁴)
    d_h, d_h2 = (f[2] - f[-2]) / (2 * H), (f[1] - f[-1]) / H
    dd_h, dd_h2 = (f[2] - 2 * f[0] + f[-2]) / H**2, (f[1] - 2 * f[0] + f[-1]) / (H / 2) ** 2
    d_fd = (4 * d_h2 - d_h) / 3
    dd_fd = (4 * dd_h2 - dd_h) / 3
    v, d, dd = _bc(jet.v), _bc(jet.d), _bc(jet.dd)
    np.testing.assert_array_equal(v, f[0])               # the jet's value is the plain value
    scale = 1.0 + np.abs(v) + np.abs(d) + np.abs(dd)
    m = mask
    # the reference's own error: where a random composition has large higher derivatives the differences at H and
    # H/2 disagree, and their disagreement bounds what Richardson's extrapolation leaves (O(H⁴) ≪ O(H²))
    d_err, dd_err = np.abs(d_h2 - d_h), np.abs(dd_h2 - dd_h)
    assert np.all(np.abs(d - d_fd)[m] <= RTOL * scale[m] + d_err[m]), (program, (d - d_fd)[m])
    assert np.all(np.abs(dd - dd_fd)[m] <= 10 * RTOL * scale[m] + dd_err[m]), (program, (dd - dd_fd)[m])


@settings(max_examples=60, deadline=None)
@given(program=program_st, seed=st.integers(0, 2**32 - 1))
def test_lower_orders_carry_the_same_values_and_first_derivatives(program, seed):
    paths = _paths(seed)
    mask = np.ones(N_ELEM, dtype=bool)
    j2 = run(program, [Jet.variable(a, b, c, 2) for a, b, c in paths], mask)
    j1 = run(program, [Jet.variable(a, b, c, 1) for a, b, c in paths], mask)
    j0 = run(program, [Jet.variable(a, b, c, 0) for a, b, c in paths], mask)
    assert (j2.order, j1.order, j0.order) == (2, 1, 0)
    assert j0.d is None and j0.dd is None and j1.dd is None
    np.testing.assert_array_equal(_bc(j0.v), _bc(j2.v))
    np.testing.assert_array_equal(_bc(j1.v), _bc(j2.v))
    np.testing.assert_array_equal(_bc(j1.d), _bc(j2.d))


# -- exact derivatives of known functions (worked out by hand with the chain/product rules) --------
S = np.array([-1.3, -0.4, 0.2, 0.7, 1.9])


def s_jet():
    """The path parameter itself: v = s, d = 1, dd = 0."""
    return Jet(S.copy(), np.ones_like(S), np.zeros_like(S))


def _check(jet, v, d, dd):
    np.testing.assert_allclose(_bc5(jet.v), v, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(_bc5(jet.d), d, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(_bc5(jet.dd), dd, rtol=1e-13, atol=1e-14)


def _bc5(x):
    return np.broadcast_to(np.asarray(x), S.shape)


def test_exact_sqrt_one_plus_s2():
    # d/ds √(1+s²) = s/√(1+s²);  d²/ds² = (1+s²)^(−3/2)
    s = s_jet()
    _check(sqrt(s * s + 1.0), np.sqrt(1 + S**2), S / np.sqrt(1 + S**2), (1 + S**2) ** -1.5)


def test_exact_expi_of_s_squared():
    # d/ds e^{is²} = 2is·e^{is²};  d²/ds² = (2i − 4s²)·e^{is²}
    s = s_jet()
    e = np.exp(1j * S**2)
    _check(expi(s * s), e, 2j * S * e, (2j - 4 * S**2) * e)


def test_exact_angle_is_atan():
    # arg(1 + i·s) = atan(s):  d = 1/(1+s²),  dd = −2s/(1+s²)²
    s = s_jet()
    _check(angle(1.0 + 1j * s), np.arctan(S), 1 / (1 + S**2), -2 * S / (1 + S**2) ** 2)


def test_exact_reciprocal():
    # d/ds (1/s) = −1/s²;  d²/ds² = 2/s³
    s = s_jet()
    _check(1.0 / s, 1 / S, -1 / S**2, 2 / S**3)


def test_exact_quotient():
    # f = (s² + 1)/(s − 3): f' = (s² − 6s − 1)/(s − 3)²,  f'' = 20/(s − 3)³ (quotient rule)
    s = s_jet()
    _check((s * s + 1.0) / (s - 3.0), (S**2 + 1) / (S - 3), (S**2 - 6 * S - 1) / (S - 3) ** 2, 20 / (S - 3) ** 3)


def test_exact_abs2_of_rotating_vector():
    # |(2 + s)·e^{is}|² = (2 + s)²:  d = 2(2 + s),  dd = 2
    s = s_jet()
    _check(abs2((s + 2.0) * expi(s)), (2 + S) ** 2, 2 * (2 + S), np.full_like(S, 2.0))


def test_exact_conj_real_imag():
    # z = s + i·s³: conj z = s − i s³ → d = 1 − 3i s², dd = −6i s; Re z = s; Im z = s³
    s = s_jet()
    z = s + 1j * (s * s * s)
    _check(z.conj(), S - 1j * S**3, 1 - 3j * S**2, -6j * S)
    _check(z.real, S, np.ones_like(S), np.zeros_like(S))
    _check(z.imag, S**3, 3 * S**2, 6 * S)


def test_exact_cross_and_dot():
    # a = e^{is}, b = 2 (constant): cross(a, b) = Im(conj(a)·b) = −2 sin s; dot = 2 cos s
    s = s_jet()
    a = expi(s)
    _check(cross(a, 2.0 + 0j), -2 * np.sin(S), -2 * np.cos(S), 2 * np.sin(S))
    _check(dot(a, 2.0 + 0j), 2 * np.cos(S), -2 * np.sin(S), -2 * np.cos(S))
    # constant first argument, jet second: cross(1, e^{is}) = sin s
    _check(cross(1.0 + 0j, a), np.sin(S), np.cos(S), -np.sin(S))
    # plain numbers give plain numbers: cross(1, i) = 1, dot(1, i) = 0
    assert cross(1 + 0j, 1j) == 1.0 and dot(1 + 0j, 1j) == 0.0


def test_constants_and_helpers():
    c = Jet.const(np.array([1.0, 2.0]), 2)
    assert c.order == 2
    np.testing.assert_array_equal(c.d, 0.0)
    np.testing.assert_array_equal(c.dd, 0.0)
    assert Jet.const(3.0, 0).order == 0
    assert value(c) is c.v and value(5.0) == 5.0
    assert as_jet(c, 2) is c and as_jet(2.0, 1).order == 1
    # where_valid: invalid samples are NaN in value and derivatives (both parts for complex)
    z = Jet(np.array([1 + 1j, 2 + 2j]), np.array([1j, 1j]), np.array([1.0, 1.0]))
    w = where_valid(z, np.array([True, False]))
    assert w.v[0] == 1 + 1j and np.isnan(w.v[1].real) and np.isnan(w.v[1].imag)
    assert np.isnan(w.d[1].real) and np.isnan(w.d[1].imag) and np.isnan(w.dd[1].imag)


@pytest.mark.parametrize("other", [np.float64(3.0), np.array(3.0), np.array([3.0, 4.0]), 3, 3.0 + 1j])
def test_plain_operands_on_the_left_defer_to_the_jet(other):
    # d/ds (c − s) = −1, d/ds (c/s) = −c/s² (here s = 2): numpy operands must not swallow the jet
    s = Jet(np.array(2.0), np.array(1.0), np.array(0.0))
    for r, d in ((other - s, -1.0), (other + s, 1.0), (other * s, other), (other / s, -np.asarray(other) / 4)):
        assert isinstance(r, Jet)
        np.testing.assert_allclose(np.broadcast_to(r.d, np.shape(r.v)), np.broadcast_to(d, np.shape(r.v)), rtol=1e-15)
