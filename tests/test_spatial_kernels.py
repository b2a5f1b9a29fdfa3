"""Spatial vector kernels of paper 003 (docs/papers/003.md §2–§3, §7; the sections cited below): primitive
identities, the robust unit-vector solver p(·) and the paper's literal closed form kept as a reference.

Reference values are identities checked in the test itself (rotation matrices against Turn, the
e_Z2 formula (8) against the matrix product, the defining equations of p) or the page's stated
special cases (§3.2: a1 = a2 = 90° gives p = s·Ort(V1 × V2); §7: V3_X = 0, negative
discriminant, V1 ∥ V2)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from assur.kernels import spatial as V
from assur.kernels.jet import Jet

finite = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
vec = st.tuples(finite, finite, finite).map(np.array).filter(lambda v: np.linalg.norm(v) > 1e-2)
angle = st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False)
EX, EY, EZ = np.eye(3)


# -- primitives --------------------------------------------------------------------------------------
@given(angle)
def test_turn_matches_the_rotation_matrices(f):
    """§2: T_X(f)·e_Y = Turn(e_Y, e_X, f, 1), and likewise about Y and Z."""
    np.testing.assert_allclose(V.turn(EY, EX, f, 1.0), V.t_x(f) @ EY, atol=1e-14)
    np.testing.assert_allclose(V.turn(EZ, EY, f, 1.0), V.t_y(f) @ EZ, atol=1e-14)
    np.testing.assert_allclose(V.turn(EX, EZ, f, 1.0), V.t_z(f) @ EX, atol=1e-14)


@given(vec, angle, st.floats(0.1, 5.0))
def test_turn_rotates_any_vector_and_rescales_it(v, a, r):
    """Turn(V, e_X, a, r) = T_X(a)·V·r/|V| (and about Y, Z): Rodrigues' rotation, right-hand rule."""
    for axis, T in ((EX, V.t_x), (EY, V.t_y), (EZ, V.t_z)):
        got = V.turn(v, 3.0 * axis, a, r)
        np.testing.assert_allclose(got, T(a) @ v * r / np.linalg.norm(v), atol=1e-12 * r)
        assert np.linalg.norm(got) == pytest.approx(r, rel=1e-12)


@given(vec, vec, angle)
def test_rodrigues_equals_turn_about_any_axis(v, k, a):
    got = V.rodrigues(v, k / np.linalg.norm(k), a)
    np.testing.assert_allclose(got, V.turn(v, k, a, np.linalg.norm(v)), atol=1e-11 * np.linalg.norm(v))


@given(vec, vec)
def test_proj_and_norm_split_a_vector(v, v0):
    p, n = V.proj(v, v0), V.norm_part(v, v0)
    np.testing.assert_allclose(p + n, v, atol=1e-12)
    assert abs(np.dot(n, v0)) <= 1e-10 * np.linalg.norm(v) * np.linalg.norm(v0)
    assert np.linalg.norm(np.cross(p, v0)) <= 1e-10 * np.linalg.norm(v) * np.linalg.norm(v0)
    assert np.linalg.norm(V.ort(v)) == pytest.approx(1.0, rel=1e-14)


