"""Synthesis terms from the force analysis: forces.torque_peak, forces.torque_rms, forces.reaction_peak
(issue: forces — kinetostatics by Assur groups; synthesis for a smaller motor)."""
import dataclasses
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.errors import SpecError
from assur.kinetostatics.gait import gait_forces, phase_shifts, population_foot_loads
from assur.model.dynamics import Dynamics, MassProperties
from assur.synthesis import Evaluator, load_problem, problem_from_dict, synthesize

ROOT = Path(__file__).resolve().parents[1]
LEG = ROOT / "examples" / "walker_fourbar.toml"
MOTOR = ROOT / "examples" / "synthesis" / "walker_fourbar_motor.toml"
M = 72                                   # cycle samples of the problems below (5°)
FORCE_Q = ("forces.torque_peak", "forces.torque_rms", "forces.reaction_peak")
#: the published leg of paper 004 (docs/papers/004.md §5): O1 = (0.567, 0.615), l1, l2, l3, l4 (m), β (deg)
PAPER004 = [0.567, 0.615, 0.27, 0.638, 0.65, 0.654, 70.8]
VARIABLES = {"O1.x": [0.3, 0.9], "O1.y": [0.3, 0.9], "crank.length": [0.15, 0.35], "rocker.length": [0.4, 0.9],
             "coupler.length": [0.4, 0.9], "coupler.H.distance": [0.4, 0.9], "coupler.H.angle": [40, 110]}


def force_problem(mechanism, samples=M):
    doc = {"format": "assur-synth/1",
           "variables": VARIABLES,
           "objective": {"deviation": "none", "terms": [{"quantity": "forces.torque_peak"}]},
           "constraints": {"limits": [{"quantity": "forces.torque_rms", "max": 1e6},
                                      {"quantity": "forces.reaction_peak", "max": 1e6}]},
           "options": {"cycle_samples": samples}}
    return problem_from_dict(doc, mechanism=mechanism)


def leg_variants():
    """The file's two-leg module with a 300 N body; one leg carrying the whole weight; masses only, no gait."""
    m = assur.load(LEG)
    return {"module": m,
            "one_leg": dataclasses.replace(m, gait=dataclasses.replace(m.gait, phases=(0.0,))),
            "no_gait": dataclasses.replace(m, gait=None)}


def independent_quantities(plan, params):
    """The three quantities of one design, computed here from assur.forces alone: the legs at q + phase as a
    batch (M, n_legs); the foot's contact arc from the sampled foot path (the samples of smallest and largest
    x split the turn, the arc of lower mean height carries); each foot on the ground takes W / n_on."""
    m = plan.mechanism
    q = np.linspace(0.0, 2 * np.pi, M, endpoint=False)
    phases = np.asarray(m.gait.phases if m.gait is not None else (0.0,))
    qq = q[:, None] + phases[None, :]
    loads = None
    if m.gait is not None and m.gait.weight is not None:
        pos = assur.solve(plan, params, q[:, None]).point(m.gait.foot).pos
        x, y = pos[:, 0], pos[:, 1]
        ia, ib = int(np.argmin(x)), int(np.argmax(x))
        arc1 = [(ia + k) % M for k in range((ib - ia) % M + 1)]
        arc2 = [(ib + k) % M for k in range((ia - ib) % M + 1)]
        contact = set(arc1 if y[arc1].mean() <= y[arc2].mean() else arc2)
        shift = np.rint(phases * M / (2 * np.pi)).astype(int)
        on = np.array([[(j + s) % M in contact for s in shift] for j in range(M)])
        N = np.where(on, m.gait.weight / np.maximum(on.sum(axis=1, keepdims=True), 1), 0.0)
        loads = [(m.gait.foot, N[..., None] * np.array([0.0, 1.0]))]
    f = assur.forces(plan, params, qq[..., None], point_loads=loads, backend="numpy")
    torque = f.driver[..., 0].sum(axis=1)                 # the common shaft: Σ over the legs
    reac = f.magnitudes[..., f.joint_pairs]
    return {"forces.torque_peak": np.max(np.abs(torque)), "forces.torque_rms": np.sqrt(np.mean(torque ** 2)),
            "forces.reaction_peak": np.max(reac)}


@pytest.mark.parametrize("variant", ["module", "one_leg", "no_gait"])
def test_force_quantities_equal_a_per_design_force_analysis(variant):
    mech = leg_variants()[variant]
    prob = force_problem(mech)
    rng = np.random.default_rng(4)
    X = np.vstack([prob.to_si([PAPER004]), prob.to_si(PAPER004 * (1 + 0.08 * (rng.random((5, 7)) - 0.5)))])
    ev = Evaluator(prob, backend="numpy")
    e = ev(X)
    params = ev.params(X)
    checked = 0
    for d in range(len(X)):
        if e.quantities["unbuildable"][d] > 0:
            continue
        ref = independent_quantities(prob.plan, params[d])
        for k in FORCE_Q:
            assert e.quantities[k][d] == pytest.approx(ref[k], rel=1e-9), (variant, d, k)
        checked += 1
    assert checked >= 3
    # the evaluator's own torque is the objective
    ok = e.feasible
    np.testing.assert_array_equal(e.objective[ok], e.quantities["forces.torque_peak"][ok])


def test_compiled_backend_gives_the_same_quantities():
    pytest.importorskip("numba")
    prob = force_problem(leg_variants()["no_gait"])       # no point loads: the compiled force kernel applies
    X = prob.to_si([PAPER004, [0.6, 0.6, 0.26, 0.64, 0.66, 0.65, 72]])
    a, b = Evaluator(prob, backend="numpy")(X), Evaluator(prob, backend="numba")(X)
    for k in FORCE_Q:
        np.testing.assert_allclose(a.quantities[k], b.quantities[k], rtol=1e-9)


