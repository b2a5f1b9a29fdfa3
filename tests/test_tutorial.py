"""docs/tutorial.md runs as written: its files are written into an empty directory, every ``assur`` command of its
``sh`` blocks runs there and exits 0, and the lines of each ``text`` block (what the command before it "prints")
appear in that command's output. The tutorial's check by hand — the energy per cycle is the load's work — is
recomputed here from the engine's rocker angles."""
import math
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
TUTORIAL = (ROOT / "docs" / "tutorial.md").read_text(encoding="utf-8")
BLOCK = re.compile(r"```(\w+)\n(.*?)```", flags=re.S)


def _blocks():
    return [(m.group(1), m.group(2)) for m in BLOCK.finditer(TUTORIAL)]


def _normal(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def test_the_tutorial_has_its_files_and_commands():
    blocks = _blocks()
    files = [b for kind, b in blocks if kind == "toml"]
    assert [b.splitlines()[0] for b in files] == ["# file: first.toml", "# file: first_loaded.toml"]
    commands = [line for kind, b in blocks if kind == "sh" for line in b.splitlines() if line.strip()]
    assert len(commands) >= 8 and all(c.startswith("assur ") for c in commands)
    for sub in ("validate", "info", "analyze", "plot", "forces", "report"):
        assert any(c.split()[1] == sub for c in commands), sub


@pytest.mark.slow
def test_every_command_of_the_tutorial_runs_and_prints_what_it_says(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "out").mkdir()
    last = None
    for kind, body in _blocks():
        if kind == "toml":
            name = body.splitlines()[0].removeprefix("# file: ").strip()
            (tmp_path / name).write_text(body, encoding="utf-8")
        elif kind == "sh":
            for line in filter(str.strip, body.splitlines()):
                code = main(shlex.split(line, comments=True)[1:])
                out, err = capsys.readouterr()
                assert code == 0, f"{line}\n{out}\n{err}"
                last = (line, _normal(out))
        elif kind == "text":
            line, out = last
            for quoted in filter(str.strip, body.splitlines()):
                assert _normal(quoted) in out, f"{line} does not print {quoted!r}"
    for path in ("out/first.png", "out/first_forces.png", "out/first/index.html"):
        assert (tmp_path / path).stat().st_size > 0, path
    # the energy per cycle (the tutorial's figure) is the work of the 20 N load along B's arc: twice the rocker's
    # swing times its length, with the swing from the engine's solution over a fine turn
    plan = assur.compile(assur.load(tmp_path / "first_loaded.toml"))
    st = assur.solve(plan, inputs=np.linspace(0, 2 * math.pi, 20001), order=0)
    B, C = st.point("B").pos, np.array(plan.mechanism.sketch("C"))
    psi = np.arctan2(B[:, 1] - C[1], B[:, 0] - C[0])
    work = 20.0 * 2 * np.ptp(psi) * np.hypot(*(B[0] - C))
    quoted = float(re.search(r"energy per cycle\s+([\d.]+) J", TUTORIAL).group(1))
    assert quoted == pytest.approx(work, rel=1e-3)
