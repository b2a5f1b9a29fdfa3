"""``assur cam FILE``: a mechanism's cam pair — its law (continuity, SVAJ peaks), its profile's checks (base and prime
circles, pressure angle, radii of curvature, undercut), the smallest base circle for its pressure-angle limit, and its
figure, DXF or SVG profile (mm) or JSON (docs/cams.md)."""
from __future__ import annotations

from ..errors import SpecError
from ..io.output import atomic_file
from .args import compile_file, output_path

EXTENSIONS = (".png", ".svg", ".pdf", ".dxf", ".json")


def register(sub) -> None:
    help_ = "a mechanism's cam pair: law continuity and SVAJ, profile, pressure angle, curvature, sizing; DXF/SVG"
    sp = sub.add_parser("cam", help=help_, description=help_)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml) with [[cams]]")
    sp.add_argument("--name", metavar="CAM", help="the cam pair (default: the first)")
    sp.add_argument("-o", "--output", type=output_path(EXTENSIONS), metavar="OUT",
                    help="the figure (.png, .pdf), the profile in mm (.dxf, .svg: the profile and its pitch curve) or "
                         "the summary (.json)")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp.set_defaults(func=cmd_cam)


def cmd_cam(args) -> int:
    from ..cams.followers import from_plan
    from ..cams.summary import cam_summary
    from ..io.output import json_text
    from ..report.cams import summary_lines
    m, plan = compile_file(args.file)
    if not m.cams:
        raise SpecError([("cams", f"{args.file} has no [[cams]]")])
    g = from_plan(plan, args.name if args.name is not None else 0)
    summary = cam_summary(plan, g)
    if args.json:
        print(json_text(summary))
    else:
        for line in summary_lines(summary):
            print(line)
    if args.output:
        _write(args, plan, g, summary)
    return 0


def _write(args, plan, g, summary):
    ext = args.output.suffix.lower()
    if ext in (".dxf", ".svg"):
        from ..io.cam_profile import write_profile
        write_profile(args.output, g)
    elif ext == ".json":
        from ..io.output import json_text
        with atomic_file(args.output) as tmp:
            tmp.write_text(json_text(summary) + "\n", encoding="utf-8")
    else:
        from ..plot.cams import cam_figure
        from ..plot.draw import close
        fig = cam_figure(g, speed=abs(float(plan.speeds[0])) if plan.n_inputs else None, title=g.name)
        try:
            with atomic_file(args.output) as tmp:
                fig.savefig(tmp, format=ext[1:])
        finally:
            close(fig)
    print(f"wrote {args.output}")
