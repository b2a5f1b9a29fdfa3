"""Spatial mechanisms in the general engine (``assur.compile`` / ``assur.solve`` on dimension-3 files):
the solve contract (shapes, broadcasting, NaN + valid), exact velocities and accelerations against
central differences and against the batched Newton loop-closure oracle (docs/papers/003.md §6), body angular
velocities, and bad input (docs/papers/003.md §7, located SpecErrors, unbuildable ranges named)."""
from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.analysis.spatial import dyads, rocker_angle
from assur.errors import StructureError, UnbuildableError, UnbuildableWarning
from assur.kernels import spatial as V
from conftest import rssr

ROOT = Path(__file__).resolve().parents[1]
P003 = (ROOT / "examples" / "rssr.toml").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.load(ROOT / "examples" / "rssr.toml"))


@pytest.fixture(scope="module")
def tilted():
    return assur.compile(assur.load(ROOT / "examples" / "rssr_tilted.toml"))


def variant(**repl) -> str:
    """The P003-2 file with lines replaced: ``variant(P4_joint='P4 = "revolute"')`` etc."""
    text = P003
    for old, new in repl.values():
        assert old in text, old
        text = text.replace(old, new)
    return text


# -- contract ------------------------------------------------------------------------------------------
def test_shapes_and_broadcasting(tilted):
    P = tilted.n_params
    params = np.broadcast_to(tilted.defaults, (3, 1, P)).copy()
    params[:, 0, tilted.param_index("crank.length")] = [0.018, 0.02, 0.022]
    q = np.linspace(0, 2 * math.pi, 5, endpoint=False)
    s = assur.solve(tilted, params, q)
    n = tilted.n_points
    assert s.pos.shape == (3, 5, n, 3) and s.vel.shape == (3, 5, n, 3) and s.acc.shape == (3, 5, n, 3)
    assert s.dpos_dq.shape == (3, 5, n, 3, 1) and s.d2pos_dq2.shape == (3, 5, n, 3, 1, 1)
    assert s.valid.shape == (3, 5) and s.body_frame.shape == (3, 5, 4, 3, 3)
    assert s.body_omega.shape == (3, 5, 4, 3) and s.body_alpha.shape == (3, 5, 4, 3)
    for i in range(3):
        for j in range(5):
            one = assur.solve(tilted, params[i, 0], q[j])
            np.testing.assert_allclose(s.pos[i, j], one.pos, rtol=0, atol=1e-16)
            np.testing.assert_allclose(s.acc[i, j], one.acc, rtol=1e-13, atol=1e-12)
    assert assur.solve(tilted, None, q, order=0).vel is None
    assert assur.solve(tilted, None, q, order=1).acc is None
    assert s.point("C").pos.shape == (3, 5, 3)


def test_bad_arguments_are_spec_errors(tilted):
    with pytest.raises(assur.SpecError, match="params"):
        assur.solve(tilted, np.zeros(3), [0.0])
    with pytest.raises(assur.SpecError, match="on_unbuildable"):
        assur.solve(tilted, None, [0.0], on_unbuildable="ignore")
    with pytest.raises(assur.SpecError, match="method"):
        assur.solve(tilted, None, [0.0], method="guess")


