"""``assur.designer.Designer``: the designer as a Jupyter widget (anywidget), tested without a notebook front end.

* the example notebook runs headless (nbclient) and shows the widget (its view mimetype, its ES module in the
  saved widget state);
* the Python side of the comm answers the front end's messages exactly as :class:`Session` does, and the arrays
  decode to the engine's positions (``assur.solve``);
* the same ``designer.js`` renders in real headless Chromium (Playwright) on a mock anywidget model whose
  ``send`` goes through the widget's comm handler in Python, and draws the engine's positions.

Reference values come from the engine (``assur.solve``, ``assur.gait_metrics``) or from the plotly package.
"""
import base64
import http.server
import json
import math
import re
import shutil
import sys
import threading
import time
import types
from functools import partial
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.designer.assembly import module_text
from assur.designer.session import Session, document_of, toml_of

pytest.importorskip("anywidget")
from assur.designer.widget import Designer, plotly_source  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
STATIC = ROOT / "src" / "assur" / "designer" / "static"
WIDGET_MIME = "application/vnd.jupyter.widget-view+json"
WIDGET_STATE = "application/vnd.jupyter.widget-state+json"


def arrays_of(message, blob):
    data = np.frombuffer(blob, dtype="<f8")
    return {k: data[o:o + n].reshape(shape) for k, (o, n, shape) in message["arrays"].items()}


class Wire:
    """What a widget sends to its front end: ``(method, content or state, buffers)`` in order."""

    def __init__(self, widget):
        self.sent = []
        self.lock = threading.Lock()
        widget._send = self._record

    def _record(self, msg, buffers=None):
        with self.lock:
            content = msg.get("content") if msg["method"] == "custom" else msg.get("state")
            self.sent.append((msg["method"], content, [bytes(b) for b in buffers or []]))

    def custom(self):
        with self.lock:
            return [(c, b) for m, c, b in self.sent if m == "custom"]

    def clear(self):
        with self.lock:
            self.sent.clear()


def from_front_end(widget, content, buffers=()):
    """Deliver ``content`` as the front end's ``model.send(content)`` reaches the kernel (ipywidgets' comm)."""
    widget._handle_msg({"content": {"data": {"method": "custom", "content": content}}, "buffers": list(buffers)})


def engine_state(doc, q):
    """The engine's state of a document at the inputs ``q``."""
    from assur.io.mechanism_file import from_dict
    plan = assur.compile(from_dict(doc))
    return plan, assur.solve(plan, inputs=np.asarray(q))


# ---------------------------------------------------------------------------------------------------------------
# the Python side

def test_import_assur_does_not_import_anywidget():
    import subprocess
    code = "import sys, assur, assur.designer; assert 'Designer' not in assur.__all__; print('anywidget' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, encoding="utf-8", check=True).stdout
    assert out.strip() == "False"
    assert assur.designer.Designer is Designer


def test_missing_anywidget_gives_the_install_hint(monkeypatch):
    from assur.errors import MissingPackageError
    monkeypatch.setitem(sys.modules, "anywidget", None)
    monkeypatch.delitem(sys.modules, "assur.designer.widget")
    with pytest.raises(MissingPackageError, match=r"pip install 'assur\[widget\]'"):
        import assur.designer.widget  # noqa: F401


def test_the_widget_carries_the_page_module_and_style():
    w = Designer(EX / "walker_fourbar.toml")
    assert w._esm == module_text()
    assert w._css == (STATIC / "designer.css").read_text(encoding="utf-8")
    state = w.get_state()
    assert state["_esm"] == w._esm and state["_css"] == w._css
    assert state["_plotly_js"] == ""          # planar: no plotly.js on the wire
    bundle, _ = w._repr_mimebundle_()
    assert WIDGET_MIME in bundle and bundle[WIDGET_MIME]["model_id"] == w.model_id


@pytest.mark.parametrize("how", ["mechanism", "path", "str", "toml"])
def test_constructor_accepts_a_mechanism_a_path_or_toml_text(how):
    path = EX / "walker_fourbar.toml"
    mech = assur.load(path)
    source = {"mechanism": mech, "path": path, "str": str(path), "toml": path.read_text(encoding="utf-8")}[how]
    w = Designer(source)
    assert w.session.path == (str(path) if how in ("path", "str") else None)
    # the document, its text and its mechanism all describe the same mechanism as the file
    assert assur.loads(w.toml).points == mech.points
    assert w.mechanism.points == mech.points and w.mechanism.links == mech.links
    assert w.document["points"].keys() == dict(mech.points).keys()


