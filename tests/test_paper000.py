"""Paper 000 (crank-slider walking leg): the general solver against the closed forms of docs/papers/000.md.

References (§N, EN) are sections of docs/papers/000.md, and equation numbers are the paper's; values
without a citation are computed independently in the test.
The mechanism file keeps the paper's frame (x left, y down, numbers as (x, y)) and its input q is
the paper's crank angle φ (zero = 90°, sense = cw: C = (l5 sin φ, l5 cos φ), §2).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import assur

FILE = Path(__file__).resolve().parent.parent / "examples" / "walker_crank_slider.toml"

# printed design, §4 ("l1 = 165 mm, l2 = 193 mm, l5 = 175 mm"), read by eq. (4) (§2, erratum E1)
L1, L2, L5 = 0.165, 0.193, 0.175
OMEGA = 1.0  # rad/s, §1 (the paper uses ω = 1 rad/s)
PHI = np.linspace(0.0, 2.0 * math.pi, 3601)
#: the five contact target angles, §4 table (φ_i = 90, 135, 180, 225, 270°)
CONTACT_DEG = np.array([90.0, 135.0, 180.0, 225.0, 270.0])


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(FILE))


def _idx(plan, name):
    return plan.point_index(name)


def _params(plan, l1=L1, l2=L2, l5=L5):
    return plan.params_with(rod__A__distance=l1, rod__length=l2, crank__length=l5)


# -- eq. (4) and its derivatives, §3 -----------------------------------------------------------

def eq4(phi, l1=L1, l2=L2, l5=L5):
    """x_A, y_A of eq. (4) (§3)."""
    s = np.sqrt(l2 ** 2 - l5 ** 2 * np.sin(phi) ** 2)
    return -(l1 / l2) * l5 * np.sin(phi), l5 * np.cos(phi) + (1.0 + l1 / l2) * s


def eq4_d1(phi, l1=L1, l2=L2, l5=L5):
    """dx_A/dφ, dy_A/dφ (§3)."""
    k, d = 1.0 + l1 / l2, l1 * l5 / l2
    s = np.sqrt(l2 ** 2 - l5 ** 2 * np.sin(phi) ** 2)
    return -d * np.cos(phi), -l5 * np.sin(phi) - k * l5 ** 2 * np.sin(phi) * np.cos(phi) / s


def eq4_d2(phi, l1=L1, l2=L2, l5=L5):
    """d²x_A/dφ² = d sin φ (§3); d²y_A/dφ² differentiated here by hand:
    s = sqrt(l2² − l5² sin² φ), s' = −l5² sin φ cos φ / s, s'' = −l5² cos 2φ / s − l5⁴ sin² φ cos² φ / s³,
    y'' = −l5 cos φ + k s''."""
    k, d = 1.0 + l1 / l2, l1 * l5 / l2
    sn, cs = np.sin(phi), np.cos(phi)
    s = np.sqrt(l2 ** 2 - l5 ** 2 * sn ** 2)
    s2 = -l5 ** 2 * np.cos(2 * phi) / s - l5 ** 4 * sn ** 2 * cs ** 2 / s ** 3
    return d * sn, -l5 * cs + k * s2


def test_file_holds_the_printed_design(plan):
    p = plan.defaults
    assert p[plan.param_index("crank.length")] == pytest.approx(L5, abs=1e-15)
    assert p[plan.param_index("rod.length")] == pytest.approx(L2, abs=1e-15)
    assert p[plan.param_index("rod.A.distance")] == pytest.approx(L1, abs=1e-15)
    assert plan.speeds[0] == pytest.approx(OMEGA)
    assert plan.structure.mobility == 1                       # §2: W = 3·3 − 2·4 = 1
    assert plan.structure.n_moving == 3 and plan.structure.pair_counts["p5"] == 4
    assert [g.kind.value for g in plan.structure.groups] == ["RRP"]   # crank → RRP dyad (§2)


def test_input_is_the_paper_crank_angle(plan):
    """C = (l5 sin φ, l5 cos φ) (§2): the file's input q is φ."""
    st = assur.solve(plan, inputs=PHI)
    C = st.pos[:, _idx(plan, "C")]
    np.testing.assert_allclose(C[:, 0], L5 * np.sin(PHI), rtol=0, atol=1e-15)
    np.testing.assert_allclose(C[:, 1], L5 * np.cos(PHI), rtol=0, atol=1e-15)


