"""The designer never loses a file's comments or a session: Save writes only what an edit changed (nothing when
nothing changed), every malformed message gets a located refusal over the real server and the session goes on,
every edit is checked by the file's own rules before it enters the history, and a drag costs one validation and
one compile.

Reference texts are the shipped example files themselves (byte for byte); the expected changed values are
computed in the tests (distances of the sketch), and `assur validate` is the project's own command run on the
saved file.
"""
import json
import math
import os
import shutil
from pathlib import Path

import pytest

import assur
from assur.designer.session import Session

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"


def copy_of(name, tmp_path) -> Path:
    return Path(shutil.copy(EX / name, tmp_path / name))


def reply(s, **request):
    (r,) = s.handle({"seq": 1, **request})
    return r.message


def changed_lines(before: str, after: str) -> list[tuple[str, str]]:
    a, b = before.splitlines(), after.splitlines()
    assert len(a) <= len(b)
    return [(x, y) for x, y in zip(a, b) if x != y]


# ---------------------------------------------------------------------------------------------------------------
# B1: Save keeps the file

@pytest.fixture(scope="module")
def server_on(request):
    pytest.importorskip("starlette")
    from assur.designer.server import start_server
    started = []

    def start(session):
        srv = start_server(session)
        started.append(srv)
        return srv
    yield start
    for srv in started:
        srv.stop()


def socket_of(srv):
    from websockets.sync.client import connect
    return connect(f"ws://127.0.0.1:{srv.port}/ws?token={srv.token}", origin=f"http://127.0.0.1:{srv.port}",
                   open_timeout=10, max_size=None)


def ask(ws, request: dict | str | bytes) -> dict:
    """Send one frame; the first answer (its binary half read too)."""
    ws.send(request if isinstance(request, (str, bytes)) else json.dumps(request))
    msg = json.loads(ws.recv(timeout=60))
    if msg.get("binary"):
        ws.recv(timeout=60)
    return msg


def test_save_at_once_writes_nothing_and_the_file_stays_byte_identical(tmp_path, server_on):
    """`assur design examples/jansen.toml`, Save at once: the file is not written at all (same bytes, same
    modification time), and the page is told so."""
    path = copy_of("jansen.toml", tmp_path)
    before, mtime = path.read_bytes(), path.stat().st_mtime_ns
    srv = server_on(Session.of_file(path))
    with socket_of(srv) as ws:
        hello = ask(ws, {"seq": 1, "op": "hello"})
        assert hello["file"] == str(path)                       # the page names the file Save writes
        msg = ask(ws, {"seq": 2, "op": "save"})
    assert msg["type"] == "saved" and msg["written"] is False and str(path) in msg["message"]
    assert path.read_bytes() == before and path.stat().st_mtime_ns == mtime


def test_an_edit_changes_only_the_touched_values_keeping_comments_order_and_units(tmp_path):
    """Moving O1 of the four-bar leg changes two lines of the file: O1's sketch and the rocker's explicit length
    (their comments kept); the masses with their units (`mass = "0.6358 kg"`), the description, every comment
    and the order stay as they were."""
    path = copy_of("walker_fourbar.toml", tmp_path)
    before = path.read_text()
    s = Session.of_file(path)
    msg = reply(s, op="commit", edits=[{"kind": "move_point", "point": "O1", "to": [0.58, 0.62]}])
    assert msg["type"] == "result"
    assert reply(s, op="save")["written"] is True
    after = path.read_text()
    rocker = math.dist((0.58, 0.62), s.doc["points"]["L"])          # the rocker O1–L follows the new sketch
    assert changed_lines(before, after) == [("O1 = [0.567, 0.615]", "O1 = [0.58, 0.62]"),
                                            ("length = 0.638                     # l2",
                                             f"length = {rocker!r}                     # l2")]
    assert len(before.splitlines()) == len(after.splitlines())
    assert 'mass = "0.6358 kg"                 # 0.27 m of bar' in after
    m = assur.load(path)
    assert dict(m.points)["O1"] == (0.58, 0.62) and m.link("rocker").length == rocker


