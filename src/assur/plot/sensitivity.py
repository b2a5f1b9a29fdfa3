"""Figures of the exact sensitivities and the tolerance analysis (matplotlib, imported lazily).

:func:`sensitivity_figure`: for each output, the contributions ∂y/∂p_k·t_k of its most influential parameters over
the cycle (the output's unit per tolerance zone); :func:`band_figure`: a point's path with its worst-case and RSS
tolerance bands, the Monte Carlo's extreme deviations, and the inputs where the first-order band fails;
:func:`clearance_figure`: the joint-clearance error over the cycle (effective link, worst case, Monte Carlo).
Lengths in the file's length unit, angles in degrees.
"""
from __future__ import annotations

import math

import numpy as np

from .draw import draw_mechanism, file_scale, length_unit, mpl, set_limits


def _nice(x: float) -> float:
    """The largest of 1, 2, 5 × 10^k not above x (at least 1): a readable exaggeration."""
    if x <= 1:
        return 1.0
    e = 10 ** math.floor(math.log10(x))
    return max(m * e for m in (1, 2, 5) if m * e <= x)


def _input_axis(study):
    sw = study.sweep
    return sw.axis, sw.axis_label


def display(plan, unit: str):
    """(factor SI → display, display unit) of an output's SI unit."""
    k = file_scale(plan)
    L = length_unit(plan)
    return {"m": (k, L), "m/s": (k, f"{L}/s"), "m/s²": (k, f"{L}/s²"), "rad": (180 / math.pi, "°"),
            "rad/s": (180 / math.pi, "°/s")}.get(unit, (1.0, unit))


def influence(sens, name: str, tol) -> np.ndarray:
    """(n_params,) the largest |∂y/∂p_k|·t_k of output ``name`` over the run (SI)."""
    d = np.abs(np.atleast_2d(np.asarray(sens[name].derivative))) * tol.half
    return np.nanmax(d, axis=0)


def sensitivity_figure(sens, names, tol, *, top: int = 4, dpi: int = 100):
    """One panel per output: the top ``top`` parameters' ∂y/∂p_k·t_k over the cycle (a gait metric: a bar chart)."""
    _, plt = mpl()
    study = sens.study
    plan = study.plan
    x, xlabel = _input_axis(study)
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.8 * len(names)), dpi=dpi, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        out = sens[name]
        f, unit = display(plan, out.unit)
        score = influence(sens, name, tol)
        order = np.argsort(score)[::-1][:top]
        if np.ndim(out.value) == 0:
            ax.barh([plan.param_names[k] for k in order][::-1],
                    (np.asarray(out.derivative)[order] * tol.half[order] * f)[::-1], color="C0")
            ax.set_xlabel(f"∂{name}/∂p · t  [{unit}]")
        else:
            for c, k in enumerate(order):
                ax.plot(x, out.derivative[:, k] * tol.half[k] * f, color=f"C{c}", label=plan.param_names[k])
            ax.axhline(0.0, color="0.6", linewidth=0.8)
            ax.set_xlabel(xlabel)
            ax.set_ylabel(f"∂{name}/∂p · t  [{unit}]")
            ax.legend(fontsize=8, loc="best")
        ax.set_title(f"{name}: the most influential parameters (tolerance zones ±t)", fontsize=10)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def band_figure(study, band, mc=None, *, rss: bool = True, dpi: int = 100, positions: int = 3):
    """The path of ``band.point`` with its worst-case (and RSS) band, drawn ``exaggeration`` times wider so that it
    shows, the Monte Carlo's extremes, and the inputs where a sample leaves the first-order band (red)."""
    _, plt = mpl()
    plan = study.plan
    k = file_scale(plan)
    L = length_unit(plan)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 5), dpi=dpi, gridspec_kw={"width_ratios": [1.3, 1]})
    path = band.path * k
    span = max(np.ptp(path.real), np.ptp(path.imag))
    wmax = float(np.nanmax(band.worst)) * k
    ex = _nice(0.05 * span / wmax) if wmax > 0 else 1.0
    pos = study.state.pos
    for i in np.linspace(0, len(pos) - 1, positions, dtype=int):
        draw_mechanism(ax, plan, pos[i], params=study.params, color="0.55", alpha=0.45, linewidth=1.4)

    def closed(z):
        return np.append(z, z[:1]) if study.cyclic else z
    lo, hi = (band.path - ex * band.worst * band.normal) * k, (band.path + ex * band.worst * band.normal) * k
    ax.fill(np.concatenate([closed(lo).real, closed(hi).real[::-1]]),
            np.concatenate([closed(lo).imag, closed(hi).imag[::-1]]), color="C1", alpha=0.35,
            label=f"worst case ×{ex:g}")
    if rss:
        lo2, hi2 = (band.path - ex * band.rss * band.normal) * k, (band.path + ex * band.rss * band.normal) * k
        for e in (lo2, hi2):
            ax.plot(closed(e).real, closed(e).imag, color="C2", linewidth=0.8)
    ax.plot(closed(path).real, closed(path).imag, color="C0", linewidth=1.2, label=f"{band.point} nominal")
    set_limits(ax, np.column_stack([np.concatenate([lo.real, hi.real, pos[..., 0].ravel() * k]),
                                    np.concatenate([lo.imag, hi.imag, pos[..., 1].ravel() * k])]))
    ax.set_xlabel(f"x [{L}]")
    ax.set_ylabel(f"y [{L}]")
    ax.legend(fontsize=8, loc="best")
    ax.set_title(f"tolerance band round the path of {band.point}", fontsize=10)
    x, xlabel = _input_axis(study)
    bx.fill_between(x, -band.worst * k, band.worst * k, color="C1", alpha=0.3, label="worst case (linear)")
    bx.plot(x, band.rss * k, color="C2", linewidth=1.0, label="RSS (±3σ)")
    bx.plot(x, -band.rss * k, color="C2", linewidth=1.0)
    if mc is not None:
        bx.plot(x, mc.low * k, color="C3", linewidth=0.9, label=f"Monte Carlo extremes ({mc.buildable} of {mc.samples})")
        bx.plot(x, mc.high * k, color="C3", linewidth=0.9)
        bad = mc.outside > 0
        if bad.any():
            bx.scatter(x[bad], np.maximum(np.abs(mc.low[bad]), np.abs(mc.high[bad])) * k, color="red", s=10,
                       zorder=5, label="first-order band exceeded")
    bx.set_xlabel(xlabel)
    bx.set_ylabel(f"deviation along the path's normal [{L}]")
    bx.legend(fontsize=8, loc="best")
    bx.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def clearance_figure(study, clr, *, dpi: int = 100):
    """|error| of the clearance analysis's point over the cycle: effective link, worst case, Monte Carlo; the inputs
    where a joint loses contact shaded."""
    _, plt = mpl()
    plan = study.plan
    k = file_scale(plan)
    L = length_unit(plan)
    x, xlabel = _input_axis(study)
    fig, ax = plt.subplots(figsize=(8, 3.4), dpi=dpi)
    ax.plot(x, clr.worst * k, color="C1", label="worst case (every orientation)")
    ax.plot(x, np.linalg.norm(clr.effective, axis=-1) * k, color="C0", label="effective links (along the reactions)")
    if clr.monte_carlo is not None:
        ax.plot(x, clr.monte_carlo * k, color="C3", linewidth=0.9, label="Monte Carlo (random orientations)")
    q = study.q
    for joint, where in clr.contact_loss.items():
        for w in where:
            i = int(np.argmin(np.abs(q - w)))
            ax.axvline(x[i], color="0.8", linewidth=0.6)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"|error of {clr.point}| [{L}]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return fig
