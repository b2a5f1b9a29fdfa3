"""Forward dynamics: verdicts and stops (a motor that cannot start, the limit of assembly, a dead centre of a linear
input, the end of a stroke), the batch of designs against single runs, spatial and geared files, and bad input.
Reference values are computed here (circle intersections, the work–energy theorem, assur's solved velocities)."""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.dynamics.reduced import reduced_terms

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_a_motor_too_weak_gets_a_verdict_not_a_hang():
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    s = assur.simulate(plan, motor='kind = "dc", stall_torque = "0.5 N*m", no_load_speed = "60 rpm"')
    assert s.stop.kind == "cannot start" and not s.starts
    assert "cannot start" in s.stop.message and "stalls at q =" in s.stop.message
    assert math.isnan(s.startup_time) and not s.turns
    # the verdict is right: at the start the load needs more than the motor's stall torque
    Qa = reduced_terms(plan, None, np.array([plan.sketch_inputs[0]])).applied[0]
    assert -Qa > 0.5


def rocker_text():
    """A non-Grashof four-bar (ground 100, crank 60, coupler 50, rocker 80 mm: 60 + 100 > 50 + 80): its crank
    cannot turn fully. The sketch at crank angle 90°, B from the circle intersection computed here."""
    A = np.array([0.0, 60.0])
    O4 = np.array([100.0, 0.0])
    d = np.linalg.norm(O4 - A)
    a = (50 ** 2 - 80 ** 2 + d * d) / (2 * d)
    h = math.sqrt(50 ** 2 - a * a)
    u = (O4 - A) / d
    B = A + a * u + h * np.array([-u[1], u[0]])
    return f"""format = "assur/1"
name = "triple rocker"
[units]
length = "mm"
angle = "deg"
[points]
O2 = [0, 0]
O4 = [100, 0]
A = [0, 60]
B = [{float(B[0])!r}, {float(B[1])!r}]
[links]
frame = ["O2", "O4"]
crank = {{ points = ["O2", "A"], mass = 0.2, com = "mid" }}
coupler = {{ points = ["A", "B"], mass = 0.3, com = "mid" }}
rocker = {{ points = ["O4", "B"], mass = 0.3, com = "mid" }}
[[drivers]]
name = "crank"
link = "crank"
pivot = "O2"
arm = "A"
speed = "10 rpm"
[motor]
kind = "torque"
torque = "0.05 N*m"
"""


def test_the_limit_of_assembly_stops_the_run_with_input_and_time():
    plan = assur.compile(assur.loads(rocker_text()))
    s = assur.simulate(plan, time=5.0)
    assert s.stop.kind == "limit"
    assert f"t = {s.stop.t:.6g} s" in s.stop.message and f"q = {s.stop.q:.6g}" in s.stop.message
    assert "cannot be assembled beyond" in s.stop.message
    upper = s.equation.upper
    assert s.stop.q == pytest.approx(upper.q, abs=1e-9) and upper.q <= upper.at
    # independently: the mechanism assembles at the reported limit and not a little beyond it
    st = assur.solve(plan, None, np.array([[upper.at - 1e-9], [upper.at + 1e-6]]), order=0)
    assert st.valid.tolist() == [True, False]
    assert s.stop.t <= 5.0 and np.all(np.diff(s.q[s.t <= s.stop.t]) >= -1e-12)


def actuator_crank(motor: str) -> str:
    """A crank O–A (100 mm) pushed by an actuator from the frame point C = (−300, 0) to A: its length runs from
    200 to 400 mm; at 400 mm (A on the far side of O from C) the crank is at a dead centre."""
    return f"""format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [0, 100]
C = [-300, 0]
[links]
frame = ["O", "C"]
crank = {{ points = ["O", "A"], mass = 1.0, com = "A", inertia = 0 }}
[actuators.push]
between = ["C", "A"]
[[drivers]]
name = "push"
kind = "linear"
actuator = "push"
speed = "10 mm/s"
{motor}"""


def test_a_dead_centre_of_a_linear_input_stops_the_run():
    plan = assur.compile(assur.loads(actuator_crank('[motor]\nkind = "force"\nforce = "20 N"\n')))
    s = assur.simulate(plan, time=10.0)
    assert s.stop.kind == "limit"
    assert s.equation.upper.at == pytest.approx(0.4, abs=1e-9)          # |OC| + |OA|, the dead centre
    assert 0.39 < s.stop.q < 0.4 and s.stop.speed > 0
    assert "dead centre" in s.stop.message or "cannot be assembled" in s.stop.message


def test_work_and_energy_balance_on_a_stroke():
    """ΔT = ∫ Q_motor·q̇ dt on a horizontal actuator-driven crank (no gravity): the work–energy theorem, with T
    = ½·m·|v_A|² from assur's solved velocity of the crank's mass at A, the work integrated here (Simpson)."""
    from scipy.integrate import cumulative_simpson
    plan = assur.compile(assur.loads(actuator_crank(
        '[motor]\nkind = "hydraulic"\npressure = "10 bar"\narea = "2 cm^2"\nflow = "1 L/min"\n')))
    s = assur.simulate(plan, time=2.0, rtol=1e-12, samples=40001)
    assert s.stop.kind == "limit"
    vA = assur.solve(plan, None, s.q[:, None], speeds=s.speed[:, None], order=1).point("A").vel
    T = 0.5 * 1.0 * np.sum(vA * vA, axis=1)
    work = cumulative_simpson(s.effort * s.speed, x=s.t, initial=0.0)
    assert np.max(np.abs(T - T[0] - work)) <= 1e-6 * np.max(T)
    # the valve limits the speed: it never exceeds the rated flow over the area
    assert np.max(s.speed) < (1e-3 / 60) / 2e-4


