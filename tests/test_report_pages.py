"""The report pages: a table of contents whose every link leads to a section of the page, and paths shown as a
person would write them (the synthesis page once printed ``examples/synthesis/../crank_rocker.toml``)."""
import re
from pathlib import Path

import assur
from assur.report.page import page, section

ROOT = Path(__file__).resolve().parents[1]


def _contents(html: str) -> tuple[list[str], set[str]]:
    nav = re.search(r'<nav class="toc"[^>]*>(.*?)</nav>', html, flags=re.S)
    assert nav, "no table of contents"
    links = re.findall(r'href="#([^"]+)"', nav.group(1))
    ids = set(re.findall(r'<h2 id="([^"]+)"', html))
    return links, ids


def test_a_page_of_three_sections_has_contents_and_unique_anchors():
    html = page("t", ["<h1>t</h1>", section("Forces", "a"), section("Plots", "b"), section("Forces", "c")])
    links, ids = _contents(html)
    assert links == ["forces", "plots", "forces-2"] and set(links) == ids
    assert html.index('<nav class="toc"') < html.index("<h2")
    assert "<nav" not in page("t", ["<h1>t</h1>", section("One", ""), section("Two", "")])


def test_the_mechanism_report_has_a_table_of_contents():
    from assur.report.mechanism import build_report
    plan = assur.compile(assur.load(ROOT / "examples" / "crank_rocker.toml"))
    html = build_report(plan, steps=36, frames=2, source="examples/crank_rocker.toml")
    links, ids = _contents(html)
    assert len(links) >= 4 and set(links) == ids
    for title in ("Structure", "Analysis", "Plots"):
        assert any(title.lower() in link for link in links), title


def test_the_synthesis_page_shows_the_template_path_normalised():
    from assur.report.synthesis import build_synthesis_page
    from assur.synthesis import load_problem, synthesize
    problem = load_problem(ROOT / "examples" / "synthesis" / "function_fourbar.toml")
    assert problem.mechanism_source == str(ROOT / "examples" / "crank_rocker.toml")
    result = synthesize(problem, seed=1, budget=200, polish="none")
    html = build_synthesis_page(result, source="examples/synthesis/function_fourbar.toml")
    assert f"<code>{ROOT / 'examples' / 'crank_rocker.toml'}</code>" in html and "/../" not in html
