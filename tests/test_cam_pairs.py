"""A cam pair as an element of a mechanism: the ``[[cams]]`` table (located errors, the writer's round trip, the
builder), its structure (p4, the follower's class II group), the engine's exact jets against finite differences of
the positions, and the contact force along the common normal against virtual power (1e-9)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import assur
from assur.cams.followers import from_plan
from assur.errors import SpecError
from conftest import EXAMPLES

PRESS = EXAMPLES / "cam_press.toml"

LIFTER = """
format = "assur/1"
name = "flat-faced lifter and lever"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
K = [30, 0]
R = [6, 45]
T = [6, 110]
L0 = [70, 180]
L = [70, 120]
[links]
frame = ["O", "L0"]
cam = ["O", "K"]
lever = ["L0", "L"]
rod = ["T", "L"]
[links.lifter]
points = ["R", "T"]
mass = "0.4 kg"
[[prismatic]]
name = "guide"
link = "lifter"
guide = "frame"
through = "O"
angle = 90
offset = -6
[[drivers]]
name = "shaft"
kind = "rotary"
link = "cam"
pivot = "O"
arm = "K"
speed = "300 rpm"
sense = "cw"
[[cams]]
name = "cam"
cam = "cam"
follower = "lifter"
point = "R"
contact = "flat"
law = [{ motion = "polynomial_345", angle = 150, lift = 15 }, { motion = "dwell", angle = 30 },
       { motion = "modified_trapezoid", angle = 150, lift = -15 }, { motion = "dwell", angle = 30 }]
[dynamics]
gravity = [0, -9.81]
[[loads]]
link = "lever"
torque = "-2 N*m"
"""


@pytest.fixture(scope="module")
def press():
    return assur.compile(assur.load(PRESS))


@pytest.fixture(scope="module")
def lifter():
    return assur.compile(assur.loads(LIFTER))


def test_structure_counts_the_cam_as_a_higher_pair(press, lifter):
    s = press.structure
    assert s.pair_counts["p4"] == 1 and s.mobility == 1
    assert s.structural_formula == "I(frame, cam) → II(rocker, lift′) → II(rod, ram.block)"
    assert [g["kind"] for g in s.describe()] == ["cam", "RRP"]
    assert s.describe()[0]["cam_pair"] == "lift" and s.describe()[0]["substitute_link"] == "lift′"
    assert [st.kind for st in press.steps] == ["frame", "crank", "cam", "RRP"]
    assert [st.kind for st in lifter.steps] == ["frame", "crank", "cam_slide", "RRR"]


def test_round_trip_through_the_writer(press, lifter):
    for m in (press.mechanism, lifter.mechanism):
        again = assur.loads(assur.dumps(m))
        assert again.cams == m.cams
        assert assur.dumps(again) == assur.dumps(m)


def test_builder_writes_the_same_table():
    m = assur.load(PRESS)
    cp = m.cams[0]
    b = (assur.Builder(units="mm").point("O", 0, 0).point("K", 40, 0).point("F", 100, 0).point("R", 30.5, 39.62)
         .frame("O", "F").link("cam", "O", "K").link("rocker", "F", "R")
         .crank("cam", pivot="O", arm="K", speed="60 rpm")
         .cam("cam", "rocker", point="R", roller_radius=10, name="lift",
              law=[{"motion": "cycloidal", "angle": 120, "lift": 20}, {"motion": "dwell", "angle": 60},
                   {"motion": "modified_sine", "angle": 120, "lift": -20}, {"motion": "dwell", "angle": 60}]))
    built = b.build()
    assert built.cams[0] == cp


@pytest.mark.parametrize("change,where", [
    (('follower = "rocker"', 'follower = "rod"'), "cams[0].follower"),
    (('point = "R"', 'point = "D"'), "cams[0].point"),
    (('roller_radius = 10\n', ''), "cams[0].roller_radius"),
    (('motion = "modified_sine"', 'motion = "wobble"'), "cams[0].law[2].motion"),
    (('angle = 120, lift = -20', 'angle = 120, lift = -19'), "cams[0].law"),
    (('angle = 60 },\n]', 'angle = 50 },\n]'), "cams[0].law"),
    (('cam = "cam"\nfollower', 'cam = "frame"\nfollower'), "cams[0].cam"),
    (('contact = "roller"', 'contact = "spring"'), "cams[0].contact"),
])
def test_errors_are_located(change, where):
    text = PRESS.read_text()
    old, new = change
    assert old in text
    with pytest.raises(SpecError) as e:
        assur.loads(text.replace(old, new, 1))
    assert where in str(e.value)


def test_the_follower_turns_by_the_law(press):
    """The rocker's angle from the sketch is −(s(φ) − s(0)) (the lift turns it clockwise, away from the cam)."""
    q = np.linspace(0, 2 * math.pi, 73)[:-1]
    st = assur.solve(press, inputs=q)
    F, R = (st.pos[:, press.point_index(p)] for p in ("F", "R"))
    ang = np.unwrap(np.arctan2(R[:, 1] - F[:, 1], R[:, 0] - F[:, 0]))
    s = press.mechanism.cams[0].law.evaluate(q)[0]
    assert np.max(np.abs((ang - ang[0]) + s)) <= 1e-12