def test_hello_and_preview_through_the_comm_equal_the_session():
    path = EX / "walker_fourbar.toml"
    w = Designer(path)
    wire = Wire(w)
    reference = Session(*document_of(path))
    mech = assur.load(path)

    # hello: the same message and the same float64 buffer as Session.handle
    from_front_end(w, {"seq": 1, "op": "hello"})
    ((content, buffers),) = wire.custom()
    (expected,) = reference.handle({"seq": 1, "op": "hello"})
    assert content == expected.message and buffers == [expected.blob]
    assert content["type"] == "result" and content["binary"] is True and content["seq"] == 1
    assert json.loads(json.dumps(content, allow_nan=False)) == content      # the comm's JSON carries it as is
    a = arrays_of(content, buffers[0])
    plan, state = engine_state(content["doc"], a["q"])
    assert list(content["model"]["point_order"]) == list(plan.point_names)
    np.testing.assert_allclose(a["pos"], state.pos, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a["vel"], state.vel, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(a["sketch"], np.array([mech.sketch(p) for p in plan.point_names]))
    # one crank turn, evenly sampled
    n = content["cycle"]["n"]
    np.testing.assert_allclose(np.diff(a["q"]), 2 * math.pi / n, rtol=1e-12)

    # preview a drag of the rocker's pivot: the answer equals the session's, and nothing is committed
    wire.clear()
    O1 = np.array(mech.sketch("O1"))
    to = (O1 + [0.01, -0.005]).tolist()
    request = {"seq": 2, "op": "preview", "edits": [{"kind": "move_point", "point": "O1", "to": to}]}
    from_front_end(w, request)
    ((content, buffers),) = wire.custom()
    (expected,) = reference.handle(request)
    assert content == expected.message and buffers == [expected.blob]
    assert content["committed"] is False and content["history"]["undo"] == 0
    a = arrays_of(content, buffers[0])
    i = content["model"]["point_order"].index("O1")
    np.testing.assert_allclose(a["sketch"][i], to, rtol=0, atol=1e-12)
    plan, state = engine_state(content["doc"], a["q"])
    np.testing.assert_allclose(a["pos"], state.pos, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a["pos"][:, i], np.broadcast_to(to, a["pos"][:, i].shape), atol=1e-12)
    # the rocker's length follows the new sketch, and the committed design is still the file's
    L = np.array(mech.sketch("L"))
    rocker = next(lk for lk in plan.mechanism.links if lk.name == "rocker")
    assert rocker.length == pytest.approx(math.dist(to, L), rel=1e-12)
    assert w.mechanism.points == mech.points

    # a commit of the same edits is one history entry; undo goes back
    wire.clear()
    from_front_end(w, {**request, "seq": 3, "op": "commit"})
    ((content, _),) = wire.custom()
    assert content["committed"] is True and content["history"]["undo"] == 1
    assert dict(w.mechanism.points)["O1"] == pytest.approx(tuple(to), abs=1e-12)
    from_front_end(w, {"seq": 4, "op": "undo"})
    assert dict(w.mechanism.points)["O1"] == pytest.approx(tuple(O1), abs=0)


def test_result_gives_the_pages_numbers():
    path = EX / "walker_fourbar.toml"
    w = Designer(path)
    message, arrays = w.result()
    plan = assur.compile(assur.load(path))
    assert message["cycle"]["gait"]["step_length"] == pytest.approx(assur.gait_metrics(plan).step_length,
                                                                      rel=1e-6)
    state = assur.solve(plan, inputs=arrays["q"])
    np.testing.assert_allclose(arrays["pos"], state.pos, atol=1e-12)


def test_a_refused_request_answers_refused_and_changes_nothing():
    w = Designer(EX / "walker_fourbar.toml")
    wire = Wire(w)
    before = w.toml
    from_front_end(w, {"seq": 7, "op": "commit", "edits": [{"kind": "move_point", "point": "nowhere", "to": [0, 0]}]})
    from_front_end(w, {"seq": 8, "op": "no_such_op"})
    (r1, b1), (r2, b2) = wire.custom()
    assert (r1["type"], r1["seq"], r2["type"], r2["seq"]) == ("refused", 7, "refused", 8)
    assert b1 == b2 == []
    assert w.toml == before


def test_a_spatial_document_brings_plotly_before_its_result():
    import plotly
    bundle = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"
    w = Designer(EX / "walker_fourbar.toml")
    wire = Wire(w)
    assert w._plotly_js == ""
    spatial = (EX / "rssr.toml").read_text(encoding="utf-8")
    from_front_end(w, {"seq": 1, "op": "load", "toml": spatial})
    methods = [m for m, _, _ in wire.sent]
    assert methods == ["update", "custom"]                      # the trait first, then the result
    (_, state, _), (_, result, buffers) = wire.sent
    assert state["_plotly_js"] == bundle.read_text(encoding="utf-8") == plotly_source()
    assert "window.Plotly" in state["_plotly_js"]
    assert result["type"] == "result" and result["model"]["dimension"] == 3
    a = arrays_of(result, buffers[0])
    plan, st = engine_state(result["doc"], a["q"])
    np.testing.assert_allclose(a["pos"], st.pos, atol=1e-12)
    # opened on a spatial file, the widget carries plotly.js from the start
    assert Designer(spatial)._plotly_js == Designer(EX / "rssr.toml")._plotly_js == w._plotly_js


class FakeJob:
    """A synthesis job that reports progress from its own thread (the interface Session expects)."""

    def __init__(self, doc, point, targets, budget, seed):
        self.id, self.running, self._out, self._lock = "fake", True, [], threading.Lock()
        self.budget = int(budget)
        self.toml = toml_of(doc)
        self._cancel = threading.Event()
        threading.Thread(target=self._run, daemon=True).start()

    def _run(self):
        for k in range(1, self.budget + 1):
            if self._cancel.wait(0.03):
                break
            with self._lock:
                self._out.append({"type": "synth_progress", "evaluations": k, "best": 1.0 / k, "elapsed": 0.03 * k})
        with self._lock:
            self._out.append({"type": "synth_done", "status": "cancelled" if self._cancel.is_set() else "done",
                              "best": 1.0 / k, "toml": self.toml})
            self.running = False

    def poll(self):
        with self._lock:
            out, self._out = self._out, []
        return out

    def cancel(self):
        self._cancel.set()


def test_synthesis_progress_streams_from_a_background_thread(monkeypatch):
    monkeypatch.setitem(sys.modules, "assur.designer.synthesis_job",
                        types.SimpleNamespace(SynthesisJob=FakeJob))
    w = Designer(EX / "walker_fourbar.toml")
    wire = Wire(w)
    main = threading.get_ident()
    senders = []
    record = wire._record
    w._send = lambda msg, buffers=None: (senders.append(threading.get_ident()), record(msg, buffers))
    from_front_end(w, {"seq": 1, "op": "synth_start", "point": "H", "targets": [[0, 0], [1, 0]], "budget": 8})
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline and not any(c["type"] == "synth_done" for c, _ in wire.custom()):
        time.sleep(0.02)
    types_ = [c["type"] for c, _ in wire.custom()]
    assert types_[0] == "synth_started"
    assert types_[-1] == "synth_done" and types_.count("synth_done") == 1
    progress = [c["evaluations"] for c, _ in wire.custom() if c["type"] == "synth_progress"]
    assert progress == list(range(1, 9))                       # every report, in order, none twice
    assert any(t != main for t in senders[1:])                 # streamed by the poller, not by a request
    w._poller.join(timeout=5)
    assert not w._poller.is_alive()
    # the best design can be inserted as one history entry
    wire.clear()
    from_front_end(w, {"seq": 2, "op": "synth_insert"})
    ((content, _),) = wire.custom()
    assert content["type"] == "result" and content["history"]["undo"] == 1


@pytest.mark.slow
def test_a_run_on_the_motor_streams_its_end_with_its_samples():
    """The real run (a worker process) on the pump's DC motor: motor_started answers the request, motor_done comes from
    the poller with the run's samples in its buffer; the summary is the session's own run_document's."""
    from assur.designer.motor_job import run_document
    from assur.designer.payload import unpack
    w = Designer(EX / "slider_crank_motor.toml")
    wire = Wire(w)
    from_front_end(w, {"seq": 1, "op": "motor_start"})
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not any(c["type"] == "motor_done" for c, _ in wire.custom()):
        time.sleep(0.05)
    sent = wire.custom()
    assert [c["type"] for c, _ in sent] == ["motor_started", "motor_done"]
    done, buffers = sent[-1]
    assert done["status"] == "finished" and done["stop"]["kind"] == "steady"
    arrays = unpack(done["arrays"], buffers[0])
    summary, stop, reference, _ = run_document(w.document, 360)
    assert done["summary"] == summary and done["stop"] == stop
    np.testing.assert_array_equal(arrays["speed"], reference["speed"])
    w._poller.join(timeout=5)
    assert not w._poller.is_alive()


# ---------------------------------------------------------------------------------------------------------------
# the example notebook, headless

@pytest.mark.slow
def test_the_example_notebook_shows_the_widget():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    path = EX / "notebooks" / "designer.ipynb"
    nb = nbformat.read(path, as_version=4)
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3", store_widget_state=True,
                            resources={"metadata": {"path": str(path.parent)}}).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.output_type == "error"]
    views = [o["data"][WIDGET_MIME] for o in outputs if WIDGET_MIME in o.get("data", {})]
    assert len(views) == 1
    state = nb.metadata["widgets"][WIDGET_STATE]["state"]
    model = state[views[0]["model_id"]]
    assert model["model_name"] == "AnyModel" and model["model_module"] == "anywidget"
    assert model["state"]["_esm"] == module_text()
    assert model["state"]["_css"] == (STATIC / "designer.css").read_text(encoding="utf-8")
    # the step length the notebook reads back from the widget is the engine's
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    step = float(re.search(r"step length ([0-9.eE+-]+) m", text).group(1))
    expected = assur.gait_metrics(assur.compile(assur.load(EX / "walker_fourbar.toml"))).step_length
    assert step == pytest.approx(expected, rel=1e-3)          # printed to 4 significant digits


