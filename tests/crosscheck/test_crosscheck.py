"""The cross-tool corpus (corpus.py): assur against pylinkage run live, PMKS+'s MATLAB verification set and
four-bar-rs's position formula. Every row agrees to 1e-9 of the mechanism's size, or its disagreement is explained
and the explanation is checked here by an independent computation."""
import functools
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import corpus  # noqa: E402

import assur  # noqa: E402
from assur.interop import import_mechanism  # noqa: E402

pytest.importorskip("pylinkage")


@functools.lru_cache(maxsize=None)
def rows(peer: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return tuple(corpus.all_rows()[peer] if peer == "all" else
                     {"pylinkage": corpus.pylinkage_rows, "PMKS+": corpus.pmks_rows,
                      "four-bar-rs": corpus.fourbar_rows}[peer]())


@pytest.mark.parametrize("peer", ["pylinkage", "PMKS+", "four-bar-rs"])
def test_every_row_agrees_or_is_explained(peer):
    found = rows(peer)
    assert len(found) >= 10
    unexplained = [f"{r.mechanism}: {r.quantity}: {r.diff:.3g}" for r in found if not r.agrees and not r.note]
    assert not unexplained, "\n".join(unexplained)


def test_pylinkage_live_agrees_to_1e_9_of_the_size_over_a_turn():
    """Every pylinkage mechanism that both tools solve, save the one where pylinkage's own error is shown below."""
    whole = [r for r in rows("pylinkage") if r.quantity.startswith("all ")]
    assert len(whole) >= 13
    assert {r.mechanism for r in whole if not r.agrees} == {"watt2.toml"}


def test_pylinkage_error_on_the_collinear_rocker_of_watt2():
    """watt2's rocker O4–B–C has its joints on one line: pylinkage places C by two touching circles and breaks the
    rocker's rigidity by about the disagreement; assur keeps it."""
    from pylinkage.mechanism import mechanism_from_json

    from assur.interop.pylinkage_write import to_dict
    m = assur.load(corpus.ROOT / "examples" / "watt2.toml")
    O4, B, C = (np.array(m.sketch(n)) * 1e3 for n in ("O4", "B", "C"))
    assert abs(np.cross(B - O4, C - O4)) / np.linalg.norm(B - O4) < 1e-5       # collinear, to the drawing's digits
    import json
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "w.json"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            path.write_text(json.dumps(to_dict(m)))
        th, peer = corpus._simulate_mechanism(mechanism_from_json(path))
    size = m.length_scale * 1e3

    def off_line(pos):   # C's distance from the line O4 → B: 0 on the rigid rocker as drawn
        u, v = pos["B"] - pos["O4"], pos["C"] - pos["O4"]
        return np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / np.linalg.norm(u, axis=-1)
    _, ours = corpus._assur_at(m, th)
    drawn = abs(np.cross(B - O4, C - O4)) / np.linalg.norm(B - O4)
    assert np.max(np.abs(off_line(ours) - drawn)) < 1e-12 * size          # assur keeps the rocker's shape
    bent = np.max(np.abs(off_line(peer) - drawn)) / size                   # pylinkage bends it
    worst = next(r.diff for r in rows("pylinkage") if r.mechanism == "watt2.toml" and r.quantity.startswith("all "))
    assert 1e-10 < bent and worst < 10 * bent
    k = int(np.argmax(np.abs(off_line(peer) - drawn)))
    assert np.linalg.norm(ours["C"][k] - peer["C"][k]) / size == pytest.approx(bent, rel=0.5)


def test_pylinkage_refuses_the_three_joint_triad():
    from pylinkage.mechanism import mechanism_from_json

    from assur.interop.pylinkage_write import to_dict
    import json
    import tempfile
    m = assur.load(corpus.ROOT / "examples" / "triad_sixbar.toml")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "t.json"
        path.write_text(json.dumps(to_dict(m)))
        with pytest.raises(ValueError, match="Triad must have exactly 2 internal nodes"):
            corpus._simulate_mechanism(mechanism_from_json(path))
    plan = assur.compile(m)
    assert assur.solve(plan, inputs=np.linspace(0, 2 * np.pi, 36), order=0).valid.all()


def test_the_pylinkage_four_bar_example_starts_at_a_change_point():
    """fourbar_linkage.py: crank 1, coupler 3, rocker 1, ground 3 (s + l = p + q: a change-point linkage) drawn folded
    flat; assur refuses to guess the assembly, and a [branches] hint then picks it."""
    name, _, obj = corpus.pylinkage_examples()[0]
    C = next(c for c in obj.components if c.name == "C")
    assert (C.x, C.y) == pytest.approx((4.0, 0.0)) and 1 + 3 == 3 + 1
    with pytest.raises(assur.SpecError, match="does not tell the assembly branch"):
        import_mechanism(obj)


def test_pmks_share_links_differ_by_their_rounding_only():
    """A share link's coordinates are the verification set's rounded to 0.001: rounding case.json the same way gives
    the imported link's mechanism exactly (so the whole difference is the rounding)."""
    links = corpus.pmks_fixture_urls()
    spec, _ = corpus.pmks_case("teaching_four_bar")
    for group in ("joints", "points"):
        for j in spec["topology"][group]:
            j["initial"] = [round(v, 3) for v in j["initial"]]
    rounded = corpus.pmks_exact(spec)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        link = import_mechanism(links[("TeachingLab four-bar", "current")])
    th = np.linspace(0, 2 * np.pi, 37)
    pr, pl = assur.compile(rounded), assur.compile(link)
    a = assur.solve(pr, inputs=th, order=0)
    b = assur.solve(pl, inputs=(th - link.drivers[0].zero) / link.drivers[0].sense, order=0)
    for n in rounded.point_names:
        # the link is drawn in cm, the set's numbers are read in m: the same numbers
        assert np.max(np.abs(np.asarray(a.pos)[:, pr.point_index(n)]
                             - np.asarray(b.pos)[:, pl.point_index(n)] * 100)) < 1e-12 * 5


def test_pmks_matlab_kinematics_agree_for_the_exact_mechanisms():
    exact = [r for r in rows("PMKS+") if "case.json" in r.source]
    assert len(exact) == 4 * len(corpus.PMKS_CASES)
    assert all(r.agrees for r in exact), [(r.mechanism, r.quantity, r.diff) for r in exact if not r.agrees]


def test_four_bar_rs_disagreements_are_folds():
    """Every four-bar-rs row that differs is at inputs where the loop folds: there the position is a double root
    and both computations lose half their digits (√ε ≈ 1.5e-8)."""
    for r in rows("four-bar-rs"):
        if not r.agrees:
            assert "within 1e-3 of a fold" in r.quantity and r.diff < 1e3 * math.sqrt(np.finfo(float).eps)


def test_strider_at_its_own_ten_steps_moves_the_right_foot_to_the_other_assembly():
    """strider.py's own 36° steps: pylinkage takes, at each step, the intersection nearest the previous position;
    at the 7th step that is the other intersection of the right foot's dyad (about E and G), and the foot stays
    there. assur (and pylinkage at 1° steps, the rows of the table) keep one assembly over the whole turn."""
    from assur.interop import draft_of
    lk = corpus.strider()
    d = draft_of(lk)
    pname, _ = d.names()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = d.build()
    steps = np.array(list(lk.step(iterations=10)), dtype=float)             # its own dt = 1: 36° a step
    names = [c.name for c in lk.components]
    crank = next(c for c in lk.components if type(c).__name__ == "Crank")
    th = math.atan2(-1.0, 0.0) + crank.angular_velocity * np.arange(1, 11)
    _, ours = corpus._assur_at(m, th)
    moved = [np.linalg.norm(steps[k, names.index("Right foot (I)")] - ours[pname["Right foot (I)"]][k]) for k in range(10)]
    assert max(moved[:6]) < 1e-12 and min(moved[6:]) > 3
    k = 6
    E, G, I_peer = (steps[k, names.index(n)] for n in ("Right knee link (E)", "Right ankle link (G)", "Right foot (I)"))
    I_ours = ours[pname["Right foot (I)"]][k]
    for point in (I_peer, I_ours):                                             # the same dyad, both intersections
        assert np.linalg.norm(point - E) == pytest.approx(2.5) and np.linalg.norm(point - G) == pytest.approx(1.8)
    assert np.sign(np.cross(G - E, I_peer - E)) == -np.sign(np.cross(G - E, I_ours - E))
    before = steps[k - 1, names.index("Right foot (I)")]                       # the other one was nearer the last step
    assert np.linalg.norm(I_peer - before) < np.linalg.norm(I_ours - before)


def test_pylinkage_own_conversion_keeps_unassembled_positions_as_dimensions():
    from pylinkage.hypergraph.mechanism_conversion import to_mechanism
    lk = corpus.strider()
    graph, dims = lk.to_hypergraph()
    mech = to_mechanism(graph, dims)
    knee = next(link for link in mech.links if set(j.id for j in link.joints) == {"Frame left (B_p)",
                                                                                 "Left knee link (D)"})
    assert abs(knee.length - 1.8) > 0.1          # the femur is 1.8 in strider.py; the drawn guess is what is kept
