"""Synthesis target kinds: function generation (input/output angle pairs of a link), motion generation (poses of
a link) and the defect check (targets met in order with the whole stretch between them buildable).

The reference values are computed independently here: the crank-rocker of examples/crank_rocker.toml (ground
O2 = (0, 0), O4 = (100, 0) mm, crank 40, coupler 120, rocker 80 mm, P 60 mm from A at 30° from A → B, B on the
left of A → O4, its sketch's branch) is solved by intersecting two circles in this file."""
from pathlib import Path

import numpy as np
import pytest

from assur.errors import SpecError
from assur.synthesis import Evaluator, load_problem, problem_from_dict, synthesize

ROOT = Path(__file__).resolve().parents[1]
SYN = ROOT / "examples" / "synthesis"
TEMPLATE = str(ROOT / "examples" / "crank_rocker.toml")
GROUND, CRANK, COUPLER, ROCKER = 100.0, 40.0, 120.0, 80.0
P_DIST, P_ANGLE = 60.0, np.radians(30.0)


def fourbar(q, crank=CRANK, coupler=COUPLER, rocker=ROCKER):
    """Independent closed form: (A, B, P (…, 2) mm, rocker angle ψ, coupler angle) at crank angles q (rad);
    NaN where the loop cannot close."""
    q = np.asarray(q, dtype=float)
    A = crank * np.stack([np.cos(q), np.sin(q)], axis=-1)
    O4 = np.array([GROUND, 0.0])
    d = O4 - A
    L = np.linalg.norm(d, axis=-1)
    with np.errstate(invalid="ignore"):
        a = (coupler**2 - rocker**2 + L**2) / (2 * L)
        h = np.sqrt(coupler**2 - a**2)
    u = d / L[..., None]
    left = np.stack([-u[..., 1], u[..., 0]], axis=-1)          # B on the left of A → O4
    B = A + a[..., None] * u + h[..., None] * left
    phi = np.arctan2(B[..., 1] - A[..., 1], B[..., 0] - A[..., 0])
    P = A + P_DIST * np.stack([np.cos(phi + P_ANGLE), np.sin(phi + P_ANGLE)], axis=-1)
    psi = np.arctan2(B[..., 1], B[..., 0] - GROUND)
    return A, B, P, psi, phi


def problem(targets, variables=None, **extra):
    doc = {"format": "assur-synth/1", "mechanism": TEMPLATE,
           "variables": variables or {"crank.length": [10, 60], "rocker.length": [40, 120]},
           "targets": targets, "objective": {"deviation": extra.pop("deviation", "squared")}}
    doc.update(extra)
    return problem_from_dict(doc, base_dir=ROOT)


TEMPLATE_X = np.array([[CRANK, ROCKER]]) / 1000.0          # the template's own lengths, SI


def wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


# -- function generation --------------------------------------------------------------------------------
def test_function_deviation_equals_an_independent_computation():
    """Relative output: ε_i = (ψ_i − ψ_0) − (y_i − y_0); Σ ε² in deg², ψ from the closed form above."""
    q = np.radians([30.0, 50.0, 70.0, 90.0])
    psi = fourbar(q)[3]
    delta = np.array([0.0, 0.4, -0.7, 1.1])                    # degrees added to the targets
    y = np.degrees(psi - psi[0]) + 17.0 + delta                # any output offset: the output is relative
    pb = problem({"kind": "function", "link": "rocker", "pairs": np.c_[np.degrees(q), y].tolist()})
    e = Evaluator(pb)(TEMPLATE_X, detail=True)
    assert e.feasible[0]
    assert e.objective[0] == pytest.approx(np.sum((delta - delta[0]) ** 2), rel=1e-9)
    assert e.quantities["distances"][0] == pytest.approx(np.abs(delta - delta[0]), abs=1e-9)
    # absolute output: ε_i = ψ_i − y_i
    pb = problem({"kind": "function", "link": "rocker", "output": "absolute",
                  "pairs": np.c_[np.degrees(q), np.degrees(psi) + delta].tolist()}, deviation="distance")
    e = Evaluator(pb)(TEMPLATE_X)
    assert e.objective[0] == pytest.approx(np.abs(delta).sum(), rel=1e-9)


