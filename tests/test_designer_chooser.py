"""The designer's chooser of assemblies without a browser: the ``assemblies`` request lists what `assur.assemblies`
finds at one input, the ``assembly`` edit puts the sketch on one of them (the points it moves, the dyads' hints
turned, the result solved to the chosen assembly), and the refusals.

References: `assur.assemblies` and `assur.solve` run in the tests on the documents the session makes (each loaded
again from its TOML text, as a saved file would be).
"""
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer import choosing
from assur.designer.session import Session

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
needs_assemblies = pytest.mark.skipif(not hasattr(assur, "assemblies"),
                                      reason="assur.assemblies (issue 26 §2) is not in this assur yet")


def reply(s, **request):
    (r,) = s.handle({"seq": 1, **request})
    return r.message


def identity(branches):
    return [list(b) if isinstance(b, tuple) else int(b) for b in branches]


def sketch_assembly(toml: str, q) -> list:
    """The branch identity of the assembly a document's own sketch solves to at the input vector ``q``."""
    plan = assur.compile(assur.loads(toml))
    return [identity(a.branches) for a in assur.assemblies(plan, np.asarray(q, float)[None, :])[0] if a.sketch]


@needs_assemblies
@pytest.mark.parametrize("example, q", [("triad_sixbar.toml", 0.0), ("triad_sixbar.toml", 2.0),
                                        ("walker_sixbar.toml", 1.0)])
def test_the_list_is_assur_assemblies_at_the_input(example, q):
    s = Session.of_file(str(EX / example))
    hello = reply(s, op="hello")
    m = reply(s, op="assemblies", input=q)
    plan = assur.compile(assur.load(EX / example))
    reference = assur.assemblies(plan, np.array([[q]]))[0]
    assert m["type"] == "assemblies" and m["input"] == q and m["inputs"] == [q]
    assert [a["branches"] for a in m["assemblies"]] == [identity(r.branches) for r in reference]
    assert [a["current"] for a in m["assemblies"]] == [bool(r.sketch) for r in reference]
    for a, r in zip(m["assemblies"], reference):
        np.testing.assert_array_equal(a["positions"], r.pos)
    assert len(m["groups"]) == len(reference[0].branches)
    assert hello["model"]["chooser"] is (example == "triad_sixbar.toml")


@needs_assemblies
def test_choosing_at_another_input_draws_the_mechanism_there_on_that_assembly():
    s = Session.of_file(str(EX / "triad_sixbar.toml"))
    before = reply(s, op="hello")["doc"]
    m = reply(s, op="assemblies", input=2.0)
    other = next(a for a in m["assemblies"] if not a["current"])
    r = reply(s, op="commit", edits=[{"kind": "assembly", "input": 2.0, "branches": other["branches"]}])
    assert r["type"] == "result" and r["history"]["undo"] == 1
    # the crank's arm moved to 2 rad and the triad to the chosen assembly; the frame stays
    moved = {p for p in before["points"] if before["points"][p] != r["doc"]["points"][p]}
    assert moved == {"A", "B", "C", "D"}
    A = np.array(r["doc"]["points"]["A"])
    assert np.arctan2(A[1], A[0]) == pytest.approx(2.0, abs=1e-12)
    assert sketch_assembly(r["toml"], [2.0]) == [other["branches"]]
    plan = assur.compile(assur.loads(r["toml"]))
    pos = assur.solve(plan, inputs=[[2.0]], order=0).pos.reshape(-1, plan.n_points, 2)[0]
    np.testing.assert_allclose(pos, other["positions"], rtol=0, atol=1e-9 * plan.length_scale)
    assert reply(s, op="undo")["doc"] == before


@needs_assemblies
def test_choosing_a_dyad_assembly_turns_the_files_hints():
    """walker_sixbar.toml holds [branches] hints: an assembly with both dyads on their other branches turns both."""
    s = Session.of_file(str(EX / "walker_sixbar.toml"))
    doc = reply(s, op="hello")["doc"]
    assert doc.get("branches")
    m = reply(s, op="assemblies", input=1.0)
    (now,) = [a for a in m["assemblies"] if a["current"]]
    far = next((a for a in m["assemblies"] if all(x != y for x, y in zip(a["branches"], now["branches"]))), None)
    assert far is not None
    r = reply(s, op="commit", edits=[{"kind": "assembly", "input": 1.0, "branches": far["branches"]}])
    assert r["type"] == "result", r.get("message")
    assert sketch_assembly(r["toml"], [1.0]) == [far["branches"]]
    sides = {p: h["side"] for p, h in doc["branches"].items()}
    assert {p: h["side"] for p, h in r["doc"]["branches"].items()} == \
        {p: ("left" if v == "right" else "right") for p, v in sides.items()}


@needs_assemblies
def test_assemblies_that_differ_only_in_a_bodys_turn_are_each_chosen():
    """lever_manipulator.toml: its passive RPR rod's two branches place every point alike (the rod toward B or half
    a turn from it): one of them is current, and each other assembly, once chosen, is the only current one."""
    s = Session.of_file(str(EX / "lever_manipulator.toml"))
    m = reply(s, op="assemblies", input=0.5)
    assert len(m["assemblies"]) == 4 and sum(a["current"] for a in m["assemblies"]) == 1
    # each is labelled with the assembly whose points it shares: the other of its pair (1–2, 3–4)
    assert [a["label"].split("(the points of ")[1][:2] for a in m["assemblies"]] == ["#2", "#1", "#4", "#3"]
    for a in m["assemblies"]:
        if a["current"]:
            continue
        r = reply(s, op="commit", edits=[{"kind": "assembly", "input": 0.5, "branches": a["branches"]}])
        assert r["type"] == "result", r.get("message")
        assert sketch_assembly(r["toml"], [0.5]) == [a["branches"]]
        reply(s, op="undo")


@needs_assemblies
@pytest.mark.parametrize("edit, says", [
    ({"input": 0.0, "branches": [[1, 7]]}, "no assembly [[1, 7]] at this input"),
    ({"input": 0.0}, "needs branches"),
    ({"input": "zero", "branches": [[1, 1]]}, "must be a finite number"),
    ({"input": float("nan"), "branches": [[1, 1]]}, "must be a finite number"),
    ({"input": 0.0, "index": 3, "branches": [[1, 1]]}, "no input 3"),
])
def test_a_bad_assembly_edit_is_refused_and_changes_nothing(edit, says):
    s = Session.of_file(str(EX / "triad_sixbar.toml"))
    r = reply(s, op="commit", edits=[{"kind": "assembly", **edit}])
    assert r["type"] == "refused" and says in r["message"] and s.position == 0


def test_without_an_enumeration_the_chooser_is_not_offered(monkeypatch):
    monkeypatch.setattr(choosing, "available", lambda: False)
    s = Session.of_file(str(EX / "triad_sixbar.toml"))
    assert reply(s, op="hello")["model"]["chooser"] is False
    r = reply(s, op="assemblies", input=0.0)
    assert r["type"] == "refused" and r["message"] == "this assur does not enumerate assemblies (assur.assemblies)"


def test_a_spatial_mechanism_has_no_chooser():
    s = Session.of_file(str(EX / "rssr.toml"))
    assert reply(s, op="hello")["model"]["chooser"] is False
    r = reply(s, op="assemblies", input=0.0)
    assert r["type"] == "refused" and "planar" in r["message"]
