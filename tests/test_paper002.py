"""Paper 002 (lever manipulator with two linear actuators in a straight guide); references (§N, EN) are
sections of docs/papers/002.md.

The sharp check P002-1 (§8) through the general engine (examples/lever_manipulator.toml) and
through the closed form of §3–§4 (assur.analysis.lever); the closed form against the general
solver and against central differences for random geometries (hypothesis), including γ < 0, γ = 90°
and β < γ; the exact invariant of §6 (the areal-velocity ratio h_O/h_A); the status of the
paper's own formulas (§5): (8), (9), (15) exact, (11) only before the foot of O, (12) and (16)
singular where §5 says; the validation of §2/§9.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

import assur
from assur.analysis.actuators import actuator_motions, rod_pairs
from assur.analysis.lever import LeverManipulator, lever_layout, paper_formulas

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "lever_manipulator.toml"
REL = 1e-9
DEG = math.radians(1e-9)

# P002-1 (§8): O = (0, 0), A = (0.6, 0), B0 = (0.3, 0.4), γ = 0, V1 = 0.1 m/s, evaluated where B
# reaches the foot of the perpendicular from O, s1 = √0.52 − 0.5.
S1_FOOT = math.sqrt(0.52) - 0.5
P002_1 = {   # §8 table: exact values
    "sigma": 0.3, "b": 0.4, "s2": 0.1, "phi": math.atan(3 / 4), "psi": math.atan(4 / 3) - math.atan(2 / 3),
    "V2": 0.0, "v_B": math.sqrt(0.52) / 6, "omega_phi": math.sqrt(0.52) / 2.4, "omega_psi": math.sqrt(0.52) / 7.8,
    "K_omega": 13 / 4, "eps_psi": -11 / 351, "eps_phi": -1 / 54, "a2": -13 / 360, "areal_ratio": 1.0,
}


def p002_1():
    return LeverManipulator.from_points((0, 0), (0.6, 0), (0.3, 0.4), (-1, 0))


def close(actual, expected, rel=REL, abs_=1e-12):
    np.testing.assert_allclose(actual, expected, rtol=rel, atol=abs_)


# -- P002-1 -------------------------------------------------------------------------------------------------
def test_p002_1_geometry():
    g = p002_1()
    close([g.a, g.b1, g.l1, g.h_O, g.h_A, g.e_O, g.d_A], [0.6, 0.5, 0.5, 0.4, 0.4, 0.3, 0.3])   # §8
    close([g.alpha, g.beta], [math.atan(4 / 3)] * 2)
    assert abs(g.gamma) < 1e-15 and not g.mirrored
    close(g.foot_stroke, S1_FOOT)        # §8b: s1* = sqrt(h_A² + (e_O + d_A)²) − l1


def test_p002_1_closed_form():
    ex = p002_1().exact(np.array([S1_FOOT]), 0.1)
    for key, want in P002_1.items():
        close(ex[key][0], want, abs_=1e-15 if key == "V2" else 1e-12)


def test_p002_1_general_engine_on_the_example_file():
    """The example file solved by the batched engine reproduces every value of the §8 table."""
    plan = assur.compile(assur.load(EXAMPLE))
    st_ = assur.solve(plan, inputs=np.array([0.5 + S1_FOOT]), speeds=[0.1])
    mot = actuator_motions(st_)
    l, b = mot["drive_rod"], mot["driven_rod"]
    B = st_.pos[0, plan.point_index("B")]
    close(B, [0.0, 0.4], abs_=1e-15)
    close(-b.extension[0], P002_1["s2"])
    close(b.length[0], P002_1["b"])
    assert abs(b.angle[0] - P002_1["phi"]) < DEG and abs(l.angle[0] - P002_1["psi"]) < DEG
    assert abs(b.rate[0]) < 1e-15                                     # V2 = 0 at the foot of O
    close(np.hypot(*st_.vel[0, plan.point_index("B")]), P002_1["v_B"])
    close(b.omega[0], P002_1["omega_phi"])
    close(l.omega[0], P002_1["omega_psi"])
    close(l.alpha[0], P002_1["eps_psi"])
    close(b.alpha[0], P002_1["eps_phi"])
    close(-b.accel[0], P002_1["a2"])                                  # s̈2 = −d²b/dt²
    (pair,) = rod_pairs(st_, mot)
    close(pair.K_omega[0], P002_1["K_omega"])
    close(pair.areal_ratio[0], P002_1["areal_ratio"])
    # the body rates of the engine's own cylinder bodies agree with the rods' rates
    close(st_.body_omega[0, st_.body("driven_rod.cylinder")], P002_1["omega_phi"])


def test_example_file_is_the_p002_1_layout():
    plan = assur.compile(assur.load(EXAMPLE))
    lay = lever_layout(plan)
    assert lay is not None and (lay.driving, lay.driven, lay.joint) == ("drive_rod", "driven_rod", "B")
    g = lay.geometry
    close([g.a, g.alpha, g.beta], [0.6, math.atan(4 / 3), math.atan(4 / 3)])
    assert abs(g.gamma) < 1e-15


def test_k_omega_maximum_of_p002_1():
    """§8b: K_ω has an interior maximum 4.0 at s1 ≈ 0.394 m. Derivation (γ = 0, h_O = h_A = 0.4,
    e_O = d_A = 0.3): K = L²/b² = (0.16 + (σ+0.3)²)/(0.16 + (σ−0.3)²); dK/dσ = 0 ⇔ (σ+0.3)(σ−0.3) = 0.16,
    σ = 0.5, L = √0.8, K = 0.8/0.2 = 4, s1 = √0.8 − 0.5."""
    from assur.analysis.actuators import stroke_envelope
    from assur.analysis.timelaw import driver_law
    plan = assur.compile(assur.load(EXAMPLE))
    env = stroke_envelope(plan, driver_law(plan), steps=120)
    k = env.extremes[("drive_rod/driven_rod", "K_omega")]
    (top,) = k["interior"]
    close(top.value, 4.0)
    assert abs(top.q - 0.5 - (math.sqrt(0.8) - 0.5)) < 1e-7
    s2 = env.extremes[("driven_rod", "extension")]
    (low,) = s2["interior"]                   # §8b: s2_max = b1 − h_O at s1*
    close(-low.value, 0.1)
    assert abs(low.q - 0.5 - S1_FOOT) < 1e-7
    assert abs(env.past_foot["drive_rod/driven_rod"] - 0.5 - S1_FOOT) < 1e-9


# -- random geometries: closed form = general engine = central differences ------------------------------------
ANGLE = st.floats(min_value=math.radians(15), max_value=math.radians(140))


@st.composite
def geometries(draw):
    """(a, α, β, γ) with −80° < β − γ < 80°, |sin(α+γ)|, |sin(β−γ)| ≥ 0.1 (§2 validity)."""
    a = draw(st.floats(min_value=0.05, max_value=2.0))
    alpha = draw(ANGLE)
    beta = draw(st.floats(min_value=math.radians(15), max_value=math.radians(165) - alpha))
    gamma = draw(st.one_of(st.just(0.0), st.just(math.pi / 2),
                           st.floats(min_value=-math.radians(70), max_value=math.radians(100))))
    assume(abs(beta - gamma) < math.radians(80))
    assume(abs(math.sin(alpha + gamma)) > 0.1 and abs(math.sin(beta - gamma)) > 0.1)
    return LeverManipulator(a, alpha, beta, gamma)


def strokes(g, n=7, seed=0):
    rng = np.random.default_rng(seed)
    return np.sort(rng.uniform(0.0, 3.0 * g.l1, n))


@settings(max_examples=40, deadline=None)
@given(geometries(), st.integers(0, 2**16))
def test_closed_form_equals_the_general_engine(g, seed):
    """§3–§4 against the batched Assur-group solver on the equivalent mechanism file."""
    plan = assur.compile(assur.loads(assur.dumps(g.mechanism(speed=0.1))))
    s1 = strokes(g, seed=seed)
    ex = g.exact(s1, 0.1)
    state = assur.solve(plan, inputs=g.l1 + s1, speeds=[0.1])
    assert state.valid.all()
    mot = actuator_motions(state)
    l, b = mot["drive_rod"], mot["driven_rod"]
    scale = g.a + g.l1 + g.b1
    close(state.pos[:, plan.point_index("B")], ex["B"], abs_=1e-12 * scale)
    close(l.angle, ex["psi"], abs_=1e-11)
    close(b.angle, ex["phi"], abs_=1e-11)
    close(-b.extension, ex["s2"], abs_=1e-12 * scale)
    for mine, key, order in ((l.dangle_dq, "dpsi", 1), (l.d2angle_dq2, "d2psi", 2), (b.dangle_dq, "dphi", 1),
                             (b.d2angle_dq2, "d2phi", 2), (-b.dlength_dq, "ds2", 0), (-b.d2length_dq2, "d2s2", 1)):
        # absolute floor: 1e-9 of the quantity's natural scale (1/l1 per order of d/ds1)
        close(mine, ex[key], rel=1e-8, abs_=1e-9 * (np.max(np.abs(ex[key])) + g.l1 ** -order))
    close(b.rate, -ex["V2"], rel=1e-8, abs_=1e-12)
    close(b.alpha, ex["eps_phi"], rel=1e-8, abs_=1e-10 * np.max(np.abs(ex["eps_phi"])))


@settings(max_examples=40, deadline=None)
@given(geometries())
def test_closed_form_analogues_equal_central_differences(g):
    s1 = np.linspace(0.05, 2.0, 9) * g.l1
    h = 1e-5 * g.l1
    ex, lo, hi = g.exact(s1), g.exact(s1 - h), g.exact(s1 + h)
    for f, d1, d2 in (("sigma", "dsigma", "d2sigma"), ("psi", "dpsi", "d2psi"), ("phi", "dphi", "d2phi"),
                      ("s2", "ds2", "d2s2")):
        cd1 = (hi[f] - lo[f]) / (2 * h)
        cd2 = (hi[f] - 2 * ex[f] + lo[f]) / h ** 2
        close(ex[d1], cd1, rel=1e-6, abs_=1e-7 * np.max(np.abs(ex[d1])) + 1e-9)
        close(ex[d2], cd2, rel=1e-3, abs_=1e-3 * np.max(np.abs(ex[d2])) / g.l1 + 1e-4 / g.l1)


@settings(max_examples=60, deadline=None)
@given(geometries(), st.integers(0, 2**16))
def test_areal_velocity_ratio_is_the_constant_h_o_over_h_a(g, seed):
    """§6: (b²·ω_φ)/(L²·ω_ψ) = h_O/h_A = S_BOB1/S_BAB1 for every s1 — computed by the engine's
    rod pairs (from positions and analogues only), against the closed-form constant."""
    plan = assur.compile(g.mechanism(speed=0.1))
    s1 = strokes(g, seed=seed) + 1e-3 * g.l1
    state = assur.solve(plan, inputs=g.l1 + s1, speeds=[0.1])
    (pair,) = rod_pairs(state)
    want = g.b1 * math.sin(g.alpha + g.gamma) / (g.l1 * math.sin(g.beta - g.gamma))
    close(pair.areal_ratio, want, rel=1e-9)
    close(pair.area_ratio, want, rel=1e-7)          # the swept triangles share the base BB1
    # K_ω itself varies: K_ω = (h_O/h_A)·(L/b)² (§6)
    b = actuator_motions(state)["driven_rod"].length
    close(pair.K_omega, want * ((g.l1 + s1) / b) ** 2, rel=1e-9)


def test_special_cases_gamma_90_and_beta_below_gamma():
    """Fig. 3's vertical guide (γ = 90°, β < γ): h_A < 0, the driving rod turns clockwise (§2)."""
    g = LeverManipulator(0.3, math.radians(70), math.radians(75), math.pi / 2)
    assert g.h_A < 0 and g.beta < g.gamma
    ex = g.exact(np.linspace(0.01, 0.5, 5), 0.1)
    assert np.all(ex["psi"] < 0) and np.all(ex["omega_psi"] < 0)
    assert np.all(ex["past_foot"])            # α + γ > 90°: e_O < 0, the driven rod lengthens from the start
    assert np.all(ex["s2"] < 0)


