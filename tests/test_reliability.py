"""Reliability of the engine's answers: the Newton oracle stays on one branch and reaches every buildable
input, non-physical designs are unbuildable (never mirrored), singular positions are named, and a sketch
that does not fit a Newton-solved group's dimensions is refused at compile time."""
import cmath
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import SpecError, UnbuildableWarning

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def fourbar_text(crank, coupler, rocker, ground=100.0, theta_deg=100.0):
    """A crank-rocker file (mm) with O2 = (0, 0), O4 = (ground, 0), sketched at crank angle ``theta_deg``
    with B above the line A → O4; B is placed by an independent circle intersection here."""
    A = crank * cmath.exp(1j * math.radians(theta_deg))
    O4 = complex(ground, 0)
    d = abs(O4 - A)
    a = (coupler ** 2 - rocker ** 2 + d ** 2) / (2 * d)
    h = math.sqrt(max(coupler ** 2 - a * a, 0.0))
    u = (O4 - A) / d
    B = A + a * u + 1j * u * h
    return f'''format = "assur/1"
name = "test four-bar"
[units]
length = "mm"
angle = "deg"
[points]
O2 = [0, 0]
O4 = [{ground}, 0]
A = [{A.real!r}, {A.imag!r}]
B = [{B.real!r}, {B.imag!r}]
[links]
frame = ["O2", "O4"]
[links.crank]
points = ["O2", "A"]
length = {crank}
[links.coupler]
points = ["A", "B"]
length = {coupler}
[links.rocker]
points = ["O4", "B"]
length = {rocker}
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O2"
arm = "A"
zero = 0
sense = "ccw"
speed = "60 rpm"
'''


def sweep(step_deg, windows=((0.0, 360.0),)):
    """Input angles (deg) at ``step_deg`` over the windows (the 0.01° sweeps cover the critical windows only)."""
    return np.concatenate([np.arange(lo, hi, step_deg) for lo, hi in windows]) % 360.0


def _compare(plan, q_deg):
    q = np.radians(q_deg)
    closed = assur.solve(plan, inputs=q, order=0)
    newton = assur.solve(plan, inputs=q, order=0, method="newton")
    return closed, newton


# -- the Newton oracle continues both ways round ------------------------------------------------------------------
LOCKED = (40.0, 70.0, 60.0)
#: |O4 − A|² = 40² + 100² − 2·40·100·cos θ exceeds (70 + 60)² where cos θ < −0.6625: the crank is locked out of
#: (131.5°, 228.5°); sketched at 100°, the inputs past the locked range (e.g. 260°) are reached only the long way.
LOCKED_GAP = (math.degrees(math.acos(-0.6625)), 360 - math.degrees(math.acos(-0.6625)))


@pytest.mark.parametrize("step", [10.0, 1.0, pytest.param(0.01, marks=pytest.mark.slow)])
def test_newton_reaches_inputs_past_a_locked_range_the_other_way_round(step):
    plan = assur.compile(assur.loads(fourbar_text(*LOCKED)))
    q = sweep(step) if step >= 1 else sweep(step, ((120.0, 140.0), (220.0, 270.0)))
    closed, newton = _compare(plan, q)
    outside = (q < LOCKED_GAP[0] - 0.01) | (q > LOCKED_GAP[1] + 0.01)
    assert closed.valid[outside].all() and not closed.valid[(q > LOCKED_GAP[0] + 0.01) & (q < LOCKED_GAP[1] - 0.01)].any()
    np.testing.assert_array_equal(newton.valid, closed.valid)
    np.testing.assert_allclose(newton.pos[newton.valid], closed.pos[closed.valid], rtol=0, atol=1e-12)


# -- the Newton oracle never reports the other branch as valid ------------------------------------------------------
#: s + l = 40 + 139.999 = 179.999 mm, 1e-3 mm short of p + q = 100 + 80: the coupler and rocker pass within
#: 1e-3 mm of a change point near θ = 0, where the two assemblies almost meet.
NEAR_GRASHOF = (40.0, 139.999, 80.0)


@pytest.mark.parametrize("sketch_deg", [100.0, 300.0])
@pytest.mark.parametrize("step", [10.0, 1.0, pytest.param(0.01, marks=pytest.mark.slow)])
def test_newton_never_certifies_the_other_branch_near_a_change_point(step, sketch_deg):
    plan = assur.compile(assur.loads(fourbar_text(*NEAR_GRASHOF, theta_deg=sketch_deg)))
    q = sweep(step) if step >= 1 else sweep(step, ((-3.0, 3.0), (175.0, 185.0)))
    closed, newton = _compare(plan, q)
    assert closed.valid.all()                            # s + l < p + q: the crank turns fully
    # every sample the oracle calls valid is on the closed form's (the sketch's) branch ...
    np.testing.assert_allclose(newton.pos[newton.valid], closed.pos[newton.valid], rtol=0, atol=1e-9)
    # ... and only samples within a whisker of the change point may stay uncertified
    uncertified = q[~newton.valid]
    assert np.all(np.minimum(uncertified, 360.0 - uncertified) < 1.0)


