"""``backend="auto"`` (issue 26 §5): the compiled kernels where numba is installed and the plan's kernel costs nothing
to start (loaded already, or in numba's disk cache) for a large batch, for a plan with Newton-solved groups already
from a small one once numba is imported, or where the batch wins a compile back; a small batch never imports numba;
both backends give the same numbers."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.engine.options import AUTO_COMPILED_MIN_SAMPLES

pytest.importorskip("numba")
ROOT = Path(__file__).resolve().parents[1]
Q = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)


def _compiled(state) -> bool:
    """Whether a State came from the compiled backend (it keeps the kernel's float views)."""
    return state._xyz is not None


def test_a_loaded_kernel_serves_a_large_batch_and_numpy_an_ordinary_one(fourbar_plan):
    """A dyad plan's compiled kernel, once loaded, serves batches of AUTO_COMPILED_MIN_SAMPLES; an ordinary batch
    (a Study's 720 samples, which also needs the bodies' angles the kernel does not write) stays on numpy, so what a
    cycle solves never depends on what the process ran before."""
    many = np.tile(Q, AUTO_COMPILED_MIN_SAMPLES // Q.size + 1)
    assur.solve(fourbar_plan, inputs=Q, backend="numba")               # the kernel is loaded in this process
    auto = assur.solve(fourbar_plan, inputs=many)
    assert _compiled(auto)
    ref = assur.solve(fourbar_plan, inputs=many, backend="numpy")
    assert not _compiled(ref)
    for k in ("pos", "vel", "acc"):
        np.testing.assert_allclose(getattr(auto, k), getattr(ref, k), rtol=0, atol=1e-12)
    assert not _compiled(assur.solve(fourbar_plan, inputs=Q))


def test_newton_groups_follow_the_same_rule_and_the_oracle_stays_on_numpy(triad_sixbar_plan, fourbar_plan,
                                                                           monkeypatch):
    """A plan with Newton-solved groups takes its compiled kernel by the same rule (tests/test_compiled_newton.py: once
    it is ready); without it an ordinary batch stays on numpy. The Newton oracle of a dyad plan is numpy's alone."""
    from assur.engine.planar import numba_backend
    monkeypatch.setattr(numba_backend, "newton_cached", lambda plan, each=True: False)
    assert not _compiled(assur.solve(triad_sixbar_plan, inputs=Q[:40]))
    assert not _compiled(assur.solve(fourbar_plan, inputs=Q, method="newton"))


def test_a_small_batch_does_not_import_numba():
    code = ("import sys, numpy as np, assur; p = assur.compile(assur.load(sys.argv[1])); "
            "assur.solve(p, inputs=np.linspace(0, 6.28, 720)); print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code, str(ROOT / "examples" / "crank_rocker.toml")],
                         capture_output=True, encoding="utf-8", check=True)
    assert out.stdout.strip() == "False"
