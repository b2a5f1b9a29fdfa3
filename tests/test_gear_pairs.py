"""Gear pairs in a mechanism file ([[gears]]): structure, kinematics through the law, forces, bad input.

Independent references: the plain four-bar of examples/walker_fourbar.toml solved at the crank angle the law gives
(positions), central finite differences in the motor angle (analogues, velocities, accelerations), virtual power
(the motor torque), per-body equilibrium with the tooth force, and the spur-gear tooth force W = T/(r·cos α)
(Shigley's Mechanical Engineering Design, 10th ed., §13-14, eq. 13-36: W_t = T/r, W = W_t/cos φ).
"""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import SpecError, StructureError
from assur.io.mechanism_file import load, loads

from test_forces_checks import applied_loads, random_dynamics, virtual_power_effort, with_dynamics

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
LAW = "phi + 0.2*sin(phi)"


def law(x):
    """The test law θ(φ) = φ + 0.2·sin φ and its two derivatives (by hand)."""
    return x + 0.2 * np.sin(x), 1 + 0.2 * np.cos(x), -0.2 * np.sin(x)


def geared_text(law_line=f'law = "{LAW}"', extra_gear="", motor_sense="cw", motor_link="motor"):
    """examples/walker_fourbar.toml with a motor on a frame pivot M driving the crank through a gear pair."""
    s = (EXAMPLES / "walker_fourbar.toml").read_text(encoding="utf-8")
    s = s.replace('O1 = [0.567, 0.615]\n', 'O1 = [0.567, 0.615]\nM = [0.0, 0.3]\nM1 = [0.1, 0.3]\n')
    s = s.replace('frame = ["O", "O1"]', 'frame = ["O", "O1", "M"]\n\n[links.motor]\npoints = ["M", "M1"]\n'
                                         'mass = "0.4 kg"\ncom = "mid"')
    s = s.replace('name = "crank"\nkind = "rotary"\nlink = "crank"\npivot = "O"\narm = "K"\nzero = 0\nsense = "ccw"',
                  f'name = "motor"\nkind = "rotary"\nlink = "{motor_link}"\npivot = "M"\narm = "M1"\nzero = 0\n'
                  f'sense = "{motor_sense}"')
    assert 'name = "motor"' in s
    return s.replace('[branches]', f'[[gears]]\nname = "drive"\na = "motor"\nb = "crank"\n{law_line}\n{extra_gear}\n'
                                   f'[branches]')


@pytest.fixture(scope="module")
def geared():
    return assur.compile(loads(geared_text(), source=str(EXAMPLES / "geared_test.toml")))


@pytest.fixture(scope="module")
def plain():
    return assur.compile(load(EXAMPLES / "walker_fourbar.toml"))


def crank_of_motor(plan, psi):
    """The crank angle of the plain four-bar for motor inputs ψ: the motor turns cw (x = −(ψ − ψ_s)), the external
    pair turns the crank the other way (θ_crank − θ_s = −L(x)); the plain file's crank input is its angle (ccw, 0)."""
    x = -(np.asarray(psi) - plan.sketch_inputs[0])
    return -law(x)[0]


def test_structure_counts_the_higher_pair(geared):
    s = geared.structure
    assert dict(s.pair_counts) == {"p5": 5, "p4": 1}
    assert s.mobility == 3 * 4 - 2 * 5 - 1 == 1          # Chebyshev with the p4 pair
    assert s.structural_formula == "I(frame, motor) → II(crank, drive′) → II(rocker, coupler)"
    assert s.describe()[0]["substitute_link"] == "drive′"


def test_positions_follow_the_law(geared, plain):
    psi = np.linspace(0, 2 * np.pi, 37)
    s = assur.solve(geared, inputs=psi)
    s0 = assur.solve(plain, inputs=crank_of_motor(geared, psi))
    for p in ("K", "L", "H"):
        np.testing.assert_allclose(s.pos[:, geared.point_index(p)], s0.pos[:, plain.point_index(p)], atol=1e-12)


