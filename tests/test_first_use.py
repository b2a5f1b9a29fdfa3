"""The compiled extra is never slower on first use than the numpy path it replaces: a command compiles a kernel for
a new mechanism (seconds, ``benchmarks/first_use.py``) only where the run wins that back — a synthesis whose numpy
evaluations would take ``PAYBACK_SECONDS`` by a fixed estimate from the problem's size (or a time limit of six times
that), a solve of ``AUTO_COMPILE_MIN_SAMPLES`` samples — and otherwise runs numpy, or the compiled kernel when the
cache has it already.

Each command runs with an empty kernel cache (``ASSUR_CACHE_DIR`` a new directory): the test asserts on what it
compiles (the notice it prints), never on how long it takes. Once ``synth walker_fourbar_motor.toml --budget 1500``
compiled three kernels first (62 s where numpy takes 8–14 s) and ``solve --steps 20000`` compiled one for a solve
numpy does in a fraction of a second.
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _assur(tmp_path, *args):
    env = {**os.environ, "ASSUR_CACHE_DIR": str(tmp_path / "cache")}
    r = subprocess.run([sys.executable, "-m", "assur", *map(str, args)], env=env, capture_output=True, encoding="utf-8",
                       timeout=900, cwd=ROOT)
    assert r.returncode == 0, r.stderr[-3000:]
    return r


def test_a_short_synthesis_runs_numpy_and_compiles_nothing(tmp_path):
    r = _assur(tmp_path, "synth", "examples/synthesis/walker_fourbar_motor.toml", "--seed", "1", "--budget", "1500",
               "--popsize", "10", "--quiet")
    assert "compil" not in r.stderr
    assert "backend numpy (default)" in r.stdout


def test_a_moderate_solve_uses_numpy_until_the_kernel_is_cached(tmp_path):
    r = _assur(tmp_path, "solve", "examples/jansen.toml", "--steps", "20000")
    assert "compil" not in r.stderr


def test_the_rule_is_the_runs_size_not_the_caches_state():
    from assur.engine.planar.numba_backend import available
    from assur.synthesis import load_problem
    from assur.synthesis.evaluate import PAYBACK_SECONDS, numpy_seconds, run_backend
    fast = "numba" if available() else "numpy"
    motor = load_problem(ROOT / "examples" / "synthesis" / "walker_fourbar_motor.toml")
    c2 = load_problem(ROOT / "examples" / "synthesis" / "c2_five_points_timed.toml")
    six = load_problem(ROOT / "examples" / "synthesis" / "stephenson3_path.toml")
    # the estimate: solved samples per evaluation × plan steps × a fixed cost (72 cycle samples, 3 steps)
    assert numpy_seconds(motor, 1000) == pytest.approx(1000 * 72 * 3 * 0.5e-6)
    assert run_backend(motor, 1500, None) == "numpy"                 # the run: numpy, nothing compiled
    assert run_backend(c2, 300_000, None) == "numpy"                  # 5 targets: numpy evaluates fast enough
    assert run_backend(six, 30_000, None) == fast                     # a six-bar's whole cycles: compiled pays
    assert run_backend(c2, None, 6 * PAYBACK_SECONDS - 1) == "numpy" and run_backend(c2, None, 600.0) == fast
    assert all(run_backend(p, b, None) == ("numpy" if numpy_seconds(p, b) < PAYBACK_SECONDS else fast)
               for p in (motor, c2, six) for b in (10, 10_000, 10 ** 7))


def test_free_timing_solved_per_design_counts_its_turn_and_refinements():
    """With the inner timing solve an evaluation solves a whole turn of the target point and refines each target's
    input (up to timing.MAX_ITERATIONS order-2 solves): the estimate counts them, so a default run of the ten-point
    ellipse compiles (counted as its 10 targets alone, 4.5 s of numpy, it ran on numpy for tens of minutes)."""
    from assur.engine.planar.numba_backend import available
    from assur.synthesis import load_problem
    from assur.synthesis.evaluate import numpy_seconds, run_backend
    from assur.synthesis.timing import MAX_ITERATIONS
    h5 = load_problem(ROOT / "examples" / "synthesis" / "benchmarks" / "hcdj5_ten_points_ellipse.toml")
    assert h5.targets.free_timing == "inner" and h5.targets.n == 10 and h5.cycle_samples == 360
    steps = len(h5.plan.steps)
    assert numpy_seconds(h5, 1000) == pytest.approx(1000 * (10 + 360 + 10 * MAX_ITERATIONS) * steps * 0.5e-6)
    assert run_backend(h5, 300_000, None) == ("numba" if available() else "numpy")


#: the body of test_a_solve_takes_the_cached_kernel_once_it_is_there, run in a new interpreter with an empty kernel
#: cache (in a test worker an earlier test may have loaded the kernel already)
_CACHED_KERNEL_SCRIPT = """
import sys
import numpy as np
import assur
from assur.engine.planar import numba_backend
plan = assur.compile(assur.load(sys.argv[1]))
assert not numba_backend.kernel_ready(plan), "the kernel is ready in a new process with an empty cache"
q = np.linspace(0, 6.28, 20000)
a = assur.solve(plan, inputs=q)                     # auto, not cached: numpy
assert not numba_backend.kernel_ready(plan)
assur.solve(plan, inputs=q[:10], backend="numba")   # compiles it
assert numba_backend.kernel_ready(plan)
b = assur.solve(plan, inputs=q)                     # auto, cached: compiled
np.testing.assert_allclose(b.pos, a.pos, rtol=0, atol=1e-12)
"""


@pytest.mark.slow
def test_a_solve_takes_the_cached_kernel_once_it_is_there(tmp_path):
    """After a synthesis compiled a mechanism's kernel, a moderate solve of the same mechanism uses it (the same
    numbers as numpy to round-off: the excerpt printed agrees). Run in a new interpreter with an empty kernel cache."""
    pytest.importorskip("numba")
    env = {**os.environ, "ASSUR_CACHE_DIR": str(tmp_path / "cache")}
    r = subprocess.run([sys.executable, "-c", _CACHED_KERNEL_SCRIPT, str(ROOT / "examples" / "jansen.toml")],
                       env=env, capture_output=True, encoding="utf-8", timeout=900, cwd=ROOT)
    assert r.returncode == 0, r.stderr[-3000:]
