"""Every command fails cleanly: one ``error: …`` line on stderr and the documented exit status (1 bad input or a
missing optional package, 2 usage, 3 no feasible synthesis, 130 interrupted), Ctrl-C included from the first
import on, an interrupted synthesis included; gear designs whose distances or module cannot mesh are refused
with their location before the long computation."""
import json
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import assur
from conftest import InterruptingExecutor, as_from_a_shell
from assur.cli.main import build_parser, main
from assur.errors import GearError, MissingPackageError, SpecError
from assur.synthesis import Evaluator, InProcess, load_problem

ROOT = Path(__file__).resolve().parents[1]
FOURBAR = ROOT / "examples" / "walker_fourbar.toml"
C2 = ROOT / "examples" / "synthesis" / "c2_five_points_timed.toml"
GEARS = ROOT / "examples" / "gears_001.toml"

# A sitecustomize module that delivers SIGINT to its own process the first time anything looks for numpy — the
# first heavy import of every command — so Ctrl-C arrives deterministically while the start-up imports run.
SIGINT_AT_FIRST_HEAVY_IMPORT = textwrap.dedent("""
    import os, signal, sys

    class _CtrlC:
        fired = False

        @classmethod
        def find_spec(cls, name, path=None, target=None):
            if name == "numpy" and not cls.fired:
                cls.fired = True
                os.kill(os.getpid(), signal.SIGINT)
            return None

    sys.meta_path.insert(0, _CtrlC)
""")


def _run_with_early_sigint(cmd, tmp_path):
    (tmp_path / "sitecustomize.py").write_text(SIGINT_AT_FIRST_HEAVY_IMPORT, encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(tmp_path)}
    return subprocess.run(cmd, capture_output=True, encoding="utf-8", env=env, timeout=120, cwd=ROOT,
                          preexec_fn=as_from_a_shell)


@pytest.mark.parametrize("how", ["python -m assur", "assur script"])
def test_ctrl_c_during_start_up_exits_130_with_one_line(how, tmp_path):
    if how == "python -m assur":
        cmd = [sys.executable, "-m", "assur", "validate", str(FOURBAR)]
    else:
        script = Path(sys.executable).parent / "assur"
        if not script.exists():
            pytest.skip("the assur console script is not installed next to this interpreter")
        cmd = [sys.executable, str(script), "validate", str(FOURBAR)]
    r = _run_with_early_sigint(cmd, tmp_path)
    import signal
    assert r.returncode == 130, (r.stderr, "this process's SIGINT:", signal.getsignal(signal.SIGINT),
                                 signal.pthread_sigmask(signal.SIG_BLOCK, []))
    assert r.stderr == "error: interrupted\n"
    assert r.stdout == ""


def test_the_start_up_guard_does_not_change_a_normal_run(tmp_path):
    # the same environment without the signal: the command runs (the hook itself is harmless)
    (tmp_path / "sitecustomize.py").write_text("", encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(tmp_path)}
    r = subprocess.run([sys.executable, "-m", "assur", "validate", str(FOURBAR)], capture_output=True, encoding="utf-8",
                       env=env, timeout=120, cwd=ROOT)
    assert r.returncode == 0, r.stderr


def test_import_assur_is_light():
    """Ctrl-C can only be caught once the entry function runs: ``import assur`` and the CLI module must not import
    numpy (the public names load on first use)."""
    code = "import sys, assur, assur.cli.main; print('numpy' in sys.modules)"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, encoding="utf-8", timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "False"
    assert assur.compile is assur.engine.compile and assur.SpecError is SpecError
    with pytest.raises(AttributeError):
        assur.no_such_name  # noqa: B018


