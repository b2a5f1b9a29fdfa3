"""Path synthesis from the designer's page in a worker process (assur.designer.synthesis_job).

Every reference number is recomputed here with the engine: the cost of a design is the sum over the targets of the
distance to the closed polyline through the point's path at 360 crank angles over one turn (the definition of a
synthesis problem's path targets, docs/synthesis.md), solved with ``assur.solve``."""
from __future__ import annotations

import math
import os
import signal
import time
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer.document import EditRefused
from assur.designer.session import document_of
from assur.designer.synthesis_job import SynthesisJob
from assur.engine import compile as compile_plan

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SAMPLES = 360


def path_of(mech, point: str) -> np.ndarray:
    """(SAMPLES, 2) positions (m) of ``point`` over one crank turn."""
    plan = compile_plan(mech)
    q = np.linspace(0.0, 2 * np.pi, SAMPLES, endpoint=False)
    st = assur.solve(plan, inputs=q, order=0)
    assert np.all(st.valid), "the design must assemble over the whole turn"
    return st.pos[:, plan.point_index(point), :]


def path_cost(mech, point: str, targets) -> float:
    """Σ over the targets of the distance (m) to the closed polyline of the sampled path."""
    a = path_of(mech, point)
    b = np.roll(a, -1, axis=0)
    total = 0.0
    for p in np.asarray(targets, dtype=float):
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        total += float(np.min(np.linalg.norm(a + t[:, None] * ab - p, axis=1)))
    return total


def targets_near_path(mech, point: str, n: int, shift: float) -> list:
    """n positions of the point's own path at equal crank steps, each moved by up to ``shift`` (m)."""
    plan = compile_plan(mech)
    st = assur.solve(plan, inputs=np.linspace(0.0, 2 * np.pi, n, endpoint=False), order=0)
    xy = st.pos[:, plan.point_index(point), :]
    k = np.arange(n)
    return (xy + shift * np.stack([np.cos(1.7 * k), np.sin(2.3 * k)], axis=1)).tolist()


def run(job: SynthesisJob, timeout: float = 60.0) -> list[dict]:
    """Every message of a job until its synth_done."""
    out, deadline = [], time.monotonic() + timeout
    while job.running:
        assert time.monotonic() < deadline, f"no synth_done within {timeout} s"
        out += job.poll()
        time.sleep(0.02)
    assert out and out[-1]["type"] == "synth_done"
    assert not job.poll() and not job.running
    return out


def wait_for_evaluations(job: SynthesisJob, timeout: float = 60.0) -> list[dict]:
    """Messages until the first progress message after a design has been evaluated."""
    out, deadline = [], time.monotonic() + timeout
    while True:
        assert time.monotonic() < deadline, "no evaluation reported"
        out += job.poll()
        if any(m["type"] == "synth_progress" and m["evaluations"] > 0 and m["best"] is not None for m in out):
            return out
        assert job.running
        time.sleep(0.02)


def check_progress(messages, job_id):
    progress = [m for m in messages if m["type"] == "synth_progress"]
    assert progress, "at least one progress message per run"
    for m in progress:
        assert m["job"] == job_id
        assert isinstance(m["evaluations"], int) and m["evaluations"] >= 0
        assert m["best"] is None or (isinstance(m["best"], float) and math.isfinite(m["best"]) and m["best"] >= 0)
        assert m["elapsed"] >= 0
    evaluations = [m["evaluations"] for m in progress]
    assert evaluations == sorted(evaluations)
    best = [m["best"] for m in progress if m["best"] is not None]
    assert all(b1 <= b0 + 1e-15 for b0, b1 in zip(best, best[1:])), "the best so far never gets worse"
    return progress


@pytest.fixture(scope="module")
def crank_rocker():
    doc, _ = document_of(EXAMPLES / "crank_rocker.toml")
    mech = assur.load(EXAMPLES / "crank_rocker.toml")
    return doc, mech, targets_near_path(mech, "P", 6, 0.003)


