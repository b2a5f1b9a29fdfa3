"""Gear pairs of a mechanism: a higher pair (p4) between two links that turn about frame pivots.

A gear pair makes the rotation of link ``b`` a function of the rotation of link ``a``::

    θ_b − θ_b,sketch = mesh · (L(x + phase) − L(phase)),   x = θ_a − θ_a,sketch

with L the pair's law (increasing, L(0) = 0, ``L(x + 2π·n) = L(x) + 2π`` for a pair whose driving gear turns n
times per driven turn), ``mesh`` −1 for an external pair (the gears turn in opposite senses) and +1 for an
internal one, and ``phase`` the driving gear's law angle at the sketch position. Angles are counter-clockwise,
radians.

:class:`GearLaw` holds either a constant ratio (circular gears) or a table of one driving period
(φ_i, θ_i) held as a periodic quintic spline of the excess θ − φ/n, so L, L' and L'' are continuous and a
geared linkage's accelerations are exact derivatives of the law the engine holds.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

TWO_PI = 2.0 * math.pi
#: mesh signs: an external pair reverses the sense of rotation, an internal pair keeps it
MESH_SIGNS = {"external": -1, "internal": 1}


@dataclass(frozen=True)
class GearLaw:
    """The law θ = L(φ) of a gear pair: driven rotation θ of driving rotation φ (rad).

    kind 'ratio': circular gears, L(φ) = φ/ratio (``ratio`` = driving turns per driven turn = z_b/z_a > 0).
    kind 'table': ``phi`` (N,) strictly increasing over one driving period [φ_0, φ_0 + 2π) and ``theta`` (N,) the
    driven rotation there, with θ advancing 2π/``driving_turns`` per driving turn; ``source`` says where it came
    from (a file, an expression) for reports.
    """
    kind: str
    ratio: float = 1.0
    phi: tuple[float, ...] = field(default=(), repr=False)
    theta: tuple[float, ...] = field(default=(), repr=False)
    driving_turns: int = 1
    source: str = ""
    #: the expression θ(phi) the table was sampled from, if any (what a written file repeats)
    expression: str | None = None
    _spline: object = field(default=None, init=False, repr=False, compare=False)

    @property
    def mean_ratio(self) -> float:
        """Driving turns per driven turn (the ratio of a circular pair; n of a non-circular one)."""
        return float(self.ratio) if self.kind == "ratio" else float(self.driving_turns)

    def _excess(self):
        s = self._spline
        if s is None:
            from scipy.interpolate import make_interp_spline
            phi = np.asarray(self.phi, dtype=float)
            theta = np.asarray(self.theta, dtype=float)
            e = theta - phi / self.driving_turns
            x = np.append(phi, phi[0] + TWO_PI)
            y = np.append(e, e[0])
            s0 = make_interp_spline(x, y, k=5, bc_type="periodic")
            s = (s0, s0.derivative(1), s0.derivative(2), float(phi[0]))
            object.__setattr__(self, "_spline", s)
        return s

    def evaluate(self, phi):
        """(L, L', L'') at driving rotations ``phi (...)``, each (...)."""
        phi = np.asarray(phi, dtype=float)
        if self.kind == "ratio":
            r = 1.0 / float(self.ratio)
            return phi * r, np.full(phi.shape, r), np.zeros(phi.shape)
        s0, s1, s2, start = self._excess()
        u = start + np.mod(phi - start, TWO_PI)
        n = self.driving_turns
        return phi / n + s0(u), 1.0 / n + s1(u), s2(u)

    def __reduce__(self):   # the spline cache is rebuilt on the other side of a pickle
        return GearLaw, (self.kind, self.ratio, self.phi, self.theta, self.driving_turns, self.source,
                         self.expression)


@dataclass(frozen=True, slots=True)
class GearPair:
    """A gear pair between the links ``a`` (driving) and ``b`` (driven), each turning about a frame pivot.

    ``law`` maps a's rotation to b's (:class:`GearLaw`); ``mesh`` 'external' (opposite senses) or 'internal';
    ``phase`` (rad) the law's driving angle at the sketch position; ``centre_distance`` (m) the distance of the
    two pivots, ``pressure_angle`` (rad) the teeth's, both used by the force analysis (the tooth force along the
    line of action); ``design`` the gear design file the law came from, if any."""
    name: str
    a: str
    b: str
    law: GearLaw
    mesh: str = "external"
    phase: float = 0.0
    pressure_angle: float = math.radians(20.0)
    design: str | None = None

    @property
    def mesh_sign(self) -> int:
        return MESH_SIGNS[self.mesh]

    def relative(self, x):
        """(y, y', y'') of b's rotation from the sketch for a's rotation ``x (...)`` from the sketch."""
        L, L1, L2 = self.law.evaluate(np.asarray(x, dtype=float) + self.phase)
        L0 = self.law.evaluate(np.asarray(self.phase, dtype=float))[0]
        s = self.mesh_sign
        return s * (L - L0), s * L1, s * L2


def pitch_points(gear: GearPair, pivot_a: complex, pivot_b: complex, samples: int = 720):
    """The two pitch curves of a pair as drawn in the sketch position: points (N,) complex relative to each pivot,
    in the link's sketch orientation. The pitch point P, where the links' velocities agree, lies on the centre
    line at O_a + r_a·e (e = unit(O_b − O_a)), r_a = −y'·d/(1 − y') with y' = dθ_b/dθ_a; with a turned by x it
    touches a's curve at r_a·e·exp(−ix) and b's at (r_a − d)·e·exp(−i·y(x)). a's curve is one turn of a, b's one
    turn of b (n turns of a, or ``ratio`` turns for a circular pair)."""
    d = abs(pivot_b - pivot_a)
    e = (pivot_b - pivot_a) / d
    turns = gear.law.mean_ratio
    x_a = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    x_b = np.linspace(0.0, TWO_PI * turns, max(samples, int(samples * turns)), endpoint=False)
    y1a = gear.relative(x_a)[1]
    y_b, y1b, _ = gear.relative(x_b)
    ra = -y1a * d / (1.0 - y1a)
    rb = -y1b * d / (1.0 - y1b) - d
    return ra * e * np.exp(-1j * x_a), rb * e * np.exp(-1j * y_b)


def gear_ends(mechanism, gear: GearPair) -> tuple[tuple[str, str], tuple[str, str]]:
    """((pivot, arm) of link a, (pivot, arm) of link b): each link's frame pivot and another of its points (its
    turn is the pivot → arm direction's)."""
    frame = set(mechanism.frame.points)
    out = []
    for name in (gear.a, gear.b):
        pts = mechanism.link(name).points
        pivot = next(p for p in pts if p in frame)
        out.append((pivot, next(p for p in pts if p != pivot)))
    return out[0], out[1]
