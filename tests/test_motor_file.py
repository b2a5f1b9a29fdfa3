"""The ``[motor]`` table: reading with located errors, writing back exactly, the ``--motor`` option, and the motor
characteristics against their formulas evaluated here."""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.dynamics.motors import drive_train
from assur.io.motor_file import parse_motor_option

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SLIDER = (EXAMPLES / "slider_crank.toml").read_text()
ACTUATOR = """format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
A = [0, 100]
C = [-300, 0]
[links]
frame = ["O", "C"]
crank = { points = ["O", "A"], mass = 1.0 }
[actuators.push]
between = ["C", "A"]
[[drivers]]
name = "push"
kind = "linear"
actuator = "push"
"""

MOTORS = {
    "torque": (SLIDER, 'kind = "torque"\ntorque = "2 N*m"\nflywheel_inertia = "0.01 kg*m^2"\n'),
    "dc": (SLIDER, 'kind = "dc"\nstall_torque = "1.5 N*m"\nno_load_speed = "3000 rpm"\nstall_current = "12 A"\n'
                   'gear_ratio = 7\nefficiency = 0.85\nrotor_inertia = "30 g*cm^2"\n'),
    "dc-electric": (SLIDER, 'kind = "dc"\ntorque_constant = "0.05 N*m/A"\nresistance = "1.2 ohm"\n'
                            'voltage = "24 V"\n'),
    "induction": (SLIDER, 'kind = "induction"\nbreakdown_torque = "20 N*m"\nbreakdown_slip = 0.2\n'
                          'synchronous_speed = "1500 rpm"\ngear_ratio = 3.5\n'),
    "table": (SLIDER, 'kind = "table"\nspeed = ["0 rpm", "1000 rpm", "2000 rpm"]\ntorque = [3, 2.5, 0]\n'),
    "force": (ACTUATOR, 'kind = "force"\nforce = "500 N"\n'),
    "hydraulic": (ACTUATOR, 'kind = "hydraulic"\npressure = "100 bar"\narea = "20 cm^2"\nflow = "10 L/min"\n'),
    "force-table": (ACTUATOR, 'kind = "table"\nspeed = ["0 mm/s", "100 mm/s"]\nforce = [800, 0]\n'),
    "screw": (ACTUATOR, 'kind = "dc"\nstall_torque = "0.5 N*m"\nno_load_speed = "4000 rpm"\nlead = 5\n'),
}


@pytest.mark.parametrize("name", sorted(MOTORS))
def test_a_motor_round_trips_through_the_writer(name):
    base, table = MOTORS[name]
    m = assur.loads(base + "\n[motor]\n" + table)
    assert m.motor is not None and m.motor.driver == m.drivers[0].name
    again = assur.loads(assur.dumps(m))
    assert again.motor == m.motor
    assert assur.dumps(again) == assur.dumps(m)


def test_units_are_converted_to_si():
    m = assur.loads(MOTORS["dc"][0] + "\n[motor]\n" + MOTORS["dc"][1])
    mo = m.motor
    assert mo.no_load_speed == pytest.approx(3000 * 2 * math.pi / 60)
    assert mo.rotor_inertia == pytest.approx(30e-3 * 1e-4)
    m = assur.loads(MOTORS["hydraulic"][0] + "\n[motor]\n" + MOTORS["hydraulic"][1])
    assert (m.motor.pressure, m.motor.area, m.motor.flow) == pytest.approx((1e7, 2e-3, 1e-2 / 60))
    m = assur.loads(MOTORS["screw"][0] + "\n[motor]\n" + MOTORS["screw"][1])
    assert m.motor.lead == pytest.approx(5e-3)          # the file's length unit (mm)


@pytest.mark.parametrize("table, where, words", [
    ('kind = "dc"\nstall_torque = -1\nno_load_speed = 100', "motor.stall_torque", "positive"),
    ('kind = "dc"\nstall_torque = 1', "motor.no_load_speed", "needs no_load_speed"),
    ('kind = "dc"\nstall_torque = 1\nno_load_speed = 5\nvoltage = 12', "motor", "one of the two"),
    ('kind = "servo"', "motor.kind", "must be one of"),
    ('kind = "torque"\ntorque = 1\nbreakdown_slip = 0.1', "motor.breakdown_slip", "does not apply"),
    ('kind = "torque"\ntorque = 1\ncolour = "red"', "motor.colour", "unknown key"),
    ('kind = "torque"\ntorque = 1\ndriver = "wheel"', "motor.driver", "unknown driver"),
    ('kind = "torque"\ntorque = 1\nlead = 5', "motor.lead", "is a crank"),
    ('kind = "torque"\ntorque = 1\nefficiency = 1.5', "motor.efficiency", "(0, 1]"),
    ('kind = "torque"\ntorque = "1 kg"', "motor.torque", "unit"),
    ('kind = "force"\nforce = 10', "motor.kind", "pushes a linear driver"),
    ('kind = "induction"\nbreakdown_torque = 5\nbreakdown_slip = 1.5\nsynchronous_speed = "1500 rpm"',
     "motor.breakdown_slip", "(0, 1)"),
    ('kind = "table"\nspeed = [0, 10, 5]\ntorque = [1, 1, 0]', "motor.speed[2]", "increase"),
    ('kind = "table"\nspeed = [0, 10]\ntorque = [1]', "motor.torque", "one value per speed"),
])
def test_bad_motors_are_located(table, where, words):
    with pytest.raises(assur.SpecError) as err:
        assur.loads(SLIDER + "\n[motor]\n" + table)
    lines = [line for line in str(err.value).splitlines() if where + ":" in line]
    assert lines and words in lines[0]


