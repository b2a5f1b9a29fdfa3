"""Paper 004 (four-bar and six-bar walking legs): structure, the closed forms (3)–(13) with the accepted
signs and corrections, loop closure, velocities, and the β1 feasibility scan.

References: sections (§N) of docs/papers/004.md and the paper's equation
numbers. Files: (a) walker_fourbar.toml, (b) walker_fourbar_adjustable.toml, (c) walker_sixbar.toml
(β1 = 0, documented assumption) and walker_sixbar_beta1_60.toml (β1 = 60°, crank.N.angle = −β1).
The file's y is the paper's z (z up, §1).
"""
from __future__ import annotations

import dataclasses
import itertools
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.model.mechanism import Link

EX = Path(__file__).resolve().parent.parent / "examples"
FOURBAR, ADJUSTABLE = EX / "walker_fourbar.toml", EX / "walker_fourbar_adjustable.toml"
SIXBAR, SIXBAR60 = EX / "walker_sixbar.toml", EX / "walker_sixbar_beta1_60.toml"

# printed dimensions, §5 (Fig. 4 and Fig. 5 tables), metres and degrees
FB = dict(l1=0.27, l2=0.638, l3=0.65, l4=0.654, beta=math.radians(70.8))
SB = dict(l_OB=0.2, l_ON=0.2, l_BM=0.755, l_O1M=0.61, l_MD=0.38, l_DA=0.558, l_AH=0.355, l_NA=0.895,
          beta2=math.radians(135.0), beta3=math.radians(135.0))
O1 = np.array([0.567, 0.615])
OMEGA = 2 * math.pi * 27 / 60          # 27 rpm = 2.8274 rad/s (§1, §5)
PHI = np.linspace(0.0, 2 * math.pi, 721)


def e(a):
    """e(a) = (cos a, sin a) as a complex number (docs/papers/README.md, Notation)."""
    return np.exp(1j * a)


def _c(xy):
    return xy[..., 0] + 1j * xy[..., 1]


def _plan(path):
    return assur.compile(assur.load(path))


def _pt(plan, st, name):
    return _c(st.pos[..., plan.point_index(name), :])


def half_angle(num, den):
    """2·arctan(num/den) exactly as printed (den = 0 gives ±π, the correct limit)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return 2 * np.arctan(num / den)


# -- structure, §2 ------------------------------------------------------------------------------

@pytest.mark.parametrize("path, n, p5, W", [(FOURBAR, 3, 4, 1), (ADJUSTABLE, 4, 5, 2), (SIXBAR, 5, 7, 1),
                                              (SIXBAR60, 5, 7, 1)])
def test_mobility(path, n, p5, W):
    """Printed counts and W = 3n − 2p5 of mechanisms a, b, c (§2, eq. 1)."""
    s = assur.analyse_structure(assur.load(path))
    assert (s.n_moving, s.pair_counts["p5"], s.mobility) == (n, p5, W)
    assert W == 3 * n - 2 * p5


def _with_free_foot(m):
    h = m.sketch("H")
    return dataclasses.replace(m, points=m.points + (("T", (h[0] + 0.05, h[1] - 0.02)),),
                               links=m.links + (Link("foot", ("H", "T")),))


@pytest.mark.parametrize("path", [FOURBAR, ADJUSTABLE, SIXBAR, SIXBAR60], ids=lambda p: p.stem)
def test_free_foot_adds_one_freedom(path):
    """The foot hinged at H adds one uncontrolled freedom: n + 1, p5 + 1, W + 1 (§2), counted on the
    structure graph with Chebyshev's formula (1)."""
    from assur.structure.assur import mobility_chebyshev
    from assur.structure.graph import build_graph
    m = assur.load(path)
    g0, g1 = build_graph(m), build_graph(_with_free_foot(m))
    n0, p0 = len(g0.bodies) - 1, len(g0.pairs)
    n1, p1 = len(g1.bodies) - 1, len(g1.pairs)
    assert (n1, p1) == (n0 + 1, p0 + 1)
    assert mobility_chebyshev(n1, p1) == mobility_chebyshev(n0, p0) + 1 == assur.analyse_structure(m).mobility + 1


