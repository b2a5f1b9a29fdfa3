"""The designer's server side without a browser: document edits, branches, history, saving, the cycle the page
receives, and the server's refusals (token, Host, Origin).

Reference values come from the engine itself (``assur.solve``, ``assur.forces``, ``assur.gait_metrics``,
``assur.transmission_angles``) or from independent geometry computed in the tests.
"""
import json
import math
import shutil
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer.document import move_point
from assur.designer.payload import describe
from assur.designer.session import Session, document_of, toml_of

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"


def session_of(name, tmp_path=None):
    path = EX / name
    if tmp_path is not None:
        path = Path(shutil.copy(path, tmp_path / name))
    doc, p = document_of(path)
    return Session(doc, p)


def reply(s, **request):
    (r,) = s.handle({"seq": 1, **request})
    return r.message, r.blob


def arrays_of(message, blob):
    data = np.frombuffer(blob, dtype="<f8")
    return {k: data[o:o + n].reshape(shape) for k, (o, n, shape) in message["arrays"].items()}


# ---------------------------------------------------------------------------------------------------------------
# edits of the document

def test_move_point_rewrites_the_explicit_dimensions_from_the_sketch():
    doc, _ = document_of(EX / "walker_fourbar.toml")
    new = move_point(doc, "L", [0.93, 0.1])
    P = new["points"]
    # the rocker O1–L and the coupler K–L have explicit lengths: they follow the new sketch
    assert new["links"]["rocker"]["length"] == pytest.approx(math.dist(P["O1"], P["L"]), rel=1e-15)
    assert new["links"]["coupler"]["length"] == pytest.approx(math.dist(P["K"], P["L"]), rel=1e-15)
    # H is placed from L toward K: its distance and angle follow the sketch (H itself did not move)
    pl = new["links"]["coupler"]["place"]["H"]
    assert pl["distance"] == pytest.approx(math.dist(P["L"], P["H"]), rel=1e-15)
    a = math.atan2(P["H"][1] - P["L"][1], P["H"][0] - P["L"][0]) - math.atan2(P["K"][1] - P["L"][1],
                                                                               P["K"][0] - P["L"][0])
    assert math.radians(pl["angle"]) == pytest.approx((a + math.pi) % (2 * math.pi) - math.pi, abs=1e-13)
    # the engine places H where the sketch shows it
    plan = assur.compile(assur.io.mechanism_file.from_dict(new))
    s = assur.solve(plan, order=0)
    assert s.point("H").pos.reshape(2) == pytest.approx(P["H"], abs=1e-12)
    assert doc["points"]["L"] != P["L"]          # the argument is never changed


def test_edits_arrive_in_si_and_are_written_in_the_file_units():
    doc, _ = document_of(EX / "slider_crank.toml")       # a mm file
    new = move_point(doc, "A", [0.03, 0.04])
    assert new["points"]["A"] == pytest.approx([30.0, 40.0], rel=1e-15)
    assert new["links"]["crank"]["length"] == pytest.approx(50.0, rel=1e-15)


def test_a_drag_never_flips_a_branch_and_flip_does_with_one_undo_entry():
    s = session_of("walker_fourbar.toml")
    P = s.doc["points"]
    K, O1, L = (np.array(P[n]) for n in ("K", "O1", "L"))
    u = (O1 - K) / np.linalg.norm(O1 - K)
    mirror = K + 2 * np.dot(L - K, u) * u - (L - K)         # L reflected across the line K–O1
    msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "L", "to": list(mirror)}])
    assert msg["type"] == "refused" and "L" in msg["message"] and "Flip" in msg["message"]
    assert msg["where"] == "L"
    before = s.handle({"seq": 2, "op": "hello"})[0].message["model"]["groups"][0]["branch"]
    msg, blob = reply(s, op="commit", edits=[{"kind": "flip", "group": 0}])
    assert msg["type"] == "result" and msg["history"] == {"undo": 1, "redo": 0, "dirty": True}
    assert msg["model"]["groups"][0]["branch"] == -before
    # the flipped sketch: L is the other intersection of the circles about K (coupler) and O1 (rocker), i.e. the
    # reflection of L across K–O1, and the mechanism still runs the whole turn
    assert msg["doc"]["points"]["L"] == pytest.approx(list(mirror), abs=1e-12)
    assert msg["cycle"]["assembled"] == 360
    msg, _ = reply(s, op="undo")
    assert msg["model"]["groups"][0]["branch"] == before and msg["history"]["redo"] == 1


