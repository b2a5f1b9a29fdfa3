"""Where a force at a point acts (docs/format.md, "Loads"): the one body at the point; where a slider meets other
bodies (a ram's wrist pin), the slider; a point where several links meet without a slider needs ``link``.

The reference of the ram test is written in the test: with a massless rod (a two-force member along A→B) and a
frictionless horizontal slide, the ram's balance along the slide gives the rod's force
r = (m·a_B − F − m·g)·u / (e·u), e the rod's unit vector, u the slide's; the driving torque is the virtual power
torque T = −(F + m·g − m·a_B)·∂r_B/∂φ (a massless crank and rod). Once the load at the pin went on the rod (the
earliest-solved body there) and |R_B| left it out.
"""
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import SpecError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RAM_MASS, LOAD = 2.0, (-300.0, 40.0)           # kg; N, on the ram at its pin B


def _slider_crank(load: str, ram_mass: float = RAM_MASS) -> str:
    text = (EXAMPLES / "slider_crank.toml").read_text(encoding="utf-8")
    text = text.replace("offset = 20\n", f'offset = 20\nmass = "{ram_mass} kg"\n', 1)
    return text + f"\n[dynamics]\ngravity = [0, -9.81]\n\n[[loads]]\n{load}\n"


def test_a_load_at_the_ram_pin_acts_on_the_ram():
    plan = assur.compile(assur.loads(_slider_crank(f'point = "B"\nforce = [{LOAD[0]}, {LOAD[1]}]')))
    q = np.linspace(0.0, 2 * math.pi, 37)[:-1]
    f = assur.forces(plan, inputs=q)
    assert f.valid.all()
    st = f.state
    A, B = (st.pos[:, plan.point_index(n)] for n in "AB")
    aB = st.acc[:, plan.point_index("B")]
    F, g = np.array(LOAD), np.array([0.0, -9.81])
    u = np.array([1.0, 0.0])                                   # the slot's direction (angle 0)
    e = (B - A) / np.linalg.norm(B - A, axis=1)[:, None]
    rod_force = (RAM_MASS * aB @ u - F @ u - RAM_MASS * g @ u) / (e @ u)
    R_B = np.linalg.norm(f.reaction("B", later="slot.block"), axis=-1)
    np.testing.assert_allclose(R_B, np.abs(rod_force), rtol=1e-9, atol=1e-9 * np.abs(rod_force).max())
    # the case: with the load on the rod |R_B| would miss F; it differs from the reference by far here
    assert np.max(np.abs(rod_force)) > 250.0
    drB = st.dpos_dq[:, plan.point_index("B"), :, 0]
    torque = -np.sum((F + RAM_MASS * g - RAM_MASS * aB) * drB, axis=1)
    np.testing.assert_allclose(f.driver[:, 0], torque, rtol=1e-9, atol=1e-9 * np.abs(torque).max())


def test_a_link_given_puts_the_load_on_that_link():
    """The same load given on the rod: the torque is unchanged, the pin's reaction differs by the load."""
    q = np.linspace(0.0, 2 * math.pi, 13)[:-1]
    on_ram = assur.forces(assur.compile(assur.loads(_slider_crank(
        f'point = "B"\nforce = [{LOAD[0]}, {LOAD[1]}]'))), inputs=q)
    on_rod = assur.forces(assur.compile(assur.loads(_slider_crank(
        f'point = "B"\nlink = "rod"\nforce = [{LOAD[0]}, {LOAD[1]}]'))), inputs=q)
    np.testing.assert_allclose(on_rod.driver, on_ram.driver, rtol=1e-12, atol=1e-9)
    # the rod's force on the ram: with the load on the rod it carries the load to the ram as well
    diff = on_rod.reaction("B", later="slot.block") - on_ram.reaction("B", later="slot.block")
    np.testing.assert_allclose(diff, np.broadcast_to(LOAD, diff.shape), rtol=1e-9, atol=1e-9)


def test_a_pin_of_two_links_without_a_slider_needs_the_link():
    text = _slider_crank('point = "A"\nforce = [0, -50]')
    with pytest.raises(SpecError) as info:
        assur.loads(text)
    msg = dict(info.value.problems)["loads[0].link"]
    assert "'crank'" in msg and "'rod'" in msg and "link" in msg
    assur.loads(_slider_crank('point = "A"\nlink = "crank"\nforce = [0, -50]'))      # named: accepted


def test_the_rule_holds_for_loads_built_in_python():
    """A Dynamics made in code (not read from a file) meets the same rule when the forces are solved."""
    import dataclasses

    from assur.model.dynamics import Load
    m = assur.loads(_slider_crank(f'point = "B"\nforce = [{LOAD[0]}, {LOAD[1]}]'))
    bad = dataclasses.replace(m, dynamics=dataclasses.replace(m.dynamics, loads=(Load(point="A", force=(0.0, 1.0)),)))
    with pytest.raises(SpecError, match=r"loads\[0\]\.link: the point 'A' joins"):
        assur.forces(assur.compile(bad), inputs=[0.3])
    with pytest.raises(SpecError, match=r"point_loads\[0\]: the point 'A' joins"):
        assur.forces(assur.compile(m), inputs=[0.3], point_loads=[("A", (0.0, 1.0))])
    f = assur.forces(assur.compile(m), inputs=[0.3], point_loads=[("A", (0.0, 1.0), "rod")])
    assert f.valid.all()


def test_a_spatial_joint_of_two_links_needs_the_link():
    from conftest import rssr
    text = rssr() + '\n[[loads]]\npoint = "B"\nforce = [0, 0, -10]\n'
    with pytest.raises(SpecError) as info:
        assur.loads(text)
    assert "'coupler'" in dict(info.value.problems)["loads[0].link"]


def test_the_shipped_lever_manipulator_keeps_its_load_on_the_carriage():
    """examples/lever_manipulator.toml: the process resistance at B, where the carriage (a slider block) meets the
    two actuators' rods, acts on the carriage."""
    m = assur.load(EXAMPLES / "lever_manipulator.toml")
    assert m.load_body("B") == "guide.block"
    assert m.bodies_at("B") == (("guide.block", "drive_rod.rod", "driven_rod.rod"), ("guide.block",))