def test_unassembled_designs_get_nan_and_do_not_disturb_the_others():
    prob = force_problem(assur.load(LEG))
    good = prob.to_si([PAPER004])
    broken = prob.to_si([[0.9, 0.9, 0.35, 0.4, 0.4, 0.654, 70.8]])   # |O O1| = 1.27 m > l1 + l2 + l3 spans
    ev = Evaluator(prob, backend="numpy")
    e = ev(np.vstack([good, broken]))
    assert e.quantities["unbuildable"][1] > 0
    for k in FORCE_Q:
        assert np.isnan(e.quantities[k][1])
        assert e.quantities[k][0] == ev(good).quantities[k][0]
    assert e.feasible[0] and not e.feasible[1]
    assert np.isfinite(e.penalised).all() and e.penalised[1] > e.penalised[0]


def test_population_foot_loads_share_the_weight_on_a_circle():
    """A foot on the unit circle, 8 samples: x is least at sample 4 (q = π) and greatest at 0, and the lower
    arc is samples 4…7, 0. Two legs 180° apart (4 samples): by hand, both feet are down at samples 0 and 4
    (W/2 each), one foot at the others (W on it)."""
    q = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    pos = np.stack([np.cos(q), np.sin(q)], axis=-1)[None]
    W = 300.0
    F = population_foot_loads(pos, np.ones((1, 8), bool), (0.0, np.pi), W, up=(0.0, 1.0), ground=(1.0, 0.0))
    leg0 = [W / 2, 0, 0, 0, W / 2, W, W, W]
    leg1 = [W / 2, W, W, W, W / 2, 0, 0, 0]
    np.testing.assert_allclose(F[0, :, :, 1], np.array([leg0, leg1]).T)
    np.testing.assert_array_equal(F[0, :, :, 0], 0.0)
    bad = population_foot_loads(pos, np.array([[True] * 7 + [False]]), (0.0,), W, (0.0, 1.0), (1.0, 0.0))
    assert np.isnan(bad).all()


def test_phases_must_fall_on_the_cycle_samples():
    assert phase_shifts((0.0, np.pi), 72).tolist() == [0, 36]
    with pytest.raises(SpecError, match="must fall on the 72 samples"):
        phase_shifts((0.0, np.radians(7.0)), 72)
    m = assur.load(LEG)
    odd = dataclasses.replace(m, gait=dataclasses.replace(m.gait, phases=(0.0, np.radians(7.0))))
    with pytest.raises(SpecError) as exc:
        force_problem(odd)
    assert exc.value.problems[0][0] == "options.cycle_samples"


def test_forces_quantity_without_masses_is_a_located_error():
    m = assur.load(LEG)
    bare = dataclasses.replace(m, dynamics=None, gait=dataclasses.replace(m.gait, weight=None))
    with pytest.raises(SpecError) as exc:
        force_problem(bare)
    where = [p for p, _ in exc.value.problems]
    assert where == ["objective.terms[0].quantity", "constraints.limits[0].quantity",
                     "constraints.limits[1].quantity"]
    assert "forces.torque_peak needs masses, loads or [gait] weight in the mechanism" in str(exc.value)
    # any one of them is enough: a mass, a load or a body weight
    for dyn, gait in ((Dynamics(bodies=(("crank", MassProperties(mass=1.0)),)), bare.gait),
                      (None, m.gait)):
        force_problem(dataclasses.replace(bare, dynamics=dyn, gait=gait))


def test_cli_reports_a_forces_term_on_a_mechanism_without_masses(tmp_path, capsys):
    (tmp_path / "p.toml").write_text(
        f'format = "assur-synth/1"\nmechanism = "{(ROOT / "examples" / "crank_rocker.toml").as_posix()}"\n'
        '[variables]\n"crank.length" = [10, 30]\n[objective]\ndeviation = "none"\n'
        '[[objective.terms]]\nquantity = "forces.torque_rms"\n')
    assert main(["synth", str(tmp_path / "p.toml")]) == 1
    err = capsys.readouterr().err
    assert "objective.terms[0].quantity: forces.torque_rms needs masses, loads or [gait] weight" in err
    assert "Traceback" not in err


def test_example_lowers_the_peak_motor_torque_within_the_limits():
    """examples/synthesis/walker_fourbar_motor.toml: the optimum's module shaft torque, computed independently
    with kinetostatics.gait_forces (exact contact arc, 720 samples), is well below the paper's leg's, and its
    exact gait keeps the problem's step and lift limits."""
    prob = load_problem(MOTOR)
    plan = prob.plan
    start = Evaluator(prob)(prob.to_si([PAPER004]))
    assert start.feasible[0]                               # the paper's leg is a feasible start
    res = synthesize(prob, "de", seed=1, popsize=10, budget=1500)
    assert res.feasible
    params = res.params()
    before = np.nanmax(np.abs(assur.Study(plan, steps=720).force_cycle.gait.module_driver))
    after_g = assur.Study(plan, params, steps=720).force_cycle.gait
    after = np.max(np.abs(after_g.module_driver))
    assert np.all(after_g.forces.valid)
    assert after < 0.8 * before
    gm = assur.gait_metrics(plan, params)
    assert gm.step_length >= 0.79 and gm.lift >= 0.19
    assert res.details["quantities"]["transmission.min"] >= 30
