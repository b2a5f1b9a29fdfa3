"""Paper 003 (Dvorzhak, spatial RSSR crank–rocker by the vector method): the sharp check P003-2 of
docs/papers/003.md §9 (the planar-equivalent RSSR against Freudenstein's closed form and the exact values
given there), the constraints of §4 at every sample, the coupler frame (27)–(30), the branch and
the paper's W (§5, §7), and random valid RSSRs keeping their link lengths over a full turn.

The paper prints no numerical results (docs/papers/003.md); every expected value below is an exact
closed form from §9 or an identity computed in the test. Section numbers are those of docs/papers/003.md."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import assur
from assur.analysis.spatial import distance_extremes, dyad_summaries, dyads, mu_int, mu_t, rocker_angle
from assur.kernels import spatial as V

ROOT = Path(__file__).resolve().parents[1]
MM = 1e-3


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(ROOT / "examples" / "rssr.toml"))


@pytest.fixture(scope="module")
def tilted():
    return assur.compile(assur.load(ROOT / "examples" / "rssr_tilted.toml"))


def freudenstein_p3(f1):
    """§9: P3 of the planar crank–rocker a = 20, b = 70, c = 50, d = 60 in (Y, Z) coordinates (mm)."""
    a, b, c, d = 20.0, 70.0, 50.0, 60.0
    g = math.atan2(48, 36)
    t2 = f1 - g
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    A = np.cos(t2) - K1 - K2 * np.cos(t2) + K3
    B = -2 * np.sin(t2)
    C = K1 - (K2 + 1) * np.cos(t2) + K3
    theta = 2 * np.arctan2(-B - np.sqrt(B * B - 4 * A * C), 2 * A)
    return np.stack([np.zeros_like(f1), 36 + 50 * np.cos(theta + g), 48 + 50 * np.sin(theta + g)], -1)


def test_p003_2_matches_freudenstein_at_every_crank_angle(plan):
    f1 = np.linspace(0, 2 * math.pi, 1441)
    s = assur.solve(plan, None, f1, order=0)
    assert s.valid.all()
    P3 = s.pos[:, plan.point_index("P3")] / MM
    np.testing.assert_allclose(P3, freudenstein_p3(f1), rtol=0, atol=1e-9)
    P2 = s.pos[:, plan.point_index("P2")] / MM
    np.testing.assert_allclose(P2, 20 * np.stack([0 * f1, np.cos(f1), np.sin(f1)], -1), rtol=0, atol=1e-9)


def test_p003_2_exact_positions(plan):
    """§9: f1 = 180° → P3 = (0, −158/17, 1176/17); folded dead centre f1 = atan2(4,3) + acos(3/5) + 180°
    → P2 = (0, 5.6, −19.2), P3 = (0, −14, 48), θ4 = −90°; extended f1 = atan2(4,3) + acos(23/27) → |P1P3| = 90."""
    folded = math.atan2(4, 3) + math.acos(3 / 5) + math.pi
    extended = math.atan2(4, 3) + math.acos(23 / 27)
    s = assur.solve(plan, None, [math.pi, folded, extended], order=0)
    pos = s.pos / MM
    i2, i3 = plan.point_index("P2"), plan.point_index("P3")
    np.testing.assert_allclose(pos[0, i3], [0, -158 / 17, 1176 / 17], atol=1e-9)
    np.testing.assert_allclose(pos[0, i2], [0, -20, 0], atol=1e-9)
    np.testing.assert_allclose(pos[1, i2], [0, 5.6, -19.2], atol=1e-9)
    np.testing.assert_allclose(pos[1, i3], [0, -14, 48], atol=1e-9)
    assert np.linalg.norm(pos[1, i3]) == pytest.approx(50, abs=1e-9)      # 70 − 20
    assert np.linalg.norm(pos[2, i3]) == pytest.approx(90, abs=1e-9)      # 20 + 70
    th = np.degrees(rocker_angle(dyads(plan, s)[0]))
    assert th[1] == pytest.approx(-90, abs=1e-7)
    swing = math.degrees(math.acos(-1 / 3) - math.acos(3 / 5))
    assert th[2] == pytest.approx(-90 - swing, abs=1e-7)


def test_p003_2_dead_centres_swing_and_transmission(plan):
    """§9: dead centres root-solved to 1e-6°, swing acos(−1/3) − acos(3/5) = 56.3411183°,
    θ4 ∈ [−146.3411183°, −90°], μ_int ∈ [acos(29/35), acos(1/7)] at f1 = atan2(4, 3) and +180°, μ_T = μ_int here."""
    (s,) = dyad_summaries(plan, steps=720)
    assert s.branch_s == 1
    dc = {c.kind: c for c in s.dead_centres}
    assert set(dc) == {"extended", "folded"}
    assert math.degrees(dc["folded"].angle) == pytest.approx(math.degrees(math.atan2(4, 3) + math.acos(3 / 5)) + 180,
                                                             abs=1e-6)
    assert math.degrees(dc["extended"].angle) == pytest.approx(math.degrees(math.atan2(4, 3) + math.acos(23 / 27)),
                                                               abs=1e-6)
    swing = math.acos(-1 / 3) - math.acos(3 / 5)
    assert math.degrees(s.swing) == pytest.approx(math.degrees(swing), abs=1e-7)
    assert math.degrees(s.rocker_angle_min) == pytest.approx(-90 - math.degrees(swing), abs=1e-7)
    assert math.degrees(s.rocker_angle_max) == pytest.approx(-90, abs=1e-7)
    ext = distance_extremes(plan)
    assert ext["q_min"] == pytest.approx(math.atan2(4, 3), abs=1e-12)
    assert ext["q_max"] == pytest.approx(math.atan2(4, 3) + math.pi, abs=1e-12)
    assert ext["d_min"] / MM == pytest.approx(40, abs=1e-9) and ext["d_max"] / MM == pytest.approx(80, abs=1e-9)
    assert ext["mu_int_at_d_min"] == pytest.approx(math.acos(29 / 35), abs=1e-12)
    assert ext["mu_int_at_d_max"] == pytest.approx(math.acos(1 / 7), abs=1e-12)
    # the same extremes from the solved positions at the closed-form angles (not from a grid)
    st_ = assur.solve(plan, None, [ext["q_min"], ext["q_max"]], order=0)
    g = dyads(plan, st_)[0]
    np.testing.assert_allclose(np.degrees(mu_int(g)), np.degrees([math.acos(29 / 35), math.acos(1 / 7)]), atol=1e-7)
    np.testing.assert_allclose(np.degrees(mu_t(g)), np.degrees(mu_int(g)), atol=1e-7)
    q = np.linspace(0, 2 * math.pi, 721)
    g = dyads(plan, assur.solve(plan, None, q, order=0))[0]
    np.testing.assert_allclose(mu_t(g), np.minimum(mu_int(g), math.pi - mu_int(g)), atol=1e-9)


def _constraints(plan, s, params=None):
    """Residuals (relative to the link lengths) of the constraints of §4 at every sample."""
    params = plan.defaults if params is None else params
    g = dyads(plan, s, params)[0]
    crank_len = params[..., plan.param_index("crank.length")]
    h = params[..., plan.param_index("rocker.axial")]
    P1 = s.pos[..., plan.point_index("P1"), :]
    e = g.axis_frame[..., :, 2]
    return (np.linalg.norm(g.A - P1, axis=-1) / crank_len - 1,
            np.linalg.norm(g.B - g.A, axis=-1) / g.coupler_length - 1,
            np.linalg.norm(g.B - g.D, axis=-1) / g.rocker_length - 1,
            (np.sum((g.B - g.D) * e, -1) - h) / g.rocker_length)


@pytest.mark.parametrize("name", ["plan", "tilted"])
def test_constraints_hold_at_every_sample(name, request):
    plan = request.getfixturevalue(name)
    s = assur.solve(plan, None, np.linspace(0, 2 * math.pi, 2881), order=0)
    assert s.valid.all()
    for r in _constraints(plan, s):
        assert np.max(np.abs(r)) < 1e-12


@pytest.mark.parametrize("name", ["plan", "tilted"])
def test_coupler_frame_is_right_handed_and_follows_27_to_30(name, request):
    """(27)–(30): e_x2 = Ort(P2 − P3), e_z2 = +Ort(e_p1 × e_x2) (Wp = +1; pin e_p1 = −e_X, fixed in the
    crank and parallel to its axis), e_y2 = e_z2 × e_x2; orthonormal with det = +1 at every sample."""
    plan = request.getfixturevalue(name)
    s = assur.solve(plan, None, np.linspace(0, 2 * math.pi, 361), order=0)
    R = s.body_frame[:, s.body("coupler")]
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape), atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-14)
    P2, P3 = s.pos[:, plan.point_index("P2")], s.pos[:, plan.point_index("P3")]
    ex = (P2 - P3) / np.linalg.norm(P2 - P3, axis=-1, keepdims=True)
    np.testing.assert_allclose(R[..., 0], ex, atol=1e-14)
    n = np.cross(np.array([-1.0, 0, 0]), ex)
    np.testing.assert_allclose(R[..., 2], n / np.linalg.norm(n, axis=-1, keepdims=True), atol=1e-14)
    # the tool point keeps its local coordinates (u, v, w) in that frame
    C = s.pos[:, plan.point_index("C")]
    local = np.einsum("nij,ni->nj", R, C - P2)
    np.testing.assert_allclose(local, np.broadcast_to(local[0], local.shape), atol=1e-15)


def test_paper_literal_solver_is_singular_for_p003_2_and_for_the_typical_pin(plan):
    """Erratum F1 (§7 item 1): with the rocker axis parallel to X, V3_X ≡ 0 and the literal p(·) is
    singular at every crank angle; the typical pin e_p1 = −e_X makes (29) singular for every coupler
    direction. The literal solver reports it (NaN) instead of returning garbage."""
    s = assur.solve(plan, None, np.linspace(0, 2 * math.pi, 73), order=0)
    g = dyads(plan, s)[0]
    v1 = g.A - g.D
    e = np.broadcast_to(g.axis_frame[..., :, 2], v1.shape)
    d = np.linalg.norm(v1, axis=-1)
    a1 = V.tcos(d, g.rocker_length, g.coupler_length)
    lit, singular = V.unit_vector_literal(v1, e, a1, math.pi / 2, -1)
    assert singular.all() and np.isnan(lit).all()
    ex = s.body_frame[:, s.body("coupler"), :, 0]
    pin = np.broadcast_to([-1.0, 0.0, 0.0], ex.shape)
    lit, singular = V.unit_vector_literal(pin, ex, math.pi / 2, math.pi / 2, 1)
    assert singular.all() and np.isnan(lit).all()
    # the robust solver gives the frame's e_z2 there
    robust, status = V.unit_vector_angles(pin, ex, math.pi / 2, math.pi / 2, 1)
    assert (status == V.OK).all()
    np.testing.assert_allclose(robust, s.body_frame[:, s.body("coupler"), :, 2], atol=1e-14)


def test_branch_sign_and_the_papers_w(plan, tilted):
    """§5: s is constant over a crank–rocker's turn; W = s·sign(V3_X) is undefined for P003-2 (V3_X ≡ 0
    to round-off) and −1 for the tilted layout. The paper's verbal rule ("P2 → P3 → P4 clockwise seen from
    +X ⇒ W = +1") gives +1 for P003-2 at every angle, which there equals s (§9)."""
    (s,) = dyad_summaries(plan)
    assert s.branch_s == 1 and s.paper_w == []
    (t,) = dyad_summaries(tilted)
    assert t.branch_s == 1 and t.paper_w == [-1.0] and not t.v3x_changes_sign
    st_ = assur.solve(plan, None, np.linspace(0, 2 * math.pi, 361), order=0)
    g = dyads(plan, st_)[0]
    assert np.all(V.branch_sign(g.A - g.D, g.axis_frame[..., :, 2], g.B - g.D) == 1)
    a, b = (g.B - g.A)[:, 1:], (g.D - g.B)[:, 1:]
    ccw = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    assert np.all(ccw < 0)            # clockwise seen from +X: the rule's W = +1 = s


