"""The MuJoCo export against a real MuJoCo: every shipped planar example loads (or is refused naming the element),
its joints follow assur's kinematics when driven at constant speed, the four-bar leg walks on the ground plane with
the stride of its kinematics (computed here: the lower foot carries the body), a DC motor's start-up matches the
closed form, and a refused export writes nothing."""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.dynamics.mjcf import MJCFOptions, mjcf_text, write_mjcf

mujoco = pytest.importorskip("mujoco")
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def planar_examples():
    out = []
    for p in sorted(EXAMPLES.glob("*.toml")):
        text = p.read_text()
        if 'format = "assur/1"' in text and "dimension = 3" not in text:
            out.append(p.name)
    return out


REFUSED = {"walker_fourbar_geared.toml": "gears.drive", "cam_press.toml": "cams.lift"}


def test_every_planar_example_is_covered():
    names = planar_examples()
    assert len(names) >= 15 and "jansen.toml" in names and "walker_fourbar.toml" in names


@pytest.mark.parametrize("name", planar_examples())
def test_each_planar_example_loads_in_mujoco_or_is_refused_by_name(name):
    plan = assur.compile(assur.load(EXAMPLES / name))
    if name in REFUSED:
        with pytest.raises(assur.SpecError) as err:
            mjcf_text(plan)
        assert str(err.value).startswith(REFUSED[name] + ":")
        return
    model = mujoco.MjModel.from_xml_string(mjcf_text(plan))
    assert model.nu == 1 and model.nsite >= len(plan.point_names)
    # every loop the tree leaves open is closed by an equality constraint
    g = plan.structure.graph
    n_pairs = sum(1 for p in g.pairs if p.kind in "RP")
    legs = len(plan.mechanism.gait.phases) if plan.mechanism.gait else 1
    bodies = len(g.bodies) - 1
    connects = int(np.sum(model.eq_type == mujoco.mjtEq.mjEQ_CONNECT))
    assert connects == legs * (n_pairs - bodies)


def test_a_spatial_file_is_refused():
    plan = assur.compile(assur.load(EXAMPLES / "rssr.toml"))
    with pytest.raises(assur.SpecError, match="dimension: the MuJoCo export covers planar"):
        mjcf_text(plan)


def _drive_one_cycle(plan, every: int = 50):
    """Drive the exported model (no legs) with its velocity servo over one turn (or the stroke); return the largest
    distance of a site from assur's position of its point at MuJoCo's input, over the mechanism's size."""
    model = mujoco.MjModel.from_xml_string(mjcf_text(plan, options=MJCFOptions(legs=False, actuator="velocity")))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    move = next(k for k in range(plan.n_inputs) if plan.speeds[k] != 0)
    adr = model.jnt_qposadr[model.actuator(0).trnid[0]]
    sense = model.actuator_gear[0, 0]
    w = abs(float(plan.speeds[move]))
    if plan.input_kinds[move] == "rotary":
        duration = 2 * math.pi / w
    else:
        lo, hi = sorted(plan.mechanism.drivers[move].range)
        duration = 0.9 * (hi - plan.sketch_inputs[move]) / w
    qs, X = [], []
    for i in range(int(duration / model.opt.timestep)):
        mujoco.mj_step(model, data)
        if i % every == 0:
            mujoco.mj_kinematics(model, data)         # the sites at the stepped qpos
            qs.append(data.qpos[adr] * sense)
            X.append(data.site_xpos.copy())
    q = np.tile(plan.sketch_inputs, (len(qs), 1))
    q[:, move] += np.array(qs)
    st = assur.solve(plan, None, q, order=0)
    names = [model.site(i).name for i in range(model.nsite)]
    P = np.stack([st.point(n).pos for n in names], axis=1)
    X = np.array(X)
    assert np.all(np.asarray(st.valid)) and np.ptp(qs) > 0.5 * w * duration
    return float(np.max(np.hypot(X[..., 0] - P[..., 0], X[..., 2] - P[..., 1]))) / plan.length_scale


QUICK = ("crank_rocker.toml", "slider_crank.toml", "walker_fourbar.toml")


