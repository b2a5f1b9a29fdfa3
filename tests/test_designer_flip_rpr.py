"""Flip of an RPR dyad in the designer, without a browser: a slotted lever's flip moves the lever's far point, a
passive cylinder's flip (paper 002's lever manipulator: every point stays, the cylinder and its rod turn half a
turn) is recorded as the file's ``slide`` hint, a flip back leaves the file as it was, Save writes the hint only.

References: the engine on the saved or hinted files (``assur.compile``, ``assur.solve``) and the geometry of the
solved poses written in the tests (the slider's hinge along the slide's direction).
"""
import shutil
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer.document import delete_slider
from assur.designer.saving import canonical
from assur.designer.session import Session, doc_of_toml

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"

WHITWORTH = (Path(__file__).parent / "data" / "whitworth_slotted_lever.toml").read_text(encoding="utf-8")


def reply(s, **request):
    (r,) = s.handle({"seq": 1, **request})
    return r.message


def group(message, kind):
    (g,) = [g for g in message["model"]["groups"] if g["kind"] == kind]
    return g


def cylinder_along(plan, state):
    """(n,) B − O along the passive cylinder's axis (its body angle): > 0 when B is ahead of O."""
    d = state.pos[:, plan.point_index("B")] - state.pos[:, plan.point_index("O")]
    th = state.body_angle[:, plan.body_names.index("driven_rod.cylinder")]
    return d[:, 0] * np.cos(th) + d[:, 1] * np.sin(th)


def test_a_passive_cylinders_flip_is_a_slide_hint_and_its_flip_back_the_file_again(tmp_path):
    path = Path(shutil.copy(EX / "lever_manipulator.toml", tmp_path))
    s = Session.of_file(str(path))
    before = reply(s, op="hello")
    rpr = group(before, "RPR")
    assert rpr["slide"] == "driven_rod" and rpr["branch"] == 1
    after = reply(s, op="commit", edits=[{"kind": "flip", "group": rpr["index"]}])
    assert after["type"] == "result" and after["history"]["undo"] == 1
    assert group(after, "RPR")["branch"] == -1 and group(after, "RRP")["branch"] == group(before, "RRP")["branch"]
    assert after["doc"]["points"] == before["doc"]["points"]            # no point moves
    assert after["doc"]["branches"] == {"B": {"slide": "behind", "on": "driven_rod"}}
    # the document is the file: its plan has the cylinder behind, every point where it was
    plan = assur.compile(assur.loads(after["toml"]))
    plain = assur.compile(assur.load(path))
    a, b = assur.solve(plain), assur.solve(plan)
    np.testing.assert_allclose(b.pos, a.pos, rtol=0, atol=1e-12)
    assert np.all(cylinder_along(plain, a)[a.valid] > 0) and np.all(cylinder_along(plan, b)[b.valid] < 0)
    # Save writes the hint only: every line of the file stays, one table more
    assert reply(s, op="save")["written"] is True
    text = path.read_text()
    original = (EX / "lever_manipulator.toml").read_text()
    assert text.startswith(original.rstrip("\n")) and "[branches]" not in original
    assert assur.load(path).branches[0].slide == "behind"
    # a drag moves the sketch without touching the hint; a flip back removes it
    again = reply(s, op="commit", edits=[{"kind": "flip", "group": rpr["index"]}])
    assert group(again, "RPR")["branch"] == 1 and "branches" not in again["doc"]
    assert canonical(again["doc"]) == canonical(before["doc"])
    assert reply(s, op="undo")["doc"]["branches"] == {"B": {"slide": "behind", "on": "driven_rod"}}


def test_a_slotted_levers_flip_moves_the_lever_and_needs_no_hint():
    s = Session(doc_of_toml(WHITWORTH))
    before = reply(s, op="hello")
    after = reply(s, op="commit", edits=[{"kind": "flip", "group": 0}])
    assert group(after, "RPR")["branch"] == -group(before, "RPR")["branch"]
    moved = {p for p in before["doc"]["points"] if before["doc"]["points"][p] != after["doc"]["points"][p]}
    assert moved == {"T"} and "branches" not in after["doc"]
    # T on the other side of O2 along the slot: C − O2 along O2 → T changes sign
    P = np.array([after["doc"]["points"][k] for k in ("O2", "C", "T")], dtype=float)
    d = (P[2] - P[0]) / np.linalg.norm(P[2] - P[0])
    assert np.dot(P[1] - P[0], d) < 0
    # back: T where the engine assembles the file at its sketch input (this sketch draws T off the slot's line)
    back = reply(s, op="commit", edits=[{"kind": "flip", "group": 0}])
    plan = assur.compile(assur.loads(WHITWORTH))
    assembled = assur.solve(plan, inputs=plan.sketch_inputs, order=0).pos.reshape(-1, 2)[plan.point_index("T")]
    np.testing.assert_allclose(back["doc"]["points"]["T"], 1e3 * assembled, rtol=0, atol=1e-9)


def test_a_slide_hint_goes_with_its_slide():
    doc = doc_of_toml(WHITWORTH + '[branches]\nC = { slide = "behind", on = "slot" }\n')
    assert "branches" not in delete_slider(doc, "slot")
    both = doc_of_toml(WHITWORTH + '[branches]\nC = { slide = "behind", on = "slot", side = "left", of = ["O", "O2"] }\n')
    assert both["branches"]["C"]["slide"] == "behind"
    assert delete_slider(both, "slot").get("branches") == {"C": {"side": "left", "of": ["O", "O2"]}}


PLANAR = sorted(p.name for p in EX.glob("*.toml")
                if 'format = "assur/1"' in p.read_text() and "dimension = 3" not in p.read_text())


@pytest.mark.slow
@pytest.mark.parametrize("example", PLANAR)
def test_every_dyad_of_the_shipped_examples_flips_and_back(example):
    s = Session.of_file(str(EX / example))
    first = reply(s, op="hello")
    assert first["model"]["groups"] or first["model"]["newton_groups"]      # no dyad: a triad's chooser instead
    for g in first["model"]["groups"]:
        flipped = reply(s, op="commit", edits=[{"kind": "flip", "group": g["index"]}])
        assert flipped["type"] == "result", flipped.get("message")
        assert flipped["model"]["groups"][g["index"]]["branch"] == -g["branch"]
        back = reply(s, op="commit", edits=[{"kind": "flip", "group": g["index"]}])
        assert back["model"]["groups"][g["index"]]["branch"] == g["branch"]
        assert [x["branch"] for x in back["model"]["groups"]] == [x["branch"] for x in first["model"]["groups"]]
