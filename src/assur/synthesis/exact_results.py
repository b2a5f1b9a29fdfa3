"""The records of exact synthesis (:mod:`assur.synthesis.exact`): one candidate four-bar or slider-crank, and the
ranked list of the kept ones with the rejected ones, the ranking criterion and, for an empty list, the reason.

Every record reads as one line (``repr``) and the list as a small table, so that a result printed in a terminal or
a notebook shows what was found: residual, Grashof class, whether the crank turns fully, the defects.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: Grashof classes whose input link (the crank) turns fully
ROTATABLE = ("crank-rocker", "double-crank")


def _deg(x: float) -> str:
    return "–" if x is None or not math.isfinite(x) else f"{math.degrees(x):.2f}°"


def _num(x: float) -> str:
    return "–" if x is None or not math.isfinite(x) else f"{x:.4g}"


@dataclass(frozen=True)
class ExactSolution:
    """One synthesised four-bar. ``inputs``: the driver's input at each precision point (rad), in the
    order passed; ``residual``: the largest error of the engine's solution at the precision points (rad for
    function generation, length for motion generation); ``transmission``: the worst transmission angle over
    the stretch (rad, folded to [0, π/2]); ``lengths``: (ground, crank, coupler, rocker); ``rank``: its place in
    the ranked list (1 = best; 0 for a rejected candidate); ``defects``: why it was rejected (empty when kept),
    e.g. ``("branch: point 2",)``; ``unit``: the residual's unit."""
    mechanism: object
    inputs: np.ndarray
    residual: float
    transmission: float
    grashof: str
    lengths: tuple[float, float, float, float]
    rank: int = 0
    defects: tuple[str, ...] = ()
    unit: str = "rad"

    @property
    def rotatable(self) -> bool:
        """True when the crank turns fully (a Grashof crank-rocker or double-crank)."""
        return self.grashof in ROTATABLE

    @property
    def kept(self) -> bool:
        return not self.defects

    def __repr__(self) -> str:
        lengths = ", ".join(f"{n} {v:.4g}" for n, v in zip(("ground", "crank", "coupler", "rocker"), self.lengths))
        where = f"#{self.rank}" if self.kept else f"rejected ({'; '.join(self.defects)})"
        return (f"ExactSolution({where}: {self.grashof}, crank {'turns fully' if self.rotatable else 'rocks'}, "
                f"residual {_num(self.residual)} {self.unit}, worst transmission {_deg(self.transmission)}, "
                f"{lengths})")


@dataclass(frozen=True)
class SliderSolution:
    """One synthesised slider-crank. ``inputs``: the crank angles at the precision points (rad, from the slide
    line's direction); ``residual``: the largest error of the engine's slider positions there (length);
    ``transmission``: the worst transmission angle over the stretch (the angle between the rod and the normal
    of the slide line, rad, in [0, π/2]; π/2 when the rod lies along the line); ``kind``: "crank-slider" when
    the crank turns fully (crank + |offset| < rod), else "rocker-slider"; ``crank``, ``rod``, ``offset``: the
    crank A0A and rod AB lengths and the slide line's signed offset from A0 (to the left of its direction);
    ``rank``, ``defects``, ``unit`` as for :class:`ExactSolution`."""
    mechanism: object
    inputs: np.ndarray
    residual: float
    transmission: float
    kind: str
    crank: float
    rod: float
    offset: float
    rank: int = 0
    defects: tuple[str, ...] = ()
    unit: str = "m"

    @property
    def grashof(self) -> str:
        """The slider-crank's class (the column the four-bars' Grashof class fills in a table)."""
        return self.kind

    @property
    def rotatable(self) -> bool:
        return self.kind == "crank-slider"

    @property
    def kept(self) -> bool:
        return not self.defects

    def __repr__(self) -> str:
        where = f"#{self.rank}" if self.kept else f"rejected ({'; '.join(self.defects)})"
        return (f"SliderSolution({where}: {self.kind}, residual {_num(self.residual)} {self.unit}, worst transmission "
                f"{_deg(self.transmission)}, crank {self.crank:.4g}, rod {self.rod:.4g}, offset {self.offset:.4g})")


class Candidates(list):
    """A ranked list of kept candidates (:class:`ExactSolution`, :class:`SliderSolution` or their mechanisms),
    best first, with what was left out.

    ``criterion``: how the list is ranked; ``rejected``: the candidates that were built but miss the task (a
    precision point on the other assembly branch, a pose not reached), with their ``defects``; ``counts``: how
    many candidates each reason removed (the Grashof filter, a toggle inside the stretch, an order defect …);
    ``reason``: why the list is empty (None when it is not)."""

    def __init__(self, kept=(), *, criterion: str = "", rejected=(), counts=None):
        super().__init__(kept)
        self.criterion = criterion
        self.rejected = list(rejected)
        self.counts = dict(counts or {})

    @property
    def reason(self) -> str | None:
        if len(self):
            return None
        if not self.counts:
            return "no candidate: the task has no solution of this kind (the fit is singular)"
        shown = ", ".join(f"{k}: {v}" for k, v in sorted(self.counts.items(), key=lambda kv: -kv[1]))
        return f"no candidate kept ({shown})"

    def with_items(self, items) -> "Candidates":
        """The same ranking and rejections over other items (the kept candidates' mechanisms)."""
        return Candidates(items, criterion=self.criterion, rejected=self.rejected, counts=self.counts)

    def __repr__(self) -> str:
        head = f"Candidates: {len(self)} kept"
        if self.counts:
            head += f", rejected {', '.join(f'{k}: {v}' for k, v in self.counts.items())}"
        lines = [head + (f"; ranked by {self.criterion}" if self.criterion else "")]
        lines += [f"  {item!r}" for item in list(self)[:10]]
        if len(self) > 10:
            lines.append(f"  … {len(self) - 10} more")
        if not len(self):
            lines.append(f"  {self.reason}")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        rows = [(f"#{i + 1}", repr(item)) for i, item in enumerate(list(self)[:20])]
        rows += [("rejected", repr(r)) for r in self.rejected[:10]]
        rows.append(("ranked by", self.criterion or "–"))
        if not len(self):
            rows.append(("reason", self.reason))
        return html_table(f"Exact synthesis: {len(self)} candidate(s)", rows)


@dataclass
class Rejections:
    """Collects the rejected candidates of one synthesis and counts each reason."""
    rejected: list = field(default_factory=list)
    counts: dict = field(default_factory=dict)

    def count(self, reason: str, n: int = 1) -> None:
        if n:
            self.counts[reason] = self.counts.get(reason, 0) + int(n)

    def add(self, solution, reason: str) -> None:
        self.rejected.append(solution)
        self.count(reason)


__all__ = ["Candidates", "ExactSolution", "ROTATABLE", "Rejections", "SliderSolution"]
