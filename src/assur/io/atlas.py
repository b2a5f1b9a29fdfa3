"""Each atlas entry as a mechanism: the mechanism file of a sketch that assembles, and its SVG drawing
(docs/atlas.md, "Each entry as a mechanism"); a face of the atlas (:mod:`assur.structure.atlas`, the mathematics).

:func:`mechanism_entry` tries the sketches of :func:`assur.structure.atlas.layout.sketch` (attempt 0, 1, …) until
the engine assembles one over a full crank turn: it compiles the mechanism file's document, solves it at the
sketch (``state.valid``) and at :data:`SAMPLES` crank angles over one turn from the sketch. Each sketch is first
screened at :data:`SCREEN` crank angles. It keeps the first sketch that turns fully, else the assembling sketch
that turns furthest (the earliest among equals), else the first sketch, flagged as not assembling. :func:`svg` draws a sketch as plain SVG text (fixed number formatting:
the same bytes on every run).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from xml.sax.saxutils import escape

import numpy as np

from ..errors import AssurError
from ..model.mechanism import Mechanism
from ..structure.atlas.layout import Sketch, document, sketch
from ..structure.atlas.mechanisms import Inversion, driver_placements
from .mechanism_file import from_dict

__all__ = ["ATTEMPTS", "SAMPLES", "AtlasMechanism", "entry_name", "mechanism_entry", "mechanism_of", "svg",
           "turn_share"]

#: the sketches tried per entry before giving up on a full crank turn
ATTEMPTS = 8
#: the crank angles of the full-turn check (one turn, 1° apart)
SAMPLES = 360
#: the crank angles of the quick check that screens a sketch before the full-turn check
SCREEN = 24
#: the size of a drawing (SVG user units) of the sketch's larger extent
DRAWING = 400.0


@dataclass(frozen=True)
class AtlasMechanism:
    """The mechanism of an atlas entry: ``sketch`` and its mechanism file ``document``; ``assembles``: the engine
    assembles it at the sketch; ``turn``: the share of the :data:`SAMPLES` crank angles of one turn (from the
    sketch) at which it assembles; ``full_turn``: all of them; ``attempts``: the sketches tried; ``problem``: the
    engine's message when no sketch assembled."""
    sketch: Sketch
    document: dict
    mechanism: Mechanism
    assembles: bool
    turn: float
    full_turn: bool
    attempts: int
    problem: str | None = None

    @property
    def name(self) -> str:
        return entry_name(self.sketch.inversion, self.sketch.crank)


def entry_name(inversion: Inversion, crank: int) -> str:
    """The file stem of an entry: ``<chain id>_f<frame>_c<crank>`` (the inversion ID without its slash)."""
    return f"{inversion.chain.id}_f{inversion.frame}_c{crank}"


def turn_share(mechanism: Mechanism, samples: int = SAMPLES) -> tuple[bool, float]:
    """(assembles at the sketch, share of the crank angles that assemble): ``samples`` + 1 angles from half a
    turn before the sketch's to half a turn after it (the solver walks each from the sketch, so both halves are
    reached without passing a dead point). A full turn (share 1) also needs the two ends, the same crank angle
    reached both ways round, to give the same positions; else the share is at most ``samples / (samples + 1)``."""
    from ..engine import compile as compile_plan
    from ..engine import solve
    plan = compile_plan(mechanism)
    q0 = float(plan.sketch_inputs[0])
    at = solve(plan, inputs=q0, order=0)
    if not bool(np.all(at.valid)):
        return False, 0.0
    qs = q0 + math.pi * np.linspace(-1.0, 1.0, samples + 1)
    st = solve(plan, inputs=qs, order=0)
    valid = np.asarray(st.valid, dtype=bool)
    share = float(np.mean(valid))
    if share == 1.0:
        pos = np.asarray(st.pos)
        if not np.allclose(pos[0], pos[-1], rtol=0.0, atol=1e-6 * plan.length_scale):
            share = float(samples) / (samples + 1)
    return True, share