def test_analogues_and_time_derivatives_against_finite_differences(geared):
    psi = np.linspace(0.1, 6.2, 23)
    h = 1e-4
    s = assur.solve(geared, inputs=psi, speeds=[1.7], accels=[0.9])
    sp, sm = assur.solve(geared, inputs=psi + h), assur.solve(geared, inputs=psi - h)
    d1 = (sp.pos - sm.pos) / (2 * h)
    d2 = (sp.pos - 2 * assur.solve(geared, inputs=psi).pos + sm.pos) / h ** 2
    np.testing.assert_allclose(s.dpos_dq[..., 0], d1, atol=1e-7)
    np.testing.assert_allclose(s.d2pos_dq2[..., 0, 0], d2, atol=2e-5)
    np.testing.assert_allclose(s.vel, 1.7 * d1, atol=2e-7)
    np.testing.assert_allclose(s.acc, 1.7 ** 2 * d2 + 0.9 * d1, atol=1e-4)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_motor_torque_by_virtual_power_and_equilibrium_with_the_tooth_force(geared, seed):
    dyn = random_dynamics(geared, np.random.default_rng(seed))      # random masses and inertias on every link
    geared = assur.compile(with_dynamics(geared.mechanism, dyn))
    psi = np.linspace(0, 2 * np.pi, 25)[:-1]
    f = assur.forces(geared, inputs=psi, accels=[3.0])
    ref, scale = virtual_power_effort(geared, f.state, dyn)
    assert np.all(np.abs(f.driver[:, 0] - ref[:, 0]) <= 1e-9 * scale[:, 0])
    # each gear's equilibrium with the tooth force at the pitch point (±F on crank and motor), its pivot reaction,
    # the joint K (the crank's force on the coupler), the motor torque and every applied and d'Alembert load
    g = f.gears["drive"]
    assert np.all(g["tooth_force"] > 0)
    z = f.state.pos[..., 0] + 1j * f.state.pos[..., 1]
    tooth, P = g["tooth_force"] * g["line_of_action"], g["pitch_point"]
    R = {name: f.reaction(name)[..., 0] + 1j * f.reaction(name)[..., 1] for name in ("O", "M", "K")}
    at = {name: z[:, geared.point_index(name)] for name in ("O", "M", "K")}
    cross = lambda u, v: np.imag(np.conj(u) * v)
    torque = f.driver[:, 0] * geared.mechanism.drivers[0].sense
    for body, force, moment in (
            ("crank", R["O"] - R["K"] + tooth, cross(at["O"], R["O"]) - cross(at["K"], R["K"]) + cross(P, tooth)),
            ("motor", R["M"] - tooth, cross(at["M"], R["M"]) - cross(P, tooth) + torque)):
        b = geared.body_names.index(body)
        for bb, fl, where, couple, *_ in applied_loads(geared, f.state, dyn):
            if bb == b:
                force, moment = force + fl, moment + cross(where, fl) + couple
        scale = np.max(np.abs(R["O"])) + np.max(g["tooth_force"])
        assert np.max(np.abs(force)) <= 1e-9 * scale, body
        assert np.max(np.abs(moment)) <= 1e-9 * scale * geared.length_scale, body


def test_circular_pair_tooth_force_is_the_textbook_one():
    """A 2:1 external pair of spur gears: W = T_b/(r_b·cos α), r_b = d·2/3 the driven pitch radius."""
    plan = assur.compile(loads(geared_text('law = 2'), source=str(EXAMPLES / "x.toml")))
    psi = np.linspace(0, 4 * np.pi, 19)
    f = assur.forces(plan, inputs=psi)
    g = f.gears["drive"]
    d = math.dist((0.0, 0.0), (0.0, 0.3))
    r_b = d * 2 / 3
    np.testing.assert_allclose(g["tooth_force"], np.abs(g["torque"]) / (r_b * math.cos(math.radians(20))),
                               rtol=1e-12)
    # and the crank turns half a turn per motor turn
    s = assur.solve(plan, inputs=np.array([0.0, 2 * np.pi]))
    e = s.pos[:, plan.point_index("K")]
    np.testing.assert_allclose(e[1], -e[0], atol=1e-12)