@pytest.mark.parametrize("name", [n if n in QUICK else pytest.param(n, marks=pytest.mark.slow)
                                  for n in planar_examples() if n not in REFUSED])
def test_driven_at_constant_speed_every_joint_follows_the_kinematics(name):
    plan = assur.compile(assur.load(EXAMPLES / name))
    assert _drive_one_cycle(plan) <= 1e-4


def kinematic_stride(plan):
    """The body's advance per crank turn of a two-leg module in antiphase when the lower foot carries the body and
    does not slip: −∮ v_x of the lower foot dq (per unit crank speed), from assur's solved foot velocities."""
    n = 7200
    q = np.linspace(0, 2 * math.pi, n, endpoint=False)
    feet = [assur.solve(plan, None, (q + p)[:, None], speeds=[1.0], order=1).point(plan.mechanism.gait.foot)
            for p in plan.mechanism.gait.phases]
    low = np.argmin(np.stack([f.pos[:, 1] for f in feet]), axis=0)
    vx = np.choose(low, [f.vel[:, 0] for f in feet])
    return -float(np.sum(vx)) * 2 * math.pi / n


def test_the_fourbar_leg_walks_with_its_kinematic_stride():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    model = mujoco.MjModel.from_xml_string(mjcf_text(plan))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    x = model.joint("base_x").qposadr[0]
    crank = model.jnt_qposadr[model.actuator(0).trnid[0]]
    worst = 0.0
    for i in range(int(10.0 / model.opt.timestep)):
        mujoco.mj_step(model, data)
        if i % 200 == 0:
            eq = data.efc_type[:data.nefc] == mujoco.mjtConstraint.mjCNSTR_EQUALITY
            worst = max(worst, float(np.max(np.abs(data.efc_pos[:data.nefc][eq]), initial=0.0)))
    assert np.all(np.isfinite(data.qpos)) and data.time >= 10.0 - 1e-9
    assert worst <= 1e-3 * plan.length_scale                      # the loops held all along
    turns = data.qpos[crank] / (2 * math.pi)
    assert turns > 4
    stride = data.qpos[x] / turns
    expected = kinematic_stride(plan)
    assert abs(stride - expected) <= 0.10 * abs(expected)


def test_a_dc_motor_actuator_starts_a_constant_inertia_as_the_closed_form():
    """The file's DC motor becomes a general actuator τ = T_s(1 − ω/ω₀); MuJoCo's start-up of a disc of constant
    inertia J then follows ω₀(1 − e^{−t/τ}), τ = J·ω₀/T_s (to the first-order integrator's error)."""
    m = (assur.Builder(units="m", angle="deg", name="disc")
         .point("O", 0, 0).point("A", 0.1, 0).frame("O").link("disc", "O", "A")
         .crank("disc", pivot="O", arm="A", speed="100 rpm", name="crank")
         .mass("disc", 2.0, inertia=0.05, com="O").build())
    text = assur.dumps(m) + '\n[motor]\nkind = "dc"\nstall_torque = 5\nno_load_speed = "100 rad/s"\n'
    plan = assur.compile(assur.loads(text))
    xml = mjcf_text(plan)
    assert '<general name="motor"' in xml
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_resetData(model, data)
    data.ctrl[0] = 1.0
    tau = 0.05 * 100 / 5
    for _ in range(int(2 * tau / model.opt.timestep)):
        mujoco.mj_step(model, data)
    assert data.qvel[0] == pytest.approx(100 * (1 - math.exp(-data.time / tau)), rel=1e-3)


def test_a_refused_export_writes_nothing(tmp_path):
    out = tmp_path / "leg.xml"
    out.write_text("keep me")
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar_geared.toml"))
    with pytest.raises(assur.SpecError):
        write_mjcf(plan, out)
    assert out.read_text() == "keep me"
    plan = assur.compile(assur.load(EXAMPLES / "crank_rocker.toml"))
    write_mjcf(plan, out)
    assert mujoco.MjModel.from_xml_path(str(out)).nbody == 4
