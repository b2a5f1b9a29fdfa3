"""A plain install runs the README's command-line tour.

A fresh virtual environment, ``pip install <this repository>`` without extras (pip's cache is reused), then every
command of README.md's "Command line" section, as written but with its outputs under tmp_path: each exits 0,
writes its output (the file or directory it names, or its report on standard output) and reports something that is
not all zero (:func:`only_zeros`).
"""
import re
import shlex
import subprocess
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def tour_commands() -> list[list[str]]:
    """The README's CLI tour: one argument list per ``assur …`` line, comments dropped."""
    block = README.split("## Command line", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    return [shlex.split(line, comments=True) for line in block.splitlines() if line.startswith("assur ")]


#: JSON keys whose numbers are results of a force analysis (not echoes of the command or the file)
RESULT_KEYS = ("driver", "power", "reaction", "magnitude", "peak", "rms", "torque", "energy", "force")
#: a text line reporting a force-analysis result: a number followed by one of these units
RESULT_LINE = re.compile(r"(-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)\s*(?:N·m|N|W|J|kg·m²)(?:\s|$|\))")


def only_zeros(stdout: str) -> bool:
    """True when a command's output reports results that are all zero: the numbers under the force-analysis keys
    of a JSON answer, or the numbers carrying N, N·m, W or J in a text report (the forces of a file without masses
    or loads). False when it reports no such number or any of them is not zero; the no-loads note counts as zeros."""
    import json
    if "no masses or loads" in stdout:
        return True
    try:
        data = json.loads(stdout)
    except ValueError:
        data = None
    values = []

    def walk(x, under):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, under or any(key in str(k).lower() for key in RESULT_KEYS))
        elif isinstance(x, list):
            for v in x:
                walk(v, under)
        elif under and isinstance(x, (int, float)) and not isinstance(x, bool):
            values.append(float(x))
    if data is not None:
        walk(data, False)
    else:
        values = [float(m.group(1)) for m in RESULT_LINE.finditer(stdout)]
    return bool(values) and all(v == 0 for v in values)


def test_only_zeros_tells_a_loaded_file_from_an_empty_one(capsys):
    """The check of the tour below, on outputs it must tell apart: the forces of the bare slider-crank (every value
    zero) and of paper 004's leg (its steel-bar masses)."""
    from assur.cli.main import main
    for args, zeros in ((["forces", "examples/slider_crank.toml", "--steps", "36"], True),
                        (["forces", "examples/slider_crank.toml", "--at", "30", "--json"], True),
                        (["forces", "examples/walker_fourbar.toml", "--steps", "36"], False),
                        (["forces", "examples/walker_fourbar.toml", "--at", "30", "--at", "90", "--json"], False)):
        assert main([a if not a.startswith("examples/") else str(ROOT / a) for a in args]) == 0
        out = capsys.readouterr().out
        # judged without the note (the output of a version that printed none), then with it
        bare = "\n".join(line for line in out.splitlines() if "no masses or loads" not in line)
        assert only_zeros(bare) == zeros, args
        assert only_zeros(out) == zeros, args


def test_the_tour_force_lines_show_forces(capsys, tmp_path):
    """The README's force lines (run here in-process, quickly) print results that are not all zero (once they used a
    file without masses: 17 rows of 0 N·m, 0 W, 0 J)."""
    from assur.cli.main import main
    lines = [c for c in tour_commands() if c[1] == "forces" or (c[1] == "plot" and "--forces" in c)]
    assert len(lines) >= 3
    for command in lines:
        args, target = _rewrite(command, tmp_path)
        assert main(args[1:]) == 0, command
        out = capsys.readouterr().out
        assert not only_zeros(out), " ".join(command)
        assert target is None or target.stat().st_size > 0


def test_tour_is_parsed():
    commands = tour_commands()
    assert len(commands) >= 10 and all(c[0] == "assur" for c in commands)
    assert any("out/" in arg for c in commands for arg in c)     # the tour writes under out/, rewritten below


