"""``synth --time`` is a wall-time limit of the whole run: every start (in this process or on workers), its polish
and restarts, within a stated margin, and the wall time printed is the real one.

The margin (docs/synthesis.md, "Time limit"): no population is evaluated after the limit, so a run ends at
most one evaluation batch after it, plus the best design's re-check in the calling process (``result.timing``:
``longest_batch``, ``finish``); a run whose first population ends after the limit (workers still starting on a
busy machine) ends right after that population. The tests take these measured durations from the run itself and
allow a further second for stopping the workers: they assert the limit's logic, not the machine's speed.
Once each start of a multi-start run got the whole limit afresh: four starts on two workers ran two rounds
(``--time 20`` took 43.7 s).
"""
import json
import subprocess
import sys
import time
from pathlib import Path

import pytest

from assur.synthesis import InProcess, load_problem, synthesize

ROOT = Path(__file__).resolve().parents[1]
C2 = ROOT / "examples" / "synthesis" / "c2_five_points_timed.toml"
C3 = ROOT / "examples" / "synthesis" / "c3_eighteen_points_closed.toml"
#: stopping worker processes and returning (not measured by the run)
STOP = 1.0


class SlowInProcess(InProcess):
    """Evaluates in this process, each population taking at least ``pause`` seconds (a slow objective), and runs
    whole starts one after another through ``map_starts`` as a worker pool with one worker would."""

    def __init__(self, pause):
        self.pause = pause

    def evaluate(self, evaluator, X, detail=False):
        time.sleep(self.pause)
        return evaluator(X, detail)


def _bound(limit, timing):
    return max(limit, timing.get("first_batch", 0.0)) + timing.get("longest_batch", 0.0) \
        + timing.get("finish", 0.0) + STOP


def test_starts_run_as_tasks_share_one_deadline():
    p = load_problem(C2)
    synthesize(p, seed=1, budget=100, polish="none")           # the compiled kernels loaded outside the timed run
    limit = 1.0
    t0 = time.perf_counter()
    r = synthesize(p, seed=1, time_limit=limit, starts=4, parallel_starts=True, executor=SlowInProcess(0.02),
                   maxiter=10 ** 9, tol=0.0, patience=10 ** 9)
    wall = time.perf_counter() - t0
    assert r.stopped == "time" and r.feasible is not None
    assert limit <= wall <= _bound(limit, getattr(r, "timing", {})), (wall, getattr(r, "timing", None))
    assert r.seconds <= wall
    # the starts that began after the deadline evaluated nothing and are not reported as starts
    assert 1 <= len(r.starts) < 4


@pytest.mark.slow
def test_cli_time_limit_holds_for_starts_on_workers():
    limit = 8.0
    cmd = [sys.executable, "-m", "assur", "synth", str(C3), "--starts", "4", "--workers", "2", "--time", str(limit),
           "--seed", "1", "--json"]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, encoding="utf-8", timeout=600, cwd=ROOT)
    outside = time.perf_counter() - t0
    assert r.returncode == 0, r.stderr[-3000:]
    d = json.loads(r.stdout)
    assert d["stopped"] == "time"
    timing = d.get("timing", {})
    # the printed figure is the real wall time of the run: the interpreter's own start-up is all it leaves out
    assert limit <= d["seconds"] <= outside
    assert d["seconds"] <= _bound(limit, timing), (d["seconds"], timing)
