"""The designer's branches in a real headless Chromium: the chooser of assemblies of a class-III triad
(examples/triad_sixbar.toml) lists what `assur.assemblies` finds at the current input, choosing one redraws the
mechanism on it in one undo step, undo returns, a saved file re-opens on the chosen assembly; and an RPR dyad's Flip
(paper 002's passive cylinder) draws the cylinder on its other branch.

References: `assur.assemblies` and `assur.solve` run in the test on the page's document and on the saved file.
"""
from __future__ import annotations

import numpy as np
import pytest

import assur
from designer_browser import browser, designer, needs_designer_browser  # noqa: F401

pytestmark = [pytest.mark.slow, needs_designer_browser]
needs_assemblies = pytest.mark.skipif(not hasattr(assur, "assemblies"),
                                      reason="assur.assemblies (issue 26 §2) is not in this assur yet")


def identity(branches):
    return [list(b) if isinstance(b, tuple) else int(b) for b in branches]


def listed(d, sample: int) -> dict:
    """The chooser's list once it is the one of the committed document at ``sample``."""
    q = float(d.array("q")[sample])
    d.page.wait_for_function(
        """([q, toml]) => { const m = window.__assur.assemblies;
                            return m && Math.abs(m.input - q) < 1e-15
                                   && !document.querySelector('[data-testid=assemblies-list]').classList.contains('asd-stale'); }""",
        arg=[q, d.state("result.toml")])
    return d.state("assemblies")


def pose(d, sample: int) -> np.ndarray:
    return d.array("pos")[sample]


@needs_assemblies
def test_the_chooser_lists_assur_assemblies_and_a_choice_is_one_undo_step_that_saves(designer):
    d = designer("triad_sixbar.toml")
    assert d.testid("assemblies-panel").is_visible()
    plan = assur.compile(assur.load(d.file))
    scale = plan.length_scale
    shown = listed(d, 0)
    q = np.array(shown["inputs"])
    reference = assur.assemblies(plan, q[None, :])[0]
    assert len(reference) >= 2
    assert [a["branches"] for a in shown["assemblies"]] == [identity(r.branches) for r in reference]
    assert [a["current"] for a in shown["assemblies"]] == [bool(r.sketch) for r in reference]
    assert shown["point_order"] == list(plan.point_names)
    for a, r in zip(shown["assemblies"], reference):
        np.testing.assert_allclose(a["positions"], r.pos, rtol=0, atol=1e-12 * scale)
    (now,) = [a for a in shown["assemblies"] if a["current"]]
    np.testing.assert_allclose(pose(d, 0), now["positions"], rtol=0, atol=1e-9 * scale)
    other = next(a for a in shown["assemblies"] if not a["current"])
    # the pointer on its row draws it as a ghost: its links at the assembly's positions
    d.testid(f"assembly-{other['index']}").hover()
    assert d.testid("ghost-tern").count() == 1
    d.page.mouse.move(5, 5)
    assert d.testid("ghost-tern").count() == 0
    # choose it: one undo step, the mechanism drawn on it at this input
    seq = d.seq()
    d.testid(f"assembly-choose-{other['index']}").click()
    r = d.wait_result(seq, "r.committed && r.history.undo === 1")
    np.testing.assert_allclose(pose(d, 0), other["positions"], rtol=0, atol=1e-9 * scale)
    circle = d.testid("point-D")
    np.testing.assert_allclose([float(circle.get_attribute("data-x")), float(circle.get_attribute("data-y"))],
                               other["positions"][plan.point_index("D")], rtol=0, atol=1e-9 * scale)
    relisted = listed(d, 0)
    assert [a["branches"] for a in relisted["assemblies"] if a["current"]] == [other["branches"]]
    chosen_plan = assur.compile(assur.loads(r["toml"]))
    ref = [a for a in assur.assemblies(chosen_plan, q[None, :])[0] if a.sketch]
    assert [identity(a.branches) for a in ref] == [other["branches"]]
    # the list follows the scrub bar: at 90°, what assur.assemblies finds for the chosen document there
    d.set_sample(90)
    at90 = listed(d, 90)
    ref90 = assur.assemblies(chosen_plan, np.array(at90["inputs"])[None, :])[0]
    assert [a["branches"] for a in at90["assemblies"]] == [identity(a.branches) for a in ref90]
    assert [a["current"] for a in at90["assemblies"]] == [bool(a.sketch) for a in ref90]
    # undo returns to the first assembly, redo to the chosen one
    d.set_sample(0)
    seq = d.seq()
    d.testid("undo").click()
    d.wait_result(seq, "r.history.undo === 0")
    np.testing.assert_allclose(pose(d, 0), now["positions"], rtol=0, atol=1e-9 * scale)
    seq = d.seq()
    d.testid("redo").click()
    d.wait_result(seq, "r.history.undo === 1")
    np.testing.assert_allclose(pose(d, 0), other["positions"], rtol=0, atol=1e-9 * scale)
    # saved, the file re-opens on the chosen assembly: only moved points changed in the file
    before = d.file.read_text()
    d.testid("save").click()
    d.page.wait_for_function("() => document.querySelector('[data-testid=status]').textContent.startsWith('saved')")
    after = d.file.read_text()
    changed = {b.split("=")[0].strip() for a, b in zip(before.splitlines(), after.splitlines()) if a != b}
    assert changed and changed <= set(plan.point_names) - {"O", "P1", "P2"}
    assert len(before.splitlines()) == len(after.splitlines())
    reopened = assur.compile(assur.load(d.file))
    state = assur.solve(reopened, inputs=q[None, :], order=0)
    np.testing.assert_allclose(state.pos.reshape(-1, reopened.n_points, 2)[0], other["positions"], rtol=0,
                               atol=1e-9 * scale)
    assert [identity(a.branches) for a in assur.assemblies(reopened, q[None, :])[0] if a.sketch] == \
        [other["branches"]]


def test_an_rpr_flip_turns_the_passive_cylinder(designer):
    d = designer("lever_manipulator.toml")
    groups = d.state("result.model.groups")
    (rpr,) = [g for g in groups if g["kind"] == "RPR"]
    cylinder = d.testid("actuator-driven_rod")
    ends = lambda: [float(cylinder.get_attribute(k)) for k in ("x1", "y1", "x2", "y2")]  # noqa: E731
    x1, y1, x2, y2 = ends()
    assert cylinder.get_attribute("data-behind") is None
    seq = d.seq()
    d.testid(f"flip-{rpr['index']}").click()
    r = d.wait_result(seq, "r.committed && r.history.undo === 1")
    assert r["doc"]["branches"] == {"B": {"slide": "behind", "on": "driven_rod"}}
    assert [g["branch"] for g in r["model"]["groups"] if g["kind"] == "RPR"] == [-1]
    assert cylinder.get_attribute("data-behind") == ""
    # the cylinder leaves its hinge the other way: away from the rod's end
    X1, Y1, X2, Y2 = ends()
    assert (X1, Y1) == pytest.approx((x1, y1), abs=1e-6)
    assert np.dot([X2 - X1, Y2 - Y1], [x2 - x1, y2 - y1]) < 0
