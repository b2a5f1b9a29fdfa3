"""The joint optimisation of a leg's dimensions and its transfer law (assur.codesign.joint).

References computed here: the file's leg with the transfer :func:`optimize_transfer` finds for it (the search's
start) — the joint result may not be worse; its gear checks recomputed from its law; its gait from gait_metrics."""
from pathlib import Path

import math

import numpy as np
import pytest

import assur
from assur.analysis.gait import gait_metrics
from assur.errors import SpecError
from assur.codesign.joint import JointProblem, default_vary, optimize_codesign

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))


def test_default_variables_leave_the_crank_alone(plan):
    names = [v[0] for v in default_vary(plan)]
    assert "crank.length" not in names and "O.x" not in names and "crank.zero" not in names
    assert {"rocker.length", "coupler.length", "O1.x"} <= set(names)
    for name, lo, hi in default_vary(plan):
        assert lo < plan.defaults[plan.param_index(name)] < hi


def test_an_unknown_variable_is_named(plan):
    with pytest.raises(SpecError) as e:
        JointProblem(plan, 0.8, centre_distance=0.12, module=0.002, vary=[("rocker.lenght", 0.5, 0.7)])
    assert "rocker.lenght" in str(e.value)


@pytest.mark.slow
def test_the_joint_result_is_feasible_and_no_worse_than_its_start(plan):
    d = optimize_codesign(plan, 0.8, centre_distance=0.1215, module=0.002, budget=300, seed=1)
    assert d.feasible and d.checks.ok
    start = JointProblem(plan, 0.8, centre_distance=0.1215, module=0.002)
    from assur.codesign.transfer import optimize_transfer
    first = optimize_transfer(plan, 0.8, centre_distance=0.1215, module=0.002, seed=1, measure=False)
    start.start_from(first.coefficients - start.gears.default_coefficients(plan.defaults))
    assert d.objective <= start(start.start()) + 1e-12
    g = gait_metrics(plan, d.params)
    assert g.step_length >= 0.95 * gait_metrics(plan).step_length - 1e-12
    assert d.vx_spread["0.8"] <= 1e-6
    assert math.isclose(d.gait["sag"], g.sag, rel_tol=1e-6)
    assert np.all(np.isfinite(d.params))
