"""The files of a co-designed geared leg (``assur codesign``): the geared mechanism file, its gear design file,
the gear outputs (outlines, mesh check), the before/after foot-speed figure, the animation and a JSON summary.

Conventions that tie the files together. The co-design law (:mod:`assur.codesign.law`) is θ(φ) = σ·q(φ) with φ
the motor's advance and θ the crank's advance in its own sense. In the mechanism file the crank's counter-clockwise
turn from the sketch is ``mesh·(L(x + phase) − L(phase))`` for the motor's counter-clockwise turn x. With an
external pair (mesh = −1): a crank that advances clockwise (D = σ_c·σ = −1) takes L = θ and a motor turning
counter-clockwise; a crank that advances counter-clockwise (D = +1) takes the mirrored law L(u) = −θ(−u) and a motor
turning clockwise. ``phase`` is the motor's law angle at the sketch (±τ(q_sketch)). The gear design file holds L,
so its pitch curves and outlines are the gears the mechanism turns.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

#: samples per turn of the law table written into the gear design file
TABLE_SAMPLES = 2048
#: manufacturing defaults of the written gear file (in modules, and mm)
TEETH_DEFAULTS = {"addendum": 1.0, "dedendum": 1.25, "clearance": 0.25, "tip_radius": 0.38, "face_width": 10.0,
                  "bore": 8.0}


def drive_law(law, driver) -> tuple:
    """(L, phase, motor sense) of the mechanism file for a co-design ``law`` and the leg's crank ``driver``:
    L(u) (u (...) → (...)) the written law, phase (rad), the motor driver's sense (±1)."""
    T = law.transmission_law()
    D = driver.sense * law.sense
    tau_s = float(law.motor_angle(np.asarray(law.foot.plan.sketch_inputs[0])))
    if D < 0:
        return (lambda u: T.theta(np.asarray(u, dtype=float))), tau_s, 1
    return (lambda u: -T.theta(-np.asarray(u, dtype=float))), -tau_s, -1


def gear_document(law, checks, L, *, name: str, pressure_angle: float) -> dict:
    """The ``assur-gears/1`` document (mm, deg) of the co-designed pair: the law L as a table over one motor turn,
    the centre distance, and envelope teeth with the whole tooth count and its module."""
    phi = np.linspace(0.0, 2 * math.pi, TABLE_SAMPLES + 1)      # the gear file's table spans the whole turn
    theta = L(phi)
    mm = 1000.0
    teeth = {"method": "envelope", "module": round(checks.module * mm, 9),
             "pressure_angle": round(math.degrees(pressure_angle), 9), "backlash": round(0.25 * checks.module * mm, 9),
             "driving_teeth": int(checks.teeth), "driven_teeth": int(checks.teeth)}
    bore = min(TEETH_DEFAULTS["bore"], 0.5 * min(checks.radius_driving[0], checks.radius_driven[0]) * mm)
    teeth.update({k: v for k, v in TEETH_DEFAULTS.items() if k != "bore"})
    teeth["bore"] = round(bore, 6)
    return {"format": "assur-gears/1", "name": f"{name}: co-designed drive",
            "description": (f"Non-circular gear pair from `assur codesign`: the motor (driving) gear turns uniformly and "
                            f"the crank (driven) gear makes the foot's horizontal speed constant over the central "
                            f"{law.fraction:g} of the stride, with a C² transfer law closing the cycle."),
            "units": {"length": "mm", "angle": "deg"},
            "law": {"kind": "table", "driving_turns": 1, "phi": [float(math.degrees(v)) for v in phi],
                    "theta": [float(math.degrees(v)) for v in theta]},
            "pair": {"centre_distance": round(checks.centre_distance * mm, 9)},
            "teeth": teeth}


