"""``assur codesign LEG.toml -o DIR``: a walking leg and the non-circular gear pair that drives its crank from a
uniform motor, designed together so that the foot moves at constant horizontal speed over the central part of its
stride (docs/codesign.md). Writes into DIR (atomically, all or nothing):

- ``<stem>_geared.toml``: the leg (its optimised dimensions with ``--optimize joint``) with a motor and the gear pair;
- ``<stem>_geared_gears.toml``: the gear design (assur-gears/1): the law table, envelope teeth, whole tooth count;
- ``gears/``: the gear outputs of ``assur gears`` (pitch curves, DXF/SVG/CSV outlines, mesh check);
- ``foot_speed.png`` (before/after), ``animation.gif`` (leg and gears), ``codesign.json`` (the summary, SI) and
  ``index.html`` (the summary page);
- with ``--tradeoff``: ``tradeoff.png`` and its rows in the summary.

When the leg has masses or loads the summary (printed, in the JSON and on the page) gives the drive's cost: the
motor's peak and RMS torque and the peak bearing loads, before (a uniform crank) and after (a uniform motor through
the gears), each from one force analysis of one turn (:func:`assur.codesign.torque.drive_cost`). ``--max-torque T``
(N·m) makes the peak motor torque a constraint of the search and of the checks.

Exit status 3 (nothing written) when no gear pair passes the checks (convexity, pressure angle, ratio range,
undercut, the torque limit), with the violations on stderr.
"""
from __future__ import annotations

import math
from pathlib import Path

from .args import MAX_BUDGET, MAX_FRAMES, finite_float, path_arg, positive, positive_float, seed_arg


def register(sub) -> None:
    help_ = "co-design a walking leg and the non-circular gears that give its foot a constant speed"
    sp = sub.add_parser("codesign", help=help_, description=help_ + " (docs/codesign.md)")
    sp.add_argument("file", metavar="FILE", help="the leg (assur/1, one crank, a [gait] foot)")
    sp.add_argument("-o", "--output", type=path_arg, required=True, metavar="DIR", help="output directory")
    sp.add_argument("--window", type=positive_float, default=0.8, metavar="F",
                    help="the central fraction of the stride with an exactly constant foot speed (default 0.8)")
    sp.add_argument("--centre-distance", type=positive_float, default=None, metavar="MM",
                    help="motor-to-crank centre distance in mm (default: 0.45 crank lengths)")
    sp.add_argument("--direction", type=finite_float, default=90.0, metavar="DEG",
                    help="where the motor sits, seen from the crank's pivot (degrees from +x, default 90: above)")
    sp.add_argument("--module", type=positive_float, default=2.0, metavar="MM",
                    help="the rack's module in mm (adjusted to a whole tooth count; default 2)")
    sp.add_argument("--pressure-angle", type=positive_float, default=20.0, metavar="DEG",
                    help="the rack's pressure angle (default 20)")
    sp.add_argument("--max-pressure-angle", type=positive_float, default=30.0, metavar="DEG",
                    help="the largest centrode pressure angle allowed (default 30)")
    sp.add_argument("--ratio-bounds", type=positive_float, nargs=2, default=(1 / 3, 3.0), metavar=("LO", "HI"),
                    help="bounds of the motor-to-crank speed ratio dτ/dq (default 1/3 3)")
    sp.add_argument("--max-torque", type=positive_float, default=None, metavar="T",
                    help="the largest motor torque allowed, in N·m (a leg with masses or loads): a constraint of "
                         "the search and of the checks")
    sp.add_argument("--optimize", choices=("none", "transfer", "joint"), default="transfer",
                    help="none: the smoothest transfer; transfer: the transfer law for the gear constraints "
                         "(default); joint: the leg's dimensions and the transfer law together")
    sp.add_argument("--budget", type=positive(50, MAX_BUDGET), default=4000, metavar="N",
                    help="objective evaluations of --optimize joint (default 4000)")
    sp.add_argument("--seed", type=seed_arg, default=1, metavar="S", help="random seed of the optimisers (default 1)")
    sp.add_argument("--tradeoff", action="store_true",
                    help="also optimise the transfer for windows 0.6 … 0.95 and draw tradeoff.png")
    sp.add_argument("--frames", type=positive(0, MAX_FRAMES), default=36, metavar="N",
                    help="frames of animation.gif (default 36; 0: none)")
    sp.add_argument("--mesh-steps", type=positive(8), default=360, metavar="N",
                    help="positions of the gear mesh check (default 360)")
    sp.add_argument("--json", action="store_true", help="print the summary as one JSON object (SI units)")
    sp.set_defaults(func=cmd_codesign)