def test_preview_stores_nothing_and_commit_stores_one_entry_per_gesture():
    s = session_of("walker_fourbar.toml")
    for k in range(5):
        msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.567 + 0.001 * k, 0.615]}])
        assert msg["type"] == "result" and not msg["committed"] and msg["history"]["undo"] == 0
    msg, _ = reply(s, op="commit", edits=[{"kind": "move_point", "point": "O1", "to": [0.571, 0.615]}])
    assert msg["committed"] and msg["history"]["undo"] == 1
    msg, _ = reply(s, op="cancel")
    assert msg["doc"]["points"]["O1"] == [0.571, 0.615]
    # every history entry is an assur/1 document
    for text in s.history_entries():
        assert assur.loads(text).name == "Four-bar walking leg (paper 004, mechanism a)"
    first = s.history_entries()[0]
    reply(s, op="undo")
    assert toml_of(s.doc) == first
    reply(s, op="redo")
    assert s.doc["points"]["O1"] == [0.571, 0.615]


def test_locks():
    s = session_of("walker_fourbar.toml")
    reply(s, op="commit", edits=[{"kind": "lock_point", "point": "O1", "locked": True}])
    msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.6, 0.6]}])
    assert msg["type"] == "refused" and "O1" in msg["message"] and "locked" in msg["message"]
    reply(s, op="commit", edits=[{"kind": "lock_link", "link": "crank", "locked": True}])
    msg, _ = reply(s, op="commit", edits=[{"kind": "move_point", "point": "K", "to": [0.5, 0.3]}])
    K = msg["doc"]["points"]["K"]
    assert math.hypot(*K) == pytest.approx(0.27, rel=1e-14)          # on the circle of the locked crank
    assert math.atan2(K[1], K[0]) == pytest.approx(math.atan2(0.3, 0.5), rel=1e-14)
    assert msg["model"]["locks"] == {"points": ["O1"], "links": ["crank"]}
    assert assur.loads(msg["toml"]).links      # the locks live in [style], the file stays an assur/1 file


def test_adding_and_deleting_elements_keeps_a_document_that_may_not_be_a_mechanism_yet():
    s = session_of("walker_fourbar.toml")
    msg, _ = reply(s, op="commit", edits=[{"kind": "delete_link", "link": "rocker"}])
    assert msg["type"] == "result" and msg["cycle"] is None
    assert any(d["level"] == "error" and "mobility" in d["message"] for d in msg["diagnostics"])
    msg, _ = reply(s, op="commit", edits=[{"kind": "add_link", "points": ["L"], "new_points": {"Q": [0.6, 0.6]}}])
    assert msg["type"] == "refused"                                    # a link needs two points
    msg, _ = reply(s, op="commit", edits=[{"kind": "add_link", "points": ["Q", "L"], "new_points": {"Q": [0.567, 0.615]}}])
    assert msg["type"] == "result" and "Q" in msg["model"]["points"]
    msg, _ = reply(s, op="commit", edits=[{"kind": "add_point", "at": [0.567, 0.615], "link": "frame", "name": "O2"}])
    assert "O2" in msg["model"]["frame_points"]
    msg, _ = reply(s, op="commit", edits=[{"kind": "delete_point", "point": "H"}])
    assert "H" not in msg["model"]["points"] and msg["model"]["foot"] is None


