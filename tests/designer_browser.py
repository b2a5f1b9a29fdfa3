"""Real headless Chromium (through Playwright) for the tests of the designer's page (`assur design`).

Conventions of ``tests/browser.py``: Chromium comes from Debian (``/usr/bin/chromium``, never downloaded); outside
CI a module using these fixtures is skipped when Chromium or Playwright is missing, in CI their absence is a
failure.

* ``browser``: one headless Chromium per test module.
* ``designer``: a factory ``designer(example, **page_options) -> Designer``: a server run in this process on a COPY
  of ``examples/<example>`` in ``tmp_path`` (the examples are never written) and a page on it. Every page routes
  all its requests through a guard that aborts (and records) any request to a host other than 127.0.0.1 or
  localhost, records console errors, page errors and the page's own ``__assur.errors``; after the test the
  fixture asserts that none of these happened and saves one screenshot under ``$ASSUR_TEST_ARTIFACTS``
  (default ``<repo>/test-artifacts/``).
* helpers on :class:`Designer`: wait for ``__assur.ready``, for a result after a given ``seq``, read the arrays of
  ``__assur.arrays`` as numpy arrays, set the sample, and drag a point with ``page.mouse`` (down, moves in
  several steps, up) from the on-screen position of its SVG element.
"""
from __future__ import annotations

import os
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

import assur

from browser import BROWSER

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
ARTIFACTS = Path(os.environ.get("ASSUR_TEST_ARTIFACTS") or ROOT / "test-artifacts")
LOCAL_HOSTS = {"127.0.0.1", "localhost"}
#: how long a page may take to answer (s): first loads include the plotly bundle and one solve of the cycle
TIMEOUT_MS = 30_000

try:
    from playwright.sync_api import sync_playwright
except ImportError:  # pragma: no cover - depends on the environment
    sync_playwright = None
    if os.environ.get("CI"):
        raise RuntimeError("CI needs Playwright for Python for the designer's browser tests") from None

needs_designer_browser = pytest.mark.skipif(BROWSER is None or sync_playwright is None,
                                            reason="headless Chromium or Playwright not installed")


def launch(playwright):
    """Debian's Chromium, headless (Playwright never downloads a browser here)."""
    return playwright.chromium.launch(executable_path=BROWSER, args=["--no-sandbox", "--disable-gpu"])


@pytest.fixture(scope="module")
def browser():
    if BROWSER is None or sync_playwright is None:
        pytest.skip("headless Chromium or Playwright not installed")
    with sync_playwright() as p:
        b = launch(p)
        try:
            yield b
        finally:
            b.close()


def host_of(url: str) -> str:
    m = re.match(r"^[a-z][a-z0-9+.-]*://(\[[^\]]*\]|[^/:?#]*)", url, re.I)
    return m.group(1).lower() if m else ""


#: installed before the page's scripts: traces the WebSocket's requests and answers (their ``seq``) in
#: ``window.__assur_wire``, so a test can wait until no request is in flight without touching the page's code
WIRE_TRACE = """
(() => {
  const Native = window.WebSocket;
  const wire = { sent: 0, answered: 0, ops: [], types: [] };
  window.__assur_wire = wire;
  class TracedWebSocket extends Native {
    constructor(...args) {
      super(...args);
      this.addEventListener("message", (event) => {
        if (typeof event.data !== "string") return;
        const message = JSON.parse(event.data);
        wire.types.push(message.type);
        if (Number.isInteger(message.seq)) wire.answered = Math.max(wire.answered, message.seq);
      });
    }
    send(data) {
      if (typeof data === "string") {
        const message = JSON.parse(data);
        wire.ops.push(message.op);
        if (Number.isInteger(message.seq)) wire.sent = Math.max(wire.sent, message.seq);
      }
      return super.send(data);
    }
  }
  window.WebSocket = TracedWebSocket;
})();
"""


def install_guard(page, record: "PageRecord") -> None:
    """Abort and record every request to a host that is not this machine's loopback; record console errors,
    page errors and failed requests."""
    def route(r):
        url = r.request.url
        if url.startswith(("data:", "blob:", "about:")) or host_of(url) in LOCAL_HOSTS:
            r.continue_()
        else:
            record.foreign.append(url)
            r.abort()
    page.route("**/*", route)
    page.add_init_script(WIRE_TRACE)
    page.on("console", lambda m: record.console.append(f"{m.type}: {m.text}") if m.type == "error" else None)
    page.on("pageerror", lambda e: record.page_errors.append(str(e)))


@dataclass
class PageRecord:
    foreign: list = field(default_factory=list)
    console: list = field(default_factory=list)
    page_errors: list = field(default_factory=list)
    assur_errors: list = field(default_factory=list)

    def problems(self) -> list[str]:
        return ([f"request to a foreign host: {u}" for u in self.foreign]
                + [f"console {m}" for m in self.console]
                + [f"page error: {m}" for m in self.page_errors]
                + [f"__assur.errors: {m}" for m in self.assur_errors])


