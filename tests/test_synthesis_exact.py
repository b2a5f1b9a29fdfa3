"""Exact synthesis (assur.synthesis.exact): Freudenstein function generation and Burmester motion generation.

Every reference is computed independently here: a four-bar's positions in closed form (circle ∩ circle,
written below, not the engine), Freudenstein's loop closure (Norton, *Design of Machinery*, §5.12), and
the circle condition of a dyad (Sandor & Erdman, *Advanced Mechanism Design* vol. 2, ch. 2). No printed
textbook example with both its data and its answer could be read for this test, so the textbook
conditions themselves are checked on known linkages instead.
"""
import numpy as np
import pytest

import assur
from assur.errors import SpecError
from assur.synthesis import exact
from assur.synthesis.burmester import Poses, centre_curve
from assur.synthesis.freudenstein import chebyshev_points

# a known crank-rocker: ground pivots, crank a, coupler b, rocker c, coupler point (1, 1) in the A → B frame
A0, B0, LA, LB, LC = 0 + 0j, 4 + 0j, 1.5, 3.5, 3.0


def fourbar(phi, left=True):
    """Closed-form positions (P, coupler angle, A, B) at crank angle phi: B on the circle about A (radius b) and
    about B0 (radius c), on the left of A → B0 for the sketched branch."""
    A = A0 + LA * np.exp(1j * phi)
    dv = B0 - A
    L = abs(dv)
    x = (LB ** 2 - LC ** 2 + L ** 2) / (2 * L)
    h = np.sqrt(LB ** 2 - x ** 2) * (1 if left else -1)
    B = A + (x + 1j * h) * dv / L
    th = np.angle(B - A)
    return A + (1 + 1j) * np.exp(1j * th), th, A, B


def poses_of(phis, left=True):
    data = [fourbar(p, left) for p in phis]
    return np.array([[d[0].real, d[0].imag, d[1]] for d in data]), data


def pivots(m):
    pts = dict(m.points)
    return complex(*pts["A0"]), complex(*pts["B0"]), complex(*pts["A"]), complex(*pts["B"])


def reaches_poses(sol, poses):
    """The returned mechanism, solved by the engine at its own inputs, puts P and the coupler at the poses."""
    plan = assur.compile(sol.mechanism)
    st = assur.solve(plan, inputs=np.asarray(sol.inputs), order=0)
    P, A, B = (st.point(n).pos for n in ("P", "A", "B"))
    ang = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
    return (np.allclose(P, poses[:, :2], atol=1e-9)
            and np.allclose(np.angle(np.exp(1j * (ang - ang[0] - (poses[:, 2] - poses[0, 2])))), 0, atol=1e-9))


def has_known(sols):
    return any(abs(pivots(s.mechanism)[0] - A0) < 1e-8 and abs(pivots(s.mechanism)[1] - B0) < 1e-8 for s in sols)


# -- motion generation ----------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [3, 4, 5])
def test_poses_of_a_known_fourbar_give_back_its_dyads(n):
    poses, data = poses_of(np.linspace(0.3, 2.5, n))
    free = None if n == 5 else [[A0.real, A0.imag], [B0.real, B0.imag]]
    sols = exact.motion_candidates(poses, free=free)
    assert has_known(sols)
    known = next(s for s in sols if abs(pivots(s.mechanism)[0] - A0) < 1e-8)
    a0, b0, a, b = pivots(known.mechanism)
    assert abs(a - data[0][2]) < 1e-8 and abs(b - data[0][3]) < 1e-8
    assert np.allclose(known.lengths, [4.0, LA, LB, LC], atol=1e-8)
    assert known.grashof == "crank-rocker"
    assert reaches_poses(known, poses)


def test_five_poses_give_at_most_four_burmester_pairs_each_exact():
    poses, _ = poses_of(np.linspace(0.3, 2.5, 5))
    G, Z = exact.dyads(poses)
    assert 2 <= len(G) <= 4
    d = poses[:, 0] + 1j * poses[:, 1]
    R = np.exp(1j * (poses[:, 2] - poses[0, 2]))
    for g, z in zip(G, Z):          # the circle condition, independently: every pose at the same distance
        r = np.abs(R * (z - d[0]) + d - g)
        assert np.ptp(r) < 1e-9 * r[0]