def test_solver_equals_eq4(plan):
    st = assur.solve(plan, inputs=PHI)
    assert st.valid.all()
    A = st.pos[:, _idx(plan, "A")]
    xa, ya = eq4(PHI)
    np.testing.assert_allclose(A[:, 0], xa, rtol=0, atol=1e-15)
    np.testing.assert_allclose(A[:, 1], ya, rtol=0, atol=1e-15)
    # B on the y axis at y_B = l5 cos φ + sqrt(l2² − l5² sin² φ), on the far side of C (§2)
    B = st.pos[:, _idx(plan, "B")]
    np.testing.assert_allclose(B[:, 0], 0.0, atol=1e-15)
    np.testing.assert_allclose(B[:, 1], L5 * np.cos(PHI) + np.sqrt(L2 ** 2 - L5 ** 2 * np.sin(PHI) ** 2), atol=1e-15)


def test_solver_equals_eq4_for_other_designs(plan):
    """Eq. (4) holds for any dimensions with l2 > l5 (§3): a batch of designs × angles."""
    rng = np.random.default_rng(4)
    l5 = rng.uniform(0.05, 0.3, 40)
    l2 = l5 * rng.uniform(1.05, 3.0, 40)
    l1 = rng.uniform(0.02, 0.4, 40)
    P = np.broadcast_to(plan.defaults, (40, plan.n_params)).copy()
    P[:, plan.param_index("crank.length")] = l5
    P[:, plan.param_index("rod.length")] = l2
    P[:, plan.param_index("rod.A.distance")] = l1
    phi = np.linspace(0, 2 * math.pi, 361)
    st = assur.solve(plan, P[:, None, :], phi)
    assert st.valid.all()
    xa, ya = eq4(phi[None, :], l1[:, None], l2[:, None], l5[:, None])
    A = st.pos[..., _idx(plan, "A"), :]
    np.testing.assert_allclose(A[..., 0], xa, atol=1e-14)
    np.testing.assert_allclose(A[..., 1], ya, atol=1e-14)


def test_analogues_equal_the_analytic_derivatives(plan):
    st = assur.solve(plan, inputs=PHI)
    a = _idx(plan, "A")
    d1 = st.dpos_dq[:, a, :, 0]
    d2 = st.d2pos_dq2[:, a, :, 0, 0]
    dx, dy = eq4_d1(PHI)
    ddx, ddy = eq4_d2(PHI)
    np.testing.assert_allclose(d1[:, 0], dx, atol=1e-14)
    np.testing.assert_allclose(d1[:, 1], dy, atol=1e-14)
    np.testing.assert_allclose(d2[:, 0], ddx, atol=1e-14)
    np.testing.assert_allclose(d2[:, 1], ddy, atol=1e-14)
    # time derivatives at ω (§3: V_Ax = ω dx_A/dφ, a_Ax = ω² d²x_A/dφ²)
    np.testing.assert_allclose(st.vel[:, a], OMEGA * d1, atol=1e-15)
    np.testing.assert_allclose(st.acc[:, a], OMEGA ** 2 * d2, atol=1e-15)


def test_analogues_against_central_differences(plan):
    h = 1e-4
    phi = np.linspace(0, 2 * math.pi, 181)
    st = assur.solve(plan, inputs=phi)
    sp, sm = assur.solve(plan, inputs=phi + h, order=0), assur.solve(plan, inputs=phi - h, order=0)
    fd1 = (sp.pos - sm.pos) / (2 * h)
    fd2 = (sp.pos - 2 * st.pos + sm.pos) / h ** 2
    np.testing.assert_allclose(st.dpos_dq[..., 0], fd1, atol=1e-8)
    np.testing.assert_allclose(st.d2pos_dq2[..., 0, 0], fd2, atol=1e-6)