# -- the paper's formulas (§5) -----------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(geometries(), st.floats(min_value=0.01, max_value=0.5))
def test_paper_eqs_8_9_15_equal_the_exact_model(g, V1):
    t = np.linspace(0.0, 2.5 * g.l1 / V1, 11)
    ex = g.exact(V1 * t, V1)
    lit = paper_formulas(g, t, V1)
    close(lit.values["psi (8)"], ex["psi"], abs_=1e-12)
    close(lit.values["omega_psi (9)"], ex["omega_psi"], rel=1e-10, abs_=1e-14)
    close(lit.values["eps_psi (15)"], ex["eps_psi"], rel=1e-9, abs_=1e-14)
    assert not lit.singular["psi (8)"].any() and not lit.singular["omega_psi (9)"].any()


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(geometries())
def test_paper_eq_11_holds_only_before_the_foot_of_o(g):
    # only geometries whose guide passes the foot of O within the stroke qualify: most draws are filtered out
    """E3: with the true s2, φ = arcsin(b1·A/b) − (α+γ) holds while α + γ + φ ≤ 90° (σ ≤ e_O);
    past the foot it is on the wrong branch (180° − arcsin(...) − (α+γ) is right)."""
    assume(g.foot_stroke > 0.05 * g.l1)
    V1 = 0.1
    t = np.linspace(0.0, 3.0 * g.foot_stroke, 31) / V1
    ex = g.exact(V1 * t, V1)
    lit = paper_formulas(g, t, V1).values
    before = ex["sigma"] < g.e_O - 1e-6 * g.l1
    after = ex["sigma"] > g.e_O + 1e-3 * g.l1
    assert before.any() and after.any()
    def wrapped(x):     # angles compared modulo 360°
        return (x + math.pi) % (2 * math.pi) - math.pi
    close(wrapped(lit["phi (11)"][before] - ex["phi"][before]), 0.0, abs_=1e-7)
    assert np.all(np.abs(wrapped(lit["phi (11)"][after] - ex["phi"][after])) > 1e-6)
    other = math.pi - np.arcsin(g.h_O / ex["b"][after]) - (g.alpha + g.gamma)
    close(wrapped(other - ex["phi"][after]), 0.0, abs_=1e-7)


