"""Figures of instant centres and centrodes (matplotlib, imported lazily).

:func:`centres_figure`: the mechanism at one input with every relative instant centre (labelled by its two bodies'
numbers, the frame 0) and Kennedy's lines (each triple of bodies' three centres on one line; a centre at infinity
drawn as an arrow along its direction); :func:`centrodes_figure`: the fixed centrode of a body relative to the frame,
its moving centrode at a few inputs (rolling on it), and the inflection circle at one input. Lengths in the file's
length unit.
"""
from __future__ import annotations

import math

import numpy as np

from .draw import draw_mechanism, file_scale, length_unit, mpl, set_limits


def centres_figure(study, q: float, *, kennedy: bool = True, dpi: int = 100):
    """All relative instant centres at input ``q`` (rad or m of the moving input)."""
    _, plt = mpl()
    plan = study.plan
    k = file_scale(plan)
    ic = study.centres_at([q])
    st = study.state_at(np.array([q]))
    fig, ax = plt.subplots(figsize=(9, 7.5), dpi=dpi)
    draw_mechanism(ax, plan, st.pos[0], params=study.params, color="C0", labels=True)
    pts, dirs = ic.points[0], ic.directions[0]
    mech = st.pos[0] * k
    span = float(max(np.ptp(mech[:, 0]), np.ptp(mech[:, 1])) or 1.0)
    shown = [p * k for p in pts if np.isfinite(p) and abs(p * k - complex(*mech.mean(axis=0))) < 4 * span]
    box = np.array([[z.real, z.imag] for z in shown] + list(mech))
    set_limits(ax, box, margin=0.1)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    reach = 3 * max(x1 - x0, y1 - y0)
    if kennedy:
        for (i, j, l), pair in ic.kennedy_lines(0):
            zs = [pts[c] for c in pair]
            finite = [z * k for z in zs if np.isfinite(z)]
            if len(finite) >= 2:
                a, b = finite[0], finite[-1]
                if abs(b - a) > 1e-12 * span:
                    u = (b - a) / abs(b - a)
                    ax.plot([(a - reach * u).real, (a + reach * u).real], [(a - reach * u).imag, (a + reach * u).imag],
                            color="0.75", linewidth=0.6, zorder=1)
            elif len(finite) == 1:
                d = next(dirs[c] for c, z in zip(pair, zs) if not np.isfinite(z) and np.isfinite(dirs[c]))
                a = finite[0]
                ax.plot([(a - reach * d).real, (a + reach * d).real], [(a - reach * d).imag, (a + reach * d).imag],
                        color="0.75", linewidth=0.6, zorder=1)
    for c, (i, j) in enumerate(ic.pairs):
        z = pts[c]
        label = f"{i}{j}" if max(i, j) < 10 else f"{i},{j}"
        if np.isfinite(z):
            ax.plot(z.real * k, z.imag * k, "o", color="C3", markersize=5, zorder=6)
            ax.annotate(label, (z.real * k, z.imag * k), xytext=(4, -10), textcoords="offset points", fontsize=8,
                        color="C3", zorder=7)
        elif np.isfinite(dirs[c]):
            d = dirs[c]
            cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
            r = 0.45 * min(x1 - x0, y1 - y0)
            ax.annotate(f"{label} → ∞", (cx + r * d.real, cy + r * d.imag), fontsize=8, color="C3")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    names = ", ".join(f"{i} {b}" for i, b in enumerate(ic.bodies))
    unit = "°" if plan.input_kinds[study.moving] == "rotary" else plan.mechanism.units.length
    shown_q = math.degrees(q) if unit == "°" else q * k
    ax.set_title(f"{len(ic.pairs)} instant centres at {plan.input_names[study.moving]} = {shown_q:.4g}{unit}"
                 f"\nbodies: {names}", fontsize=9)
    ax.set_xlabel(f"x [{length_unit(plan)}]")
    ax.set_ylabel(f"y [{length_unit(plan)}]")
    fig.tight_layout()
    return fig


def centrodes_figure(study, body: str, *, fixed: str = "frame", at: float | None = None, positions: int = 4,
                     dpi: int = 100):
    """The fixed and moving centrodes of ``body`` relative to ``fixed`` over the run, the moving one drawn at
    ``positions`` inputs, and (relative to the frame) the inflection circle at ``at``."""
    _, plt = mpl()
    plan = study.plan
    k = file_scale(plan)
    c = study.centrodes(body, fixed)
    st = study.state
    n = len(study.q)
    b = plan.body_names.index(body)
    f = plan.body_names.index(fixed)
    fig, ax = plt.subplots(figsize=(9, 7), dpi=dpi)
    g = plan.structure.graph
    first = plan.point_index(g.bodies[b].points[0])
    ffirst = plan.point_index(g.bodies[f].points[0])
    span = float(np.ptp(st.pos[..., 0]) + np.ptp(st.pos[..., 1])) * k
    ok = np.isfinite(c.world) & (np.abs(c.world * k) < 5 * span)
    idx = np.linspace(0, n - 1, positions, dtype=int)
    for s in idx:
        draw_mechanism(ax, plan, st.pos[s], params=study.params, color="0.6", alpha=0.5, linewidth=1.3)
        e = np.exp(1j * st.body_angle[s, b])
        o = complex(*st.pos[s, first])
        mv = (o + e * c.moving_curve) * k
        good = ok & np.isfinite(mv)
        ax.plot(np.where(good, mv.real, np.nan), np.where(good, mv.imag, np.nan), color="C1", linewidth=1.0)
    ef = np.exp(1j * st.body_angle[0, f])
    of = complex(*st.pos[0, ffirst]) if f else 0j
    fx = (of + ef * c.fixed_curve) * k
    ax.plot(np.where(ok, fx.real, np.nan), np.where(ok, fx.imag, np.nan), color="C0", linewidth=1.6,
            label=f"fixed centrode ({body} on {fixed})")
    ax.plot([], [], color="C1", label=f"moving centrode (on {body})")
    if at is not None and fixed == "frame":
        i = int(np.argmin(np.abs(study.q - at)))
        infl = study.inflection(body)
        ctr, dia = infl.centre[i] * k, infl.diameter[i] * k
        if np.isfinite(ctr) and dia < 10 * span:
            t = np.exp(1j * np.linspace(0, 2 * math.pi, 200))
            circ = ctr + 0.5 * dia * t
            ax.plot(circ.real, circ.imag, color="C2", linewidth=1.0, linestyle="--", label="inflection circle")
            P, J = infl.pole[i] * k, infl.inflection_pole[i] * k
            ax.plot([P.real, J.real], [P.imag, J.imag], "o", color="C2", markersize=4)
            ax.annotate("P", (P.real, P.imag), xytext=(4, 4), textcoords="offset points", fontsize=8)
            ax.annotate("J", (J.real, J.imag), xytext=(4, 4), textcoords="offset points", fontsize=8)
    pts = np.column_stack([np.concatenate([fx[ok].real, st.pos[idx, :, 0].ravel() * k]),
                           np.concatenate([fx[ok].imag, st.pos[idx, :, 1].ravel() * k])])
    set_limits(ax, pts, margin=0.1)
    ax.set_xlabel(f"x [{length_unit(plan)}]")
    ax.set_ylabel(f"y [{length_unit(plan)}]")
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"centrodes of {body} relative to {fixed}", fontsize=10)
    fig.tight_layout()
    return fig
