"""Figures of a non-circular gear pair and a wheel-step shoe: pitch curves, teeth in mesh, the speed law, the shoe
profile, and an animation of the meshing pair. Lengths in mm, angles in degrees. matplotlib is imported lazily
(Agg backend) through :func:`assur.plot.draw.mpl`.
"""
from __future__ import annotations

import math

import numpy as np

from .draw import closed, mpl

MM = 1e3
TWO_PI = 2.0 * math.pi


def _rot(xy, angle, centre=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([centre[0] + c * xy[:, 0] - s * xy[:, 1], centre[1] + s * xy[:, 0] + c * xy[:, 1]], axis=-1)


def pitch_figure(pair, *, title: str = "", dpi: int = 100):
    """Both pitch curves in mesh position (φ = 0) and the pitch radii over the cycle."""
    _, plt = mpl()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.8), dpi=dpi, gridspec_kw={"width_ratios": [1.3, 1]})
    L = pair.centre_distance
    c1 = pair.driving.xy(2048)
    c2 = _rot(pair.driven.xy(4096), -float(pair.law(0.0)), (L, 0.0))
    ax.plot(*(closed(c1, True) * MM).T, color="C0", label=f"driving (perimeter {pair.driving.perimeter * MM:.2f} mm)")
    ax.plot(*(closed(c2, True) * MM).T, color="C1", label=f"driven (perimeter {pair.driven.perimeter * MM:.2f} mm)")
    ax.plot([0, L * MM], [0, 0], "k+", ms=10)
    ax.axhline(0, color="0.8", lw=0.6, zorder=0)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.legend(loc="best", fontsize=8)   # inside the axes: never clipped by the figure
    ax.set_title(title or f"pitch curves, L = {L * MM:.2f} mm")
    phi = np.linspace(0.0, TWO_PI * pair.driving_turns, 1441)
    r1, r2 = pair.contact_radii(phi)
    ax2.plot(np.degrees(phi), r1 * MM, color="C0", label="r₁ driving")
    ax2.plot(np.degrees(phi), r2 * MM, color="C1", label="r₂ driven")
    ax2.set_xlabel("driving angle φ [°]")
    ax2.set_ylabel("pitch radius at contact [mm]")
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    return fig


def teeth_figure(driving_xy, driven_xy, pair, *, title: str = "", zoom: float | None = None, dpi: int = 100,
                 phi: float = 0.0):
    """Both tooth outlines (body frames, m) placed in mesh at driving angle φ, whole pair and a zoom at the
    pitch point (``zoom``: half width, m; default 6 module-ish: 4 % of L)."""
    _, plt = mpl()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 5), dpi=dpi)
    L = pair.centre_distance
    a = _rot(np.asarray(driving_xy), phi)
    b = _rot(np.asarray(driven_xy), -float(pair.law(phi)), (L, 0.0))
    r1 = float(pair.contact_radii(np.array([phi]))[0][0])
    for axis in (ax, ax2):
        axis.fill(*(closed(a, True) * MM).T, color="C0", alpha=0.25, lw=0)
        axis.plot(*(closed(a, True) * MM).T, color="C0", lw=0.6)
        axis.fill(*(closed(b, True) * MM).T, color="C1", alpha=0.25, lw=0)
        axis.plot(*(closed(b, True) * MM).T, color="C1", lw=0.6)
        axis.set_aspect("equal")
        axis.set_xlabel("x [mm]")
    ax.plot([0, L * MM], [0, 0], "k+", ms=10)
    ax.set_ylabel("y [mm]")
    ax.set_title(title or "tooth outlines in mesh")
    h = (zoom or 0.04 * L) * MM
    ax2.set_xlim(r1 * MM - h, r1 * MM + h)
    ax2.set_ylim(-h, h)
    ax2.plot([r1 * MM], [0], "k.", ms=4)
    ax2.set_title(f"at the pitch point, φ = {math.degrees(phi):.1f}°")
    fig.tight_layout()
    return fig