def test_analyse_reports_mobility_of_the_free_foot_model():
    m = assur.load(FOURBAR)
    free = assur.analyse_structure(_with_free_foot(m))
    assert free.mobility == 2                      # §2: the hinged foot adds one freedom
    assert "foot" in " ".join(free.undetermined)   # ... which no driver determines
    bare = assur.analyse_structure(dataclasses.replace(m, drivers=()))
    assert bare.mobility == 1 and set(bare.undetermined) == {"coupler", "crank", "rocker"}
    with pytest.raises(assur.StructureError, match=r"= 2 but 1 driver"):
        assur.compile(_with_free_foot(m))


def test_fourbar_structure():
    """I(frame 0, crank 1) → II(coupler 3, rocker 2) (§2, eq. 2)."""
    s = _plan(FOURBAR).structure
    assert len(s.drivers) == 1 and len(s.groups) == 1
    g = s.describe()[0]
    assert (g["class"], g["kind"], set(g["bodies"])) == (2, "RRR", {"coupler", "rocker"})


@pytest.mark.parametrize("path", [SIXBAR, SIXBAR60])
def test_sixbar_structural_formula_is_a_chain(path):
    """Derived formula: I(0, 1) → II(B–M, O1–M–D) → II(N–A, D–A–H), the last group attached to the crank and to
    the first group's rocker (§2: the printed brace hides that dependency)."""
    s = _plan(path).structure
    assert s.structural_formula.count("→") == 2
    assert s.structural_formula.startswith("I(frame, crank) → II(")
    g1, g2 = s.describe()
    assert all(g["class"] == 2 and g["kind"] == "RRR" for g in (g1, g2))
    assert set(g1["bodies"]) == {"coupler_BM", "rocker"} and set(g1["attaches_to"]) == {"frame", "crank"}
    assert set(g2["bodies"]) == {"coupler_NA", "lever"} and set(g2["attaches_to"]) == {"crank", "rocker"}


def test_adjustable_default_is_mechanism_a():
    """Mechanism b at its default adjuster input places O1 at the printed (0.567, 0.615) m and is mechanism a."""
    pa, pb = _plan(FOURBAR), _plan(ADJUSTABLE)
    k = pb.input_names.index("adjuster")
    inp = np.zeros((len(PHI), 2))
    inp[:, pb.input_names.index("crank")] = PHI
    inp[:, k] = pb.sketch_inputs[k]
    sb, sa = assur.solve(pb, inputs=inp), assur.solve(pa, inputs=PHI)
    np.testing.assert_allclose(sb.pos[:, pb.point_index("O1")], np.broadcast_to(O1, (len(PHI), 2)), atol=1e-15)
    for p in ("K", "L", "H"):
        np.testing.assert_allclose(_pt(pb, sb, p), _pt(pa, sa, p), atol=1e-14)
    # moving the adjuster moves O1 (and the foot path): a second, independent input
    inp[:, k] += math.radians(10)
    moved = assur.solve(pb, inputs=inp)
    assert moved.valid.all()
    assert np.linalg.norm(moved.pos[0, pb.point_index("O1")] - O1) > 0.01


# -- four-bar, eqs. (3)–(6), §3 ------------------------------------------------------------------

def fourbar_eq5(phi, s2, s3, l1=FB["l1"], l2=FB["l2"], l3=FB["l3"]):
    """γ2, γ3 of eq. (5) as printed, with the root signs s2, s3, and K of eq. (3)."""
    xK, zK = l1 * np.cos(phi), l1 * np.sin(phi)
    xO1, zO1 = O1
    d2 = (xK - xO1) ** 2 + (zK - zO1) ** 2
    S = np.sqrt(((l2 + l3) ** 2 - d2) * (d2 - (l2 - l3) ** 2))
    g2 = half_angle(2 * l2 * (zO1 - zK) + s2 * S, (l2 - xK + xO1) ** 2 - l3 ** 2 + (zK - zO1) ** 2)
    g3 = half_angle(2 * l3 * (zO1 - zK) + s3 * S, (l3 - xK + xO1) ** 2 - l2 ** 2 + (zK - zO1) ** 2)
    return xK + 1j * zK, g2, g3


def fourbar_L_both_sides(phi, s2, s3):
    """L from the crank side K + l3 e(γ3) and from the rocker side O1 − l2 e(γ2) (eq. 4)."""
    K, g2, g3 = fourbar_eq5(phi, s2, s3)
    return K + FB["l3"] * e(g3), _c(O1) - FB["l2"] * e(g2), g2, g3


@pytest.fixture(scope="module")
def fourbar():
    plan = _plan(FOURBAR)
    return plan, assur.solve(plan, inputs=PHI)


