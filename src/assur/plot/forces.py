"""Figures of the force analysis (matplotlib, imported lazily): the driving torque (or actuator force) and
power against the input (:func:`torque_figure`), the reaction hodographs of the joints (:func:`hodograph_figure`),
the forces as arrows on the kinematic diagram at one input (:func:`arrows_figure`), Zhukovsky's lever
(:func:`lever_figure`) and all four on one sheet (:func:`forces_figure`). Forces in N, torques in N·m, power in W;
inputs in the file's units, lengths in the file's length unit.
"""
from __future__ import annotations

import math

import numpy as np

from ..kinetostatics.lever import lever
from ..kinetostatics.overview import ForceCycle
from .draw import draw_mechanism, file_scale, length_unit, mpl, set_limits


def _input_scale(plan):
    u = plan.mechanism.units
    if plan.input_kinds[0] == "rotary":
        return (math.pi / 180.0, "°") if u.angle == "deg" else (1.0, "rad")
    return 1.0 / file_scale(plan), u.length


def _cycle(source, steps) -> ForceCycle:
    """The ForceCycle of a ForceCycle, a Study (its force cycle) or a plan (a Study of ``steps`` samples)."""
    if isinstance(source, ForceCycle):
        return source
    from ..analysis.study import Study
    return Study.of(source, steps=steps).force_cycle


def constant_rate(effort, power) -> float | None:
    """The input's rate (rad/s or m/s) when ``power = rate · effort`` at every sample with the same rate (a crank at
    constant speed, a linear driver at constant speed), else None. ``effort``, ``power``: (n,)."""
    effort, power = np.asarray(effort, float), np.asarray(power, float)
    ok = np.isfinite(effort) & np.isfinite(power) & (np.abs(effort) > 1e-12 * np.nanmax(np.abs(effort), initial=0))
    if not ok.any():
        return None
    rate = power[ok] / effort[ok]
    r = float(np.median(rate))
    return r if np.all(np.abs(rate - r) <= 1e-9 * max(abs(r), 1e-300)) else None


def draw_torque(ax, cycle: ForceCycle) -> None:
    """The driving effort and the power against the input. At a constant input speed the power is the effort
    times that speed: one curve with two scales (the power's on the right axis, P = T·ω); two curves on twin
    axes only where the speed varies."""
    f = cycle.forces
    plan = f.plan
    fac, iu = _input_scale(plan)
    x = cycle.q / fac
    rotary = plan.input_kinds[0] == "rotary"
    effort = f.driver[:, 0]
    ax.plot(x, effort, color="C0", label="torque" if rotary else "force")
    ax.set_xlabel(f"{plan.input_names[0]} [{iu}]")
    ax.set_ylabel("driving torque [N·m]" if rotary else "actuator force [N]", color="C0")
    ax.axhline(0.0, color="0.6", linewidth=0.6)
    what = "torque" if rotary else "force"
    rate = constant_rate(effort, f.power)
    if rate is not None and rate != 0:
        sec = ax.secondary_yaxis("right", functions=(lambda t: t * rate, lambda p: p / rate))
        speed = f"ω = {rate:.4g} rad/s" if rotary else f"v = {rate:.4g} m/s"
        sec.set_ylabel(f"power [W] = {what} × {speed.split(' =')[0]}", color="C3")
        ax.set_title(f"driving {what}; power on the right scale ({speed} constant)")
    else:
        ax2 = ax.twinx()
        ax2.plot(x, f.power, color="C3", linestyle="--", label="power")
        ax2.set_ylabel("power [W]", color="C3")
        ax.set_title(f"driving {what} and power")
    ax.grid(True, alpha=0.3)