# ---------------------------------------------------------------------------------------------------------------
# designer.js in real headless Chromium, on a mock anywidget model

PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><link rel="icon" href="data:,">
<link rel="stylesheet" href="designer.css"></head>
<body><div id="app" style="width: 1100px; height: 760px"></div>
<script type="module">
// an anywidget model as the widget manager gives it to render(): its synced state is there before render,
// send() goes through the kernel's comm (here: a function exposed by the test), and what comes back is applied in
// order: state updates ("change:<name>" events) and custom messages ("msg:custom", the float64 arrays in a DataView)
import widget from "./designer.js";
const listeners = new Map();
const traits = await window.widgetState();
const emit = (event, ...args) => { for (const handler of listeners.get(event) || []) handler(...args); };
const model = {
  send(content) {
    window.widgetSend(content).then((replies) => {
      for (const { method, content, blob } of replies) {
        if (method === "update") {
          for (const [name, value] of Object.entries(content)) { traits[name] = value; emit(`change:${name}`, value); }
          continue;
        }
        const buffers = blob === null ? [] : [new DataView(Uint8Array.from(atob(blob), (c) => c.charCodeAt(0)).buffer)];
        emit("msg:custom", content, buffers);
      }
    });
  },
  on(event, handler) { if (!listeners.has(event)) listeners.set(event, new Set()); listeners.get(event).add(handler); },
  off(event, handler) { if (listeners.has(event)) listeners.get(event).delete(handler); },
  get(name) { return traits[name]; },
  set(name, value) { traits[name] = value; },
  save_changes() {},
};
window.widgetModel = model;
window.widgetCleanup = widget.render({ model, el: document.getElementById("app") });
</script></body></html>
"""


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    if not Path("/usr/bin/chromium").exists():
        pytest.skip("headless Chromium not installed")
    with sync_api.sync_playwright() as p:
        # swiftshader: WebGL for the plotly 3D view of a spatial file
        b = p.chromium.launch(executable_path="/usr/bin/chromium", args=["--no-sandbox", "--enable-unsafe-swiftshader"])
        yield b
        b.close()


@pytest.fixture
def served(tmp_path):
    """designer.js and designer.css next to the mock page, served on 127.0.0.1."""
    root = tmp_path / "www"
    root.mkdir()
    (root / "designer.js").write_text(module_text(), encoding="utf-8")
    shutil.copy(STATIC / "designer.css", root / "designer.css")
    (root / "index.html").write_text(PAGE, encoding="utf-8")

    class Quiet(http.server.SimpleHTTPRequestHandler):
        extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".js": "text/javascript"}

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), partial(Quiet, directory=str(root)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{server.server_address[1]}/"
    server.shutdown()
    server.server_close()


def open_widget(browser, url, widget):
    """The mock page with the widget's comm behind ``model.send``; returns (page, problems, requests, seen)."""
    wire = Wire(widget)
    seen = []          # every reply the page received (message, blob)

    def widget_send(content):
        wire.clear()
        from_front_end(widget, content)
        out = []
        for method, message, buffers in list(wire.sent):
            blob = buffers[0] if buffers else None
            if method == "custom":
                seen.append((message, blob))
            out.append({"method": method, "content": message,
                        "blob": None if blob is None else base64.b64encode(blob).decode()})
        return out

    page = browser.new_page(viewport={"width": 1280, "height": 900})
    problems, requests = [], []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: problems.append(str(e)))
    page.on("request", lambda r: requests.append(r.url))
    page.expose_function("widgetSend", widget_send)
    page.expose_function("widgetState", widget.get_state)
    page.goto(url + "index.html")
    page.wait_for_function("window.__assur && window.__assur.ready", timeout=30000)
    return page, problems, requests, seen