def test_fourbar_dimensions_in_file(fourbar):
    plan, _ = fourbar
    p = plan.defaults
    for name, v in [("crank.length", FB["l1"]), ("rocker.length", FB["l2"]), ("coupler.length", FB["l3"]),
                    ("coupler.H.distance", FB["l4"]), ("coupler.H.angle", FB["beta"]), ("O1.x", O1[0]),
                    ("O1.y", O1[1]), ("O.x", 0.0), ("O.y", 0.0)]:
        assert p[plan.param_index(name)] == pytest.approx(v, abs=1e-15), name
    assert plan.speeds[0] == pytest.approx(OMEGA, rel=1e-15)
    assert OMEGA == pytest.approx(2.8274, abs=5e-5)       # printed rate, §1


def test_fourbar_eq5_accepted_signs_equal_solver(fourbar):
    """(s2, s3) = (+1, −1) closes the loop and equals the circle–circle solution for all φ (§3)."""
    plan, st = fourbar
    assert st.valid.all()
    Lc, Lr, _, _ = fourbar_L_both_sides(PHI, +1, -1)
    L = _pt(plan, st, "L")
    np.testing.assert_allclose(Lc, L, rtol=0, atol=1e-12)
    np.testing.assert_allclose(Lr, L, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_pt(plan, st, "K"), FB["l1"] * e(PHI), atol=1e-15)         # eq. (3)


def test_fourbar_eq6_foot(fourbar):
    """H = L − l4 e(γ3 + β) = O1 − l2 e(γ2) − l4 e(γ3 + β) (eq. 6), β counter-clockwise from LK to LH."""
    plan, st = fourbar
    Lc, Lr, g2, g3 = fourbar_L_both_sides(PHI, +1, -1)
    H = _pt(plan, st, "H")
    np.testing.assert_allclose(Lc - FB["l4"] * e(g3 + FB["beta"]), H, atol=1e-12)
    np.testing.assert_allclose(_c(O1) - FB["l2"] * e(g2) - FB["l4"] * e(g3 + FB["beta"]), H, atol=1e-12)
    # the accepted reading puts the foot loop below the crank axis (§3, "Why this reading")
    assert np.all(H.imag < 0)


def test_fourbar_printed_signs_do_not_close():
    """The printed (+1, +1) mixes two assembly modes: L from the two sides differ (§3, §8)."""
    Lc, Lr, _, _ = fourbar_L_both_sides(PHI, +1, +1)
    assert np.max(np.abs(Lc - Lr)) > 0.1
    assert np.mean(np.abs(Lc - Lr) > 1e-6) > 0.5        # open over most of the turn
    # the other consistent pair (−1, +1) closes too, but on the other branch (L left of K → O1)
    Lc2, Lr2, _, _ = fourbar_L_both_sides(PHI, -1, +1)
    np.testing.assert_allclose(Lc2, Lr2, atol=1e-12)
    K = FB["l1"] * e(PHI)
    assert np.all(np.imag(np.conj(_c(O1) - K) * (Lc2 - K)) > 0)


def test_fourbar_L_is_right_of_K_O1(fourbar):
    plan, st = fourbar
    K, L = _pt(plan, st, "K"), _pt(plan, st, "L")
    assert np.all(np.imag(np.conj(_c(O1) - K) * (L - K)) < 0)


def test_fourbar_assembly_condition():
    """|l2 − l3| ≤ |K O1| ≤ l2 + l3 with |K O1| ∈ |O O1| ± l1: the crank turns fully (§3)."""
    oo1 = float(np.hypot(*O1))
    assert abs(FB["l2"] - FB["l3"]) <= oo1 - FB["l1"] and oo1 + FB["l1"] <= FB["l2"] + FB["l3"]


# -- six-bar, eqs. (7)–(13), §4 --------------------------------------------------------------------

