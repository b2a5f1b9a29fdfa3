"""Kill trials of the commands that write an output directory: ``assur codesign -o DIR`` and ``assur atlas -o DIR``.

A first run writes DIR completely; then the same command is started again and killed with SIGKILL (no handler can
run) at several moments: before it writes, and while it fills its temporary directory (the moment a careless writer
loses the earlier output). After every kill DIR must still hold exactly the earlier output, byte for byte; the
next run that completes removes the killed runs' temporaries and replaces DIR whole (io/output.py).
"""
import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LEG = ROOT / "examples" / "walker_fourbar.toml"

pytestmark = pytest.mark.slow


def _digest(directory: Path) -> dict:
    """{relative path: sha256} of every file under ``directory``."""
    return {str(p.relative_to(directory)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(directory.rglob("*")) if p.is_file()}


def _temporaries(out: Path) -> list[Path]:
    return sorted(out.parent.glob(f".{out.name}.*.tmp"))


def _run(cmd, cwd):
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, encoding="utf-8", timeout=1800)
    assert r.returncode == 0, r.stderr[-3000:]


def _kill(cmd, cwd, out, *, when: str, after: float) -> bool:
    """Start ``cmd`` and SIGKILL it: ``when`` "start" after ``after`` seconds, "writing" ``after`` seconds after its
    temporary output directory appears. Returns True when the kill landed while the command ran."""
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        if when == "writing":
            seen = set(_temporaries(out))
            t_end = time.monotonic() + 1200
            while p.poll() is None and time.monotonic() < t_end:
                if set(_temporaries(out)) - seen:
                    break
                time.sleep(0.02)
        time.sleep(after)
        alive = p.poll() is None
        p.send_signal(signal.SIGKILL)
    finally:
        p.wait(timeout=60)
    return alive


def _trials(cmd, cwd, out, plan):
    _run(cmd, cwd)                                      # the earlier, complete output
    before = _digest(out)
    assert before and ".assur-output" in before
    landed = 0
    for when, after in plan:
        landed += _kill(cmd, cwd, out, when=when, after=after)
        assert _digest(out) == before, f"killed ({when}, {after} s): the earlier output changed"
        assert not [p for p in out.parent.iterdir() if p.name.startswith(out.name) and p != out], \
            "a half-written output beside the directory"
    assert landed >= 2, "the kills came too late: the command had ended"
    _run(cmd, cwd)                                      # a run to completion: the killed runs' temporaries go
    assert _temporaries(out) == []
    assert set(_digest(out)) == set(before)


def test_killed_atlas_runs_keep_the_earlier_output(tmp_path):
    out = tmp_path / "atlas"
    cmd = [sys.executable, "-m", "assur", "atlas", "--links", "6", "--dof", "1", "-o", str(out)]
    # atlas computes everything, then writes its files in milliseconds: most kills land while it computes
    _trials(cmd, tmp_path, out, [("start", 0.5), ("start", 1.5), ("start", 3.0), ("writing", 0.0)])


def test_killed_codesign_runs_keep_the_earlier_output(tmp_path):
    out = tmp_path / "codesign"
    # a quick co-design (no optimisation, a narrow window: 5 s instead of 14) that writes the same files
    cmd = [sys.executable, "-m", "assur", "codesign", str(LEG), "-o", str(out), "--frames", "0", "--mesh-steps", "8",
           "--optimize", "none", "--window", "0.5"]
    _trials(cmd, tmp_path, out, [("start", 1.0), ("writing", 0.0), ("writing", 0.5)])
