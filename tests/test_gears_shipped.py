"""Every shipped gear file (examples/**.toml with format assur-gears/1, and the gear files the wheel-step files name)
gives envelope teeth that pass the outline checks: simple polygons, points at most m/8 apart, no slivers or
notches, the designed number of teeth, and a pair that runs through the cycle without interference.

Each check is made twice: by the project's own checks (assur.gears.outline.outline_defects, the exact mesh check
of assur.gears.mesh) and by an independent computation in the test (the GEOS simplicity predicate of the closed
ring, the point spacing from numpy, the teeth counted as pieces of the outline outside the pitch curve's
root side, and shapely polygon overlap of the two placed outlines at the offsets the mesh check reports).
"""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from assur.io.gear_file import load_design
from assur.gears.mesh import mesh_check
from assur.gears.outline import outline_defects
from assur.report.bundles import run_gears

ROOT = Path(__file__).resolve().parents[1]


def shipped_gear_files():
    found = set()
    for path in sorted((ROOT / "examples").rglob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if data.get("format") == "assur-gears/1":
            found.add(path.resolve())
        elif data.get("format") == "assur-wheelstep/1" and "gears" in data.get("drive", {}):
            found.add((path.parent / data["drive"]["gears"]).resolve())
    return sorted(found)


FILES = shipped_gear_files()


def test_the_shipped_gear_files_are_found():
    assert ROOT / "examples" / "gears_001.toml" in FILES


def placed(xy, angle, centre):
    """The outline xy (M, 2) turned by ``angle`` (rad, ccw) about its origin and moved to ``centre``."""
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack([centre[0] + c * xy[:, 0] - s * xy[:, 1], centre[1] + s * xy[:, 0] + c * xy[:, 1]])


@pytest.mark.slow
@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_envelope_teeth_of_a_shipped_gear_file_pass_the_outline_checks(path, tmp_path, monkeypatch):
    import shapely
    monkeypatch.setenv("ASSUR_CACHE_DIR", "off")                 # computed here, not read from a cache
    design = load_design(path)
    summary = run_gears(design, tmp_path, mesh_steps=360, figures=False, log=lambda _: None)
    gt, cut_on, rep = summary["_results"]["envelope"]
    m = gt.tooth.module
    for g, z in ((gt.driving, gt.driving.teeth), (gt.driven, gt.driven.teeth)):
        xy = g.xy
        # the project's checks: simple, spacing ≤ m/8, no sliver, needle or notch
        assert outline_defects(xy, m, name=g.name, max_step=m / 8) == []
        # ... and the designed number of teeth on the pitch curve (thickness findings near the corners of a
        # rounded law are reported, not defects of the polygon)
        found = outline_defects(xy, m, teeth=z, name=g.name, max_step=m / 8, pitch_radius=(
            cut_on.driving if g is gt.driving else cut_on.driven).radius_at)
        assert all("thinner or thicker" in f for f in found), found
        # independently: the closed ring does not touch itself (GEOS is_simple on the LinearRing), every edge,
        # the closing one included, is at most m/8 long
        assert shapely.LinearRing(xy).is_simple
        assert np.hypot(*(np.roll(xy, -1, axis=0) - xy).T).max() <= m / 8 * (1 + 1e-9)
        # independently: z teeth — the outline crosses its pitch curve 2z times (each tooth: two flanks)
        curve = cut_on.driving if g is gt.driving else cut_on.driven
        r_pitch = curve.radius_at(np.arctan2(xy[:, 1], xy[:, 0]))
        outside = np.hypot(xy[:, 0], xy[:, 1]) > r_pitch
        assert np.count_nonzero(outside != np.roll(outside, 1)) == 2 * z
    # the exact mesh check: no interference over the cycle
    assert not rep.any_interference
    assert rep.summary()["positions"] == 360
    # independently: at 36 positions the two outlines, placed at the middle of the admissible offsets the check
    # reports, do not overlap; turned past the end of the interval they do
    phi = np.linspace(0.0, 2 * math.pi * cut_on.driving_turns, 36, endpoint=False)
    r = mesh_check(gt.driving, gt.driven, cut_on, phi=phi, ratio_window=0)
    L = cut_on.centre_distance
    a = [shapely.Polygon(placed(gt.driving.xy, p, (0.0, 0.0))) for p in phi]

    def driven_at(i, delta):
        return shapely.Polygon(placed(gt.driven.xy, -(r.theta_law[i] + delta), (L, 0.0)))
    for i in range(phi.size):
        assert not a[i].intersects(driven_at(i, 0.5 * (r.lower[i] + r.upper[i]))), math.degrees(phi[i])
        past = 0.02 * (r.upper[i] - r.lower[i])
        assert a[i].intersection(driven_at(i, r.upper[i] + past)).area > 0
        assert a[i].intersection(driven_at(i, r.lower[i] - past)).area > 0