def test_a_batch_of_designs_matches_single_runs():
    text = (EXAMPLES / "slider_crank.toml").read_text()
    text = text.replace('length = 50\n', 'length = 50\nmass = 0.5\ncom = "O"\ninertia = 5e-4\n', 1)
    text = text.replace('length = 150\n', 'length = 150\nmass = 0.3\n', 1)
    text += '\n[motor]\nkind = "dc"\nstall_torque = "1 N*m"\nno_load_speed = "3000 rpm"\ngear_ratio = 5\n'
    plan = assur.compile(assur.loads(text))
    P = np.tile(plan.defaults, (3, 1))
    P[1, plan.param_index("crank.length")] *= 0.9
    P[2, plan.param_index("rod.length")] *= 1.2
    batch = assur.simulate(plan, params=P, backend="numpy")      # the compiled route: test_dynamics_faces.py
    assert batch.q.shape == (3, batch.t.size) and batch.speed.shape == batch.q.shape
    for d in range(3):
        one = assur.simulate(plan, params=P[d])
        assert batch.stop[d] == "steady" and one.steady
        assert batch.mean_speed[d] == pytest.approx(one.mean_speed, rel=1e-6)
        assert batch.delta[d] == pytest.approx(one.delta, rel=1e-4)
        assert batch.startup_time[d] == pytest.approx(one.startup_time, rel=1e-5)
        t = batch.t[batch.t <= one.t[-1]]
        assert np.nanmax(np.abs(np.interp(t, one.t, one.speed) - batch.speed[d, : t.size])) < 1e-3 * one.mean_speed


def test_a_batch_reports_designs_that_do_not_turn():
    plan = assur.compile(assur.loads(rocker_text()))
    r = assur.simulate(plan, params=plan.defaults[None, :], time=1.0, backend="numpy")
    assert r.stop == ("does not turn",) and not r.starts[0]


SPATIAL_MASSES = """
[links.crank]
points = ["P1", "P2"]
mass = 0.1
com = "P2"
inertia = 0
[links.coupler]
points = ["P2", "P3", "C"]
length = 70
mass = 0.2
com = "P3"
inertia = 0
[links.rocker]
points = ["P4", "P3"]
length = 50
mass = 0.15
com = "P3"
inertia = 0
"""


def test_spatial_reduced_inertia_is_the_kinetic_energy():
    """J* of the RSSR with point masses at P2 and P3 (no rotational inertia) is Σ m·|v|² at unit crank speed,
    from assur's solved velocities."""
    text = (EXAMPLES / "rssr.toml").read_text()
    links = ('crank = ["P1", "P2"]\ncoupler = { points = ["P2", "P3", "C"], length = 70 }\n'
             'rocker = { points = ["P4", "P3"], length = 50 }\n')
    assert links in text
    text = text.replace(links, "").replace('frame = ["P1", "P4"]\n', 'frame = ["P1", "P4"]\n' + SPATIAL_MASSES)
    text = text.split("# -- forces")[0]           # no resisting torque: a free motion
    plan = assur.compile(assur.loads(text))
    q = np.linspace(0, 2 * math.pi, 9)
    t = reduced_terms(plan, None, q)
    st = assur.solve(plan, None, q[:, None], speeds=[1.0], order=1)
    v2, v3 = st.point("P2").vel, st.point("P3").vel
    J = 0.1 * np.sum(v2 * v2, axis=1) + (0.2 + 0.15) * np.sum(v3 * v3, axis=1)
    assert np.allclose(t.inertia, J, rtol=1e-9, atol=1e-15)
    h = 1e-6
    tp, tm = reduced_terms(plan, None, q + h), reduced_terms(plan, None, q - h)
    assert np.allclose(t.inertia_rate, (tp.inertia - tm.inertia) / (2 * h), rtol=1e-5, atol=1e-12)
    s = assur.simulate(plan, motor=False, cycles=2, speed0=30.0)
    assert len(s.turns) == 2 and s.energy is not None
    assert np.ptp(s.energy) <= 1e-8 * np.max(np.abs(s.energy))


def test_geared_reduced_inertia_is_the_force_analysis_response():
    """In the motor's angle: J* from the analogues equals the driving torque's response to q̈ in the force analysis
    (its tooth forces included), ½J*′ its response to q̇²."""
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar_geared.toml"))
    q = np.linspace(0, 2 * math.pi, 11)
    t = reduced_terms(plan, None, q)
    d = {(w, a): assur.forces(plan, None, q[:, None], speeds=[w], accels=[a]).driver[:, 0]
         for w, a in ((0, 0), (0, 1), (1, 0))}
    assert np.allclose(t.inertia, d[0, 1] - d[0, 0], rtol=1e-9, atol=1e-12)
    assert np.allclose(0.5 * t.inertia_rate, d[1, 0] - d[0, 0], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("kwargs, where", [
    (dict(motor=False), "time"),
    (dict(time=1.0, cycles=2), "time"),
    (dict(time=-1.0), "time"),
    (dict(cycles=1.5), "cycles"),
    (dict(motor='kind = "dc", stall_torque = -1, no_load_speed = 10'), "--motor.stall_torque"),
    (dict(motor="kind = dc"), "--motor"),
    (dict(motor={"kind": "force", "force": 10}), "motor.kind"),
    (dict(method="Euler", time=1.0), "method"),
])
def test_bad_input_is_located(kwargs, where):
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    with pytest.raises(assur.SpecError) as err:
        assur.simulate(plan, **kwargs)
    assert where in str(err.value)


def test_a_mechanism_without_inertia_is_refused():
    plan = assur.compile(assur.load(EXAMPLES / "crank_rocker.toml"))
    with pytest.raises(assur.SpecError, match="inertia"):
        assur.simulate(plan, motor=False, time=1.0)