def test_with_branch_accepts_s_and_converts_w(plan, tilted):
    other = tilted.with_branch("P3", s=-1)
    assert other.rss_steps()[0].branch == -1
    # W is converted by s = W·sign(V3_X), V3 = (P2 − P4) × e_Z2 at the sketch input
    A, D = (np.array(tilted.mechanism.sketch(p)) for p in ("P2", "P4"))
    e = V.axis_frame(*(tilted.defaults[tilted.param_index(f"P4.axis.gamma{i}")] for i in (1, 2)))[:, 2]
    for w in (1, -1):
        assert tilted.with_branch("P3", w=w).rss_steps()[0].branch == w * int(np.sign(np.cross(A - D, e)[0]))
    # the file's assembly (s = +1) is W = −1 (dyad_summaries above)
    assert tilted.with_branch("P3", w=-1).rss_steps()[0].branch == 1
    with pytest.raises(assur.SpecError, match="W is undefined"):
        plan.with_branch("P3", w=1)
    with pytest.raises(assur.SpecError, match="not solved by an R–S–S dyad"):
        plan.with_branch("C", s=1)
    s1 = assur.solve(tilted, None, [0.3], order=0).pos
    s2 = assur.solve(other, None, [0.3], order=0).pos
    g1 = dyads(tilted, assur.solve(tilted, None, [0.3], order=0))[0]
    # the other branch is the mirror image of P3 in the plane through the rocker axis and P2
    n = np.cross(g1.A[0] - g1.D[0], g1.axis_frame[:, 2])
    n /= np.linalg.norm(n)
    r = s1[0, 3] - g1.D[0]
    np.testing.assert_allclose(s2[0, 3] - g1.D[0], r - 2 * (r @ n) * n, atol=1e-15)


