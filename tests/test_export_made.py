"""A MuJoCo model of a file with a [make] table takes the made parts' masses (issue 28: "the file's masses and
inertias, or the parts of assur make when present")."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

import assur
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_the_mjcf_of_a_made_mechanism_carries_its_parts_masses(tmp_path):
    pytest.importorskip("build123d")
    from assur.parts.massback import with_masses
    text = (ROOT / "examples" / "crank_rocker.toml").read_text(encoding="utf-8") + '\n[make]\nthickness = "4 mm"\n'
    path = tmp_path / "made.toml"
    path.write_text(text, encoding="utf-8")
    assert main(["export", str(path), "--to", "mjcf", str(tmp_path / "m.xml")]) == 0
    xml = (tmp_path / "m.xml").read_text(encoding="utf-8")
    made = with_masses(assur.Study(assur.compile(assur.load(path))).parts)     # what assur make --mass-back writes
    expected = sorted(mp.mass for _, mp in made.dynamics.bodies if mp.mass)
    body_masses = sorted(float(x) for x in re.findall(r'<inertial[^>]*mass="([^"]+)"', xml) if float(x) > 0)
    for m in expected:      # every made body's mass is a body of the model (the model adds its own base)
        assert any(abs(b - m) <= 1e-9 * m for b in body_masses), (m, body_masses)
