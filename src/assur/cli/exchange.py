"""``assur import`` and ``assur export``: moving a design between assur and pylinkage, PMKS+, Pyslvs and four-bar-rs
(docs/interop.md).

``assur export`` is a table: ``WRITERS`` maps each ``--to`` format onto its writer, loaded on first use (a literal
import), ``write(mechanism, path) -> str | None`` (the file written atomically; the returned line, e.g. a PMKS+
link, is printed). Another format registers with one line::

    WRITERS["mjcf"] = lambda: importlib.import_module("assur.dynamics.mjcf").write
"""
from __future__ import annotations

import importlib
import sys
import warnings

from .args import load_mechanism, output_path, path_arg

#: --to FORMAT → its writer, loaded on first use: the exporters of ``assur export``
WRITERS = {
    "pylinkage": lambda: importlib.import_module("assur.interop.pylinkage_write").write,
    "pmks": lambda: importlib.import_module("assur.interop.pmks").write,
    "pyslvs": lambda: importlib.import_module("assur.interop.pyslvs").write,
    "fourbar": lambda: importlib.import_module("assur.interop.fourbar").write,
    "mjcf": lambda: importlib.import_module("assur.dynamics.mjcf").write,
}
#: --format FORMAT of ``assur import`` (told from the content when not given)
READERS = ("pylinkage", "pmks", "pyslvs", "fourbar")
LENGTH_UNITS = ("m", "mm", "cm", "dm", "km", "in", "ft")


def register(sub) -> None:
    """Add ``import`` and ``export`` to the argparse sub-parsers ``sub``."""
    h = ("read a pylinkage JSON, a PMKS+ link or .pmks file, a Pyslvs project or expression, or a four-bar-rs RON "
         "file into an assur/1 mechanism file")
    sp = sub.add_parser("import", help=h, description=h)
    sp.add_argument("source", metavar="SOURCE",
                    help="a file, '-' for standard input, or the text itself (a PMKS+ link, a Pyslvs expression)")
    sp.add_argument("-o", "--output", type=output_path((".toml",)), required=True, metavar="FILE.toml",
                    help="the mechanism file to write")
    sp.add_argument("--format", choices=READERS, help="the source's format (default: told from its content)")
    sp.add_argument("--units", choices=LENGTH_UNITS,
                    help="length unit of a unitless source (pylinkage, Pyslvs, four-bar-rs; default m)")
    sp.set_defaults(func=cmd_import)
    h = "write a mechanism file for another tool: pylinkage JSON, PMKS+ (.pmks and its link), Pyslvs, four-bar-rs"
    sp = sub.add_parser("export", help=h, description=h)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    sp.add_argument("--to", required=True, choices=tuple(WRITERS), help="the format to write")
    sp.add_argument("output", type=path_arg, metavar="OUT", help="the file to write ('-': standard output)")
    sp.set_defaults(func=cmd_export)


def _warnings(caught) -> None:
    for w in caught:
        print(f"warning: {w.message}", file=sys.stderr)


def cmd_import(args) -> int:
    from ..interop import import_mechanism
    from ..io.mechanism_writer import dump
    source = args.source
    if source == "-":
        source = sys.stdin.read(16 * 2 ** 20 + 1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        m = import_mechanism(source, format=args.format, units=args.units)
    _warnings(caught)
    dump(m, args.output)
    print(f"wrote {args.output}: {len(m.points)} points, {len(m.links)} links, {len(m.drivers)} driver(s)")
    return 0


def _with_made_masses(m):
    """For a MuJoCo model of a file with a ``[make]`` table: the mechanism with its made parts' masses, centres of
    mass and inertias (as ``assur make --mass-back`` writes them) when the CAD packages are installed, else the
    file's own with a note."""
    import sys

    from ..errors import MissingPackageError
    try:
        from ..parts.solids import require_make
        require_make()
    except (ImportError, MissingPackageError):
        print("note: the file has a [make] table but the CAD packages are not installed: the model takes the file's "
              "masses (pip install 'assur[make]' for the parts')", file=sys.stderr)
        return m
    from ..analysis.study import Study
    from ..engine import compile as compile_
    from ..parts.massback import with_masses
    return with_masses(Study(compile_(m)).parts)


def cmd_export(args) -> int:
    m = load_mechanism(args.file)
    if args.to == "mjcf" and m.make is not None and m.dimension == 2:
        m = _with_made_masses(m)
    writer = WRITERS[args.to]()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        message = writer(m, args.output)
    _warnings(caught)
    if str(args.output) != "-":
        print(f"wrote {args.output} ({args.to})")
    if message:
        print(message)
    return 0


__all__ = ["READERS", "WRITERS", "cmd_export", "cmd_import", "register"]
