"""The chooser of assemblies: every assembly of the committed mechanism at the page's current input, and the edit
that puts the sketch on one of them (docs/designer.md, "Assemblies").

:func:`assemblies_message` answers the page's ``assemblies`` request from :func:`assur.engine.assemblies` (every real
assembly of a planar mechanism at one input: all combinations of its groups' assemblies, each with its branch
identity, one entry per branched group in the plan's order: a dyad's sign ±1, a Newton-solved group's (sign of its
certificate determinant, index among that group's assemblies there); ``sketch``: the one the committed document
solves to). :func:`assembled` makes the edit ``{"kind": "assembly", "input": q, "branches": [...]}``: the document's
points moved to that assembly at that input (the points it does not move keep their sketch exactly), the
``[branches]`` hints of its dyads turned to it, and the result checked: the new document solves to the chosen
assembly at that input, and that assembly is the one its sketch chooses. So the file stays the single source of
truth: the plan's branch signs follow from the moved sketch.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from ..errors import AssurError
from . import document as D

#: a chosen assembly is drawn when the new document solves to it within this share of the mechanism's size
DRAWN_TOLERANCE = 1e-7
#: a point moves when its new sketch lies farther than this share of the mechanism's size (round-off: it stays)
ROUND_OFF = 1e-12


def available() -> bool:
    """Whether the engine enumerates assemblies (``assur.engine.assemblies``): the page offers the chooser then."""
    from .. import engine
    return hasattr(engine, "assemblies")


def enumerate_at(plan, inputs):
    """Every assembly of ``plan`` at the input vector ``inputs (n_inputs,)``: a list of
    :class:`~assur.engine.planar.assemblies.Assembly` (``branches``, ``pos (n_points, 2)``, ``sketch``,
    ``closure``, ``certified``)."""
    from .. import engine
    if not available():
        raise D.EditRefused("this assur does not enumerate assemblies (assur.assemblies)", "assemblies")
    return engine.assemblies(plan, np.asarray(inputs, dtype=float)[None, :])[0]


def input_vector(plan, value, index: int = 0) -> np.ndarray:
    """(n_inputs,) the sketch's inputs with input ``index`` at ``value`` (SI; None: the sketch's); refused unless a
    finite number."""
    q = np.array(plan.sketch_inputs, dtype=float)
    if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < plan.n_inputs:
        raise D.EditRefused(f"no input {index!r} (the mechanism has {plan.n_inputs})", "input")
    if value is None:
        return q
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or abs(value) >= 1e9:
        raise D.EditRefused(f"the input must be a finite number (rad or m) below 1e9: {value!r}", "input")
    q[index] = float(value)
    return q


def branch_groups(plan, structure) -> list[dict]:
    """One record per entry of an assembly's ``branches`` (the plan's branched dyads and Newton-solved groups, in
    its order): ``label`` (the group's structural label), ``kind`` and ``point`` (a dyad's) or None."""
    from ..engine.plan import BRANCHED
    from ..structure.assur import roman
    labels = {}
    for g in structure.groups:
        names = ", ".join(dict.fromkeys(structure.graph.bodies[b].source or structure.body_label(b) for b in g.bodies))
        for b in g.bodies:
            labels[b] = f"{roman(g.group_class)}({names})"
    out = []
    for st in plan.steps:
        if st.kind in BRANCHED or st.kind == "newton":
            label = next((labels[b] for b in st.bodies if b in labels), st.kind)
            out.append({"label": label, "kind": st.kind, "point": st.key_point})
    return out


def identity(branches) -> list:
    """An assembly's branch identity as JSON: dyads' signs, a Newton group's [sign, index]."""
    return [list(b) if isinstance(b, (tuple, list)) else int(b) for b in branches]


def label_of(groups: list[dict], branches) -> str:
    """One line naming an assembly: each group's branch (a dyad's + or −, a Newton group's assembly number and its
    determinant's sign)."""
    parts = []
    for g, b in zip(groups, identity(branches)):
        if isinstance(b, list):
            parts.append(f"{g['label']} #{b[1] + 1} (det {'+' if b[0] > 0 else '−'})")
        else:
            parts.append(f"{g['label']} {'+' if b > 0 else '−'}")
    return " · ".join(parts)


