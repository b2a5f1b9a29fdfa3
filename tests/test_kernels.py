"""Layer L0: hypothesis properties of the closed-form planar kernels (assur.kernels.planar).

Points are complex numbers z = x + iy; the kernels take complex jets (order 0 here unless a
derivative is checked) with batch axes first. Each property is a geometric fact checked by an
independent computation in the test (distances, cross products, reflections), never by calling
the kernel a second way only.
"""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays

from assur.kernels import planar
from assur.kernels.jet import Jet

SETTINGS = settings(max_examples=40, deadline=None)
N = st.integers(1, 12)


def J(v):
    """An order-0 jet of a plain array (the kernels' input type)."""
    return Jet(np.asarray(v))


def V(x):
    return x.v if isinstance(x, Jet) else np.asarray(x)


def cross(a, b):
    return np.imag(np.conj(a) * b)


def dot(a, b):
    return np.real(np.conj(a) * b)


def unif(n, lo, hi):
    return arrays(np.float64, (n,), elements=st.floats(lo, hi, allow_nan=False, allow_infinity=False))


@st.composite
def two_circles(draw, buildable=True):
    """(c1, r1, c2, r2) batches; buildable: |r1 − r2| < d < r1 + r2 with a 5 % margin of the range."""
    n = draw(N)
    c1 = draw(unif(n, -10, 10)) + 1j * draw(unif(n, -10, 10))
    phi = draw(unif(n, -np.pi, np.pi))
    d = draw(unif(n, 0.1, 10))
    r1 = draw(unif(n, 0.1, 10))
    c2 = c1 + d * np.exp(1j * phi)
    if buildable:
        lo, hi = np.abs(d - r1), d + r1
        t = draw(unif(n, 0.05, 0.95))
        r2 = lo + t * (hi - lo)
    else:
        # too far apart (r2 < d − r1) or one inside the other (r2 > d + r1 or r2 < r1 − d)
        which = draw(arrays(np.int64, (n,), elements=st.integers(0, 1)))
        f = draw(unif(n, 1.01, 3.0))
        r1 = np.where(which == 0, 0.4 * d, r1)                  # r1 < d: separate circles are possible
        far = (d - r1) / f                                       # r1 + r2 < d
        inside = (d + r1) * f                                    # r2 − r1 > d: circle 1 inside circle 2
        r2 = np.where(which == 0, far, inside)
    return c1, r1, c2, r2


# -- circle_circle ------------------------------------------------------------------------------------------
@SETTINGS
@given(two_circles(), st.sampled_from([1, -1]))
def test_circle_circle_point_lies_on_both_circles(circ, branch):
    c1, r1, c2, r2 = circ
    z, ok = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), branch)
    z = V(z)
    assert np.all(ok)
    scale = np.maximum.reduce([np.abs(c1), np.abs(c2), r1, r2, np.ones_like(r1)])
    np.testing.assert_array_less(np.abs(np.abs(z - c1) - r1), 1e-12 * scale * 10)
    np.testing.assert_array_less(np.abs(np.abs(z - c2) - r2), 1e-12 * scale * 10)


@SETTINGS
@given(two_circles())
def test_circle_circle_branch_flip_mirrors_across_the_line_of_centres(circ):
    c1, r1, c2, r2 = circ
    zp, okp = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), 1)
    zm, okm = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), -1)
    zp, zm = V(zp), V(zm)
    D = c2 - c1
    mirrored = c1 + D * np.conj((zp - c1) / D)      # reflection across the line c1 → c2
    scale = np.maximum.reduce([np.abs(c1), np.abs(c2), r1, r2, np.ones_like(r1)])
    np.testing.assert_array_less(np.abs(zm - mirrored), 1e-11 * scale)
    # branch +1 is on the left of c1 → c2 (module convention), −1 on the right
    assert np.all(cross(D, zp - c1) > 0) and np.all(cross(D, zm - c1) < 0)


