"""The four-bar loops of a planar mechanism and their Grashof class.

Every RRR dyad whose two known points A and B lie on two bodies U and V that are hinged to each other at a point C
closes a four-bar loop C–A–J–B (J the dyad's joint): the ground link U (C…A), the input link V (B…C), the coupler
(the dyad's link at B, J…B) and the output link (the dyad's link at A, A…J). Seen from U (the frame when either is
the frame), its lengths g, a, b, c classify it (Grashof 1883; the names of R. L. Norton, *Design of Machinery*,
§2.14, and the codes of C. Barker, "A complete classification of planar four-bar linkages", Mech. Mach. Theory 20
(1985) 535–554). With s and l the shortest and longest link and p, q the other two:

* s + l < p + q, **Grashof**: the shortest link turns fully relative to every other. Shortest the ground:
  double-crank (drag link, GCCC); the input: crank-rocker (GCRR); the coupler: double-rocker (GRCR, the coupler
  turns fully); the output: rocker-crank (GRRC).
* s + l > p + q, **non-Grashof**: no link turns fully; a triple-rocker (RRR1–RRR4 by the longest link: ground,
  input, coupler, output). A crank driving it stops at the toggles.
* s + l = p + q (within :attr:`~assur.tolerances.Tolerances.fourbar_slack` of the longest link), **change point**:
  the links can become collinear, where the loop may switch assemblies.

Lengths come from the design's parameters (the bodies' local geometry), not from a solve.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..engine import geometry
from ..tolerances import DEFAULT as TOL

__all__ = ["FourBarLoop", "four_bar_loops", "grashof_class"]

_ROLES = ("ground", "input", "coupler", "output")
_GRASHOF = {"ground": ("double-crank", "GCCC"), "input": ("crank-rocker", "GCRR"),
            "coupler": ("double-rocker", "GRCR"), "output": ("rocker-crank", "GRRC")}
_NON_GRASHOF = {"ground": "RRR1", "input": "RRR2", "coupler": "RRR3", "output": "RRR4"}


@dataclass(frozen=True)
class FourBarLoop:
    """One four-bar loop: the names of its ``ground``, ``input``, ``coupler`` and ``output`` links, its ``joint``
    (the dyad's joint J), ``lengths`` (g, a, b, c) in m, and its class: ``grashof`` (s + l < p + q),
    ``change_point`` (s + l = p + q), ``kind`` ('crank-rocker', 'double-crank', 'double-rocker', 'rocker-crank' or
    'triple-rocker'), ``barker`` (GCRR, …, RRR1–RRR4; a change point adds its Grashof inversion's code) and
    ``shortest`` (the role of the shortest link)."""
    ground: str
    input: str
    coupler: str
    output: str
    joint: str
    lengths: tuple[float, float, float, float]
    grashof: bool
    change_point: bool
    kind: str
    barker: str
    shortest: str

    @property
    def crank_turns_fully(self) -> bool:
        """Whether the input link turns fully relative to the ground (a Grashof double-crank or crank-rocker)."""
        return self.grashof and self.shortest in ("ground", "input")

    def describe(self) -> str:
        """One line: the class, its inversion and the lengths' condition."""
        g = "Grashof" if self.grashof else "change point" if self.change_point else "non-Grashof"
        return (f"four-bar {self.ground}–{self.input}–{self.coupler}–{self.output}: {g} {self.kind} ({self.barker}; "
                f"shortest: the {self.shortest})")

    def as_dict(self) -> dict:
        d = asdict(self)
        d["lengths"] = dict(zip(_ROLES, self.lengths))
        return d


def grashof_class(lengths) -> tuple[bool, bool, str, str, str]:
    """(grashof, change_point, kind, Barker code, role of the shortest link) of a loop's lengths (g, a, b, c)."""
    lengths = [float(x) for x in lengths]
    s_i = int(np.argmin(lengths))
    l_i = int(np.argmax(lengths))
    s, l_ = lengths[s_i], lengths[l_i]
    p_q = sum(lengths) - s - l_
    slack = (s + l_) - p_q
    tol = TOL.fourbar_slack * l_
    shortest = _ROLES[s_i]
    if abs(slack) <= tol:
        kind, code = _GRASHOF[shortest]
        return False, True, kind, code + " (change point)", shortest
    if slack < 0:
        kind, code = _GRASHOF[shortest]
        return True, False, kind, code, shortest
    return False, False, "triple-rocker", _NON_GRASHOF[_ROLES[l_i]], shortest


def four_bar_loops(plan, params=None) -> list[FourBarLoop]:
    """The four-bar loops of a planar plan at ``params`` (n_params,) (default its defaults), in solve order."""
    if plan.dimension != 2:
        return []
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    w, _ = geometry(plan, params)
    graph = plan.structure.graph
    names = plan.body_names
    out = []
    for st in plan.steps:
        if st.kind != "RRR" or st.side_a.actuator is not None or st.side_b.actuator is not None:
            continue
        A, B, J = st.point_a, st.point_b, st.joint
        U, V = plan.point_body[plan.point_index(A)], plan.point_body[plan.point_index(B)]
        if U == V:
            continue
        common = sorted(set(graph.bodies[U].points) & set(graph.bodies[V].points) - {A, B})
        if not common:
            continue
        C = common[0]
        out_link, cpl = st.side_a.body, st.side_b.body
        if V == 0:      # see the loop from the frame
            U, V, A, B, out_link, cpl = V, U, B, A, cpl, out_link
        d = lambda body, p1, p2: float(np.abs(w[(body, p1)] - w[(body, p2)]))  # noqa: E731
        try:
            lengths = (d(U, C, A), d(V, B, C), d(cpl, J, B), d(out_link, A, J))
        except KeyError:
            continue
        if not all(np.isfinite(lengths)) or min(lengths) <= 0:
            continue
        grashof, change, kind, code, shortest = grashof_class(lengths)
        out.append(FourBarLoop(names[U], names[V], names[cpl], names[out_link], J, lengths, grashof, change, kind,
                               code, shortest))
    return out