def _richardson(f, x, h):
    d1 = (f(x + h) - f(x - h)) / (2 * h)
    d2 = (f(x + h / 2) - f(x - h / 2)) / h
    return (4 * d2 - d1) / 3


@pytest.mark.parametrize("which", ["press", "lifter"])
def test_kinematics_against_finite_differences(which, press, lifter):
    """Every point's velocity and acceleration analogues (d/dq, d²/dq²) equal Richardson-extrapolated central
    differences of the solved positions, to 1e-9 of the mechanism's size (away from the laws' joints)."""
    plan = press if which == "press" else lifter
    q = np.array([0.3, 1.1, 2.7, 3.9, 4.6])
    st = assur.solve(plan, inputs=q, order=2)
    pos = lambda x: assur.solve(plan, inputs=x).pos   # noqa: E731
    h = 1e-3
    v = _richardson(pos, q, h)
    a = _richardson(lambda x: assur.solve(plan, inputs=x, order=1).dpos_dq[..., 0], q, h)
    L = plan.length_scale
    assert np.max(np.abs(st.dpos_dq[..., 0] - v)) <= 1e-9 * L
    assert np.max(np.abs(st.d2pos_dq2[..., 0, 0] - a)) <= 1e-9 * L * 10


def _virtual_power(plan, st, f):
    """−Σ (applied and d'Alembert loads)·(velocities) per unit input rate, from the state alone (masses as the file
    gives them: a point-mass polygon for a link of three points, a slender bar for a binary link, a block's point
    mass, a given com and inertia)."""
    m = plan.mechanism
    dyn = m.dynamics
    g = np.array(dyn.gravity[:2])
    P = lambda n: st.pos[:, plan.point_index(n)]          # noqa: E731
    V = lambda n: st.vel[:, plan.point_index(n)]          # noqa: E731
    A = lambda n: st.acc[:, plan.point_index(n)]          # noqa: E731
    power = np.zeros(len(st.pos))
    for name, mp in dyn.bodies:
        if name.endswith(".block"):
            pts = [next(p.point for p in m.prismatic if f"{p.name}.block" == name)]
        else:
            pts = list(m.link(name).points)
        if mp.com == "O":                                  # the cam: on its pivot, no α at a constant speed
            power += mp.mass * np.einsum("ij,ij->i", g - A("O"), V("O"))
            continue
        if len(pts) == 2 and mp.inertia is None:           # a slender bar about its middle
            c_v = 0.5 * (V(pts[0]) + V(pts[1]))
            c_a = 0.5 * (A(pts[0]) + A(pts[1]))
            d = P(pts[1]) - P(pts[0])
            dv = V(pts[1]) - V(pts[0])
            da = A(pts[1]) - A(pts[0])
            L2 = np.einsum("ij,ij->i", d, d)
            omega = (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]) / L2
            alpha = (d[:, 0] * da[:, 1] - d[:, 1] * da[:, 0]) / L2
            power += mp.mass * np.einsum("ij,ij->i", g - c_a, c_v) - mp.mass * L2 / 12 * alpha * omega
        else:                                              # point masses m/k at the points
            for p in pts:
                power += mp.mass / len(pts) * np.einsum("ij,ij->i", g - A(p), V(p))
    for ld in dyn.loads:
        if ld.force is not None:
            power += np.einsum("ij,j->i", V(ld.point), np.array(ld.force[:2]))
        else:
            lk = m.link(ld.link).points
            d, dv = P(lk[1]) - P(lk[0]), V(lk[1]) - V(lk[0])
            power += ld.torque * (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]) / np.einsum("ij,ij->i", d, d)
    return -power / st.qdot[0]


@pytest.mark.parametrize("which", ["press", "lifter"])
def test_driving_torque_by_virtual_power(which, press, lifter):
    plan = press if which == "press" else lifter
    q = np.linspace(0, 2 * math.pi, 181)[:-1]
    st = assur.solve(plan, inputs=q, order=2)
    f = assur.forces(plan, inputs=q, state=st)
    want = _virtual_power(plan, st, f)
    scale = np.max(np.abs(want))
    assert scale > 0
    assert np.nanmax(np.abs(f.driver[:, 0] - want)) <= 1e-9 * scale
    fm = assur.forces(plan, inputs=q, state=st, method="matrix")
    assert np.nanmax(np.abs(fm.driver - f.driver)) <= 1e-9 * scale


