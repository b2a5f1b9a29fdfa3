"""The report pages' skeleton and HTML pieces: one style sheet, escaping, tables, sections and inline
PNG figures. Every page is self-contained: nothing refers to an external file or the network.
"""
from __future__ import annotations

import base64
import html
import re

from ..plot.animation import html_page

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 0 auto;
       max-width: 1240px; padding: 1em 2em 3em; color: #222; line-height: 1.45; }
h1 { margin-bottom: 0.1em; } h2 { border-bottom: 1px solid #ccc; margin-top: 1.8em; }
.meta { color: #666; font-size: 0.9em; }
.desc { white-space: pre-wrap; background: #f6f6f3; padding: 0.7em 1em; border-radius: 4px; font-size: 0.92em; }
table { border-collapse: collapse; margin: 0.6em 0 1em; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
th { background: #eef0f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
code, .formula { font-family: ui-monospace, "SFMono-Regular", Menlo, Consolas, monospace; }
.formula { font-size: 1.1em; background: #f3f5fa; padding: 0.3em 0.6em; display: inline-block; border-radius: 3px; }
.ok { color: #1a7f37; font-weight: 600; } .bad { color: #b42318; font-weight: 600; }
img.figure { max-width: 100%; height: auto; border: 1px solid #ddd; }
.note { color: #666; font-style: italic; }
.scroll { overflow-x: auto; }
nav.toc { margin: 1em 0; padding: 0.5em 0.8em; background: #f3f5fa; border-radius: 4px; font-size: 0.92em; }
"""

VIEWPORT = '<meta name="viewport" content="width=device-width, initial-scale=1">\n'


def escape(x) -> str:
    """``x`` as HTML text."""
    return html.escape(str(x))


def table(head, rows, num_cols=()) -> str:
    """An HTML table: the ``head`` cells and ``rows`` (sequences of cells, escaped); the columns ``num_cols``
    are right-aligned numbers."""
    out = ["<table>", "<tr>" + "".join(f"<th>{escape(h)}</th>" for h in head) + "</tr>"]
    for r in rows:
        cells = []
        for i, c in enumerate(r):
            cls = ' class="num"' if i in num_cols else ""
            cells.append(f"<td{cls}>{escape(c)}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</table>")
    return "\n".join(out)


def png_tag(png: bytes, alt: str) -> str:
    """An ``<img>`` with the PNG bytes ``png`` inlined."""
    return (f'<img class="figure" alt="{escape(alt)}" src="data:image/png;base64,'
            f'{base64.b64encode(png).decode("ascii")}">')


def slug(title) -> str:
    """The anchor of a section title: lower case letters, digits and hyphens (``Gait of the leg`` → ``gait-of-the-
    leg``)."""
    text = re.sub(r"[^0-9a-z]+", "-", str(title).lower()).strip("-")
    return text or "section"


def section(title, body) -> str:
    """A titled section of a page (its heading carries the anchor :func:`slug` for the table of contents)."""
    return f'<h2 id="{slug(title)}">{escape(title)}</h2>\n{body}\n'


_HEADING = re.compile(r'<h2 id="([^"]+)">(.*?)</h2>')


def _with_contents(parts: list[str]) -> list[str]:
    """``parts`` with a table of contents before the first section when the page has three sections or more;
    repeated anchors get a number so that every link leads to its own section."""
    found = [(i, m) for i, part in enumerate(parts) for m in [_HEADING.match(part)] if m]
    if len(found) < 3:
        return parts
    parts, seen, links = list(parts), {}, []
    for i, m in found:
        anchor = m.group(1)
        seen[anchor] = seen.get(anchor, 0) + 1
        if seen[anchor] > 1:
            anchor = f"{anchor}-{seen[anchor]}"
            parts[i] = parts[i].replace(f'<h2 id="{m.group(1)}">', f'<h2 id="{anchor}">', 1)
        links.append(f'<a href="#{anchor}">{m.group(2)}</a>')
    nav = '<nav class="toc" aria-label="Contents"><strong>Contents:</strong> ' + " · ".join(links) + "</nav>"
    first = found[0][0]
    return parts[:first] + [nav] + parts[first:]


def header(title: str, meta: str, description: str = "") -> list[str]:
    """The top of a page: the title, the ``meta`` line (HTML) and the description, if any."""
    out = [f"<h1>{escape(title)}</h1>", f'<p class="meta">{meta}</p>']
    if description.strip():
        out.append(f'<div class="desc">{escape(description.strip())}</div>')
    return out


def page(title: str, parts) -> str:
    """A report page: the HTML ``parts`` one per line under the style sheet, titled ``title``; a page of three
    sections or more gets a table of contents under its header."""
    return html_page("\n".join(_with_contents(list(parts))), title, meta=VIEWPORT, style=CSS)
