"""Animations of a planar mechanism over one turn (or a run of its inputs) and their files: GIF, MP4 and a
self-contained HTML page (the ``to_jshtml`` player with its frames inlined, no network access).

matplotlib is imported lazily inside the functions, with the non-interactive "Agg" backend.

The frames of an :func:`animation` are written by blitting: the static part of the figure (axes, ticks, labels,
the traced path, the frame guides) is drawn once and every frame draws only the moving artists over it, the
same pixels as a full redraw; each frame is then handed to matplotlib's writers as a one-image figure, so a
frame is drawn once, not twice (``Animation.save`` draws every frame before saving it).
"""
from __future__ import annotations

import html
import weakref

import numpy as np

from ..analysis.sampling import CYCLE_STEPS, tracked_point
from ..errors import SpecError
from .draw import closed, draw_mechanism, file_scale, frame_guides, frame_rate, mpl, set_limits
from .figures import study_of


def animation(plan, frames: int = 60, fps: float = 20.0, *, params=None, ranges=None, figsize=(6.4, 6.4),
              dpi: int = 100, path=None):
    """A matplotlib FuncAnimation of ``frames`` positions over one turn (or over ``ranges``) with the traced
    path of the foot (or of the last point). ``plan``: a plan, or a Study whose run is drawn: the frames are its
    samples where they fall on them (:meth:`~assur.analysis.sampling.Cycle.frames`) and the path its whole run.
    ``path``: the solved run (a :class:`~assur.analysis.study.Sweep`) the path is drawn from, default the
    Study's run (:data:`~assur.analysis.sampling.CYCLE_STEPS` samples). Returns ``(figure, animation)``."""
    fps = frame_rate(fps)
    _, plt = mpl()
    from matplotlib.animation import FuncAnimation
    study = study_of(plan, params, CYCLE_STEPS, ranges)
    plan, params = study.plan, study.params
    sw = study.frame_sweep(frames)
    st = sw.state
    k = file_scale(plan)
    unit = plan.mechanism.units.length
    foot = tracked_point(plan)
    fi = plan.point_index(foot)
    # a dense path for the faint full trace
    dense = path if path is not None else study.sweep
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
    _FRAMES[anim] = (fig, update, sw.n)
    return fig, anim


#: animations made by :func:`animation` → (figure, update(i) → the moving artists, number of frames)
_FRAMES: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _frame_renderer(fig, update):
    """``render(i)`` → the RGBA pixels (h, w, 4) of frame i: the figure without the moving artists is drawn
    once, then each frame restores it and draws the artists ``update(i)`` returns, in the order (zorder, then
    the order in which they were added) of a full draw."""
    canvas = fig.canvas
    hidden = [a for a in update(0) if a.get_visible()]
    for a in hidden:
        a.set_visible(False)
    canvas.draw()
    for a in hidden:
        a.set_visible(True)
    background = canvas.copy_from_bbox(fig.bbox)

    def render(i):
        canvas.restore_region(background)
        mine = set(update(i))
        for ax in fig.axes:
            drawn = sorted((a for a in ax.get_children() if a in mine), key=lambda a: a.get_zorder())
            for a in drawn:
                ax.draw_artist(a)
        return np.array(canvas.buffer_rgba())
    return render


def _blitted(anim, dpi=None, even: bool = False):
    """(render(i) → RGBA pixels of frame i, number of frames) of an animation made by :func:`animation` drawn
    at its figure's resolution (``dpi`` None or the figure's); None for any other animation. ``even``: first
    resize the figure to an even number of pixels each way, as matplotlib's movie and HTML writers do."""
    entry = _FRAMES.get(anim)
    if entry is None or not hasattr(entry[0].canvas, "copy_from_bbox"):
        return None
    fig, update, n = entry
    if dpi is not None and float(dpi) != float(fig.dpi):
        return None
    if even:
        from matplotlib.animation import adjusted_figsize
        size = adjusted_figsize(*fig.get_size_inches(), fig.dpi, 2)
        if tuple(size) != tuple(fig.get_size_inches()):
            fig.set_size_inches(*size)
    return _frame_renderer(fig, update), n


def _frames(render, n, progress=None):
    """The frames 0 … n−1 of ``render``, calling ``progress(i, n)`` for each."""
    for i in range(n):
        if progress is not None:
            progress(i, n)
        yield render(i)


