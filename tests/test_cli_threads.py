"""A command runs with one BLAS thread (assur.cli.main._one_blas_thread) unless the user set a number: checked in
fresh processes, where numpy is not loaded before the command starts."""
import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

from assur.cli.main import BLAS_THREAD_VARIABLES as VARIABLES

ROOT = Path(__file__).resolve().parents[1]
#: run a command, then print the variables and, where threadpoolctl is installed, OpenBLAS's thread counts
PROGRAM = """
import os, sys
from assur.cli.main import main
assert main(["validate", sys.argv[1]]) == 0
import numpy  # noqa: F401  (OpenBLAS loaded, after the command set its variables)
try:
    import threadpoolctl
except ImportError:
    pools = []
else:
    pools = [p["num_threads"] for p in threadpoolctl.threadpool_info() if p.get("internal_api") == "openblas"]
import json
print("RESULT " + json.dumps([[os.environ.get(v) for v in %r], pools]))
""" % (VARIABLES,)


def _run(env_changes: dict) -> list:
    """[the variables after the command, OpenBLAS's thread counts (empty without threadpoolctl)]."""
    env = {k: v for k, v in os.environ.items() if k not in VARIABLES} | env_changes
    out = subprocess.run([sys.executable, "-c", PROGRAM, str(ROOT / "examples" / "jansen.toml")], env=env,
                         capture_output=True, encoding="utf-8", check=True).stdout
    return json.loads(next(line for line in out.splitlines() if line.startswith("RESULT "))[len("RESULT "):])


def test_a_command_runs_with_one_blas_thread():
    variables, pools = _run({})
    assert variables == ["1", "1", "1"]
    assert all(n == 1 for n in pools)
    assert pools or not importlib.util.find_spec("threadpoolctl")


def test_a_thread_count_the_user_set_is_kept():
    variables, pools = _run({"OPENBLAS_NUM_THREADS": "2"})
    assert variables == ["2", "1", "1"]
    assert all(n == 2 for n in pools)
