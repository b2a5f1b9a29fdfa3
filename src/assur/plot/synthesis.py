"""The figure of a synthesis result (``assur synth … --plot BEST.png``, the synthesis page of ``assur report``).

Three panels: (a) the task — point targets against the achieved path, poses (target frames against the
achieved coupler frames), or the function curve (target pairs against the achieved output curve), with the
best design drawn at its first target; (b) the distance of each target; (c) the convergence history, the best
value of the optimiser's scalar against the evaluations (infeasible stretches marked). Lengths and angles in the
problem file's units.
"""
from __future__ import annotations

import numpy as np

from ..io.units import ANGLE
from .draw import draw_mechanism, file_scale, mpl, set_limits

TWO_PI = 2.0 * np.pi


def _wrap(a):
    return np.mod(a + np.pi, TWO_PI) - np.pi


def _solved(result, q):
    """The best design solved at inputs q (M,)."""
    from ..engine import solve
    plan = result.problem.plan
    return solve(plan, result.params(), q[:, None] if plan.n_inputs == 1 else q, order=0)


def _target_inputs(result):
    from ..synthesis.evaluate import Evaluator
    t = result.problem.targets
    if t is None or t.timing == "path":
        return None
    return Evaluator(result.problem).target_inputs(result.x[None, :])[0]


def _frames(ax, xy, angles, size, color, label, k):
    """Short arrows along the link's line at each pose (file units)."""
    d = np.stack([np.cos(angles), np.sin(angles)], axis=-1) * size
    ax.quiver(xy[:, 0] * k, xy[:, 1] * k, d[:, 0], d[:, 1], angles="xy", scale_units="xy", scale=1.0, color=color,
              width=0.006, label=label, zorder=5)


def _task_plane(ax, result, q, st, theta):
    """Points or poses: the targets, the achieved path and positions, the design at its first target."""
    pb = result.problem
    t, plan = pb.targets, pb.plan
    k = file_scale(plan)
    i = plan.point_index(t.point)
    path = st.pos[:, i, :]
    ok = st.valid
    ax.plot(np.where(ok, path[:, 0], np.nan) * k, np.where(ok, path[:, 1], np.nan) * k, "-", color="C0", lw=1.2,
            label=f"path of {t.point}")
    ax.plot(t.xy[:, 0] * k, t.xy[:, 1] * k, "o", mfc="none", mec="C3", ms=8, mew=1.6, label="targets")
    for j, (x, y) in enumerate(t.xy * k):
        ax.annotate(str(j + 1), (x, y), textcoords="offset points", xytext=(5, 5), fontsize=8, color="C3")
    pts = [path[ok] * k, t.xy * k]
    if theta is not None:
        at = _solved(result, theta)
        got = at.pos[:, i, :]
        ax.plot(got[:, 0] * k, got[:, 1] * k, "x", color="C2", ms=7, mew=1.6, label="achieved")
        for a, b in zip(t.xy * k, got * k):
            ax.plot([a[0], b[0]], [a[1], b[1]], ":", color="0.4", lw=0.8)
        if np.all(at.valid[:1]):
            draw_mechanism(ax, plan, at.pos[0], params=result.params(), color="0.55", alpha=0.7, linewidth=1.6)
            pts.append(at.pos[0][np.all(np.isfinite(at.pos[0]), axis=1)] * k)
        if t.kind == "poses":
            size = 0.12 * float(np.ptp(np.vstack(pts), axis=0).max() or 1.0)
            _frames(ax, t.xy, t.angles, size, "C3", "target poses", k)
            _frames(ax, got, at.body_angle[:, plan.body_names.index(t.link)], size, "C2", "achieved poses", k)
    set_limits(ax, np.vstack(pts), margin=0.12)
    unit = plan.mechanism.units.length
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.set_title("poses: target and achieved" if t.kind == "poses" else "targets and the achieved path")