# -- non-physical designs --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["crank.length", "rocker.length", "coupler.length"])
@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_negative_length_is_unbuildable_never_mirrored(name, backend):
    plan = assur.compile(assur.loads(fourbar_text(40.0, 120.0, 80.0)))
    p = plan.defaults.copy()
    p[plan.param_index(name)] *= -1.0
    q = np.radians(np.arange(0.0, 360.0, 5.0))
    good = assur.solve(plan, inputs=q)
    assert good.valid.all()
    bad = assur.solve(plan, p, q, backend=backend)
    assert not bad.valid.any() and np.isnan(bad.pos).all()


@pytest.mark.parametrize("name", ["crank.length", "rocker.length", "coupler.length"])
def test_a_negative_spatial_length_is_unbuildable(name):
    plan = assur.compile(assur.load(EXAMPLES / "rssr.toml"))
    q = np.radians(np.arange(0.0, 360.0, 10.0))
    assert assur.solve(plan, inputs=q).valid.any()
    p = plan.defaults.copy()
    p[plan.param_index(name)] *= -1.0
    assert not assur.solve(plan, p, q).valid.any()


# -- singular positions are named -------------------------------------------------------------------------------------
def test_a_change_point_is_flagged_singular():
    """s + l = 40 + 140 = p + q = 100 + 80: at θ = 0 the crank lies along the ground, |O4 − A| = 60 = 140 − 80,
    so coupler and rocker are collinear: the two assemblies meet (a change point) and the velocity is not
    finite there; everywhere else the positions and velocities are finite."""
    plan = assur.compile(assur.loads(fourbar_text(40.0, 140.0, 80.0)))
    q = np.radians(np.arange(0.0, 360.0, 1.0))
    st = assur.solve(plan, inputs=q)
    assert st.valid.all()
    assert st.singular[0] and not st.singular[1:].any()
    assert not np.isfinite(st.vel[0]).all() and np.isfinite(st.vel[1:]).all()
    assert assur.solve(plan, inputs=q, order=0).singular is None
    with pytest.warns(UnbuildableWarning, match="1 samples are at a singular position"):
        assur.solve(plan, inputs=q, on_unbuildable="warn")


# -- a sketch that does not fit a Newton-solved group ------------------------------------------------------------------
def test_a_triad_sketch_off_its_dimensions_is_refused_with_the_joint_and_the_distance():
    """examples/triad_sixbar.toml sketches |P1 C| = |(200, 90) − (300, 0)| = 134.54 mm; giving r1 a length of
    120 mm moves C by 14.5 mm from where the drawn triad has it."""
    text = (EXAMPLES / "triad_sixbar.toml").read_text(encoding="utf-8")
    assur.compile(assur.loads(text))                       # the file as shipped fits
    bad = text.replace('r1 = ["P1", "C"]', '')
    bad += '\n[links.r1]\npoints = ["P1", "C"]\nlength = 120\n'
    with pytest.raises(SpecError, match=r"points\.C: the sketch does not fit the dimensions of the group .*at C it is "
                                        r"0\.01454 m off"):
        assur.compile(assur.loads(bad))


def test_a_point_drawn_on_another_point_of_its_link_is_refused():
    """B drawn on O4 (both on the rocker): the sketch no longer tells which of the two assemblies is meant."""
    text = (EXAMPLES / "crank_rocker.toml").read_text(encoding="utf-8")
    bad = text.replace("B = [133.880965996, 72.471236661]", "B = [100, 0]")
    assert bad != text
    with pytest.warns(Warning), pytest.raises(SpecError, match=r"points\.B: the sketch puts B on O4, a point of the "
                                                               r"same link: it cannot tell the assembly branch"):
        assur.compile(assur.loads(bad))
    hinted = bad + '\n[branches.B]\nside = "left"\nof = ["A", "O4"]\n'
    with pytest.warns(Warning):
        plan = assur.compile(assur.loads(hinted))            # a hint decides instead
    assert plan.n_points == 5


def test_a_driven_actuator_between_two_frame_points_is_refused():
    text = (EXAMPLES / "lever_manipulator.toml").read_text(encoding="utf-8")
    bad = text.replace('[actuators.drive_rod]\nbetween = ["A", "B"]', '[actuators.drive_rod]\nbetween = ["O", "A"]')
    assert bad != text
    with pytest.raises(SpecError, match=r"drivers\[0\]\.actuator: the driven actuator drive_rod joins two frame "
                                        r"points \(O, A\): its length cannot change"):
        assur.compile(assur.loads(bad))
