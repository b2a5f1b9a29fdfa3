"""The disk cache of the expensive gear results (assur.gears.cache): the rack-cut outlines and the mesh checks.

Reference for every cached value: the same computation with the cache off (``ASSUR_CACHE_DIR=off``) in the test
itself; a hit must return it bit for bit (arrays equal, not approximately equal).
"""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from assur.gears import cache, pitch_pair
from assur.gears import teeth as teeth_module
from assur.gears.mesh import mesh_check
from assur.gears.teeth import ToothParameters, cut_gear, cut_pair

M = 2e-3
ROOT = Path(__file__).resolve().parents[1]


def circle(r):
    return lambda a: np.full(np.shape(a), r)


def cut(backlash=0.1e-3, r=12 * M / 2):
    return cut_gear(circle(r), ToothParameters(module=M, backlash=backlash), 12, samples=1536)


def assert_same_outline(a, b):
    assert np.array_equal(a.xy, b.xy)
    for name in ("name", "teeth", "tooth", "perimeter", "undercut", "undercut_text", "corners",
                 "min_curvature_radius", "mirror", "defects", "shift"):
        assert getattr(a, name) == getattr(b, name), name


def assert_same_report(a, b):
    for name in ("phi", "theta_law", "lower", "upper", "penetration", "interferes", "law_ratio", "actual_ratio",
                 "backlash", "law_ratio_window"):
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert a.summary() == b.summary()


def entries(d):
    return sorted((d / "gears").glob("*.npz")) if (d / "gears").is_dir() else []


@pytest.fixture
def off(monkeypatch):
    """Compute without the cache (the reference)."""
    monkeypatch.setenv(cache.ENV, "off")


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, str(tmp_path))
    return tmp_path


def reference(monkeypatch, make):
    monkeypatch.setenv(cache.ENV, "off")
    out = make()
    monkeypatch.undo()
    return out


def test_a_hit_returns_the_computed_outline_without_cutting(cache_dir, monkeypatch):
    ref = reference(monkeypatch, cut)
    monkeypatch.setenv(cache.ENV, str(cache_dir))
    first = cut()
    assert len(entries(cache_dir)) == 1
    assert_same_outline(first, ref)
    hits = cache.STATS["hits"]

    def no_cutting(*a, **k):
        raise AssertionError("recomputed although cached")
    monkeypatch.setattr(teeth_module, "_cut_gear", no_cutting)
    again = cut()
    assert cache.STATS["hits"] == hits + 1
    assert_same_outline(again, ref)


def test_a_hit_returns_the_computed_mesh_check(cache_dir, monkeypatch):
    pair = pitch_pair(lambda p: p / 2, M * (12 + 24) / 2, driving_turns=2)

    def check():
        gt = cut_pair(pair, module=M, teeth=12, backlash=0.1e-3, samples=1536)
        return mesh_check(gt.driving, gt.driven, pair, steps=16)
    ref = reference(monkeypatch, check)
    monkeypatch.setenv(cache.ENV, str(cache_dir))
    first = check()
    names = [p.name.split("-")[0] + "-" + p.name.split("-")[1] for p in entries(cache_dir)]
    assert sorted(names) == ["gear-outline", "gear-outline", "mesh-check"]
    hits = cache.STATS["hits"]
    second = check()
    assert cache.STATS["hits"] == hits + 3
    assert_same_report(first, ref)
    assert_same_report(second, ref)


def test_a_changed_design_misses(cache_dir):
    a = cut()
    misses = cache.STATS["misses"]
    b = cut(backlash=0.2e-3)                       # another backlash
    cut(r=12 * M / 2 * (1 + 1e-12))                # a pitch circle 1e-12 larger
    assert cache.STATS["misses"] == misses + 2
    assert len(entries(cache_dir)) == 3
    assert not np.array_equal(a.xy, b.xy)


def test_entries_of_other_sources_are_not_used(cache_dir, monkeypatch):
    cut()
    monkeypatch.setattr(cache, "_SOURCE_DIGEST", "0" * 64)       # as after an edit of assur/gears
    hits, misses = cache.STATS["hits"], cache.STATS["misses"]
    cut()
    assert (cache.STATS["hits"], cache.STATS["misses"]) == (hits, misses + 1)
    assert len(entries(cache_dir)) == 2


@pytest.mark.parametrize("damage", ["garbage", "truncated", "another key"])
def test_a_corrupt_or_foreign_entry_is_recomputed(cache_dir, monkeypatch, damage):
    ref = reference(monkeypatch, cut)
    monkeypatch.setenv(cache.ENV, str(cache_dir))
    cut()
    (path,) = entries(cache_dir)
    if damage == "garbage":
        path.write_bytes(b"not an npz file")
    elif damage == "truncated":
        path.write_bytes(path.read_bytes()[:1000])
    else:                                          # a whole entry of another design under this name
        cut(backlash=0.3e-3)
        other = next(p for p in entries(cache_dir) if p != path)
        path.write_bytes(other.read_bytes())
    rejected, misses = cache.STATS["rejected"], cache.STATS["misses"]
    assert_same_outline(cut(), ref)
    assert cache.STATS["rejected"] == rejected + 1 and cache.STATS["misses"] == misses + 1
    hits = cache.STATS["hits"]
    assert_same_outline(cut(), ref)                # rewritten: a hit now
    assert cache.STATS["hits"] == hits + 1