def sixbar_closed_form(phi, beta1, s1=-1, s2=+1, s3=+1, s4=+1, printed_den=False):
    """Eqs. (7)–(13) with the accepted signs (λ1 '−', λ2 '+', λ3 '+', λ4 '+') and the corrected λ4 denominator.
    Returns a dict of complex points; 'A_N' and 'A_D' are A from the two sides of eq. (11)."""
    g = SB
    B = g["l_OB"] * e(phi)                                            # (7)
    N = g["l_ON"] * e(phi - beta1)
    xB, zB = B.real, B.imag
    xO1, zO1 = O1
    d2 = (xB - xO1) ** 2 + (zB - zO1) ** 2                            # (9)
    S = np.sqrt(((g["l_O1M"] + g["l_BM"]) ** 2 - d2) * (d2 - (g["l_O1M"] - g["l_BM"]) ** 2))
    lam1 = half_angle(2 * g["l_BM"] * (zO1 - zB) + s1 * S,
                      (g["l_BM"] - xB + xO1) ** 2 - g["l_O1M"] ** 2 + (zB - zO1) ** 2)
    lam2 = half_angle(2 * g["l_O1M"] * (zO1 - zB) + s2 * S,
                      (g["l_O1M"] - xB + xO1) ** 2 - g["l_BM"] ** 2 + (zB - zO1) ** 2)
    M_B = B + g["l_BM"] * e(lam1)                                     # (8), both sides
    M_O1 = _c(O1) - g["l_O1M"] * e(lam2)
    D = M_O1 + g["l_MD"] * e(lam2 - g["beta2"])                       # (10)
    xN, zN, xD, zD = N.real, N.imag, D.real, D.imag
    dd2 = (xN - xD) ** 2 + (zN - zD) ** 2                              # (12)
    S2 = np.sqrt(((g["l_NA"] + g["l_DA"]) ** 2 - dd2) * (dd2 - (g["l_NA"] - g["l_DA"]) ** 2))
    lam3 = half_angle(2 * g["l_NA"] * (zN - zD) + s3 * S2,
                      (g["l_NA"] - xN + xD) ** 2 - g["l_DA"] ** 2 + (zN - zD) ** 2)
    first = g["l_NA"] if printed_den else g["l_DA"]                   # printed: l_NA (typo); corrected: l_DA
    lam4 = half_angle(2 * g["l_DA"] * (zD - zN) + s4 * S2, (first - xN + xD) ** 2 - g["l_NA"] ** 2 + (zN - zD) ** 2)
    A_N = (xN + g["l_NA"] * np.cos(lam3)) + 1j * (zN - g["l_NA"] * np.sin(lam3))   # (11), note −sin
    A_D = D - g["l_DA"] * e(lam4)
    H = A_D + g["l_AH"] * e(lam4 - g["beta3"])                        # (13)
    H13 = (g["l_ON"] * np.cos(phi - beta1) + g["l_NA"] * np.cos(lam3) + g["l_AH"] * np.cos(lam4 - g["beta3"])) + 1j * (
        g["l_ON"] * np.sin(phi - beta1) - g["l_NA"] * np.sin(lam3) + g["l_AH"] * np.sin(lam4 - g["beta3"]))
    return dict(B=B, N=N, M_B=M_B, M_O1=M_O1, D=D, A_N=A_N, A_D=A_D, H=H, H13=H13)


SIXBAR_CASES = [(SIXBAR, 0.0), (SIXBAR60, math.radians(60.0))]


@pytest.fixture(scope="module", params=SIXBAR_CASES, ids=["beta1_0", "beta1_60"])
def sixbar(request):
    path, beta1 = request.param
    plan = _plan(path)
    return plan, assur.solve(plan, inputs=PHI), beta1


def test_sixbar_dimensions_in_file(sixbar):
    plan, _, beta1 = sixbar
    p = plan.defaults
    for name, v in [("crank.length", SB["l_OB"]), ("coupler_BM.length", SB["l_BM"]),
                    ("rocker.length", SB["l_O1M"]), ("rocker.D.distance", SB["l_MD"]),
                    ("rocker.D.angle", -SB["beta2"]), ("coupler_NA.length", SB["l_NA"]),
                    ("lever.length", SB["l_DA"]), ("lever.H.distance", SB["l_AH"]),
                    ("lever.H.angle", -SB["beta3"]), ("O1.x", O1[0]), ("O1.y", O1[1])]:
        assert p[plan.param_index(name)] == pytest.approx(v, abs=1e-15), name
    if beta1:
        assert p[plan.param_index("crank.N.distance")] == pytest.approx(SB["l_ON"], abs=1e-15)
        assert p[plan.param_index("crank.N.angle")] == pytest.approx(-beta1, abs=1e-15)
    assert plan.speeds[0] == pytest.approx(OMEGA, rel=1e-15)


