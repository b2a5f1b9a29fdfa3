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
    assert namespace["gait"].step_length > 0
    # the published C2-3 design's objective, docs/papers/synthesis_benchmarks.md §2.2 (f_ref 1.284000744e-06)
    assert abs(namespace["e"].objective[0] - 1.284000744e-06) <= 1e-6 * 1.284000744e-06
    assert namespace["best"].feasible


def test_cli_tour_commands_and_files_exist():
    from assur.cli.main import main
    tour = README.split("## Command line", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
    commands = re.findall(r"^assur (\w+) (\S+)", tour, flags=re.M)
    assert len(commands) >= 7
    for command, path in commands:
        if path.startswith("-"):    # a command without a file (assur atlas --links …)
            continue
        assert (ROOT / path).exists(), path
    # each sub-command is known to the parser: its help returns 0 (an unknown one is a usage error, 2)
    for command in {c for c, _ in commands}:
        assert main([command, "--help"]) == 0
    assert main(["no-such-command"]) == 2