class Designer:
    """One designer server (on a copy of an example) and its page."""

    def __init__(self, browser, tmp_path: Path, example: str, viewport=(1400, 900), fragment: str = ""):
        from assur.designer.server import start_server
        from assur.designer.session import Session, document_of
        self.file = tmp_path / Path(example).name
        if not self.file.exists():
            source = EXAMPLES / example if not Path(example).is_absolute() else Path(example)
            shutil.copy(source, self.file)
            for gear in assur.load(source).gears:          # a gear pair's design file goes with its mechanism
                if gear.design is not None:
                    shutil.copy(gear.design, tmp_path / Path(gear.design).name)
        doc, path = document_of(self.file)
        self.server = start_server(Session(doc, path))
        self.context = browser.new_context(viewport={"width": viewport[0], "height": viewport[1]})
        self.pages: list = []
        self.records: list[PageRecord] = []
        self.page = self.open(fragment)

    # -- pages ------------------------------------------------------------------------------------------------
    def open(self, fragment: str = "", url: str | None = None, wait: bool = True):
        """A new page on ``url`` (default: this server's) with the guard installed; waits for ``ready``."""
        page = self.context.new_page()
        record = PageRecord()
        install_guard(page, record)
        page.set_default_timeout(TIMEOUT_MS)
        self.pages.append(page)
        self.records.append(record)
        page.goto((url or self.server.url) + fragment)
        if wait:
            wait_ready(page)
        return page

    def close(self) -> list[str]:
        """Close the pages and stop the server; the problems every page recorded."""
        problems = []
        for page, record in zip(self.pages, self.records):
            try:
                if not page.is_closed():
                    record.assur_errors.extend(page.evaluate("(window.__assur && window.__assur.errors) || []"))
            except Exception as exc:  # a crashed page is a problem too
                problems.append(f"cannot read the page's errors: {exc}")
            problems.extend(record.problems())
        self.context.close()
        self.server.stop()
        return problems

    # -- state -------------------------------------------------------------------------------------------------
    def state(self, expression: str, page=None):
        """``window.__assur.<expression>`` evaluated in the page (JSON-able values)."""
        return (page or self.page).evaluate(f"() => window.__assur.{expression}")

    def array(self, name: str, page=None) -> np.ndarray:
        """``__assur.arrays[name]`` reshaped by the sizes of the result on display (float64, NaN kept)."""
        page = page or self.page
        values = page.evaluate(
            """(name) => { const a = window.__assur.arrays[name];
                          return a ? Array.from(a, (v) => (Number.isFinite(v) ? v : null)) : null; }""", name)
        if values is None:
            raise KeyError(name)
        a = np.array([np.nan if v is None else v for v in values], dtype=float)
        shape = self.shapes(page).get(name)
        return a.reshape(shape) if shape else a

    def shapes(self, page=None) -> dict:
        """The array shapes of the result on display: from the result's sizes and the model."""
        page = page or self.page
        r = page.evaluate("() => window.__assur.result")
        n = r["cycle"]["n"] if r.get("cycle") else 0
        P = len(r["model"].get("point_order") or r["model"]["points"])
        B = len(r["model"].get("body_names") or [])
        G = len(r["model"].get("groups") or [])
        D = 3 if r["model"].get("dimension") == 3 else 2
        return {"pos": (n, P, D), "vel": (n, P, D), "acc": (n, P, D), "ic": (n, B, 2), "omega": (n, B),
                "alpha": (n, B), "transmission": (n, G), "sketch": (P, D)}

    def wire(self, page=None) -> dict:
        """The WebSocket trace: ``sent``/``answered`` (highest seq), ``ops`` sent, message ``types`` received."""
        return (page or self.page).evaluate("() => window.__assur_wire")

    def seq(self, page=None) -> int:
        return int(self.state("seq", page) or 0)

    def point_order(self, page=None) -> list[str]:
        m = self.state("result.model", page)
        return list(m.get("point_order") or m["points"])

    def testid(self, name: str, page=None):
        return (page or self.page).locator(f'[data-testid="{name}"]')

    def text(self, name: str, page=None) -> str:
        return self.testid(name, page).text_content()

    def set_sample(self, k: int, page=None) -> None:
        """Move the scrub bar to sample ``k`` (as a user would: an input event on the range)."""
        page = page or self.page
        page.evaluate("""(k) => { const s = document.querySelector('[data-testid="scrub"]');
                                  s.value = String(k); s.dispatchEvent(new Event('input', {bubbles: true})); }""", k)
        page.wait_for_function("(k) => window.__assur.sample === k", arg=k)

    # -- waiting -------------------------------------------------------------------------------------------------
    def wait_result(self, after: int, predicate: str = "true", page=None) -> dict:
        """Wait until a result with ``seq > after`` is on display and ``predicate`` (JS on ``r``, the result)
        holds; returns the result (without arrays)."""
        page = page or self.page
        page.wait_for_function(
            f"(after) => {{ const a = window.__assur; const r = a && a.result;"
            f" return r && a.seq > after && ({predicate}); }}", arg=after)
        return self.state("result", page)

    def wait_refusal(self, page=None) -> str:
        page = page or self.page
        page.wait_for_function("() => Boolean(window.__assur.refusal)")
        return self.state("refusal", page)

    # -- geometry on screen --------------------------------------------------------------------------------------
    def screen_of(self, name: str, page=None) -> tuple[float, float]:
        """The centre of point ``name``'s circle on screen (CSS pixels)."""
        box = self.testid(f"point-{name}", page).bounding_box()
        assert box is not None, f"point {name} is not drawn"
        return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2

    def world_to_screen(self, page=None):
        """The map world (SI, y up) → screen of the canvas on display, fitted from two drawn points (their SVG
        circles and their ``data-x/data-y``): an isotropic scale with y flipped."""
        page = page or self.page
        pts = page.evaluate("""() => [...document.querySelectorAll('[data-testid^="point-"]')].map((c) => {
            const b = c.getBoundingClientRect();
            return [Number(c.dataset.x), Number(c.dataset.y), b.x + b.width / 2, b.y + b.height / 2]; })""")
        pts = np.array(pts, dtype=float)
        i, j = max(((a, b) for a in range(len(pts)) for b in range(a + 1, len(pts))),
                   key=lambda ab: np.hypot(*(pts[ab[0], :2] - pts[ab[1], :2])))
        (x1, y1, sx1, sy1), (x2, y2, sx2, sy2) = pts[i], pts[j]
        scale = np.hypot(sx2 - sx1, sy2 - sy1) / np.hypot(x2 - x1, y2 - y1)

        def to_screen(xy):
            return sx1 + (xy[0] - x1) * scale, sy1 - (xy[1] - y1) * scale
        to_screen.scale = scale
        return to_screen

    def drag(self, name: str, to_world, steps: int = 12, release: bool = True, page=None,
             on_step=None) -> None:
        """Drag point ``name`` with the mouse to the world position ``to_world`` (m): down on its circle, ``steps``
        moves (each waits for the page to answer or refuse), up (unless ``release`` is False). ``on_step(i)`` is
        called after every move."""
        page = page or self.page
        to_screen = self.world_to_screen(page)
        sx, sy = self.screen_of(name, page)
        tx, ty = to_screen(to_world)
        page.mouse.move(sx, sy)
        page.mouse.down()
        for i in range(1, steps + 1):
            page.mouse.move(sx + (tx - sx) * i / steps, sy + (ty - sy) * i / steps)
            settle(page)
            if on_step is not None:
                on_step(i)
        if release:
            page.mouse.up()

    def click_world(self, xy, page=None) -> None:
        """A click on the canvas at the world position ``xy`` (m)."""
        page = page or self.page
        sx, sy = self.world_to_screen(page)(xy)
        page.mouse.click(sx, sy)

    def screenshot(self, name: str) -> Path:
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        path = ARTIFACTS / f"{re.sub(r'[^A-Za-z0-9_.-]+', '_', name)}.png"
        self.page.screenshot(path=str(path), full_page=True)
        return path


