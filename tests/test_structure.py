"""Layer L1: structure from connectivity alone — mobility, Assur groups, structural formulas.

Reference values: the Chebyshev (Grübler) formula for planar mechanisms W = 3n − 2p5 (n moving
bodies, p5 lower pairs; a hinge joining k bodies counts k − 1 pairs; a pin in a slot adds a slider
block with one R and one P pair), and the Somov–Malyshev formula for spatial ones
W = 6n − 5p5 − 4p4 − 3p3 − 2p2 − p1 (Artobolevsky, *Theory of Mechanisms and Machines*, ch. 1–2).
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

import assur
from conftest import rssr
from assur import GroupKind
from assur.structure import mobility_chebyshev, mobility_somov_malyshev

HERE = os.path.dirname(__file__)
EXAMPLES = os.path.join(HERE, "..", "examples")


def mech(points, links, extra="", drivers=(("crank", "O", "A"),)):
    """A planar file (m, deg) from point coordinates, link point lists and crank drivers."""
    text = 'format = "assur/1"\n[units]\nlength = "m"\nangle = "deg"\n[points]\n'
    text += "".join(f"{n} = [{x!r}, {y!r}]\n" for n, (x, y) in points.items())
    text += "[links]\n" + "".join(f"{n} = {list(p)!r}\n".replace("'", '"') for n, p in links.items())
    text += extra
    for link, pivot, arm in drivers:
        text += f'[[drivers]]\nname = "{link}"\nlink = "{link}"\npivot = "{pivot}"\narm = "{arm}"\n'
    return assur.loads(text)


FOURBAR = mech(dict(O=(0, 0), O1=(1, 0), A=(0.3, 0.1), B=(0.9, 0.8)),
               dict(frame=("O", "O1"), crank=("O", "A"), coupler=("A", "B"), rocker=("O1", "B")))
FIVEBAR = mech(dict(O=(0, 0), O2=(1, 0), A=(0.2, 0.25), B=(1.1, 0.35), C=(0.6, 1.0)),
               dict(frame=("O", "O2"), crank=("O", "A"), crank2=("O2", "B"), left=("A", "C"), right=("B", "C")),
               drivers=(("crank", "O", "A"), ("crank2", "O2", "B")))
# Watt six-bar: the two ternary links (coupler A-B-C and rocker O1-B-D) are adjacent (joined at B)
WATT = mech(dict(O=(0, 0), O1=(1, 0), A=(0.2, 0.25), B=(0.9, 0.8), C=(0.5, 1.3), D=(1.4, 0.9), E=(1.1, 1.6)),
            dict(frame=("O", "O1"), crank=("O", "A"), coupler=("A", "B", "C"), rocker=("O1", "B", "D"),
                 link5=("C", "E"), link6=("D", "E")))
# Stephenson six-bar: the ternary links (frame O-O1-O2 and coupler A-B-C) are not adjacent
STEPHENSON = mech(dict(O=(0, 0), O1=(1, 0), O2=(1.6, 1.2), A=(0.2, 0.25), B=(0.9, 0.8), C=(0.7, 1.4),
                       D=(1.3, 1.9)),
                  dict(frame=("O", "O1", "O2"), crank=("O", "A"), coupler=("A", "B", "C"), rocker=("O1", "B"),
                       link5=("C", "D"), link6=("O2", "D")))
# Jansen-like leg: crank, two binary links from the crank pin A, the upper triangle P-B-D, the link P-C,
# the link D-E and the lower triangle C-E-F (foot F): 7 moving bodies and 10 pairs (A and P and C are
# hinges of three bodies, two pairs each)
JANSEN = mech(dict(O=(0, 0), P=(-38, -7.8), A=(5, 14), B=(-35, 35), C=(-30, -40), D=(-75, 10), E=(-70, -40),
                   F=(-45, -85)),
              dict(frame=("O", "P"), crank=("O", "A"), j=("A", "B"), k=("A", "C"), upper=("P", "B", "D"),
                   c=("P", "C"), f=("D", "E"), lower=("C", "E", "F")))
SLIDER = mech(dict(O=(0, 0), A=(0.3, 0.1), B=(1.2, 0.1)), dict(frame=("O",), crank=("O", "A"), rod=("A", "B")),
              extra='[[prismatic]]\nname = "slide"\npoint = "B"\nguide = "frame"\nthrough = "O"\nangle = 0\n')
TRIAD = mech(dict(O=(0, 0), P1=(3, 0), P2=(0.5, 2.5), A=(0.4, 0), B=(1.4, 0.4), C=(2.0, 0.9), D=(1.2, 1.3)),
             dict(frame=("O", "P1", "P2"), crank=("O", "A"), ab=("A", "B"), tern=("B", "C", "D"),
                  r1=("P1", "C"), r2=("P2", "D")))


@pytest.mark.parametrize("m, n, p5, W", [
    (FOURBAR, 3, 4, 1),            # 3·3 − 2·4 = 1
    (FIVEBAR, 4, 5, 2),            # 3·4 − 2·5 = 2
    (WATT, 5, 7, 1),               # 3·5 − 2·7 = 1
    (STEPHENSON, 5, 7, 1),         # 3·5 − 2·7 = 1
    (SLIDER, 3, 4, 1),             # crank, rod, slider block; R O, R A, R B, P: 3·3 − 2·4 = 1
    (JANSEN, 7, 10, 1),            # 3·7 − 2·10 = 1 (Jansen's linkage is a one-degree-of-freedom leg)
    (TRIAD, 5, 7, 1),              # 3·5 − 2·7 = 1
], ids=["four-bar", "five-bar", "watt", "stephenson", "slider-crank", "jansen-like", "triad-six-bar"])
def test_chebyshev_mobility_of_textbook_mechanisms(m, n, p5, W):
    s = assur.analyse_structure(m)
    assert (s.n_moving, s.pair_counts["p5"], s.mobility) == (n, p5, W)
    assert s.formula_name == "Chebyshev"
    assert W == 3 * n - 2 * p5 == mobility_chebyshev(n, p5)


def test_paper_000_crank_slider_walker():
    # paper 000: crank KC, rod C-B-A, slider block at B on a frame guide: n = 3, p5 = 4, W = 1
    s = assur.analyse_structure(assur.load(os.path.join(EXAMPLES, "walker_crank_slider.toml")))
    assert (s.n_moving, s.pair_counts["p5"], s.mobility) == (3, 4, 1)
    assert [g.kind for g in s.groups] == [GroupKind.RRP]


def test_paper_004_sixbar_with_a_compound_hinge():
    # paper 004 six-bar with beta1 = 0: B joins the crank and both couplers (a hinge of 3 bodies = 2 pairs)
    s = assur.analyse_structure(assur.load(os.path.join(EXAMPLES, "walker_sixbar.toml")))
    assert (s.n_moving, s.pair_counts["p5"], s.mobility) == (5, 7, 1)
    assert s.structural_formula == "I(frame, crank) → II(coupler_BM, rocker) → II(coupler_NA, lever)"


def test_mobility_formula_functions():
    # Chebyshev with a higher pair: a cam follower n = 2, p5 = 2, p4 = 1 → 6 − 4 − 1 = 1
    assert mobility_chebyshev(2, 2, 1) == 1
    # Somov–Malyshev for the RSSR chain: 6·3 − 5·2 − 3·2 = 2 (one idle spin of the coupler)
    assert mobility_somov_malyshev(3, p5=2, p3=2) == 2
    # spatial four-bar of four revolutes (Bennett-type count) 6·3 − 5·4 = −2
    assert mobility_somov_malyshev(3, p5=4) == -2


RSSR = rssr("m", 1.0, driver=True)


def test_somov_malyshev_for_a_spatial_rssr():
    m = assur.loads(RSSR)
    assert m.dimension == 3 and m.sketch("B") == (0.9, 0.7, 0.5)
    s = assur.analyse_structure(m)
    assert s.formula_name == "Somov–Malyshev"
    assert s.n_moving == 3 and s.pair_counts["p5"] == 2 and s.pair_counts["p3"] == 2
    assert s.mobility == 6 * 3 - 5 * 2 - 3 * 2 == 2
    # the planar engine refuses to solve it, with a message saying so
    with pytest.raises(assur.StructureError, match="spatial"):
        assur.compile(m)


def test_spatial_joints_need_dimension_three():
    text = RSSR.replace("dimension = 3\n", "").replace(", 0]", "]").replace(", 0.3]", "]").replace(", 0.5]", "]")
    with pytest.raises(assur.SpecError) as info:
        assur.loads(text)
    assert str(info.value) == "joints: spherical, cylindrical and universal joints need dimension = 3"


@pytest.mark.parametrize("m, named, numbered", [
    (FOURBAR, "I(frame, crank) → II(coupler, rocker)", "I(0,1) → II(2,3)"),
    (FIVEBAR, "I(frame, crank) → I(frame, crank2) → II(left, right)", "I(0,1) → I(0,2) → II(3,4)"),
    (WATT, "I(frame, crank) → II(coupler, rocker) → II(link5, link6)", "I(0,1) → II(2,3) → II(4,5)"),
    (STEPHENSON, "I(frame, crank) → II(coupler, rocker) → II(link5, link6)", "I(0,1) → II(2,3) → II(4,5)"),
    (TRIAD, "I(frame, crank) → III(ab, tern, r1, r2)", "I(0,1) → III(2,3,4,5)"),
    (JANSEN, "I(frame, crank) → II(j, upper) → II(k, c) → II(f, lower)", "I(0,1) → II(2,4) → II(3,5) → II(6,7)"),
], ids=["four-bar", "five-bar", "watt", "stephenson", "triad", "jansen-like"])
def test_structural_formula(m, named, numbered):
    # the papers' notation: class-I mechanisms (frame + driven link), then the groups in solving order,
    # by name and by body number (frame 0, links in file order)
    s = assur.analyse_structure(m)
    assert s.structural_formula == named
    assert s.structural_formula_numbered == numbered


def test_group_details_of_the_four_bar():
    s = assur.analyse_structure(FOURBAR)
    (g,) = s.groups
    assert (g.group_class, g.order, g.kind) == (2, 2, GroupKind.RRR)
    assert [s.body_label(b) for b in g.bodies] == ["coupler", "rocker"]
    assert [s.body_label(b) for b in g.attaches_to] == ["frame", "crank"]
    assert s.describe() == [{"class": 2, "order": 2, "kind": "RRR", "bodies": ["coupler", "rocker"],
                             "attaches_to": ["frame", "crank"]}]


def test_the_triad_is_a_class_three_group_of_order_three():
    (g,) = assur.analyse_structure(TRIAD).groups
    assert (g.group_class, g.order, g.kind, len(g.bodies)) == (3, 3, GroupKind.TRIAD, 4)


def _slot(name, point=None, link=None, guide="frame", through="O", angle=0):
    who = f'point = "{point}"' if point else f'link = "{link}"'
    return f'[[prismatic]]\nname = "{name}"\n{who}\nguide = "{guide}"\nthrough = "{through}"\nangle = {angle}\n'


# one mechanism per dyad kind (Artobolevsky's five kinds of class-II groups)
DYADS = {
    GroupKind.RRR: FOURBAR,
    GroupKind.RRP: SLIDER,
    GroupKind.RPR: mech(dict(O=(0, 0), O2=(0, -0.5), A=(0.2, 0.1), R=(0.8, 1.6)),
                        dict(frame=("O", "O2"), crank=("O", "A"), rocker=("O2", "R")),
                        extra=_slot("slot", point="A", guide="rocker", through="O2")),
    GroupKind.PRP: mech(dict(O=(0, 0), X=(1, 0), A=(0.3, 0.1), J=(1.0, 1 / 3)),
                        dict(frame=("O", "X"), crank=("O", "A")),
                        extra=_slot("s1", point="J", guide="crank") + _slot("s2", point="J", through="X", angle=90)),
    GroupKind.PPR: mech(dict(O=(0, 0), A=(0.3, 0.2), Y1=(0.3, 0), Y2=(0.3, 0.5)),
                        dict(frame=("O",), crank=("O", "A"), yoke=("Y1", "Y2")),
                        extra=_slot("slot", point="A", guide="yoke", through="Y1") + _slot("rail", link="yoke")),
}


@pytest.mark.parametrize("kind", list(DYADS), ids=[k.value for k in DYADS])
def test_every_dyad_kind_is_recognised(kind):
    s = assur.analyse_structure(DYADS[kind])
    assert [g.kind for g in s.groups] == [kind]
    assert s.groups[0].group_class == 2 and s.mobility == 1
    # Artobolevsky's numbering of the dyad kinds: RRR 1, RRP 2, RPR 3, PRP 4, PPR 5
    assert kind.dyad_kind_number == {"RRR": 1, "RRP": 2, "RPR": 3, "PRP": 4, "PPR": 5}[kind.value]
    assert assur.compile(DYADS[kind]).structure.groups[0].kind == kind


def test_structure_never_reads_lengths():
    # the same topology with very different coordinates has the same structure
    other = mech(dict(O=(5, -3), O1=(-2, 7), A=(4, 1), B=(-9, 0.5)),
                 dict(frame=("O", "O1"), crank=("O", "A"), coupler=("A", "B"), rocker=("O1", "B")))
    a, b = assur.analyse_structure(FOURBAR), assur.analyse_structure(other)
    assert a.structural_formula == b.structural_formula and a.describe() == b.describe()
    assert a.mobility == b.mobility


def test_jansen_like_leg_compiles_into_three_dyads():
    plan = assur.compile(JANSEN)
    assert [g.kind for g in plan.structure.groups] == [GroupKind.RRR] * 3
    assert [st.kind for st in plan.steps] == ["frame", "crank", "RRR", "RRR", "RRR"]


def test_missing_driver_leaves_bodies_undetermined():
    m = mech(dict(O=(0, 0), O1=(1, 0), A=(0.3, 0.1), B=(0.9, 0.8)),
             dict(frame=("O", "O1"), crank=("O", "A"), coupler=("A", "B"), rocker=("O1", "B")), drivers=())
    s = assur.analyse_structure(m)
    assert s.mobility == 1 and s.groups == () and set(s.undetermined) == {"crank", "coupler", "rocker"}


def test_idle_spin_of_a_binary_link_between_spherical_joints():
    """RSSR: W = 2 by Somov–Malyshev, of which one is the coupler's idle spin about its own axis
    (the S–S link), so the chain has one working freedom — the crank."""
    s = assur.analyse_structure(assur.loads(RSSR))
    assert (s.mobility, s.idle, s.mobility_without_idle) == (2, 1, 1)
    planar = assur.analyse_structure(assur.load(Path(__file__).resolve().parents[1] / "examples" / "crank_rocker.toml"))
    assert planar.idle == 0


@pytest.mark.parametrize("m, classes", [(FOURBAR, []), (JANSEN, []), (TRIAD, [3]),
                                        (assur.load(os.path.join(HERE, "data", "dyad_then_newton_eightbar.toml")),
                                         None)], ids=["fourbar", "jansen", "triad", "eightbar"])
def test_a_plans_newton_steps_are_its_groups_without_a_closed_form(m, classes):
    # the reference is the structure's own decomposition: every group of class III or more is solved by Newton
    plan = assur.compile(m)
    above_two = [g.group_class for g in plan.structure.groups if g.group_class > 2]
    if classes is not None:
        assert above_two == classes
    else:
        assert above_two                          # the eight-link file has one group beyond a dyad
    assert len(plan.newton_steps()) == len(above_two)
    assert all(st.kind == "newton" for st in plan.newton_steps())
    assert plan.has_newton_groups == bool(above_two)


def test_a_spatial_plan_has_no_newton_steps(rssr_plan):
    assert rssr_plan.newton_steps() == [] and rssr_plan.has_newton_groups is False