def test_velocity_and_acceleration_amplitudes(plan):
    """V_Ax amplitude d·ω and a_Ax amplitude d·ω², d = l1 l5 / l2 (§3, §7)."""
    st = assur.solve(plan, inputs=PHI)
    a = _idx(plan, "A")
    d = L1 * L5 / L2
    assert np.max(np.abs(st.vel[:, a, 0])) == pytest.approx(d * OMEGA, rel=1e-12)
    assert np.max(np.abs(st.acc[:, a, 0])) == pytest.approx(d * OMEGA ** 2, rel=1e-12)
    # x_A is a pure sinusoid: extremes −d at 90°, +d at 270° (§3); step = 2d (§6)
    s = assur.solve(plan, inputs=np.radians([90.0, 270.0])).pos[:, a, 0]
    np.testing.assert_allclose(s, [-d, d], atol=1e-15)
    assert np.ptp(st.pos[:, a, 0]) == pytest.approx(2 * d, rel=1e-12)


def test_apex_and_bottom_dead_centre(plan):
    """y_A(0) = l1 + l2 + l5 and y_A(180°) = l1 + l2 − l5 (§3)."""
    st = assur.solve(plan, inputs=np.array([0.0, math.pi, 2 * math.pi]))
    y = st.pos[:, _idx(plan, "A"), 1]
    np.testing.assert_allclose(y, [L1 + L2 + L5, L1 + L2 - L5, L1 + L2 + L5], atol=1e-15)
    assert np.max(assur.solve(plan, inputs=PHI).pos[:, _idx(plan, "A"), 1]) == pytest.approx(L1 + L2 + L5, abs=1e-15)


def test_slider_stroke(plan):
    """y_B runs from l2 − l5 (φ = 180°) to l2 + l5 (φ = 0): stroke 2·l5 (§2, relations (1)–(2))."""
    st = assur.solve(plan, inputs=PHI)
    yb = st.pos[:, _idx(plan, "B"), 1]
    assert yb.max() == pytest.approx(L2 + L5, abs=1e-15)
    assert yb.min() == pytest.approx(L2 - L5, abs=1e-15)
    assert np.ptp(yb) == pytest.approx(2 * L5, abs=1e-15)


def test_interior_minimum(plan):
    """cos φ* = −sqrt((l2² − l5²)/(l5²(k² − 1))), y_A(φ*) = sqrt((k² − 1)(l2² − l5²)) (§3, E4)."""
    k = 1.0 + L1 / L2
    assert (L2 ** 2 - L5 ** 2) <= L5 ** 2 * (k ** 2 - 1)          # the interior minimum exists (§3)
    c = -math.sqrt((L2 ** 2 - L5 ** 2) / (L5 ** 2 * (k ** 2 - 1)))
    phis = np.array([math.acos(c), 2 * math.pi - math.acos(c)])     # in 90…270°, symmetric about 180°
    assert np.all((phis > math.pi / 2) & (phis < 3 * math.pi / 2))
    ymin = math.sqrt((k ** 2 - 1) * (L2 ** 2 - L5 ** 2))
    st = assur.solve(plan, inputs=phis)
    a = _idx(plan, "A")
    np.testing.assert_allclose(st.pos[:, a, 1], ymin, atol=1e-15)
    np.testing.assert_allclose(st.dpos_dq[:, a, 1, 0], 0.0, atol=1e-14)   # a stationary point
    assert np.all(st.d2pos_dq2[:, a, 1, 0, 0] > 0)                        # a minimum
    dense = assur.solve(plan, inputs=np.linspace(0, 2 * math.pi, 100001), order=0).pos[:, a, 1]
    assert dense.min() >= ymin - 1e-15 and dense.min() == pytest.approx(ymin, abs=1e-9)   # the path minimum
    # closer to K than y(90°) = k·sqrt(l2² − l5²) (§6), so the continuous sag exceeds the 5-point sag (E4)
    assert ymin < k * math.sqrt(L2 ** 2 - L5 ** 2)