#: the tour's effort flags cut to these values at most (a plain install must run each command, not reproduce its
#: result: the README's figures are checked by their own tests): the synthesis time limit (s), the evaluation
#: budgets, the Monte Carlo draws, the walking legs ranked, the designs of the window ranking's widening search (its
#: default, 450, where the command leaves it out), the evaluations of a synthesis problem's report (the problem's own
#: budget where the command leaves it out: 37 320 evaluations, 15 s, on a plain install for motion_three_poses)
EFFORT_CAPS = {"--time": 3, "--budget": 1000, "--monte-carlo": 2000, "--limit": 1, "--window-budget": 50}


def _rewrite(args: list[str], out: Path) -> tuple[list[str], Path | None]:
    """The outputs moved from out/ to ``out``; the effort flags cut to :data:`EFFORT_CAPS`. Returns the arguments
    and the output path, if any."""
    args = [str(out / a[len("out/"):]) if a.startswith("out/") else a for a in args]
    if "--rank" in args and args[args.index("--rank") + 1] == "window" and "--window-budget" not in args:
        args += ["--window-budget", "450"]
    if args[1] == "report" and "synthesis" in Path(args[2]).parts and "--budget" not in args:
        args += ["--budget", "1000000"]
    for flag, cap in EFFORT_CAPS.items():
        if flag in args:
            i = args.index(flag) + 1
            args[i] = str(min(float(args[i]), cap)).removesuffix(".0")
    target = None
    for flag in ("-o", "--output", "--csv", "--plot"):
        if flag in args:
            target = Path(args[args.index(flag) + 1])
    return args, target


def _check_design_server(args, shown) -> None:
    import re
    import signal
    import urllib.request
    if "--no-browser" not in args:       # the test machine has no screen to open a browser on
        args = [*args, "--no-browser"]
    p = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding="utf-8")
    try:
        line = p.stdout.readline()
        url = re.search(r"http://127\.0\.0\.1:\d+/\?token=\S+", line)
        assert url, f"{shown}: printed {line!r}"
        with urllib.request.urlopen(url.group(0), timeout=60) as r:
            assert r.status == 200 and b'type="module"' in r.read(), shown
    finally:
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    assert p.returncode == 0, f"{shown}\n{err[-4000:]}"


@pytest.mark.slow
def test_plain_install_runs_the_cli_tour(tmp_path):
    env_dir = tmp_path / "venv"
    venv.EnvBuilder(with_pip=True).create(env_dir)
    py = env_dir / "bin" / "python"
    install = subprocess.run([str(py), "-m", "pip", "install", "--quiet", str(ROOT)], capture_output=True, encoding="utf-8")
    assert install.returncode == 0, install.stderr[-4000:]
    # nothing but the core dependencies: no extra was asked for
    extras = subprocess.run([str(py), "-c", "import importlib.util as u; print([m for m in ('numba', 'cma', 'dask') "
                             "if u.find_spec(m)])"], capture_output=True, encoding="utf-8")
    assert extras.stdout.strip() == "[]"
    out = tmp_path / "out"
    out.mkdir()
    before = sorted(p.name for p in ROOT.iterdir())      # the tour writes only under out/: nothing in the project
    for command in tour_commands():
        args, target = _rewrite(command, out)
        args[0] = str(env_dir / "bin" / "assur")
        shown = " ".join(command)
        if command[1] == "design":      # a server: it must print its URL and serve the page, then stop on Ctrl-C
            _check_design_server(args, shown)
            continue
        run = subprocess.run(args, cwd=ROOT, capture_output=True, encoding="utf-8", timeout=900)
        assert run.returncode == 0, f"{shown}\n{run.stdout[-2000:]}\n{run.stderr[-4000:]}"
        if target is not None:
            assert target.exists(), f"{shown}: no {target}"
            assert target.is_dir() and any(target.iterdir()) or target.is_file() and target.stat().st_size > 0, shown
        else:
            assert run.stdout.strip(), f"{shown}: printed nothing"
        assert not only_zeros(run.stdout), f"{shown}: prints only zeros"
    assert sorted(p.name for p in ROOT.iterdir()) == before, "a tour command wrote into the project directory"
