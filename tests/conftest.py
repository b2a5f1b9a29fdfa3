"""Shared test data: the mechanism texts several test modules use, and fixtures for them.

The texts are plain functions too (``from conftest import rssr``) because some modules build module-level
constants from them.

Markers (registered in pyproject.toml): ``slow`` marks the seeded optimiser threshold runs, the Dask cluster
and headless-Chromium tests, the reproduction page and anything else over about 5 s; the quick loop is
``pytest -m "not slow"``, ``make test`` runs everything.
"""
import os

from assur.cli.main import _one_blas_thread  # loads no numpy

# One BLAS thread per process, as the command line has (assur.cli.main._one_blas_thread). The test workers run side by
# side on every core, and OpenBLAS's own threads on the small matrices assur multiplies and factorises only spin:
# measured on a 2-core machine, the four-bar leg's joint co-design (budget 300) took 54 s of CPU in 32 s with
# OpenBLAS's default threads and 25 s in 25 s with one. Set before numpy loads OpenBLAS (Makefile's test target sets
# the variables too, for the processes pytest starts first).
_one_blas_thread()

# numba without AVX-512 before any test module imports it (assur/kernels/numba_target.py): a library a test imports
# first (pylinkage) would otherwise fix numba's target with it, and the compiled kernels would not be used.
from assur.kernels.numba_target import configure  # noqa: E402

configure()

from pathlib import Path  # noqa: E402  (after the thread limits)

import pytest  # noqa: E402
from assur.synthesis import InProcess  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

# Text in the tests' files and pipes is UTF-8 whatever the locale (a library may set LC_CTYPE to "C" inside the test
# process, and CI runs without a UTF-8 locale): the test workers and every process a test starts run in UTF-8 mode.
os.environ.setdefault("PYTHONUTF8", "1")

# Property tests draw the same examples on every run (a failure found once is found again, in any order of the
# tests) and have no time limit per example (the machines that run them are shared and often loaded).
try:
    from hypothesis import HealthCheck, settings
except ImportError:                                                      # hypothesis is a test extra
    pass
else:
    settings.register_profile("assur", derandomize=True, deadline=None,
                              suppress_health_check=[HealthCheck.too_slow])
    settings.load_profile("assur")

#: the canonical mechanisms, one shipped file each (compiled on first use by their fixtures, never at import)
CANONICAL = {"fourbar": "crank_rocker.toml", "walking_fourbar": "walker_fourbar.toml",
             "slider_crank": "slider_crank.toml", "rssr": "rssr.toml", "triad_sixbar": "triad_sixbar.toml",
             "geared_leg": "walker_fourbar_geared.toml"}


def compiled_example(name: str):
    """The plan of a shipped example file (``examples/<name>``)."""
    import assur
    return assur.compile(assur.load(EXAMPLES / name))


@pytest.fixture(scope="session")
def fourbar_plan():
    """A Grashof crank-rocker four-bar (examples/crank_rocker.toml)."""
    return compiled_example(CANONICAL["fourbar"])


@pytest.fixture(scope="session")
def walking_fourbar_plan():
    """The four-bar walking leg of paper 004 with its masses (examples/walker_fourbar.toml)."""
    return compiled_example(CANONICAL["walking_fourbar"])


@pytest.fixture(scope="session")
def slider_crank_plan():
    """An offset slider-crank without masses or loads (examples/slider_crank.toml; slider_crank_motor.toml has them)."""
    return compiled_example(CANONICAL["slider_crank"])


@pytest.fixture(scope="session")
def rssr_plan():
    """The spatial RSSR crank-rocker of paper 003 (examples/rssr.toml)."""
    return compiled_example(CANONICAL["rssr"])


@pytest.fixture(scope="session")
def triad_sixbar_plan():
    """A six-bar with a class-III triad, solved by Newton (examples/triad_sixbar.toml)."""
    return compiled_example(CANONICAL["triad_sixbar"])


@pytest.fixture(scope="session")
def geared_leg_plan():
    """The four-bar leg driven through a co-designed non-circular gear pair (examples/walker_fourbar_geared.toml)."""
    return compiled_example(CANONICAL["geared_leg"])

_RSSR_POINTS = {"A0": (0, 0, 0), "D0": (1, 0, 0.3), "A": (0.2, 0.1, 0), "B": (0.9, 0.7, 0.5)}


def rssr(unit: str = "m", scale: float = 1.0, driver: bool = True) -> str:
    """A spatial RSSR crank-rocker (revolutes at A0 and D0, spherical joints at A and B):
    Somov–Malyshev W = 6·3 − 5·2 − 3·2 = 2 (one idle spin of the coupler). Coordinates are the points
    above times ``scale``, written in ``unit``; ``driver`` adds the crank's rotary driver."""
    pts = "\n".join(f"{n} = [{', '.join(f'{c * scale:g}' for c in xyz)}]" for n, xyz in _RSSR_POINTS.items())
    text = f"""
format = "assur/1"
dimension = 3
[units]
length = "{unit}"
angle = "deg"
[points]
{pts}
[links]
frame = ["A0", "D0"]
crank = ["A0", "A"]
coupler = ["A", "B"]
rocker = ["D0", "B"]
[joints]
A = "spherical"
B = "spherical"
"""
    if driver:
        text += '[[drivers]]\nname = "crank"\nlink = "crank"\npivot = "A0"\narm = "A"\n'
    return text


@pytest.fixture
def rssr_text():
    """The :func:`rssr` text builder: ``rssr_text(unit="m", scale=1.0, driver=True) -> str``."""
    return rssr


class InterruptingExecutor(InProcess):
    """A synthesis executor that evaluates in this process, records every population's penalised objectives in
    ``seen`` and raises KeyboardInterrupt (as Ctrl-C would) after ``after`` populations."""

    def __init__(self, after):
        self.seen, self.after = [], after

    def evaluate(self, evaluator, X, detail=False):
        if len(self.seen) >= self.after:
            raise KeyboardInterrupt
        ev = evaluator(X, detail)
        self.seen.append(ev.penalised)
        return ev


def as_from_a_shell():
    """``preexec_fn`` of a child the tests interrupt with SIGINT: Ctrl-C delivered and handled as in a process a shell
    starts (default disposition, not blocked), whatever the test process inherited or set up for its own threads
    (an ignored SIGINT survives exec, and Python then never turns it into KeyboardInterrupt)."""
    import signal
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    signal.signal(signal.SIGINT, signal.SIG_DFL)


# The files whose tests take the longest (measured with `make test` on 2026-12-05, 2 cores: 110–145 s each, the
# next one 35 s) run first. `make test` hands each worker whole files in the order they were collected, so a long file
# collected late ran alone at the end while the other core had nothing left to do (16 min 6 s on that day for 28 min
# of CPU). Within a file the order is the file's own.
LONGEST_FIRST = ("test_install.py", "test_synthesis_defaults.py", "test_codesign_widest.py", "test_parts_make.py",
                 "test_atlas_legs.py", "test_compiled_newton.py")


def pytest_collection_modifyitems(session, config, items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))      # stable: the rest keep their order