# -- derivatives -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["plan", "tilted"])
def test_velocities_and_accelerations_against_central_differences(name, request):
    plan = request.getfixturevalue(name)
    q = np.linspace(0, 2 * math.pi, 37)
    h = 1e-5
    s = assur.solve(plan, None, q)
    p1 = assur.solve(plan, None, q + h, order=0).pos
    p0 = assur.solve(plan, None, q - h, order=0).pos
    scale = plan.length_scale
    np.testing.assert_allclose(s.dpos_dq[..., 0], (p1 - p0) / (2 * h), rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(s.d2pos_dq2[..., 0, 0], (p1 - 2 * s.pos + p0) / h ** 2, rtol=0, atol=1e-5 * scale)
    w = plan.speeds[0]
    np.testing.assert_allclose(s.vel, s.dpos_dq[..., 0] * w, rtol=1e-14, atol=0)
    np.testing.assert_allclose(s.acc, s.d2pos_dq2[..., 0, 0] * w * w, rtol=1e-14, atol=0)
    # input speed and acceleration given explicitly: a = x''·ω² + x'·ε
    t = assur.solve(plan, None, q, speeds=[3.0], accels=[2.0])
    np.testing.assert_allclose(t.acc, s.d2pos_dq2[..., 0, 0] * 9.0 + s.dpos_dq[..., 0] * 2.0, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("name", ["plan", "tilted"])
def test_closed_form_equals_the_newton_loop_closure_oracle(name, request):
    """docs/papers/003.md §10: the same mechanism solved by Newton on the loop-closure equations (continued
    from the sketch, derivatives by §6's linear systems) equals the closed form with jets."""
    plan = request.getfixturevalue(name)
    q = np.linspace(0, 2 * math.pi, 49)
    a = assur.solve(plan, None, q)
    b = assur.solve(plan, None, q, method="newton")
    assert a.valid.all() and b.valid.all()
    L = plan.length_scale
    np.testing.assert_allclose(b.pos, a.pos, rtol=0, atol=1e-12 * L)
    np.testing.assert_allclose(b.dpos_dq, a.dpos_dq, rtol=0, atol=1e-11 * L)
    np.testing.assert_allclose(b.d2pos_dq2, a.d2pos_dq2, rtol=0, atol=1e-10 * L)
    np.testing.assert_allclose(b.body_frame, a.body_frame, rtol=0, atol=1e-11)


def test_newton_oracle_for_other_designs_and_an_inclined_rocker_arm(tilted):
    """Designs other than the file's (reached by continuation in the parameters too), including a rocker
    arm not perpendicular to its axis (α2 ≠ 90°: (P3 − P4)·e_Z2 = axial offset)."""
    p = tilted.params_with(rocker__axial=0.004, crank__length=0.018, P4__axis__gamma2=0.5)
    q = np.linspace(0, 2 * math.pi, 25)
    a = assur.solve(tilted, p, q)
    b = assur.solve(tilted, p, q, method="newton")
    assert a.valid.all()
    np.testing.assert_allclose(b.pos, a.pos, rtol=0, atol=1e-13)
    np.testing.assert_allclose(b.dpos_dq, a.dpos_dq, rtol=0, atol=1e-12)
    g = dyads(tilted, a, p)[0]
    np.testing.assert_allclose(np.sum((g.B - g.D) * g.axis_frame[..., :, 2], -1), 0.004, atol=1e-15)


def test_body_angular_velocities(tilted):
    """ω of the crank = ω_in·e_X; of the rocker = θ4'·ω_in·e (θ4' by central differences); of the
    coupler from its frame: ω× = R'Rᵀ against differences of the frames; α of the crank = 0."""
    q = np.linspace(0.1, 6.2, 23)
    h = 1e-5
    s = assur.solve(tilted, None, q)
    w = tilted.speeds[0]
    crank, rocker, coupler = (s.body(n) for n in ("crank", "rocker", "coupler"))
    np.testing.assert_allclose(s.body_omega[:, crank], np.broadcast_to([w, 0, 0], (len(q), 3)), atol=1e-12)
    np.testing.assert_allclose(s.body_alpha[:, crank], 0.0, atol=1e-9)
    th = [rocker_angle(dyads(tilted, assur.solve(tilted, None, q + k * h, order=0))[0]) for k in (-1, 0, 1)]
    dth = (np.unwrap(np.stack(th), axis=0)[2] - np.unwrap(np.stack(th), axis=0)[0]) / (2 * h)
    d2th = (th[2] - 2 * th[1] + th[0]) / h ** 2
    e = V.e_z2(*(tilted.defaults[tilted.param_index(f"P4.axis.gamma{i}")] for i in (1, 2)))
    np.testing.assert_allclose(s.body_omega[:, rocker], dth[:, None] * w * e, atol=1e-6 * w)
    np.testing.assert_allclose(s.body_alpha[:, rocker], d2th[:, None] * w * w * e, atol=1e-3 * w * w)
    R1 = assur.solve(tilted, None, q + h, order=0).body_frame[:, coupler]
    R0 = assur.solve(tilted, None, q - h, order=0).body_frame[:, coupler]
    W = (R1 - R0) / (2 * h) @ np.swapaxes(s.body_frame[:, coupler], -1, -2) * w
    omega = np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], -1)
    np.testing.assert_allclose(s.body_omega[:, coupler], omega, atol=1e-6 * w)
    # the crank-pin end P2 moves with the crank: v = ω × r
    r = s.pos[:, tilted.point_index("P2")] - s.pos[:, tilted.point_index("P1")]
    np.testing.assert_allclose(s.vel[:, tilted.point_index("P2")], np.cross(s.body_omega[:, crank], r), atol=1e-12)


