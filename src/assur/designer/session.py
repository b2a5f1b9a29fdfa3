"""One designer session: the committed document, its history, the edits of a gesture and the answers to the page
(the protocol of ``docs/designer.md``), independent of the transport (a WebSocket or a notebook widget's comm).

:meth:`Session.handle` takes one request (a dict) and returns the replies, each ``(message dict, blob or None)``;
a blob holds the float64 arrays the message indexes. A request that cannot be carried out answers ``refused``
with the reason and changes nothing.
"""
from __future__ import annotations

import copy
import math
import time
from dataclasses import dataclass

from ..errors import AssurError
from . import document as D
from .payload import Description, branched_steps, compile_document, describe, pack

#: the largest history a session keeps (older entries are dropped)
HISTORY_LIMIT = 500


@dataclass
class Reply:
    message: dict
    blob: bytes | None = None


def document_of(mechanism_or_path) -> tuple[dict, str | None]:
    """(document, path or None) of a file path or a :class:`~assur.Mechanism`; a file's ``[style]`` table is kept."""
    from ..io.mechanism_writer import as_dict
    from ..model.mechanism import Mechanism
    if isinstance(mechanism_or_path, Mechanism):
        return as_dict(mechanism_or_path), None
    from ..io.toml_reader import read_text
    path = str(mechanism_or_path)
    return doc_of_toml(read_text(path), path), path


def toml_of(doc: dict) -> str:
    from ..io.toml_writer import dumps
    return dumps(doc)


def doc_of_toml(text: str, where: str = "the document") -> dict:
    """A document from ``assur/1`` text (the file reader's size and nesting limits, every problem located): it
    must load as a mechanism file; its ``[style]`` table is kept."""
    from ..io.mechanism_file import from_dict
    from ..io.mechanism_writer import as_dict
    from ..io.toml_reader import MAX_FILE_BYTES, parse_toml
    if not isinstance(text, str) or len(text.encode("utf-8", "surrogatepass")) > MAX_FILE_BYTES:
        raise D.EditRefused(f"{where} must be TOML text of at most {MAX_FILE_BYTES // 2**20} MiB", "toml")
    raw = parse_toml(text, where)
    if raw.get("format") != "assur/1":
        raise D.EditRefused(f"{where} is not an assur/1 mechanism file (format = {raw.get('format')!r})", "format")
    doc = as_dict(from_dict(raw, source=where))
    if isinstance(raw.get("style"), dict):
        doc["style"] = raw["style"]
    return doc