@SETTINGS
@given(two_circles(), st.floats(-np.pi, np.pi), st.floats(-50, 50), st.floats(-50, 50), st.sampled_from([1, -1]))
def test_circle_circle_is_invariant_under_rigid_motions(circ, phi, tx, ty, branch):
    c1, r1, c2, r2 = circ
    R, T = np.exp(1j * phi), tx + 1j * ty
    z, _ = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), branch)
    zt, _ = planar.circle_circle(J(R * c1 + T), J(r1), J(R * c2 + T), J(r2), branch)
    scale = np.maximum.reduce([np.abs(c1), np.abs(c2), r1, r2, np.ones_like(r1)]) + abs(T)
    np.testing.assert_array_less(np.abs(V(zt) - (R * V(z) + T)), 1e-11 * scale)


@SETTINGS
@given(two_circles(), st.sampled_from([1, -1]))
def test_circle_circle_batched_equals_looped(circ, branch):
    c1, r1, c2, r2 = circ
    z, ok = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), branch)
    for k in range(len(c1)):
        zk, okk = planar.circle_circle(J(c1[k]), J(r1[k]), J(c2[k]), J(r2[k]), branch)
        assert np.shape(V(zk)) == () and bool(okk) == bool(ok[k])
        np.testing.assert_allclose(V(zk), V(z)[k], rtol=1e-14, atol=1e-14)


@SETTINGS
@given(two_circles(buildable=False), st.sampled_from([1, -1]))
def test_circle_circle_unbuildable_is_nan_and_invalid(circ, branch):
    c1, r1, c2, r2 = circ
    d = np.abs(c2 - c1)
    assert np.all((d > r1 + r2) | (d < np.abs(r1 - r2)))      # the independent unbuildability test
    z, ok = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), branch)
    assert not np.any(ok)
    assert np.all(np.isnan(V(z).real)) and np.all(np.isnan(V(z).imag))


@SETTINGS
@given(two_circles(), two_circles(buildable=False))
def test_circle_circle_mixed_batch_flags_exactly_the_unbuildable(good, bad):
    c1, r1, c2, r2 = (np.concatenate([g, b]) for g, b in zip(good, bad))
    z, ok = planar.circle_circle(J(c1), J(r1), J(c2), J(r2), 1)
    d = np.abs(c2 - c1)
    expect = (np.abs(r1 - r2) < d) & (d < r1 + r2)              # triangle inequality
    np.testing.assert_array_equal(ok, expect)
    assert np.all(np.isfinite(V(z)[expect])) and np.all(np.isnan(V(z)[~expect]))


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # 1/0 inside the kernel for concentric circles
def test_circle_circle_tangent_and_concentric():
    # externally tangent circles (d = r1 + r2): the single contact point c1 + r1·unit(D), valid
    z, ok = planar.circle_circle(J(0j), J(1.0), J(3 + 0j), J(2.0), 1)
    assert bool(ok) and abs(V(z) - 1.0) < 1e-12
    # concentric circles never intersect in a point: invalid, NaN
    z, ok = planar.circle_circle(J(1 + 1j), J(1.0), J(1 + 1j), J(1.0), 1)
    assert not bool(ok) and np.isnan(V(z).real) and np.isnan(V(z).imag)


@SETTINGS
@given(two_circles(), st.sampled_from([1, -1]), unif(6, -1, 1))
def test_circle_circle_jet_derivatives_match_central_differences(circ, branch, rates):
    # moving centres and radii along s: c(s) = c + ċ s, r(s) = r + ṙ s (each with its own rate)
    c1, r1, c2, r2 = circ
    dc1, dc2 = rates[0] + 1j * rates[1], rates[2] + 1j * rates[3]
    dr1, dr2 = 0.1 * rates[4] * r1, 0.1 * rates[5] * r2

    def at(s, order):
        mk = (lambda v, d: Jet(v + d * s, np.broadcast_to(d, np.shape(v)) + 0 * v, 0 * v)) if order else \
            (lambda v, d: Jet(v + d * s))
        return planar.circle_circle(mk(c1, dc1), mk(r1, dr1), mk(c2, dc2), mk(r2, dr2), branch)[0]

    z = at(0.0, 2)
    h = 1e-4 * np.maximum(1.0, np.minimum(r1, r2))
    fp, fm, f0 = V(at(h, 0)), V(at(-h, 0)), V(at(0.0, 0))
    fp2, fm2 = V(at(h / 2, 0)), V(at(-h / 2, 0))
    d_fd = (4 * (fp2 - fm2) / h - (fp - fm) / (2 * h)) / 3
    dd_fd = (4 * (fp2 - 2 * f0 + fm2) / (h / 2) ** 2 - (fp - 2 * f0 + fm) / h**2) / 3
    scale = 1 + np.abs(z.v) + np.abs(z.d) + np.abs(z.dd)
    np.testing.assert_array_less(np.abs(z.d - d_fd), 1e-5 * scale)
    np.testing.assert_array_less(np.abs(z.dd - dd_fd), 1e-3 * scale)


