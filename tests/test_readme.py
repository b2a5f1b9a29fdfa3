"""The README's Python tour runs as written, and its CLI tour names real sub-commands and files."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


@pytest.mark.slow
def test_python_tour_runs(monkeypatch):
    code = README.split("## Python API", 1)[1].split("```python", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(ROOT)
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    assert namespace["batch"].pos.shape[:2] == (1000, 360)
    study = namespace["study"]
    assert study.gait.step_length > 0 and study.four_bars[0].kind == "crank-rocker"
    assert study.as_dict()["gait"]["step_length"] == study.gait.step_length
    # the published C2-3 design's objective, docs/papers/synthesis_benchmarks.md §2.2 (f_ref 1.284000744e-06)
    assert abs(namespace["e"].objective[0] - 1.284000744e-06) <= 1e-6 * 1.284000744e-06
    assert namespace["best"].feasible


def test_cli_tour_commands_and_files_exist():
    from assur.cli.main import main
    tour = README.split("## Command line", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    commands = re.findall(r"^assur (\w+) (\S+)", tour, flags=re.M)
    assert len(commands) >= 7
    lines = [line for line in tour.splitlines() if line.startswith("assur ")]
    for command, path in commands:
        if path.startswith("-"):    # a command without a file (assur atlas --links …)
            continue
        # a file an earlier tour line writes (assur export … out/x.pmks, then assur import out/x.pmks)
        written = any(path in line.split()[3:] for line in lines[:next(i for i, line in enumerate(lines)
                                                                          if line.startswith(f"assur {command} {path}"))])
        assert (ROOT / path).exists() or written, path
    # each sub-command is known to the parser: its help returns 0 (an unknown one is a usage error, 2)
    for command in {c for c, _ in commands}:
        assert main([command, "--help"]) == 0
    assert main(["no-such-command"]) == 2
