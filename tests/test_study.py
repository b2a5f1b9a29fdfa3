"""The Study: one solved run per (plan, params, steps) serves every field and every face.

The solve counts are taken at the engine's one entry (``assur.engine.api.solve`` prepares every batch with
``prepare_batch``); a batch of a whole run's samples (720 by default) is a run, any smaller one a refinement (the
roots of dead centres and extremes, refined together in batches, the buildable edges, the candidates of an extreme).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import assur
import assur.engine.api as api
from assur.analysis.study import Study
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


@pytest.fixture
def solves(monkeypatch):
    """The batch sizes of every engine solve made while the fixture is active (a list that grows)."""
    sizes = []
    prepare = api.prepare_batch

    def counting(plan, params, inputs):
        p, q = prepare(plan, params, inputs)
        sizes.append(math.prod(np.broadcast_shapes(p.shape[:-1], q.shape[:-1])))
        return p, q
    monkeypatch.setattr(api, "prepare_batch", counting)
    return sizes


def runs_and_refinements(sizes, steps: int = 720):
    """(the batch sizes of the runs, the samples of the refinements)."""
    return [n for n in sizes if n >= steps], sum(n for n in sizes if n < steps)


def test_the_summary_of_a_walking_leg_solves_its_turn_once_and_its_contact_arc_once(walking_fourbar_plan, solves):
    Study(walking_fourbar_plan).as_dict()
    runs, refined = runs_and_refinements(solves)
    assert runs == [720, 720]       # the turn, then the contact arc at 720 samples (the gait's time means)
    assert refined < 400


@pytest.mark.slow
@pytest.mark.parametrize("name, runs, refined", [
    # the turn (720) and a walking leg's contact arc (720, the gait's time means over the arc); the refinements are
    # the roots of the gait's extremes, the dead centres, the output link's extremes, the buildable edges and the
    # force figure at its peak input. A geared leg's constant-speed window puts hundreds of roots of the speed's
    # derivative on its contact arc: its bound is larger.
    ("walker_fourbar", [720, 720], 400),
    ("jansen", [720, 720], 400),
    ("crank_rocker", [720], 100),
    ("slider_crank", [720], 100),
    ("walker_fourbar_geared", [720, 720], 6000),
    ("rssr", [720], 100),
])
def test_the_report_solves_one_turn_and_only_refines_it(name, runs, refined, solves, tmp_path):
    assert main(["report", str(EXAMPLES / f"{name}.toml"), "-o", str(tmp_path / "r"), "--frames", "36"]) == 0
    got_runs, got_refined = runs_and_refinements(solves)
    assert got_runs == runs and got_refined <= refined, (got_runs, got_refined)


def test_frames_are_the_runs_samples_and_equal_a_fresh_solve():
    plan = assur.compile(assur.load(EXAMPLES / "jansen.toml"))
    study = Study(plan)
    inputs, state = study.frames(36)
    fresh = assur.solve(plan, None, np.linspace(0, 2 * math.pi, 36, endpoint=False)[:, None], order=2)
    assert np.allclose(inputs[:, 0], fresh.inputs[:, 0], rtol=0, atol=1e-14)
    scale = plan.length_scale
    for a, b in ((state.pos, fresh.pos), (state.vel, fresh.vel), (state.acc, fresh.acc)):
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * scale)
    assert np.allclose(state.body_angle, fresh.body_angle, rtol=0, atol=1e-12)


def test_a_taken_state_is_the_state_of_its_inputs():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    q = np.linspace(0, 2 * math.pi, 90, endpoint=False)
    st = assur.solve(plan, None, q[:, None], order=2)
    idx = (np.arange(90)[:, None] + np.array([0, 45])[None, :]) % 90      # two legs half a turn apart
    legs = st.take(idx)
    ref = assur.solve(plan, None, q[idx][..., None], order=2)
    assert legs.shape == (90, 2) and legs.n_unbuildable == 0
    assert np.array_equal(legs.pos, ref.pos) and np.array_equal(legs.acc, ref.acc)
    assert np.array_equal(legs.body_omega, ref.body_omega)


def test_a_geared_leg_has_its_four_bars_dead_centres_in_the_motors_angle(geared_leg_plan, walking_fourbar_plan):
    """The geared leg's crank turns through the gear law; its dead centres, found in the motor's angle, are where
    the crank reaches the plain four-bar's dead-centre angles (the same four-bar: walker_fourbar.toml, crank zero 0,
    counter-clockwise), and the crank and coupler are collinear there (an independent check in the test)."""
    geared, plain = geared_leg_plan, walking_fourbar_plan
    g, p = Study(geared).dead_centres, Study(plain).dead_centres
    assert [d.kind for d in g] == [d.kind for d in p] == ["extended", "folded"]
    assert all(d.crank == "crank" and d.link == "coupler" and d.driver == "motor" for d in g)
    study = Study(geared)
    crank = geared.body_names.index("crank")
    for dg, dp in zip(g, p):
        st = study.state_at(np.array([dg.angle]), order=0)
        theta = float(st.body_angle[0, crank])
        assert abs(math.remainder(theta - dp.angle, 2 * math.pi)) < 1e-9
        K, O, L = (st.pos[0, geared.point_index(n)] for n in ("K", "O", "L"))
        a, b = K - O, L - K
        assert abs(a[0] * b[1] - a[1] * b[0]) < 1e-10 * np.linalg.norm(a) * np.linalg.norm(b)
    assert math.degrees(g[0].angle) == pytest.approx(2.64, abs=0.005)      # the rocker's extremes of issue 25 A1
    assert math.degrees(g[1].angle) == pytest.approx(115.20, abs=0.005)


def test_the_module_gait_forces_read_the_phase_shifted_run():
    """A walking module's legs are the run's samples shifted by their phases: the same forces as solving every leg
    at q + phase (an independent solve in the test)."""
    from assur.kinetostatics.api import forces
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    study = Study(plan)
    gf = study.force_cycle.gait
    assert gf is not None and len(gf.phases) == 2
    qq = study.q[:, None] + np.asarray(gf.phases)[None, :]
    ref = forces(plan, None, qq[..., None], point_loads=[("H", gf.foot_force)])
    scale = np.nanmax(np.abs(ref.driver))
    assert np.allclose(gf.forces.driver, ref.driver, rtol=0, atol=1e-9 * scale)
    assert np.allclose(gf.forces.reactions, ref.reactions, rtol=0, atol=1e-9 * np.nanmax(np.abs(ref.reactions)))


def test_fields_equal_the_public_wrappers_and_the_wrappers_take_a_study():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    study = Study(plan)
    assert assur.gait_metrics(plan) == study.gait == assur.gait_metrics(study)
    assert assur.dead_centres(plan) == study.dead_centres
    assert Study.of(study) is study


def test_bad_study_arguments_are_located():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    with pytest.raises(assur.SpecError, match="steps"):
        Study(plan, steps=1)
    with pytest.raises(assur.SpecError, match="params"):
        Study(plan, params=[1.0, 2.0])
    with pytest.raises(assur.SpecError, match="frames"):
        Study(plan).frames(0)


def test_a_mechanism_with_two_inputs_gets_its_header_and_a_note():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar_adjustable.toml"))
    d = Study(plan).as_dict()
    assert d["mobility"] == plan.n_inputs and "note" in d and d["unbuildable"] is None


def test_the_root_shows_its_public_names_and_warns_on_the_former_ones():
    assert dir(assur) == sorted(assur.__all__)
    assert "Study" in dir(assur) and "SolvePlan" not in dir(assur) and "Designer" not in dir(assur)
    for name, replacement in (("SolvePlan", "PlanarPlan"), ("analyse", "analyse_structure"), ("analyze", "Study"),
                              ("summarize", "Study"), ("Designer", "assur.designer.Designer")):
        with pytest.warns(DeprecationWarning, match=replacement):
            getattr(assur, name)


@pytest.mark.slow
def test_the_report_of_a_file_with_a_motor_has_its_run_on_the_motor(tmp_path):
    """examples/slider_crank_motor.toml has a [motor]: the report shows the run from rest (start-up time, steady
    speed, δ beside the kinetostatic estimate) read from the Study's motor run; a file without a motor has none."""
    plan = assur.compile(assur.load(EXAMPLES / "slider_crank_motor.toml"))
    study = Study(plan)
    run = study.motor_run
    assert run is not None and run.simulation.stop is not None
    assert main(["report", str(EXAMPLES / "slider_crank_motor.toml"), "-o", str(tmp_path / "m"), "--frames", "4"]) == 0
    page = (tmp_path / "m" / "index.html").read_text(encoding="utf-8")
    assert "Dynamics on the motor" in page and "start-up" in page
    assert Study(assur.compile(assur.load(EXAMPLES / "crank_rocker.toml"))).motor_run is None


@pytest.mark.slow
def test_the_report_of_a_file_with_a_make_table_has_its_parts(tmp_path):
    """A mechanism file with a [make] table: the report's Parts section reads the Study's parts (the layer count
    there is the one `assur make --layers-only` finds)."""
    text = (EXAMPLES / "crank_rocker.toml").read_text(encoding="utf-8") + '\n[make]\nthickness = "4 mm"\n'
    path = tmp_path / "made.toml"
    path.write_text(text, encoding="utf-8")
    study = Study(assur.compile(assur.load(path)))
    cert = study.parts.certificate
    assert cert.proven and cert.layers == cert.bound == 2          # rocker and coupler cross: two layers
    assert main(["report", str(path), "-o", str(tmp_path / "r"), "--frames", "4"]) == 0
    page = (tmp_path / "r" / "index.html").read_text(encoding="utf-8")
    assert ">Parts<" in page and "Minimality certificate" in page and "Bill of materials" in page
