"""Conflicts certified over the continuous cycle: the body poses and their exact velocities, the certificate
between samples against a dense independent sampling, the refinement, and the error of a stack that does not fit.
No CAD package is needed here."""
import math
from pathlib import Path

import numpy as np
import pytest
import shapely

import assur
from assur.analysis.sampling import Cycle
from assur.errors import SpecError
from assur.parts import make_parts
from assur.parts.conflicts import frame_arrays, items_of, pair_verdict
from assur.analysis.study import Study
from assur.parts.motion import body_frames

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def plan_of(name):
    return assur.compile(assur.load(EXAMPLES / f"{name}.toml"))


@pytest.fixture(scope="module")
def jansen():
    return make_parts(Cycle(plan_of("jansen")))


@pytest.fixture(scope="module")
def coarse():
    """Jansen's parts certified on a coarse grid (120 samples): the bound between samples is loose there."""
    cyc = Cycle(plan_of("jansen"), steps=120)
    return cyc, make_parts(cyc)


def test_body_velocities_match_finite_differences_of_the_poses():
    plan = plan_of("klann")
    fr = body_frames(Cycle(plan, steps=3600))
    dt = fr.dt[0]
    for b in range(1, plan.n_bodies):
        vel = (np.roll(fr.origin[:, b], -1, axis=0) - np.roll(fr.origin[:, b], 1, axis=0)) / (2 * dt)
        omega = (np.roll(fr.angle[:, b], -1) - np.roll(fr.angle[:, b], 1))
        omega = (omega + np.pi) % (2 * np.pi) - np.pi
        omega /= 2 * dt
        scale = np.abs(fr.vel[:, b]).max()
        assert np.abs(vel - fr.vel[:, b]).max() <= 1e-4 * scale + 1e-12
        assert np.abs(omega - fr.omega[:, b]).max() < 1e-4 * np.abs(fr.omega[:, b]).max()
        acc = (np.roll(fr.vel[:, b], -1, axis=0) - np.roll(fr.vel[:, b], 1, axis=0)) / (2 * dt)
        assert np.abs(acc - fr.acc[:, b]).max() <= 1e-4 * np.abs(fr.acc[:, b]).max() + 1e-12


def test_a_body_point_at_every_sample_is_the_engines():
    plan = plan_of("walker_fourbar_adjustable")            # two inputs: the setting held at its sketch value
    cyc = Study(plan)
    assert cyc.cyclic and cyc.moving == 0
    fr = body_frames(cyc)
    q, st = cyc.grid()
    pos = np.asarray(st.pos)
    assert np.ptp(np.asarray(st.inputs)[:, 1]) == 0                # the setting held
    for lk in plan.mechanism.links:
        if lk.name == "frame":
            continue
        b = plan.body_names.index(lk.name)
        for p in lk.points:
            local = fr.to_local(b, np.asarray(fr.sketch_state.pos).reshape(-1, 2)[plan.point_index(p)])
            assert np.abs(fr.to_world(b, local[None])[:, 0] - pos[:, plan.point_index(p)]).max() < 1e-12


def test_a_stroke_does_not_wrap():
    fr = body_frames(Study(plan_of("lever_manipulator")))
    assert not fr.closed and fr.dt[-1] == 0.0 and np.all(fr.dt[:-1] > 0)


def dense_distances(result, a, b, per_interval=8):
    """The two parts' region distance at ``per_interval`` inputs inside every interval of the run, from the
    engine's positions (not the certificate's poses)."""
    plan, fr = result.plan, result.frames
    n = fr.n
    q = fr.q[0] + (np.arange(n * per_interval) + 0.5) * (2 * np.pi / (n * per_interval))
    st = assur.solve(plan, None, q[:, None])
    pos, ang = np.asarray(st.pos), np.asarray(st.body_angle)
    out = []
    for name in (a, b):
        part = next(p for p in result.parts if p.name == name)
        ring = np.asarray(part.region().exterior.coords)
        body = part.body
        ref = fr.ref[body]
        r0, a0 = fr.sketch_origin[body], fr.sketch_angle[body]
        world0 = fr.at_sketch(body, ring)
        origin = pos[:, ref] if ref is not None else np.zeros((q.size, 2))
        th = ang[:, body] - a0 if ref is not None else np.zeros(q.size)
        c, s = np.cos(th)[:, None], np.sin(th)[:, None]
        d = world0 - r0
        out.append(shapely.polygons(np.stack([origin[:, None, 0] + c * d[:, 0] - s * d[:, 1],
                                              origin[:, None, 1] + s * d[:, 0] + c * d[:, 1]], axis=-1)))
    return shapely.distance(out[0], out[1])


