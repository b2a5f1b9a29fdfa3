"""Newton-solved groups swept through a crank's turn (solve(..., sweep=True), assur.engine.planar.sweep) against
the per-sample continuation from the sketch (the default): the same positions where the default's motion is
continuous, and a continuous motion always (independent check here: the largest jump of any point between
neighbouring samples, against the largest first-order step |dP/dq|·Δq the exact derivatives allow)."""
from pathlib import Path

import numpy as np
import pytest

import assur

TRIAD = Path(__file__).resolve().parent.parent / "examples" / "triad_sixbar.toml"
Q = np.linspace(0.0, 2 * np.pi, 120, endpoint=False)


@pytest.fixture(scope="module")
def plan():
    p = assur.compile(assur.load(TRIAD))
    assert any(st.kind == "newton" for st in p.steps)          # the example's triad is Newton-solved
    return p


def _designs(plan, n=12, spread=0.04, seed=5):
    rng = np.random.default_rng(seed)
    return np.vstack([plan.defaults, plan.defaults * (1 + spread * rng.standard_normal((n, plan.n_params)))])


def _largest_jump_ratio(st):
    """Per design: the largest point displacement between neighbouring samples over the bound from its exact
    derivatives at both ends (2·max|dP/dq|·Δq): about 1/2 on a smooth path, ≫ 1 where the assembly jumps."""
    dq = Q[1] - Q[0]
    step = np.linalg.norm(np.roll(st.pos, -1, axis=1) - st.pos, axis=-1).max(axis=-1)       # (n, M)
    speed = np.linalg.norm(st.dpos_dq[..., 0], axis=-1).max(axis=-1)                        # (n, M)
    bound = (speed + np.roll(speed, -1, axis=1)) * dq
    with np.errstate(all="ignore"):
        ratio = step / bound
    return np.where(np.isfinite(ratio), ratio, -np.inf).max(axis=1)     # -inf: a design with no valid sample


def test_the_file_design_is_the_same_either_way(plan):
    a = assur.solve(plan, inputs=Q, order=2)
    b = assur.solve(plan, inputs=Q, order=2, sweep=True)
    assert a.valid.all() and b.valid.all()
    for k in ("pos", "vel", "acc"):
        np.testing.assert_allclose(getattr(b, k), getattr(a, k), rtol=0, atol=1e-9, err_msg=k)


@pytest.mark.slow
def test_swept_designs_move_continuously_and_agree_where_the_default_does(plan):
    P = _designs(plan)
    a = assur.solve(plan, P[:, None, :], Q[:, None], order=1)
    b = assur.solve(plan, P[:, None, :], Q[:, None], order=1, sweep=True)
    full_b = b.valid.all(axis=1)
    assert full_b.sum() >= 3
    assert np.all(_largest_jump_ratio(b)[full_b] < 1.0)
    smooth_a = a.valid.all(axis=1) & (_largest_jump_ratio(a) < 1.0)
    both = smooth_a & full_b
    assert both.sum() >= 3
    np.testing.assert_allclose(b.pos[both], a.pos[both], rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.dpos_dq[both], a.dpos_dq[both], rtol=0, atol=1e-7)


def test_sweep_is_ignored_where_it_does_not_apply(plan):
    """Designs varying along the samples' axis, or a plan without Newton groups: the default solve, bit for bit (on
    one backend: with backend="auto" the choice between the compiled and the numpy route depends on which kernels
    earlier tests of the process left compiled, and the two agree to round-off, not bit for bit)."""
    P = _designs(plan, n=len(Q) - 1)
    a = assur.solve(plan, P, Q, order=0, backend="numpy")
    b = assur.solve(plan, P, Q, order=0, sweep=True, backend="numpy")
    assert np.array_equal(np.nan_to_num(a.pos), np.nan_to_num(b.pos))
    four = assur.compile(assur.load(TRIAD.parent / "crank_rocker.toml"))
    c = assur.solve(four, inputs=Q, backend="numpy")
    d = assur.solve(four, inputs=Q, backend="numpy", sweep=True)
    assert np.array_equal(c.pos, d.pos)
