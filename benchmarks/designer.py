#!/usr/bin/env python3
"""The designer's drag round trip in headless Chromium: pointer move → WebSocket → solve → redraw.

Run: ``python benchmarks/designer.py`` (writes ``benchmarks/designer_results.md``; ``--out -`` prints only).
Needs the ``web`` extra, Playwright for Python and Debian's Chromium (``/usr/bin/chromium``; never downloaded).

Each case runs one designer server as the user does, ``assur design FILE --no-browser`` in its own process (so the
browser driver and the server do not share an interpreter), on the case's document written to a temporary file,
and one page. A point
is dragged with real mouse events in a small circle (a few pixels from its start, so no branch is crossed): every
move sends a ``preview`` with the move, the server solves the whole cycle (360 samples, positions, velocities,
accelerations, and the driving torque and power when the document has masses) and the page draws it. The page
records each round trip in ``window.__assur.roundTrips`` (from the pointer move to the drawn answer); the moves are
made one at a time (the next after the answer is drawn), so a round trip is the latency of one answer, not a
queue. Reported over ``--moves`` moves after ``--warmup`` unrecorded ones: min, p50 (the median) and p95 (ms),
and, for comparison, the median of the server's own answer to the same preview (``Session.handle`` called
directly, no browser, no socket).

Cases: the four-bar walking leg (``examples/walker_fourbar.toml``) and Jansen's linkage (``examples/jansen.toml``),
each with the torque panel off (masses, gravity and the gait's body weight stripped from the document) and on (the
four-bar file's own masses; for Jansen every link given ``--jansen-mass`` kg and gravity); the triad six-bar
(``examples/triad_sixbar.toml``, a class-III group: its compiled Newton kernel, compiled before the drag, as the
designer compiles it in the background). ``--only TEXT`` runs the cases whose name contains TEXT (``'Jansen, torque off|triad'``: two).
"""
from __future__ import annotations

import argparse
import copy
import datetime
import math
import platform
import shutil
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from tables import publish

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or "/usr/bin/chromium"


def without_masses(doc: dict) -> dict:
    """The document with no mass, inertia, centre of mass, gravity or body weight: no torque panel."""
    doc = copy.deepcopy(doc)
    for entry in doc["links"].values():
        if isinstance(entry, dict):
            for key in ("mass", "com", "inertia"):
                entry.pop(key, None)
    doc.pop("dynamics", None)
    if isinstance(doc.get("gait"), dict):
        doc["gait"].pop("weight", None)
    return doc


def with_masses(doc: dict, kg: float) -> dict:
    """Every moving link given ``kg`` (its centre of mass and inertia by the file format's defaults), gravity −y."""
    doc = copy.deepcopy(doc)
    for name, entry in list(doc["links"].items()):
        if name == "frame":
            continue
        if not isinstance(entry, dict):
            entry = doc["links"][name] = {"points": entry}
        entry["mass"] = f"{kg} kg"
    doc["dynamics"] = {"gravity": [0, -9.81]}
    return doc


def cases(jansen_mass: float) -> dict:
    from assur.designer.session import document_of
    fourbar, _ = document_of(ROOT / "examples" / "walker_fourbar.toml")
    jansen, _ = document_of(ROOT / "examples" / "jansen.toml")
    triad, _ = document_of(ROOT / "examples" / "triad_sixbar.toml")
    return {  # name: (document, dragged point, torque panel expected)
        "four-bar leg, torque off": (without_masses(fourbar), "O1", False),
        "four-bar leg, torque on": (fourbar, "O1", True),
        "Jansen, torque off": (without_masses(jansen), "P", False),
        "Jansen, torque on": (with_masses(jansen, jansen_mass), "P", True),
        "triad six-bar (Newton kernel)": (without_masses(triad), "B", False),
    }


