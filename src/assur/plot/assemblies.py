"""Every assembly of a mechanism at one input, drawn side by side (``assur plot FILE --assemblies``)."""
from __future__ import annotations

import math

import numpy as np

from .draw import draw_mechanism, file_scale, length_unit, mpl, set_limits


def assemblies_figure(plan, found, labels, where: str, *, dpi: int = 100, units: str = "file"):
    """A figure with one panel per assembly in ``found`` (:class:`~assur.engine.planar.assemblies.Assembly` list at
    one input, described by the text ``where``), the sketch's in its own colour, each titled by its branches
    (``labels``: one list of branch labels per assembly); the same axes limits in all."""
    _, plt = mpl()
    n = max(len(found), 1)
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 4.0 * rows + 0.6), dpi=dpi, squeeze=False)
    k = file_scale(plan, units)
    everything = np.concatenate([a.pos for a in found]) * k if found else np.zeros((0, 2))
    for i, ax in enumerate(axes.ravel()):
        if i >= len(found):
            ax.set_axis_off()
            continue
        a = found[i]
        draw_mechanism(ax, plan, a.pos, color="C3" if a.sketch else "C0", scale=k)
        set_limits(ax, everything)
        title = "\n".join(labels[i]) or "(no branched group)"
        ax.set_title(f"{i + 1}. {title}" + ("\nthe sketch's" if a.sketch else ""), fontsize=8)
        ax.set_xlabel(f"x [{length_unit(plan, units)}]", fontsize=8)
        ax.tick_params(labelsize=7)
    if not found:
        axes[0, 0].text(0.5, 0.5, "no assembly at this input", ha="center", va="center")
    name = plan.mechanism.name or "mechanism"
    fig.suptitle(f"{name}: {len(found)} assemblies at {where}", fontsize=10)
    fig.tight_layout()
    return fig
