"""``assur sensitivity FILE``: exact derivatives of outputs by every parameter, ranked; tolerance bands, a Monte Carlo
and joint clearance (docs/sensitivity.md).

The parameters are ranked by their influence on each output: the largest |∂y/∂p|·t over the run, t the parameter's
tolerance (ISO 286 IT9 on its size unless ``--it`` or ``--tolerance`` say otherwise). ``--band P`` adds the
worst-case and RSS band round P's path, ``--monte-carlo N`` N random designs on the batched engine (the buildable
fraction and where the first-order band fails), ``--clearance C`` (diametral, file length unit; ``J=C`` per joint) the
effective-link error of P with a Monte Carlo of random clearance directions. ``-o OUT.png`` draws the figures.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.sampling import CYCLE_STEPS
from ..errors import SpecError
from ..io.output import atomic_file
from .args import PLOT_EXTENSIONS, compile_file, output_path, positive, seed_arg

DEFAULT_STEPS = 360


def register(sub) -> None:
    """Add ``assur sensitivity`` to the argparse sub-parsers ``sub``."""
    help_ = "exact sensitivities of outputs to every parameter, ranked by tolerance; bands, Monte Carlo, clearance"
    sp = sub.add_parser("sensitivity", help=help_, description=help_)
    sp.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    sp.add_argument("--of", action="append", metavar="OUTPUT",
                    help="an output: P.x, P.y, P.vx, link.angle, mu.J, DRIVER.effort, R.P, gait.step, gait.lift … "
                         "(repeatable; default: the gait's step and lift, or the tracked point's x and y)")
    sp.add_argument("--steps", type=positive(16), default=DEFAULT_STEPS, metavar="N",
                    help=f"samples of the turn (default {DEFAULT_STEPS})")
    sp.add_argument("--top", type=positive(1), default=8, metavar="K", help="parameters shown (default 8)")
    sp.add_argument("--it", default="IT9", metavar="GRADE", help="ISO 286 grade of every length (default IT9)")
    sp.add_argument("--tolerance", action="append", default=[], metavar="NAME=VALUE",
                    help="a parameter's tolerance ± in the file's units, or NAME=IT7 (repeatable)")
    sp.add_argument("--band", metavar="POINT", help="the tolerance band round this point's path")
    sp.add_argument("--monte-carlo", type=positive(1), default=None, metavar="N",
                    help="N random designs within the tolerances, on the batched engine (with --band)")
    sp.add_argument("--clearance", action="append", default=[], metavar="C",
                    help="diametral clearance of every revolute (file length unit), or JOINT=C (repeatable; with "
                         "--band, or the tracked point)")
    sp.add_argument("--seed", type=seed_arg, default=1, help="the Monte Carlo's random seed (default 1)")
    sp.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    sp.add_argument("-o", "--output", type=output_path(PLOT_EXTENSIONS[:3]), metavar="OUT",
                    help="write the figures (.png, .svg, .pdf)")
    sp.set_defaults(func=cmd_sensitivity)


def _defaults(plan, sens) -> list[str]:
    from ..analysis.sampling import tracked_point
    if plan.mechanism.gait is not None and sens.gait():
        return ["gait.step", "gait.lift"]
    p = tracked_point(plan)
    return [f"{p}.x", f"{p}.y"]


def _clearances(plan, specs):
    from ..io.units import LENGTH
    f = LENGTH[plan.mechanism.units.length]
    every, per = None, {}
    for s in specs:
        name, sep, value = str(s).partition("=")
        try:
            v = float(value if sep else name) * f
        except ValueError:
            raise SpecError([("--clearance", f"{s!r}: give a clearance (file length unit) or JOINT=C")]) from None
        if not (v >= 0 and math.isfinite(v)):
            raise SpecError([("--clearance", f"{s!r}: a clearance must be ≥ 0")])
        if sep:
            per[name.strip()] = v
        else:
            every = v
    if every is None:
        return per
    return {"*": every, **per}


def cmd_sensitivity(args) -> int:
    from ..analysis.sensitivity.tolerance import envelope, parse_tolerances, path_band
    from ..analysis.study import Study
    from ..io.output import json_text
    from ..plot.sensitivity import display, influence
    m, plan = compile_file(args.file)
    if plan.dimension != 2:
        raise SpecError([("file", "sensitivities are computed for planar mechanisms")])
    if args.monte_carlo and not args.band:
        raise SpecError([("--monte-carlo", "needs --band POINT (the path whose band it checks)")])
    if args.band and args.band not in plan.point_names:
        raise SpecError([("--band", f"unknown point {args.band!r} (known: {', '.join(plan.point_names)})")])
    study = Study(plan, steps=args.steps)
    sens = study.sensitivity
    tol = parse_tolerances(plan, args.tolerance, args.it)
    names = args.of or _defaults(plan, sens)
    outs = {n: sens[n] for n in names}
    report: dict = {"file": str(args.file), "parameters": list(plan.param_names), "tolerances": tol.as_rows(plan),
                    "outputs": {}}
    for n, o in outs.items():
        score = influence(sens, n, tol)
        env = envelope(o, tol)
        dmax = np.nanmax(np.abs(np.atleast_2d(o.derivative)), axis=0)
        report["outputs"][n] = {
            "unit": o.unit,
            "value": float(o.value) if np.ndim(o.value) == 0 else {"min": float(np.nanmin(o.value)),
                                                                    "max": float(np.nanmax(o.value))},
            "worst_case": float(np.nanmax(env.worst)), "rss": float(np.nanmax(env.rss)),
            "influence": {p: float(score[k]) for k, p in enumerate(plan.param_names)},
            "derivative_max": {p: float(dmax[k]) for k, p in enumerate(plan.param_names)}}
    band = mc = clr = None
    point = args.band
    if args.band:
        band = path_band(sens, args.band, tol)
        report["band"] = {"point": args.band, "worst_case_max": float(np.nanmax(band.worst)),
                          "rss_max": float(np.nanmax(band.rss))}
        if args.monte_carlo:
            from ..analysis.sensitivity.montecarlo import monte_carlo
            mc = monte_carlo(study, band, tol, args.monte_carlo, seed=args.seed)
            report["monte_carlo"] = {"samples": mc.samples, "buildable": mc.buildable,
                                     "buildable_fraction": mc.buildable_fraction,
                                     "largest_ratio_to_worst_case": _finite(np.nanmax(mc.ratio)),
                                     "inputs_beyond_worst_case": mc.failures(study.q)}
    if args.clearance:
        from ..analysis.sampling import tracked_point
        from ..analysis.sensitivity.clearance import clearance, joint_names
        spec = _clearances(plan, args.clearance)
        point = point or tracked_point(plan)
        every = spec.pop("*", None)
        if every is not None:
            from ..analysis.sensitivity.closure import Closure
            spec = {n: spec.get(n, every) for n in joint_names(plan, Closure(plan))}
        clr = clearance(study, point, spec, samples=min(args.monte_carlo or 200, 2000), seed=args.seed)
        report["clearance"] = {"point": point, "joints": dict(zip(clr.joints, (2 * clr.radius).tolist())),
                               "worst_case_max": float(np.nanmax(clr.worst)),
                               "effective_max": float(np.nanmax(np.linalg.norm(clr.effective, axis=-1))),
                               "monte_carlo_max": None if clr.monte_carlo is None else
                               float(np.nanmax(clr.monte_carlo)),
                               "contact_loss": clr.contact_loss}
    if args.json:
        print(json_text(report))
    else:
        _print(plan, args, study, sens, tol, outs, report, band, mc, clr, display)
    if args.output:
        _figures(args, study, sens, names, tol, band, mc, clr)
    return 0


def _finite(x):
    x = float(x)
    return x if math.isfinite(x) else None


def _print(plan, args, study, sens, tol, outs, report, band, mc, clr, display):
    from ..io.units import ANGLE, LENGTH
    from ..plot.draw import file_scale, length_unit
    u = plan.mechanism.units
    L = length_unit(plan)
    print(f"{plan.mechanism.name or args.file}  [{args.file}]: exact sensitivities over {len(study.q)} samples; "
          f"tolerances ±t ({args.it} unless given)")
    first = next(iter(outs))
    order = np.argsort([-report["outputs"][first]["influence"][p] for p in plan.param_names])[:args.top]
    heads = ["parameter", "nominal", "±t"] + [f"{n} [{display(plan, o.unit)[1]}]" for n, o in outs.items()]
    rows = []
    for k in order:
        name = plan.param_names[k]
        angle = plan.param_kind_of(name) == "angle"
        f = ANGLE[u.angle] if angle else LENGTH[u.length]
        row = [name, f"{plan.defaults[k] / f:.6g}", f"{tol.half[k] / f:.3g}"]
        for n, o in outs.items():
            fac, _ = display(plan, o.unit)
            row.append(f"{report['outputs'][n]['influence'][name] * fac:.4g}")
        rows.append(row)
    widths = [max(len(str(r[i])) for r in rows + [heads]) for i in range(len(heads))]
    print("  " + "  ".join(h.ljust(w) for h, w in zip(heads, widths)))
    for r in rows:
        print("  " + "  ".join(str(c).ljust(w) for c, w in zip(r, widths)))
    print("  (each output column: the largest |∂y/∂p|·t over the run; ranked by the first)")
    for n, o in outs.items():
        fac, unit = display(plan, o.unit)
        r = report["outputs"][n]
        print(f"  {n}: worst case ±{r['worst_case'] * fac:.4g} {unit}, RSS ±{r['rss'] * fac:.4g} {unit} (largest over "
              f"the run)")
    k = file_scale(plan)
    if band is not None:
        print(f"band round {band.point}: worst case ±{np.nanmax(band.worst) * k:.4g} {L}, RSS ±{np.nanmax(band.rss) * k:.4g}"
              f" {L} (along the path's normal, largest over the run)")
    if mc is not None:
        fails = mc.failures(study.q)
        where = "nowhere" if not fails else f"at {len(fails)} of {len(study.q)} inputs"
        print(f"Monte Carlo: {mc.samples} designs, {100 * mc.buildable_fraction:.2f} % buildable; the worst-case band "
              f"is exceeded {where} (largest deviation / band: {np.nanmax(mc.ratio):.3f})")
    if clr is not None:
        print(f"clearance at {', '.join(f'{j} {2 * r * k:g} {L}' for j, r in zip(clr.joints, clr.radius) if r > 0)}: "
              f"error of {clr.point} up to {np.nanmax(np.linalg.norm(clr.effective, axis=-1)) * k:.4g} {L} (effective "
              f"links), worst case {np.nanmax(clr.worst) * k:.4g} {L}" +
              (f", Monte Carlo {np.nanmax(clr.monte_carlo) * k:.4g} {L}" if clr.monte_carlo is not None else ""))
        for joint, where in clr.contact_loss.items():
            fac = 180 / math.pi if plan.input_kinds[0] == "rotary" else k
            print(f"  contact loss at {joint}: the reaction nears zero at {len(where)} inputs "
                  f"({', '.join(f'{w * fac:.4g}' for w in where[:6])}{' …' if len(where) > 6 else ''})")


def _figures(args, study, sens, names, tol, band, mc, clr):
    from ..plot.draw import close
    from ..plot.sensitivity import band_figure, clearance_figure, sensitivity_figure
    figs = [sensitivity_figure(sens, names, tol, top=min(args.top, 6))]
    if band is not None:
        figs.append(band_figure(study, band, mc))
    if clr is not None:
        figs.append(clearance_figure(study, clr))
    ext = args.output.suffix.lower()
    paths = [args.output] + [args.output.with_name(f"{args.output.stem}_{tag}{args.output.suffix}")
                             for tag in (["band"] if band is not None else []) + (["clearance"] if clr else [])]
    try:
        for fig, path in zip(figs, paths):
            with atomic_file(path) as tmp:
                fig.savefig(tmp, format=ext[1:])
            print(f"wrote {path}")
    finally:
        for fig in figs:
            close(fig)
