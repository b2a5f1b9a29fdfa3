"""The page of an exact synthesis (``assur synth PROBLEM --exact --report DIR``): the problem, the method, the ranked
table of the candidates (residual, Grashof class, whether the crank turns fully, the worst transmission angle, the
lengths, the defects) with the rejected ones and the counts of every reason, the figure of the best candidates
and the best one as ``best.toml`` beside the page.
"""
from __future__ import annotations

from pathlib import Path

from .page import escape, header, page, png_tag, section, table
from .synthesis import problem_html


def build_exact_page(problem, task, *, source: str = "", best_file: str | None = None) -> str:
    """The page of ``task`` (:class:`~assur.synthesis.exact_task.ExactTask`) for ``problem`` as one HTML string."""
    from .. import __version__
    from ..plot.draw import close, figure_png
    from ..plot.exact import exact_figure
    from ..synthesis.exact_task import table_rows
    title = f"{problem.name or (Path(source).stem if source else 'synthesis')} — exact synthesis"
    meta = f"{escape(source)} — synthesis problem (assur-synth/1), exact method — assur {escape(__version__)}"
    body = header(title, meta, problem.description)
    body.append(section("Problem", problem_html(problem)))
    c = task.candidates
    head, rows = table_rows(task, rejected=20)
    parts = [f"<p>{escape(task.method)}. Ranked by {escape(c.criterion)}.</p>",
             f'<div class="scroll">{table(head, rows, num_cols=(1, 4))}</div>']
    if c.counts:
        parts.append("<p>Dropped: " + escape(", ".join(f"{k}: {v}" for k, v in c.counts.items())) + ".</p>")
    if not len(c):
        parts.append(f'<p class="bad">{escape(c.reason)}</p>')
    if best_file and len(c):
        parts.append(f'<p>The best candidate as a mechanism file: <a href="{escape(best_file)}">'
                     f'{escape(best_file)}</a>.</p>')
    body.append(section("Candidates", "\n".join(parts)))
    fig = exact_figure(task, problem.targets)
    body.append(section("Figures", png_tag(figure_png(fig, dpi=80), "the best candidates at the task")))
    close(fig)
    return page(title, body)


def write_exact_report(problem, task, out_dir, *, source: str = "") -> Path:
    """Write ``out_dir/index.html`` (and ``out_dir/best.toml`` when a candidate was kept) atomically."""
    from ..io.mechanism_file import dumps
    from ..io.output import atomic_directory
    with atomic_directory(out_dir) as tmp:
        tmp = Path(tmp)
        best = None
        if len(task.candidates):
            (tmp / "best.toml").write_text(dumps(task.candidates[0].mechanism, clean=True), encoding="utf-8")
            best = "best.toml"
        (tmp / "index.html").write_text(build_exact_page(problem, task, source=source, best_file=best),
                                        encoding="utf-8")
    return Path(out_dir) / "index.html"


__all__ = ["build_exact_page", "write_exact_report"]