@pytest.mark.slow
def test_small_run_improves_the_design_and_returns_a_loadable_document(crank_rocker):
    doc, mech, targets = crank_rocker
    doc = dict(doc, style={"designer": {"locked_points": [], "locked_links": ["crank"]}, "note": "kept"})
    start = path_cost(mech, "P", targets)
    job = SynthesisJob(doc, "P", targets, budget=1000, seed=1)
    assert job.running and isinstance(job.id, str) and job.id
    messages = run(job)
    progress = check_progress(messages, job.id)
    times = [m["elapsed"] for m in progress]
    assert max(np.diff(times), default=0.0) < 1.0, "progress about every 0.25 s while running"
    done = messages[-1]
    assert done["job"] == job.id and done["status"] == "finished", done["message"]
    assert 1000 <= done["evaluations"] <= 1000 + 15 * 9     # the budget, passed by at most one population
    assert done["toml"] and isinstance(done["message"], str) and done["message"]
    best = assur.loads(done["toml"])
    cost = path_cost(best, "P", targets)
    assert cost <= start + 1e-12, (cost, start)
    assert cost < 0.9 * start                               # a real improvement, not just the start kept
    assert done["best"] == pytest.approx(cost, rel=1e-6, abs=1e-12)
    assert progress[-1]["best"] == pytest.approx(cost, rel=1e-6, abs=1e-12)
    # the document's other content is kept; the locked link keeps its length; the units stay the file's
    import tomllib
    raw = tomllib.loads(done["toml"])
    assert raw["style"] == doc["style"] and raw["name"] == doc["name"] and raw["units"] == doc["units"]
    lengths = {lk.name: lk.length for lk in best.links}
    assert lengths["crank"] == pytest.approx(next(lk.length for lk in mech.links if lk.name == "crank"), rel=1e-12)
    assert lengths["coupler"] != pytest.approx(next(lk.length for lk in mech.links if lk.name == "coupler"))


@pytest.mark.slow
def test_same_seed_and_budget_give_the_same_design():
    doc, _ = document_of(EXAMPLES / "walker_fourbar.toml")
    mech = assur.load(EXAMPLES / "walker_fourbar.toml")
    targets = targets_near_path(mech, "H", 5, 0.02)
    a = SynthesisJob(doc, "H", targets, budget=600, seed=7)
    b = SynthesisJob(doc, "H", targets, budget=600, seed=7)
    assert a.id != b.id
    da, db = run(a)[-1], run(b)[-1]
    assert da["status"] == db["status"] == "finished"
    assert da["toml"] == db["toml"] and da["best"] == db["best"] and da["evaluations"] == db["evaluations"]
    assert path_cost(assur.loads(da["toml"]), "H", targets) <= path_cost(mech, "H", targets) + 1e-12


@pytest.mark.slow
def test_cancel_stops_the_run_and_keeps_the_best_design(crank_rocker):
    doc, mech, targets = crank_rocker
    job = SynthesisJob(doc, "P", targets, budget=10 ** 6, seed=3)
    messages = wait_for_evaluations(job)
    t0 = time.monotonic()
    job.cancel()
    job.cancel()                                            # twice is harmless
    # at once: a cancel that waited for the run would take the 10⁶ evaluations' minutes; the bounds leave room for
    # a loaded machine (they hold the logic, not the speed)
    assert time.monotonic() - t0 < 10.0, "cancel returns at once"
    messages += run(job, timeout=60.0)
    assert time.monotonic() - t0 < 60.0
    check_progress(messages, job.id)
    done = messages[-1]
    assert done["status"] == "cancelled", done["message"]
    assert done["evaluations"] < 10 ** 6
    cost = path_cost(assur.loads(done["toml"]), "P", targets)
    assert cost <= path_cost(mech, "P", targets) + 1e-12
    assert done["best"] == pytest.approx(cost, rel=1e-6, abs=1e-12)


@pytest.mark.slow
def test_a_worker_that_ignores_cancel_is_stopped_and_its_last_design_kept(crank_rocker):
    doc, mech, targets = crank_rocker
    job = SynthesisJob(doc, "P", targets, budget=10 ** 6, seed=4)
    messages = wait_for_evaluations(job)
    time.sleep(0.6)                                         # a few more reports (with the design reported)
    messages += job.poll()
    os.kill(job._process.pid, signal.SIGSTOP)               # the worker can no longer answer
    try:
        t0 = time.monotonic()
        job.cancel()
        messages += run(job, timeout=60.0)                  # its grace period, then the kill (a loaded machine too)
        assert time.monotonic() - t0 < 60.0
    finally:
        if job._process.is_alive():                         # pragma: no cover - only if the test failed
            job._process.kill()
    assert not job._process.is_alive()
    done = messages[-1]
    assert done["status"] == "cancelled"
    assert done["toml"], done["message"]
    cost = path_cost(assur.loads(done["toml"]), "P", targets)
    assert cost <= path_cost(mech, "P", targets) + 1e-12