def _check_leg(m, plan, args):
    from ..codesign.torque import carries_loads
    from ..errors import SpecError
    if m.dimension != 2 or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary" or m.gears:
        raise SpecError([("drivers", "a leg to co-design needs a planar mechanism with one crank and no gears")])
    if m.gait is None:
        raise SpecError([("gait", "a leg to co-design needs a [gait] block with its foot")])
    if not 0 < args.window < 1:
        raise SpecError([("--window", f"must be between 0 and 1 (a fraction of the stride): {args.window!r}")])
    if args.max_torque is not None and not carries_loads(m):
        raise SpecError([("--max-torque", "the leg has no masses and no loads, so its motor torque is zero "
                                          "whatever the gears: give its links masses (docs/forces.md)")])


def cmd_codesign(args) -> int:
    """``assur codesign LEG -o DIR``."""
    from ..engine import compile as compile_
    from ..io.output import atomic_directory, check_output_directory, json_text
    from .args import load_mechanism
    m = load_mechanism(args.file)
    plan = compile_(m)
    _check_leg(m, plan, args)
    check_output_directory(args.output)
    crank = m.drivers[0]
    crank_length = abs(complex(*m.sketch(crank.arm)[:2]) - complex(*m.sketch(crank.pivot)[:2]))
    L = args.centre_distance / 1000.0 if args.centre_distance else 0.45 * crank_length
    options = {"centre_distance": L, "module": args.module / 1000.0,
               "max_pressure_angle": math.radians(args.max_pressure_angle), "ratio_bounds": tuple(args.ratio_bounds),
               "max_torque": args.max_torque}
    log = (lambda _: None) if args.json else print
    params, law, checks, search = _design(plan, args, options, log)
    if not checks.ok:
        import sys
        more = ", a larger --max-torque" if args.max_torque is not None else ""
        print(f"no feasible gear pair for a window of {args.window:g} ({search['kind']} optimisation); nothing "
              f"written. Try a smaller --window, other --centre-distance / --module{more}, or --optimize joint:",
              file=sys.stderr)
        for text in checks.violations:
            print(f"  {text}", file=sys.stderr)
        return 3
    stem = f"{Path(args.file).stem}_geared"
    with atomic_directory(args.output) as tmp:
        summary = write_bundle(Path(tmp), plan, params, law, checks, stem=stem, options=options, args=args, log=log)
        summary["search"] = search
        (Path(tmp) / "codesign.json").write_text(json_text(summary), encoding="utf-8")
        from ..report.codesign import summary_page
        (Path(tmp) / "index.html").write_text(summary_page(summary, Path(tmp), summary_lines(summary)),
                                              encoding="utf-8")
    if args.json:
        print(json_text(summary))
    else:
        for line in summary_lines(summary):
            print(line)
        print(f"wrote {args.output}/")
    return 0