# -- unbuildable samples ---------------------------------------------------------------------------------
def test_unassemblable_part_of_the_cycle_is_nan_with_the_range_named(plan):
    """Coupler 50, rocker 20 on P003-2's frame: |P2 − P4| exceeds 70 where cos(f1 − atan2(4,3)) < −0.375,
    i.e. for f1 in (atan2(4,3) + acos(−0.375), atan2(4,3) + 2π − acos(−0.375)) = (165.15°, 301.11°)."""
    p = plan.params_with(coupler__length=0.05, rocker__length=0.02)
    q = np.radians(np.arange(0, 360, 1.0))
    s = assur.solve(plan, p, q)
    lo = math.degrees(math.atan2(4, 3) + math.acos(-0.375))
    hi = math.degrees(math.atan2(4, 3) + 2 * math.pi - math.acos(-0.375))
    expect_bad = (np.degrees(q) > lo) & (np.degrees(q) < hi)
    np.testing.assert_array_equal(~s.valid, expect_bad)
    assert np.isnan(s.pos[~s.valid]).all() and np.isnan(s.vel[~s.valid]).all()
    assert np.isfinite(s.pos[s.valid]).all()
    assert np.all(s.status["P3"][~s.valid] == V.CANNOT_ASSEMBLE)
    with pytest.warns(UnbuildableWarning, match=r"the dyad solving P3 \(cannot assemble.*\) at crank 166°…301°"):
        assur.solve(plan, p, q, on_unbuildable="warn")
    with pytest.raises(UnbuildableError, match=f"{int(expect_bad.sum())} of 360 samples cannot be assembled"):
        assur.solve(plan, p, q, on_unbuildable="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assur.solve(plan, p, q)           # 'nan' is silent


def test_analyze_reports_the_buildable_range(plan):
    """The buildable range's ends refined by bisection to the closed-form toggle angles above."""
    sub = _compile_text(variant(
        c=('coupler = { points = ["P2", "P3", "C"], length = 70 }', 'coupler = { points = ["P2", "P3", "C"], length = 50 }'),
        r=('rocker = { points = ["P4", "P3"], length = 50 }', 'rocker = { points = ["P4", "P3"], length = 20 }'),
        p=("P3 = [0, -9.294117647058824, 69.17647058823529]", "P3 = [0, 20, 50]"),
        s=("P2 = [0, -20, 0]", "P2 = [0, 20, 0]")))
    out = assur.Study(sub, steps=360).as_dict()
    assert out["full_rotation"] is False
    (r,) = out["buildable_ranges"]
    lo = math.atan2(4, 3) + math.acos(-0.375)
    hi = math.atan2(4, 3) + 2 * math.pi - math.acos(-0.375)
    assert r["end"] == pytest.approx(lo, abs=1e-9)
    assert r["start"] == pytest.approx(hi, abs=1e-9)          # the range wraps through 0: start > end


# -- bad input: located errors at compile ------------------------------------------------------------------
def _compile_text(text):
    return assur.compile(assur.loads(text))


def test_a_revolute_without_an_axis_is_located():
    text = variant(j=('P4 = { kind = "revolute", axis = { gamma1 = 90, gamma2 = 0 } }', 'P4 = "revolute"'))
    with pytest.raises(assur.SpecError, match=r"joints\.P4: a revolute of a spatial mechanism needs an axis"):
        _compile_text(text)


def test_a_degenerate_axis_is_rejected_at_load():
    text = variant(j=("axis = [1, 0, 0] }", "axis = [0, 0, 0] }"))
    with pytest.raises(assur.SpecError, match=r"joints\.P1\.axis: must be a non-zero vector"):
        assur.loads(text)


def test_a_crank_arm_on_its_axis_is_located():
    text = variant(j=('P1 = { kind = "revolute", axis = [1, 0, 0] }', 'P1 = { kind = "revolute", axis = [0, 1, 0] }'))
    with pytest.raises(assur.SpecError, match=r"links\.crank: the arm P2 lies on the axis of P1"):
        _compile_text(text)


def test_a_rocker_arm_parallel_to_its_axis_is_located():
    # P3 − P4 of the sketch is (0, −45.29, 21.18): an axis along it
    text = variant(j=("axis = { gamma1 = 90, gamma2 = 0 }",
                      "axis = [0, -45.294117647058826, 21.17647058823529]"))
    with pytest.raises(assur.SpecError, match=r"links\.rocker: the point P3 lies on the axis of P4"):
        _compile_text(text)


def test_a_pin_parallel_to_the_coupler_is_located():
    text = variant(j=('P2 = { kind = "universal", axis = [-1, 0, 0] }',
                      'P2 = { kind = "universal", axis = [0, -10.705882352941176, -69.17647058823529] }'))
    with pytest.raises(assur.SpecError, match=r"joints\.P2\.axis: the pin axis is parallel to the coupler"):
        _compile_text(text)


def test_the_rocker_axis_through_the_crank_pin_is_undetermined():
    """§7 item 7 at the sketch: P2 on the rocker-axis line (V1 ∥ V2)."""
    text = variant(j=("axis = { gamma1 = 90, gamma2 = 0 }", "axis = [0, -56, -48]"))
    with pytest.raises(assur.SpecError, match=r"points\.P2: P2 lies on the axis line of P4"):
        _compile_text(text)


def test_a_sketch_that_cannot_assemble_is_located():
    text = variant(c=("length = 70", "length = 200"))
    with pytest.raises(assur.SpecError, match=r"points\.P3: the dyad solving 'P3' cannot be assembled"):
        _compile_text(text)


def test_an_ambiguous_sketch_branch_is_located():
    # P3 in the plane through the rocker axis (X) and P2: both assemblies are equally near
    text = variant(p=("P3 = [0, -9.294117647058824, 69.17647058823529]", "P3 = [5, 8, 24]"))
    with pytest.raises(assur.SpecError, match=r"points\.P3: the sketch does not tell the assembly branch"):
        _compile_text(text)


def test_a_coupler_point_on_an_idly_spinning_coupler_is_named():
    """Two spherical ends leave the coupler's spin free; with a tool point on it that spin is a real freedom
    (W = 6·3 − 5·2 − 3·2 = 2) and the message says which joint to make universal."""
    text = variant(j=('P2 = { kind = "universal", axis = [-1, 0, 0] }', 'P2 = "spherical"'))
    with pytest.raises(StructureError, match=r"W = 2 .* link coupler spins about the line of its two spherical "
                                             r"joints and carries C"):
        _compile_text(text)


def test_without_a_driver_the_mobility_is_named():
    text = P003[: P003.index("[[drivers]]")]
    with pytest.raises(StructureError, match=r"mobility W = 1 .* but 0 driver"):
        _compile_text(text)


def test_axis_given_by_angles_equals_the_vector_and_round_trips():
    m = assur.loads(P003.replace("axis = { gamma1 = 90, gamma2 = 0 }", "axis = { gamma1 = 60, gamma2 = 20 }"))
    j = next(j for j in m.joints if j.point == "P4")
    np.testing.assert_allclose(j.axis, V.e_z2(math.radians(60), math.radians(20)), atol=1e-16)
    assert assur.loads(assur.dumps(m)) == m
    assert re.search(r"\[joints\.P4\]\nkind = \"revolute\"\naxis = \[", assur.dumps(m))


def test_a_structure_only_description_says_what_is_missing():
    """A spatial file without any joint axis is structural only (its mobility is computed): solving it names
    the frame revolutes whose axes are needed."""
    with pytest.raises(StructureError, match=r"no joint axes: .* joints\.A0 = .*joints\.D0 = "):
        _compile_text(rssr("mm", 100.0))


def test_a_branch_point_is_valid_and_warned_about(plan):
    """§7 item 6: rocker 10 mm on P003-2's frame: at f1 = atan2(4,3) + 180° |P2 − P4| = 80 = 70 + 10, the
    discriminant is 0 and P3 = P4 + 10·Ort(P2 − P4) = (0, 30, 40) mm: a valid assembly at a branch point."""
    p = plan.params_with(rocker__length=0.01)
    q = np.array([math.atan2(4, 3) + math.pi])
    with pytest.warns(UnbuildableWarning, match="P3: some samples are at a branch point"):
        s = assur.solve(plan, p, q, on_unbuildable="warn")
    assert s.valid.all() and s.status["P3"][0] == V.BRANCH_POINT
    np.testing.assert_allclose(s.pos[0, plan.point_index("P3")], [0, 0.030, 0.040], atol=1e-12)