def test_a_set_speed_in_rpm_and_a_lock_write_those_values_only(tmp_path):
    path = copy_of("walker_fourbar.toml", tmp_path)
    before = path.read_text()
    s = Session.of_file(path)
    msg = reply(s, op="commit", edits=[{"kind": "set_speed", "driver": "crank", "speed": "60 rpm"},
                                       {"kind": "lock_link", "link": "crank", "locked": True}])
    assert msg["type"] == "result", msg
    reply(s, op="save")
    after = path.read_text()
    assert changed_lines(before, after) == [('speed = "27 rpm"', 'speed = "60 rpm"')]
    assert after.startswith(before.replace('"27 rpm"', '"60 rpm"'))       # the locks are appended as [style]
    assert assur.load(path).drivers[0].speed == pytest.approx(2 * math.pi, rel=1e-15)   # 60 rpm = 2π rad/s
    assert "locked_links" in after and "crank" in after.split("[style]")[1]


def test_undo_back_to_the_file_writes_nothing_and_a_flip_keeps_the_points_it_does_not_move(tmp_path):
    path = copy_of("jansen.toml", tmp_path)
    before = path.read_text()
    s = Session.of_file(path)
    reply(s, op="commit", edits=[{"kind": "move_point", "point": "P", "to": [-0.39, -0.08]}])
    reply(s, op="undo")
    assert reply(s, op="save")["written"] is False and path.read_text() == before
    reply(s, op="commit", edits=[{"kind": "flip", "group": 2}])    # the last dyad: f and the lower triangle
    reply(s, op="save")
    changed = {b.split("=")[0].strip() for _, b in changed_lines(before, path.read_text())}
    assert changed == {"G", "F"}                                    # only the points the flip moves


def test_save_refuses_a_file_changed_on_disk_and_an_unfinished_mechanism(tmp_path):
    path = copy_of("walker_fourbar.toml", tmp_path)
    s = Session.of_file(path)
    reply(s, op="commit", edits=[{"kind": "move_point", "point": "O1", "to": [0.58, 0.62]}])
    path.write_text(path.read_text() + "# edited elsewhere\n")
    msg = reply(s, op="save")
    assert msg["type"] == "refused" and "changed on disk" in msg["message"]
    assert path.read_text().endswith("# edited elsewhere\n")
    t = Session.of_file(copy_of("crank_rocker.toml", tmp_path))
    name = t.doc["drivers"][0]["name"]
    reply(t, op="commit", edits=[{"kind": "delete_driver", "name": name}])
    msg = reply(t, op="save")
    assert msg["type"] == "refused" and "assur validate" in msg["message"] and "mobility" in msg["message"]


# ---------------------------------------------------------------------------------------------------------------
# B2: five message shapes that dropped the session, through the real server on 127.0.0.1

def _deep(n: int) -> str:
    return "[" * n + "]" * n


SHAPES = {
    "add_slider with angle 'x'": ({"seq": 10, "op": "preview", "edits": [
        {"kind": "add_slider", "point": "L", "angle": "x"}]}, "refused", "angle"),
    "a binary frame": (b"\x00\x01binary", "refused", "frame"),
    "JSON nested 100 000 deep": ('{"seq": 11, "op": "preview", "edits": ' + _deep(100_000) + "}", "refused",
                                 "request"),
    "edits nested 5 000 deep": ('{"seq": 12, "op": "commit", "edits": ' + _deep(5_000) + "}", "refused", "request"),
}


@pytest.mark.parametrize("label", list(SHAPES))
def test_a_malformed_message_gets_a_located_refusal_and_the_session_survives(label, server_on):
    request, kind, where = SHAPES[label]
    srv = server_on(Session.of_file(EX / "walker_fourbar.toml"))
    with socket_of(srv) as ws:
        msg = ask(ws, request)
        assert msg["type"] == kind and msg["where"] == where and msg["message"], msg
        again = ask(ws, {"seq": 20, "op": "hello"})                # the same connection goes on
        assert again["type"] == "result" and again["seq"] == 20 and again["cycle"]["assembled"] == 360
        assert again["history"]["undo"] == 0