def test_slider_and_driver_edits():
    s = session_of("crank_rocker.toml")
    names = s.doc["points"]
    msg, _ = reply(s, op="commit", edits=[{"kind": "set_speed", "driver": s.doc["drivers"][0]["name"], "speed": 5.0}])
    assert assur.loads(msg["toml"]).drivers[0].speed == 5.0                 # exactly the SI value sent
    msg, _ = reply(s, op="commit", edits=[{"kind": "delete_driver", "name": s.doc["drivers"][0]["name"]}])
    assert msg["cycle"] is None and msg["diagnostics"]
    d = msg["doc"]
    crank = next(n for n, e in d["links"].items() if n != "frame" and "frame" not in n
                 and set(e if isinstance(e, list) else e["points"]) & set(d["links"]["frame"]
                                                                          if isinstance(d["links"]["frame"], list)
                                                                          else d["links"]["frame"]["points"]))
    pts = d["links"][crank] if isinstance(d["links"][crank], list) else d["links"][crank]["points"]
    pivot = next(p for p in pts if p in d["links"]["frame"])
    arm = next(p for p in pts if p != pivot)
    msg, _ = reply(s, op="commit", edits=[{"kind": "add_driver", "link": crank, "pivot": pivot, "arm": arm,
                                           "speed": 2.0}])
    assert msg["cycle"] is not None and msg["cycle"]["input"]["speed"] == 2.0
    assert len(names) == len(msg["doc"]["points"])


def test_bad_requests_are_refused_with_a_reason():
    s = session_of("walker_fourbar.toml")
    cases = [({"op": "nope"}, "unknown request"),
             ({"op": "preview", "edits": "x"}, "list"),
             ({"op": "preview", "edits": [{"kind": "move_point", "point": "Z", "to": [0, 0]}]}, "no point named"),
             ({"op": "preview", "edits": [{"kind": "move_point", "point": "L", "to": [float("nan"), 0]}]}, "finite"),
             ({"op": "preview", "edits": [{"kind": "bend"}]}, "unknown edit"),
             ({"op": "commit", "edits": [{"kind": "flip", "group": 7}]}, "no group"),
             ({"op": "undo"}, "nothing to undo"),
             ({"op": "load", "toml": "format = 'assur-gears/1'"}, "not an assur/1"),
             ({"op": "load", "toml": "= ="}, "not valid TOML"),
             ({"op": "set_params", "params": {"crank.length": "a"}}, "not a number"),
             ({"op": "set_params", "params": {"x": 1.0}}, "no such parameter")]
    for request, words in cases:
        msg, blob = reply(s, **request)
        assert msg["type"] == "refused" and words in msg["message"], (request, msg)
        assert blob is None
    assert s.position == 0 and len(s.history) == 1
    assert s.handle("not a dict")[0].message["type"] == "refused"


def test_save_round_trips_with_load_and_dump(tmp_path):
    s = session_of("walker_fourbar.toml", tmp_path)
    reply(s, op="commit", edits=[{"kind": "move_point", "point": "O1", "to": [0.58, 0.62]}])
    msg, _ = reply(s, op="save")
    assert msg["type"] == "saved" and msg["written"] and msg["path"] == str(tmp_path / "walker_fourbar.toml")
    saved = assur.load(tmp_path / "walker_fourbar.toml")
    assert assur.dumps(saved) == assur.dumps(assur.io.mechanism_file.from_dict(s.doc))
    assert dict(saved.points)["O1"] == pytest.approx((0.58, 0.62), abs=0)
    # a session on a Mechanism has no file to save to
    t = Session(document_of(saved)[0])
    msg, _ = reply(t, op="save")
    assert msg["type"] == "refused" and "no file" in msg["message"]


def test_save_writes_through_a_special_file_never_replacing_it(tmp_path):
    import os
    fifo = tmp_path / "mech.toml"
    os.mkfifo(fifo)
    doc, _ = document_of(EX / "walker_fourbar.toml")
    s = Session(doc, str(fifo))
    import threading
    got = {}
    reader = threading.Thread(target=lambda: got.setdefault("text", fifo.read_text()))
    reader.start()
    reply(s, op="commit", edits=[{"kind": "move_point", "point": "O1", "to": [0.58, 0.62]}])   # something to save
    msg, _ = reply(s, op="save")
    reader.join(10)
    assert msg["type"] == "saved" and fifo.is_fifo()
    assert assur.loads(got["text"]).name.startswith("Four-bar walking leg")
    assert dict(assur.loads(got["text"]).points)["O1"] == (0.58, 0.62)


# ---------------------------------------------------------------------------------------------------------------
# the cycle the page receives

