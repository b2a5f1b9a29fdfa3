"""Command start-up imports what the command needs: ``assur --version`` and ``assur validate`` load no integrator,
no optimiser, no plotting library and no compiler (each costs a large part of a second to import).

Each command runs in a fresh interpreter (the modules a test process already holds would hide an import), and the
test lists the modules loaded when the command has finished.
"""
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
#: modules a light command must not load (and everything below them)
HEAVY = ("scipy.integrate", "scipy.optimize", "matplotlib", "numba")

_PROBE = """
import contextlib, io, json, sys
from assur.cli.main import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    try:
        code = main(sys.argv[1:])
    except SystemExit as exc:
        code = exc.code
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def _modules_after(*argv) -> tuple[int, list[str]]:
    r = subprocess.run([sys.executable, "-c", _PROBE, *argv], capture_output=True, encoding="utf-8", timeout=300, cwd=ROOT)
    assert r.returncode == 0, r.stderr[-3000:]
    d = json.loads(r.stdout.strip().splitlines()[-1])
    return d["code"], d["modules"]


def _heavy(modules) -> list[str]:
    return [m for m in modules if any(m == h or m.startswith(h + ".") for h in HEAVY)]


def test_version_imports_nothing_heavy():
    code, modules = _modules_after("--version")
    assert code == 0
    assert _heavy(modules) == []


# a planar file with masses and actuators, a spatial one, a walking leg with a gait block: validate loads and
# compiles each without the heavy modules (a file with a [[gears]] law builds its spline with scipy.interpolate,
# which imports scipy.optimize itself: not listed here)
@pytest.mark.parametrize("name", ["jansen.toml", "lever_manipulator.toml", "rssr.toml", "walker_fourbar.toml"])
def test_validate_imports_nothing_heavy(name):
    code, modules = _modules_after("validate", str(EXAMPLES / name))
    assert code == 0
    assert "assur.engine.api" in modules          # the file was compiled, not only read
    assert _heavy(modules) == []
