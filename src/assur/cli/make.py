"""``assur make FILE -o DIR``: the mechanism as parts a workshop can make (docs/make.md): plates, pins, blocks and
gear plates on the fewest layers, every conflict certified over the continuous cycle, written as STL and 3MF per
part, one STEP assembly, ``parts.json``, ``certificate.json``, ``bom.csv`` and ``parts.html``; the output
directory appears complete or not at all.
"""
from __future__ import annotations

from pathlib import Path

from .args import path_arg, positive

HELP = ("the mechanism as printable and machinable parts: plates, pins and gears on a proven-minimal, certified "
        "collision-free layer stack (STL, 3MF, STEP, parts.json, bom.csv, an HTML page)")


def register(sub) -> None:
    """Add ``assur make`` to the argparse sub-parsers ``sub``."""
    sp = sub.add_parser("make", help=HELP, description=HELP,
                        epilog="Sizes, material and process come from the file's [make] table (docs/make.md); the "
                               "CAD packages install with: pip install 'assur[make]'")
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    sp.add_argument("-o", "--output", type=path_arg, required=True, metavar="DIR", help="output directory")
    sp.add_argument("--clearance", metavar="LENGTH",
                    help="least gap between two parts of one layer over the cycle: a number in the file's length "
                         "unit or '<number> <unit>' (default: the file's [make] clearance, else by process)")
    sp.add_argument("--process", choices=("fdm", "laser-cut", "machined"),
                    help="manufacturing process (default: the file's [make] process, else fdm)")
    sp.add_argument("--layers-only", action="store_true",
                    help="the layer stack, parts.json, certificate.json and the page only: no solids")
    sp.add_argument("--max-layers", type=positive(1), metavar="N", help="use at most N layers")
    sp.add_argument("--mass-back", type=path_arg, metavar="OUT.toml",
                    help="also write a copy of the mechanism file with the parts' masses, centres of mass and "
                         "inertias (for assur forces)")
    sp.add_argument("--steps", type=positive(8), default=720, metavar="N",
                    help="samples of the cycle the conflicts are certified between (default 720)")
    sp.add_argument("--time-limit", type=float, default=60.0, metavar="S",
                    help="time limit (s) of each phase of the layer program (default 60)")
    sp.add_argument("--json", action="store_true", help="print the summary as one JSON object (SI units)")
    sp.set_defaults(func=cmd_make)


def _clearance(text, mechanism):
    from ..errors import SpecError
    from ..io.units import parse_quantity
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        value = text
    try:
        return parse_quantity(value, "length", mechanism.units)
    except SpecError as exc:
        raise SpecError([("--clearance", str(exc))]) from None


def cmd_make(args) -> int:
    from ..errors import SpecError
    from ..io.output import atomic_directory, atomic_file, json_text
    from ..parts.solids import require_make
    if not args.layers_only or args.mass_back:
        require_make()                                   # before any work: the install command, exit 1
    if not (args.time_limit > 0):
        raise SpecError([("--time-limit", f"must be a positive number of seconds: {args.time_limit!r}")])
    from ..analysis.study import Study
    from ..parts import make_parts
    from ..parts.files import write_all
    from .args import compile_file
    if args.mass_back is not None:
        from ..io.output import check_writable
        if args.layers_only:
            raise SpecError([("--mass-back", "needs the solids: leave out --layers-only")])
        if Path(args.mass_back).resolve() == Path(args.file).resolve():
            raise SpecError([("--mass-back", f"{args.mass_back} is the mechanism file itself: write the copy "
                                             "elsewhere")])
        check_writable(args.mass_back)
    m, plan = compile_file(args.file)
    clearance = _clearance(args.clearance, m)
    quiet = args.json
    log = (lambda _: None) if quiet else _progress()
    log("solving the cycle")
    if plan.dimension != 2:
        raise SpecError([("dimension", "assur make builds planar mechanisms (dimension = 2)")])
    cycle = Study(plan, steps=args.steps)
    log("certifying the conflicts and solving the layer program")
    result = make_parts(cycle, clearance=clearance, process=args.process, max_layers=args.max_layers,
                        time_limit=args.time_limit)
    text = None
    with atomic_directory(args.output) as tmp:
        summary = write_all(result, Path(tmp), layers_only=args.layers_only, log=log)
        if args.mass_back is not None:
            from ..io.mechanism_writer import dumps
            from ..parts.massback import with_masses
            text = dumps(with_masses(result))
    if text is not None:
        with atomic_file(args.mass_back) as out:
            out.write_text(text, encoding="utf-8")
    if args.json:
        print(json_text(summary))
        return 0
    _print(result, summary, args)
    return 0


def _print(result, summary, args) -> None:
    c = result.certificate
    s = result.settings
    name = result.mechanism.name or Path(args.file).stem
    proof = ("proven minimal: " + ("the maximum clique needs as many" if c.layers == c.bound else
                                   "HiGHS optimal" + (", no layout with one fewer (exhaustive)" if c.exhaustive else ""))
             if c.proven else f"NOT proven minimal ({c.status}, gap {100 * c.gap:.0f} %)")
    print(f"{name}  [{args.file}]: {len(result.parts)} parts on {c.layers} layer{'s' if c.layers != 1 else ''} "
          f"({proof})")
    print(f"  {s.process}, {s.material}: plates {s.thickness * 1e3:g} mm, bars {s.width * 1e3:g} mm wide, pins "
          f"⌀{s.pin * 1e3:g} mm, washers {s.washer * 1e3:g} mm, clearance {s.clearance * 1e3:g} mm")
    by_layer: dict = {}
    for name_, k in summary["layered"]:
        by_layer.setdefault(k, []).append(name_)
    for k in sorted(by_layer):
        where = "in the base plate" if k < 0 else "in the top plate" if k >= c.layers else f"layer {k}"
        print(f"  {where}: {', '.join(by_layer[k])}")
    print(f"  {summary['pairs_checked']} pairs certified over the cycle, {summary['conflicts']} in conflict"
          + (f", {summary['refined_intervals']} intervals refined" if summary['refined_intervals'] else ""))
    big = summary["larger_than_print_bed"]
    if big:
        n0 = big[0]
        print(f"  note: {len(big)} part{'s do' if len(big) > 1 else ' does'} not fit a 250 mm print bed (largest "
              f"{n0['name']}, {n0['size'][0] * 1e3:.0f} × {n0['size'][1] * 1e3:.0f} mm): print in pieces, scale "
              "the file, or choose --process laser-cut or machined")
    print(f"wrote {args.output}/" + (f" and {args.mass_back}" if args.mass_back else ""))


def _progress():
    """One line on stderr per slow step, on a terminal only."""
    import sys
    import time
    if not sys.stderr.isatty():
        return lambda _: None
    start = time.perf_counter()

    def show(text):
        print(f"  [{time.perf_counter() - start:5.1f} s] {text} …", file=sys.stderr, flush=True)
    return show