def _task_function(ax, result, q, st, theta):
    """Function: the target pairs against the achieved output curve ψ(input), in the file's angle unit."""
    pb = result.problem
    t, plan = pb.targets, pb.plan
    a = 1.0 / ANGLE[pb.angle_unit]
    b = plan.body_names.index(t.link)
    x, y = t.xy[:, 0], t.xy[:, 1]
    at = _solved(result, theta)
    psi_t = at.body_angle[:, b]
    base = psi_t[0] - y[0] if t.relative else 0.0
    qq = theta[0] + np.mod(q - theta[0], TWO_PI)                 # the turn from the first target's input
    order = np.argsort(qq)
    qq = qq[order]
    psi = st.body_angle[order, b]
    curve = y[0] + _wrap(psi - base - y[0])
    curve = np.where(st.valid[order], curve, np.nan)
    jump = np.abs(np.diff(curve)) > np.pi
    curve[1:][jump] = np.nan
    ax.plot(qq * a, curve * a, "-", color="C0", lw=1.2, label=f"achieved: {t.link}")
    tq = theta[0] + np.mod(theta - theta[0], TWO_PI)
    ax.plot(tq * a, y * a, "o", mfc="none", mec="C3", ms=8, mew=1.6, label="target pairs")
    ax.plot(tq * a, (y[0] + _wrap(psi_t - base - y[0])) * a, "x", color="C2", ms=7, mew=1.6, label="achieved")
    span = max(float(np.ptp(tq)), 1e-9)
    ax.set_xlim((tq.min() - 0.3 * span) * a, (tq.max() + 0.3 * span) * a)
    lo, hi = float(y.min()), float(y.max())
    pad = 0.3 * max(hi - lo, 1e-9)
    ax.set_ylim((lo - pad) * a, (hi + pad) * a)
    unit = pb.angle_unit
    ax.set_xlabel(f"input [{unit}]")
    ax.set_ylabel(f"{t.link} angle{' change' if t.relative else ''} [{unit}]")
    ax.set_title("function: target pairs and the achieved output")


def _distances(ax, result):
    pb = result.problem
    d = result.details["quantities"].get("distances")
    unit = pb.angle_unit if pb.targets is not None and pb.targets.kind == "function" else pb.length_unit
    if d is None or not len(d):
        ax.text(0.5, 0.5, "no targets", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return
    d = np.asarray(d, dtype=float)
    ax.bar(np.arange(1, len(d) + 1), d, color="C1")
    ax.set_xticks(np.arange(1, len(d) + 1))
    ax.set_xlabel("target")
    ax.set_ylabel(f"distance [{unit}]")
    ax.set_title(f"per target (max {np.nanmax(d):.4g} {unit})")


def _history(ax, result):
    h = np.asarray(result.history, dtype=float)
    if h.size == 0:
        ax.text(0.5, 0.5, "no history", ha="center", va="center", transform=ax.transAxes)
        return
    e, F = h[:, 0], h[:, 2]
    bad = F >= result.problem.infeasible_offset
    ax.step(e, np.where(bad, np.nan, F), where="post", color="C0", label="best objective (feasible)")
    if bad.any():
        ax.step(e, np.where(bad, F, np.nan), where="post", color="C3", lw=1.0, label="no feasible design yet")
    if np.all(F[np.isfinite(F)] > 0):
        ax.set_yscale("log")
    ax.set_xlabel("evaluations")
    ax.set_ylabel("best value")
    ax.set_title(f"convergence ({result.method}, {len(result.starts)} start(s))")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(True, alpha=0.3)


def synthesis_figure(result, *, steps: int | None = None, dpi: int = 100):
    """The figure of a :class:`~assur.synthesis.SynthesisResult`: (a) the task against the best design, (b) the
    per-target distances, (c) the convergence history. ``steps``: samples of the turn (default: the problem's
    ``cycle_samples``). Returns a matplotlib Figure."""
    _, plt = mpl()
    pb = result.problem
    fig, axes = plt.subplots(1, 3, figsize=(15.5, 4.8), dpi=dpi, gridspec_kw={"width_ratios": [1.25, 0.9, 1.0]})
    t = pb.targets
    if t is None or pb.plan.n_inputs != 1 or pb.plan.dimension != 2:
        axes[0].text(0.5, 0.5, "no targets to draw", ha="center", va="center", transform=axes[0].transAxes)
        axes[0].set_axis_off()
    else:
        q = np.linspace(0.0, TWO_PI, steps or pb.cycle_samples, endpoint=False)
        st = _solved(result, q)
        theta = _target_inputs(result)
        (_task_function if t.kind == "function" else _task_plane)(axes[0], result, q, st, theta)
        axes[0].legend(fontsize=8, loc="best")
        axes[0].grid(True, alpha=0.3)
    _distances(axes[1], result)
    _history(axes[2], result)
    title = pb.name or "synthesis"
    status = (f"objective {result.objective:.6g}" if result.feasible else
              f"no feasible design (violation {result.violation:.4g})")
    fig.suptitle(f"{title} — {status}, {result.evaluations} evaluations")
    fig.tight_layout()
    return fig


__all__ = ["synthesis_figure"]