def test_set_speed_with_a_unit_string_works_through_the_server(server_on):
    """"60 rpm" is how the file format writes a speed: the designer takes it too (2π rad/s)."""
    srv = server_on(Session.of_file(EX / "walker_fourbar.toml"))
    with socket_of(srv) as ws:
        msg = ask(ws, {"seq": 1, "op": "commit", "edits": [{"kind": "set_speed", "driver": "crank",
                                                             "speed": "60 rpm"}]})
        assert msg["type"] == "result" and msg["cycle"]["input"]["speed"] == pytest.approx(2 * math.pi, rel=1e-15)
        assert msg["doc"]["drivers"][0]["speed"] == "60 rpm"
        msg = ask(ws, {"seq": 2, "op": "commit", "edits": [{"kind": "set_speed", "driver": "crank",
                                                             "speed": "fast"}]})
        assert msg["type"] == "refused" and msg["where"] == "speed" and "rpm" in msg["message"]


# ---------------------------------------------------------------------------------------------------------------
# B3: every edit checked by the file's own rules before it enters the history

@pytest.mark.parametrize("edit, where, words", [
    ({"kind": "add_point", "at": [0.1, 0.1], "link": "frame", "name": "bad name!"}, "points.bad name!",
     "point name"),
    ({"kind": "add_link", "points": ["O", "L"], "name": "2x"}, "links.2x", "link name"),
    ({"kind": "lock_point", "point": "O1", "locked": "yes"}, "locked", "true or false"),
    ({"kind": "lock_link", "link": "crank", "locked": 1}, "locked", "true or false"),
])
def test_an_edit_the_file_reader_would_refuse_never_enters_the_history(edit, where, words):
    s = Session.of_file(EX / "walker_fourbar.toml")
    for op in ("preview", "commit"):
        msg = reply(s, op=op, edits=[edit])
        assert msg["type"] == "refused" and msg["where"] == where and words in msg["message"], msg
    assert len(s.history) == 1 and s.position == 0


@pytest.mark.parametrize("params, where, words", [
    ({"crank.length": -0.1}, "params.crank.length", "positive"),
    ({"nonsense.length": 0.1}, "params.nonsense.length", "no such parameter"),
    ({"crank.length": True}, "params.crank.length", "not a number"),
])
def test_set_params_refuses_what_the_file_would(params, where, words):
    s = Session.of_file(EX / "rssr.toml")
    msg = reply(s, op="set_params", params=params)
    assert msg["type"] == "refused" and msg["where"] == where and words in msg["message"], msg
    assert s.overrides == {}


def test_every_saved_file_passes_assur_validate(tmp_path, capsys):
    """After a run of edits (a move, a driver's speed, a lock, a coupler point added) Save writes a
    file that `assur validate` accepts."""
    from assur.cli.main import main
    path = copy_of("walker_fourbar.toml", tmp_path)
    s = Session.of_file(path)
    for edits in ([{"kind": "move_point", "point": "L", "to": [0.92, 0.09]}],
                  [{"kind": "set_speed", "driver": "crank", "speed": 3.0}],
                  [{"kind": "lock_point", "point": "O1", "locked": True}],
                  [{"kind": "add_point", "at": [0.8, -0.2], "link": "coupler", "name": "Q"}]):
        assert reply(s, op="commit", edits=edits)["type"] == "result"
    assert reply(s, op="save")["written"] is True
    assert main(["validate", str(path)]) == 0
    assert ": ok (W = 1" in capsys.readouterr().out


# ---------------------------------------------------------------------------------------------------------------
# issue 24 §2: a drag on one compile