DESIGN = st.fixed_dictionaries({
    "P4__x": st.floats(-0.06, 0.06), "P4__y": st.floats(-0.06, 0.06), "P4__z": st.floats(-0.06, 0.06),
    "P4__axis__gamma1": st.floats(0, 2 * math.pi), "P4__axis__gamma2": st.floats(-1.5, 1.5),
    "crank__length": st.floats(0.01, 0.025), "rocker__length": st.floats(0.03, 0.06),
    "coupler__length": st.floats(0.05, 0.09), "rocker__axial": st.floats(-0.005, 0.005)})


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(DESIGN)
def test_random_valid_rssrs_keep_their_link_lengths_over_a_full_turn(tilted, design):
    """§10 / the issue's "done when": link lengths constant to 1e-9 relative over a full turn for random valid
    RSSRs (any rocker axis, rocker arm not necessarily perpendicular), and the branch s never changes."""
    p = tilted.params_with(**design)
    q = np.linspace(0, 2 * math.pi, 721)
    s = assur.solve(tilted, p, q, order=0)
    assume(s.valid.all())
    for r in _constraints(tilted, s, p):
        assert np.max(np.abs(r)) < 1e-9
    g = dyads(tilted, s, p)[0]
    assert np.all(V.branch_sign(g.A - g.D, g.axis_frame[..., :, 2], g.B - g.D) == tilted.rss_steps()[0].branch)