def test_swapping_l1_and_l5_leaves_x_unchanged(plan):
    """d = l1 l5 / l2 is symmetric, so x_A, V_Ax and a_Ax are unchanged by l1 ↔ l5 (§3)."""
    assert {"crank.length", "rod.A.distance", "rod.length"} <= set(plan.param_names)
    a = _idx(plan, "A")
    st = assur.solve(plan, _params(plan), PHI)
    sw = assur.solve(plan, plan.params_with(crank__length=L1, rod__A__distance=L5), PHI)
    assert sw.valid.all()
    np.testing.assert_allclose(sw.pos[:, a, 0], st.pos[:, a, 0], atol=1e-15)
    np.testing.assert_allclose(sw.vel[:, a, 0], st.vel[:, a, 0], atol=1e-15)
    np.testing.assert_allclose(sw.acc[:, a, 0], st.acc[:, a, 0], atol=1e-15)
    # … but not the vertical coordinate (it does depend on the naming, E1)
    assert np.max(np.abs(sw.pos[:, a, 1] - st.pos[:, a, 1])) > 1e-3
    np.testing.assert_allclose(sw.pos[:, a, 1], eq4(PHI, l1=L5, l5=L1)[1], atol=1e-15)


def test_delta2_at_the_five_contact_angles(plan):
    """Δ2 = Σ (∂²x_A/∂φ²)² over 90…270° = 3·(l1 l5 / l2)² (§5, eq. 6), from d2pos_dq2."""
    st = assur.solve(plan, inputs=np.radians(CONTACT_DEG))
    d2x = st.d2pos_dq2[:, _idx(plan, "A"), 0, 0, 0]
    assert np.sum(d2x ** 2) == pytest.approx(3 * (L1 * L5 / L2) ** 2, rel=1e-12)
    step = 2 * L1 * L5 / L2
    assert np.sum(d2x ** 2) == pytest.approx(0.75 * step ** 2, rel=1e-12)   # = (3/4)·step² (§5)


def test_sixth_target_distance(plan):
    """The 6th target (φ = 360°, x = 0, y = 530 mm; §4) is at |l1 + l2 + l5 − 530 mm| for any design."""
    target = np.array([0.0, 0.530])
    a = _idx(plan, "A")
    st = assur.solve(plan, inputs=2 * math.pi)
    dist = np.linalg.norm(st.pos[a] - target)
    assert dist == pytest.approx(abs(L1 + L2 + L5 - 0.530), abs=1e-15)
    assert dist == pytest.approx(0.003, abs=1e-15)       # 533 ≠ 530 mm (E2)
    rng = np.random.default_rng(6)
    designs = np.column_stack([rng.uniform(0.05, 0.3, 25), rng.uniform(0.2, 0.4, 25), rng.uniform(0.05, 0.19, 25)])
    P = np.broadcast_to(plan.defaults, (25, plan.n_params)).copy()
    for col, name in enumerate(("rod.A.distance", "rod.length", "crank.length")):
        P[:, plan.param_index(name)] = designs[:, col]
    st = assur.solve(plan, P, np.full(25, 2 * math.pi))
    np.testing.assert_allclose(np.linalg.norm(st.pos[:, a] - target, axis=-1),
                               np.abs(designs.sum(axis=1) - 0.530), atol=1e-15)


def test_unbuildable_designs_are_flagged(plan):
    """l2 < l5 cannot turn fully (§2): exactly the samples with l5·|sin φ| > l2 are invalid."""
    l2 = 0.15
    st = assur.solve(plan, plan.params_with(rod__length=l2), PHI)
    reach = L5 * np.abs(np.sin(PHI))
    assert st.valid[reach < l2 * (1 - 1e-9)].all()
    assert not st.valid[reach > l2 * (1 + 1e-9)].any()
    assert st.n_unbuildable == np.count_nonzero(~st.valid) > 0
    assert np.all(np.isnan(st.pos[~st.valid][..., 0]))


def test_unbuildable_samples_are_nan_in_both_coordinates(plan):
    """docs/papers/README.md (Assembly branches): unbuildable samples are NaN, never finite garbage."""
    st = assur.solve(plan, plan.params_with(rod__length=0.15), PHI)
    bad = ~st.valid
    assert np.all(np.isnan(st.pos[bad]))
    assert np.all(np.isnan(st.dpos_dq[bad])) and np.all(np.isnan(st.d2pos_dq2[bad]))
