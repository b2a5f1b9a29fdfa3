"""The animation player of an HTML animation (``assur animate … -o F.html``, and the report's animation) shows a
visible icon on every button in Debian's Chromium (through Playwright).

Once two buttons (first and last frame: the characters ⏮ and ⏭) were empty boxes: no font of the system has those
glyphs. The test renders each button and, as a reference, a button of the same style holding a character no font
has (U+10FFFD, a private-use code point): every button must show dark pixels (an icon) and differ from that
reference (not the "missing glyph" box).
"""
import io

import numpy as np
import pytest

from assur.cli.main import main
from designer_browser import EXAMPLES, launch, needs_designer_browser

pytestmark = [pytest.mark.slow, needs_designer_browser]


def _pixels(png: bytes) -> np.ndarray:
    import matplotlib.image as mpimg
    return mpimg.imread(io.BytesIO(png), format="png")[..., :3]


def test_every_player_button_shows_an_icon(tmp_path):
    from playwright.sync_api import sync_playwright
    page_file = tmp_path / "anim.html"
    assert main(["animate", str(EXAMPLES / "crank_rocker.toml"), "-o", str(page_file), "--frames", "4"]) == 0
    with sync_playwright() as p:
        browser = launch(p)
        try:
            page = browser.new_page(viewport={"width": 1000, "height": 900})
            page.goto(page_file.as_uri())
            buttons = page.locator("button")
            n = buttons.count()
            assert n >= 8                                  # speed −/+, first, previous, reverse, pause, play, …
            # the reference: a button like the first one, holding a character no font draws
            page.evaluate("""() => {
                const b = document.querySelector('button');
                const ref = b.cloneNode(false);
                ref.id = 'missing-glyph'; ref.removeAttribute('onclick');
                ref.innerHTML = '<span>&#x10FFFD;</span>';
                b.parentNode.appendChild(ref);
            }""")
            reference = _pixels(page.locator("#missing-glyph").screenshot())
            for k in range(n):
                b = buttons.nth(k)
                shot = _pixels(b.screenshot())
                title = b.get_attribute("title") or f"button {k}"
                # the icon: dark pixels inside the button (its border excluded)
                inner = shot[3:-3, 3:-3]
                assert (inner.mean(axis=-1) < 0.45).sum() >= 6, f"{title}: no visible icon"
                if shot.shape == reference.shape:
                    assert not np.allclose(shot, reference, atol=0.02), f"{title}: drawn as a missing glyph"
        finally:
            browser.close()