def test_a_rotary_motor_on_a_linear_driver_needs_a_lead():
    with pytest.raises(assur.SpecError, match="motor.lead: a rotary motor on the linear driver"):
        assur.loads(ACTUATOR + '\n[motor]\nkind = "torque"\ntorque = 1\n')
    with pytest.raises(assur.SpecError, match="motor.gear_ratio"):
        assur.loads(ACTUATOR + '\n[motor]\nkind = "torque"\ntorque = 1\nlead = 5\ngear_ratio = 3\n')


def test_the_motor_option_reads_the_same_keys():
    m = assur.loads(SLIDER)
    mo = parse_motor_option('kind = "dc", stall_torque = "2 N*m", no_load_speed = "3000 rpm", gear_ratio = 4',
                            m.units, m.drivers)
    assert (mo.kind, mo.stall_torque, mo.gear_ratio) == ("dc", 2.0, 4.0)
    assert parse_motor_option('{kind = "torque", torque = 3}', m.units, m.drivers).torque == 3.0
    with pytest.raises(assur.SpecError, match="--motor.torque"):
        parse_motor_option('kind = "torque", torque = "3 apples"', m.units, m.drivers)
    with pytest.raises(assur.SpecError, match="--motor: must be KEY = VALUE"):
        parse_motor_option("dc 2 Nm", m.units, m.drivers)


def train(name):
    base, table = MOTORS[name]
    m = assur.loads(base + "\n[motor]\n" + table)
    return drive_train(m.motor, assur.compile(m))


def test_dc_characteristics_of_both_forms():
    t = train("dc-electric")
    k, R, V = 0.05, 1.2, 24.0
    w = np.array([0.0, 100.0, 480.0, 600.0])
    Q, tau, wm = t.generalised(w)
    assert np.allclose(tau, k * (V - k * w) / R)                      # i = (V − kω)/R, τ = k·i
    assert np.allclose(t.current(tau), (V - k * w) / R)
    assert t.input_free_speed() == pytest.approx(V / k)
    t = train("dc")
    N, eta, Ts, w0 = 7.0, 0.85, 1.5, 3000 * math.pi / 30
    Q, tau, wm = t.generalised(np.array([0.0, 10.0, 2 * w0 / N]))
    assert np.allclose(wm, N * np.array([0.0, 10.0, 2 * w0 / N]))
    assert np.allclose(tau, Ts * (1 - wm / w0))
    assert Q[0] == pytest.approx(N * eta * Ts) and Q[1] == pytest.approx(N * eta * tau[1])
    assert Q[2] == pytest.approx(N * tau[2] / eta)                     # driven backwards: τ/η reaches the motor
    assert t.inertia == pytest.approx(N * N * 30e-7)
    assert np.allclose(t.current(tau), tau * 12 / 1.5)


def test_induction_table_hydraulic_characteristics():
    t = train("induction")
    ws = 1500 * math.pi / 30
    wb = ws * (1 - 0.2)                                                # the breakdown slip
    tau = t.effort(np.array([wb, ws, 0.0]))
    assert tau[0] == pytest.approx(20.0) and tau[1] == 0.0
    assert tau[2] == pytest.approx(2 * 20 / (1 / 0.2 + 0.2))          # starting torque, slip 1
    t = train("table")
    w1 = 1000 * math.pi / 30
    tau = t.effort(np.array([0.0, 0.5 * w1, 3 * w1, -w1]))
    assert np.allclose(tau, [3.0, 2.75, -2.5, 3.5])                   # linear, continued beyond the rows
    t = train("hydraulic")
    vmax = (10e-3 / 60) / 20e-4
    F = t.effort(np.array([0.0, 0.5 * vmax, vmax, -vmax]))
    assert np.allclose(F, 1e7 * 20e-4 * np.array([1.0, 0.75, 0.0, 2.0]))
    t = train("screw")
    assert t.ratio == pytest.approx(2 * math.pi / 5e-3)                # rad of the motor per metre
