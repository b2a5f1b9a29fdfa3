"""``assur report PROBLEM.toml``: the page of a synthesis problem (format assur-synth/1) and its best design.

The problem is run with :func:`assur.synthesis.synthesize` (a fixed seed, so the page is reproducible) and the
page (``out_dir/index.html``, self-contained like the mechanism report) holds the problem (template, variables
with their bounds, targets, objective, constraints), the run (method, evaluations, why it stopped), the best
design's variables, its per-target distances, constraint measures and quantities, the synthesis figure (the task
against the design, the distances, the convergence history), the best design's kinematic figure and, for a
walking leg, its exact gait. The best design is also written beside the page as ``best.toml``.
"""
from __future__ import annotations

from pathlib import Path

from .page import escape, header, page, png_tag, section, table
from .text import format_number


def _unit_of(problem, kind: str) -> str:
    return problem.length_unit if kind == "length" else problem.angle_unit if kind == "angle" else ""


def problem_html(problem) -> str:
    """The problem: template, variables with bounds (file units), targets, objective and constraints."""
    scale = problem.variable_scale()
    rows = [(v.name, v.kind, format_number(v.low * s), format_number(v.high * s), _unit_of(problem, v.kind))
            for v, s in zip(problem.variables, scale)]
    parts = [f"<p>Template: <code>{escape(problem.mechanism_source or problem.plan.mechanism.name)}</code> — units: "
             f"length {escape(problem.length_unit)}, angle {escape(problem.angle_unit)}.</p>",
             table(["variable", "kind", "low", "high", "unit"], rows, num_cols=(2, 3))]
    if problem.parameters:
        expr = [(name, e.source) for name, e in problem.parameters if e.source != name]
        if expr:
            parts.append(table(["mechanism parameter", "expression of the variables (SI)"], expr))
    t = problem.targets
    if t is not None:
        what = {"points": f"positions of point {t.point}", "function": f"input/output angle pairs of link {t.link}"
                f" ({'angle change from the first pair' if t.relative else 'absolute angle'})",
                "poses": f"poses of link {t.link} at point {t.point}"}[t.kind]
        parts.append(f"<p>Targets: {t.n} {escape(what)}; timing {escape(t.timing)}.</p>")
    terms = ", ".join(f"{tm.weight:g}·{tm.quantity}" + ("" if tm.target is None else f" → {tm.target:g}")
                      for tm in problem.terms)
    parts.append(f"<p>Objective: {escape(problem.deviation)} deviation (weight {problem.deviation_weight:g})"
                 + (f" + {escape(terms)}" if terms else "") + ".</p>")
    lims = ", ".join(f"{lim.low if lim.low is not None else '−∞'} ≤ {lim.quantity} ≤ "
                     f"{lim.high if lim.high is not None else '∞'}" for lim in problem.limits)
    parts.append(f"<p>Constraints: {escape(', '.join(problem.constraints))}"
                 + (f"; limits: {escape(lims)}" if lims else "") + ".</p>")
    return "\n".join(parts)


def result_html(result) -> str:
    """The run and the best design: objective, variables, distances, constraint measures and quantities."""
    pb = result.problem
    d = result.details
    status = (f'<span class="ok">feasible</span>, objective {escape(format_number(result.objective))}'
              if result.feasible else
              f'<span class="bad">no feasible design found</span> (least total violation {result.violation:.6g})')
    parts = [f"<p>{status}. {result.evaluations} evaluations in {result.seconds:.2f} s, stopped: "
             f"{escape(result.stopped)} ({escape(result.method)}, {len(result.starts)} start(s), seed "
             f"{escape(result.seed)}).</p>",
             table(["variable", "value", "unit"],
                   [(n, format_number(float(v)), _unit_of(pb, var.kind))
                    for n, v, var in zip(pb.names, result.x_file, pb.variables)], num_cols=(1,))]
    q = d["quantities"]
    if "distances" in q:
        unit = pb.angle_unit if pb.targets.kind == "function" else pb.length_unit
        parts.append(table(["target", f"distance [{unit}]"],
                           [(i + 1, format_number(v)) for i, v in enumerate(q["distances"])], num_cols=(0, 1)))
    rows = [(k, format_number(v)) for k, v in sorted(q.items())
            if k not in ("distances", "offsets") and not isinstance(v, list)]
    rows += [(f"violation: {k}", format_number(v)) for k, v in d["violations"].items() if not isinstance(v, list)]
    parts.append(table(["quantity", "value"], rows, num_cols=(1,)))
    return "\n".join(parts)