def test_paper_eq_11_is_wrong_at_t0_for_a_vertical_guide():
    """E3: γ = 90°, α + γ = 100° gives φ(0) = arcsin(sin 100°) − 100° = −20° instead of 0."""
    g = LeverManipulator(1.0, math.radians(10), math.radians(120), math.pi / 2)
    lit = paper_formulas(g, np.array([0.0]), 0.1)
    assert abs(math.degrees(lit.values["phi (11)"][0]) + 20.0) < 1e-9
    assert abs(g.exact(np.array([0.0]))["phi"][0]) < 1e-15


def test_paper_eq_12_singularities_are_reported_not_evaluated():
    """§8: at the foot of O the chain-rule reading of (12) has sqrt(b² − b1²A²) = 0 (true ω_φ is
    finite); with V2 frozen at its start value the root's argument turns negative after b1 − V2·t < h_O.
    Both are flagged (NaN + singular), never a number."""
    g = p002_1()
    t = np.array([0.0, 1.0, S1_FOOT / 0.1, 3.0])
    inst = paper_formulas(g, t, 0.1)
    assert inst.reading == "instantaneous"
    assert inst.singular["omega_phi (12)"].tolist() == [False, False, True, False]
    assert np.isnan(inst.values["omega_phi (12)"][2]) and np.isnan(inst.values["eps_phi (16)"][2])
    assert any("omega_phi (12)" in n and "2.2111" in n for n in inst.notes)
    ex = g.exact(0.1 * t, 0.1)
    close(inst.values["omega_phi (12)"][:2], ex["omega_phi"][:2])            # exact before the foot ...
    close(inst.values["omega_phi (12)"][3], -ex["omega_phi"][3])             # ... wrong sign after it
    v2_0 = float(g.exact(np.array([0.0]), 0.1)["V2"][0])
    close(v2_0, 0.1)                          # V2(0) = V1·cos(α+γ)/cos(β−γ) = V1 (symmetric start)
    frozen = paper_formulas(g, np.linspace(0.0, 3.0, 31), 0.1, v2_0)
    t_bad = (g.b1 - g.h_O) / v2_0             # b1 − V2·t = h_O at t = 1 s
    sing = frozen.singular["omega_phi (12)"]
    assert np.array_equal(sing, frozen.t >= t_bad - 1e-9)
    assert np.all(np.isnan(frozen.values["omega_phi (12)"][sing]))
    assert np.all(np.isfinite(frozen.values["omega_phi (12)"][~sing]))