def draw_hodographs(ax, cycle: ForceCycle) -> None:
    """Polar plots of the reaction vectors over the cycle, one curve per joint (on polar axes ``ax``)."""
    f = cycle.forces
    for n, k in enumerate(f.joint_pairs):
        r = f.reactions[:, k, :2]
        mag = np.hypot(r[:, 0], r[:, 1])
        ang = np.arctan2(r[:, 1], r[:, 0])
        label = f"{f.pair_names[k]} ({f.pair_bodies[k][0]}–{f.pair_bodies[k][1]})"
        ax.plot(np.append(ang, ang[:1]), np.append(mag, mag[:1]), color=f"C{n % 10}", linewidth=1.2, label=label)
    ax.set_title("reaction hodographs [N]", pad=14)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.05, 1.0))


def _arrow_scale(span: float, vectors) -> float:
    mags = [abs(v) for v in vectors if np.isfinite(v) and abs(v) > 0]
    return 0.25 * span / max(mags) if mags else 0.0


def draw_arrows(ax, plan, at: float, params=None) -> None:
    """The mechanism at input ``at`` (SI) with the reactions on the later bodies (blue) and the applied
    forces (red) as arrows; arrow lengths are proportional to the forces (the longest a quarter of the drawing)."""
    from ..kinetostatics import forces
    f = forces(plan, params, np.array([[at]]))
    lv = lever(plan, params, np.array([[at]]))
    pos = np.asarray(f.state.pos)[0]
    s = file_scale(plan)
    draw_mechanism(ax, plan, pos, params=params, color="0.55", labels=True)
    pts = pos[np.isfinite(pos).all(axis=1)] * s
    span = float(np.ptp(pts, axis=0).max()) if len(pts) else 1.0
    reac = [complex(*f.reactions[0, k, :2]) for k in f.joint_pairs]
    applied = list(lv.forces[0])
    k_ = _arrow_scale(span, reac + applied)
    tips = []              # the arrows' heads: the limits include them (an arrow is never clipped)
    for k, r in zip(f.joint_pairs, reac):
        name = f.pair_names[k]
        if f.pair_kinds[k] == "R":
            p = pos[plan.point_index(name)] * s
        else:
            rec = next(r_ for r_ in plan.lines if r_[1] == name)
            p = pos[plan.point_index(rec[7])] * s
        if np.isfinite(r) and r:
            ax.annotate("", xy=(p[0] + k_ * r.real, p[1] + k_ * r.imag), xytext=(p[0], p[1]),
                        arrowprops=dict(arrowstyle="->", color="C0", linewidth=1.4))
            ax.text(p[0] + k_ * r.real, p[1] + k_ * r.imag, f" {abs(r):.3g} N", color="C0", fontsize=7)
            tips.append((p[0] + k_ * r.real, p[1] + k_ * r.imag))
    for z, F in zip(lv.points[0], applied):
        if np.isfinite(F) and F:
            ax.annotate("", xy=(z.real * s + k_ * F.real, z.imag * s + k_ * F.imag), xytext=(z.real * s, z.imag * s),
                        arrowprops=dict(arrowstyle="->", color="C3", linewidth=1.4))
            tips.append((z.real * s + k_ * F.real, z.imag * s + k_ * F.imag))
    fac, iu = _input_scale(plan)
    ax.set_title(f"forces at {plan.input_names[0]} = {at / fac:.4g} {iu} (blue: reactions, red: applied)")
    ax.set_xlabel(f"x [{length_unit(plan)}]")
    ax.set_ylabel(f"y [{length_unit(plan)}]")
    set_limits(ax, np.vstack([pts] + ([np.array(tips)] if tips else [])))
    ax.set_aspect("equal")