def wait_ready(page) -> None:
    page.wait_for_function("() => window.__assur && window.__assur.ready === true")


def settle(page) -> None:
    """Wait until the page's request channel is idle: two animation frames (the page's pointer handlers ran),
    every request sent has its answer (``__assur_wire``), one more frame (the answer is drawn)."""
    page.evaluate("() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)))")
    page.wait_for_function("() => window.__assur_wire.answered >= window.__assur_wire.sent")
    page.evaluate("() => new Promise((ok) => requestAnimationFrame(ok))")


@pytest.fixture
def designer(browser, tmp_path, request):
    """``designer(example, **options) -> Designer``; after the test: no foreign request, no console or page
    error on any page, one screenshot of the first page saved under ``$ASSUR_TEST_ARTIFACTS``."""
    made: list[Designer] = []

    def make(example: str, **options) -> Designer:
        d = Designer(browser, tmp_path, example, **options)
        made.append(d)
        return d

    yield make
    problems = []
    for i, d in enumerate(made):
        try:
            if not d.page.is_closed():
                d.screenshot(request.node.name + (f"-{i}" if i else ""))
        except Exception as exc:  # the screenshot is an artifact; its failure is not the test's
            print(f"screenshot failed: {exc}")
        problems += d.close()
    assert not problems, "the page misbehaved:\n" + "\n".join(problems)
