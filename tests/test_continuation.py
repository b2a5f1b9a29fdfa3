"""Continuation that never jumps (issue 26 §3): perturbed triad and class-IV six-bars solved by the default
``assur.solve`` over a turn at 10°, 1° and 0.01° steps.

Independent checks written here:

- no jump: between neighbouring valid samples no point moves farther than the exact derivatives at both ends allow
  (|ΔP| ≤ (|dP/dq|ᵢ + |dP/dq|ᵢ₊₁)·Δq, about twice the true chord on a smooth path; a jump to another assembly
  breaks it by orders of magnitude);
- the same valid set, and the same positions, at every step size (on the samples the grids share);
- agreement with the closed form: every valid sample is one of the assemblies ``assur.assemblies`` finds there (the
  triad's polynomial roots; the class-IV group's certified reduction) — the one marked as the sketch's.

The 0.01° grid covers windows of the turn in the quick run (where the group moves fastest), the whole turn in the
slow one.
"""
from __future__ import annotations

import numpy as np
import pytest

import assur
from conftest import EXAMPLES

FILES = {"triad": "triad_sixbar.toml", "classiv": "classiv_sixbar.toml"}


def _designs(plan, n, seed, spread=0.03):
    """The file's design and ``n − 1`` random perturbations of its lengths and coordinates by ``spread``."""
    rng = np.random.default_rng(seed)
    out = [plan.defaults]
    kinds = np.array([plan.param_names[i].rsplit(".", 1)[-1] for i in range(plan.n_params)])
    for _ in range(n - 1):
        p = plan.defaults.copy()
        lengths = np.isin(kinds, ("length", "distance"))
        p[lengths] *= 1 + spread * rng.standard_normal(lengths.sum())
        coords = np.isin(kinds, ("x", "y"))
        p[coords] += spread * plan.length_scale * rng.standard_normal(coords.sum())
        out.append(p)
    return out


def _jump_ratio(q, st):
    """The largest point displacement between neighbouring valid samples over its derivative bound."""
    dq = np.diff(q)
    step = np.linalg.norm(np.diff(st.pos, axis=0), axis=-1).max(axis=-1)
    speed = np.linalg.norm(st.dpos_dq[..., 0], axis=-1).max(axis=-1)
    both = st.valid[1:] & st.valid[:-1]
    bound = (speed[1:] + speed[:-1]) * dq + 1e-12
    return float(np.max(step[both] / bound[both], initial=0.0))


def _check_design(plan, params, fine_windows):
    L = plan.length_scale
    coarse = np.arange(36) * np.radians(10.0)
    medium = np.arange(360) * np.radians(1.0)
    a = assur.solve(plan, params, coarse, order=1)
    b = assur.solve(plan, params, medium, order=1)
    assert _jump_ratio(medium, b) < 1.0
    np.testing.assert_array_equal(b.valid[::10], a.valid)
    both = a.valid
    np.testing.assert_allclose(b.pos[::10][both], a.pos[both], rtol=0, atol=1e-9 * L)
    for lo, hi in fine_windows:
        fine = np.radians(np.arange(round(lo * 100), round(hi * 100) + 1) / 100.0)
        c = assur.solve(plan, params, fine, order=1)
        assert _jump_ratio(fine, c) < 1.0
        on_medium = np.flatnonzero(np.isclose(np.mod(fine, np.radians(1.0)), 0.0, atol=1e-12))
        idx = np.rint(np.degrees(fine[on_medium])).astype(int) % 360
        np.testing.assert_array_equal(c.valid[on_medium], b.valid[idx])
        ok = c.valid[on_medium]
        np.testing.assert_allclose(c.pos[on_medium][ok], b.pos[idx][ok], rtol=0, atol=1e-9 * L)
    # every valid sample of the 10° grid is the assembly the enumeration marks as the sketch's
    for i, found in enumerate(assur.assemblies(plan, coarse, params)):
        if not a.valid[i]:
            continue
        mine = [f for f in found if f.sketch]
        assert len(mine) == 1
        np.testing.assert_allclose(mine[0].pos, a.pos[i], rtol=0, atol=1e-9 * L)
    return a.valid.mean()


