"""One validation and one compile per document the designer shows, and the structural cache behind them.

A document the page sends (an edit of the committed one) is read once by the file reader
(:func:`assur.io.mechanism_file.from_dict`: the file's own rules; a document it refuses never enters the history)
and compiled once. Its Assur decomposition depends on its topology only (names, links' points, pairs, drivers:
never a number), so :class:`StructureCache` keeps it by :func:`topology_key`: a drag, which changes numbers only,
never decomposes again. The branch check of a drag compares the branch each group's sketch shows before and after
(:func:`~assur.engine.planar.compile.sketch_branch_signs`, read from the same compiled plan: no second compile
without the ``[branches]`` hints), so the key of a compiled group is its topology and its branch signs.
"""
from __future__ import annotations

import dataclasses
import warnings
from collections import OrderedDict
from dataclasses import dataclass, field

from ..errors import AssurError, SpecError

#: how many topologies a session keeps decomposed
STRUCTURES_KEPT = 16


@dataclass
class Compiled:
    """What one document gives: ``invalid`` (the SpecError of the file reader, when the document breaks the file's
    rules), else ``mechanism``; ``error`` (the AssurError of compiling it: not a mechanism yet) or ``structure``
    and ``plan``; the ``warnings`` of reading and compiling; ``signs``: the branch of every branched group as the
    sketch draws it, ``{(point, kind): (sign, points it is solved from)}``."""
    invalid: SpecError | None = None
    mechanism: object = None
    structure: object = None
    plan: object = None
    error: AssurError | None = None
    warnings: list = field(default_factory=list)
    signs: dict = field(default_factory=dict)

    def described(self):
        """What :func:`~.payload.describe` takes as ``compiled``: ``(mechanism, structure, plan, warnings)`` or the
        AssurError that stopped the document."""
        if self.invalid is not None:
            return self.invalid
        if self.error is not None:
            return self.error
        return self.mechanism, self.structure, self.plan, self.warnings


#: the parts of a Mechanism its Assur decomposition reads (its name, description, units, gait, masses and branch
#: hints it does not)
TOPOLOGY_FIELDS = ("dimension", "points", "links", "prismatic", "actuators", "drivers", "gears", "joints")


def topology_key(m) -> tuple:
    """Every part of a mechanism's topology that is not a real number (point names, links' points, pairs, drivers,
    gears, joints: :data:`TOPOLOGY_FIELDS`), as a hashable tuple: two drawings of one topology have the same key."""
    def walk(x):
        if isinstance(x, float):
            return None
        if isinstance(x, (str, int, bool)) or x is None:
            return x
        if isinstance(x, (list, tuple)):
            return tuple(walk(v) for v in x)
        if dataclasses.is_dataclass(x):
            return (type(x).__name__, *(walk(getattr(x, f.name)) for f in dataclasses.fields(x)))
        if isinstance(x, dict):
            return tuple((walk(k), walk(v)) for k, v in x.items())
        return type(x).__name__        # numpy scalars and arrays: numbers
    return tuple(walk(getattr(m, name)) for name in TOPOLOGY_FIELDS)


class StructureCache:
    """Assur decompositions of the topologies a session met (:data:`STRUCTURES_KEPT`, least recently used
    dropped)."""

    def __init__(self):
        self._kept: OrderedDict = OrderedDict()

    def structure(self, m):
        from ..structure.assur import analyse
        key = topology_key(m)
        hit = self._kept.get(key)
        if hit is None:
            try:
                hit = analyse(m)
            except AssurError as exc:
                hit = exc
            self._kept[key] = hit
            if len(self._kept) > STRUCTURES_KEPT:
                self._kept.popitem(last=False)
        else:
            self._kept.move_to_end(key)
        if isinstance(hit, AssurError):
            raise hit
        return hit


def compile_doc(doc: dict, structures: StructureCache) -> Compiled:
    """Validate (one :func:`~assur.io.mechanism_file.from_dict`) and compile (one :func:`assur.engine.api.compile`
    on the cached decomposition) a document; never raises an AssurError."""
    from ..engine import api
    from ..io import mechanism_file
    out = Compiled()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out.mechanism = mechanism_file.from_dict(doc, source="the designer's document")
        except SpecError as exc:
            out.invalid = exc
            return out
        try:
            if out.mechanism.dimension == 2:
                out.structure = structures.structure(out.mechanism)
                out.plan = api.compile(out.mechanism, structure=out.structure)
            else:
                from ..structure.assur import analyse
                out.structure = analyse(out.mechanism)
                out.plan = api.compile(out.mechanism)
        except AssurError as exc:
            out.error = exc
    out.warnings = list(caught)
    if out.plan is not None:
        out.signs = branch_signs(out.plan)
    return out


def branch_signs(plan) -> dict:
    """The branch of every branched group as the plan's sketch draws it (``[branches]`` hints set aside; where the
    sketch does not tell, and in a file without hints, the plan's own: compilation chose it nearest the sketch; an RPR
    group's ``slide`` hint stands, as the sketch may not show its branch at all),
    keyed by (point, kind), with the points it is solved from; a Newton-solved group by (its bodies, "newton"), with
    the sign of its Jacobian at the sketch."""
    if plan.dimension != 2:
        return {}
    from ..engine.planar.compile import newton_branch_signs, sketch_branch_signs
    # without a [branches] hint the plan's own branches are the sketch's (compilation chose them so): nothing to solve
    drawn = sketch_branch_signs(plan) if plan.mechanism.branches else {}
    # an RPR group with a slide hint is on the hint's branch, whatever the sketch shows (it may show none)
    slid = {(h.point, h.on) for h in plan.mechanism.branches if h.slide is not None}
    sig = {}
    for i, st in enumerate(plan.steps):
        if st.key_point is not None:
            sign = None if st.kind == "RPR" and (st.key_point, plan.lines[st.line][1]) in slid else drawn.get(i)
            sig[(st.key_point, st.kind)] = (int(st.branch if sign is None else sign), st.points_in())
    if plan.has_newton_groups:
        for i, sign in newton_branch_signs(plan).items():
            names = tuple(plan.body_names[b] for b in plan.steps[i].bodies)
            sig[(", ".join(names), "newton")] = (sign, names)
    return sig


__all__ = ["Compiled", "StructureCache", "branch_signs", "compile_doc", "topology_key"]
