"""Argument checks and input reading shared by the commands: argparse types, output extensions, the
``--range`` option, loading and compiling a file, and a TOML document's format.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..errors import SpecError
from ..io.units import ANGLE, LENGTH

PLOT_EXTENSIONS = (".png", ".svg", ".pdf", ".html")   # .html: interactive 3D view (spatial files)
ANIMATION_EXTENSIONS = (".gif", ".mp4", ".html")


#: the largest count (samples, frames, positions, …) a command takes unless its option says otherwise: far more
#: than any figure or table needs, small enough that its arrays fit in memory
MAX_COUNT = 1_000_000
#: the most animation frames (each is drawn: a million would take days)
MAX_FRAMES = 10_000
#: the largest objective-evaluation budget of a search
MAX_BUDGET = 1_000_000_000
#: the most worker processes
MAX_WORKERS = 256
#: the finest resolution of a figure (dots per inch)
MAX_DPI = 1200


def positive(minimum: int = 1, maximum: int = MAX_COUNT):
    """An argparse type: an integer from ``minimum`` to ``maximum``."""
    def parse(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer: {text!r}") from None
        if v < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}: {v}")
        if v > maximum:
            raise argparse.ArgumentTypeError(f"must be at most {maximum}: {v}")
        return v
    return parse


#: the largest random seed a command takes (numpy's legacy generators, which scipy's optimisers seed, take 32 bits)
MAX_SEED = 2**32 - 1


def seed_arg(text) -> int:
    """An argparse type: a random seed, a whole number from 0 to :data:`MAX_SEED`."""
    try:
        v = int(text)
    except ValueError:
        v = -1
    if not 0 <= v <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"must be a whole number from 0 to {MAX_SEED}: {text!r}")
    return v


def fps_arg(text) -> float:
    """An argparse type: an animation's frame rate (:func:`assur.plot.draw.frame_rate`)."""
    from ..errors import SpecError
    from ..plot.draw import frame_rate
    try:
        return frame_rate(text)
    except SpecError as exc:
        raise argparse.ArgumentTypeError(exc.problems[0][1]) from None


def _finite_number(text, zero: bool) -> float:
    """``text`` as a finite number > 0 (≥ 0 with ``zero``), else argparse's error."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number: {text!r}") from None
    if not ((v >= 0 if zero else v > 0) and math.isfinite(v)):
        raise argparse.ArgumentTypeError(f"must be a number ≥ 0: {text!r}" if zero else
                                         f"must be a positive number: {text!r}")
    return v


def finite_float(text) -> float:
    """An argparse type: a finite number (any sign)."""
    try:
        v = float(text)
    except ValueError:
        v = math.nan
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"must be a finite number: {text!r}")
    return v


def positive_float(text):
    """An argparse type: a positive finite number."""
    return _finite_number(text, zero=False)


def nonnegative_float(text):
    """An argparse type: a finite number ≥ 0."""
    return _finite_number(text, zero=True)


def path_arg(text) -> Path:
    """An argparse type: a path, never an empty one (``-o ""`` would otherwise mean the current directory)."""
    if not str(text).strip():
        raise argparse.ArgumentTypeError("the path is empty")
    return Path(text)


def output_path(extensions):
    """An argparse type: a path ending with one of ``extensions``."""
    def parse(text):
        path = path_arg(text)
        ext = path.suffix.lower()
        if ext not in extensions:
            raise argparse.ArgumentTypeError(f"the output must end with {', '.join(extensions)}: {text!r}")
        return Path(text)
    return parse


def add_range(sp) -> None:
    """The ``--range START STOP`` option (once per input) of a sub-parser."""
    sp.add_argument("--range", nargs=2, type=finite_float, action="append", metavar=("START", "STOP"),
                    help="run an input from START to STOP (the file's angle or length unit); once per input, "
                         "in driver order; needed for a linear input or several moving inputs")


def input_ranges(plan, args):
    """--range pairs (file units) → SI, one per input; None when not given."""
    if not getattr(args, "range", None):
        return None
    u = plan.mechanism.units
    if len(args.range) != plan.n_inputs:
        raise SpecError([("--range", f"give one --range START STOP per input, in driver order "
                                     f"({plan.n_inputs}: {', '.join(plan.input_names)}): {len(args.range)} given")])
    out = []
    for k, (a, b) in enumerate(args.range):
        f = ANGLE[u.angle] if plan.input_kinds[k] == "rotary" else LENGTH[u.length]
        out.append((a * f, b * f))
    return out


def load_mechanism(path):
    """The mechanism of the file ``path``."""
    from ..io.mechanism_file import load
    return load(path)


def compile_file(path):
    """(mechanism, plan) of the file ``path``."""
    from ..engine import compile as compile_
    m = load_mechanism(path)
    return m, compile_(m)


def document_format(path) -> str:
    """The top-level ``format`` key of a TOML document: "assur/1" (a mechanism, planar or spatial),
    "assur-gears/1", "assur-wheelstep/1" or "assur-synth/1". A missing key reads as "assur/1" so that the
    mechanism loader reports what is wrong with the file."""
    from ..io.mechanism_file import read_toml
    doc = read_toml(path)
    fmt = doc.get("format", "assur/1")
    return fmt if isinstance(fmt, str) else "assur/1"