def test_a_known_fourbars_own_function_gives_zero():
    q = np.radians(np.linspace(20, 140, 7))
    psi = fourbar(q)[3]
    pb = problem({"kind": "function", "link": "rocker", "pairs": np.c_[np.degrees(q), np.degrees(psi)].tolist()})
    e = Evaluator(pb)(TEMPLATE_X)
    assert e.feasible[0] and e.objective[0] < 1e-18
    # uniform timing: the start is a design variable; the pairs keep their spacing
    pb = problem({"kind": "function", "link": "rocker", "timing": "uniform", "start": "phi0",
                  "pairs": np.c_[np.degrees(q - q[0]), np.degrees(psi)].tolist()},
                 variables={"crank.length": [10, 60], "rocker.length": [40, 120],
                            "phi0": {"bounds": [0, 360], "kind": "angle"}})
    e = Evaluator(pb)(np.c_[TEMPLATE_X, [[q[0]]]])
    assert e.feasible[0] and e.objective[0] < 1e-18
    # free timing: the input spacing error counts too, sqrt(Δin² + Δout²) per pair
    names = [f"t{i}" for i in range(len(q))]
    pb = problem({"kind": "function", "link": "rocker", "timing": "free", "variables": names,
                  "pairs": np.c_[np.degrees(q), np.degrees(psi)].tolist()},
                 variables={"crank.length": [10, 60], "rocker.length": [40, 120],
                            **{n: {"bounds": [0, 360], "kind": "angle"} for n in names}}, deviation="distance")
    shifted = q + np.radians([0, 0.5, 0, 0, 0, 0, 0])
    e = Evaluator(pb)(np.c_[TEMPLATE_X, [shifted]], detail=True)
    psi_s = fourbar(shifted)[3]
    d_out = np.degrees(wrap(psi_s - psi_s[0] - (psi - psi[0])))
    d_in = np.degrees(shifted - shifted[0] - (q - q[0]))
    assert e.objective[0] == pytest.approx(np.hypot(d_in, d_out).sum(), rel=1e-9)


# -- motion generation ----------------------------------------------------------------------------------
def test_pose_deviation_equals_an_independent_computation():
    """Σ (|Δp| + w·|Δθ|) with w in mm per radian; Δθ of the coupler line A → B."""
    q = np.radians([40.0, 80.0, 120.0])
    _, _, P, _, phi = fourbar(q)
    dp = np.array([[0.5, -0.2], [0.0, 0.0], [-1.0, 2.0]])
    dth = np.radians([0.0, 2.0, -3.0])
    w = 50.0
    poses = np.c_[P + dp, np.degrees(phi + dth)]
    pb = problem({"kind": "poses", "link": "coupler", "point": "P", "poses": poses.tolist(), "angle_weight": w,
                  "inputs": np.degrees(q).tolist()}, deviation="distance")
    e = Evaluator(pb)(TEMPLATE_X)
    expected = np.linalg.norm(dp, axis=1) + w * np.abs(dth)
    assert e.objective[0] == pytest.approx(expected.sum(), rel=1e-9)
    pb = problem({"kind": "poses", "link": "coupler", "point": "P", "poses": poses.tolist(), "angle_weight": w,
                  "inputs": np.degrees(q).tolist()}, deviation="squared")
    assert Evaluator(pb)(TEMPLATE_X).objective[0] == pytest.approx(np.sum(expected**2), rel=1e-9)


def test_a_known_fourbars_own_poses_give_zero_and_the_default_angle_weight():
    q = np.radians([40.0, 100.0, 160.0])
    _, _, P, _, phi = fourbar(q)
    names = ["t1", "t2", "t3"]
    pb = problem({"kind": "poses", "link": "coupler", "point": "P", "poses": np.c_[P, np.degrees(phi)].tolist(),
                  "timing": "free", "variables": names},
                 variables={"crank.length": [10, 60], "rocker.length": [40, 120],
                            **{n: {"bounds": [0, 360], "kind": "angle"} for n in names}})
    e = Evaluator(pb)(np.c_[TEMPLATE_X, [q]])
    assert e.feasible[0] and e.objective[0] < 1e-18
    # default angle weight: the largest distance between two pose positions (mm per rad), kept in SI
    spread = max(np.linalg.norm(a - b) for a in P for b in P)
    assert pb.targets.angle_weight == pytest.approx(spread / 1000.0)


# -- defects ----------------------------------------------------------------------------------------------
def _poses_free(q, free_timing="explicit", **constraints):
    """The template's coupler poses at crank angles q as free-timing targets (the angles searched explicitly unless
    ``free_timing`` says "inner")."""
    _, _, P, _, phi = fourbar(q)
    names = [f"t{i}" for i in range(len(q))]
    return problem({"kind": "poses", "link": "coupler", "point": "P", "poses": np.c_[P, np.degrees(phi)].tolist(),
                    "timing": "free", "variables": names, "free_timing": free_timing},
                   variables={"crank.length": [10, 60], "rocker.length": [40, 120],
                              **{n: {"bounds": [0, 360], "kind": "angle"} for n in names}}, **constraints)