def test_help_describes_the_whole_tool(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out.lower()
    for topic in ("structural", "kinematic", "spatial", "synthesis", "gear", "wheel-step", "exit status", "130"):
        assert topic in out, topic
    assert "analysis of planar mechanisms" not in out


# -- synthesis: Ctrl-C, missing optional packages ----------------------------------------------------------


@pytest.mark.parametrize("json_out", [False, True])
def test_interrupted_synth_exits_130_and_writes_the_best_design(json_out, tmp_path, monkeypatch, capsys):
    import assur.synthesis
    ex = InterruptingExecutor(after=5)
    monkeypatch.setattr(assur.synthesis, "make_executor", lambda workers, dask: ex)
    best = tmp_path / "best.toml"
    argv = ["synth", str(C2), "--seed", "3", "--budget", "1000000", "--polish", "none", "-o", str(best)]
    code = main(argv + (["--json"] if json_out else []))
    out, err = capsys.readouterr()
    assert code == 130
    err = without_compile_notes(err)          # an empty kernel cache adds "compiling a kernel …" lines first
    assert err.count("\n") == 1 and err.startswith("error: interrupted") and str(best) in err
    assert best.exists()
    plan = assur.compile(assur.load(best))           # the written design is a working mechanism file
    assert plan.n_inputs == 1
    if json_out:
        d = json.loads(out)
        assert d["stopped"] == "interrupted" and d["written"] == str(best)
        p = load_problem(C2)
        x = p.to_si([[d["variables"][n] for n in p.names]])
        best_seen = min(F.min() for F in ex.seen)     # the best of everything evaluated before Ctrl-C
        assert Evaluator(p)(x).penalised[0] == pytest.approx(best_seen, rel=1e-9)
    else:
        assert "stopped: interrupted" in out and f"wrote {best}" in out


def without_compile_notes(err: str) -> str:
    """Standard error without the compiled backend's notes (two lines each time it compiles a kernel for a new
    mechanism, before and after: with an empty ``ASSUR_CACHE_DIR``, on the first use of every mechanism)."""
    return "".join(line for line in err.splitlines(keepends=True)
                   if not line.startswith(("compiling a ", "compiled it in ")))


def _no_work(monkeypatch):
    """Make loading a problem or running a synthesis fail the test: nothing may start before the package check."""
    import assur.synthesis

    def forbidden(*a, **k):
        raise AssertionError("the work started before the missing package was reported")
    monkeypatch.setattr(assur.synthesis, "load_problem", forbidden)
    monkeypatch.setattr(assur.synthesis, "synthesize", forbidden)
    monkeypatch.setattr(assur.synthesis, "make_executor", forbidden)


def test_cmaes_without_cma_says_how_to_install_before_any_work(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "cma", None)          # `import cma` now fails as if it were not installed
    _no_work(monkeypatch)
    assert main(["synth", str(C2), "--method", "cmaes", "--budget", "100"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: --method cmaes needs the optional package 'cma'")
    assert "pip install cma" in err


def test_dask_without_distributed_says_how_to_install_before_any_work(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)
    _no_work(monkeypatch)
    assert main(["synth", str(C2), "--dask", "tcp://127.0.0.1:9"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--dask needs the optional package 'distributed'" in err
    assert "pip install 'dask[distributed]'" in err


def test_synthesize_cmaes_without_cma_raises_before_evaluating(monkeypatch):
    from assur.synthesis import synthesize
    monkeypatch.setitem(sys.modules, "cma", None)
    ex = InterruptingExecutor(after=10 ** 9)
    with pytest.raises(MissingPackageError, match="pip install cma"):
        synthesize(load_problem(C2), "cmaes", seed=1, budget=100, executor=ex)
    assert ex.seen == []


def test_missing_tqdm_is_a_note_not_a_failure(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)   # a terminal: the progress bar would be shown
    code = main(["synth", str(C2), "--seed", "1", "--budget", "300", "--polish", "none"])
    err = capsys.readouterr().err
    assert code in (0, 3)
    assert "note: no progress bar without the optional package 'tqdm'" in err and "pip install tqdm" in err


# -- gear designs that cannot mesh -------------------------------------------------------------------------
def _mutant(tmp_path, old, new):
    text = GEARS.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "gears.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def _problems(path):
    from assur.io.gear_file import load_design
    with pytest.raises(SpecError) as info:
        load_design(path)
    return dict(info.value.problems)


def test_installation_distance_beyond_the_working_depth_is_refused(tmp_path, capsys):
    # working depth = 2 addenda = 2·1·m = 4 mm for module 2 (addendum coefficient 1): the teeth of two gears can
    # only touch while the centre distance stays within it of the one they were laid out for (143.5 mm)
    from assur.io.gear_file import load_design
    assert load_design(_mutant(tmp_path, "installation_distance = 144 ", "installation_distance = 147.4 "))
    assert load_design(_mutant(tmp_path, "installation_distance = 144 ", "installation_distance = 139.6 "))
    for bad in ("147.6", "139.4", "400"):
        problems = _problems(_mutant(tmp_path, "installation_distance = 144 ", f"installation_distance = {bad} "))
        assert "working depth" in problems["pair.installation_distance"]
    out = tmp_path / "out"
    assert main(["gears", str(tmp_path / "gears.toml"), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "pair.installation_distance" in err and "Traceback" not in err
    assert not out.exists()


def test_centre_distance_that_forces_a_huge_module_is_refused(tmp_path):
    # the sector scheme carries one tooth per sector: π·m must match the sector arc, and the arc grows with L
    # (a thousand times L → a thousand times the arc, far from π·2 mm)
    problems = _problems(_mutant(tmp_path, "centre_distance = 143.5", "centre_distance = 143500"))
    assert "does not fit the sectors" in problems["teeth.module"]
    assert "centre_distance" in problems["teeth.module"]


def test_sector_module_must_match_the_sector_arc(tmp_path):
    from assur.gears.design import SECTOR_PITCH_TOLERANCE
    from assur.io.gear_file import load_design
    s = load_design(GEARS).sector_model().arc                # the sector arc of the paper's design, m
    assert s == pytest.approx(6.2123e-3, abs=1e-7)           # paper 001 (docs/reproduction.md): s = 6.2123 mm
    # the bound is on s / (π·m) − 1: a module just inside it is accepted, one just outside refused
    ok = s / (math.pi * (1 - 0.9 * SECTOR_PITCH_TOLERANCE)) * 1e3
    bad = s / (math.pi * (1 - 1.1 * SECTOR_PITCH_TOLERANCE)) * 1e3
    assert load_design(_mutant(tmp_path, "module = 2\n", f"module = {ok:.6f}\n"))
    for m in (f"{bad:.6f}", "20", "0.5"):
        assert "does not fit the sectors" in _problems(_mutant(tmp_path, "module = 2\n", f"module = {m}\n"))[
            "teeth.module"]


def test_mesh_check_of_gears_that_do_not_reach_each_other_is_a_gear_error():
    import dataclasses

    from assur.io.gear_file import load_design
    from assur.gears.mesh import mesh_check
    pair = load_design(GEARS).pair(samples=512)
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    circle = np.column_stack([np.cos(t), np.sin(t)]) * 0.05   # two 50 mm discs 1 m apart cannot touch
    with pytest.raises(GearError, match="do not reach each other"):
        mesh_check(circle, circle, dataclasses.replace(pair, centre_distance=1.0), steps=8, pitch=math.pi * 2e-3)

