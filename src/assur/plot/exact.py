"""The figure of an exact synthesis (``assur synth PROBLEM --exact --report DIR``): each of the best candidates
drawn at its precision points, driven by the engine along the stretch between the first and the last.

Function generation: the candidate's output angle against its input over the stretch (the engine's solution) with
the task's pairs, one panel; and the linkage at its first and last precision points. Motion generation: the
coupler point's path over the stretch with the task's poses (a point and an arrow of the link's angle) and the
linkage at each pose. Lengths in the candidates' unit (the problem's), angles in degrees.
"""
from __future__ import annotations

import math

import numpy as np

from .draw import draw_mechanism, mpl, set_limits


def _stretch(inputs, per_gap: int = 40) -> np.ndarray:
    t = np.asarray(inputs, dtype=float)
    s = np.linspace(0.0, 1.0, per_gap, endpoint=False)
    q = (t[:-1, None] + np.diff(t)[:, None] * s).ravel()
    return np.concatenate([q, t[-1:]])


def exact_figure(task, targets, *, best: int = 3, dpi: int = 100):
    """A matplotlib Figure of the ``best`` first candidates of an :class:`~assur.synthesis.exact_task.ExactTask`.
    ``targets``: the problem's Targets (SI); the candidates are in ``task.length_unit``."""
    from ..engine import compile as compile_, solve
    from ..io.units import LENGTH
    _, plt = mpl()
    sols = list(task.candidates)[:best]
    n = max(1, len(sols))
    fig, axes = plt.subplots(1, n + (task.kind == "function"), figsize=(4.2 * (n + (task.kind == "function")), 4.0),
                             dpi=dpi, squeeze=False)
    axes = axes[0]
    L = LENGTH[task.length_unit]
    if not sols:
        axes[0].text(0.5, 0.5, task.candidates.reason or "no candidate", ha="center", va="center", wrap=True)
        axes[0].set_axis_off()
        return fig
    if task.kind == "function":
        ax = axes[0]
        x, y = np.asarray(targets.xy, float).T
        for k, s in enumerate(sols):
            plan = compile_(s.mechanism)
            q = _stretch(s.inputs)
            st = solve(plan, inputs=q, order=0, on_unbuildable="nan")
            B, B0 = st.point("B").pos, np.asarray(s.mechanism.sketch("B0"))
            flip = math.pi if "+ π" in s.mechanism.description else 0.0
            psi = np.unwrap(np.arctan2(B[:, 1] - B0[1], B[:, 0] - B0[0]) + flip)
            # the task's pairs relative to the candidate's own start angles (a relative task has them free)
            phi0, psi0 = s.inputs[0] - x[0], psi[0] - y[0]
            ax.plot(np.degrees(q - phi0), np.degrees(psi - psi0), color=f"C{k}", lw=1.6,
                    label=f"#{s.rank}: residual {s.residual:.3g} rad")
        ax.plot(np.degrees(x), np.degrees(y), "ko", ms=4, label="task")
        ax.set_xlabel("input change [°]")
        ax.set_ylabel("output change [°]")
        ax.set_title("output against input")
        ax.legend(fontsize=7)
        axes = axes[1:]
    for ax, (k, s) in zip(axes, enumerate(sols)):
        plan = compile_(s.mechanism)
        at = np.asarray(s.inputs, float)
        q = _stretch(at)
        path = solve(plan, inputs=q, order=0, on_unbuildable="nan")
        pos = solve(plan, inputs=at if task.kind == "motion" else at[[0, -1]], order=0, on_unbuildable="nan").pos
        for j, row in enumerate(pos):
            draw_mechanism(ax, plan, row, color=f"C{k}", alpha=1.0 if j == 0 else 0.45, scale=1.0 / L)
        pts = [pos.reshape(-1, 2) / L]
        if task.kind == "motion":
            P = path.point("P").pos / L
            ax.plot(P[:, 0], P[:, 1], color=f"C{k}", lw=1.0, ls="--")
            xy = np.asarray(targets.xy, float) / L
            size = 0.08 * float(np.ptp(xy, axis=0).max() or 1.0)
            for (px, py), a in zip(xy, targets.angles):
                ax.annotate("", (px + size * math.cos(a), py + size * math.sin(a)), (px, py),
                            arrowprops={"arrowstyle": "->", "color": "k", "lw": 1.2})
            ax.plot(xy[:, 0], xy[:, 1], "ko", ms=4)
            pts.append(P)
        set_limits(ax, np.concatenate([p[np.all(np.isfinite(p), axis=1)] for p in pts]))
        ax.set_aspect("equal")
        ax.set_title(f"#{s.rank} {s.grashof}: μ ≥ {math.degrees(s.transmission):.1f}°", fontsize=9)
        ax.set_xlabel(f"x [{task.length_unit}]")
    fig.tight_layout()
    return fig


__all__ = ["exact_figure"]