def geared_document(m, law, gear_file: str, *, centre_distance: float, direction: float, pressure_angle: float) -> dict:
    """The mechanism document of the leg ``m`` driven by a motor at ``centre_distance`` (m) from the crank's pivot
    in the direction ``direction`` (rad, from +x) through the gear pair of ``gear_file``."""
    from ..io import units as U
    from ..io.mechanism_writer import as_dict
    d = as_dict(m)
    crank = m.drivers[0]
    Lf, Af = U.LENGTH[m.units.length], U.ANGLE[m.units.angle]
    names = set(m.point_names) | {lk.name for lk in m.links}
    motor, pivot, arm = (_fresh(n, names) for n in ("motor", "M", "M1"))
    O = np.asarray(m.sketch(crank.pivot)[:2], dtype=float)
    u = np.array([math.cos(direction), math.sin(direction)])
    M = O + centre_distance * u
    M1 = M + 0.5 * centre_distance * np.array([1.0, 0.0])
    d["points"][pivot] = [_clean(v / Lf) for v in M]
    d["points"][arm] = [_clean(v / Lf) for v in M1]
    frame = d["links"]["frame"]
    if isinstance(frame, dict):
        frame["points"] = list(frame["points"]) + [pivot]
    else:
        d["links"]["frame"] = list(frame) + [pivot]
    d["links"][motor] = {"points": [pivot, arm]}
    _, phase, sense = drive_law(law, crank)
    speed = abs(crank.speed) * 60.0 / (2 * math.pi)
    d["drivers"] = [{"name": motor, "kind": "rotary", "link": motor, "pivot": pivot, "arm": arm, "zero": 0.0,
                     "sense": "ccw" if sense > 0 else "cw", "speed": f"{speed:.12g} rpm"}]
    d["gears"] = [{"name": "drive", "a": motor, "b": crank.link, "law": gear_file, "mesh": "external",
                   "phase": _clean(phase / Af), "pressure_angle": _clean(pressure_angle / Af)}]
    d["description"] = (d.get("description", "") + f"\nDriven from a uniform motor through the co-designed "
                        f"non-circular gear pair of {gear_file} (`assur codesign`): the foot's horizontal speed is "
                        f"constant over the central {law.fraction:g} of the stride.").strip() + "\n"
    d["name"] = f"{m.name} (geared)" if m.name else "geared leg"
    if "dynamics" in d and isinstance(d["dynamics"], dict) and "drivers" in d["dynamics"]:
        d["dynamics"].pop("drivers")
    return d


def _clean(v: float) -> float:
    """A coordinate or angle rounded to 12 significant digits (no −0.0, no 1e-18 noise of a rotated axis)."""
    v = float(f"{v:.12g}")
    return 0.0 if abs(v) < 1e-12 else v


def _fresh(name: str, taken: set) -> str:
    out, k = name, 2
    while out in taken:
        out, k = f"{name}{k}", k + 1
    taken.add(out)
    return out


def foot_speed_figure(before, after, path: Path, *, fraction: float, dpi: int = 110) -> None:
    """|v_x| of the foot over the stride position (the window shaded), support samples only: the plain leg
    (uniform crank) and the geared leg (uniform motor). ``before``, ``after``: (GaitMetrics, GaitCurves) of
    :func:`assur.analysis.gait.gait_metrics_and_curves`."""
    from ..plot.draw import close, mpl
    _, plt = mpl()
    fig, ax = plt.subplots(figsize=(7.0, 4.2), dpi=dpi)
    for (metrics, curves), label, color in ((before, "uniform crank (before)", "0.45"),
                                            (after, "uniform motor, co-designed gears (after)", "tab:blue")):
        x = np.asarray(curves.x)
        on = np.asarray(curves.contact, dtype=bool)
        vx = np.abs(np.asarray(curves.vx))
        lo, hi = x[on].min(), x[on].max()
        s = (x - lo) / (hi - lo)
        order = np.argsort(s[on])
        ax.plot(s[on][order], vx[on][order], color=color, linewidth=2.0,
                label=f"{label}: spread(0.9) = {metrics.vx_spread['0.9']:.3g}")
    lo, hi = 0.5 - fraction / 2, 0.5 + fraction / 2
    ax.axvspan(lo, hi, color="tab:green", alpha=0.08, label=f"window: central {fraction:g} of the stride")
    ax.set_xlabel("foot position along the stride (0 … 1)")
    ax.set_ylabel("|v_x| of the foot on the ground [m/s]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower center")
    ax.set_title("Foot speed while carrying the body", fontsize=11)
    fig.tight_layout()
    fig.savefig(path)
    close(fig)