def test_paper_eq_16_has_the_wrong_sign_at_t0():
    """§8b: α = β = 60°, γ = 0, a = 1 m, V1 = 0.1 m/s: true ε_φ(0) = −0.01732 rad/s² against
    (16) = +0.0866 (V2 frozen at V2(0)); the condition is sin³β > sin 2α·cos β."""
    g = LeverManipulator(1.0, math.radians(60), math.radians(60), 0.0)
    ex = g.exact(np.array([0.0]), 0.1)
    lit = paper_formulas(g, np.array([0.0]), 0.1, float(ex["V2"][0]))
    assert round(float(ex["eps_phi"][0]), 5) == -0.01732
    assert round(float(lit.values["eps_phi (16)"][0]), 4) == 0.0866
    assert math.sin(g.beta) ** 3 > math.sin(2 * g.alpha) * math.cos(g.beta)


def test_paper_eq_14_is_not_the_driven_rod_speed():
    """E4: (14) mixes metres and m/s; it is not V2 = V1·ds2/ds1, not even in sign."""
    g = p002_1()
    t = np.array([1.0, 3.0])
    lit = paper_formulas(g, t, 0.1)
    ex = g.exact(0.1 * t, 0.1)
    v14 = lit.values["V2 (14)"]
    assert abs(v14[0] - ex["V2"][0]) > 0.3 * abs(ex["V2"][0])       # 0.0718 against the true 0.0479 m/s
    assert ex["V2"][1] < 0 < v14[1]                                  # past the foot of O: the wrong sign
    assert lit.singular["V2 (14)"].tolist() == [False, False]
    assert paper_formulas(g, np.array([0.0]), 0.1).singular["V2 (14)"][0]     # sin φ = 0 at t = 0