@pytest.mark.slow
def test_the_certified_gap_is_a_lower_bound_of_the_continuous_distance(coarse):
    _, result = coarse
    checked = 0
    for v in result.conflicts.parts + result.conflicts.pins:
        dense = dense_distances(result, v.a, v.b)
        assert dense.min() >= v.gap - 1e-12, (v.a, v.b, dense.min(), v.gap)
        if not v.conflict:
            assert dense.min() >= result.settings.clearance
        checked += 1
    assert checked > 50


def test_a_tight_clearance_is_refined_between_samples_and_stays_sound(coarse):
    cyc, result = coarse
    F = frame_arrays(result.frames)
    items = {it.name: it for it in items_of(result.design.stack + [p.part for p in result.design.pins])}
    free = [v for v in result.conflicts.parts + result.conflicts.pins if not v.conflict]
    v0 = min(free, key=lambda v: v.sampled)               # the pair that comes closest without meeting
    truth = float(dense_distances(result, v0.a, v0.b, per_interval=32).min())
    a, b = items[v0.a], items[v0.b]
    for clearance in (0.5 * truth, 0.995 * truth):
        v = pair_verdict(cyc, result.frames, F, a, b, clearance)
        assert not v.conflict and clearance <= v.gap <= truth + 1e-12
    assert pair_verdict(cyc, result.frames, F, a, b, 0.995 * truth).refined > 0
    assert pair_verdict(cyc, result.frames, F, a, b, 1.005 * truth).conflict   # never certified above the truth


def test_a_stack_over_the_limit_names_the_parts_and_where_they_meet(jansen):
    plan = jansen.plan
    with pytest.raises(SpecError) as exc:
        make_parts(Cycle(plan), max_layers=2)
    text = str(exc.value)
    assert "cannot be stacked in 2 layers" in text
    clique = sorted(n for g in jansen.certificate.clique for n in g)
    for name in clique:
        assert name in text
    # each pair is named with an input where the two parts really meet (closer than the clearance there)
    v = jansen.conflicts.verdict(clique[0], clique[1])
    at = f"{math.degrees(v.at):.6g} deg"
    assert f"{v.a} and {v.b} meet at {at}" in text
    fr = jansen.frames
    i = int(np.argmin(np.abs(fr.q - v.at)))
    pa, pb = jansen.part(v.a), jansen.part(v.b)
    ra = shapely.Polygon(fr.to_world(pa.body, np.asarray(pa.region().exterior.coords))[i])
    rb = shapely.Polygon(fr.to_world(pb.body, np.asarray(pb.region().exterior.coords))[i])
    assert ra.distance(rb) < jansen.settings.clearance


def test_jansen_needs_three_layers_the_clique_proves_it(jansen):
    cert = jansen.certificate
    assert jansen.layers == cert.bound == 3 and cert.proven and cert.status == "optimal"
    # the clique: the crank and the two links on its pin, which all overlap at C at every input
    assert sorted(n for g in cert.clique for n in g) == ["plate_crank", "plate_j", "plate_k"]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["walker_sixbar_beta1_60", "watt2"])
def test_unstackable_examples_are_refused_with_the_reason(name):
    with pytest.raises(SpecError) as exc:
        make_parts(Study(plan_of(name)))
    text = str(exc.value)
    assert "cannot be stacked at all" in text and "covers" in text
