"""Four-bar loops and their Grashof class (issue 25 A6): the classification of Grashof's condition with Norton's
names and Barker's codes (R. L. Norton, *Design of Machinery*, 5th ed., §2.14; C. Barker, Mech. Mach. Theory 20
(1985) 535–554), the loops found in a mechanism, and their place in ``info`` and ``analyze``."""
from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

import assur
from assur.analysis.fourbar import four_bar_loops, grashof_class

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("lengths, grashof, kind, code", [
    # (ground, input, coupler, output): s + l against p + q, by hand
    ((4.0, 1.0, 3.0, 3.5), True, "crank-rocker", "GCRR"),      # 1 + 4 = 5 < 6.5, the input shortest
    ((1.0, 4.0, 3.0, 3.5), True, "double-crank", "GCCC"),      # the ground shortest
    ((4.0, 3.0, 1.0, 3.5), True, "double-rocker", "GRCR"),     # the coupler shortest
    ((4.0, 3.5, 3.0, 1.0), True, "rocker-crank", "GRRC"),      # the output shortest
    ((6.0, 2.0, 3.0, 3.5), False, "triple-rocker", "RRR1"),    # 2 + 6 = 8 > 6.5, the ground longest
    ((2.0, 6.0, 3.0, 3.5), False, "triple-rocker", "RRR2"),    # the input longest
])
def test_grashof_classes_by_hand(lengths, grashof, kind, code):
    g, change, k, c, _ = grashof_class(lengths)
    assert (g, change, k, c) == (grashof, False, kind, code)


def test_a_change_point_is_its_own_class():
    g, change, kind, code, shortest = grashof_class((4.0, 1.0, 3.0, 2.0))      # 1 + 4 = 3 + 2
    assert not g and change and kind == "crank-rocker" and code == "GCRR (change point)" and shortest == "input"


def test_the_walking_legs_four_bar_is_a_grashof_crank_rocker_of_the_files_lengths():
    plan = assur.compile(assur.load(ROOT / "examples" / "walker_fourbar.toml"))
    (loop,) = four_bar_loops(plan)
    assert (loop.ground, loop.input, loop.coupler, loop.output) == ("frame", "crank", "coupler", "rocker")
    assert loop.lengths == pytest.approx((math.hypot(0.567, 0.615), 0.27, 0.65, 0.638), rel=1e-12)
    assert loop.grashof and loop.kind == "crank-rocker" and loop.crank_turns_fully


NON_GRASHOF = """
format = "assur/1"
name = "triple-rocker"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
O4 = [100, 0]
A = [60, 0]
B = [120, 50]
[links]
frame = ["O", "O4"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["O4", "B"]
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
speed = "10 rpm"
"""


def test_a_non_grashof_file_says_so_and_marks_the_peak_acceleration_at_a_toggle(tmp_path):
    path = tmp_path / "rocker.toml"
    path.write_text(NON_GRASHOF, encoding="utf-8")
    plan = assur.compile(assur.load(path))
    study = assur.Study(plan)
    (loop,) = study.four_bars
    assert not loop.grashof and loop.kind == "triple-rocker"
    assert not study.buildable.full_rotation
    assert any(m.alpha_at_toggle for m in study.links.values())
    run = lambda *a: subprocess.run([sys.executable, "-m", "assur", *a, str(path)], capture_output=True,  # noqa: E731
                                    encoding="utf-8", cwd=ROOT)
    info, analyze = run("info"), run("analyze")
    assert info.returncode == analyze.returncode == 0, info.stderr + analyze.stderr
    for out in (info.stdout, analyze.stdout):
        assert "non-Grashof triple-rocker" in out
    assert "(at a toggle)" in analyze.stdout