def _design(plan, args, options, log):
    """(params, law, checks, search info) of the requested optimisation."""
    from ..codesign import transfer as CD
    rb = options["ratio_bounds"]
    if args.optimize == "joint":
        from ..codesign.joint import optimize_codesign
        log(f"optimising the leg and the transfer law together (budget {args.budget}) …")
        d = optimize_codesign(plan, args.window, centre_distance=options["centre_distance"], module=options["module"],
                              max_pressure_angle=options["max_pressure_angle"], ratio_bounds=rb,
                              budget=args.budget, seed=args.seed, progress=log, max_torque=options["max_torque"])
        return d.params, d.law, d.checks, {"kind": "joint", "feasible": d.feasible, "evaluations": d.evaluations,
                                           "varied": [v[0] for v in d.vary], "gait": d.gait}
    if args.optimize == "transfer":
        log("optimising the transfer law for the gear constraints …")
        t = CD.optimize_transfer(plan, args.window, centre_distance=options["centre_distance"],
                                 module=options["module"], max_pressure_angle=options["max_pressure_angle"],
                                 ratio_bounds=rb, seed=args.seed, measure=False, max_torque=options["max_torque"])
        return plan.defaults, t.law, t.checks, {"kind": "transfer", "feasible": t.success,
                                                "evaluations": t.evaluations}
    r = CD.codesign(plan, args.window, centre_distance=options["centre_distance"], module=options["module"],
                    max_pressure_angle=options["max_pressure_angle"], ratio_bounds=rb, n_bumps=6,
                    max_torque=options["max_torque"])
    return plan.defaults, r.law, r.checks, {"kind": "none", "feasible": r.checks.ok, "evaluations": 1}


def write_bundle(out: Path, plan, params, law, checks, *, stem, options, args, log) -> dict:
    """Every output file but the summary into ``out``; returns the summary (SI)."""
    import numpy as np

    from ..analysis.study import Study
    from ..codesign.law import geared_vx_spread
    from ..codesign.torque import drive_cost
    from ..engine import compile as compile_
    from ..io.gear_file import load_design
    from ..io.mechanism_file import load
    from ..io.toml_writer import dumps
    from ..report import codesign as R
    from ..report.bundles import public_summary, run_gears
    from ..synthesis.design import mechanism_with_params
    leg = mechanism_with_params(plan, np.asarray(params, dtype=float))
    alpha = math.radians(args.pressure_angle)
    Lw, _, _ = R.drive_law(law, leg.drivers[0])
    gear_name = f"{stem}_gears.toml"
    (out / gear_name).write_text(dumps(R.gear_document(law, checks, Lw, name=leg.name or stem, pressure_angle=alpha)),
                                 encoding="utf-8")
    doc = R.geared_document(leg, law, gear_name, centre_distance=options["centre_distance"],
                            direction=math.radians(args.direction), pressure_angle=alpha)
    (out / f"{stem}.toml").write_text(dumps(doc), encoding="utf-8")
    geared = compile_(load(out / f"{stem}.toml"))
    plain = compile_(leg)
    log("cutting the gears and checking the mesh …")
    (out / "gears").mkdir()
    gears = run_gears(load_design(out / gear_name), out / "gears", mesh_steps=args.mesh_steps, log=lambda _: None,
                      frames=0)
    plain_run, geared_run = Study(plain), Study(geared)       # one turn of the crank, one turn of the motor
    (before, curves_before), (after, curves_after) = _gait(plain_run), _gait(geared_run)
    R.foot_speed_figure((before, curves_before), (after, curves_after), out / "foot_speed.png", fraction=law.fraction)
    if args.frames:
        log("drawing the animation …")
        from ..plot.animation import animation, save_animation
        from ..plot.draw import close
        fig, anim = animation(geared, frames=args.frames)
        save_animation(anim, out / "animation.gif")
        close(fig)
    env = gears.get("envelope", {})
    mesh = env.get("mesh", {})
    summary = {"leg": str(args.file), "window": law.fraction, "centre_distance": options["centre_distance"],
               "files": {"mechanism": f"{stem}.toml", "gears": gear_name},
               "law": {"k": law.k, "window_speed": law.window_speed(abs(float(plan.speeds[0]))),
                       "coefficients": [float(c) for c in law.coefficients]},
               "checks": {"ok": checks.ok, "violations": list(checks.violations), "teeth": checks.teeth,
                          "module": checks.module, "convexity": dict(checks.convexity),
                          "max_pressure_angle": checks.max_pressure_angle,
                          "ratio_range": [checks.ratio_min, checks.ratio_max]},
               "outlines": {"valid": mesh.get("outline_valid"), "interference": mesh.get("interference"),
                            "defects": mesh.get("outline_defects", []),
                            "undercut": [env.get("undercut_driving", ""), env.get("undercut_driven", "")]},
               "vx_spread": {"before": before.vx_spread, "after": after.vx_spread,
                             "after_law": geared_vx_spread(law)},
               "gait": {"step": after.step_length, "lift": after.lift, "sag": after.sag},
               "drive": drive_cost(plain_run, geared_run),
               "gear_summary": public_summary(gears)}
    if args.max_torque is not None:
        summary["checks"].update({"max_torque": args.max_torque, "torque_peak": checks.torque_peak,
                                  "torque_peak_at": checks.torque_peak_at})
    if args.tradeoff:
        log("optimising the transfer for each window of the trade-off …")
        from ..codesign.transfer import tradeoff
        rows = tradeoff(plain, centre_distance=options["centre_distance"], module=options["module"],
                        max_pressure_angle=options["max_pressure_angle"], ratio_bounds=options["ratio_bounds"],
                        seed=args.seed, max_torque=options["max_torque"])
        R.tradeoff_figure(rows, out / "tradeoff.png")
        summary["tradeoff"] = rows
    return summary