def test_sixbar_closed_forms_equal_solver(sixbar):
    """Eq. (9) with λ2 '+', λ1 '−', eq. (12) corrected with (+, +), eqs. (10), (11), (13) equal the solver."""
    plan, st, beta1 = sixbar
    assert st.valid.all()
    cf = sixbar_closed_form(PHI, beta1)
    n_name = "N" if "N" in plan.point_names else "B"        # β1 = 0: N ≡ B (one crank pin)
    np.testing.assert_allclose(_pt(plan, st, "B"), cf["B"], atol=1e-15)
    np.testing.assert_allclose(_pt(plan, st, n_name), cf["N"], atol=1e-15)
    for key, name in [("M_B", "M"), ("M_O1", "M"), ("D", "D"), ("A_N", "A"), ("A_D", "A"), ("H", "H"),
                      ("H13", "H")]:
        np.testing.assert_allclose(cf[key], _pt(plan, st, name), rtol=0, atol=1e-12, err_msg=key)


def test_sixbar_branches(sixbar):
    """M on the clockwise side of B → O1, A on the clockwise side of N → D (§4)."""
    plan, st, beta1 = sixbar
    B, M, D, A = (_pt(plan, st, p) for p in "BMDA")
    N = sixbar_closed_form(PHI, beta1)["N"]
    assert np.all(np.imag(np.conj(_c(O1) - B) * (M - B)) < 0)
    assert np.all(np.imag(np.conj(D - N) * (A - N)) < 0)


def test_sixbar_printed_signs_of_eq9_do_not_close():
    for beta1 in (0.0, math.radians(60)):
        cf = sixbar_closed_form(PHI, beta1, s1=+1, s2=+1)
        assert np.max(np.abs(cf["M_B"] - cf["M_O1"])) > 0.1


def test_sixbar_printed_eq12_denominator_does_not_close():
    """With the printed λ4 denominator no root pair closes the loop (§4, §8); with the correction,
    (+, +) and (−, −) close."""
    for beta1 in (0.0, math.radians(60)):
        for s3, s4 in itertools.product((+1, -1), repeat=2):
            cf = sixbar_closed_form(PHI, beta1, s3=s3, s4=s4, printed_den=True)
            assert np.min(np.abs(cf["A_N"] - cf["A_D"])) > 0.05, (s3, s4)      # open at every φ
            fixed = sixbar_closed_form(PHI, beta1, s3=s3, s4=s4)
            gap = np.max(np.abs(fixed["A_N"] - fixed["A_D"]))
            assert (gap < 1e-12) if s3 == s4 else (gap > 0.05), (s3, s4)


def test_sixbar_beta1_0_is_beta1_60_file_at_zero():
    """The single-pin file equals the β1 file with crank.N.angle = 0 (N moved onto B)."""
    p0, p60 = _plan(SIXBAR), _plan(SIXBAR60)
    s0 = assur.solve(p0, inputs=PHI)
    s60 = assur.solve(p60, p60.params_with(crank__N__angle=0.0), PHI)
    for p in ("B", "M", "D", "A", "H"):
        np.testing.assert_allclose(_pt(p0, s0, p), _pt(p60, s60, p), atol=1e-12)


# -- loop closure and velocities -------------------------------------------------------------------------------

LOOPS = {
    FOURBAR: [("O", "K", FB["l1"]), ("K", "L", FB["l3"]), ("O1", "L", FB["l2"]), ("L", "H", FB["l4"])],
    SIXBAR: [("O", "B", SB["l_OB"]), ("B", "M", SB["l_BM"]), ("O1", "M", SB["l_O1M"]), ("M", "D", SB["l_MD"]),
             ("B", "A", SB["l_NA"]), ("D", "A", SB["l_DA"]), ("A", "H", SB["l_AH"])],
    SIXBAR60: [("O", "B", SB["l_OB"]), ("O", "N", SB["l_ON"]), ("B", "M", SB["l_BM"]), ("O1", "M", SB["l_O1M"]),
               ("M", "D", SB["l_MD"]), ("N", "A", SB["l_NA"]), ("D", "A", SB["l_DA"]), ("A", "H", SB["l_AH"])],
}


@pytest.mark.parametrize("path", list(LOOPS), ids=lambda p: p.stem)
def test_loops_close_at_every_phi(path):
    plan = _plan(path)
    phi = np.linspace(0, 2 * math.pi, 3601)
    st = assur.solve(plan, inputs=phi)
    assert st.valid.all()
    for a, b, length in LOOPS[path]:
        np.testing.assert_allclose(np.abs(_pt(plan, st, a) - _pt(plan, st, b)), length, rtol=1e-12, err_msg=a + b)
    np.testing.assert_allclose(_pt(plan, st, "O1"), _c(O1), atol=1e-15)
    # the bends keep their printed angles (counter-clockwise from the first direction to the second)
    def turn(p, q, r):                       # angle from p→q to p→r
        P, Q, R = (_pt(plan, st, n) for n in (p, q, r))
        return np.angle((R - P) / (Q - P))
    if path == FOURBAR:
        np.testing.assert_allclose(turn("L", "K", "H"), FB["beta"], atol=1e-12)
    else:
        np.testing.assert_allclose(turn("M", "O1", "D"), -SB["beta2"], atol=1e-12)
        np.testing.assert_allclose(turn("A", "D", "H"), -SB["beta3"], atol=1e-12)