class DesignServer:
    """``assur design`` on ``doc`` (written to a temporary file) in a child process; ``url``, ``stop()``."""

    def __init__(self, doc: dict):
        import re
        import subprocess
        import tempfile
        from assur.designer.session import toml_of
        self._dir = tempfile.TemporaryDirectory()
        path = Path(self._dir.name) / "mechanism.toml"
        path.write_text(toml_of(doc), encoding="utf-8")
        self._proc = subprocess.Popen([sys.executable, "-m", "assur", "design", str(path), "--no-browser"],
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self._proc.stdout.readline()
        found = re.search(r"http://127\.0\.0\.1:\d+/\?token=\S+", line)
        if not found:
            self.stop()
            raise RuntimeError(f"assur design did not start: {line!r}")
        self.url = found.group(0)

    def stop(self) -> None:
        import signal
        self._proc.send_signal(signal.SIGINT)
        self._proc.communicate(timeout=30)
        self._dir.cleanup()


def percentile(values, p: float) -> float:
    return float(np.percentile(np.asarray(values, dtype=float), p))


def drag_round_trips(browser, doc: dict, point: str, moves: int, warmup: int, radius_px: float,
                     torque: bool) -> list[float]:
    """The round trips (ms) of the last ``moves`` of ``warmup + moves`` pointer moves of ``point`` in a circle."""
    server = DesignServer(doc)
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    try:
        page.goto(server.url)
        page.wait_for_function("() => window.__assur && window.__assur.ready === true", timeout=60_000)
        has_torque = page.evaluate("() => Boolean(window.__assur.arrays.torque)")
        if has_torque != torque:
            raise RuntimeError(f"torque panel {'on' if has_torque else 'off'}, expected {'on' if torque else 'off'}")
        box = page.locator(f'[data-testid="point-{point}"]').bounding_box()
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(cx, cy)
        page.mouse.down()
        page.mouse.move(cx + radius_px, cy, steps=4)          # past the drag threshold: the drag has started
        page.wait_for_function("() => window.__assur.roundTrips.length >= 1", timeout=60_000)
        page.wait_for_timeout(500)                             # the answers to the start of the drag are in
        base = page.evaluate("() => window.__assur.roundTrips.length")
        for i in range(warmup + moves):
            a = 2 * math.pi * (i + 1) / 50
            page.mouse.move(cx + radius_px * math.cos(a), cy + radius_px * math.sin(a))
            page.wait_for_function("(n) => window.__assur.roundTrips.length >= n || window.__assur.refusal",
                                   arg=base + i + 1, timeout=60_000)
            refusal = page.evaluate("() => window.__assur.refusal")
            if refusal:
                raise RuntimeError(f"a preview was refused: {refusal}")
        trips = page.evaluate("() => Array.from(window.__assur.roundTrips)")[base + warmup:base + warmup + moves]
        page.keyboard.press("Escape")
        page.mouse.up()
        if errors:
            raise RuntimeError("the page reported errors: " + "; ".join(errors))
        return trips
    finally:
        page.close()
        server.stop()


def server_previews(doc: dict, point: str, count: int) -> list[float]:
    """ms of ``Session.handle`` answering a preview that moves ``point`` by a little (no browser, no socket)."""
    from assur.designer.payload import describe
    from assur.designer.session import Session
    from assur.designer.server import _prepare_kernels
    session = Session(doc, None)
    loading = _prepare_kernels(session)        # as `assur design` does: a Newton kernel loaded in the background
    if loading is not None:
        loading.join()
    sketch = describe(doc).mechanism.sketch(point)
    out = []
    for i in range(count):
        a = 2 * math.pi * i / 50
        to = [sketch[0] + 1e-3 * math.cos(a), sketch[1] + 1e-3 * math.sin(a)]
        t = time.perf_counter()
        (reply,) = session.handle({"op": "preview", "seq": i, "edits": [{"kind": "move_point", "point": point,
                                                                         "to": to}]})
        out.append(1000 * (time.perf_counter() - t))
        assert reply.message["type"] == "result", reply.message
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--moves", type=int, default=200, help="recorded pointer moves per case")
    ap.add_argument("--warmup", type=int, default=10, help="unrecorded pointer moves before them")
    ap.add_argument("--radius", type=float, default=12.0, help="radius of the dragged circle (CSS px)")
    ap.add_argument("--jansen-mass", type=float, default=0.1, help="kg given to each link of Jansen's leg")
    ap.add_argument("--out", default=str(HERE / "designer_results.md"), help="Markdown file to write ('-' for none)")
    ap.add_argument("--only", default="", help="run only the cases whose name contains this text (or one of "
                                                 "several separated by |)")
    args = ap.parse_args(argv)
    import subprocess
    import assur
    if not args.only or "triad" in args.only:
        # the Newton kernel into the disk cache the designer's process reads, compiled in a process of its own (this
        # one does not import numba before the cases that come first: the triad's case is the last)
        subprocess.run([sys.executable, "-c", "import assur; from assur.engine.planar import numba_backend; "
                        "numba_backend.prepare_newton(assur.compile(assur.load(%r)))"
                        % str(ROOT / "examples" / "triad_sixbar.toml")], check=True)
    from playwright.sync_api import sync_playwright
    rows = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        try:
            for name, (doc, point, torque) in cases(args.jansen_mass).items():
                if not any(part in name for part in args.only.split("|")):
                    continue
                trips = drag_round_trips(browser, doc, point, args.moves, args.warmup, args.radius, torque)
                server = server_previews(doc, point, max(20, args.moves // 4))
                rows.append((name, point, len(trips), min(trips), statistics.median(trips), percentile(trips, 95),
                             max(trips), statistics.median(server)))
                print(f"{name}: p50 {rows[-1][4]:.1f} ms, p95 {rows[-1][5]:.1f} ms", file=sys.stderr)
        finally:
            browser.close()
    command = (f"python benchmarks/designer.py --moves {args.moves} --warmup {args.warmup} --radius {args.radius:g} "
               f"--jansen-mass {args.jansen_mass:g}" + (f" --only '{args.only}'" if args.only else ""))
    lines = [f"# The designer's drag round trip ({datetime.date.today().isoformat()})", "",
             f"`{command}` on {platform.machine()} ({_cores()} cores), Python {platform.python_version()}, "
             f"numpy {np.__version__}, assur {assur.__version__}, headless Chromium ({Path(CHROMIUM).name}).", "",
             "One round trip: a pointer move on the dragged point → `preview` over the WebSocket → the server (`assur "
             "design`, its own process) solves "
             "the whole cycle (360 samples, positions, velocities and accelerations; torque and power when the "
             "document has masses) → the page has drawn the answer (`window.__assur.roundTrips`). Moves one at a "
             "time; the server column is `Session.handle` answering the same preview directly.", "",
             "| case | dragged | moves | min (ms) | p50 (ms) | p95 (ms) | max (ms) | server p50 (ms) |",
             "|---|---|---|---|---|---|---|---|"]
    for name, point, n, lo, p50, p95, hi, srv in rows:
        lines.append(f"| {name} | {point} | {n} | {lo:.1f} | {p50:.1f} | {p95:.1f} | {hi:.1f} | {srv:.1f} |")
    return publish(lines, args.out)


def _cores() -> int:
    import os
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


if __name__ == "__main__":
    raise SystemExit(main())