def test_a_preview_does_one_validation_one_compile_and_at_most_one_serialisation(monkeypatch):
    """Count the file reader (validation), the engine's compile, the Assur decomposition and the TOML writer
    during one preview of a drag on the four-bar leg (a file with [branches])."""
    import assur.engine.api as api
    import assur.engine.planar.compile as planar_compile
    import assur.io.mechanism_file as mechanism_file
    import assur.io.toml_writer as toml_writer
    import assur.structure.assur as structure
    s = Session.of_file(EX / "walker_fourbar.toml")
    assert "branches" in s.doc
    reply(s, op="hello")
    reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.568, 0.615]}])
    counts = {}

    def counting(module, name, label):
        original = getattr(module, name)

        def counted(*args, **kwargs):
            counts[label] = counts.get(label, 0) + 1
            return original(*args, **kwargs)
        monkeypatch.setattr(module, name, counted)
    counting(mechanism_file, "from_dict", "validation")
    counting(api, "compile_planar", "compile")
    counting(planar_compile, "analyse", "decomposition")
    counting(structure, "analyse", "decomposition")
    counting(toml_writer, "dumps", "serialisation")
    for k in range(3):
        counts.clear()
        msg = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.569 + 0.001 * k, 0.615]}])
        assert msg["type"] == "result" and msg["cycle"]["assembled"] == 360
        assert counts.get("validation") == 1 and counts.get("compile") == 1, counts
        assert counts.get("serialisation", 0) <= 1 and counts.get("decomposition", 0) == 0, counts
    # the branch check still refuses a flip from that one compile (L mirrored across K–O1)
    P = s.doc["points"]
    K, O1, L = (P[n] for n in ("K", "O1", "L"))
    u = [(O1[i] - K[i]) / math.dist(O1, K) for i in range(2)]
    d = sum((L[i] - K[i]) * u[i] for i in range(2))
    mirror = [K[i] + 2 * d * u[i] - (L[i] - K[i]) for i in range(2)]
    counts.clear()
    msg = reply(s, op="preview", edits=[{"kind": "move_point", "point": "L", "to": mirror}])
    assert msg["type"] == "refused" and msg["where"] == "L" and counts.get("compile") == 1, (msg, counts)


# ---------------------------------------------------------------------------------------------------------------
# B4: a synthesis started from the page stops when the last page leaves

@pytest.mark.slow
def test_a_synthesis_stops_when_the_last_page_closes(server_on):
    import time
    srv = server_on(Session.of_file(EX / "crank_rocker.toml"))
    plan = assur.compile(assur.load(EX / "crank_rocker.toml"))
    path = assur.solve(plan, inputs=[0.0, 2.0, 4.0], order=0).point("P").pos.reshape(-1, 2) * 1.05
    with socket_of(srv) as first, socket_of(srv) as second:
        msg = ask(first, {"seq": 1, "op": "synth_start", "point": "P", "targets": path.tolist(), "budget": 10 ** 6,
                          "seed": 1})
        assert msg["type"] == "synth_started", msg
        job = srv.session.job
        first.close()                                   # another page is still open: the run goes on
        time.sleep(1.0)
        assert not job._cancel.is_set() and job._process.is_alive()
        assert ask(second, {"seq": 2, "op": "hello"})["type"] in ("result", "synth_progress")
    deadline = time.monotonic() + 30
    while job._process.is_alive() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert job._cancel.is_set() and not job._process.is_alive()


def test_a_drag_across_a_dyad_line_is_refused_in_a_file_without_branch_hints():
    """Jansen's file has no [branches]: the plan's branches are the sketch's. U (the dyad j–upper, solved from C and
    P) mirrored across the line C–P is refused; a small move is not."""
    s = Session.of_file(EX / "jansen.toml")
    assert "branches" not in s.doc
    f = 0.01                                                            # cm
    C, P, U = ([f * c for c in s.doc["points"][n]] for n in ("C", "P", "U"))
    u = [(P[i] - C[i]) / math.dist(P, C) for i in range(2)]
    d = sum((U[i] - C[i]) * u[i] for i in range(2))
    mirror = [C[i] + 2 * d * u[i] - (U[i] - C[i]) for i in range(2)]
    msg = reply(s, op="preview", edits=[{"kind": "move_point", "point": "U", "to": mirror}])
    assert msg["type"] == "refused" and msg["where"] == "U" and "Flip" in msg["message"], msg
    msg = reply(s, op="preview", edits=[{"kind": "move_point", "point": "U", "to": [U[0] + 0.002, U[1]]}])
    assert msg["type"] == "result"