def _fastest_windows(plan, params, width=2.0, count=2):
    """``count`` windows of ``width`` degrees centred where the group's points move fastest (1° grid)."""
    q = np.arange(360) * np.radians(1.0)
    st = assur.solve(plan, params, q, order=1)
    speed = np.where(st.valid, np.linalg.norm(st.dpos_dq[..., 0], axis=-1).max(axis=-1), -1.0)
    out = []
    for i in np.argsort(-speed):
        if all(abs((i - c + 180) % 360 - 180) > width for c, _ in out):
            out.append((int(i), None))
        if len(out) == count:
            break
    return [(c - width / 2, c + width / 2) for c, _ in out]


@pytest.mark.parametrize("name", sorted(FILES))
def test_continuation_never_jumps_at_any_step(name):
    """The file's design (a full turn)."""
    plan = assur.compile(assur.load(EXAMPLES / FILES[name]))
    assert _check_design(plan, plan.defaults, _fastest_windows(plan, plan.defaults)) == 1.0


#: perturbed designs (seed, design) that turn fully and that lock over part of the turn (a toggle of the group)
PERTURBED = {"triad": [(3, 1), (3, 0)], "classiv": [(1, 0), (1, 1)]}


@pytest.mark.slow
@pytest.mark.parametrize("name,seed,k", [(n, s, k) for n in sorted(FILES) for s, k in PERTURBED[n]])
def test_perturbed_designs_never_jump_at_any_step(name, seed, k):
    plan = assur.compile(assur.load(EXAMPLES / FILES[name]))
    params = _designs(plan, 3, seed)[1 + k]
    built = _check_design(plan, params, _fastest_windows(plan, params))
    assert 0.1 < built


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(FILES))
def test_continuation_over_a_whole_turn_at_a_hundredth_of_a_degree(name):
    plan = assur.compile(assur.load(EXAMPLES / FILES[name]))
    params = _designs(plan, 2, 4)[1]          # a perturbed design that turns fully
    assert _check_design(plan, params, [(0.0, 359.99)]) == 1.0


@pytest.mark.parametrize("name", sorted(FILES))
def test_a_sample_is_the_same_alone_in_a_batch_and_after_any_call(name, monkeypatch):
    """The file's design's samples start at the last whole step of crank before them (continuation.WholeSteps,
    walked once and kept with the plan): a sample solved alone on a fresh plan, the same sample inside a turn of 720,
    and alone again once the whole steps are kept give the same numbers bit for bit, both ways round; and the kept
    whole steps spare the walk: a single sample then takes at most three Newton steps instead of one per whole step
    of crank between it and the sketch."""
    from assur.engine.planar import continuation
    text = (EXAMPLES / FILES[name]).read_text()
    q = np.arange(720) * np.radians(0.5)
    picks = [100, 350, 400, 600]                                          # both ways round from the sketch
    alone_fresh = []
    for i in picks:
        fresh = assur.compile(assur.loads(text))
        alone_fresh.append(assur.solve(fresh, inputs=q[i:i + 1], order=2, backend="numpy"))
    plan = assur.compile(assur.loads(text))
    turn = assur.solve(plan, inputs=q, order=2, backend="numpy")
    runs = [0]
    real_run = continuation._run

    def counted(*args, **kw):
        runs[0] += 1
        return real_run(*args, **kw)

    monkeypatch.setattr(continuation, "_run", counted)
    for i, fresh in zip(picks, alone_fresh):
        runs[0] = 0
        again = assur.solve(plan, inputs=q[i:i + 1], order=2, backend="numpy")
        assert runs[0] <= 5            # the sketch, at most three walk steps, the sample's own run
        for st in (fresh, again):
            np.testing.assert_array_equal(st.valid[0], turn.valid[i])
            np.testing.assert_array_equal(st.pos[0], turn.pos[i])
            np.testing.assert_array_equal(st.acc[0], turn.acc[i])
    assert turn.valid[picks].all()
    # on a fresh plan the same sample walks from the sketch through every whole step between
    runs[0] = 0
    assur.solve(assur.compile(assur.loads(text)), inputs=q[350:351], order=2, backend="numpy")
    assert runs[0] >= 10


def test_a_plan_is_freed_with_its_kept_whole_steps():
    """The whole steps are kept with the plan (weakly): once the plan is gone, so are they."""
    import gc
    import weakref

    from assur.engine.planar import continuation
    plan = assur.compile(assur.load(EXAMPLES / FILES["triad"]))
    st = assur.solve(plan, inputs=[[np.radians(175.0)]], backend="numpy")
    assert st.valid.all() and plan in continuation._WHOLE_STEPS
    ref = weakref.ref(plan)
    del plan, st
    gc.collect()
    assert ref() is None
