"""A synthesis problem on a mechanism with a class-III triad runs (issue 26 §5; on the numpy path, its populations
swept through the cycle in certified steps): path targets taken from the file's own design are met again from a
perturbed start, and the best design's path, recomputed here by ``assur.solve``, passes through them."""
from __future__ import annotations

import numpy as np
import pytest

import assur
from assur.synthesis import Evaluator, synthesize
from assur.synthesis.problem import problem_from_dict


@pytest.mark.slow
def test_a_triad_six_bar_path_is_found_again(triad_sixbar_plan):
    plan = triad_sixbar_plan
    q = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    st = assur.solve(plan, inputs=q, order=0)
    targets = st.pos[:, plan.point_index("D")] * 1e3                                 # mm, the file's own path
    data = {"format": "assur-synth/1", "name": "triad path",
            "variables": {"r2.length": [120, 160], "tern.D.distance": [80, 120]},
            "targets": {"point": "D", "xy": targets.tolist(), "timing": "path"},
            "objective": {"deviation": "squared"}, "constraints": {"use": ["buildable"]},
            "options": {"cycle_samples": 90}}
    problem = problem_from_dict(data, mechanism=plan)
    x_file = [[v * 1e3 for v in (plan.defaults[plan.param_index("r2.length")],
                                 plan.defaults[plan.param_index("tern.D.distance")])]]
    at_file = Evaluator(problem)(problem.to_si(x_file))
    assert at_file.feasible[0]
    best = synthesize(problem, "de", seed=3, budget=240, popsize=8, polish="none")
    assert best.feasible and np.isfinite(best.objective)
    # the best design's path, solved afresh over a fine turn, passes near every target (mm)
    found = assur.solve(plan, best.params(), np.linspace(0, 2 * np.pi, 720, endpoint=False), order=0)
    path = found.pos[:, plan.point_index("D")] * 1e3
    gap = np.min(np.linalg.norm(path[:, None, :] - targets[None, :, :], axis=-1), axis=0)
    assert np.all(gap < 3.0), gap


def test_transmission_limit_on_a_mechanism_without_a_dyad_is_refused(triad_sixbar_plan):
    """The triad six-bar (a crank and one class III group) has no transmission angle: a limit on
    ``transmission.min`` could never hold, so the problem is refused where it stands, not searched to 'infeasible'."""
    from assur.errors import SpecError
    plan = triad_sixbar_plan
    assert {st.kind for st in plan.steps} & {"RRR", "RRP", "RPR", "PRP", "PPR"} == set()
    data = {"format": "assur-synth/1", "name": "triad transmission",
            "variables": {"r2.length": [120, 160]},
            "objective": {"deviation": "none", "terms": [{"quantity": "unbuildable", "weight": 1.0}]},
            "constraints": {"use": ["buildable"], "limits": [{"quantity": "transmission.min", "min": 30}]}}
    with pytest.raises(SpecError) as err:
        problem_from_dict(data, mechanism=plan)
    assert "constraints.limits[0].quantity" in str(err.value) and "no dyad" in str(err.value)


def test_the_recheck_of_a_result_solves_a_newton_plan_on_numpy(triad_sixbar_plan):
    """``Evaluator.recheck`` (a run's result, once): on a plan with a Newton-solved group it is the numpy evaluator's
    detailed evaluation, to the last bit (no compiled solve kernel is compiled for one design), and the evaluator
    keeps its own backend for the search afterwards."""
    plan = triad_sixbar_plan
    data = {"format": "assur-synth/1", "name": "triad recheck",
            "variables": {"r2.length": [120, 160], "tern.D.distance": [80, 120]},
            "targets": {"point": "D", "xy": [[0.0, 0.0]], "timing": "path"},
            "objective": {"deviation": "squared"}, "constraints": {"use": ["buildable"]},
            "options": {"cycle_samples": 36}}
    problem = problem_from_dict(data, mechanism=plan)
    X = problem.to_si(np.array([[140.0, 100.0], [150.0, 90.0]]))
    fast = Evaluator(problem, backend="numba")
    got = fast.recheck(X)
    ref = Evaluator(problem, backend="numpy")(X, detail=True)
    assert [got.row(i) for i in range(2)] == [ref.row(i) for i in range(2)]
    assert fast.backend == "numba"