def test_kernels_accept_plain_arrays_like_line_line():
    # line_line already works on plain arrays: lines y = 0 and x = 1 meet at 1 + 0i
    z, ok = planar.line_line(np.array(0j), 1 + 0j, np.array(1 + 0j), 1j)
    assert bool(ok) and abs(z - 1) < 1e-15
    # the same call style for circle_circle: unit circles about 0 and 1 meet at ½ ± i·√3/2
    z, ok = planar.circle_circle(np.array(0j), 1.0, np.array(1 + 0j), 1.0, 1)
    assert bool(ok) and abs(z - (0.5 + 1j * np.sqrt(3) / 2)) < 1e-15


# -- circle_line ----------------------------------------------------------------------------------------------
@st.composite
def circle_and_line(draw, buildable=True):
    """(c, r, q, u): a circle and a line q + t·u (|u| = 1) at signed distance δ from c."""
    n = draw(N)
    c = draw(unif(n, -10, 10)) + 1j * draw(unif(n, -10, 10))
    r = draw(unif(n, 0.1, 10))
    u = np.exp(1j * draw(unif(n, -np.pi, np.pi)))
    frac = draw(unif(n, -0.95, 0.95)) if buildable else \
        draw(unif(n, 1.01, 3.0)) * np.where(draw(arrays(np.bool_, (n,))), 1, -1)
    along = draw(unif(n, -10, 10))
    q = c + 1j * u * (frac * r) + along * u          # foot of the perpendicular shifted along the line
    return c, r, q, u


@SETTINGS
@given(circle_and_line(), st.sampled_from([1, -1]))
def test_circle_line_point_lies_on_circle_and_line(cl, branch):
    c, r, q, u = cl
    z, ok = planar.circle_line(J(c), J(r), J(q), J(u), branch)
    z = V(z)
    assert np.all(ok)
    scale = 1 + np.abs(c) + np.abs(q) + r
    np.testing.assert_array_less(np.abs(np.abs(z - c) - r), 1e-12 * scale * 10)
    np.testing.assert_array_less(np.abs(cross(u, z - q)), 1e-12 * scale * 10)


@SETTINGS
@given(circle_and_line())
def test_circle_line_branch_plus_is_farther_along_u(cl):
    c, r, q, u = cl
    zp, _ = planar.circle_line(J(c), J(r), J(q), J(u), 1)
    zm, _ = planar.circle_line(J(c), J(r), J(q), J(u), -1)
    # the chord between the two intersections has length 2·√(r² − δ²) (δ = distance of c from the line)
    delta = cross(u, c - q)
    chord = 2 * np.sqrt(r**2 - delta**2)
    along = dot(u, V(zp) - V(zm))
    # (rad = proj² − |q − c|² + r² loses ~eps·|q − c|²/r to cancellation: the tolerance follows it)
    cond = 1 + np.abs(q - c) ** 2 / r
    np.testing.assert_array_less(np.abs(along - chord), 1e-13 * cond)
    assert np.all(along > 0)
    # both are mirror images across the perpendicular from c to the line
    foot = q + u * dot(u, c - q)
    np.testing.assert_array_less(np.abs((V(zp) - foot) + (V(zm) - foot)), 1e-13 * cond)