def _figures(result, study) -> str:
    from ..plot.draw import close, figure_png
    from ..plot.figures import mechanism_figure
    from ..plot.synthesis import synthesis_figure
    fig = synthesis_figure(result)
    out = [png_tag(figure_png(fig, dpi=80), "targets against the best design, per-target distances, convergence")]
    close(fig)
    plan = result.problem.plan
    if plan.dimension == 2:
        try:
            fig = mechanism_figure(study)
            out.append(png_tag(figure_png(fig, dpi=80), "the best design: paths, kinematic diagram, velocity and "
                                                        "acceleration"))
            close(fig)
        except Exception as exc:   # a design that cannot be drawn over a turn still gets its page  # noqa: BLE001
            out.append(f'<p class="note">no kinematic figure of the best design: {escape(exc)}</p>')
    return "\n".join(out)


def _gait_html(result, study) -> str:
    from ..errors import AssurError
    from ..io.units import LENGTH
    from .text import gait_rows
    try:
        g = study.gait if result.problem.plan.mechanism.gait is not None else None
    except AssurError:
        g = None
    if g is None:
        return ""
    u = result.problem.length_unit
    return table(["quantity", "value", "unit"], gait_rows(g.as_dict(), LENGTH[u], u), num_cols=(1,))


def build_synthesis_page(result, *, source: str = "", best_file: str | None = None) -> str:
    """The synthesis page of a :class:`~assur.synthesis.SynthesisResult` as one HTML string."""
    from ..version import __version__
    pb = result.problem
    title = pb.name or (Path(source).stem if source else "synthesis")
    meta = f"{escape(source)} — synthesis problem (assur-synth/1) — assur {escape(__version__)}"
    body = header(title, meta, pb.description)
    body.append(section("Problem", problem_html(pb)))
    best = result_html(result)
    if best_file:
        best += f'\n<p>The best design as a mechanism file: <a href="{escape(best_file)}">{escape(best_file)}</a>.</p>'
    body.append(section("Best design", best))
    study = result.study()       # the best design's turn: the figure and the gait read one solve
    body.append(section("Figures", _figures(result, study)))
    gait = _gait_html(result, study)
    if gait:
        body.append(section("Gait of the best design (exact)", gait))
    return page(title, body)


def write_synthesis_report(path, out_dir, *, seed: int = 1, budget: int | None = None) -> tuple[Path, object]:
    """Run the problem file ``path`` (``seed``, ``budget``: as ``assur synth``) and write ``out_dir/index.html``
    and ``out_dir/best.toml`` atomically. Returns (the page's path, the SynthesisResult)."""
    from ..io.mechanism_file import dumps
    from ..io.output import atomic_directory
    from ..synthesis import load_problem, synthesize
    problem = load_problem(path)
    result = synthesize(problem, seed=seed, budget=budget)
    with atomic_directory(out_dir) as tmp:
        tmp = Path(tmp)
        (tmp / "best.toml").write_text(dumps(result.mechanism(), clean=True), encoding="utf-8")
        text = build_synthesis_page(result, source=str(path), best_file="best.toml")
        (tmp / "index.html").write_text(text, encoding="utf-8")
    return Path(out_dir) / "index.html", result


__all__ = ["build_synthesis_page", "write_synthesis_report"]
