"""The ``slide`` hint of ``[branches]``: the branch of an RPR group (docs/format.md, Branches), the one hint of an
RPR group whose bodies carry no point but their hinges (paper 002's passive cylinder, O → B in
examples/lever_manipulator.toml), where both branches put every point at the same place.

Reference: the geometry of the solved poses, computed in the tests: the slider's hinge minus the guide's hinge,
projected on the slide's direction in the world (the guide body's angle plus the slide's angle on it) is positive
"ahead", negative "behind".
"""
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import SpecError

ROOT = Path(__file__).resolve().parents[1]
LEVER = (ROOT / "examples" / "lever_manipulator.toml").read_text()

#: a crank-driven slotted lever (Whitworth): the crank pin C slides in the slot of the rocker O2–T
WHITWORTH = (Path(__file__).parent / "data" / "whitworth_slotted_lever.toml").read_text(encoding="utf-8")


def along(state, plan, slider_point, guide_point, guide_body, slide_angle):
    """(n,) the slider's hinge minus the guide's hinge along the slide's world direction."""
    i, j = plan.point_index(slider_point), plan.point_index(guide_point)
    d = state.pos[:, i] - state.pos[:, j]
    theta = state.body_angle[:, plan.body_names.index(guide_body)] + slide_angle
    return d[:, 0] * np.cos(theta) + d[:, 1] * np.sin(theta)


@pytest.mark.parametrize("slide, sign", [("ahead", 1), ("behind", -1)])
def test_a_passive_cylinders_branch_is_its_hint(slide, sign):
    plain = assur.compile(assur.loads(LEVER))
    hinted = assur.compile(assur.loads(LEVER + f'\n[branches]\nB = {{ slide = "{slide}", on = "driven_rod" }}\n'))
    (rpr,) = [s for s in hinted.steps if s.kind == "RPR"]
    assert rpr.branch == sign
    a, b = assur.solve(plain), assur.solve(hinted)
    # every point where it was: only the cylinder and its rod turn
    np.testing.assert_array_equal(a.valid, b.valid)
    np.testing.assert_allclose(b.pos, a.pos, rtol=0, atol=1e-12)
    s = along(b, hinted, "B", "O", "driven_rod.cylinder", 0.0)
    assert np.all(np.sign(s[b.valid]) == sign)
    turn = b.body_angle[:, hinted.body_names.index("driven_rod.cylinder")] - \
        a.body_angle[:, plain.body_names.index("driven_rod.cylinder")]
    np.testing.assert_allclose(np.cos(turn[a.valid]), 1.0 if sign == 1 else -1.0, atol=1e-12)


def test_the_hint_overrides_the_sketch_of_a_slotted_lever_and_writes_back():
    drawn = assur.compile(assur.loads(WHITWORTH))
    hinted_mech = assur.loads(WHITWORTH + '\n[branches]\nC = { slide = "behind", on = "slot" }\n')
    hinted = assur.compile(hinted_mech)
    sa, sb = assur.solve(drawn), assur.solve(hinted)
    assert np.all(along(sa, drawn, "C", "O2", "rocker", 0.0) > 0)        # the sketch: C ahead of O2 towards T
    assert np.all(along(sb, hinted, "C", "O2", "rocker", 0.0) < 0)
    assert np.max(np.abs(sb.pos[:, hinted.point_index("T")] - sa.pos[:, drawn.point_index("T")])) > 0.1
    again = assur.loads(assur.dump(hinted_mech))
    assert again.branches == hinted_mech.branches


@pytest.mark.parametrize("hint, path, says", [
    ('B = { slide = "behind", on = "guide" }', "branches.B.on", "no RPR group slides on 'guide'"),
    ('B = { slide = "back", on = "driven_rod" }', "branches.B.slide", "must be 'ahead' or 'behind'"),
    ('B = { slide = "behind", on = "rod" }', "branches.B.on", "must name the prismatic pair or actuator"),
    ('B = { slide = "behind" }', "branches.B.on", "must name the prismatic pair or actuator"),
    ('B = { tilt = 1 }', "branches.B", "or {slide = 'ahead'|'behind', on = SLIDE}"),
])
def test_a_bad_slide_hint_is_located(hint, path, says):
    with pytest.raises(SpecError) as info:
        assur.compile(assur.loads(LEVER + f"\n[branches]\n{hint}\n"))
    where, message = info.value.problems[0]
    assert where == path and says in message


def test_a_side_and_a_slide_hint_at_one_point():
    """B is the RRP's joint and the passive cylinder's slider hinge: one table holds both hints."""
    m = assur.loads(LEVER + '\n[branches]\nB = { side = "left", of = ["O", "A"], slide = "behind", on = "driven_rod" }\n')
    plan = assur.compile(m)
    assert {s.kind: s.branch for s in plan.steps if s.key_point == "B"} == {"RRP": 1, "RPR": -1}
    b = assur.loads(assur.dump(m))
    assert b.branches[0].side == "left" and b.branches[0].slide == "behind"


def test_the_builder_writes_a_slide_hint():
    built = (assur.Builder(units="mm").point("O", 0, 0).point("O2", 0, -60).point("C", 30, 0).point("T", 0, 80)
             .frame("O", "O2").link("crank", "O", "C").link("rocker", "O2", "T")
             .slider(name="slot", point="C", guide="rocker", through="O2", angle=0, offset=5)
             .crank("crank", name="crank", pivot="O", arm="C")
             .branch("C", slide="behind", on="slot"))
    assert built.to_dict()["branches"] == {"C": {"slide": "behind", "on": "slot"}}
    assert built.build().branches == assur.loads(WHITWORTH + '[branches]\nC = { slide = "behind", on = "slot" }\n'
                                                 ).branches
