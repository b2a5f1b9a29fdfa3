"""``assur gears DESIGN.toml -o DIR`` and ``assur wheelstep DESIGN.toml -o DIR``: the outputs of a gear-pair
design (format assur-gears/1) or of a wheel-step mover (assur-wheelstep/1), written into DIR atomically (all or
nothing) by :mod:`assur.report.bundles`, which lists them.
"""
from __future__ import annotations

from pathlib import Path

from .args import MAX_FRAMES, path_arg, positive


#: the gear cache (assur.gears.cache), told in the sub-commands' help
CACHE_NOTE = ("The rack-cut outlines and the mesh checks are kept in a cache ($ASSUR_CACHE_DIR/gears, else "
              "$XDG_CACHE_HOME/assur/gears or ~/.cache/assur/gears; never the output directory), so the same gears "
              "are not computed twice, in this or a later run (assur gears, assur wheelstep, assur report). "
              "ASSUR_CACHE_DIR=off turns the cache off.")


def register(sub) -> None:
    """Add this module's sub-commands to the argparse sub-parsers `sub`."""
    for name, func, help_ in (("gears", cmd_gears, "non-circular gear pair: pitch curves, teeth (DXF/SVG), "
                                                   "mesh check, tables and plots"),
                              ("wheelstep", cmd_wheelstep, "wheel-step mover: shoe profile, displacement budget, "
                                                           "and the outputs of its gear drive")):
        sp = sub.add_parser(name, help=help_, description=help_, epilog=CACHE_NOTE)
        sp.add_argument("file", metavar="FILE", help="design file (.toml)")
        sp.add_argument("-o", "--output", type=path_arg, required=True, metavar="DIR", help="output directory")
        sp.add_argument("--json", action="store_true", help="print the summary as one JSON object (SI units)")
        sp.add_argument("--mesh-steps", type=positive(8), default=360, metavar="N",
                        help="driving-angle positions of the mesh check over the cycle (default 360)")
        sp.add_argument("--frames", type=positive(0, MAX_FRAMES), default=24, metavar="N",
                        help="frames of the meshing animation envelope_mesh.html (default 24; 0: none)")
        sp.set_defaults(func=func)


def _run(args, expected: str) -> int:
    from ..errors import SpecError
    from ..io.gear_file import load_design
    from ..io.output import atomic_directory, json_text
    from ..report.bundles import public_summary, run_gears, run_wheelstep
    design = load_design(args.file)
    if type(design).__name__ != expected:
        want = "assur-gears/1" if expected == "GearDesign" else "assur-wheelstep/1"
        raise SpecError([("format", f"`assur {args.command}` needs a {want} file")], source=str(args.file))
    runner = run_gears if expected == "GearDesign" else run_wheelstep
    log = (lambda _: None) if args.json else print
    with atomic_directory(args.output) as tmp:
        summary = runner(design, Path(tmp), mesh_steps=args.mesh_steps, log=log, frames=args.frames,
                         progress=_progress())
    if args.json:
        print(json_text(public_summary(summary)))
    else:
        print(f"wrote {args.output}/")
    return 0


def _progress():
    """``progress(text)`` for the slow steps: one line on stderr per step ("… cutting the envelope teeth"), on a
    terminal only (a pipe, a file or a test's captured output gets nothing extra), like the other commands'
    progress feedback (:mod:`assur.cli.progress`)."""
    import sys
    import time
    if not sys.stderr.isatty():
        return None
    start = time.perf_counter()

    def show(text):
        print(f"  [{time.perf_counter() - start:5.1f} s] {text} …", file=sys.stderr, flush=True)
    return show


def cmd_gears(args) -> int:
    """``assur gears DESIGN -o DIR``."""
    return _run(args, "GearDesign")


def cmd_wheelstep(args) -> int:
    """``assur wheelstep DESIGN -o DIR``."""
    return _run(args, "WheelStepDesign")