@SETTINGS
@given(circle_and_line(), st.floats(-np.pi, np.pi), st.floats(-50, 50), st.floats(-50, 50), st.sampled_from([1, -1]))
def test_circle_line_is_invariant_under_rigid_motions(cl, phi, tx, ty, branch):
    c, r, q, u = cl
    R, T = np.exp(1j * phi), tx + 1j * ty
    z, _ = planar.circle_line(J(c), J(r), J(q), J(u), branch)
    zt, _ = planar.circle_line(J(R * c + T), J(r), J(R * q + T), J(R * u), branch)
    scale = 1 + np.abs(c) + np.abs(q) + r + abs(T)
    np.testing.assert_array_less(np.abs(V(zt) - (R * V(z) + T)), 1e-11 * scale)


@SETTINGS
@given(circle_and_line(), st.sampled_from([1, -1]))
def test_circle_line_batched_equals_looped(cl, branch):
    c, r, q, u = cl
    z, ok = planar.circle_line(J(c), J(r), J(q), J(u), branch)
    for k in range(len(c)):
        zk, okk = planar.circle_line(J(c[k]), J(r[k]), J(q[k]), J(u[k]), branch)
        assert bool(okk) == bool(ok[k])
        # scalar and vector loops may round differently; the kernel's cancellation amplifies it
        cond = 1 + abs(q[k] - c[k]) ** 2 / r[k] + abs(c[k])
        assert abs(V(zk) - V(z)[k]) <= 1e-14 * cond


@SETTINGS
@given(circle_and_line(buildable=False), st.sampled_from([1, -1]))
def test_circle_line_unbuildable_is_nan_and_invalid(cl, branch):
    c, r, q, u = cl
    assert np.all(np.abs(cross(u, c - q)) > r)                 # the line misses the circle
    z, ok = planar.circle_line(J(c), J(r), J(q), J(u), branch)
    assert not np.any(ok)
    assert np.all(np.isnan(V(z).real)) and np.all(np.isnan(V(z).imag))


# -- line_line --------------------------------------------------------------------------------------------------
@st.composite
def two_lines(draw):
    n = draw(N)
    q1 = draw(unif(n, -10, 10)) + 1j * draw(unif(n, -10, 10))
    q2 = draw(unif(n, -10, 10)) + 1j * draw(unif(n, -10, 10))
    a1 = draw(unif(n, -np.pi, np.pi))
    gap = draw(unif(n, 0.1, np.pi - 0.1))                     # the lines cross at an angle ≥ 0.1 rad
    return q1, np.exp(1j * a1), q2, np.exp(1j * (a1 + gap))


@SETTINGS
@given(two_lines())
def test_line_line_point_lies_on_both_lines(ll):
    q1, u1, q2, u2 = ll
    z, ok = planar.line_line(J(q1), J(u1), J(q2), J(u2))
    z = V(z)
    assert np.all(ok)
    scale = 1 + np.abs(q1) + np.abs(q2) + np.abs(z)
    np.testing.assert_array_less(np.abs(cross(u1, z - q1)), 1e-12 * scale * 10)
    np.testing.assert_array_less(np.abs(cross(u2, z - q2)), 1e-12 * scale * 10)


@SETTINGS
@given(two_lines(), st.floats(-np.pi, np.pi), st.floats(-50, 50), st.floats(-50, 50))
def test_line_line_rigid_motion_and_batch(ll, phi, tx, ty):
    q1, u1, q2, u2 = ll
    R, T = np.exp(1j * phi), tx + 1j * ty
    z, _ = planar.line_line(J(q1), J(u1), J(q2), J(u2))
    zt, _ = planar.line_line(J(R * q1 + T), J(R * u1), J(R * q2 + T), J(R * u2))
    scale = 1 + np.abs(V(z)) + abs(T)
    np.testing.assert_array_less(np.abs(V(zt) - (R * V(z) + T)), 1e-11 * scale)
    for k in range(len(q1)):
        zk, _ = planar.line_line(J(q1[k]), J(u1[k]), J(q2[k]), J(u2[k]))
        np.testing.assert_allclose(V(zk), V(z)[k], rtol=1e-14, atol=1e-14)