def tradeoff_figure(rows: list, path: Path, dpi: int = 110) -> None:
    """The trade-off of the window fraction f: vx spread over the central 90 % (left axis, log) and the least
    convexity κ·L of the two pitch curves and the centrode pressure angle (right axes)."""
    from ..plot.draw import close, mpl
    _, plt = mpl()
    ok = [r for r in rows if "error" not in r]
    f = np.array([r["fraction"] for r in ok])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.0, 3.8), dpi=dpi)
    spread = np.maximum([r["vx_spread_0.9"] for r in ok], 1e-12)
    a1.semilogy(f, spread, "o-", color="tab:blue")
    a1.axhline(0.01, color="tab:red", linestyle="--", linewidth=1, label="1 % target")
    a1.set_xlabel("window f (central fraction of the stride)")
    a1.set_ylabel("vx spread over the central 90 %")
    a1.grid(True, alpha=0.3)
    a1.legend(fontsize=8)
    conv = [r["convexity"] for r in ok]
    a2.plot(f, conv, "s-", color="tab:green", label="least κ·L of the two pitch curves (≥ 0 convex)")
    a2.axhline(0, color="0.3", linewidth=1)
    a2.set_xlabel("window f")
    a2.set_ylabel("κ·L")
    a3 = a2.twinx()
    a3.plot(f, [r["max_pressure_angle"] for r in ok], "^-", color="tab:orange", label="max pressure angle [°]")
    a3.axhline(30, color="tab:orange", linestyle=":", linewidth=1)
    a3.set_ylabel("centrode pressure angle [°]")
    h1, l1 = a2.get_legend_handles_labels()
    h2, l2 = a3.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower left")
    a2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    close(fig)


def summary_page(summary: dict, out: Path, lines: list[str]) -> str:
    """The summary page (``index.html``) of a co-design run: the summary ``lines`` (as printed), the drive's cost
    before/after as a table (a leg with masses or loads), the figures found in ``out`` and links to the files."""
    from ..version import __version__
    from .page import escape, header, page, png_tag, section, table
    title = f"Co-design of {Path(summary['leg']).stem}"
    body = header(title, f"{escape(summary['leg'])} — <code>assur codesign</code> — assur {escape(__version__)}")
    body.append(section("Summary", "<ul>\n" + "\n".join(f"<li>{escape(t)}</li>" for t in lines) + "\n</ul>"))
    drive = summary.get("drive")
    if drive:
        b, a = drive["before"], drive["after"]
        rows = [(f"peak motor torque [N·m] ({b['driver']} → {a['driver']})", _num(b["peak"]), _num(a["peak"])),
                ("RMS motor torque [N·m]", _num(b["rms"]), _num(a["rms"]))]
        joints = list(b["joint_peaks"]) + [k for k in a["joint_peaks"] if k not in b["joint_peaks"]]
        rows += [(f"peak bearing load at {k} [N]", _num(b["joint_peaks"].get(k)), _num(a["joint_peaks"].get(k)))
                 for k in joints]
        note = ('<p class="note">One force analysis of one turn each: the plain leg driven by a uniform crank, the '
                'geared leg by a uniform motor at the same mean crank speed (docs/codesign.md, "What the constant '
                'foot speed costs").</p>')
        body.append(section("The drive's cost", table(["", "before (plain leg)", "after (geared leg)"], rows,
                                                      num_cols=(1, 2)) + "\n" + note))
    figures = [png_tag((out / name).read_bytes(), alt) for name, alt in
               (("foot_speed.png", "foot speed before and after"), ("tradeoff.png", "the window's trade-off"))
               if (out / name).exists()]
    if (out / "animation.gif").exists():
        figures.append('<p><a href="animation.gif">animation.gif</a>: the leg and its gears over one motor turn.</p>')
    if figures:
        body.append(section("Figures", "\n".join(figures)))
    files = [summary["files"]["mechanism"], summary["files"]["gears"], "gears/", "codesign.json"]
    body.append(section("Files", "<ul>\n" + "\n".join(f'<li><a href="{escape(f)}">{escape(f)}</a></li>'
                                                      for f in files) + "\n</ul>"))
    return page(title, body)


def _num(v) -> str:
    return "—" if v is None else f"{v:.4g}"
