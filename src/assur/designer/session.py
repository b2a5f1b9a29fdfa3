"""One designer session: the committed document, its history, the edits of a gesture and the answers to the page
(the protocol of ``docs/designer.md``), independent of the transport (a WebSocket or a notebook widget's comm).

:meth:`Session.handle` takes one request (a dict) and returns the replies, each ``(message dict, blob or None)``;
a blob holds the float64 arrays the message indexes. A request that cannot be carried out answers ``refused``
with the reason and changes nothing.
"""
from __future__ import annotations

import copy
import json
import math
import os
import stat
import sys
import time
import traceback
from dataclasses import dataclass

from ..errors import AssurError
from . import document as D
from .compiled import Compiled, StructureCache, compile_doc
from .payload import DESIGNER_STEPS, Description, branched_steps, describe, pack

#: the largest history a session keeps (older entries are dropped)
HISTORY_LIMIT = 500
#: a flip rewrites the sketch of the points it moves by more than this times the mechanism's size (the others
#: keep their coordinates exactly, so the file changes where the flip changed it only)
ROUND_OFF = 1e-12


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


def _regular_file_text(path) -> str | None:
    """The text of the regular file ``path`` (None for no path, a special file, or one that cannot be read)."""
    if path is None:
        return None
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return None
        from ..io.toml_reader import read_text
        return read_text(path)
    except (OSError, AssurError):
        return None


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


#: the deepest nesting of a request (a list in a table in a list …): requests nest four levels at most
MAX_REQUEST_NESTING = 32
#: the largest request text accepted (bytes; a share link's document is at most the file reader's 16 MiB)
MAX_REQUEST_BYTES = 24 * 2 ** 20


def _too_deep(x, limit: int) -> bool:
    """Whether ``x`` nests dicts and lists deeper than ``limit`` levels (iterative: any depth is safe)."""
    stack = [(x, 1)]
    while stack:
        v, d = stack.pop()
        if isinstance(v, (dict, list, tuple)):
            if d > limit:
                return True
            stack.extend((c, d + 1) for c in (v.values() if isinstance(v, dict) else v))
    return False


def parse_request(data) -> dict:
    """A request of the page from a WebSocket frame's payload (text): the JSON object, or a request that
    :meth:`Session.handle` refuses with the reason (a binary frame, text that is not JSON, too long or nested
    too deep). Never raises."""
    if not isinstance(data, str):
        return {"op": None, "_refuse": ("a request must be a text frame holding a JSON object (the designer sends "
                                        "binary frames, never receives them)", "frame")}
    if len(data) > MAX_REQUEST_BYTES:
        return {"op": None, "_refuse": (f"a request must be at most {MAX_REQUEST_BYTES // 2 ** 20} MiB", "frame")}
    try:
        return json.loads(data)
    except RecursionError:
        return {"op": None, "_refuse": (f"a request must not nest deeper than {MAX_REQUEST_NESTING} levels",
                                        "request")}
    except ValueError as exc:
        return {"op": None, "_refuse": (f"a request must be a JSON object: {exc}", "request")}