@given(angle, angle)
def test_e_z2_formula_is_the_matrix_product(g1, g2):
    """Eq. (8): e_Z2 = T_Y(γ1)·T_X(γ2)·e_Z = (sin γ1 cos γ2, −sin γ2, cos γ1 cos γ2); the frame is a rotation."""
    E = V.axis_frame(g1, g2)
    np.testing.assert_allclose(E @ EZ, V.e_z2(g1, g2), atol=1e-15)
    np.testing.assert_allclose(V.e_z2(g1, g2), [math.sin(g1) * math.cos(g2), -math.sin(g2),
                                                math.cos(g1) * math.cos(g2)], atol=1e-15)
    np.testing.assert_allclose(E @ E.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(E) == pytest.approx(1.0)
    # the angles back from the axis give the same axis
    b1, b2 = V.axis_angles(V.e_z2(g1, g2))
    np.testing.assert_allclose(V.e_z2(b1, b2), V.e_z2(g1, g2), atol=1e-12)


def test_axis_frame_of_the_planar_equivalent_check():
    """§9: γ1 = 90°, γ2 = 0 gives e_Z2 = e_X, e_X2 = (0, 0, −1), e_Y2 = (0, 1, 0)."""
    E = V.axis_frame(math.pi / 2, 0.0)
    np.testing.assert_allclose(E.T, [[0, 0, -1], [0, 1, 0], [1, 0, 0]], atol=1e-15)


def test_tcos_is_the_triangle_angle():
    """(23): the 3-4-5 triangle: the angle between sides 3 and 4 is 90°, between 3 and 5 acos(3/5)."""
    assert V.tcos(3.0, 4.0, 5.0) == pytest.approx(math.pi / 2)
    assert V.tcos(3.0, 5.0, 4.0) == pytest.approx(math.acos(3 / 5))
    assert np.isnan(V.tcos(1.0, 1.0, 3.0))      # no such triangle


def test_batched_primitives_equal_looped():
    rng = np.random.default_rng(3)
    v, k, a = rng.normal(size=(7, 3)), rng.normal(size=(7, 3)), rng.uniform(-4, 4, 7)
    batch = V.turn(v, k, a, 2.0)
    for i in range(7):
        np.testing.assert_allclose(batch[i], V.turn(v[i], k[i], a[i], 2.0), rtol=1e-15, atol=0)


# -- the robust unit-vector solver ---------------------------------------------------------------------
@st.composite
def solvable(draw):
    """V1, V2 and a unit p (on either side); the solver must recover p from the two angles."""
    v1, v2, p = draw(vec), draw(vec), draw(vec)
    p = p / np.linalg.norm(p)
    n = np.cross(v1, v2)
    if np.linalg.norm(n) < 1e-2 * np.linalg.norm(v1) * np.linalg.norm(v2) or abs(p @ n) < 1e-3 * np.linalg.norm(n):
        v2 = v2 + np.array([0.3, -0.7, 1.1]) * np.linalg.norm(v2)
        n = np.cross(v1, v2)
    return v1, v2, p


@settings(max_examples=200)
@given(solvable())
def test_unit_vector_solves_its_equations(case):
    v1, v2, p = case
    n = np.cross(v1, v2)
    if np.linalg.norm(n) < 1e-3 * np.linalg.norm(v1) * np.linalg.norm(v2) or abs(p @ n) < 1e-3 * np.linalg.norm(n):
        return
    c1 = p @ v1 / np.linalg.norm(v1)
    c2 = p @ v2 / np.linalg.norm(v2)
    s = int(np.sign(p @ n))
    got, status = V.unit_vector(v1, v2, c1, c2, s)
    assert status == V.OK
    np.testing.assert_allclose(got, p, atol=1e-8)
    assert V.branch_sign(v1, v2, got) == s
    # the other branch is the mirror image in the plane of V1 and V2
    other, _ = V.unit_vector(v1, v2, c1, c2, -s)
    m = n / np.linalg.norm(n)
    np.testing.assert_allclose(other, p - 2 * (p @ m) * m, atol=1e-8)


def test_unit_vector_with_v3x_zero_is_accurate_and_the_literal_form_reports_itself():
    """§7 item 1: V2 = e_X puts X in the plane of V1 and V2 (V3_X = 0). The robust solver is at
    round-off; the paper's literal form divides by V3_X = 0 and flags its singularity (NaN, not garbage)."""
    v1, v2 = np.array([0.0, -56.0, -48.0]), EX
    a1, a2 = 1.1, math.pi / 2
    p, status = V.unit_vector_angles(v1, v2, a1, a2, 1)
    assert status == V.OK
    assert np.linalg.norm(p) == pytest.approx(1.0, abs=1e-15)
    assert p @ v1 / np.linalg.norm(v1) == pytest.approx(math.cos(a1), abs=1e-15)
    assert abs(p @ v2) <= 1e-15
    lit, singular = V.unit_vector_literal(v1, v2, a1, a2, 1)
    assert singular and np.all(np.isnan(lit))


def test_literal_form_loses_accuracy_near_v3x_zero_while_the_robust_one_does_not():
    """§7 items 1–2: a rocker axis along Z with |P4_Y| < l1_2 (P4 = (50, 5, 10), crank 20, rocker 40,
    coupler 60): V3_X = 0 where P2_Y = P4_Y. Approaching that crank angle by Δ, the literal form's
    rocker-length error grows like 1/V3_X² (×1e4 per ×1e-2 in Δ) and reaches millimetres within 1e-8 rad
    (about a microdegree); the robust form stays at round-off. The literal form flags
    |V3_X| < 1e-3·|V3| itself."""
    P4, lr, lc = np.array([50.0, 5.0, 10.0]), 40.0, 60.0
    f0 = math.acos(5 / 20)
    lit_err, rob_err = [], []
    for df in (1e-2, 1e-4, 1e-6, 1e-8):
        f = f0 + df
        P2 = np.array([0.0, 20 * math.cos(f), 20 * math.sin(f)])
        v1 = P2 - P4
        d = np.linalg.norm(v1)
        a1 = math.acos((d * d + lr * lr - lc * lc) / (2 * d * lr))
        rob, status = V.unit_vector_angles(v1, EZ, a1, math.pi / 2, 1)
        lit, _ = V.unit_vector_literal(v1, EZ, a1, math.pi / 2, V.paper_w(v1, EZ, 1), singular_tol=0.0)
        assert status == V.OK
        rob_err.append(abs(np.linalg.norm(P4 + lr * rob - P2) - lc))
        lit_err.append(abs(np.linalg.norm(P4 + lr * lit - P2) - lc))
        flagged = V.unit_vector_literal(v1, EZ, a1, math.pi / 2, 1)[1]
        v3 = np.cross(v1, EZ)
        assert flagged == (abs(v3[0]) < 1e-3 * np.linalg.norm(v3))
    assert max(rob_err) < 1e-12
    assert lit_err[-1] > 0.1                                  # > 0.1 mm at Δ = 1e-8 rad
    growth = np.array(lit_err[1:]) / np.array(lit_err[:-1])
    assert np.all(growth > 1e3)                                # ~1/V3_X²: ×1e4 per step of ×1e-2


def test_negative_discriminant_cannot_assemble():
    """§7 item 5: angles that no unit vector can meet: NaN and CANNOT_ASSEMBLE, never complex or finite garbage."""
    p, status = V.unit_vector_angles(EX, EY, 0.1, 0.1, 1)    # 5.7° from both X and Y: impossible
    assert status == V.CANNOT_ASSEMBLE and np.all(np.isnan(p))


def test_parallel_vectors_are_undetermined():
    """§7 item 7: V1 ∥ V2 leaves p undetermined."""
    p, status = V.unit_vector_angles(np.array([1.0, 2, 3]), np.array([-2.0, -4, -6]), 1.0, 2.0, 1)
    assert status == V.UNDETERMINED and np.all(np.isnan(p))


def test_right_angles_give_the_normal():
    """§3.2: a1 = a2 = 90° gives p = s·Ort(V1 × V2)."""
    v1, v2 = np.array([1.0, 2, 0.5]), np.array([-0.3, 0.2, 2.0])
    n = np.cross(v1, v2)
    for s in (1, -1):
        p, _ = V.unit_vector(v1, v2, 0.0, 0.0, s)
        np.testing.assert_allclose(p, s * n / np.linalg.norm(n), atol=1e-15)


def test_a_branch_point_is_clamped_not_rejected():
    """disc within −1e-12 of 0 is a branch point (§9 thresholds): valid, p in the plane of V1, V2."""
    p, status = V.unit_vector(EX, EY, math.cos(math.pi / 4), math.cos(math.pi / 4), 1)
    assert status == V.BRANCH_POINT and V.assembled(status)
    np.testing.assert_allclose(p, [math.sqrt(0.5), math.sqrt(0.5), 0.0], atol=1e-8)


@settings(max_examples=100)
@given(solvable())
def test_literal_and_robust_agree_where_the_literal_one_is_regular(case):
    """§3.2: wherever the literal form is not singular the two agree to round-off, with W = s·sign(V3_X)."""
    v1, v2, p = case
    n = np.cross(v1, v2)
    if abs(n[0]) < 0.05 * np.linalg.norm(n) or abs(p @ n) < 1e-3 * np.linalg.norm(n):
        return
    a1 = math.acos(np.clip(p @ v1 / np.linalg.norm(v1), -1, 1))
    a2 = math.acos(np.clip(p @ v2 / np.linalg.norm(v2), -1, 1))
    for s in (1, -1):
        rob, status = V.unit_vector_angles(v1, v2, a1, a2, s)
        w = V.paper_w(v1, v2, s)
        lit, singular = V.unit_vector_literal(v1, v2, a1, a2, w)
        assert status == V.OK and not singular
        np.testing.assert_allclose(lit, rob, atol=1e-7)


def test_no_branch_jump_over_a_turn_where_v3x_changes_sign():
    """§7 items 1 and 3: a rocker axis along Z with |P4_Y| < l1_2: V3_X = P2_Y − P4_Y changes sign twice per
    turn. The robust solver with a fixed s moves continuously; the literal form with a fixed W jumps to
    the other assembly where V3_X changes sign."""
    f = np.linspace(0, 2 * math.pi, 3601)
    P2 = np.stack([np.zeros_like(f), 20 * np.cos(f), 20 * np.sin(f)], -1)
    P4 = np.array([50.0, 5.0, 10.0])
    lr, lc = 40.0, 60.0
    v1 = P2 - P4
    d = np.linalg.norm(v1, axis=-1)
    c1 = (d * d + lr * lr - lc * lc) / (2 * d * lr)
    v3x = np.cross(v1, EZ)[:, 0]
    assert v3x.min() < 0 < v3x.max()
    p, status = V.unit_vector(v1, np.broadcast_to(EZ, v1.shape), c1, 0.0, 1)
    assert np.all(status == V.OK)
    step = np.linalg.norm(np.diff(p, axis=0), axis=-1)
    assert step.max() < 5 * np.median(step) + 1e-12           # smooth: no jump
    assert np.all(V.branch_sign(v1, EZ, p) == 1)
    lit, singular = V.unit_vector_literal(v1, np.broadcast_to(EZ, v1.shape), np.arccos(c1), math.pi / 2, 1)
    ok = ~singular
    mirror = np.linalg.norm(lit[ok] - p[ok], axis=-1) > 1e-6
    assert mirror.any() and not mirror.all()                   # a fixed W is the other assembly part of the turn
    np.testing.assert_array_equal(mirror, np.sign(v3x[ok]) != 1)


def test_unit_vector_derivatives_are_exact():
    """Jets through the solver: first and second derivatives against central differences."""
    def inputs(t):
        v1 = np.array([1.0 + 0.3 * t, 2.0 - t * t, 0.5 + np.sin(t)])
        v2 = np.array([-0.3 + t, 0.2, 2.0 + 0.1 * t])
        return v1, v2, 0.2 + 0.1 * t, 0.1 - 0.05 * t * t

    t0, h = 0.3, 1e-4
    v1, v2, c1, c2 = inputs(t0)
    J = Jet(np.array(t0), np.array(1.0), np.array(0.0))
    jv1 = Jet(v1, np.array([0.3, -2 * t0, np.cos(t0)]), np.array([0.0, -2.0, -np.sin(t0)]))
    jv2 = Jet(v2, np.array([1.0, 0.0, 0.1]), np.zeros(3))
    jc1 = 0.2 + 0.1 * J
    jc2 = 0.1 - 0.05 * (J * J)
    p, _ = V.unit_vector(jv1, jv2, jc1, jc2, 1)
    f = [V.unit_vector(*inputs(t0 + k * h), 1)[0] for k in (-1, 0, 1)]
    np.testing.assert_allclose(p.v, f[1], atol=1e-15)
    np.testing.assert_allclose(p.d, (f[2] - f[0]) / (2 * h), atol=1e-7)
    np.testing.assert_allclose(p.dd, (f[2] - 2 * f[1] + f[0]) / h ** 2, atol=1e-5)


def test_newton_rss_recovers_the_closed_form():
    A, D, e = np.array([0.0, 20, 0]), np.array([0.0, 36, 48]), EX
    p, _ = V.unit_vector(A - D, e, ((A - D) @ (A - D) + 50 ** 2 - 70 ** 2) / (2 * 50 * np.linalg.norm(A - D)), 0.0, 1)
    B = D + 50 * p
    x, ok = V.newton_rss(A, D, e, 50.0, 0.0, 70.0, B + np.array([1.0, -2.0, 1.5]), tol=1e-10)
    assert ok
    np.testing.assert_allclose(x, B, atol=1e-10)


def test_atan2_of_jets_has_the_derivatives_of_the_angle():
    """θ(s) = atan2(y(s), x(s)) for y = 1 + 2s − s², x = 3 − s + 0.5s² at s = 0.3: the jet's first and second
    derivatives against central differences of θ computed with math.atan2 (h = 1e-4: O(h²) ≈ 1e-8 error)."""
    s, h = 0.3, 1e-4
    y = lambda t: 1 + 2 * t - t * t            # noqa: E731
    x = lambda t: 3 - t + 0.5 * t * t          # noqa: E731
    theta = lambda t: math.atan2(y(t), x(t))   # noqa: E731
    jet = V.atan2(Jet(np.array(y(s)), np.array(2 - 2 * s), np.array(-2.0)),
                  Jet(np.array(x(s)), np.array(-1 + s), np.array(1.0)))
    assert float(jet.v) == pytest.approx(theta(s), abs=1e-15)
    assert float(jet.d) == pytest.approx((theta(s + h) - theta(s - h)) / (2 * h), abs=1e-7)
    assert float(jet.dd) == pytest.approx((theta(s + h) - 2 * theta(s) + theta(s - h)) / h ** 2, abs=1e-5)