def mechanism_entry(inversion: Inversion, crank: int | None = None, attempts: int = ATTEMPTS,
                    samples: int = SAMPLES) -> AtlasMechanism:
    """The mechanism of ``inversion`` driven by ``crank`` (default: its first crank placement), by the first
    sketch that assembles over a full turn (module docstring)."""
    if crank is None:
        places = driver_placements(inversion)
        if not places:
            raise ValueError(f"{inversion.id} has no link hinged to its frame")
        crank = places[0].link
    best = None
    first = None
    for a in range(attempts):
        sk = sketch(inversion, crank, a)
        doc = document(sk)
        mech = from_dict(doc, entry_name(inversion, crank))
        try:
            ok, share = turn_share(mech, SCREEN)
            if ok and share == 1.0:
                ok, share = turn_share(mech, samples)
            problem = None if ok else "the engine does not assemble the sketch"
        except AssurError as exc:
            ok, share, problem = False, 0.0, str(exc)
        entry = AtlasMechanism(sk, doc, mech, ok, share, ok and share == 1.0, a + 1, problem)
        if first is None:
            first = entry
        if entry.full_turn:
            return entry
        if ok and (best is None or share > best.turn):
            best = entry
    chosen = best if best is not None else first
    share = chosen.turn
    if chosen.assembles:        # the screen's share, measured again at the full resolution
        share = turn_share(chosen.mechanism, samples)[1]
    return AtlasMechanism(chosen.sketch, chosen.document, chosen.mechanism, chosen.assembles, share,
                          chosen.assembles and share == 1.0, attempts, chosen.problem)


def mechanism_of(inversion: Inversion, crank: int | None = None) -> Mechanism:
    """The :class:`Mechanism` of an atlas entry (:func:`mechanism_entry`): joints ``J0 …``, links ``frame``,
    ``L1 …``, lengths from the sketch (mm), a rotary driver ``crank`` on the crank about the frame."""
    return mechanism_entry(inversion, crank).mechanism


# -- the drawing ---------------------------------------------------------------------------------------------

def _f(v: float) -> str:
    """A coordinate as fixed text (two decimals, no negative zero)."""
    text = f"{v:.2f}"
    return "0.00" if text == "-0.00" else text


