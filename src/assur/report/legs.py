"""The walking-leg ranking as files: a report page with a thumbnail, the metrics and a ready mechanism file per
entry (docs/atlas.md, "Walking legs ranked by gait"); a face of the atlas (:mod:`assur.structure.atlas`) and of
its ranking (:mod:`assur.synthesis.legs`).

:func:`write_leg_ranking` writes, into one directory at once (all or nothing):

* ``index.html``: the ranking, best first, one row per candidate: rank, drawing (inline SVG: the leg at its
  sketch position and the foot's path), name and key, objective, the exact gait metrics and the file's name;
* ``ranking.json``: the same as data (format ``assur-legs/1``; the mechanism files' texts left out);
* ``NN_<stem>.toml``: the best design of each candidate as an ``assur/1`` mechanism file (with its ``[gait]``),
  ``NN_<stem>.svg``: its drawing.
"""
from __future__ import annotations

import dataclasses
import json

import numpy as np

from .page import escape, header, page, section, table

__all__ = ["leg_drawing", "leg_rows", "leg_stem", "write_leg_ranking"]

#: the crank angles of a drawn foot path
PATH_SAMPLES = 120


def leg_stem(entry: dict) -> str:
    """The file stem of a ranked entry: ``NN_<inversion id without the slash>_<crank>_<foot link>``."""
    inv = entry["inversion"].replace("/", "_")
    return f"{entry['rank']:02d}_{inv}_{entry['crank']}_foot{entry['foot_link']}"


def leg_drawing(entry: dict, sketch) -> str:
    """The SVG drawing of a ranked entry: its mechanism file solved at its sketch's crank angle (the atlas
    ``sketch``'s joints moved there) with the foot point and the foot's path over one turn."""
    from ..engine import compile as compile_plan
    from ..engine import solve
    from ..io.atlas import svg
    from ..io.mechanism_file import loads
    from ..synthesis.legs import FOOT
    plan = compile_plan(loads(entry["mechanism"]))
    q0 = float(plan.sketch_inputs[0])
    at = solve(plan, inputs=q0, order=0)
    names = sketch.joint_names
    joints = tuple((float(x), float(y)) for x, y in (at.pos[plan.point_index(n)] for n in names))
    moved = dataclasses.replace(sketch, joints=joints)
    q = q0 + np.linspace(0.0, 2 * np.pi, PATH_SAMPLES, endpoint=False)
    st = solve(plan, inputs=q, order=0)
    path = np.asarray(st.pos)[:, plan.point_index(FOOT)]
    path = path[np.asarray(st.valid, dtype=bool)]
    foot_link = sketch.link_names.index(entry["foot_link"])
    return svg(moved, f"#{entry['rank']} {entry['name']}", foot=(foot_link, at.pos[plan.point_index(FOOT)]),
               path=path if len(path) > 2 else None)


def _n(v, digits=4) -> str:
    return "—" if v is None else f"{v:.{digits}g}"


def leg_rows(entries) -> list[list[str]]:
    """The ranking's table rows (text): rank, name, objective, step, lift, sag (mm), vx spreads, transmission; and
    when the ranking is by window (an entry's metrics have ``window``: :data:`WINDOW_HEAD`), the widest screened
    window, the worst screen margin at the target window and the window's pressure-angle bound there."""
    rows = []
    windows = any("window" in (e["metrics"] or {}) for e in entries)
    for e in entries:
        m = e["metrics"] or {}
        status = ("skipped" if e.get("skipped") else "refused" if e.get("refused")
                  else "yes" if e["feasible"] and e["metrics"] else "no")
        rows.append([str(e["rank"]), e["name"], status,
                     _n(e["objective"]), _n(m.get("step")), _n(m.get("lift")), _n(m.get("sag")),
                     _n(m.get("vx_spread_80")), _n(m.get("vx_spread_90")), _n(m.get("transmission_min"), 3)])
        if windows:
            rows[-1] += [_n(m.get("window"), 3), m.get("window_target_worst") or "—",
                         _n(m.get("window_pressure_bound"), 3)]
    return rows


WINDOW_HEAD = ["widest window", "worst at 0.9", "μ bound at 0.9 (°)"]
HEAD = ["rank", "leg", "feasible", "objective", "step (mm)", "lift (mm)", "sag (mm)", "|vx| spread 80 %",
        "|vx| spread 90 %", "min transmission (°)"]