def test_an_order_defect_is_penalised():
    """Poses met at the crank angles 40°, 160°, 100°: each pose is met exactly, but out of order in the
    direction of the input; the order measure is the excess of the gaps' sum over one turn."""
    q = np.radians([40.0, 100.0, 160.0])
    pb = _poses_free(q)
    assert "defects" in pb.constraints                         # on by default for poses
    ev = Evaluator(pb)
    swapped = q[[0, 2, 1]]
    e = ev(np.c_[TEMPLATE_X, [q]])
    assert e.feasible[0] and e.objective[0] < 1e-18            # in order: fine
    e = ev(np.c_[TEMPLATE_X, [swapped]])
    gaps = np.mod(np.diff(swapped), 2 * np.pi).sum()
    assert not e.feasible[0]
    assert e.violations["defects"][0] == pytest.approx(gaps - 2 * np.pi)
    assert e.penalised[0] >= pb.infeasible_offset
    assert e.quantities["defects.order"][0] == pytest.approx(np.degrees(gaps - 2 * np.pi))
    # switched off, the same design counts
    off = _poses_free(q, constraints={"defects": False})
    assert "defects" not in off.constraints
    assert Evaluator(off)(np.c_[TEMPLATE_X, [swapped]]).feasible[0]
    # solved per design (the default for poses), the template's own crank angles come back, in order
    inner = Evaluator(_poses_free(q, free_timing="inner"))(np.c_[TEMPLATE_X, [swapped]])
    assert inner.feasible[0] and inner.objective[0] < 1e-18
    assert np.allclose(inner.x[0, -3:], q, atol=1e-9)


def test_an_unbuildable_stretch_is_penalised_by_its_share():
    """A crank of 90 mm cannot turn fully (|A − O4| must stay within [40, 200] mm: not near 0°); targets at
    300° and 60° are each assemblable, but the stretch between them (through 0°) is not: the share of the cycle
    samples in it where the loop cannot close, counted here from the circle condition."""
    q = np.radians([300.0, 60.0])
    crank = 90.0
    psi = fourbar(q, crank=crank)[3]
    assert np.all(np.isfinite(psi))
    pb = problem({"kind": "function", "link": "rocker", "pairs": np.c_[np.degrees(q), np.degrees(psi)].tolist()})
    e = Evaluator(pb)(np.array([[crank, ROCKER]]) / 1000.0)
    M = pb.cycle_samples
    s = np.linspace(0, 2 * np.pi, M, endpoint=False)
    inside = np.mod(s - q[0], 2 * np.pi) <= np.mod(q[1] - q[0], 2 * np.pi) + 1e-12
    L = np.hypot(crank * np.cos(s) - GROUND, crank * np.sin(s))
    closes = (L >= COUPLER - ROCKER) & (L <= COUPLER + ROCKER)
    share = np.count_nonzero(inside & ~closes) / np.count_nonzero(inside)
    assert share > 0
    assert not e.feasible[0]
    assert e.violations["defects"][0] == pytest.approx(share)
    assert e.violations["assembly"][0] == 0                     # the targets themselves assemble


def test_defects_can_be_asked_for_point_targets_too():
    q = np.radians([40.0, 100.0, 160.0])
    P = fourbar(q)[2]
    pb = problem({"point": "P", "xy": P.tolist(), "inputs": np.degrees(q[[0, 2, 1]]).tolist()},
                 constraints={"use": ["defects"]})
    e = Evaluator(pb)(TEMPLATE_X)
    assert not e.feasible[0] and e.violations["defects"][0] > 0
    assert "defects" not in problem({"point": "P", "xy": P.tolist(), "inputs": np.degrees(q).tolist()}).constraints