@pytest.mark.parametrize("law_line, extra, field, words", [
    ('law = "phi - 0.9*sin(2*phi)"', "", "gears[0].law", "must increase"),
    ('law = "1.1*phi"', "", "gears[0].law", "does not close"),
    ('law = "phi + 1"', "", "gears[0].law", "must be 0 at phi = 0"),
    ('law = -2', "", "gears[0].law", "ratio must be a finite number > 0"),
    ('law = "phi +"', "", "gears[0].law", ""),
    ('law = "gears_001.toml"', "", "gears[0].law", "corners"),
    ('law = "missing.toml"', "", "gears[0].law", "cannot be used"),
    (f'law = "{LAW}"', 'mesh = "sideways"', "gears[0].mesh", "external"),
    (f'law = "{LAW}"', 'teeth = 3', "gears[0]", "teeth"),
])
def test_bad_gear_entries_are_named(law_line, extra, field, words):
    with pytest.raises(SpecError) as e:
        loads(geared_text(law_line, extra), source=str(EXAMPLES / "x.toml"))
    text = str(e.value)
    assert field in text and words in text, text


def test_a_gear_whose_driving_link_is_not_turned_by_the_drive_is_refused():
    text = geared_text()
    # drive the crank directly and let the gear drive the motor link back: the motor link is driven twice
    text = text.replace('a = "motor"\nb = "crank"', 'a = "rocker"\nb = "motor"')
    with pytest.raises((SpecError, StructureError)) as e:
        assur.compile(loads(text, source="x.toml"))
    assert "rocker" in str(e.value)


@pytest.mark.parametrize("law_line", [f'law = "{LAW}"', "law = 2",
                                      "law = { phi = [0, 45, 90, 135, 180, 225, 270, 315], "
                                      "theta = [0, 50, 95, 138, 180, 222, 265, 310] }"])
def test_a_written_file_reads_back_the_same_gear(law_line, tmp_path):
    from assur.io.mechanism_writer import dump
    m = loads(geared_text(law_line), source=str(EXAMPLES / "x.toml"))
    path = tmp_path / "again.toml"
    dump(m, path)
    again = load(path)
    assert again.gears[0].name == "drive" and again.gears[0].mesh == "external"
    x = np.linspace(-7, 7, 101)
    np.testing.assert_allclose(again.gears[0].relative(x), m.gears[0].relative(x), atol=1e-9)


def test_drawn_pitch_curves_are_the_gear_modules_pitch_curves():
    """The pitch curves drawn with a geared linkage (model.gearing.pitch_points) against assur.gears.pitch_pair,
    an independent construction (r_driving = L·k/(1 + k) from the law's rate k), and the rolling condition: both
    curves have the same perimeter for a 1:1 pair."""
    from assur.gears.law import law_from_callable
    from assur.gears.pitch import pitch_pair
    from assur.model.gearing import pitch_points
    m = loads(geared_text(), source=str(EXAMPLES / "x.toml"))
    ca, cb = pitch_points(m.gears[0], 0.3j, 0j, samples=720)
    pair = pitch_pair(law_from_callable(lambda x: law(x)[0]), 0.3, samples=720)
    phi = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    r1, r2 = pair.contact_radii(phi)
    np.testing.assert_allclose(np.abs(ca), r1, rtol=1e-9)
    np.testing.assert_allclose(np.sort(np.abs(cb)), np.sort(r2), rtol=1e-9)
    perimeter = lambda c: np.sum(np.abs(np.diff(np.append(c, c[0]))))
    assert abs(perimeter(ca) - perimeter(cb)) < 1e-5 * perimeter(ca)