def _page(ranking, drawings: dict) -> str:
    s = ranking.settings
    meta = (f"{len(ranking.entries)} candidates of {ranking.links} links, 1 DOF; crank r = 100 mm; "
            f"{s['budget']} evaluations and {s['starts']} starts per candidate ({s['method']}), seed {s['seed']}; "
            f"{escape(ranking.executor)}, {ranking.seconds:.0f} s")
    desc = (f"Each candidate is an atlas mechanism, a crank at its frame and a foot point on one of its links, "
            f"dimensioned by a short gait synthesis: step ≥ {s['step']:g} r, lift ≥ {s['lift']:g} r, "
            f"the foot path ≥ {s['below']:g} r under the crank's axis, transmission angle ≥ {s['transmission']:g}° wherever a dyad has one, "
            + (f"a swing ≥ {s['clearance']:g} r above the support, " if s.get("clearance") else "")
            + f"the crank turning fully; objective = sag / "
            f"({s['step']:g} r / 10) + spread of |vx| over the central 80 % of the stride. Metrics: the exact gait "
            f"of each best design (720 crank angles). A design the search found feasible is refused when its exact "
            f"gait contradicts the search's samples (another part of the path taken for the support, or a crank that "
            f"does not turn fully). Ground: the x axis, up: +y.")
    rows = leg_rows(ranking.entries)
    by_window = s.get("rank") == "window"
    if by_window:
        desc += (" Ranked by the widest constant-speed window the co-design screen passes (docs/codesign.md): the "
                 "widest window a gear pair passing every check may give each leg; at 0.9, the screen's worst "
                 "margin and the window's own pressure-angle bound.")
    head = HEAD + WINDOW_HEAD if rows and len(rows[0]) > len(HEAD) else HEAD
    title = "the widest constant-speed window" if by_window else "gait"
    parts = header(f"Walking legs of {ranking.links} links ranked by {title}", meta, desc)
    parts.append(section("Ranking", '<div class="scroll">' + table(head, rows, num_cols=(
        0, 3, 4, 5, 6, 7, 8, 9, *((10, 12) if head is not HEAD else ()))) + "</div>"))
    cards = []
    for e in ranking.entries:
        stem = leg_stem(e)
        m = e["metrics"] or {}
        starts = ", ".join(f"{v:.4g}" for v in e["starts"])
        cards.append(f'<div class="leg" id="{escape(stem)}"><h3>#{e["rank"]} {escape(e["name"])}</h3>'
                     f'<p class="meta"><code>{escape(e["key"])}</code> · objective {_n(e["objective"])} · '
                     f'duty {_n(m.get("duty"), 3)} · starts {escape(starts or "—")} · '
                     f'<a href="{escape(stem)}.toml">{escape(stem)}.toml</a></p>'
                     + (f'<p class="note">{escape(e["skipped"])}</p>' if e.get("skipped") else "")
                     + (f'<p class="note">refused: {escape(e["refused"])}</p>' if e.get("refused") else "")
                     + f'<div class="thumb">{drawings[e["key"]]}</div></div>')
    parts.append(section("Entries", "\n".join(cards)))
    style = ("<style>.leg{display:inline-block;vertical-align:top;width:380px;margin:0 1em 1em 0}"
             ".leg h3{font-size:1em;margin:0.4em 0}.thumb svg{width:100%;height:auto;border:1px solid #ddd}</style>")
    return page(f"Walking legs of {ranking.links} links", [style, *parts])


def write_leg_ranking(ranking, out_dir, candidates) -> dict:
    """Write the ranking's files (module docstring) into ``out_dir`` at once; ``candidates``: the
    :class:`~assur.synthesis.legs.LegCandidate` of every entry (their sketches are drawn). Returns
    {file name: text}."""
    from ..io.output import atomic_directory
    by_key = {c.key: c for c in candidates}
    files, drawings = {}, {}
    for e in ranking.entries:
        stem = leg_stem(e)
        drawings[e["key"]] = leg_drawing(e, by_key[e["key"]].sketch)
        files[f"{stem}.toml"] = e["mechanism"]
        files[f"{stem}.svg"] = drawings[e["key"]]
    data = ranking.as_dict()
    for e in data["entries"]:
        e.pop("mechanism", None)
        e["file"] = f"{leg_stem(e)}.toml"
    files["ranking.json"] = json.dumps(data, ensure_ascii=False, indent=1) + "\n"
    files["index.html"] = _page(ranking, drawings)
    with atomic_directory(out_dir) as tmp:
        for name, text in files.items():
            (tmp / name).write_text(text, encoding="utf-8")
    return files
