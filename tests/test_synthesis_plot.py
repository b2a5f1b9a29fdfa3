"""Synthesis results a person can judge: ``assur synth … --plot`` (the task against the best design, the
per-target distances, the convergence history) and ``assur report PROBLEM.toml`` (the synthesis page)."""
import json
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.synthesis import load_problem, synthesize

ROOT = Path(__file__).resolve().parents[1]
SYN = ROOT / "examples" / "synthesis"
FUNCTION = SYN / "function_fourbar.toml"
MOTION = SYN / "motion_three_poses.toml"
P000 = SYN / "paper000_six_points.toml"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def test_cli_plot_writes_a_png_and_json_records_the_history(tmp_path, capsys):
    out = tmp_path / "best.png"
    code = main(["synth", str(FUNCTION), "--seed", "1", "--budget", "400", "--plot", str(out), "--json"])
    assert code == 0
    d = json.loads(capsys.readouterr().out)
    assert d["plot"] == str(out)
    data = out.read_bytes()
    assert data.startswith(PNG_MAGIC)
    import matplotlib.image as mpimg
    img = mpimg.imread(out)
    assert img.shape[0] > 300 and img.shape[1] > 1000          # three panels side by side
    assert img[..., :3].std() > 0.05                            # not a blank canvas
    # the convergence history: evaluations increase, the best value never rises
    h = np.array(d["history"])
    assert len(h) > 1 and np.all(np.diff(h[:, 0]) > 0) and np.all(np.diff(h[:, 2]) <= 0)
    assert h[-1, 0] == d["evaluations"]


def test_plot_option_checks_the_extension_and_the_directory(tmp_path, capsys):
    assert main(["synth", str(FUNCTION), "--plot", str(tmp_path / "best.gif")]) == 2
    assert main(["synth", str(FUNCTION), "--budget", "50", "--plot", str(tmp_path / "missing" / "b.png")]) == 1
    assert "error:" in capsys.readouterr().err


@pytest.mark.parametrize("path", [P000, MOTION, FUNCTION], ids=lambda p: p.stem)
def test_the_figure_draws_the_files_targets(path):
    """Panel (a) holds the problem file's own targets (read here from the TOML, in its units); panel (b) one bar
    per target; panel (c) the run's history."""
    from assur.io.toml_reader import read_toml
    from assur.plot.draw import close
    from assur.plot.synthesis import synthesis_figure
    doc = read_toml(path)
    r = synthesize(load_problem(path), seed=2, budget=300, polish="none")
    fig = synthesis_figure(r)
    try:
        task, bars, hist = fig.axes[:3]
        t = doc["targets"]
        want = (np.array(t["pairs"]) if "pairs" in t else np.array(t.get("xy", t.get("poses")))[:, :2])
        found = [ln for ln in task.get_lines() if ln.get_label() in ("targets", "target pairs")]
        assert len(found) == 1
        xy = np.c_[found[0].get_xdata(), found[0].get_ydata()]
        if "pairs" in t:   # inputs: the uniform start plus the pairs' spacing; outputs as given
            assert np.allclose(np.diff(xy[:, 0]), np.diff(want[:, 0]), atol=1e-6)
            assert np.allclose(xy[:, 1], want[:, 1], atol=1e-9)
        else:
            assert np.allclose(xy, want, atol=1e-9)
        assert len(bars.patches) == len(want)
        assert len(hist.get_lines()) >= 1
    finally:
        close(fig)


def test_report_of_a_problem_file_writes_the_synthesis_page(tmp_path, capsys):
    out = tmp_path / "page"
    assert main(["report", str(FUNCTION), "-o", str(out), "--budget", "300", "--seed", "3"]) == 0
    assert "wrote" in capsys.readouterr().out
    html = (out / "index.html").read_text(encoding="utf-8")
    for words in ("Problem", "Best design", "Figures", "crank.length", "phi0", "defects", "best.toml"):
        assert words in html
    assert html.count("<img") >= 2
    assert 'src="http' not in html                             # self-contained: figures inlined
    best = assur.load(out / "best.toml")                        # the best design as a mechanism file
    assert assur.compile(best).n_inputs == 1


def test_report_options_for_a_problem_only(tmp_path, capsys):
    assert main(["report", str(ROOT / "examples" / "crank_rocker.toml"), "-o", str(tmp_path / "r"),
                 "--seed", "1"]) == 1
    assert "--seed" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()