def test_the_cycle_is_the_engines():
    s = session_of("walker_fourbar.toml")
    msg, blob = reply(s, op="hello")
    A = arrays_of(msg, blob)
    plan = assur.compile(assur.load(EX / "walker_fourbar.toml"))
    q = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    st = assur.solve(plan, inputs=q)
    assert np.array_equal(A["q"], q)
    for name in ("pos", "vel", "acc"):
        assert np.allclose(A[name], getattr(st, name), rtol=0, atol=1e-12)
    assert msg["cycle"]["assembled"] == 360 and A["valid"].all()
    # velocities are the time derivative of the path: central difference quotients over Δt = Δq/ω
    w, dq = plan.speeds[0], q[1] - q[0]
    dq_fd = (np.roll(A["pos"], -1, 0) - np.roll(A["pos"], 1, 0)) / (2 * dq / w)
    assert np.max(np.abs(dq_fd - A["vel"])) < 2e-3 * np.max(np.abs(A["vel"]))    # O(Δq²) ≈ 5e-5 relative
    # instant centres: the link's velocity field vanishes there, v(I) = v_P + ω k×(I − P)
    for b, name in enumerate(msg["model"]["body_names"]):
        if b == 0 or name not in ("crank", "rocker", "coupler"):
            continue
        P0 = plan.mechanism.link(name).points[0] if hasattr(plan.mechanism, "link") else None
        i = plan.point_index(P0 or dict((lk.name, lk.points) for lk in plan.mechanism.links)[name][0])
        I, om = A["ic"][:, b], A["omega"][:, b]
        r = I - A["pos"][:, i]
        vI = A["vel"][:, i] + om[:, None] * np.stack([-r[:, 1], r[:, 0]], -1)
        ok = np.isfinite(I[:, 0])
        assert ok.sum() > 300 and np.max(np.abs(vI[ok])) < 1e-9 * np.max(np.abs(A["vel"]))
    # transmission angles and the dead centres (interpolated on the grid: O(h²) of the refined roots)
    mu = assur.transmission_angles(plan, st)
    assert np.allclose(A["transmission"][:, 0], mu["L"], atol=1e-12)
    ref = assur.dead_centres(plan)
    got = msg["cycle"]["dead_centres"]
    assert [d["kind"] for d in got] == [d.kind for d in ref]
    assert np.allclose([d["q"] for d in got], [d.angle for d in ref], atol=(2 * np.pi / 360) ** 2)
    # the driving torque of the file's masses
    f = assur.forces(plan, inputs=q)
    assert np.allclose(A["torque"], f.driver[..., 0], rtol=1e-9, atol=1e-9)
    assert np.allclose(A["power"], f.power, rtol=1e-9, atol=1e-9)


def test_gait_refined_after_a_commit_and_sampled_in_a_preview():
    s = session_of("walker_fourbar.toml")
    msg, blob = reply(s, op="hello")
    plan = assur.compile(assur.load(EX / "walker_fourbar.toml"))
    g = assur.gait_metrics(plan, steps=360)
    got = msg["cycle"]["gait"]
    assert got["exact"] and got["step_length"] == pytest.approx(g.step_length, rel=1e-12)
    assert got["lift"] == pytest.approx(g.lift, rel=1e-12) and got["duty_factor"] == pytest.approx(g.duty_factor)
    # two legs in antiphase: one or two feet on the ground (the module of the file's phases)
    A = arrays_of(msg, blob)
    assert set(np.unique(A["feet"])) <= {1.0, 2.0} and msg["cycle"]["module"]["min_feet"] >= 1
    msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.567, 0.615]}])
    assert not msg["cycle"]["gait"]["exact"]
    assert msg["cycle"]["gait"]["step_length"] == pytest.approx(g.step_length, rel=1e-3)   # on the samples


def test_unassemblable_stretches_are_invalid_samples_never_finite_garbage():
    s = session_of("walker_fourbar.toml")
    msg, blob = reply(s, op="preview", edits=[{"kind": "move_point", "point": "O1", "to": [0.9, 0.9]}])
    A = arrays_of(msg, blob)
    bad = A["valid"] == 0
    assert 0 < bad.sum() < 360 and msg["cycle"]["assembled"] == 360 - bad.sum()
    assert np.isnan(A["pos"][bad]).all()
    assert any(d["code"] == "unbuildable" for d in msg["diagnostics"])