def test_limits_of_spec_3():
    g = LeverManipulator(0.4, math.radians(50), math.radians(70), math.radians(20))
    far = g.exact(np.array([1e7]))
    lim = g.limits
    assert abs(far["psi"][0] - lim["psi"]) < 1e-6 and abs(far["phi"][0] - lim["phi"]) < 1e-6
    assert abs(lim["phi"] - (math.pi - g.alpha - g.gamma)) < 1e-15
    close(far["K_omega"][0], lim["K_omega"], rel=1e-5)


# -- other parametrisations and validation (§2, §9) ---------------------------------------------------
def test_triangle_and_points_parametrisations_agree():
    g = LeverManipulator(0.5, math.radians(55), math.radians(65), math.radians(-20))
    t = LeverManipulator.from_triangle(g.b1, g.l1, g.alpha + g.gamma, math.pi - (g.beta - g.gamma))
    close([t.a, t.alpha, t.beta, t.gamma], [g.a, g.alpha, g.beta, g.gamma])
    # a rigid motion and a mirror of the points give the same geometry (mirrored flagged)
    R = np.array([[math.cos(0.7), -math.sin(0.7)], [math.sin(0.7), math.cos(0.7)]])
    M = np.diag([1.0, -1.0])
    shift = np.array([3.0, -1.0])
    pts = [np.zeros(2), np.array([g.a, 0.0]), g.B0, g.u]
    for T, mirrored in ((R, False), (R @ M, True)):
        p = LeverManipulator.from_points(T @ pts[0] + shift, T @ pts[1] + shift, T @ pts[2] + shift, T @ pts[3])
        close([p.a, p.alpha, p.beta, p.gamma], [g.a, g.alpha, g.beta, g.gamma])
        assert p.mirrored is mirrored


