"""Regenerate the screenshots of docs/designer.md: the designer in headless Chromium on the bundled examples.

    .venv/bin/python docs/designer_screenshots.py        # writes docs/designer/*.png

Needs Debian's chromium (/usr/bin/chromium) and Playwright for Python (the test extra); nothing is downloaded.
"""
from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "designer"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"


def _open(browser, url, size=(1400, 860)):
    page = browser.new_page(viewport={"width": size[0], "height": size[1]})
    page.goto(url)
    page.wait_for_function("window.__assur && window.__assur.ready", timeout=60_000)
    return page


def _served(path):
    from assur.designer.server import start_server
    from assur.designer.session import Session, document_of
    doc, file = document_of(path)
    return start_server(Session(doc, file))


def _screen_centre(page, point):
    box = page.locator(f'[data-testid="point-{point}"][data-point]').bounding_box()
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2


def main() -> int:
    from playwright.sync_api import sync_playwright
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        # 1. paper 004's four-bar leg at a quarter turn: paths, vectors, instant centres, gait and torque panels
        src = Path(shutil.copy(ROOT / "examples" / "walker_fourbar.toml", tmp))
        srv = _served(src)
        page = _open(browser, srv.url)
        page.locator('[data-testid="scrub"]').fill("90")
        page.wait_for_timeout(300)
        page.screenshot(path=OUT / "fourbar.png")
        # 2. a drag that would flip the coupler's branch is refused with the reason
        page.locator('[data-testid="scrub"]').fill("0")
        x, y = _screen_centre(page, "L")
        kx, ky = _screen_centre(page, "K")
        ox, oy = _screen_centre(page, "O1")
        page.mouse.move(x, y)
        page.mouse.down()
        # towards L's mirror image across the line K–O1
        ux, uy = ox - kx, oy - ky
        t = ((x - kx) * ux + (y - ky) * uy) / (ux * ux + uy * uy)
        mx, my = 2 * (kx + t * ux) - x, 2 * (ky + t * uy) - y
        for k in range(1, 21):
            page.mouse.move(x + (mx - x) * k / 20, y + (my - y) * k / 20)
            page.wait_for_timeout(30)
        page.wait_for_timeout(300)
        page.screenshot(path=OUT / "refused.png")
        page.keyboard.press("Escape")
        page.mouse.up()
        page.close()
        srv.stop()
        # 3. Jansen's linkage
        srv = _served(Path(shutil.copy(ROOT / "examples" / "jansen.toml", tmp)))
        page = _open(browser, srv.url)
        page.screenshot(path=OUT / "jansen.png")
        page.close()
        srv.stop()
        # 4. the spatial RSSR crank-rocker in the 3D view with its parameter sliders
        srv = _served(Path(shutil.copy(ROOT / "examples" / "rssr.toml", tmp)))
        page = _open(browser, srv.url)
        page.wait_for_timeout(1500)
        page.screenshot(path=OUT / "rssr.png")
        page.close()
        srv.stop()
        # 5. the slider-crank pump run from rest on its DC motor: the panel "Run on the motor"
        srv = _served(Path(shutil.copy(ROOT / "examples" / "slider_crank_motor.toml", tmp)))
        page = _open(browser, srv.url, size=(1400, 1000))
        page.locator('[data-testid="motor-run"]').click()
        page.wait_for_function("window.__assur.motor && window.__assur.motor.status === 'finished'", timeout=120_000)
        page.locator('[data-testid="motor-panel"]').screenshot(path=OUT / "motor.png")
        page.close()
        srv.stop()
        browser.close()
    for f in sorted(OUT.glob("*.png")):
        print(f.relative_to(ROOT))
    return 0


if __name__ == "__main__":
    sys.exit(main())
