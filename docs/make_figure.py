#!/usr/bin/env python3
"""The exploded assembly of README.md and docs/make.md: Jansen's leg as ``assur make`` builds it, each part's
solid (the meshes of its STL files) at its sketch pose, the layers pulled apart, coloured by layer.

``python docs/make_figure.py`` writes docs/make/jansen_exploded.png (needs ``pip install 'assur[make]'``).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "make" / "jansen_exploded.png"


def main() -> int:
    sys.path.insert(0, str(ROOT / "src"))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    import assur
    from assur.analysis.study import Study
    from assur.parts import make_parts
    from assur.parts.page import color_of
    result = make_parts(Study(assur.compile(assur.load(ROOT / "examples" / "jansen.toml"))))
    meshes = result.meshes()
    factor = 30.0
    fig = plt.figure(figsize=(8, 7), dpi=110)
    ax = fig.add_subplot(projection="3d")
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for p in result.parts:
        v, t = meshes[p.name]
        v = v.copy()
        if p.kind == "pin":                  # a pin stretches through the parts it holds, pulled apart
            v[:, 2] = factor * v[:, 2]
        else:
            v[:, 2] = v[:, 2] + (factor - 1.0) * 0.5 * (p.z[0] + p.z[1]) * 1e3
        if p.body != 0:                       # the view frames the moving parts; the base plate shows faintly
            lo, hi = np.minimum(lo, v.min(axis=0)), np.maximum(hi, v.max(axis=0))
        alpha = 0.12 if p.kind in ("base", "top") else 1.0
        coll = Poly3DCollection(v[t], facecolors=color_of(p), edgecolors=color_of(p), linewidths=0, alpha=alpha, shade=True,
                                lightsource=matplotlib.colors.LightSource(azdeg=225, altdeg=45))
        ax.add_collection3d(coll)
    span = (hi - lo).max()
    mid = 0.5 * (lo + hi)
    ax.set_xlim(mid[0] - span / 2, mid[0] + span / 2)
    ax.set_ylim(mid[1] - span / 2, mid[1] + span / 2)
    ax.set_zlim(mid[2] - span / 4, mid[2] + span / 4)
    ax.set_box_aspect((1, 1, 1 / 2))
    ax.view_init(elev=24, azim=-58)
    ax.set_axis_off()
    c = result.certificate
    ax.set_title(f"{result.mechanism.name}: {len(result.parts)} parts on {c.layers} layers "
                 f"(minimal: clique bound {c.bound}); heights × {factor:g}", fontsize=10)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, bbox_inches="tight")
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
