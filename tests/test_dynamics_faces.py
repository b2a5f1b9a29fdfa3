"""What the report, the designer and synthesis reach: a solved cycle's run on its motor and its HTML fragment, the
``dynamics.*`` synthesis quantities against single runs, the compiled and the numpy population routes against each
other, and friction solved at every step against the force analysis with friction at the simulated motion."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import assur
from assur.dynamics.batch import compiled_available, run_designs
from assur.dynamics.cycle import cycle_simulation
from assur.dynamics.motors import drive_train
from assur.dynamics.population import population_equation
from assur.report.dynamics import dynamics_html

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PUMP = EXAMPLES / "slider_crank_motor.toml"


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(PUMP))


def test_a_solved_cycle_runs_on_its_motor(plan):
    cycle = assur.Study(plan)
    run = cycle_simulation(cycle, time=0.3)
    direct = assur.simulate(plan, time=0.3)
    assert run.simulation.stop.kind == "time"
    assert np.allclose(run.simulation.speed, direct.speed, rtol=1e-8, atol=1e-9)
    assert run.forces is not None and run.forces.reactions.shape[0] == run.simulation.t.size
    assert set(run.summary()) >= {"stop", "mean_speed", "delta", "joint_peaks", "events"}
    assert cycle_simulation(assur.Study(assur.compile(assur.load(EXAMPLES / "crank_rocker.toml")))) is None


def test_the_report_fragment(plan):
    html = dynamics_html(cycle_simulation(assur.Study(plan), time=0.3))
    assert "<table" in html and "run on the motor" in html and 'src="data:image/png;base64,' in html
    assert dynamics_html(assur.Study(assur.compile(assur.load(EXAMPLES / "crank_rocker.toml")))) == ""


def _designs(plan, n=4):
    P = np.tile(plan.defaults, (n, 1))
    P[:, plan.param_index("crank.length")] *= np.linspace(0.85, 1.15, n)
    return P


@pytest.mark.slow            # numba compiles the kernel once (about 10 s; cached afterwards)
@pytest.mark.skipif(not compiled_available(), reason="the compiled route needs numba")
def test_the_compiled_and_numpy_routes_agree(plan):
    eq = population_equation(plan, _designs(plan), drive_train(plan.mechanism.motor, plan))
    a = run_designs(eq, q0=plan.sketch_inputs[0], speed0=0.0, compiled=True, samples=50)
    b = run_designs(eq, q0=plan.sketch_inputs[0], speed0=0.0, compiled=False, samples=50)
    assert a["stop"] == b["stop"] == ("steady",) * 4
    assert np.allclose(a["mean_speed"], b["mean_speed"], rtol=1e-5)
    # the steady state is detected to 1e-6 of the period; the time the speed crosses 95 % of the mean moves by
    # that share of the mean over the slope there, ~20 times more
    assert np.allclose(a["startup"], b["startup"], rtol=1e-4)
    assert np.allclose(a["delta"], b["delta"], rtol=1e-3)


def test_synthesis_quantities_are_the_single_runs(plan, tmp_path):
    from assur.synthesis import Evaluator, problem_from_dict
    data = {"format": "assur-synth/1", "mechanism": str(PUMP),
            "variables": {"crank.length": [40, 60]},
            "objective": {"deviation": "none", "terms": [{"quantity": "dynamics.startup_time"}]},
            "constraints": {"limits": [{"quantity": "dynamics.delta", "max": 0.05},
                                       {"quantity": "dynamics.starts", "min": 1},
                                       {"quantity": "dynamics.mean_speed", "min": 0}]},
            "options": {"cycle_samples": 128}}
    ev = Evaluator(problem_from_dict(data), backend="numpy")
    X = np.array([[45e-3]])
    e = ev(X)
    for k, x in enumerate(ev.params(X)):
        s = assur.simulate(plan, params=x)
        assert e.quantities["dynamics.starts"][k] == 1.0
        # the first crossing of 95 % may fall near a peak of the start-up's fluctuation, where the speed's slope is
        # small: the 1e-5 by which the routes' steady means differ (128 grid samples here) moves it by a few ms
        assert e.quantities["dynamics.startup_time"][k] == pytest.approx(s.startup_time, rel=5e-3)
        assert e.quantities["dynamics.delta"][k] == pytest.approx(s.delta, rel=1e-2)
        assert e.quantities["dynamics.mean_speed"][k] == pytest.approx(np.degrees(s.mean_speed), rel=1e-4)
    data["mechanism"] = str(EXAMPLES / "slider_crank.toml")
    with pytest.raises(assur.SpecError, match=r"objective.terms\[0\].quantity: dynamics.startup_time needs a \[motor\]"):
        problem_from_dict(data)


@pytest.mark.slow
def test_friction_is_the_force_analysis_with_friction_at_every_step():
    text = PUMP.read_text().replace("[dynamics]\n", '[dynamics]\njoint_friction_radius = "1 mm"\n'
                                                   'slide_friction = 0.1\n')
    plan = assur.compile(assur.loads(text))
    s = assur.simulate(plan, time=0.03, friction=True, samples=12)
    free = assur.simulate(plan, time=0.03, samples=12)
    assert s.speed[-1] < free.speed[-1]                    # friction takes energy
    f = assur.forces(plan, None, s.q[:, None], speeds=s.speed[:, None], accels=s.accel[:, None], friction=True)
    expected = s.effort - 0.031 * s.accel
    assert np.allclose(f.driver[1:, 0], expected[1:], rtol=1e-8, atol=1e-10)