def _write_gif(path, render, n, fps, progress=None):
    """A looping GIF of the frames: one adaptive palette of 256 colours (Pillow's median cut, from the
    first and the middle frame) that every frame is mapped to, so the colours do not flicker between frames
    and each frame costs a lookup, not a quantisation of its own."""
    from PIL import Image
    rgb = [Image.fromarray(f[..., :3]) for f in (render(0), render(n // 2))]
    both = Image.new("RGB", (rgb[0].width, rgb[0].height * 2))
    both.paste(rgb[0], (0, 0))
    both.paste(rgb[1], (0, rgb[0].height))
    palette = both.quantize(256)
    frames = [Image.fromarray(f[..., :3]).quantize(palette=palette, dither=Image.Dither.NONE)
              for f in _frames(render, n, progress)]
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0)


def _write_mp4(path, render, n, fps, ffmpeg, progress=None):
    """An H.264 MP4 (yuv420p, the encoder's default quality) of the frames, piped to ``ffmpeg`` (imageio-ffmpeg);
    an odd width or height loses its last pixel row or column (yuv420p needs even sizes)."""
    import imageio_ffmpeg
    first = render(0)
    h, w = (first.shape[0] // 2) * 2, (first.shape[1] // 2) * 2
    writer = imageio_ffmpeg.write_frames(str(path), (w, h), pix_fmt_in="rgba", fps=fps, quality=None, codec="libx264",
                                         macro_block_size=1, output_params=["-f", "mp4"])
    writer.send(None)
    try:
        for f in _frames(render, n, progress):
            writer.send(np.ascontiguousarray(f[:h, :w]))
    finally:
        writer.close()


def _image_animation(render, n, fps: float, progress=None):
    """A stand-in animation for matplotlib's writers: a figure holding one image, one figure pixel per
    image pixel, whose frame i shows ``render(i)``; ``progress(i, n)`` is called once per frame."""
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure
    first = render(0)
    h, w = first.shape[:2]
    proxy = Figure(figsize=(w, h), dpi=1)
    image = proxy.figimage(first, origin="upper")
    shown, reported = [0], set()

    def show(i):
        if i != shown[0]:
            image.set_data(render(i))
            shown[0] = i
        if progress is not None and i not in reported:
            reported.add(i)
            progress(i, n)
        return [image]
    return FuncAnimation(proxy, show, frames=n, interval=1000.0 / float(fps), blit=False, repeat=True)


def save_animation(anim, path, fps: float = 20.0, dpi: int = 100, progress=None, title: str = "animation"):
    """Save an animation by the file's extension: .gif (Pillow), .mp4 (ffmpeg from imageio-ffmpeg),
    .html (a self-contained page from ``to_jshtml``). ``progress(i, n)`` is called per frame
    (GIF and MP4; for an animation of :func:`animation`, HTML too). An animation of :func:`animation`
    saved at its figure's ``dpi`` is drawn by blitting."""
    matplotlib, _ = mpl()
    from pathlib import Path
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in (".gif", ".mp4", ".html", ".htm"):
        raise SpecError(f"unknown animation format {ext!r} (use .gif, .mp4 or .html)")
    ffmpeg = None
    if ext == ".mp4":
        try:
            import imageio_ffmpeg
        except ImportError:
            raise ImportError("MP4 output needs ffmpeg from imageio-ffmpeg: install assur[video] "
                              "(pip install 'assur[video]')") from None
        ffmpeg = imageio_ffmpeg.get_ffmpeg_exe()
    fast = _blitted(anim, dpi, even=ext != ".gif")
    if ext in (".html", ".htm"):
        page = jshtml(anim, fps, progress=progress) if fast is None else _jshtml_text(
            _image_animation(*fast, fps, progress), fps)
        path.write_text(html_page(page, title=title), encoding="utf-8")
    elif fast is not None:
        (_write_gif(path, *fast, fps, progress) if ext == ".gif" else _write_mp4(path, *fast, fps, ffmpeg, progress))
    elif ext == ".gif":
        from matplotlib.animation import PillowWriter
        anim.save(str(path), writer=PillowWriter(fps=fps), dpi=dpi, progress_callback=progress)
    else:
        matplotlib.rcParams["animation.ffmpeg_path"] = ffmpeg
        from matplotlib.animation import FFMpegWriter
        anim.save(str(path), writer=FFMpegWriter(fps=fps, codec="libx264",
                                                 extra_args=["-pix_fmt", "yuv420p"]), dpi=dpi,
                  progress_callback=progress)


# the player's icons without the font-awesome style sheet that to_jshtml links from a CDN: small inline SVG paths
# (14 × 14, the text colour), not characters, since fonts lack some of the media symbols (⏮, ⏭ are empty boxes in
# Debian's Chromium)
_PATHS = {"fa-minus": "M2 6h10v2H2z",
          "fa-fast-backward": "M2 2h2v10H2zM8 7l5-5v10zM3 7l5-5v10z",
          "fa-step-backward": "M3 2h2v10H3zM5 7l7-5v10z",
          "fa-flip-horizontal": "M11 2v10L3 7z",
          "fa-pause": "M3 2h3v10H3zM8 2h3v10H8z",
          "fa-play": "M3 2l8 5-8 5z",
          "fa-step-forward": "M9 2h2v10H9zM2 2l7 5-7 5z",
          "fa-fast-forward": "M10 2h2v10h-2zM1 2l5 5-5 5zM6 2l5 5-5 5z",
          "fa-plus": "M6 2h2v4h4v2H8v4H6V8H2V6h4z"}
_ICONS = {k: (f'<svg width="14" height="14" viewBox="0 0 14 14" fill="currentColor" focusable="false" '
              f'style="vertical-align:-2px"><path d="{d}"/></svg>') for k, d in _PATHS.items()}


def jshtml(anim, fps: float = 20.0, default_mode: str = "loop", progress=None) -> str:
    """``anim.to_jshtml()`` made self-contained: the frames are embedded (base64 PNG) and the
    link to the icon font on a CDN is replaced by inline SVG icons (no network access, no font needed).
    An animation of :func:`animation` is drawn by blitting (``progress(i, n)`` is called per frame)."""
    fast = _blitted(anim, even=True)
    return _jshtml_text(anim if fast is None else _image_animation(*fast, fps, progress), fps, default_mode)


def _jshtml_text(anim, fps: float, default_mode: str = "loop") -> str:
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