def test_every_example_describes(tmp_path):
    for path in sorted(EX.glob("*.toml")):
        text = path.read_text()
        if 'format = "assur/1"' not in text:
            continue
        d = describe(document_of(path)[0], exact=False)
        assert d.meta["cycle"] is not None, (path.name, d.meta["diagnostics"])
        assert d.arrays["pos"].shape == (360, len(d.meta["model"]["point_order"]), d.meta["model"]["dimension"])


# ---------------------------------------------------------------------------------------------------------------
# the server: loopback only, token, Host and Origin

@pytest.fixture(scope="module")
def server():
    pytest.importorskip("starlette")
    from assur.designer.server import start_server
    doc, path = document_of(EX / "walker_fourbar.toml")
    srv = start_server(Session(doc, None))
    yield srv
    srv.stop()


def _status(url, headers=None):
    try:
        return urllib.request.urlopen(urllib.request.Request(url, headers=headers or {}), timeout=10).status
    except urllib.error.HTTPError as exc:
        return exc.code


def test_the_server_refuses_a_missing_token_and_a_foreign_host(server):
    base = f"http://127.0.0.1:{server.port}"
    assert _status(server.url) == 200
    assert _status(base + "/") == 403
    assert _status(base + "/?token=wrong") == 403
    assert _status(base + "/static/designer.js") == 403
    assert _status(base + f"/static/designer.js?token={server.token}") == 200
    assert _status(base + f"/static/plotly.min.js?token={server.token}") == 200
    assert _status(server.url, {"Host": "evil.example"}) == 400
    assert _status(server.url.replace("127.0.0.1", "localhost")) == 200


def test_the_websocket_refuses_a_foreign_origin_and_a_missing_token(server):
    from websockets.exceptions import InvalidStatus
    from websockets.sync.client import connect
    ws_url = f"ws://127.0.0.1:{server.port}/ws"
    own = f"http://127.0.0.1:{server.port}"
    for url, origin in ((f"{ws_url}?token={server.token}", "http://evil.example"),
                        (f"{ws_url}?token={server.token}", f"http://127.0.0.1:{server.port + 1}"),
                        (ws_url, own), (f"{ws_url}?token=x", own)):
        with pytest.raises(InvalidStatus) as exc:
            with connect(url, origin=origin, open_timeout=10):
                pass
        assert exc.value.response.status_code == 403
    with connect(f"{ws_url}?token={server.token}", origin=own, open_timeout=10) as ws:
        ws.send(json.dumps({"seq": 3, "op": "hello"}))
        msg = json.loads(ws.recv(timeout=30))
        blob = ws.recv(timeout=30)
        assert msg["type"] == "result" and msg["seq"] == 3 and len(blob) == 8 * sum(n for _, n, _ in msg["arrays"].values())


def test_the_server_listens_on_loopback_only(server):
    """The listening socket of the port is bound to 127.0.0.1 (the kernel's table of TCP sockets), so no other
    interface reaches it; where the machine has another address, a connection to it is refused."""
    import socket
    table = Path("/proc/net/tcp")
    if table.exists():
        listening = [line.split() for line in table.read_text().splitlines()[1:]]
        ours = [f[1] for f in listening if f[3] == "0A" and int(f[1].split(":")[1], 16) == server.port]
        assert ours == ["0100007F:%04X" % server.port]
    addresses = {a[4][0] for a in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)}
    for addr in addresses - {"127.0.0.1"}:
        if addr.startswith("127."):
            continue
        with socket.socket() as s:
            s.settimeout(2)
            assert s.connect_ex((addr, server.port)) != 0


def test_a_drag_never_changes_the_assembly_mode_of_a_triad():
    """A Newton-solved group (the triad of examples/triad_sixbar.toml) keeps the sign of its equilibrated Jacobian
    determinant: a sketch drawn in another assembly mode (D moved to (25, 300) mm, where that sign is the other
    one) is refused, a small move is not."""
    s = session_of("triad_sixbar.toml")
    msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "D", "to": [0.121, 0.131]}])
    assert msg["type"] == "result" and msg["cycle"]["assembled"] > 0
    msg, _ = reply(s, op="preview", edits=[{"kind": "move_point", "point": "D", "to": [0.025, 0.300]}])
    assert msg["type"] == "refused" and "assembly" in msg["message"] and "ab, tern, r1, r2" in msg["where"]