@pytest.mark.parametrize("args, where, text", [
    ((0.5, math.radians(50), math.radians(100), math.radians(5)), "beta - gamma", "95°"),
    ((0.5, math.radians(50), math.radians(60), math.radians(60)), "gamma", "passes through A"),
    ((0.5, math.radians(50), math.radians(30), math.radians(-50)), "gamma", "passes through O"),
    ((0.5, math.radians(100), math.radians(90), 0.0), "alpha, beta", "degenerate"),
    ((0.0, math.radians(50), math.radians(60), 0.0), "a", "positive"),
])
def test_validation_names_the_quantity(args, where, text):
    with pytest.raises(assur.SpecError) as info:
        LeverManipulator(*args)
    assert any(p == where and text in m for p, m in info.value.problems), info.value.problems


def test_degenerate_points_are_rejected():
    with pytest.raises(assur.SpecError, match="B0: lies on the line O–A"):
        LeverManipulator.from_points((0, 0), (1, 0), (0.5, 0), (-1, 0))
    with pytest.raises(assur.SpecError, match="angle O B0 A"):
        LeverManipulator.from_triangle(0.5, 0.5, math.radians(80), math.radians(60))


def test_omega_phi_has_an_interior_maximum_in_some_geometries_only():
    """§8b: ω_φ has an interior maximum in some geometries (P002-1: d²φ/ds1² changes sign) and not
    in others (α = β = 60°, γ = 0: d²φ/ds1² < 0 along the whole stroke, here up to s1 = 20·l1)."""
    s = np.linspace(0.0, 20.0, 20001)
    g60 = LeverManipulator(1.0, math.radians(60), math.radians(60), 0.0)
    assert np.all(g60.exact(s * g60.l1)["d2phi"] < 0)
    g = p002_1()
    d2 = g.exact(s * g.l1)["d2phi"]
    assert d2[0] > 0 and d2[-1] < 0 and np.count_nonzero(np.diff(np.sign(d2))) == 1


def test_a_mirrored_file_reports_angles_in_its_own_frame():
    """§2: B0 below O → A mirrors the paper's frame; ψ and φ keep their sizes and flip their senses."""
    text = EXAMPLE.read_text(encoding="utf-8").replace("G = [0, 400]", "G = [0, -400]").replace(
        "B = [300, 400]", "B = [300, -400]")
    plan = assur.compile(assur.loads(text))
    lay = lever_layout(plan)
    assert lay.geometry.mirrored and lay.sign == -1
    s1 = np.array([0.1, S1_FOOT, 0.4])
    st_ = assur.solve(plan, inputs=0.5 + s1, speeds=[0.1])
    mot = actuator_motions(st_)
    ex = p002_1().exact(s1, 0.1)
    close(mot["drive_rod"].angle, -ex["psi"])
    close(mot["driven_rod"].omega, -ex["omega_phi"])
    (pair,) = rod_pairs(st_, mot)
    close(pair.K_omega, ex["K_omega"])          # a ratio of two rates: the mirror cancels