def test_default_rules_give_exact_dyads_and_working_fourbars():
    for n in (3, 4):
        poses, _ = poses_of(np.linspace(0.3, 2.5, n))
        G, Z = exact.dyads(poses)
        assert len(G) >= 10
        d = poses[:, 0] + 1j * poses[:, 1]
        R = np.exp(1j * (poses[:, 2] - poses[0, 2]))
        r = np.abs(R[None] * (Z[:, None] - d[0]) + d[None] - G[:, None])
        assert np.max(np.ptp(r, axis=1) / r[:, 0]) < 1e-9
        sols = exact.motion_candidates(poses, limit=5)
        assert sols and all(reaches_poses(s, poses) for s in sols)
        assert [s.transmission for s in sols] == sorted((s.transmission for s in sols), reverse=True)


def test_known_pivots_lie_on_the_four_pose_centre_curve():
    poses, _ = poses_of(np.linspace(0.3, 2.5, 4))
    P = Poses(poses)
    # the centre-point curve: det [m_j | h_j] = 0 (module burmester); the known ground pivots are on it and
    # a point off the linkage is not
    dets = [np.linalg.det(P.rows(P.to_local(g), [1, 2, 3])) for g in (A0, B0, 1 + 5j)]
    assert abs(dets[0]) < 1e-9 and abs(dets[1]) < 1e-9 and abs(dets[2]) > 1e-3
    G, Z, res = centre_curve(P)
    assert len(G) > 20 and np.max(res) < 1e-9


def test_branch_defect_is_rejected():
    """Poses on the two assembly branches of one linkage: its dyads fit every pose (the circle condition
    holds), but no single branch carries the coupler through them, so the pair is rejected."""
    left, _ = poses_of([0.3, 1.2])
    right, _ = poses_of([2.1], left=False)
    poses = np.vstack([left, right])
    G, Z = exact.dyads(poses, free=[[A0.real, A0.imag], [B0.real, B0.imag]])
    assert len(G) == 2          # both dyads exist …
    assert not has_known(exact.motion_candidates(poses, free=[[0, 0], [4, 0]]))     # … the four-bar does not


def test_order_defect_is_rejected():
    """A double-rocker whose crank (a rocker) reaches the poses 1, 3, 2 in its only buildable stretch: the
    crank would have to turn back, so the candidate is rejected; the same poses in passing order are kept."""
    global LA, LB, LC
    saved = LA, LB, LC
    try:
        LA, LB, LC = 3.0, 2.0, 2.5           # ground 4: s + l = 2 + 4 > 3 + 2.5 → non-Grashof, the crank rocks
        phis = np.array([0.3, 0.7, 1.1])          # inside the crank's buildable range |φ| ≤ acos(0.198) = 1.371
        poses, _ = poses_of(phis)
        free = [[0, 0], [4, 0]]
        kept = exact.motion_candidates(poses, free=free)
        assert has_known(kept)
        swapped = poses[[0, 2, 1]]
        # the crank angles 0.3, 1.1, 0.7 are in cyclic order only the long way round (ccw 0.3 → 1.1 → 0.7 + 2π,
        # or cw 0.3 → 1.1 − 2π → 0.7 − 2π), through the toggles of the rocking crank
        assert not has_known(exact.motion_candidates(swapped, free=free))
    finally:
        LA, LB, LC = saved


# -- function generation --------------------------------------------------------------------------------
def output_angles(phis):
    return np.array([np.angle(fourbar(p)[3] - B0) for p in phis])


@pytest.mark.parametrize("n", [3, 6])
def test_function_pairs_of_a_known_fourbar_give_it_back(n):
    phis = np.linspace(0.3, 1.7, n)
    psis = output_angles(phis)
    sols = exact.function_candidates(phis, psis, ground=4.0)
    assert sols
    s = sols[0]
    assert np.allclose(s.lengths, [4.0, LA, LB, LC], atol=1e-9)
    # Freudenstein's loop closure (Norton §5.12) holds at every precision point with the returned lengths
    d, a, b, c = s.lengths
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    assert np.allclose(K1 * np.cos(psis) - K2 * np.cos(phis) + K3, np.cos(phis - psis), atol=1e-9)
    # the engine's mechanism: input = φ, output = the rocker's angle from the ground line
    st = assur.solve(assur.compile(s.mechanism), inputs=phis, order=0)
    B = st.point("B").pos
    assert np.allclose(np.arctan2(B[:, 1], B[:, 0] - 4.0), psis, atol=1e-9)
    assert s.residual < 1e-9