def _gait(run):
    """(GaitMetrics, GaitCurves) of a Study's walking leg, raising why when it has none."""
    if run.gait is None:
        from ..analysis.gait import gait_metrics_and_curves
        return gait_metrics_and_curves(run)           # raises the reason (the crank cannot turn fully)
    return run.gait, run.gait_curves


def summary_lines(s: dict) -> list[str]:
    c, o, v = s["checks"], s["outlines"], s["vx_spread"]
    lines = [f"window: central {s['window']:g} of the stride; centre distance {1000 * s['centre_distance']:.4g} mm",
             f"foot |v_x| spread, central 80 % / 90 %: before {v['before']['0.8']:.4g} / {v['before']['0.9']:.4g}; "
             f"after {v['after']['0.8']:.3g} / {v['after']['0.9']:.3g}",
             f"gears: {c['teeth']} teeth each, module {1000 * c['module']:.4g} mm; convex "
             f"{'yes' if min(c['convexity'].values()) >= 0 else 'no'} (least κ·L {min(c['convexity'].values()):.3g}); "
             f"max pressure angle {math.degrees(c['max_pressure_angle']):.3g}°; ratio "
             f"{c['ratio_range'][0]:.3g} … {c['ratio_range'][1]:.3g}",
             f"outlines: {'valid' if o['valid'] else 'NOT valid'}, "
             f"{'interference' if o['interference'] else 'no interference'}"]
    lines += drive_lines(s.get("drive"), c)
    lines += [f"  violation: {t}" for t in c["violations"]]
    lines += [f"  outline: {t}" for t in o["defects"]]
    lines += [f"  the rack cutter undercuts the working flanks of the {g} gear near body angle {u}"
              for g, u in zip(("motor", "crank"), o["undercut"]) if u]
    return lines


def drive_lines(drive, checks: dict) -> list[str]:
    """The drive's cost before → after (the summary's ``drive``), none for a leg without masses or loads."""
    if not drive:
        return []
    b, a = drive["before"], drive["after"]
    lines = [f"motor torque over one turn (uniform crank → uniform motor): peak {b['peak']:.4g} → {a['peak']:.4g} "
             f"N·m, RMS {b['rms']:.4g} → {a['rms']:.4g} N·m"
             + (f" (limit {checks['max_torque']:.4g} N·m)" if checks.get("max_torque") is not None else "")]
    joints = list(b["joint_peaks"]) + [k for k in a["joint_peaks"] if k not in b["joint_peaks"]]
    cells = [f"{k} {_load(b['joint_peaks'].get(k))} → {_load(a['joint_peaks'].get(k))} N" for k in joints]
    lines.append("peak bearing loads: " + "; ".join(cells))
    return lines


def _load(v) -> str:
    return "—" if v is None else f"{v:.4g}"
