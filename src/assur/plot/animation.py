"""Animations of a planar mechanism over one turn (or a run of its inputs) and their files: GIF, MP4 and a
self-contained HTML page (the ``to_jshtml`` player with its frames inlined, no network access).

matplotlib is imported lazily inside the functions, with the non-interactive "Agg" backend.
"""
from __future__ import annotations

import html

import numpy as np

from ..analysis.sampling import CYCLE_STEPS, tracked_point
from ..errors import SpecError
from .draw import closed, draw_mechanism, file_scale, frame_guides, mpl, set_limits
from .figures import sample


def animation(plan, frames: int = 60, fps: float = 20.0, *, params=None, ranges=None, figsize=(6.4, 6.4),
              dpi: int = 100, path=None):
    """A matplotlib FuncAnimation of ``frames`` positions over one turn (or over ``ranges``) with the traced
    path of the foot (or of the last point). ``path``: the solved run (a :class:`~assur.plot.figures.Sweep`)
    the path is drawn from, default :data:`~assur.analysis.sampling.CYCLE_STEPS` samples of the same run.
    Returns ``(figure, animation)``."""
    _, plt = mpl()
    from matplotlib.animation import FuncAnimation
    sw = sample(plan, frames, params, ranges)
    st = sw.state
    k = file_scale(plan)
    unit = plan.mechanism.units.length
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    # a dense path for the faint full trace
    dense = path if path is not None else sample(plan, CYCLE_STEPS, params, ranges)
    full = closed(dense.state.pos[:, fi] * k, dense.cyclic)
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    pos_all = np.concatenate([st.pos.reshape(-1, 2), dense.state.pos.reshape(-1, 2)]) * k
    ax.plot(full[:, 0], full[:, 1], color="0.75", linewidth=1.0, linestyle="--", zorder=1)
    frame_guides(ax, plan, dense.state.pos, params=params)
    (trace,) = ax.plot([], [], color="tab:blue", linewidth=2.0, zorder=2)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(True, alpha=0.3)
    ax.set_title(plan.mechanism.name or "mechanism", fontsize=11)
    set_limits(ax, pos_all, margin=0.12)
    xl, yl = ax.get_xlim(), ax.get_ylim()
    info = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=9)
    drawn: list = []
    dpos = dense.state.pos[:, fi] * k

    def upto(i):
        """Dense samples traced by frame i."""
        if sw.cyclic:
            return int(round(i * dense.n / sw.n)) + 1
        return int(round(i * (dense.n - 1) / max(sw.n - 1, 1))) + 1

    def update(i):
        for a in drawn:
            a.remove()
        drawn.clear()
        if st.valid[i]:
            drawn.extend(draw_mechanism(ax, plan, st.pos[i], params=params, color="tab:blue", labels=True,
                                        frame_guide=False, foot=foot))
            status = ""
        else:
            status = "  (cannot be assembled)"
        j = upto(i)
        trace.set_data(dpos[:j, 0], dpos[:j, 1])
        if plan.input_kinds[sw.moving] == "rotary":
            info.set_text(f"φ = {sw.axis[i]:.0f}°{status}")
        else:
            info.set_text(f"{plan.input_names[sw.moving]} = {sw.axis[i]:.4g} {unit}{status}")
        ax.set_xlim(xl)
        ax.set_ylim(yl)
        return drawn + [trace, info]

    anim = FuncAnimation(fig, update, frames=sw.n, interval=1000.0 / float(fps), blit=False, repeat=True)
    return fig, anim


def save_animation(anim, path, fps: float = 20.0, dpi: int = 100, progress=None, title: str = "animation"):
    """Save an animation by the file's extension: .gif (Pillow), .mp4 (ffmpeg from imageio-ffmpeg),
    .html (a self-contained page from ``to_jshtml``). ``progress(i, n)`` is called per frame
    (GIF and MP4)."""
    matplotlib, _ = mpl()
    from pathlib import Path
    path = Path(path)
    ext = path.suffix.lower()
    if ext == ".gif":
        from matplotlib.animation import PillowWriter
        anim.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi, progress_callback=progress)
    elif ext == ".mp4":
        try:
            import imageio_ffmpeg
        except ImportError:
            raise ImportError("MP4 output needs ffmpeg from imageio-ffmpeg: install assur[video] "
                              "(pip install 'assur[video]')") from None
        matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
        from matplotlib.animation import FFMpegWriter
        anim.save(str(path), writer=FFMpegWriter(fps=fps, codec="libx264",
                                                 extra_args=["-pix_fmt", "yuv420p"]), dpi=dpi,
                  progress_callback=progress)
    elif ext in (".html", ".htm"):
        path.write_text(html_page(jshtml(anim, fps), title=title), encoding="utf-8")
    else:
        raise SpecError(f"unknown animation format {ext!r} (use .gif, .mp4 or .html)")


# the player's icons without the font-awesome style sheet that to_jshtml links from a CDN
_ICONS = {"fa-minus": "&minus;", "fa-fast-backward": "&#x23EE;&#xFE0E;", "fa-step-backward": "&#x2759;&#x25C0;&#xFE0E;",
          "fa-flip-horizontal": "&#x25C0;&#xFE0E;", "fa-pause": "&#x2759;&#x2759;", "fa-play": "&#x25B6;&#xFE0E;",
          "fa-step-forward": "&#x25B6;&#xFE0E;&#x2759;", "fa-fast-forward": "&#x23ED;&#xFE0E;", "fa-plus": "+"}


def jshtml(anim, fps: float = 20.0, default_mode: str = "loop") -> str:
    """``anim.to_jshtml()`` made self-contained: the frames are embedded (base64 PNG) and the
    link to the icon font on a CDN is replaced by plain Unicode symbols (no network access)."""
    import re
    text = anim.to_jshtml(fps=fps, default_mode=default_mode)
    text = re.sub(r'<link[^>]*href="https?://[^"]*"[^>]*>', "", text)

    def icon(mt):
        classes = mt.group(1).split()
        for key in ("fa-flip-horizontal", *_ICONS):
            if key in classes:
                return f'<span aria-hidden="true">{_ICONS[key]}</span>'
        return ""
    return re.sub(r'<i class="([^"]*)"></i>', icon, text)


def html_page(body: str, title: str = "", *, meta: str = "", style: str = "") -> str:
    """The one skeleton of every HTML page assur writes: ``body`` in a UTF-8 English page titled ``title``
    (escaped), with ``meta`` (complete tags, each ending in a newline) before the title and the style sheet
    ``style`` after it."""
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"{meta}<title>{html.escape(title)}</title>\n" + (f"<style>{style}</style>\n" if style else "")
            + f"</head>\n<body>\n{body}\n</body>\n</html>\n")
