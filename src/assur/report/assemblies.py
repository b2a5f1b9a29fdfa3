"""The assemblies of a mechanism at one input as text (``assur info FILE --assemblies``)."""
from __future__ import annotations

import numpy as np

from ..engine.plan import BRANCHED
from ..engine.planar.assemblies import twins
from ..errors import SpecError
from ..io.units import ANGLE, LENGTH
from .text import format_number

_ROMAN = {2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI", 7: "VII", 8: "VIII"}


def input_values(plan, texts) -> np.ndarray:
    """The inputs (n_inputs,) SI of ``--at`` values (file units: the angle unit for a crank, the length unit for an
    actuator), one per input in driver order; inputs not given stay at the sketch's. SpecError on a bad value."""
    q = np.array(plan.sketch_inputs, dtype=float)
    texts = list(texts or [])
    if len(texts) > plan.n_inputs:
        raise SpecError([("--at", f"give at most one value per input ({plan.n_inputs}: "
                                  f"{', '.join(plan.input_names)}): {len(texts)} given")])
    u = plan.mechanism.units
    for k, t in enumerate(texts):
        try:
            v = float(t)
        except ValueError:
            v = float("nan")
        if not np.isfinite(v):
            raise SpecError([("--at", f"must be a number (input {plan.input_names[k]} in the file's units): {t!r}")])
        q[k] = v * (ANGLE[u.angle] if plan.input_kinds[k] == "rotary" else LENGTH[u.length])
    return q


def branch_labels(plan, assembly) -> list[str]:
    """One label per branched group of the plan: a dyad's point and sign, a Newton-solved group's class, bodies,
    determinant sign and index."""
    out, it = [], iter(assembly.branches)
    for st in plan.steps:
        if st.kind in BRANCHED:
            out.append(f"{st.key_point} {'+' if next(it) > 0 else '−'}")
        elif st.kind == "newton":
            sign, k = next(it)
            cls = _ROMAN.get(st.group.group_class, str(st.group.group_class))
            names = ", ".join(plan.body_names[b] for b in st.bodies)
            out.append(f"{cls}({names}) det {'+' if sign > 0 else '−'} #{k + 1}")
    return out


def input_text(plan, q) -> str:
    u = plan.mechanism.units
    parts = []
    for k, v in enumerate(q):
        if plan.input_kinds[k] == "rotary":
            parts.append(f"{plan.input_names[k]} = {format_number(v / ANGLE[u.angle], 6)}"
                         f"{'°' if u.angle == 'deg' else ' rad'}")
        else:
            parts.append(f"{plan.input_names[k]} = {format_number(v / LENGTH[u.length], 6)} {u.length}")
    return ", ".join(parts)


def assembly_lines(plan, found, q) -> list[str]:
    """The assemblies ``found`` (a list of :class:`~assur.engine.planar.assemblies.Assembly`) at inputs ``q`` as
    text: each with its branches, whether it is the sketch's and its solved points in the file's length unit."""
    u = plan.mechanism.units
    f = LENGTH[u.length]
    moving = [i for i, p in enumerate(plan.point_names) if p not in plan.mechanism.frame.points]
    lines = [f"assemblies at {input_text(plan, q)}: {len(found)}"
             + ("" if all(a.certified for a in found) else " (next to a singular position: two assemblies of a "
                                                              "group could not be told apart)")]
    if not found:
        lines.append("  none: the mechanism cannot be assembled at this input")
    for i, a in enumerate(found, 1):
        tag = "  ← the sketch's (what assur solve follows)" if a.sketch else ""
        lines.append(f"  {i}. {'; '.join(branch_labels(plan, a)) or '(no branched group)'}{tag}")
        pts = "  ".join(f"{plan.point_names[j]} = ({format_number(a.pos[j, 0] / f, 6, plan.length_scale / f)}, "
                        f"{format_number(a.pos[j, 1] / f, 6, plan.length_scale / f)})" for j in moving)
        lines.append(f"     {pts} {u.length}; loops close to {a.closure:.1e} of the size")
        turned = twins(plan, found, i - 1)
        if turned:
            lines.append("     the same points as " + ", ".join(f"#{k + 1}" for k in turned[0])
                         + ", its bodies otherwise turned: "
                         + ", ".join(f"{plan.body_names[b]} at {format_number(a.angles[b] / ANGLE[u.angle], 6)}"
                                     f"{'°' if u.angle == 'deg' else ' rad'}" for b in turned[1]))
    return lines


def assembly_labels(plan, found) -> list[list[str]]:
    """Per assembly in ``found``, the lines naming it in a figure: its branches (:func:`branch_labels`) and, where
    another assembly places every point alike (:func:`~assur.engine.planar.assemblies.twins`), which."""
    out = []
    for i, a in enumerate(found):
        same = twins(plan, found, i)
        out.append(branch_labels(plan, a) + ([f"points as {', '.join(f'#{k + 1}' for k in same[0])}, bodies turned"]
                                             if same else []))
    return out
