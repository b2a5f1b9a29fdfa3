"""A plain install runs the README's command-line tour.

A fresh virtual environment, ``pip install <this repository>`` without extras (pip's cache is reused), then every
command of README.md's "Command line" section, as written but with its outputs under tmp_path: each exits 0 and
writes its output (the file or directory it names, or its report on standard output).
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


def test_tour_is_parsed():
    commands = tour_commands()
    assert len(commands) >= 10 and all(c[0] == "assur" for c in commands)
    assert any("out/" in arg for c in commands for arg in c)     # the tour writes under out/, rewritten below


def _rewrite(args: list[str], out: Path) -> tuple[list[str], Path | None]:
    """The outputs moved from out/ to ``out``; the C3 synthesis run's --time shortened from 60 s to 10 s (a plain
    install must run it, not reproduce its result). Returns the arguments and the output path, if any."""
    args = [str(out / a[len("out/"):]) if a.startswith("out/") else a for a in args]
    if "--time" in args:
        args[args.index("--time") + 1] = "10"
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
    p = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
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
    install = subprocess.run([str(py), "-m", "pip", "install", "--quiet", str(ROOT)], capture_output=True, text=True)
    assert install.returncode == 0, install.stderr[-4000:]
    # nothing but the core dependencies: no extra was asked for
    extras = subprocess.run([str(py), "-c", "import importlib.util as u; print([m for m in ('numba', 'cma', 'dask') "
                             "if u.find_spec(m)])"], capture_output=True, text=True)
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
        run = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, timeout=900)
        assert run.returncode == 0, f"{shown}\n{run.stdout[-2000:]}\n{run.stderr[-4000:]}"
        if target is not None:
            assert target.exists(), f"{shown}: no {target}"
            assert target.is_dir() and any(target.iterdir()) or target.is_file() and target.stat().st_size > 0, shown
        else:
            assert run.stdout.strip(), f"{shown}: printed nothing"
    assert sorted(p.name for p in ROOT.iterdir()) == before, "a tour command wrote into the project directory"
