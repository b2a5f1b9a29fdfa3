"""Feedback on the slow steps of a command, on stderr and only on a terminal (a pipe, a file or a test's
captured output gets nothing extra):

- :func:`frame_progress` — ``progress(i, n)`` for the frames of an animation: a tqdm bar when tqdm is
  installed, else one plain line rewritten in place ("frames 12/60");
- :func:`announce_compiles` — while a command runs, the one line of the compiled backend when it generates
  and compiles a kernel for a new mechanism (numba's first compile takes seconds; later runs load it from the
  disk cache and say nothing).
"""
from __future__ import annotations

import contextlib
import logging
import sys

#: the logger the compiled backends report a fresh kernel compile on (assur.kernels.codegen.LOG)
COMPILE_LOGGER = "assur.compile"


def frame_progress(desc: str = "frames"):
    """A ``progress(i, n)`` callable (frame i of n done being drawn) for stderr, or None when stderr is not a
    terminal."""
    stream = sys.stderr
    if not stream.isatty():
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        tqdm = None
    bar = []

    def show(i, n):
        done = min(i + 1, n)
        if tqdm is None:
            print(f"\r{desc} {done}/{n}", end="" if done < n else "\n", file=stream, flush=True)
            return
        if not bar:
            bar.append(tqdm(total=n, desc=desc, unit="frame", file=stream, dynamic_ncols=True, leave=False))
        bar[0].update(done - bar[0].n)
        if done >= n:
            bar[0].close()
    return show


class _StderrLine(logging.Handler):
    """Prints each record's message as one line on the current ``sys.stderr``."""

    def emit(self, record):
        try:
            print(record.getMessage(), file=sys.stderr, flush=True)
        except Exception:   # noqa: BLE001 - a message must never break a command
            self.handleError(record)


@contextlib.contextmanager
def announce_compiles():
    """While the block runs, print the compiled backend's "compiling a kernel …" line on stderr."""
    log = logging.getLogger(COMPILE_LOGGER)
    handler = _StderrLine(logging.INFO)
    old_level = log.level
    log.addHandler(handler)
    if log.getEffectiveLevel() > logging.INFO:
        log.setLevel(logging.INFO)
    try:
        yield
    finally:
        log.removeHandler(handler)
        log.setLevel(old_level)