class Session:
    """The state behind one page: ``history`` (documents; ``position`` the committed one), the file ``path`` (or
    None), the parameter ``overrides`` of the spatial view and the running synthesis ``job``."""

    def __init__(self, doc: dict, path: str | None = None):
        self.history = [copy.deepcopy(doc)]
        self.position = 0
        self.saved_position = 0
        self.path = path
        self.overrides: dict = {}
        self.job = None
        self.best_toml: str | None = None
        self._texts: dict = {}        # id(doc) → (doc, its TOML text): history documents are never changed
        self._compiled: dict = {}     # TOML text → compile_document(doc) or the AssurError it raised

    # -- the document ------------------------------------------------------------------------------------------
    @property
    def doc(self) -> dict:
        return self.history[self.position]

    def history_entries(self) -> list[str]:
        """Every history entry as ``assur/1`` TOML text (oldest first)."""
        return [self.text(d) for d in self.history]

    def text(self, doc: dict) -> str:
        """The document's TOML text (kept for the documents of the session, which never change)."""
        hit = self._texts.get(id(doc))
        if hit is None or hit[0] is not doc:
            if len(self._texts) > 4 * HISTORY_LIMIT:
                live = {id(d) for d in self.history}
                self._texts = {k: v for k, v in self._texts.items() if k in live}
            hit = self._texts[id(doc)] = (doc, toml_of(doc))
        return hit[1]

    def compiled(self, doc: dict):
        """:func:`~.payload.compile_document` of ``doc`` (or the AssurError it raised), kept by its text."""
        key = self.text(doc)
        if key not in self._compiled:
            if len(self._compiled) > 32:
                self._compiled.clear()
            try:
                self._compiled[key] = compile_document(doc)
            except AssurError as exc:
                self._compiled[key] = exc
        return self._compiled[key]

    def _push(self, doc: dict) -> None:
        del self.history[self.position + 1:]
        self.history.append(doc)
        if len(self.history) > HISTORY_LIMIT:
            del self.history[0]
            self.saved_position -= 1
        self.position = len(self.history) - 1

    # -- edits -------------------------------------------------------------------------------------------------
    def apply(self, edits) -> dict:
        """The committed document with ``edits`` applied (refused: :class:`~.document.EditRefused`)."""
        if not isinstance(edits, list) or not all(isinstance(e, dict) for e in edits):
            raise D.EditRefused("edits must be a list of tables with a 'kind'", "edits")
        doc, flipped = self.doc, set()
        for e in edits:
            kind = e.get("kind")
            if int(doc.get("dimension", 2)) != 2 and kind not in ("lock_point", "lock_link"):
                raise D.EditRefused("a spatial mechanism is shown, not edited: use the parameter sliders", kind or "")
            if kind == "flip":
                doc, point = self.flipped(doc, e.get("group"))
                flipped.add(point)
            elif kind in D.EDITS:
                doc = D.EDITS[kind](doc, e)
            else:
                raise D.EditRefused(f"unknown edit {kind!r}; the edits are {', '.join(sorted([*D.EDITS, 'flip']))}",
                                    str(kind))
        self.check_branches(self.doc, doc, flipped)
        return doc

    def _signature(self, doc: dict) -> dict:
        """The branch sign of every branched step as the sketch shows it (the ``[branches]`` hints set aside),
        keyed by (point, kind), or {} when the document does not compile."""
        sketch_only = {k: v for k, v in doc.items() if k != "branches"} if "branches" in doc else doc
        c = self.compiled(sketch_only)
        if isinstance(c, AssurError) and sketch_only is not doc:
            c = self.compiled(doc)
        if isinstance(c, AssurError):
            return {}
        plan = c[2]
        sig = {(st.key_point, st.kind): (int(st.branch), st.points_in()) for _, st in branched_steps(plan)}
        if plan.dimension == 2 and any(st.kind == "newton" for st in plan.steps):
            from ..engine.planar.compile import newton_branch_signs
            for i, sign in newton_branch_signs(plan).items():
                names = tuple(plan.body_names[b] for b in plan.steps[i].bodies)
                sig[(", ".join(names), "newton")] = (sign, names)
        return sig

    def check_branches(self, before: dict, after: dict, flipped=()) -> None:
        """Refuse a new sketch that shows a group on its other branch: only ``flip`` changes a branch (the points
        in ``flipped``)."""
        if int(after.get("dimension", 2)) != 2:
            return
        old, new = self._signature(before), self._signature(after)
        for key, (sign, known) in new.items():
            point, kind = key
            if key in old and key not in flipped and old[key][0] != sign and old[key][1] == known:
                if kind == "newton":
                    raise D.EditRefused(
                        f"refused: this would draw the group {point} (solved by Newton iterations) in another "
                        f"assembly mode; a drag never changes an assembly", point)
                line = " → ".join(known)
                across = f"across the line {line}" if kind == "RRR" and len(known) == 2 else "to its other assembly"
                raise D.EditRefused(
                    f"refused: this would flip the {kind} group of {point} ({point} would go {across}); a drag "
                    f"never changes a branch, use Flip on that group to change it", point)

    def flipped(self, doc: dict, index) -> tuple[dict, str]:
        """(``doc`` with group ``index`` assembled on its other branch: the sketch of the group and of everything it
        carries is re-solved at the sketch inputs on the new branch, and a ``[branches]`` hint of its point flips; the
        group's point)."""
        from ..engine import solve
        c = self.compiled(doc)
        if isinstance(c, AssurError):
            raise D.EditRefused(f"nothing to flip: the document is not a mechanism yet ({c})", "flip")
        plan = c[2]
        steps = branched_steps(plan)
        if not isinstance(index, int) or not 0 <= index < len(steps):
            raise D.EditRefused(f"no group {index!r} to flip (the mechanism has {len(steps)} branched groups)", "flip")
        i, st = steps[index]
        flipped_steps = list(plan.steps)
        flipped_steps[i] = st.with_branch(-st.branch)
        state = solve(plan.with_steps(flipped_steps), order=0)
        pos = state.pos.reshape(-1, plan.n_points, 2)[0]
        if not bool(state.valid.reshape(-1)[0]):
            raise D.EditRefused(f"the group of {st.key_point} cannot be assembled on its other branch at the "
                                f"sketch position", st.key_point)
        new = copy.deepcopy(doc)
        fL = D.length_factor(new)
        frame = set(D.link_points(new["links"].get("frame", [])))
        for k, name in enumerate(plan.point_names):
            if name in new["points"] and name not in frame:
                new["points"][name] = [float(c) / fL for c in pos[k]]
        hint = new.get("branches", {}).get(st.key_point)
        if isinstance(hint, dict) and hint.get("side") in ("left", "right"):
            hint["side"] = "left" if hint["side"] == "right" else "right"
        sig = self._signature(new)
        if sig.get((st.key_point, st.kind), (None,))[0] != -st.branch:
            raise D.EditRefused(f"the group of {st.key_point} could not be drawn on its other branch", st.key_point)
        return new, (st.key_point, st.kind)

    # -- answers -----------------------------------------------------------------------------------------------
    def result(self, seq, doc: dict | None = None, committed: bool = True, exact: bool = True) -> Reply:
        doc = self.doc if doc is None else doc
        desc: Description = describe(doc, self.overrides, exact=exact, compiled=self.compiled(doc))
        index, blob = pack(desc.arrays)
        msg = {"type": "result", "seq": seq, "committed": committed, "doc": doc, "toml": self.text(doc),
               "history": {"undo": self.position, "redo": len(self.history) - 1 - self.position,
                           "dirty": self.position != self.saved_position},
               "file": self.path, "units": doc.get("units", {}), **desc.meta,
               "binary": True, "arrays": index}
        return Reply(_json_safe(msg), blob)

    def refused(self, seq, exc: D.EditRefused | AssurError) -> Reply:
        return Reply({"type": "refused", "seq": seq, "message": str(exc), "where": getattr(exc, "where", "")})

    def handle(self, request: dict) -> list[Reply]:
        """The replies to one request of the page (see the module docstring)."""
        if not isinstance(request, dict):
            return [Reply({"type": "refused", "seq": None, "message": "a request must be a JSON object", "where": ""})]
        seq, op = request.get("seq"), request.get("op")
        try:
            handler = getattr(self, f"op_{op}", None) if isinstance(op, str) else None
            if handler is None:
                raise D.EditRefused(f"unknown request {op!r}", str(op))
            return handler(seq, request)
        except D.EditRefused as exc:
            return [self.refused(seq, exc)]
        except AssurError as exc:
            return [self.refused(seq, exc)]

    def op_hello(self, seq, req):
        return [self.result(seq)]

    def op_preview(self, seq, req):
        return [self.result(seq, self.apply(req.get("edits")), committed=False, exact=False)]

    def op_commit(self, seq, req):
        doc = self.apply(req.get("edits"))
        self._push(doc)
        return [self.result(seq)]

    def op_cancel(self, seq, req):
        return [self.result(seq)]

    def op_undo(self, seq, req):
        if self.position == 0:
            raise D.EditRefused("nothing to undo", "undo")
        self.position -= 1
        return [self.result(seq)]

    def op_redo(self, seq, req):
        if self.position == len(self.history) - 1:
            raise D.EditRefused("nothing to redo", "redo")
        self.position += 1
        return [self.result(seq)]

    def op_load(self, seq, req):
        doc = doc_of_toml(req.get("toml"), "the shared document")
        self._push(doc)
        return [self.result(seq)]

    def op_save(self, seq, req):
        from ..io.output import atomic_file
        if self.path is None:
            raise D.EditRefused("this designer was opened on a mechanism, not a file: there is no file to save to; "
                                "copy the document (Share) instead", "save")
        text = self.text(self.doc)
        try:
            with atomic_file(self.path) as tmp:
                tmp.write_text(text, encoding="utf-8")
        except (OSError, AssurError) as exc:
            raise D.EditRefused(f"cannot save {self.path}: {exc}", self.path) from None
        self.saved_position = self.position
        return [Reply({"type": "saved", "seq": seq, "path": self.path})]

    def op_set_params(self, seq, req):
        params = req.get("params")
        if not isinstance(params, dict):
            raise D.EditRefused("set_params needs params: {name: value}", "params")
        new = dict(self.overrides)
        for name, value in params.items():
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise D.EditRefused(f"parameter {name}: not a number: {value!r}", str(name)) from None
            if not math.isfinite(v):
                raise D.EditRefused(f"parameter {name}: not finite", str(name))
            new[str(name)] = v
        self.overrides = new
        return [self.result(seq)]

    # -- synthesis from the page --------------------------------------------------------------------------------
    def op_synth_start(self, seq, req):
        from .synthesis_job import SynthesisJob
        if self.job is not None and self.job.running:
            raise D.EditRefused("a synthesis is running; cancel it first", "synthesis")
        self.job = SynthesisJob(self.doc, req.get("point"), req.get("targets"), req.get("budget", 3000),
                                req.get("seed", 1))
        self.best_toml = None
        return [Reply({"type": "synth_started", "seq": seq, "job": self.job.id})]

    def op_synth_cancel(self, seq, req):
        if self.job is None:
            raise D.EditRefused("no synthesis is running", "synthesis")
        self.job.cancel()
        return self.poll_synthesis(wait=5.0)

    def op_synth_insert(self, seq, req):
        if self.best_toml is None:
            raise D.EditRefused("no synthesised design to insert yet", "synthesis")
        doc = doc_of_toml(self.best_toml, "the synthesised design")
        self._push(doc)
        return [self.result(seq)]

    def poll_synthesis(self, wait: float = 0.0) -> list[Reply]:
        """The synthesis messages that arrived (``synth_progress``, ``synth_done``); waits up to ``wait`` s for
        the end of a cancelled run."""
        if self.job is None:
            return []
        out, deadline = [], time.monotonic() + wait
        while True:
            for m in self.job.poll():
                if m.get("type") == "synth_done" and m.get("toml"):
                    self.best_toml = m["toml"]
                out.append(Reply(m))
            if not self.job.running or time.monotonic() >= deadline:
                return out
            time.sleep(0.02)

    def close(self) -> None:
        if self.job is not None:
            self.job.cancel()


def _json_safe(x):
    """NaN and infinities as None (strict JSON)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json_safe(v) for v in x]
    return x