@pytest.mark.parametrize("path", [FOURBAR, SIXBAR, SIXBAR60], ids=lambda p: p.stem)
def test_velocities_against_central_differences(path):
    plan = _plan(path)
    h = 1e-4
    phi = np.linspace(0, 2 * math.pi, 241)
    st = assur.solve(plan, inputs=phi)
    sp = assur.solve(plan, inputs=phi + h)
    sm = assur.solve(plan, inputs=phi - h)
    fd1 = (sp.pos - sm.pos) / (2 * h)
    fd2 = (sp.pos - 2 * st.pos + sm.pos) / h ** 2
    np.testing.assert_allclose(st.dpos_dq[..., 0], fd1, atol=1e-8)
    np.testing.assert_allclose(st.d2pos_dq2[..., 0, 0], fd2, atol=1e-6)
    # second analogue against central differences of the first analogue
    fd2b = (sp.dpos_dq[..., 0] - sm.dpos_dq[..., 0]) / (2 * h)
    np.testing.assert_allclose(st.d2pos_dq2[..., 0, 0], fd2b, atol=1e-7)
    # time derivatives at 27 rpm: vel = ω·d/dφ, acc = ω²·d²/dφ² (constant ω)
    np.testing.assert_allclose(st.vel, OMEGA * fd1, atol=3e-8)
    np.testing.assert_allclose(st.acc, OMEGA ** 2 * fd2, atol=1e-5)
    np.testing.assert_allclose(st.vel, OMEGA * st.dpos_dq[..., 0], atol=1e-15)
    np.testing.assert_allclose(st.acc, OMEGA ** 2 * st.d2pos_dq2[..., 0, 0], atol=1e-14)


# -- β1 feasibility scan, §4 ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def beta1_scan():
    plan = _plan(SIXBAR60)
    beta1 = np.arange(360)
    P = np.broadcast_to(plan.defaults, (360, plan.n_params)).copy()
    P[:, plan.param_index("crank.N.angle")] = -np.radians(beta1)
    st = assur.solve(plan, P[:, None, :], PHI, order=0)
    assert st.valid.shape == (360, len(PHI))
    return plan, beta1, st


def test_beta1_feasibility_intervals(beta1_scan):
    """Full rotation exactly for β1 ∈ 0…116° and 253…359° on a 1° grid (§4)."""
    plan, beta1, st = beta1_scan
    full = st.valid.all(axis=-1)
    expected = (beta1 <= 116) | (beta1 >= 253)
    assert np.array_equal(full, expected), np.flatnonzero(full != expected)
    for b in (135, 180, 225):                     # the "natural" guesses cannot turn fully (§4)
        assert not full[b]


def test_beta1_feasibility_from_the_ND_condition(beta1_scan):
    """Independent check: the N–A–D dyad needs 0.337 ≤ |ND| ≤ 1.453 m at every φ (§4), with D from
    the first dyad (independent of β1) and N from eq. (7); 135°, 180°, 225° violate the upper bound."""
    plan, beta1, st = beta1_scan
    lo, hi = SB["l_NA"] - SB["l_DA"], SB["l_NA"] + SB["l_DA"]
    assert (round(lo, 3), round(hi, 3)) == (0.337, 1.453)
    D = sixbar_closed_form(PHI, 0.0)["D"]
    N = SB["l_ON"] * e(PHI[None, :] - np.radians(beta1)[:, None])
    dist = np.abs(N - D[None, :])
    ok = ((dist >= lo) & (dist <= hi)).all(axis=-1)
    assert np.array_equal(ok, st.valid.all(axis=-1))
    for b in (135, 180, 225):
        assert dist[b].max() > hi
    # and per sample: valid exactly where the dyad can be assembled (away from tangency)
    margin = np.minimum(dist - lo, hi - dist)
    clear = np.abs(margin) > 1e-9
    assert np.array_equal(st.valid[clear], (margin > 0)[clear])
