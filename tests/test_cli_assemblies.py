"""``assur info FILE --assemblies [--at …]`` and ``assur plot FILE --assemblies -o F``: what they print and draw is
what ``assur.assemblies`` returns; bad input is one error line."""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
TRIAD = ROOT / "examples" / "triad_sixbar.toml"
FOURBAR = ROOT / "examples" / "crank_rocker.toml"


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_info_lists_the_assemblies_at_an_input(capsys):
    code, out, err = run(["info", TRIAD, "--assemblies", "--at", "90"], capsys)
    assert code == 0 and not err
    plan = assur.compile(assur.load(TRIAD))
    found = assur.assemblies(plan, math.radians(90.0))[0]
    head = next(line for line in out.splitlines() if line.startswith("assemblies at"))
    assert head == f"assemblies at crank = 90°: {len(found)}"
    lines = out.splitlines()
    rows = [line for line in lines[lines.index(head):] if re.match(r"  \d+\. ", line)]
    assert len(rows) == len(found)
    marked = [line for line in rows if "the sketch's" in line]
    assert len(marked) == 1
    k = int(marked[0].split(".")[0])
    assert found[k - 1].sketch
    # the sketch's positions, printed in mm, are the solve's
    st = assur.solve(plan, inputs=math.radians(90.0), order=0)
    line = out.splitlines()[out.splitlines().index(marked[0]) + 1]
    d = re.search(r"D = \(([-\d.e]+), ([-\d.e]+)\)", line)
    np.testing.assert_allclose([float(d.group(1)), float(d.group(2))], st.pos[plan.point_index("D")] * 1e3, atol=1e-3)


def test_a_four_bar_has_its_two_assemblies(capsys):
    code, out, _ = run(["info", FOURBAR, "--assemblies"], capsys)
    assert code == 0
    assert re.search(r"assemblies at crank = [\d.]+°: 2", out)
    assert "B +" in out and "B −" in out


def test_plot_draws_the_assemblies(tmp_path, capsys):
    out = tmp_path / "a.png"
    code, text, err = run(["plot", TRIAD, "--assemblies", "--at", "45", "-o", out], capsys)
    assert code == 0 and out.stat().st_size > 10_000 and f"wrote {out}" in text


def test_assemblies_with_the_same_points_name_their_turned_bodies(capsys):
    """lever_manipulator.toml: the passive RPR rod O–B's two branches place B alike; the listing says which
    assemblies share their points and where the rod points in each (toward B at (300, 400) mm: atan2(400, 300))."""
    code, out, err = run(["info", ROOT / "examples" / "lever_manipulator.toml", "--assemblies"], capsys)
    assert code == 0 and "assemblies at drive = 500 mm: 4" in out
    assert out.count("← the sketch's") == 1
    assert f"the same points as #2, its bodies otherwise turned: driven_rod.cylinder at " \
           f"{math.degrees(math.atan2(400, 300)):.6g}°" in out


@pytest.mark.parametrize("argv,message", [
    (["info", TRIAD, "--at", "10"], "--at: is for the assemblies: add --assemblies"),
    (["info", TRIAD, "--assemblies", "--at", "ten"], "--at: must be a number"),
    (["info", TRIAD, "--assemblies", "--at", "1", "2"], "--at: give at most one value per input"),
    (["info", ROOT / "examples" / "rssr.toml", "--assemblies"], "--assemblies: assemblies are listed for planar"),
    (["plot", TRIAD, "--assemblies", "--forces", "-o", "x.png"], "give one of them"),
])
def test_bad_assembly_options_are_one_error_line(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = run(argv, capsys)
    assert code == 1 and err.count("\n") == 1 and message in err
    assert out == ""        # refused before anything is printed
    assert list(tmp_path.iterdir()) == []