def drawn_points(page):
    return page.eval_on_selector_all(
        "[data-testid^=point-][data-point]",
        "els => Object.fromEntries(els.map(e => [e.dataset.point, [Number(e.dataset.x), Number(e.dataset.y)]]))")


def expected_pose(page, message, blob):
    """The positions the page should show, from the engine: the sketch or the cycle at the page's sample."""
    a = arrays_of(message, blob)
    plan, state = engine_state(message["doc"], a["q"])
    kind = page.get_attribute("[data-testid=canvas]", "data-pose")
    k = page.evaluate("window.__assur.sample")
    if kind == "cycle":
        pose = state.pos[k]
    else:
        mech = plan.mechanism
        pose = np.array([mech.sketch(p) for p in plan.point_names])
    return kind, k, {name: pose[i] for i, name in enumerate(plan.point_names)}


@pytest.mark.slow
def test_designer_js_renders_the_widget_in_chromium(browser, served, tmp_path):
    path = Path(shutil.copy(EX / "walker_fourbar.toml", tmp_path / "walker_fourbar.toml"))
    widget = Designer(path)
    page, problems, requests, seen = open_widget(browser, served, widget)
    try:
        assert seen and seen[0][0]["type"] == "result" and seen[0][0]["seq"] is not None
        drawn = drawn_points(page)
        kind, k, expected = expected_pose(page, *seen[-1])
        assert kind in ("cycle", "sketch")
        assert set(drawn) == set(expected)
        for name, xy in drawn.items():
            np.testing.assert_allclose(xy, expected[name], rtol=0, atol=1e-12, err_msg=f"{kind} {k} {name}")

        # scrub to a quarter turn: the page shows the engine's positions at that sample
        n = seen[-1][0]["cycle"]["n"]
        page.eval_on_selector("[data-testid=scrub]", "(el, k) => { el.value = String(k); "
                                                       "el.dispatchEvent(new Event('input', {bubbles: true})); }",
                              n // 4)
        page.wait_for_function("k => window.__assur.sample === k", arg=n // 4)
        kind, k, expected = expected_pose(page, *seen[-1])
        assert k == n // 4
        drawn = drawn_points(page)
        for name, xy in drawn.items():
            np.testing.assert_allclose(xy, expected[name], rtol=0, atol=1e-12, err_msg=f"{kind} {k} {name}")

        # drag the rocker's pivot a little: previews, then one commit the Python widget holds
        before = dict(widget.mechanism.points)["O1"]
        box = page.locator("[data-testid=point-O1]").bounding_box()
        x0, y0 = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x0, y0)
        page.mouse.down()
        for s in range(1, 6):
            page.mouse.move(x0 + 3 * s, y0 + 2 * s)
        page.mouse.up()
        page.wait_for_function("() => window.__assur.history && window.__assur.history.undo === 1 || "
                               "document.querySelector('[data-testid=history]').textContent.includes('undo 1')",
                               timeout=30000)
        ops = [m for m, _ in seen]
        assert any(m["type"] == "result" and m["committed"] is False for m in ops)     # previews
        assert ops[-1]["type"] == "result" and ops[-1]["committed"] is True
        after = dict(widget.mechanism.points)["O1"]
        assert after != before and after[0] > before[0] and after[1] < before[1]        # screen y points down
        page.wait_for_timeout(200)
        drawn = drawn_points(page)
        np.testing.assert_allclose(drawn["O1"], after, rtol=0, atol=1e-12)
        assert widget.session.history[-1]["points"]["O1"] == pytest.approx(list(after), abs=1e-12)

        assert problems == []
        assert page.evaluate("window.__assur.errors") == []
        assert requests and all(u.startswith(served) or u.startswith("data:") for u in requests), requests
    finally:
        page.close()


@pytest.mark.slow
def test_designer_js_draws_a_spatial_file_with_the_widgets_plotly(browser, served):
    widget = Designer(EX / "rssr.toml")
    assert widget._plotly_js                        # plotly.js travels with the widget's state, not from a CDN
    page, problems, requests, seen = open_widget(browser, served, widget)
    try:
        page.wait_for_function("() => document.querySelector('[data-testid=view3d]')"
                               ".classList.contains('js-plotly-plot')", timeout=30000)
        assert page.evaluate("typeof window.Plotly") == "object"
        message, blob = seen[-1]
        a = arrays_of(message, blob)
        plan, state = engine_state(message["doc"], a["q"])
        k = page.evaluate("window.__assur.sample")
        scale = {"m": 1.0, "mm": 1000.0}[page.evaluate("window.__assur.units.length")]
        traces = page.evaluate("() => document.querySelector('[data-testid=view3d]').data"
                               ".map(t => ({name: t.name, x: t.x, y: t.y, z: t.z}))")
        links = {t["name"]: t for t in traces}
        index = {p: i for i, p in enumerate(plan.point_names)}
        for link in plan.mechanism.links:
            corners = [state.pos[k, index[p]] * scale for p in link.points]
            if len(corners) > 2:
                corners.append(corners[0])
            t = links[link.name]
            np.testing.assert_allclose(np.array([t["x"], t["y"], t["z"]]).T, corners, rtol=1e-12, atol=1e-9)
        assert [e for e in problems if "WebGL" not in e and "GPU" not in e] == []
        assert all(u.startswith(served) or u.startswith("data:") for u in requests), requests
    finally:
        page.close()

@pytest.mark.slow
def test_in_a_kernel_replies_and_progress_reach_the_front_end_as_comm_messages():
    """In a real ipykernel the answers leave as ``comm_msg`` (custom content, the arrays as a binary buffer),
    and the progress of a synthesis keeps arriving from the widget's thread after the cell has finished."""
    import inspect
    jupyter_client = pytest.importorskip("jupyter_client")
    pytest.importorskip("ipykernel")
    path = EX / "walker_fourbar.toml"
    code = "\n".join([
        "import sys, threading, types", "import assur", "from assur.designer.session import toml_of",
        inspect.getsource(FakeJob),
        "sys.modules['assur.designer.synthesis_job'] = types.SimpleNamespace(SynthesisJob=FakeJob)",
        f"w = assur.designer.Designer({str(path)!r})", "display(w)",
        "def front(content):",
        "    w._handle_msg({'content': {'data': {'method': 'custom', 'content': content}}, 'buffers': []})",
        "front({'seq': 1, 'op': 'hello'})",
        "front({'seq': 2, 'op': 'synth_start', 'point': 'H', 'targets': [[0, 0], [1, 0]], 'budget': 20})",
    ])
    km, kc = jupyter_client.manager.start_new_kernel(kernel_name="python3")
    try:
        msg_id = kc.execute(code)
        custom, idle, deadline = [], False, time.monotonic() + 120
        while time.monotonic() < deadline:
            try:
                msg = kc.get_iopub_msg(timeout=1)
            except Exception:                     # queue.Empty: keep waiting for the thread's messages
                continue
            if msg["msg_type"] == "error":
                pytest.fail("\n".join(msg["content"]["traceback"]))
            if msg["msg_type"] == "status" and msg["parent_header"].get("msg_id") == msg_id:
                idle = idle or msg["content"]["execution_state"] == "idle"
            if msg["msg_type"] == "comm_msg" and msg["content"]["data"].get("method") == "custom":
                custom.append((msg["content"]["data"]["content"], msg["buffers"], idle))
                if custom[-1][0]["type"] == "synth_done":
                    break
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    kinds = [c["type"] for c, _, _ in custom]
    assert kinds[:2] == ["result", "synth_started"] and kinds[-1] == "synth_done"
    assert [c["evaluations"] for c, _, _ in custom if c["type"] == "synth_progress"] == list(range(1, 21))
    assert custom[-1][2]                            # the end of the run arrived after the cell had finished
    # the result's buffer is the session's float64 blob: the engine's positions
    result, buffers, _ = custom[0]
    (expected,) = Session(*document_of(path)).handle({"seq": 1, "op": "hello"})
    assert len(buffers) == 1 and bytes(buffers[0]) == expected.blob
    a = arrays_of(result, bytes(buffers[0]))
    plan, state = engine_state(result["doc"], a["q"])
    np.testing.assert_allclose(a["pos"], state.pos, atol=1e-12)