def test_chebyshev_spaced_log_task_is_exact_at_its_three_points():
    """y = log10(x) on 1 ≤ x ≤ 2 mapped to 60° of input and of output (the classic Freudenstein task): the
    three Chebyshev-spaced precision points are met exactly by the engine's solution of the design; with 7
    points the least-squares design is returned with its (non-zero) residual."""
    phi0, psi0 = np.radians(40), np.radians(240)
    span = np.radians(60)

    def out(phi):
        x = 1 + (phi - phi0) / span
        return psi0 + span * np.log10(x) / np.log10(2)

    sols = exact.function_candidates((phi0, phi0 + span), out, spacing="chebyshev", n=3)
    assert sols and sols[0].residual < 1e-9
    assert np.allclose(sols[0].inputs, chebyshev_points(3, phi0, phi0 + span))
    seven = exact.function_candidates((phi0, phi0 + span), out, spacing="chebyshev", n=7)
    assert seven and 1e-9 < seven[0].residual < np.radians(1)


def test_chebyshev_points():
    # Norton, Design of Machinery §5.12: x_j = (a + b)/2 − (b − a)/2 · cos((2j − 1)π / 2n)
    assert np.allclose(chebyshev_points(3, 0.0, 1.0), [0.5 - 0.5 * np.cos(np.pi / 6), 0.5, 0.5 + 0.5 * np.cos(np.pi / 6)])


# -- bad input ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("call, where", [
    (lambda: exact.motion_generation(np.zeros((2, 3))), "poses"),
    (lambda: exact.motion_generation([[0, 0, 0], [1, 0, 0.1], [2, 0, np.nan]]), "poses"),
    (lambda: exact.motion_generation(np.eye(5, 3) + np.arange(5)[:, None], free=[[0, 0]]), "free"),
    (lambda: exact.function_generation([0, 1, 0.5], [0, 1, 2]), "inputs"),
    (lambda: exact.function_generation([0, 1], [0, 1]), "inputs"),
    (lambda: exact.function_generation([0, 1, 2], [0, 1, 2], grashof="crankrocker"), "grashof"),
    (lambda: exact.function_generation((0, 1), lambda x: x, spacing="cheb"), "spacing"),
])
def test_bad_input_is_a_spec_error_with_its_location(call, where):
    with pytest.raises(SpecError, match=where):
        call()


# -- seeds for the optimisers ---------------------------------------------------------------------------
def test_seed_rows_reproduce_an_exact_solution_in_a_benchmark_problem():
    """Poses of the benchmark template's sketch design (r = 4, 1.5, 3.5, 3; P at (1, 1)) at the C2 crank angles:
    the exact solution fitted into the C2 problem's variables gives f = 0 at those targets."""
    from pathlib import Path

    from assur.synthesis import Evaluator, problem_from_dict
    from assur.synthesis.seeding import seed_rows
    phis = np.radians([30, 45, 60, 75, 90])
    poses, _ = poses_of(phis)
    sols = [s for s in exact.motion_candidates(poses) if abs(pivots(s.mechanism)[0] - A0) < 1e-8]
    root = Path(__file__).resolve().parents[1] / "examples" / "synthesis"
    data = {"format": "assur-synth/1", "mechanism": "fourbar_benchmark.toml",
            "variables": {n: [0, 50] for n in ("r1", "r2", "r3", "r4")} | {"rcx": [-50, 50], "rcy": [-50, 50]},
            "parameters": {"O4.x": "r1", "crank.length": "r2", "coupler.length": "r3", "rocker.length": "r4",
                           "coupler.P.distance": "hypot(rcx, rcy)", "coupler.P.angle": "atan2(rcy, rcx)"},
            "targets": {"point": "P", "xy": poses[:, :2].tolist(), "inputs": phis.tolist()},
            "objective": {"deviation": "squared"}}
    problem = problem_from_dict(data, base_dir=root)
    X = seed_rows(problem, sols)
    assert X.shape == (1, 6)
    assert np.allclose(X[0], [4, 1.5, 3.5, 3, 1, 1], atol=1e-6)
    assert Evaluator(problem)(X).objective[0] < 1e-12