def draw_lever(ax, plan, at: float, params=None) -> float:
    """Zhukovsky's lever at input ``at`` (SI): the velocity plan turned 90° (ccw) about its pole, the applied
    forces at their points' images. Returns the lever's moment sum (W), which equals driver × speed."""
    lv = lever(plan, params, np.array([[at]]))
    img, F = lv.images[0], lv.forces[0]
    ax.plot([0.0], [0.0], "ko")
    ax.annotate("pole", (0.0, 0.0), textcoords="offset points", xytext=(4, 4), fontsize=7)
    span = max([abs(z) for z in img if np.isfinite(z)] + [1e-12])
    k_ = _arrow_scale(span * 2.0, list(F))
    tips = []
    for n, (z, f, name) in enumerate(zip(img, F, lv.bodies)):
        ax.plot([0.0, z.real], [0.0, z.imag], color="0.7", linewidth=0.8)
        ax.plot([z.real], [z.imag], "o", color=f"C{n % 10}", markersize=3)
        ax.annotate("", xy=(z.real + k_ * f.real, z.imag + k_ * f.imag), xytext=(z.real, z.imag),
                    arrowprops=dict(arrowstyle="->", color="C3", linewidth=1.2))
        ax.annotate(name, (z.real, z.imag), textcoords="offset points", xytext=(3, -8), fontsize=6)
        if np.isfinite(f):
            tips.append([z.real + k_ * f.real, z.imag + k_ * f.imag])
    m = float(lv.moment[0])
    fac, iu = _input_scale(plan)
    ax.set_title(f"Zhukovsky's lever at {at / fac:.4g} {iu}: Σ moment = {m:.4g} W (= driver × speed)", fontsize=9)
    ax.set_xlabel("i·v, x [m/s]")
    ax.set_ylabel("i·v, y [m/s]")
    pts = np.array([[z.real, z.imag] for z in img if np.isfinite(z)] + [[0.0, 0.0]] + tips)
    set_limits(ax, pts, margin=0.3)
    ax.set_aspect("equal")
    return m


def _default_at(cycle: ForceCycle) -> float:
    """The input of the largest driving effort (where the forces matter most), else the first valid one."""
    Q = np.abs(cycle.forces.driver[:, 0])
    if np.isfinite(Q).any():
        return float(cycle.q[int(np.nanargmax(Q))])
    return float(cycle.q[0])


def _one_panel(draw, figsize, dpi, projection=None):
    """A figure of one panel drawn by ``draw(ax)``."""
    _, plt = mpl()
    fig = plt.figure(figsize=figsize, dpi=dpi)
    draw(fig.add_subplot(projection=projection))
    fig.tight_layout()
    return fig


def torque_figure(plan, steps: int = 360, *, cycle=None, dpi: int = 100):
    """Driving torque (or actuator force) and power against the input."""
    return _one_panel(lambda ax: draw_torque(ax, cycle or _cycle(plan, steps)), (7, 3.6), dpi)


def hodograph_figure(plan, steps: int = 360, *, cycle=None, dpi: int = 100):
    """The reaction hodographs (polar) of every joint over the cycle."""
    return _one_panel(lambda ax: draw_hodographs(ax, cycle or _cycle(plan, steps)), (7, 4.5), dpi, "polar")


def arrows_figure(plan, at: float, *, dpi: int = 100):
    """The forces as arrows on the kinematic diagram at input ``at`` (SI)."""
    return _one_panel(lambda ax: draw_arrows(ax, plan, at), (7, 5), dpi)


def lever_figure(plan, at: float, *, dpi: int = 100):
    """Zhukovsky's lever at input ``at`` (SI)."""
    return _one_panel(lambda ax: draw_lever(ax, plan, at), (6, 6), dpi)


def forces_figure(plan, steps: int = 360, *, at: float | None = None, cycle=None, dpi: int = 100):
    """One sheet: torque and power, the reaction hodographs, the forces on the diagram and Zhukovsky's lever at
    ``at`` (SI; default: the input of the largest driving effort)."""
    _, plt = mpl()
    cycle = cycle or _cycle(plan, steps)
    plan = cycle.forces.plan
    at = _default_at(cycle) if at is None else float(at)
    fig = plt.figure(figsize=(13, 10), dpi=dpi)
    draw_torque(fig.add_subplot(2, 2, 1), cycle)
    draw_hodographs(fig.add_subplot(2, 2, 2, projection="polar"), cycle)
    draw_arrows(fig.add_subplot(2, 2, 3), plan, at)
    draw_lever(fig.add_subplot(2, 2, 4), plan, at)
    fig.tight_layout()
    return fig