def speed_figure(report, *, law_name: str = "law", reference=None, dpi: int = 100):
    """Speed law k(φ) = dθ/dφ of the law and as transmitted by the outlines (mesh report), the transmission
    error δ_lo and the backlash; ``reference``: optional (phi, k) of an unrounded law."""
    _, plt = mpl()
    fig, axs = plt.subplots(3, 1, figsize=(9, 7.5), dpi=dpi, sharex=True)
    d = np.degrees(report.phi)
    axs[0].plot(d, report.law_ratio, color="C0", label=law_name)
    axs[0].plot(d, report.actual_ratio, color="C3", lw=0.8, label="transmitted by the teeth")
    if reference is not None:
        axs[0].plot(np.degrees(reference[0]), reference[1], color="0.5", ls="--", lw=0.8, label="exact law")
    axs[0].set_ylabel("dθ/dφ")
    axs[0].legend(fontsize=8)
    bad = report.interferes
    if bad.any():
        for ax in axs:
            ax.fill_between(d, 0, 1, where=bad, transform=ax.get_xaxis_transform(), color="red", alpha=0.15,
                            lw=0, label="interference" if ax is axs[2] else None)
    axs[1].plot(d, np.degrees(report.lower - np.nanmean(report.lower)) * 60, color="C2")
    axs[1].set_ylabel("transmission error [′]")
    axs[2].plot(d, report.backlash * MM, color="C4", label="backlash at the driven pitch point")
    if bad.any():
        axs[2].plot(d, np.where(bad, report.penetration * MM, np.nan), color="red", label="penetration")
    axs[2].set_ylabel("[mm]")
    axs[2].set_xlabel("driving angle φ [°]")
    axs[2].legend(fontsize=8)
    for ax in axs:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def shoe_figure(shoe, *, dpi: int = 100, samples: int = 361):
    """The support-shoe profile (X, Y) over one step with the hub and crank axes, its curvature radius R(φ),
    and the mover displacement X(φ) split into crank and rolling parts."""
    _, plt = mpl()
    phi = np.linspace(-math.pi / 4, math.pi / 4, samples)
    xy = np.asarray(shoe.profile(phi))
    fig, axs = plt.subplots(1, 3, figsize=(13, 4.2), dpi=dpi)
    ax = axs[0]
    ax.plot(xy[..., 0], xy[..., 1], color="C0", label="shoe profile")
    ax.plot([0], [0], "k+", ms=9)
    ax.set_aspect("equal")
    ax.set_xlabel("X [m]")
    ax.set_ylabel("Y [m]")
    ax.set_title("profile, eqs. (1)–(3)")
    ax.grid(alpha=0.3)
    d = np.degrees(phi)
    axs[1].plot(d, np.asarray(shoe.curvature_radius(phi)), color="C1")
    axs[1].set_xlabel("hub angle φ [°]")
    axs[1].set_ylabel("R [m]")
    axs[1].set_title(f"curvature radius, eq. (8); R_min = {shoe.r_min:.4g} m")
    axs[1].grid(alpha=0.3)
    axs[2].plot(d, np.asarray(shoe.displacement(phi, periodic=False)), color="C2", label="X(φ)")
    axs[2].plot(d, np.asarray(shoe.rolling_displacement(phi)), color="C0", ls="--", label="rolling part")
    axs[2].plot(d, np.asarray(shoe.crank_displacement(phi)), color="C3", ls=":", label="crank part")
    axs[2].set_xlabel("hub angle φ [°]")
    axs[2].set_ylabel("displacement [m]")
    axs[2].set_title(f"X_01 = {shoe.budget.total:.4f} m per step")
    axs[2].legend(fontsize=8)
    axs[2].grid(alpha=0.3)
    fig.tight_layout()
    return fig


def mesh_animation(driving_xy, driven_xy, pair, frames: int = 36, fps: float = 12.0, *, figsize=(6.4, 4.2),
                   dpi: int = 72, report=None):
    """(fig, FuncAnimation) of the two outlines turning through one driven turn (the driven gear at θ(φ) + δ_lo
    when a mesh report is given, else at the law)."""
    _, plt = mpl()
    from matplotlib.animation import FuncAnimation
    L = pair.centre_distance
    n = pair.driving_turns
    a0 = np.asarray(driving_xy)
    b0 = np.asarray(driven_xy)
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    ext = max(np.abs(a0).max(), 1e-9)
    ax.set_xlim(-ext * MM * 1.05, (L + np.abs(b0).max()) * MM * 1.05)
    ax.set_ylim(-np.abs(b0).max() * MM * 1.05, np.abs(b0).max() * MM * 1.05)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    la, = ax.fill([], [], color="C0", alpha=0.5)
    lb, = ax.fill([], [], color="C1", alpha=0.5)
    ax.plot([0, L * MM], [0, 0], "k+", ms=8)
    text = ax.set_title("")
    phis = np.arange(frames) * (TWO_PI * n / frames)

    def offset(phi):
        if report is None:
            return 0.0
        lo = np.interp(np.mod(phi, TWO_PI * n), report.phi, np.nan_to_num(report.lower), period=TWO_PI * n)
        return float(lo)

    def update(i):
        phi = phis[i]
        th = float(pair.law(phi)) + offset(phi)
        la.set_xy(_rot(a0, phi) * MM)
        lb.set_xy(_rot(b0, -th, (L, 0.0)) * MM)
        text.set_text(f"φ = {math.degrees(phi):.0f}°, θ = {math.degrees(th):.1f}°")
        return la, lb, text

    anim = FuncAnimation(fig, update, frames=frames, interval=1000.0 / fps, blit=False, repeat=True)
    return fig, anim


__all__ = ["mesh_animation", "pitch_figure", "shoe_figure", "speed_figure", "teeth_figure"]