def test_contact_force_is_along_the_profile_normal(press):
    """The contact force is normal to the cam profile at the contact: its direction, seen from the cam, is
    perpendicular to the profile's tangent (central differences of the profile), and it pushes (F > 0)."""
    q = np.linspace(0.1, 2 * math.pi - 0.1, 50)
    st = assur.solve(press, inputs=q, order=2)
    f = assur.forces(press, inputs=q, state=st)
    c = f.cams["lift"]
    assert np.all(c["contact_force"] > 0) and not np.any(c["lost"])
    g = from_plan(press, "lift")
    h = 1e-5
    tangent = (g.at(q + h).profile - g.at(q - h).profile) / (2 * h)
    n_cam = np.exp(-1j * q) * c["normal"]                  # the cam turned by q from the sketch
    cosang = np.real(np.conj(n_cam) * tangent) / np.abs(tangent)
    assert np.max(np.abs(cosang)) <= 1e-8
    # the contact point seen from the cam lies on the profile
    assert np.max(np.abs(np.exp(-1j * q) * (c["contact"] - complex(*st.pos[0, press.point_index("O")]))
                         - g.at(q).profile)) <= 1e-12


def test_pressure_angle_of_the_mechanism_matches_the_cam_geometry(press):
    q = np.linspace(0, 2 * math.pi, 37)[:-1]
    f = assur.forces(press, inputs=q)
    g = from_plan(press, "lift")
    assert np.max(np.abs(f.cams["lift"]["pressure_angle"] - g.at(q).pressure_angle)) <= 1e-12


def test_translating_follower_sits_on_its_law(lifter):
    """The lifter's reference point rises by s(φ) − s(0) along its slide, the law running as the shaft turns
    clockwise (its crank's sense)."""
    q = np.linspace(0, 2 * math.pi, 73)[:-1]
    st = assur.solve(lifter, inputs=q)
    y = st.pos[:, lifter.point_index("R"), 1]
    law = lifter.mechanism.cams[0].law
    assert lifter.mechanism.cams[0].rotation == -1
    assert np.max(np.abs((y - y[0]) - (law.evaluate(q)[0] - law.evaluate(np.asarray(0.0))[0]))) <= 1e-12


def test_a_cam_must_be_turned_by_the_drive():
    """A lever turned by the linkage cannot be a cam (the solver does not know its whole turn before the groups)."""
    from assur.errors import StructureError
    bad = PRESS.read_text().replace('cam = "cam"\nfollower = "rocker"', 'cam = "rod"\nfollower = "rocker"')
    with pytest.raises(SpecError, match=r"cams\[0\]\.cam"):
        assur.loads(bad)                                    # the rod turns about no frame pivot
    text = LIFTER.replace('cam = "cam"\nfollower', 'cam = "lever"\nfollower')
    with pytest.raises(StructureError):
        assur.compile(assur.loads(text))


def _as_profile_cam(text: str, plan) -> str:
    """The file ``text`` with its law replaced by its cam's own profile (a polar table in mm and degrees, 720 points
    read off a periodic quintic spline of the conjugate profile's radius by its polar angle)."""
    from scipy.interpolate import make_interp_spline
    prof = from_plan(plan, 0).profile(2880)
    ang, rad = np.angle(prof) % (2 * math.pi), np.abs(prof)
    o = np.argsort(ang)
    ang, rad = ang[o], rad[o]
    sp = make_interp_spline(np.append(ang, ang[0] + 2 * math.pi), np.append(rad, rad[0]), k=5, bc_type="periodic")
    A = np.linspace(0.0, 360.0, 720, endpoint=False)
    R = sp(np.radians(A) + (np.radians(A) < ang[0]) * 2 * math.pi) * 1e3
    start = text.index("law = [")
    end = text.index("]", text.index("}", text.rindex("motion"))) + 1
    table = ("law = { profile = { angle = [" + ", ".join(f"{a:.12g}" for a in A) + "], radius = ["
             + ", ".join(f"{r:.15g}" for r in R) + "] } }")
    return text[:start] + table + text[end:]


@pytest.mark.parametrize("which", [pytest.param("press", marks=pytest.mark.slow), "lifter"])
def test_a_cam_given_by_its_profile_moves_the_follower_by_the_law(which, press, lifter):
    """Law → conjugate profile (the envelope) → a cam given by that profile → the follower's motion by contact: the
    same motion (to the profile table's own resolution), and the profile table round-trips through the writer."""
    plan = press if which == "press" else lifter
    text = PRESS.read_text() if which == "press" else LIFTER
    m2 = assur.loads(_as_profile_cam(text, plan))
    assert m2.cams[0].law.profile and m2.cams[0].law.kind == "table"
    p2 = assur.compile(m2)
    q = np.linspace(0, 2 * math.pi, 97)[:-1]
    a, b = assur.solve(plan, inputs=q).pos, assur.solve(p2, inputs=q).pos
    assert np.max(np.abs(a - b)) <= 1e-8 * plan.length_scale
    again = assur.loads(assur.dumps(m2))
    assert again.cams[0].law.profile == m2.cams[0].law.profile
    assert np.allclose(again.cams[0].law.lifts, m2.cams[0].law.lifts, rtol=0, atol=1e-15)


@pytest.mark.slow
def test_a_profile_off_the_sketch_is_refused(press):
    text = _as_profile_cam(PRESS.read_text(), press).replace("R = [30.5, 39.62]", "R = [31.5, 40.62]")
    with pytest.raises(SpecError, match=r"cams\[0\]\.point"):
        assur.loads(text)
