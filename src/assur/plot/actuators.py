"""Figures of linear actuators along a working stroke, in the style of paper 002's Figs. 4–7.

(a) angular velocities ω and (b) angular accelerations ε of every actuator rod against time, for
one or several constant driving speeds (or the driver's table law); (c) K_ω = ω_b/ω_l and the ratio
of areal velocities of each rod pair against the driving rod's extension s1 (both independent of
the speed); (d) the rods' length changes against s1. For paper 002's layout, (a) also shows the
paper's eq. (12) with V2 frozen at its start value (dashed), which parts from the exact curve and
breaks off where its square root turns negative. matplotlib is imported lazily (Agg backend).
"""
from __future__ import annotations

import numpy as np

from ..analysis.actuators import actuator_motions, rod_pairs
from ..analysis.timelaw import ConstantSpeed, TableLaw, driver_law, solve_in_time
from ..errors import SpecError
from ..io.units import LENGTH
from .draw import mpl


def actuator_figure(plan, params=None, *, speeds=None, stroke=None, steps: int = 300, figsize=(14, 9.5),
                    dpi: int = 100):
    """The four panels above for a one-input plan with a linear driver. ``speeds`` (m/s): constant
    driving speeds to compare (default: the driver's speed, or its table law); ``stroke`` (m, the
    driving rod's length range; default the driver's ``range``). Returns a matplotlib Figure."""
    _, plt = mpl()
    if plan.n_inputs != 1 or plan.input_kinds[0] != "linear":
        raise SpecError([("drivers", "actuator figures need a single linear driver")])
    d = plan.mechanism.drivers[0]
    q0 = float(plan.sketch_inputs[0])
    laws = []
    if speeds is None:
        law = driver_law(plan, 0, stroke)
        laws = [(law, "table law" if isinstance(law, TableLaw) else f"V1 = {plan.speeds[0]:g} m/s")]
    else:
        rng = stroke if stroke is not None else d.range
        if rng is None:
            driver_law(plan)   # the SpecError naming the missing range
        laws = [(ConstantSpeed.over(q0, float(v), rng), f"V1 = {float(v):g} m/s") for v in speeds]
    k_len = 1.0 / LENGTH[plan.mechanism.units.length]
    unit = plan.mechanism.units.length
    fig, axes = plt.subplots(2, 2, figsize=figsize, dpi=dpi)
    (ax_w, ax_e), (ax_k, ax_s) = axes
    styles = ["-", "--", ":", "-."]
    colours = {}
    first = None
    for n_law, (law, label) in enumerate(laws):
        t = np.linspace(law.t_start, law.t_end, steps)
        st = solve_in_time(plan, law, t, params)
        mot = actuator_motions(st)
        if first is None:
            first = (t, st, mot, law)
        for i, (name, mo) in enumerate(mot.items()):
            c = colours.setdefault(name, f"C{len(colours)}")
            ls = styles[n_law % len(styles)]
            ax_w.plot(t, mo.omega, color=c, linestyle=ls, label=f"ω {name}, {label}")
            ax_e.plot(t, mo.alpha, color=c, linestyle=ls, label=f"ε {name}, {label}")
    t, st, mot, law = first
    # the paper's eq. (12) with V2 frozen, for paper 002's layout at the first speed
    from ..analysis.lever import lever_layout, paper_formulas
    lay = lever_layout(plan, params)
    if lay is not None and isinstance(law, ConstantSpeed) and law.t_start == 0:
        g = lay.geometry
        v1 = law.speed
        v2_0 = float(g.exact(np.array([0.0]), v1)["V2"][0])
        lit = paper_formulas(g, t, v1, v2_0)
        for ax, key, sym in ((ax_w, "omega_phi (12)", "ω"), (ax_e, "eps_phi (16)", "ε")):
            exact = np.concatenate([ln.get_ydata() for ln in ax.lines])
            lo, hi = np.nanmin(exact), np.nanmax(exact)
            pad = 0.25 * max(hi - lo, 1e-12)
            lit_v = lay.sign * lit.values[key]
            if np.isfinite(lit_v).any():
                ax.plot(t, lit_v, color=colours.get(lay.driven, "k"), linestyle=(0, (1, 1)), linewidth=1.6,
                        label=f"paper eq. {key.split()[-1]} for {sym} {lay.driven}, V2 frozen at {v2_0:.4g} m/s")
                ax.set_ylim(lo - pad, hi + pad)   # the literal formula diverges: keep the exact curves in view
    for ax, name, u in ((ax_w, "angular velocity", "rad/s"), (ax_e, "angular acceleration", "rad/s²")):
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        ax.set_xlabel("time t [s]")
        ax.set_ylabel(f"{name} [{u}]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=7)
    ax_w.set_title("(a) angular velocities of the rods (paper Figs. 4, 5)")
    ax_e.set_title("(b) angular accelerations of the rods (paper Figs. 6, 7)")
    # (c), (d) against the driving rod's extension s1: independent of the speed
    s1 = (st.inputs[..., 0] - q0) * k_len
    for p in rod_pairs(st, mot):
        ax_k.plot(s1, p.K_omega, color="tab:purple", linewidth=2.0, label=f"K_ω = ω {p.driven} / ω {p.driving}")
        ax_k.plot(s1, p.areal_ratio, color="tab:green", linewidth=2.0, linestyle="--",
                  label=f"areal-velocity ratio (L² ω) {p.driven} / {p.driving}")
    ax_k.set_title("(c) K_ω and the ratio of areal velocities (constant for a straight guide)")
    ax_k.set_xlabel(f"extension s1 of {d.actuator} [{unit}]")
    ax_k.grid(True, alpha=0.3)
    if ax_k.lines:
        ax_k.legend(loc="best", fontsize=8)
    for name, mo in mot.items():
        ax_s.plot(s1, mo.extension * k_len, color=colours[name], linewidth=1.8, label=f"L − L₀ of {name}")
    ax_s.axhline(0.0, color="0.5", linewidth=0.6)
    ax_s.set_title("(d) length changes of the rods")
    ax_s.set_xlabel(f"extension s1 of {d.actuator} [{unit}]")
    ax_s.set_ylabel(f"length change [{unit}]")
    ax_s.grid(True, alpha=0.3)
    ax_s.legend(loc="best", fontsize=8)
    bad = int(st.n_unbuildable)
    fig.suptitle(f"{plan.mechanism.name or 'mechanism'}: actuators along the stroke"
                 + (f" ({bad} of {len(t)} samples cannot be assembled)" if bad else ""), fontsize=12)
    fig.subplots_adjust(left=0.06, right=0.985, bottom=0.07, top=0.91, wspace=0.22, hspace=0.32)
    return fig