def test_off_disables_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, "off")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache.cache_dir() is None
    before = dict(cache.STATS)
    cut()
    cut()
    assert cache.STATS == before
    assert not any(tmp_path.rglob("*"))


def test_where_the_cache_lives(tmp_path, monkeypatch):
    monkeypatch.delenv(cache.ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache.cache_dir() == tmp_path / "xdg" / "assur" / "gears"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert cache.cache_dir() == tmp_path / "home" / ".cache" / "assur" / "gears"
    monkeypatch.setenv(cache.ENV, str(tmp_path / "mine"))
    assert cache.cache_dir() == tmp_path / "mine" / "gears"


def test_writes_are_atomic(cache_dir, monkeypatch):
    ref = reference(monkeypatch, cut)
    monkeypatch.setenv(cache.ENV, str(cache_dir))
    cut()
    d = cache_dir / "gears"
    assert [p.suffix for p in d.iterdir()] == [".npz"]          # no temporary file left behind

    real_savez = np.savez

    def full_disk(fh, **arrays):                 # half an entry written, then the disk is full
        fh.write(b"PK\x03\x04 half an entry")
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(cache.np, "savez", full_disk)
    writes = cache.STATS["writes"]
    other = cut(backlash=0.2e-3)                 # computed and returned although it cannot be stored
    assert cache.STATS["writes"] == writes
    assert [p.suffix for p in d.iterdir()] == [".npz"]          # neither a temporary file nor a partial entry
    monkeypatch.setattr(cache.np, "savez", real_savez)
    monkeypatch.setenv(cache.ENV, "off")
    assert_same_outline(other, cut(backlash=0.2e-3))
    assert_same_outline(ref, cut())


def test_an_unwritable_cache_is_skipped(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the cache directory would be")
    monkeypatch.setenv(cache.ENV, str(blocker))
    ref = reference(monkeypatch, cut)
    monkeypatch.setenv(cache.ENV, str(blocker))
    assert_same_outline(cut(), ref)


def test_the_key_follows_the_sources_and_the_values():
    assert cache.digest(1.0, "a") == cache.digest(1.0, "a")
    assert len({cache.digest(p) for p in (1.0, 1, "1", True, np.float64(1.0).view(np.int64), -0.0, 0.0,
                                          np.zeros(2), np.zeros(2, np.float32), np.zeros((1, 2)), (0.0, 0.0))}) == 11
    assert len(cache.source_digest()) == 64


def test_entries_are_shared_between_processes(cache_dir, monkeypatch):
    """An outline cut by another process is read here, equal to the one computed without the cache."""
    code = ("import numpy as np\nfrom assur.gears.teeth import ToothParameters, cut_gear\n"
            "cut_gear(lambda a: np.full(np.shape(a), 0.012), ToothParameters(module=2e-3, backlash=0.1e-3), 12, "
            "samples=1536)\n")
    subprocess.run([sys.executable, "-c", code], env={**os.environ, cache.ENV: str(cache_dir)}, check=True,
                   cwd=ROOT, timeout=300)
    assert len(entries(cache_dir)) == 1
    ref = reference(monkeypatch, cut)
    monkeypatch.setenv(cache.ENV, str(cache_dir))
    hits = cache.STATS["hits"]
    assert_same_outline(cut(), ref)
    assert cache.STATS["hits"] == hits + 1


@pytest.mark.slow
def test_wheelstep_reuses_the_gear_results_of_another_process(cache_dir, tmp_path):
    """``assur gears`` in one process, ``assur wheelstep`` (same gear file) in another: the second reads every
    outline and mesh check from the cache, computes none, and writes the same gear outputs."""
    env = {**os.environ, cache.ENV: str(cache_dir)}
    subprocess.run([sys.executable, "-m", "assur", "gears", "examples/gears_001.toml", "-o", str(tmp_path / "g"),
                    "--frames", "0"], env=env, cwd=ROOT, check=True, timeout=600, stdout=subprocess.DEVNULL)
    n = len(entries(cache_dir))
    assert n == 2 + 5                      # two outlines; mesh checks: envelope, sectors at 2 distances × 2 scans
    code = ("import sys\nfrom assur.cli.main import main\nfrom assur.gears import cache\n"
            f"assert main(['wheelstep', 'examples/wheelstep_001.toml', '-o', {str(tmp_path / 'w')!r}, "
            "'--frames', '0']) == 0\nprint(cache.STATS['hits'], cache.STATS['misses'], file=sys.stderr)\n")
    run = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, check=True, timeout=600,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, encoding="utf-8")
    assert run.stderr.split()[-2:] == [str(n), "0"]
    assert len(entries(cache_dir)) == n
    for f in ("envelope_driving_outline.csv", "envelope_driven_outline.csv", "envelope_mesh.json",
              "sectors_mesh.json", "summary.json", "envelope_driving.svg"):
        assert (tmp_path / "w" / "gears" / f).read_bytes() == (tmp_path / "g" / f).read_bytes(), f