@SETTINGS
@given(two_lines(), arrays(np.bool_, (1,)))
def test_line_line_parallel_is_invalid_and_nan(ll, flip):
    q1, u1, q2, _ = ll
    u2 = u1 * (-1 if flip[0] else 1)                            # parallel or antiparallel
    z, ok = planar.line_line(J(q1), J(u1), J(q2), J(u2))
    assert not np.any(ok)
    assert np.all(np.isnan(V(z).real)) and np.all(np.isnan(V(z).imag))


# -- rotation_from_slide -----------------------------------------------------------------------------------------
@st.composite
def slide(draw, buildable=True):
    """(D, c_par, c_perp): |D| > |c_perp| when buildable."""
    n = draw(N)
    Dm = draw(unif(n, 0.1, 10))
    D = Dm * np.exp(1j * draw(unif(n, -np.pi, np.pi)))
    c_par = draw(unif(n, -5, 5))
    frac = draw(unif(n, -0.95, 0.95)) if buildable else \
        draw(unif(n, 1.01, 3.0)) * np.where(draw(arrays(np.bool_, (n,))), 1, -1)
    return D, c_par, frac * Dm


@SETTINGS
@given(slide(), st.sampled_from([1, -1]))
def test_rotation_from_slide_solves_its_defining_equation(sl, branch):
    # rotation_from_slide solves D = e·((c_par + t) + i·c_perp) for a unit e and a real slide t; the
    # branch is the sign of c_par + t (+1: the slider ahead along the guide line).
    D, c_par, c_perp = sl
    e, ok = planar.rotation_from_slide(J(D), c_par, c_perp, branch)
    e = V(e)
    assert np.all(ok)
    np.testing.assert_allclose(np.abs(e), 1.0, rtol=0, atol=1e-14)
    w = D / e                                                   # = (c_par + t) + i·c_perp
    scale = 1 + np.abs(D)
    np.testing.assert_array_less(np.abs(w.imag - c_perp), 1e-12 * scale * 10)
    t = w.real - c_par
    assert np.all(np.sign(c_par + t) == branch)
    np.testing.assert_allclose(np.abs(c_par + t), np.sqrt(np.abs(D) ** 2 - c_perp**2), rtol=1e-12, atol=1e-13)
    # reconstruct D from e and t
    np.testing.assert_array_less(np.abs(e * ((c_par + t) + 1j * c_perp) - D), 1e-12 * scale * 10)


@SETTINGS
@given(slide(), st.floats(-np.pi, np.pi))
def test_rotation_from_slide_rotates_with_D_and_batches(sl, phi):
    D, c_par, c_perp = sl
    R = np.exp(1j * phi)
    ep, _ = planar.rotation_from_slide(J(D), c_par, c_perp, 1)
    em, _ = planar.rotation_from_slide(J(D), c_par, c_perp, -1)
    er, _ = planar.rotation_from_slide(J(R * D), c_par, c_perp, 1)
    np.testing.assert_allclose(V(er), R * V(ep), rtol=0, atol=1e-13)
    # the other branch: D = e₊(s + ic) = e₋(−s + ic) with s = √(|D|² − c²)
    s = np.sqrt(np.abs(D) ** 2 - c_perp**2)
    np.testing.assert_allclose(V(em), V(ep) * (s + 1j * c_perp) / (-s + 1j * c_perp), rtol=0, atol=1e-12)
    for k in range(len(D)):
        ek, _ = planar.rotation_from_slide(J(D[k]), c_par[k], c_perp[k], 1)
        np.testing.assert_allclose(V(ek), V(ep)[k], rtol=1e-14, atol=1e-14)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@SETTINGS
@given(slide(buildable=False), st.sampled_from([1, -1]))
def test_rotation_from_slide_unbuildable_is_nan_and_invalid(sl, branch):
    D, c_par, c_perp = sl
    assert np.all(np.abs(c_perp) > np.abs(D))                   # the offset is longer than the joint distance
    e, ok = planar.rotation_from_slide(J(D), c_par, c_perp, branch)
    assert not np.any(ok)
    assert np.all(np.isnan(V(e).real)) and np.all(np.isnan(V(e).imag))