def svg(sk: Sketch, title: str | None = None, *, foot=None, path=None) -> str:
    """The drawing of a sketch as SVG text: one element of class ``link`` per link (a ``line`` for a binary link,
    a ``polygon`` through its joints otherwise; the frame hatched, the crank marked), one ``circle`` of class
    ``joint`` per joint, the frame's ground marks and the crank's turning arrow. ``foot``: (link, (x, y)) a foot
    point on that link, drawn as a bar from the link's joints to a dot of class ``foot``; ``path``: (M, 2) the
    foot's closed path, a polyline of class ``path`` (both in the sketch's coordinates). Plain text, fixed
    formatting."""
    inv = sk.inversion
    J = np.array(sk.joints, dtype=float)
    extra = [np.asarray(foot[1], dtype=float)[None, :]] if foot is not None else []
    if path is not None:
        extra.append(np.asarray(path, dtype=float).reshape(-1, 2))
    every = np.vstack([J, *extra])
    extent = float(np.max(np.ptp(every, axis=0))) or 1.0
    scale = DRAWING / extent                         # the drawing's size, whatever the sketch's
    P = J * scale
    margin = 25.0
    lo = every.min(axis=0) * scale - margin
    hi = every.max(axis=0) * scale + margin
    w, h = hi - lo

    def at(p) -> tuple[str, str]:
        return _f(p[0] * scale - lo[0]), _f(hi[1] - p[1] * scale)

    def xy(k: int) -> tuple[str, str]:
        x, y = P[k]
        return _f(x - lo[0]), _f(hi[1] - y)          # y up in the sketch, down in SVG

    ln, jn = sk.link_names, sk.joint_names
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {_f(w)} {_f(h)}" width="{_f(w)}" '
           f'height="{_f(h)}" font-family="sans-serif" font-size="7">',
           f"<title>{escape(title or (inv.name or inv.id))}</title>",
           '<defs><pattern id="hatch" width="5" height="5" patternUnits="userSpaceOnUse" '
           'patternTransform="rotate(45)"><line x1="0" y1="0" x2="0" y2="5" stroke="#555" stroke-width="1"/>'
           '</pattern></defs>']
    frame_joints = [k for k, e in enumerate(inv.chain.edges) if inv.frame in e]
    # ground marks under the frame's joints
    marks = []
    for k in frame_joints:
        x, y = (float(c) for c in xy(k))
        marks.append(f"M{_f(x - 8)} {_f(y + 9)}h16")
        marks += [f"M{_f(x - 8 + 4 * i)} {_f(y + 9)}l-4 5" for i in range(5)]
    out.append(f'<path class="ground" d="{" ".join(marks)}" stroke="#555" stroke-width="1" fill="none"/>')
    for v in range(inv.chain.n):
        ks = sk.links[v]
        cls = "link frame" if v == inv.frame else "link crank" if v == sk.crank else "link"
        colour = "#555" if v == inv.frame else "#c0392b" if v == sk.crank else "#2c6fbb"
        attrs = f'class="{cls}" data-name="{ln[v]}"'
        if len(ks) == 2:
            (x1, y1), (x2, y2) = xy(ks[0]), xy(ks[1])
            width = 5 if v == inv.frame else 3
            out.append(f'<line {attrs} x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}" stroke="{colour}" '
                       f'stroke-width="{width}" stroke-linecap="round"/>')
        else:
            pts = " ".join(",".join(xy(k)) for k in ks)
            fill = "url(#hatch)" if v == inv.frame else colour
            out.append(f'<polygon {attrs} points="{pts}" fill="{fill}" fill-opacity="0.35" stroke="{colour}" '
                       f'stroke-width="2" stroke-linejoin="round"/>')
    # the crank's turning arrow: an arc about its pivot
    px, py = (float(c) for c in xy(sk.pivot))
    r = 11.0
    out.append(f'<path class="drive" d="M{_f(px + r)} {_f(py)}A{_f(r)} {_f(r)} 0 1 0 {_f(px)} {_f(py + r)}'
               f'l-3 -3m3 3l-3 3" stroke="#c0392b" stroke-width="1.2" fill="none"/>')
    if path is not None:
        pts = " ".join(",".join(at(p)) for p in np.asarray(path, dtype=float).reshape(-1, 2))
        out.append(f'<polygon class="path" points="{pts}" fill="none" stroke="#1a7f37" stroke-width="1.5"/>')
    if foot is not None:
        fx, fy = at(foot[1])
        for j in sk.links[foot[0]]:
            x, y = xy(j)
            out.append(f'<line class="link foot-bar" x1="{x}" y1="{y}" x2="{fx}" y2="{fy}" stroke="#2c6fbb" '
                       'stroke-width="2" stroke-opacity="0.6"/>')
    for k in range(len(sk.joints)):
        x, y = xy(k)
        out.append(f'<circle class="joint" data-name="{jn[k]}" cx="{x}" cy="{y}" r="3" fill="#fff" '
                   f'stroke="#222" stroke-width="1.2"/>')
    for v in range(inv.chain.n):
        c = P[list(sk.links[v])].mean(axis=0)
        out.append(f'<text class="label" x="{_f(c[0] - lo[0] + 4)}" y="{_f(hi[1] - c[1] - 4)}" '
                   f'fill="#333">{ln[v]}</text>')
    if foot is not None:
        fx, fy = at(foot[1])
        out.append(f'<circle class="foot" cx="{fx}" cy="{fy}" r="4" fill="#1a7f37"/>')
    out.append("</svg>")
    return "\n".join(out) + "\n"