def assemblies_message(plan, structure, value, index: int = 0) -> dict:
    """The ``assemblies`` answer (without ``seq``) at input ``index`` = ``value`` (SI; the others at the sketch's):
    ``input``, ``inputs``, ``point_order``, ``groups`` (:func:`branch_groups`) and ``assemblies``: per assembly its
    ``index``, ``branches`` (:func:`identity`), ``label``, ``current`` (the committed document's own), ``certified``,
    ``closure`` (relative to the size) and ``positions`` [[x, y]] (m, in ``point_order``)."""
    if plan.dimension != 2:
        raise D.EditRefused("assemblies are enumerated for planar mechanisms", "assemblies")
    q = input_vector(plan, value, index)
    groups = branch_groups(plan, structure)
    found = enumerate_at(plan, q)
    from ..engine.planar.assemblies import twins
    shared = [twins(plan, found, k) for k in range(len(found))]
    return {"type": "assemblies", "input": float(q[index]), "index": int(index), "inputs": q.tolist(),
            "point_order": list(plan.point_names), "groups": groups,
            "assemblies": [{"index": k, "branches": identity(a.branches),
                            "label": label_of(groups, a.branches) + (
                                f" (the points of #{', #'.join(str(j + 1) for j in shared[k][0])}, "
                                f"{', '.join(plan.body_names[b] for b in shared[k][1])} turned)" if shared[k] else ""),
                            "current": bool(a.sketch), "certified": bool(a.certified), "closure": float(a.closure),
                            "positions": np.asarray(a.pos, dtype=float).tolist()} for k, a in enumerate(found)]}


def assembled(session, doc: dict, edit: dict) -> tuple[dict, set]:
    """(``doc`` on the assembly ``edit["branches"]`` at input ``edit["input"]``, the signature keys it may change):
    see the module docstring. ``session`` compiles documents (:meth:`~.session.Session.compiled`, ``_signature``)."""
    from ..engine.plan import BRANCHED
    c = session.compiled(doc)
    if isinstance(c, AssurError):
        raise D.EditRefused(f"no assemblies: the document is not a mechanism yet ({c})", "assembly")
    plan = c[2]
    if plan.dimension != 2:
        raise D.EditRefused("a spatial mechanism is shown, not edited", "assembly")
    q = input_vector(plan, edit.get("input"), edit.get("index", 0))
    want = edit.get("branches")
    if not isinstance(want, list):
        raise D.EditRefused(f"an assembly edit needs branches: the identity of an assembly (as the page lists it): "
                            f"{want!r}", "branches")
    found = enumerate_at(plan, q)
    chosen = next((a for a in found if identity(a.branches) == want), None)
    if chosen is None:
        shown = "; ".join(str(identity(a.branches)) for a in found) or "none"
        raise D.EditRefused(f"no assembly {want} at this input (there: {shown})", "branches")
    new = copy.deepcopy(doc)
    fL = D.length_factor(new)
    frame = set(D.link_points(new["links"].get("frame", [])))
    scale = float(plan.length_scale)
    for k, name in enumerate(plan.point_names):
        if name in new["points"] and name not in frame:
            old = [v * fL for v in new["points"][name]]
            if math.hypot(chosen.pos[k][0] - old[0], chosen.pos[k][1] - old[1]) > ROUND_OFF * scale:
                new["points"][name] = [float(v) / fL for v in chosen.pos[k]]
    # the dyads' hints turned to the chosen branches (a hint overrides the sketch)
    branched = [st for st in plan.steps if st.kind in BRANCHED or st.kind == "newton"]
    for st, sign in zip(branched, chosen.branches):
        if st.kind == "newton" or int(sign) == st.branch:
            continue
        hint = new.get("branches", {}).get(st.key_point)
        if st.kind == "RPR":
            session._flip_slide_hint(new, st, plan.lines[st.line][1])
        elif isinstance(hint, dict) and hint.get("side") in ("left", "right"):
            hint["side"] = "left" if hint["side"] == "right" else "right"
    for st, sign in zip(branched, chosen.branches):
        if st.kind == "RPR" and int(sign) != st.branch and \
                session._signature(new).get((st.key_point, st.kind), (None,))[0] != int(sign):
            new = copy.deepcopy(new)
            session._flip_slide_hint(new, st, plan.lines[st.line][1], add=True)
    _check_drawn(session, new, q, chosen, scale, want)
    return new, set(session._signature(doc)) | set(session._signature(new))


def _check_drawn(session, new: dict, q, chosen, scale: float, want) -> None:
    """Refuse unless ``new`` solves to ``chosen`` at ``q`` and that is the assembly its sketch chooses."""
    from ..engine import solve
    c = session.compiled(new)
    if isinstance(c, AssurError):
        raise D.EditRefused(f"the mechanism could not be drawn on the assembly {want}: {c}", "assembly")
    plan = c[2]
    state = solve(plan, inputs=q[None, :], order=0)
    pos = np.asarray(state.pos, dtype=float).reshape(-1, plan.n_points, 2)[0]
    off = float(np.nanmax(np.hypot(*(pos - chosen.pos).T))) if np.all(np.isfinite(pos)) else math.inf
    mine = [a for a in enumerate_at(plan, q) if a.sketch]
    if not off <= DRAWN_TOLERANCE * scale or not mine or identity(mine[0].branches) != want:
        raise D.EditRefused(f"the mechanism could not be drawn on the assembly {want} at this input (its gears, "
                            f"cams or hints tie it to the sketch's input: choose at the sketch's input)", "assembly")


__all__ = ["assembled", "assemblies_message", "available", "branch_groups", "enumerate_at", "identity",
           "input_vector", "label_of"]