def _seq(value):
    """A request's ``seq`` as echoed back: a number or a short string, else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int) and abs(value) < 2 ** 53 or isinstance(value, float) and math.isfinite(value):
        return value
    return value if isinstance(value, str) and len(value) <= 64 else None


class Session:
    """The state behind one page: ``history`` (documents; ``position`` the committed one), the file ``path`` (or
    None), the parameter ``overrides`` of the spatial view and the running synthesis ``job``.

    ``text``: the file's text as read (when None and ``path`` is a regular file, it is read now): Save writes the
    edits into it and keeps the rest (:mod:`.saving`)."""

    def __init__(self, doc: dict, path: str | None = None, text: str | None = None):
        self.history = [copy.deepcopy(doc)]
        self.position = 0
        self.saved_position = 0
        self.path = path
        self.overrides: dict = {}
        self.job = None
        self.motor_job = None
        self.best_toml: str | None = None
        self.clients = 0
        self._texts: dict = {}        # id(doc) → (doc, its TOML text): history documents are never changed
        self._compiled: dict = {}     # id(doc) → (doc, Compiled): likewise
        self._structures = StructureCache()
        self.file_doc = self.history[0]     # the document the file on disk loads to
        self.file_text = text if text is not None else _regular_file_text(path)

    @classmethod
    def of_file(cls, path) -> "Session":
        """A session on a mechanism file (read once: the document and the text Save keeps)."""
        from ..io.toml_reader import read_text
        text = read_text(path)
        return cls(doc_of_toml(text, str(path)), str(path), text)

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

    def entry(self, doc: dict) -> Compiled:
        """The document validated and compiled once (:func:`.compiled.compile_doc`), kept while it lives."""
        hit = self._compiled.get(id(doc))
        if hit is None or hit[0] is not doc:
            if len(self._compiled) > 64:
                keep = {id(d) for d in self.history[max(0, self.position - 8):self.position + 9]}
                self._compiled = {k: v for k, v in self._compiled.items() if k in keep}
            hit = self._compiled[id(doc)] = (doc, compile_doc(doc, self._structures))
        return hit[1]

    def compiled(self, doc: dict):
        """``(mechanism, structure, plan, warnings)`` of ``doc``, or the AssurError that stops it."""
        return self.entry(doc).described()

    def _push(self, doc: dict) -> None:
        del self.history[self.position + 1:]
        self.history.append(doc)
        if len(self.history) > HISTORY_LIMIT:
            del self.history[0]
            self.saved_position -= 1
        self.position = len(self.history) - 1

    # -- edits -------------------------------------------------------------------------------------------------
    def apply(self, edits) -> dict:
        """The committed document with ``edits`` applied, validated by the file's own rules and checked for
        branch flips (refused: :class:`~.document.EditRefused`, located)."""
        if not isinstance(edits, list) or not all(isinstance(e, dict) for e in edits):
            raise D.EditRefused("edits must be a list of tables with a 'kind'", "edits")
        doc, flipped = self.doc, set()
        for i, e in enumerate(edits):
            kind = e.get("kind")
            if int(doc.get("dimension", 2)) != 2 and kind not in ("lock_point", "lock_link"):
                raise D.EditRefused("a spatial mechanism is shown, not edited: use the parameter sliders", str(kind))
            try:
                if kind == "flip":
                    doc, point = self.flipped(doc, e.get("group"))
                    flipped.add(point)
                elif kind == "assembly":
                    from .choosing import assembled
                    doc, keys = assembled(self, doc, e)
                    flipped |= keys
                elif isinstance(kind, str) and kind in D.EDITS:
                    doc = D.EDITS[kind](doc, e)
                else:
                    raise D.EditRefused(f"unknown edit {kind!r}; the edits are "
                                        f"{', '.join(sorted([*D.EDITS, 'assembly', 'flip']))}", f"edits[{i}].kind")
            except (TypeError, ValueError, KeyError, AttributeError, IndexError, OverflowError) as exc:
                if isinstance(exc, AssurError):
                    raise
                raise D.EditRefused(f"edit {i} ({kind}) is malformed: {exc}", f"edits[{i}]") from None
        if doc is self.doc:
            return doc
        bad = self.entry(doc).invalid
        if bad is not None:
            where, message = bad.problems[0] if bad.problems else ("", str(bad))
            more = f" (and {len(bad.problems) - 1} more)" if len(bad.problems) > 1 else ""
            raise D.EditRefused(f"refused: the file would not load: {where}: {message}{more}", where)
        self.check_branches(self.doc, doc, flipped)
        return doc

    def _signature(self, doc: dict) -> dict:
        """The branch of every branched group as the sketch shows it (see :func:`.compiled.branch_signs`), or {}
        when the document does not compile."""
        return self.entry(doc).signs

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
        group's point). Points the flip does not move (beyond round-off) keep their sketch exactly. An RPR group's
        ``slide`` hint flips with it; where the sketch cannot show an RPR group's branch (its bodies carry no point but
        their hinges: both branches put every point at the same place), the flip writes one."""
        from ..engine import solve
        c = self.compiled(doc)
        if isinstance(c, AssurError):
            raise D.EditRefused(f"nothing to flip: the document is not a mechanism yet ({c})", "flip")
        plan = c[2]
        steps = branched_steps(plan)
        if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(steps):
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
        noise = ROUND_OFF * float(plan.length_scale)
        for k, name in enumerate(plan.point_names):
            if name in new["points"] and name not in frame:
                old = [c * fL for c in new["points"][name]]
                if math.hypot(pos[k][0] - old[0], pos[k][1] - old[1]) > noise:
                    new["points"][name] = [float(c) / fL for c in pos[k]]
        hint = new.get("branches", {}).get(st.key_point)
        if st.kind == "RPR":
            self._flip_slide_hint(new, st, plan.lines[st.line][1])
        elif isinstance(hint, dict) and hint.get("side") in ("left", "right"):
            hint["side"] = "left" if hint["side"] == "right" else "right"
        sig = self._signature(new)
        if st.kind == "RPR" and sig.get((st.key_point, st.kind), (None,))[0] != -st.branch:
            # the sketch cannot show this group's branch (its bodies carry no point but their hinges): the file
            # records it as a slide hint (in a new document: the session's caches key documents by identity)
            new = copy.deepcopy(new)
            self._flip_slide_hint(new, st, plan.lines[st.line][1], add=True)
            sig = self._signature(new)
        elif st.kind == "RPR" and "slide" in new.get("branches", {}).get(st.key_point, {}):
            # back on the branch the sketch shows: the hint goes (a flip and its flip back leave the file as it was)
            bare = copy.deepcopy(new)
            table = bare["branches"][st.key_point]
            del table["slide"], table["on"]
            if not table:
                del bare["branches"][st.key_point]
            if not bare["branches"]:
                del bare["branches"]
            if self._signature(bare).get((st.key_point, st.kind), (None,))[0] == -st.branch:
                new, sig = bare, self._signature(bare)
        if sig.get((st.key_point, st.kind), (None,))[0] != -st.branch:
            raise D.EditRefused(f"the group of {st.key_point} could not be drawn on its other branch", st.key_point)
        return new, (st.key_point, st.kind)

    @staticmethod
    def _flip_slide_hint(doc: dict, st, on: str, add: bool = False) -> None:
        """Turn the ``slide`` hint of RPR step ``st`` (sliding on ``on``) to the step's other branch in ``doc``; with
        ``add``, write one when there is none (refused when the point's hint holds another slide's)."""
        want = "behind" if st.branch == 1 else "ahead"
        table = doc.get("branches", {}).get(st.key_point)
        if isinstance(table, dict) and "slide" in table:
            if table.get("on") != on:
                raise D.EditRefused(f"the file's [branches] hint of {st.key_point} holds the slide "
                                    f"{table.get('on')!r}: it cannot record the branch of the group on {on!r} too",
                                    f"branches.{st.key_point}")
            table["slide"] = want
        elif add:
            doc.setdefault("branches", {}).setdefault(st.key_point, {}).update({"slide": want, "on": on})

    # -- answers -----------------------------------------------------------------------------------------------
    def result(self, seq, doc: dict | None = None, committed: bool = True, exact: bool = True) -> Reply:
        doc = self.doc if doc is None else doc
        desc: Description = describe(doc, self.overrides, exact=exact, compiled=self.compiled(doc))
        if desc.meta["model"].get("motor_hint"):
            from .motor_job import located_hint
            desc.meta["model"]["motor_hint"] = located_hint(desc.meta["model"]["motor_hint"], self.path,
                                                            self.file_text)
        index, blob = pack(desc.arrays)
        msg = {"type": "result", "seq": seq, "committed": committed, "doc": doc, "toml": self.text(doc),
               "history": {"undo": self.position, "redo": len(self.history) - 1 - self.position,
                           "dirty": self.position != self.saved_position},
               "file": self.path, "units": doc.get("units", {}), **desc.meta,
               "binary": True, "arrays": index}
        return Reply(_json_safe(msg), blob)

    def refused(self, seq, exc: D.EditRefused | AssurError) -> Reply:
        return Reply({"type": "refused", "seq": _seq(seq), "message": str(exc), "where": getattr(exc, "where", "")})

    def handle(self, request: dict) -> list[Reply]:
        """The replies to one request of the page (see the module docstring). Never raises: a request that cannot
        be carried out (malformed, nested too deep, refused by the file's rules, or failing inside) answers
        ``refused`` with the reason and where, and the session goes on."""
        if not isinstance(request, dict):
            return [Reply({"type": "refused", "seq": None, "message": "a request must be a JSON object",
                           "where": "request"})]
        seq, op = _seq(request.get("seq")), request.get("op")
        try:
            if "_refuse" in request:
                raise D.EditRefused(*request["_refuse"])
            if _too_deep(request, MAX_REQUEST_NESTING):
                raise D.EditRefused(f"a request must not nest deeper than {MAX_REQUEST_NESTING} levels", "request")
            handler = getattr(self, f"op_{op}", None) if isinstance(op, str) else None
            if handler is None:
                raise D.EditRefused(f"unknown request {op!r}", "op")
            return handler(seq, request)
        except AssurError as exc:
            return [self.refused(seq, exc)]
        except RecursionError:
            return [self.refused(seq, D.EditRefused("the request is nested too deep", "request"))]
        except Exception as exc:   # noqa: BLE001 - a defect must not drop the page's session: say it and go on
            traceback.print_exc(file=sys.stderr)
            return [self.refused(seq, D.EditRefused(
                f"the designer could not carry out '{op}' ({type(exc).__name__}: {exc}); the document is "
                f"unchanged", str(op)))]

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
        """Write the committed document into the file: only the values the edits changed (:mod:`.saving`), nothing
        at all when the document is the file's; refused when the file changed on disk since it was read (Save would
        lose those changes) or when the document would not pass ``assur validate``."""
        from ..io.output import atomic_file
        from .saving import canonical, updated_text
        if self.path is None:
            raise D.EditRefused("this designer was opened on a mechanism, not a file: there is no file to save to; "
                                "copy the document (Share) instead", "save")
        c = self.entry(self.doc)
        stop = c.invalid or c.error
        if stop is not None:
            raise D.EditRefused(f"not saved: {self.path} would not pass `assur validate` ({stop}); finish the "
                                f"mechanism first, or keep this draft with Share link", "save")
        if canonical(self.doc) == canonical(self.file_doc):
            self.saved_position = self.position
            return [Reply({"type": "saved", "seq": seq, "path": self.path, "written": False,
                           "message": f"{self.path} already holds this design: nothing written"})]
        if self.file_text is not None:
            on_disk = _regular_file_text(self.path)
            if on_disk is not None and on_disk != self.file_text:
                raise D.EditRefused(f"not saved: {self.path} changed on disk since the designer read it; Save would "
                                    f"overwrite those changes (keep this design with Share link, or reopen the "
                                    f"file)", self.path)
            text = updated_text(self.file_text, self.file_doc, self.doc)
        else:
            text = self.text(self.doc)
        try:
            with atomic_file(self.path) as tmp:
                tmp.write_text(text, encoding="utf-8")
        except (OSError, AssurError) as exc:
            raise D.EditRefused(f"cannot save {self.path}: {exc}", self.path) from None
        self.saved_position = self.position
        self.file_doc = self.doc
        self.file_text = text if _regular_file_text(self.path) is not None else None
        return [Reply({"type": "saved", "seq": seq, "path": self.path, "written": True,
                       "message": f"saved {self.path}"})]

    def op_set_params(self, seq, req):
        """Parameter overrides of the spatial view's sliders, each checked as the file reader checks the value it
        stands for: a known parameter of the compiled plan, a finite number below 1e9, a length positive and a
        coupler point's distance non-negative."""
        params = req.get("params")
        if not isinstance(params, dict):
            raise D.EditRefused("set_params needs params: {name: value}", "params")
        c = self.compiled(self.doc)
        if isinstance(c, AssurError):
            raise D.EditRefused(f"no parameters: the document is not a mechanism yet ({c})", "params")
        plan = c[2]
        new = dict(self.overrides)
        for name, value in params.items():
            where = f"params.{name}"
            if name not in plan.param_names:
                shown = ", ".join(plan.param_names[:12]) + (", …" if len(plan.param_names) > 12 else "")
                raise D.EditRefused(f"parameter {name!r}: no such parameter (known: {shown})", where)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise D.EditRefused(f"parameter {name}: not a number: {value!r}", where)
            v = float(value)
            if not math.isfinite(v) or abs(v) >= 1e9:
                raise D.EditRefused(f"parameter {name}: must be finite and below 1e9 in magnitude: {value!r}", where)
            if name.endswith(".length") and v <= 0:
                raise D.EditRefused(f"parameter {name}: a length must be positive: {value!r}", where)
            if name.endswith(".distance") and v < 0:
                raise D.EditRefused(f"parameter {name}: a distance must not be negative: {value!r}", where)
            new[name] = v
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

    # -- the chooser of assemblies --------------------------------------------------------------------------------
    def op_assemblies(self, seq, req):
        """Every assembly of the committed mechanism at input ``index`` (default 0) = ``input`` (SI; default the
        sketch's), the others at the sketch's (:mod:`.choosing`)."""
        from .choosing import assemblies_message
        c = self.compiled(self.doc)
        if isinstance(c, AssurError):
            raise D.EditRefused(f"no assemblies: the document is not a mechanism yet ({c})", "assemblies")
        return [Reply({**assemblies_message(c[2], c[1], req.get("input"), req.get("index", 0)), "seq": seq})]

    # -- the run on the motor --------------------------------------------------------------------------------------
    def op_motor_start(self, seq, req):
        """Run the committed document on its motor in a worker process (:mod:`.motor_job`), to its steady state or
        for ``time`` s: ``motor_started`` now, ``motor_done`` when it ends (:meth:`poll_jobs`)."""
        from .motor_job import MotorJob, check_runnable, run_time
        if self.motor_job is not None and self.motor_job.running:
            raise D.EditRefused("a run on the motor is going; cancel it first", "motor")
        time_ = run_time(req.get("time"))
        check_runnable(self.doc, self.entry(self.doc), self.path, self.file_text)
        self.motor_job = MotorJob(self.doc, DESIGNER_STEPS, time_)
        return [Reply({"type": "motor_started", "seq": seq, "job": self.motor_job.id})]

    def op_motor_cancel(self, seq, req):
        if self.motor_job is None or not self.motor_job.running:
            raise D.EditRefused("no run on the motor is going", "motor")
        self.motor_job.cancel()
        return self.poll_motor()

    def poll_motor(self) -> list[Reply]:
        """The run on the motor's ``motor_done`` once it has ended (its arrays packed as a result's)."""
        if self.motor_job is None:
            return []
        out = []
        for message, arrays in self.motor_job.poll():
            index, blob = pack(arrays)
            out.append(Reply(_json_safe({**message, "binary": True, "arrays": index}), blob))
        return out

    def poll_jobs(self) -> list[Reply]:
        """The messages of the page's jobs that arrived: a synthesis's progress and end, a run on the motor's
        end."""
        return self.poll_synthesis() + self.poll_motor()

    @property
    def jobs_running(self) -> bool:
        """A synthesis or a run on the motor has not ended (or its last message has not been polled)."""
        return any(j is not None and j.running for j in (self.job, self.motor_job))

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
        for job in (self.job, self.motor_job):
            if job is not None:
                job.cancel()


def _json_safe(x):
    """NaN and infinities as None (strict JSON)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: _json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json_safe(v) for v in x]
    return x
