"""The figure of a cam pair (matplotlib, imported lazily): the law's SVAJ diagrams over the cam turn, the profile
and pitch curve (mm, the cam's frame, the base and prime circles dashed, the pressure-angle peak marked), the
pressure angle against its limit, and the radii of curvature of the profile and the pitch curve."""
from __future__ import annotations

import math

import numpy as np

from .draw import mpl


def cam_figure(geometry, *, speed: float | None = None, dpi: int = 100, title: str = ""):
    """Four panels of a :class:`~assur.cams.geometry.CamGeometry` (lengths in mm, angles in degrees; ``speed`` the
    cam's rad/s for the SVAJ in time, else per radian of cam angle)."""
    from ..cams.laws import continuity, svaj
    _, plt = mpl()
    g = geometry
    c = g.turn_samples(1440)
    s = g.summary(1440)
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), dpi=dpi)
    d = svaj(g.law, speed=speed)
    phi = np.degrees(d.phi)
    angular = g.motion == "oscillating"
    f = (180 / math.pi) if angular else 1e3
    unit = "°" if angular else "mm"
    per = "/s" if speed else "/rad"
    ax = axes[0, 0]
    for name, arr, col in (("s", d.s, "C0"), ("v", d.v, "C1"), ("a", d.a, "C2"), ("j", d.j, "C3")):
        peak = np.max(np.abs(arr)) or 1.0
        lab = f"{name} (peak {peak * f:.4g} {unit}{'' if name == 's' else per + ('' if name == 'v' else '²' if name == 'a' else '³')})"
        ax.plot(phi, arr / peak, color=col, label=lab)
    cont = continuity(g.law)
    for b in cont.boundaries:
        if b.order is not None and b.order <= 2:
            ax.axvline(math.degrees(b.angle), color="red", linewidth=0.8)
    ax.set_xlabel("cam angle [°]")
    ax.set_ylabel("SVAJ, each / its peak")
    ax.set_title("motion law" + ("" if cont.ok else ": red lines break the fundamental law (infinite jerk)"),
                 fontsize=10)
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(alpha=0.3)
    ax = axes[0, 1]
    pr, pt = c.profile * 1e3, c.pitch * 1e3
    ax.fill(pr.real, pr.imag, color="0.85", edgecolor="C0", linewidth=1.4, label="profile")
    if g.contact != "flat":
        ax.plot(np.append(pt.real, pt.real[:1]), np.append(pt.imag, pt.imag[:1]), "--", color="C1", linewidth=1.0,
                label="pitch curve")
    t = np.exp(1j * np.linspace(0, 2 * math.pi, 200))
    for r, lab, col in ((s["base_radius"], "base circle", "0.5"), (s["prime_radius"], "prime circle", "0.7")):
        z = r * 1e3 * t
        ax.plot(z.real, z.imag, ":", color=col, linewidth=0.8, label=f"{lab} {r * 1e3:.4g} mm")
    i = int(np.argmax(np.abs(c.pressure_angle)))
    ax.plot(pr[i].real, pr[i].imag, "o", color="red", markersize=5, label="largest pressure angle")
    ax.plot(0, 0, "+", color="k")
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (cam frame)")
    ax.set_ylabel("y [mm]")
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"{title or g.name or 'cam'}: {g.motion} {g.contact} follower" +
                 (" — UNDERCUT" if s["undercut"] else ""), fontsize=10)
    xs = np.degrees((g.phase + g.rotation * c.x) % (2 * math.pi))
    order = np.argsort(xs)
    ax = axes[1, 0]
    ax.plot(xs[order], np.degrees(c.pressure_angle[order]), color="C0")
    lim = math.degrees(g.pressure_limit)
    ax.axhline(lim, color="red", linewidth=0.8, linestyle="--", label=f"limit ±{lim:g}°")
    ax.axhline(-lim, color="red", linewidth=0.8, linestyle="--")
    ax.set_xlabel("cam angle [°]")
    ax.set_ylabel("pressure angle [°]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1, 1]
    rho = c.profile_radius * 1e3
    cap = 5 * (s["prime_radius"] * 1e3)
    ax.plot(xs[order], np.clip(rho[order], -cap, cap), color="C0", label="profile")
    if g.contact != "flat":
        ax.plot(xs[order], np.clip(c.pitch_radius[order] * 1e3, -cap, cap), color="C1", linewidth=0.9,
                label="pitch curve")
    if g.contact == "roller":
        ax.axhline(g.roller_radius * 1e3, color="red", linewidth=0.8, linestyle="--",
                   label=f"roller radius {g.roller_radius * 1e3:g} mm")
    ax.axhline(0, color="0.6", linewidth=0.6)
    ax.set_xlabel("cam angle [°]")
    ax.set_ylabel("radius of curvature [mm] (+ convex)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