def test_seed_designs_from_pose_targets():
    """A problem with three pose targets of the sketch design at 30°, 60°, 90° (prescribed timing, frame fixed
    at O2 = origin, O4 on the x axis): the motion generator with the known ground pivots as the free choice is
    fitted into the problem's variables and meets the poses (f = 0)."""
    from pathlib import Path

    from assur.synthesis import Evaluator, problem_from_dict
    from assur.synthesis.seeding import seed_designs
    phis = np.radians([30, 60, 90])
    poses, _ = poses_of(phis)
    data = {"format": "assur-synth/1", "mechanism": "fourbar_benchmark.toml",
            "variables": {n: [0, 50] for n in ("r1", "r2", "r3", "r4")} | {"rcx": [-50, 50], "rcy": [-50, 50]},
            "parameters": {"O4.x": "r1", "crank.length": "r2", "coupler.length": "r3", "rocker.length": "r4",
                           "coupler.P.distance": "hypot(rcx, rcy)", "coupler.P.angle": "atan2(rcy, rcx)"},
            "targets": {"kind": "poses", "link": "coupler", "point": "P", "poses": poses.tolist(),
                        "inputs": phis.tolist()},
            "objective": {"deviation": "squared"}}
    problem = problem_from_dict(data, base_dir=Path(__file__).resolve().parents[1] / "examples" / "synthesis")
    X = seed_designs(problem, free=[[0, 0], [4, 0]])
    assert np.allclose(X, [[4, 1.5, 3.5, 3, 1, 1]], atol=1e-6)
    assert Evaluator(problem)(X).objective[0] < 1e-12


# -- a candidate that misses its own precision points is rejected, with its residual and the reason -----------
def _square_task(phi):
    """y = x² on 1 ≤ x ≤ 3, x onto the crank's 40° → 130°, y onto the rocker's 230° → 320° (the task of issue 25)."""
    x = 1 + (np.degrees(phi) - 40) / 90 * 2
    return np.radians(230 + (x ** 2 - 1) / 8 * 90)


def _engine_output(mech, phis):
    """The rocker angle B0 → B the engine gives at the crank inputs ``phis`` (rad), on the sketch's branch."""
    plan = assur.compile(mech)
    st = assur.solve(plan, inputs=np.asarray(phis), order=0)
    B, B0 = st.point("B").pos, np.asarray(mech.sketch("B0"))
    return np.arctan2(B[:, 1] - B0[1], B[:, 0] - B0[0])


def test_a_function_generator_on_the_other_branch_is_rejected_with_its_residual():
    span = np.radians([40, 130])
    sols = exact.function_candidates(span, _square_task, spacing="chebyshev", n=3)
    assert list(sols) == [] and "branch defect" in sols.reason
    assert exact.function_generation(span, _square_task, spacing="chebyshev", n=3) == []
    [bad] = sols.rejected
    assert bad.rank == 0 and bad.defects == ("branch: point 2 on the other assembly branch",)
    # the engine, driven along the candidate's own branch, misses the middle point by the residual reported
    phis = chebyshev_points(3, *span)
    flip = np.pi if "+ π" in bad.mechanism.description else 0.0
    err = np.abs(np.angle(np.exp(1j * (_engine_output(bad.mechanism, phis) + flip - _square_task(phis)))))
    assert err[0] < 1e-9 and err[2] < 1e-9 and err[1] > np.radians(5)
    assert bad.residual == pytest.approx(err.max(), rel=1e-6)
    assert "rejected (branch" in repr(bad) and "residual 0.17" in repr(bad)


def test_kept_function_generators_meet_their_points_and_say_how_they_are_ranked():
    phis = np.linspace(0.3, 1.7, 3)
    psis = output_angles(phis)
    sols = exact.function_candidates(phis, psis, ground=4.0)
    assert "residual" in sols.criterion and "transmission" in sols.criterion and sols.reason is None
    for k, s in enumerate(sols, start=1):
        assert s.rank == k and s.kept and s.defects == ()
        err = np.abs(np.angle(np.exp(1j * (_engine_output(s.mechanism, phis) - psis))))
        assert err.max() <= 1e-9 and s.residual <= 1e-9
    r = repr(sols[0])
    assert r.startswith("ExactSolution(#1: ") and "residual" in r and "transmission" in r
    assert sols[0].rotatable == (sols[0].grashof in ("crank-rocker", "double-crank"))
    assert repr(sols).startswith("Candidates: ")


def test_motion_and_slider_candidates_count_what_they_drop():
    poses = [[0, 0, 0], [1, 0.3, 0.2], [2, 0.2, 0.5]]
    m = exact.motion_candidates(poses, limit=3)
    assert len(m) == 3 and [s.rank for s in m] == [1, 2, 3] and sum(m.counts.values()) > 0
    assert all(s.residual <= 1e-6 * 2 for s in m)
    sc = exact.slider_candidates([0.3, 1.0, 1.7], [3.4, 3.1, 2.6])
    assert sc and sc[0].rank == 1 and repr(sc[0]).startswith("SliderSolution(#1: ")
