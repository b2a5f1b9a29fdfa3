"""The report's and ``assur analyze``'s instant centres at chosen inputs, and the report's cam section."""
from __future__ import annotations

import math

import numpy as np

from .page import escape, png_tag, table


def centre_rows(study, q, units: str = "file"):
    """(header, rows) of every relative instant centre at input ``q`` (SI), in the file's length unit (or m)."""
    from .text import length_display
    plan = study.plan
    ic = study.centres_at([q])
    Lf, Lu = length_display(plan.mechanism.units, units)
    rows = []
    pts, dirs = ic.points[0], ic.directions[0]
    from ..analysis.instant_centres import KINDS
    for c, (i, j) in enumerate(ic.pairs):
        z = pts[c]
        how = KINDS[int(ic.kind[0, c])]
        if np.isfinite(z):
            where = (f"{z.real / Lf + 0.0:.6g}", f"{z.imag / Lf + 0.0:.6g}")
        elif np.isfinite(dirs[c]):
            where = ("∞", f"direction {math.degrees(math.atan2(dirs[c].imag, dirs[c].real)) % 180:.4g}°")
        else:
            where = ("—", "undetermined")
        rows.append((f"I{i}{j}" if max(i, j) < 10 else f"I{i},{j}", f"{ic.bodies[i]} – {ic.bodies[j]}", *where, how))
    return ["centre", "bodies", f"x [{Lu}]", f"y [{Lu}]", "from"], rows, float(np.max(ic.kennedy_residual()[0],
                                                                                     initial=0.0))


def input_text(plan, k: int, q: float) -> str:
    from ..io.units import ANGLE, LENGTH
    u = plan.mechanism.units
    if plan.input_kinds[k] == "rotary":
        return f"{plan.input_names[k]} = {q / ANGLE[u.angle]:.6g} {u.angle}"
    return f"{plan.input_names[k]} = {q / LENGTH[u.length]:.6g} {u.length}"


def centres_lines(study, inputs, units: str = "file") -> list[str]:
    """The text of ``assur analyze --at``: a table of the centres at each input."""
    out = []
    for q in inputs:
        head, rows, kennedy = centre_rows(study, q, units)
        out.append(f"Instant centres at {input_text(study.plan, study.moving, q)} "
                   f"({len(rows)} centres of {len(study.plan.body_names)} bodies; Kennedy's residual {kennedy:.1e}):")
        widths = [max(len(str(r[i])) for r in rows + [head]) for i in range(len(head))]
        out.append("  " + "  ".join(h.ljust(w) for h, w in zip(head, widths)))
        out += ["  " + "  ".join(str(c).ljust(w) for c, w in zip(r, widths)) for r in rows]
    return out


def centres_dict(study, inputs) -> list[dict]:
    """The JSON of the centres at ``inputs`` (SI): per input, every pair's centre, direction at infinity and kind."""
    out = []
    for q in inputs:
        ic = study.centres_at([q])
        out.append({"input": float(q), "centres": ic.as_dict()[0],
                    "kennedy_residual": float(np.max(ic.kennedy_residual()[0], initial=0.0))})
    return out


def centres_html(study, inputs, units: str = "file") -> str:
    """The report's section: per input, the figure of every centre with Kennedy's lines and its table."""
    from ..plot.centres import centres_figure
    from ..plot.draw import close, figure_png
    parts = ['<p class="note">Every relative instant centre from the exact velocities (hinges and slides where they '
             "decide it, Kennedy's theorem where the velocities do not); grey: Kennedy's lines, one per triple of "
             "bodies.</p>"]
    for q in inputs:
        head, rows, kennedy = centre_rows(study, q, units)
        parts.append(f"<h3>At {escape(input_text(study.plan, study.moving, q))}</h3>")
        fig = centres_figure(study, q)
        parts.append(png_tag(figure_png(fig, dpi=80), "instant centres and Kennedy's lines"))
        close(fig)
        parts.append(table(head, rows, num_cols=(2, 3)))
        parts.append(f'<p class="note">largest Kennedy residual |det| of a triple: {kennedy:.2e}</p>')
    return "\n".join(parts)
