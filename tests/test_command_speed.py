"""Everyday commands: an animation's frames are drawn once each, by blitting, with the pixels of a full redraw;
progress of the slow steps on a terminal only; one line when a kernel is compiled for a new mechanism."""
from __future__ import annotations

import base64
import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.plot.animation import animation, jshtml, save_animation
from assur.plot.draw import close

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
KLANN = EXAMPLES / "klann.toml"            # ternary links, sliders-free, labels: every artist kind of a frame
SLIDER = EXAMPLES / "slider_crank.toml"


def _png_frames(text: str) -> list:
    from PIL import Image
    data = re.findall(r"data:image/png;base64,([^\"]*)\"", text.replace("\\\n", ""))
    return [np.asarray(Image.open(io.BytesIO(base64.b64decode(b)))) for b in data]


@pytest.mark.parametrize("size,dpi", [((6.4, 6.4), 100), ((5.6, 5.6), 72)])   # 403.2 px: the writers' even resize
def test_blitted_frames_are_the_pixels_of_a_full_redraw(size, dpi):
    plan = assur.compile(assur.load(KLANN))
    fig, ref_anim = animation(plan, 3, 12, figsize=size, dpi=dpi)
    reference = _png_frames(ref_anim.to_jshtml(fps=12))   # matplotlib's own save: a full draw per frame
    close(fig)
    fig, anim = animation(plan, 3, 12, figsize=size, dpi=dpi)
    frames = _png_frames(jshtml(anim, 12))
    close(fig)
    assert len(frames) == len(reference) == 3
    for got, want in zip(frames, reference):
        assert got.shape == want.shape
        assert np.array_equal(got, want)


@pytest.mark.parametrize("ext", [".gif", ".html", ".mp4"])
def test_saving_draws_the_figure_once(tmp_path, ext):
    """matplotlib's Animation.save draws the whole figure twice per frame; blitting draws it once in all."""
    if ext == ".mp4":
        pytest.importorskip("imageio_ffmpeg")
    plan = assur.compile(assur.load(KLANN))
    n = 6
    fig, anim = animation(plan, n, 12)
    draws = []
    fig.canvas.mpl_connect("draw_event", lambda event: draws.append(1))
    seen = []
    save_animation(anim, tmp_path / f"a{ext}", fps=12, progress=lambda i, k: seen.append((i, k)))
    close(fig)
    assert len(draws) == 1
    assert seen == [(i, n) for i in range(n)]
    data = (tmp_path / f"a{ext}").read_bytes()
    if ext == ".gif":
        from PIL import Image
        with Image.open(tmp_path / "a.gif") as im:
            assert im.n_frames == n and im.size == (640, 640)
    elif ext == ".mp4":
        assert data[4:8] == b"ftyp"
    else:
        assert len(_png_frames(data.decode("utf-8"))) == n


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_on_a_terminal_only(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)          # the plain-text fallback
    term = _Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    assert main(["animate", str(SLIDER), "-o", str(tmp_path / "a.gif"), "--frames", "2"]) == 0
    assert "frames 2/2\n" in term.getvalue()
    monkeypatch.undo()
    assert main(["animate", str(SLIDER), "-o", str(tmp_path / "b.gif"), "--frames", "2"]) == 0
    assert capsys.readouterr().err == ""                     # captured (not a terminal): nothing extra


def test_report_shows_the_animation_progress(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    term = _Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    assert main(["report", str(SLIDER), "-o", str(tmp_path / "rep"), "--steps", "36", "--frames", "3"]) == 0
    assert "animation frames 3/3\n" in term.getvalue()


@pytest.mark.slow
@pytest.mark.parametrize("numba_cache_dir", [False, True])
def test_compile_is_announced_once(tmp_path, numba_cache_dir):
    """With NUMBA_CACHE_DIR set, numba keeps its index there, not beside the kernels: the second run knows it too."""
    pytest.importorskip("numba")
    env = {**os.environ, "ASSUR_CACHE_DIR": str(tmp_path)}
    env.pop("NUMBA_CACHE_DIR", None)
    if numba_cache_dir:
        env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba")
    # a synthesis asked to run compiled compiles the problem's kernels once, says so and what it cost
    problem = Path(__file__).resolve().parents[1] / "examples" / "synthesis" / "c2_five_points_timed.toml"
    cmd = [sys.executable, "-m", "assur", "synth", str(problem), "--backend", "numba", "--budget", "400", "--seed", "1",
           "--polish", "none", "--quiet"]
    line = f"compiling a kernel for this mechanism (once, cached in {tmp_path / 'kernels'})"
    first = subprocess.run(cmd, env=env, capture_output=True, encoding="utf-8", check=True)
    assert first.stderr.count(line) >= 1, first.stderr
    assert first.stderr.count("compiled it in ") == first.stderr.count(line)
    second = subprocess.run(cmd, env=env, capture_output=True, encoding="utf-8", check=True)
    assert "compil" not in second.stderr
    strip = [ln for ln in first.stdout.splitlines() if "wall time" not in ln]
    assert strip == [ln for ln in second.stdout.splitlines() if "wall time" not in ln]   # the same numbers
