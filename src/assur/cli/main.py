"""The ``assur`` command line: the parser and the dispatch to the commands of
:mod:`assur.cli.mechanism` (validate, info, solve, analyze, plot, animate, report), :mod:`assur.cli.forces`
(forces), :mod:`assur.cli.synth`
(synth), :mod:`assur.cli.gears` (gears, wheelstep), :mod:`assur.cli.exchange` (import, export),
:mod:`assur.cli.sensitivity` (sensitivity), :mod:`assur.cli.cams` (cam), :mod:`assur.cli.simulate` (simulate) and
:mod:`assur.cli.make` (make).

Every failure prints one line starting with ``error:`` to stderr and exits with its status: 1 bad input (an
invalid file, a structure that cannot be solved, a missing file or optional package, an output that cannot be
written), 2 usage errors (argparse), 3 a synthesis that found no feasible design, 130 interrupted (Ctrl-C, also
during start-up: this module imports nothing heavy, the commands load inside :func:`main`'s guard). Heavy modules
(matplotlib) are imported only by the commands that draw.
"""
from __future__ import annotations

import contextlib
import os
import sys

DESCRIPTION = ("Structural and kinematic analysis and synthesis of mechanisms described in TOML files: "
               "mobility and Assur groups, positions, velocities and accelerations of planar and spatial "
               "linkages, transmission angles and dead centres, walking-leg gait, linear actuators, plots, "
               "animations and HTML reports (format assur/1); dimensional synthesis (assur-synth/1); "
               "non-circular gear pairs with teeth (assur-gears/1) and the wheel-step mover (assur-wheelstep/1).")
EPILOG = ("exit status: 0 done, 1 bad input (one 'error: ...' line), 2 usage error, 3 synthesis found no feasible "
          "design, 130 interrupted (Ctrl-C; an interrupted synthesis still writes its best design with -o)")

#: the exit status of an interrupted command (128 + SIGINT, as a shell reports it)
INTERRUPTED = 130


def build_parser():
    """The parser of every command."""
    import argparse

    from ..version import __version__
    from . import atlas, cams, codesign, design, exchange, forces, gears, make, mechanism, sensitivity, simulate, synth
    p = argparse.ArgumentParser(prog="assur", description=DESCRIPTION, epilog=EPILOG)
    p.add_argument("--version", action="version", version=f"assur {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)
    mechanism.register(sub)
    forces.register(sub)
    sensitivity.register(sub)
    cams.register(sub)
    synth.register(sub)
    gears.register(sub)   # `assur gears` and `assur wheelstep`
    codesign.register(sub)
    design.register(sub)
    atlas.register(sub)
    exchange.register(sub)   # `assur import` and `assur export`
    simulate.register(sub)
    make.register(sub)
    return p


def format_error(exc: BaseException) -> str:
    """The one-line message of a failed command."""
    return f"error: {exc}"


def _run(argv) -> int:
    from ..errors import AssurError
    from .progress import announce_compiles
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help/--version (0)
        return int(exc.code) if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    try:
        with announce_compiles():    # one line on stderr when a kernel is compiled for a new mechanism
            return int(args.func(args) or 0)
    except AssurError as exc:
        print(format_error(exc), file=sys.stderr)
        return 1
    except ImportError as exc:   # an optional dependency (e.g. imageio-ffmpeg for MP4)
        print(format_error(exc), file=sys.stderr)
        return 1
    except BrokenPipeError:      # e.g. `assur analyze --json f | head`: the reader took what it wanted
        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:       # an output cannot be written
        name = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"error: cannot write{name}: {exc.strerror or exc}", file=sys.stderr)
        return 1


def _utf8_streams() -> None:
    """Standard output and error in UTF-8 where the locale says ASCII (``LC_ALL=C`` in a container or a CI job): the
    commands print degrees, ⌀ and →, which ASCII cannot encode (the terminals that run such jobs show UTF-8)."""
    import codecs
    for stream in (sys.stdout, sys.stderr):
        encoding = getattr(stream, "encoding", None)
        if encoding and codecs.lookup(encoding).name == "ascii" and hasattr(stream, "reconfigure"):
            stream.reconfigure(encoding="utf-8")


#: the thread counts of the BLAS libraries numpy and scipy may load
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _one_blas_thread() -> None:
    """One BLAS thread for this command and the processes it starts, unless the user set a number (the variables of
    :data:`BLAS_THREAD_VARIABLES`), and only where numpy is not loaded yet (a command run inside a Python session
    leaves the session's setting alone). assur multiplies and factorises small matrices, on which OpenBLAS's own
    threads only spin: measured on a 2-core machine, ``assur codesign examples/walker_fourbar.toml --optimize joint
    --budget 300`` took 63 s of CPU in 40 s with OpenBLAS's default threads and 29 s in 29 s with one."""
    if "numpy" in sys.modules:
        return
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 bad input, 2 usage error, 3 no feasible
    synthesis, 130 interrupted). Ctrl-C is answered with one line from the first import on."""
    _one_blas_thread()
    _utf8_streams()
    try:
        return _run(argv)
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return INTERRUPTED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
