"""The ``assur`` command line: the parser and the dispatch to the commands of
:mod:`assur.cli.mechanism` (validate, info, solve, analyze, plot, animate, report), :mod:`assur.cli.synth`
(synth) and :mod:`assur.cli.gears` (gears, wheelstep).

Bad input (an invalid file, a structure that cannot be solved, a missing file) prints one message
starting with ``error:`` to stderr and exits with status 1; usage errors exit with status 2
(argparse). Heavy modules (matplotlib) are imported only by the commands that draw.
"""
from __future__ import annotations

import argparse
import contextlib
import os
import sys

from ..errors import AssurError
from . import gears, mechanism, synth


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command."""
    from .. import __version__
    p = argparse.ArgumentParser(prog="assur", description="Structural and kinematic analysis of planar mechanisms "
                                "described in mechanism files (format assur/1).")
    p.add_argument("--version", action="version", version=f"assur {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", required=True)
    mechanism.register(sub)
    synth.register(sub)
    gears.register(sub)   # `assur gears` and `assur wheelstep`
    return p


def format_error(exc: BaseException) -> str:
    """The one-line message of a failed command."""
    return f"error: {exc}"


def main(argv=None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 bad input, 2 usage error)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # usage errors (2) and --help/--version (0)
        return int(exc.code) if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    try:
        return int(args.func(args) or 0)
    except AssurError as exc:
        print(format_error(exc), file=sys.stderr)
        return 1
    except ImportError as exc:   # an optional dependency (e.g. imageio-ffmpeg for MP4)
        print(format_error(exc), file=sys.stderr)
        return 1
    except BrokenPipeError:      # e.g. `assur analyze --json f | head`
        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except OSError as exc:       # an output cannot be written
        name = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        print(f"error: cannot write{name}: {exc.strerror or exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
