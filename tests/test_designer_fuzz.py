"""Seeded random messages to the designer's session (the page's protocol, docs/designer.md): every message is
answered (a result, a refusal that says why and where, or a save), never by an exception or an internal error; the
answers are strict JSON; every document that enters the history loads with the file reader, and every file Save
writes passes `assur validate`. The frames a WebSocket may carry (text that is not JSON, bytes, deep nesting) go
through the server's own parser first."""
import json
import math
import random
import shutil
from pathlib import Path

import pytest

import assur
from assur.designer.session import Session, parse_request
from assur.io.mechanism_file import from_dict

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ["walker_fourbar.toml", "slider_crank.toml", "jansen.toml", "rssr.toml", "lever_manipulator.toml"]
#: messages per file in the quick loop, and in the slow run
MESSAGES_PER_FILE = 40
MESSAGES_SLOW = 400

#: values put where a message expects something
WILD = [None, True, False, 0, -1, 1e400, -1e308, float("nan"), 2e8, 0.05, "", "x", "bad name!", "60 rpm",
        "30 deg", "-5 mm", "1e400 rpm", "frame", [], [0.1], [0.1, 0.2], [0.1, 0.2, 0.3], ["x", "y"], [[0.1, 0.2]],
        {}, {"a": 1}, {"P9": [0.1, 0.2]}, [[[[1]]]]]
OPS = ["hello", "preview", "commit", "cancel", "undo", "redo", "load", "save", "set_params", "synth_cancel",
       "synth_insert", "motor_cancel", "assemblies", "nope", None, 3]
KINDS = ["move_point", "add_point", "delete_point", "add_link", "delete_link", "add_slider", "delete_slider",
         "add_driver", "delete_driver", "set_speed", "lock_point", "lock_link", "flip", "assembly", "bend", None]
FIELDS = ["point", "to", "at", "link", "name", "points", "new_points", "guide", "through", "angle", "offset", "pivot",
          "arm", "speed", "driver", "locked", "group", "input", "index", "branches"]


def a_value(rng, names):
    """A plausible value (a real name or position) or a wild one."""
    r = rng.random()
    if r < 0.35 and names:
        return rng.choice(names)
    if r < 0.55:
        return [rng.uniform(-1, 1), rng.uniform(-1, 1)]
    if r < 0.65:
        return rng.randrange(-1, 4)
    return rng.choice(WILD)


def an_edit(rng, names):
    kind = rng.choice(KINDS)
    edit = {"kind": kind} if kind is not None else {}
    for field in rng.sample(FIELDS, rng.randrange(0, 6)):
        edit[field] = a_value(rng, names)
    return edit


def a_message(rng, s: Session):
    doc = s.doc
    names = [*doc.get("points", {}), *doc.get("links", {}), *(d.get("name") for d in doc.get("drivers", [])),
             *(p.get("name") for p in doc.get("prismatic", []))]
    op = rng.choice(OPS)
    msg = {"seq": rng.choice([rng.randrange(1000), None, "s", [1]]), "op": op}
    if op in ("preview", "commit"):
        msg["edits"] = [an_edit(rng, names) for _ in range(rng.randrange(0, 3))] if rng.random() < 0.9 \
            else rng.choice(WILD)
    elif op == "load":
        msg["toml"] = rng.choice([s.text(doc), "format = 'assur/1'", "= =", "", 3, None])
    elif op == "assemblies":
        msg.update({k: a_value(rng, names) for k in rng.sample(["input", "index"], rng.randrange(0, 3))})
    elif op == "set_params":
        msg["params"] = {rng.choice(["crank.length", "O.x", "nope", "crank.zero"]): rng.choice(WILD + [0.1, -0.1])}
    return msg


@pytest.mark.parametrize("example, count", [*((e, MESSAGES_PER_FILE) for e in EXAMPLES),
                                            *(pytest.param(e, MESSAGES_SLOW, marks=pytest.mark.slow) for e in EXAMPLES)])
def test_random_messages_are_answered_and_the_history_stays_loadable(example, count, tmp_path):
    from assur.cli.main import main
    path = Path(shutil.copy(ROOT / "examples" / example, tmp_path / example))
    s = Session.of_file(path)
    rng = random.Random(f"designer {example} {count}")
    answered = {"result": 0, "refused": 0, "saved": 0}
    for k in range(count):
        request = a_message(rng, s)
        replies = s.handle(json.loads(json.dumps(request, allow_nan=True)))
        assert replies, request
        for r in replies:
            kind = r.message["type"]
            json.dumps(r.message, allow_nan=False)                      # strict JSON on the wire
            assert kind in answered or kind.startswith(("synth_", "motor_")) or kind == "assemblies", (request, r.message)
            answered[kind] = answered.get(kind, 0) + 1
            if kind == "refused":
                assert r.message["message"] and "could not carry out" not in r.message["message"], (request, r.message)
            if kind == "saved" and r.message.get("written"):
                assert main(["validate", str(path)]) == 0
        for doc in s.history[-2:]:
            from_dict(doc)                                               # every history entry loads
    assert answered["result"] > count // 10 and answered["refused"] > count // 10, answered


@pytest.mark.parametrize("frame", [b"\x00\xff", "", "[", "{\"op\": ", "null", "[1, 2]", "\"hello\"", "1e999",
                                   "[" * 50_000 + "]" * 50_000, "{\"op\": \"hello\", \"x\": " + "[" * 40 + "]" * 40 + "}",
                                   "{\"op\": \"preview\", \"edits\": [{\"kind\": \"move_point\", \"point\": \"O1\", "
                                   "\"to\": [NaN, Infinity]}]}"])
def test_every_frame_is_parsed_or_refused(frame):
    s = Session.of_file(ROOT / "examples" / "walker_fourbar.toml")
    (reply,) = s.handle(parse_request(frame))
    assert reply.message["type"] == "refused" and reply.message["where"], reply.message
    json.dumps(reply.message, allow_nan=False)
    assert s.handle({"seq": 1, "op": "hello"})[0].message["type"] == "result"


def test_the_fuzzed_answers_keep_the_numbers_of_the_file():
    """A control: an untouched session still describes the file as the engine does (no state leaks between
    messages): after refused junk, hello's positions are the engine's."""
    import numpy as np
    s = Session.of_file(ROOT / "examples" / "walker_fourbar.toml")
    rng = random.Random(7)
    for _ in range(40):
        request = a_message(rng, s)
        if request["op"] in ("commit", "load", "undo", "redo", "save", "set_params"):
            continue
        s.handle(json.loads(json.dumps(request)))
    r = s.handle({"seq": 1, "op": "hello"})[0]
    assert len(s.history) == 1
    data = np.frombuffer(r.blob, dtype="<f8")
    o, n, shape = r.message["arrays"]["pos"]
    pos = data[o:o + n].reshape(shape)
    plan = assur.compile(assur.load(ROOT / "examples" / "walker_fourbar.toml"))
    ref = assur.solve(plan, inputs=np.linspace(0, 2 * math.pi, 360, endpoint=False), order=0).pos
    assert np.allclose(pos, ref, atol=1e-12)