def _bad_requests():
    crank, _ = document_of(EXAMPLES / "crank_rocker.toml")
    spatial, _ = document_of(EXAMPLES / "rssr.toml")
    two, _ = document_of(EXAMPLES / "walker_fourbar_adjustable.toml")
    good = [[0.06, 0.08], [0.05, 0.07], [0.04, 0.09]]
    return [
        ("unknown point", (crank, "Q", good, 1000, 1), "unknown point"),
        ("frame point", (crank, "O2", good, 1000, 1), "frame point"),
        ("no point", (crank, None, good, 1000, 1), "unknown point"),
        ("one target", (crank, "P", good[:1], 1000, 1), "at least 2"),
        ("NaN target", (crank, "P", [good[0], [float("nan"), 0.1]], 1000, 1), "targets[1]"),
        ("malformed target", (crank, "P", [good[0], [0.1]], 1000, 1), "targets[1]"),
        ("targets not a list", (crank, "P", "here", 1000, 1), "targets"),
        ("spatial document", (spatial, "P", good, 1000, 1), "planar"),
        ("two drivers", (two, "H", good, 1000, 1), "one rotary driver"),
        ("budget 0", (crank, "P", good, 0, 1), "budget"),
        ("budget too large", (crank, "P", good, 10 ** 7, 1), "budget"),
        ("budget not an integer", (crank, "P", good, 2.5, 1), "budget"),
        ("budget a boolean", (crank, "P", good, True, 1), "budget"),
        ("negative seed", (crank, "P", good, 1000, -1), "seed"),
        ("not a document", ({"format": "assur/1", "units": {"length": "m", "angle": "deg"}}, "P", good, 1000, 1),
         "not a mechanism"),
    ]


@pytest.mark.parametrize("label,args,says", _bad_requests(), ids=[r[0] for r in _bad_requests()])
def test_bad_requests_are_refused_before_any_process_starts(monkeypatch, label, args, says):
    started = []
    monkeypatch.setattr(SynthesisJob, "_start", lambda self, x0: started.append(self))
    with pytest.raises(EditRefused) as info:
        SynthesisJob(*args)
    assert says in str(info.value), str(info.value)
    assert not started


def test_a_valid_request_builds_its_problem_and_starts_one_process(monkeypatch, crank_rocker):
    doc, mech, targets = crank_rocker
    started = []
    monkeypatch.setattr(SynthesisJob, "_start", lambda self, x0: started.append(list(x0)))
    job = SynthesisJob(doc, "P", targets, budget=500, seed=2)
    assert len(started) == 1
    problem = job._problem
    plan = compile_plan(mech)
    value = dict(zip(plan.param_names, plan.defaults))
    # the varied parameters start at the document's values, inside their bounds (0.5x..2x for lengths)
    assert started[0] == pytest.approx([value[n] for n in problem.names])
    for v, x in zip(problem.variables, started[0]):
        assert v.low < x < v.high
        if v.name.endswith(".length"):
            assert (v.low, v.high) == pytest.approx((0.5 * x, 2 * x))
    assert "crank.zero" not in problem.names and "coupler.length" in problem.names
    assert problem.targets.timing == "path"
    assert problem.targets.xy == pytest.approx(np.asarray(targets))


def test_the_session_runs_a_synthesis_and_inserts_its_design_as_one_undo_step(crank_rocker):
    from assur.designer.session import Session
    doc, mech, targets = crank_rocker
    session = Session(doc)
    [started] = session.handle({"op": "synth_start", "seq": 1, "point": "P", "targets": targets, "budget": 400,
                                "seed": 1})
    assert started.message["type"] == "synth_started" and started.message["job"] == session.job.id
    [busy] = session.handle({"op": "synth_start", "seq": 2, "point": "P", "targets": targets})
    assert busy.message["type"] == "refused"                 # one run at a time
    replies, deadline = [], time.monotonic() + 60
    while session.job.running:
        assert time.monotonic() < deadline
        replies += session.poll_synthesis()
        time.sleep(0.05)
    done = replies[-1].message
    assert done["type"] == "synth_done" and done["status"] == "finished"
    [inserted] = session.handle({"op": "synth_insert", "seq": 3})
    assert inserted.message["type"] == "result" and inserted.message["history"]["undo"] == 1
    assert path_cost(assur.loads(inserted.message["toml"]), "P", targets) == pytest.approx(done["best"], rel=1e-6)
    [undone] = session.handle({"op": "undo", "seq": 4})
    assert undone.message["history"]["undo"] == 0 and undone.message["doc"] == doc