# -- bad input ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("targets, where, words", [
    ({"kind": "function", "link": "rokcer", "pairs": [[0, 0], [10, 5]]}, "targets.link", "unknown link 'rokcer'"),
    ({"kind": "function", "link": "rocker", "pairs": [[0, 0, 1], [10, 5, 2]]}, "targets.pairs", "(2, 3)"),
    ({"kind": "poses", "link": "coupler", "point": "P", "poses": [[0, 0], [1, 1]], "inputs": [0, 1]},
     "targets.poses", "[x, y, angle]"),
    ({"kind": "poses", "link": "coupler", "point": "O4", "poses": [[0, 0, 0]], "inputs": [0]},
     "targets.point", "not on link 'coupler'"),
    ({"kind": "poses", "link": "coupler", "point": "P", "poses": [[0, 0, 0]], "timing": "path"},
     "targets.timing", "for poses targets"),
    ({"kind": "curve", "point": "P", "xy": [[0, 0]]}, "targets.kind", "must be one of points, function, poses"),
    ({"kind": "function", "link": "rocker", "pairs": [[0, 0]], "point": "P"}, "targets.point", "unknown key"),
    ({"kind": "poses", "link": "coupler", "point": "P", "poses": [[0, 0, 0]], "inputs": [0], "angle_weight": -1},
     "targets.angle_weight", "negative"),
])
def test_bad_targets_are_located(targets, where, words):
    with pytest.raises(SpecError) as exc:
        problem(targets)
    hits = [(p, m) for p, m in exc.value.problems if p == where]
    assert hits and any(words in m for _, m in hits), exc.value.problems


def test_bad_defects_switch_and_acceleration_of_a_function_are_located():
    t = {"kind": "function", "link": "rocker", "pairs": [[0, 0], [10, 5]]}
    with pytest.raises(SpecError) as exc:
        problem(t, constraints={"defects": "yes"})
    assert any(p == "constraints.defects" for p, _ in exc.value.problems)
    with pytest.raises(SpecError) as exc:
        problem(t, objective={"deviation": "squared", "terms": [{"quantity": "acceleration"}]})
    assert any(p == "objective.terms[0].quantity" and "acceleration" in m for p, m in exc.value.problems)


# -- the examples ---------------------------------------------------------------------------------------------
def test_the_motion_example_holds_the_poses_of_its_source_design():
    """examples/synthesis/motion_three_poses.toml: the poses of the four-bar its description states, to the file's
    rounding (0.005 mm, 0.00005°)."""
    pb = load_problem(SYN / "motion_three_poses.toml")
    assert pb.targets.kind == "poses" and "defects" in pb.constraints
    x = pb.to_si([[0, 0, 400, 150, 350, 300, 100, 100, 40, 100, 160]])
    e = Evaluator(pb)(x, detail=True)
    assert e.feasible[0]
    assert np.all(e.quantities["distances"][0] < 0.005 * np.sqrt(2) + 100 * np.radians(0.00005) + 1e-9)


@pytest.mark.slow
def test_the_examples_reach_their_tasks_with_default_options():
    """Motion: three poses of a known four-bar are met exactly (deviation 0 is reachable). Function: y = log10 x
    within 0.5° of the 45° output swing at every pair (about 1 % of the range), on a defect-free design."""
    r = synthesize(load_problem(SYN / "motion_three_poses.toml"), seed=1)
    assert r.feasible and r.objective <= 1e-12                 # the file's [solver] target
    r = synthesize(load_problem(SYN / "function_fourbar.toml"), seed=1)
    assert r.feasible and max(r.details["quantities"]["distances"]) < 0.5


def test_a_design_working_over_a_range_is_written_as_a_loadable_mechanism():
    """A function generator whose crank cannot reach the template's sketch angle (60°) is sketched at the nearest
    crank angle where it assembles: the file loads back to the same dimensions and the same output angles (the
    same branch), checked against the closed form above."""
    import assur
    from assur.synthesis.design import mechanism_with_params
    pb = problem({"kind": "function", "link": "rocker", "pairs": [[200, 0], [230, 10]]})
    rocker = 20.0               # |A − O4| must lie in [100, 140] mm: 87 mm at 60°, 129 mm at 130°
    params = Evaluator(pb).params(np.array([[CRANK, rocker]]) / 1000.0)[0]
    plan = pb.plan
    assert not assur.solve(plan, params, plan.sketch_inputs[None, :]).valid.all()
    assert np.isnan(fourbar(plan.sketch_inputs, rocker=rocker)[3]).all()
    m = mechanism_with_params(plan, params)
    back = assur.compile(assur.loads(assur.dumps(m)))
    assert back.defaults[back.param_index("rocker.length")] == pytest.approx(rocker / 1000.0)
    q = np.radians([130.0, 150.0, 175.0])
    got = assur.solve(back, inputs=q).body_angle[:, back.body_names.index("rocker")]
    assert np.all(np.isfinite(fourbar(q, rocker=rocker)[3]))
    assert got == pytest.approx(fourbar(q, rocker=rocker)[3], abs=1e-9)
