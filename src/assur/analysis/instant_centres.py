"""Every relative instant centre of a planar mechanism, from the exact velocities, and the instant-centre method.

For two bodies i and j (the frame, links, slider blocks, actuator cylinders and rods) the relative velocity field is
w(X) = w₀ + i·Δω·(X − P_i), with w₀ = v_j(P_i) − v_i(P_i) and Δω = ω_j − ω_i; their instant centre is where it
vanishes, X = P_i + i·w₀/Δω. It is held in homogeneous coordinates (x/L, y/L, w) of unit norm — (P_i·Δω + i·w₀)/L
and Δω — so that a centre at infinity (a relative translation, Δω = 0: the direction i·w₀) is a number like any
other and Kennedy's theorem is a determinant: the three centres of any three bodies are collinear,
det[h_ij, h_jk, h_ik] = 0.

Where the velocities do not decide a centre they are not asked: two bodies hinged at a point have it there (a
permanent centre), two bodies on a slide have it at infinity across the slide. A centre whose relative motion
vanishes at this instant (a rocker at its dead centre, against the frame; two bodies momentarily moving as one)
is undetermined by the velocities: it is found by Kennedy's theorem, the intersection of the lines through the
centres (i, k), (k, j) of two other bodies k.

:func:`velocities_from_centres` is the instant-centre method: from one body's motion and the centres, every body's
angular velocity and every point's velocity (what the engine's jets give exactly; the tests compare).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations

import numpy as np

#: a relative motion counts as none below this fraction of the sample's velocity scale (undetermined centre)
STILL = 1e-12

KINDS = ("pin", "slide", "velocity", "kennedy", "undetermined")


def _normalised(h):
    n = np.linalg.norm(h, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, h / np.where(n > 0, n, 1.0), np.nan)


def _homogeneous(z, w, L):
    """(..., 3) homogeneous coordinates of the points z/w (complex z, real w: w = 0 is the direction z at infinity)."""
    return _normalised(np.stack([np.real(z) / L, np.imag(z) / L, w * np.ones_like(np.real(z))], axis=-1))


@dataclass(frozen=True)
class InstantCentres:
    """The relative instant centres of every pair of bodies over a batch of ``n`` samples.

    ``bodies`` (B,) names; ``pairs`` ((i, j), …) with i < j, the n(n − 1)/2 of them; ``homogeneous`` (n, n_pairs, 3)
    unit homogeneous coordinates (x/L, y/L, w) with L = ``length_scale``; ``kind`` (n, n_pairs) int codes into
    :data:`KINDS` (how each centre was found). NaN rows where a sample is not assembled."""
    bodies: tuple[str, ...]
    pairs: tuple[tuple[int, int], ...]
    homogeneous: np.ndarray
    kind: np.ndarray
    length_scale: float
    _index: dict = field(default_factory=dict, repr=False, compare=False)

    def index(self, a, b) -> tuple[int, bool]:
        """(pair index, swapped) of bodies ``a``, ``b`` (names or indices)."""
        if not self._index:
            self._index.update({p: k for k, p in enumerate(self.pairs)})
        i = self.bodies.index(a) if isinstance(a, str) else int(a)
        j = self.bodies.index(b) if isinstance(b, str) else int(b)
        if i == j:
            raise KeyError(f"a body has no instant centre with itself: {self.bodies[i]!r}")
        return self._index[(min(i, j), max(i, j))], i > j

    @property
    def finite(self) -> np.ndarray:
        """(n, n_pairs) bool: the centre is a point (not at infinity)."""
        return np.abs(self.homogeneous[..., 2]) > 1e-13

    @property
    def points(self) -> np.ndarray:
        """(n, n_pairs) complex: each centre (m); inf + inf·i at infinity, NaN where undetermined."""
        h = self.homogeneous
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (h[..., 0] + 1j * h[..., 1]) * (self.length_scale / h[..., 2])
        return np.where(self.finite, z, np.where(np.isfinite(h[..., 0]), complex(np.inf, np.inf), np.nan))

    @property
    def directions(self) -> np.ndarray:
        """(n, n_pairs) complex unit: the direction of a centre at infinity (NaN for a finite one)."""
        h = self.homogeneous
        d = h[..., 0] + 1j * h[..., 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.finite, np.nan, d / np.abs(d))

    def centre(self, a, b) -> np.ndarray:
        """(n,) complex: the centre of bodies ``a`` and ``b``."""
        return self.points[:, self.index(a, b)[0]]

    def kennedy_residual(self) -> np.ndarray:
        """(n, n_triples) |det[h_ij, h_jk, h_ik]| of every triple of bodies (0: collinear, Kennedy's theorem)."""
        B = len(self.bodies)
        out = []
        for i, j, k in combinations(range(B), 3):
            H = np.stack([self.homogeneous[:, self.index(i, j)[0]], self.homogeneous[:, self.index(j, k)[0]],
                          self.homogeneous[:, self.index(i, k)[0]]], axis=-2)
            out.append(np.abs(np.linalg.det(H)))
        return np.stack(out, axis=-1) if out else np.zeros((len(self.homogeneous), 0))

    def kennedy_lines(self, sample: int) -> list[tuple[tuple[int, int, int], tuple[int, int, int]]]:
        """The triples of centres (pair indices) that Kennedy's theorem puts on one line at ``sample``: for each
        triple of bodies (i, j, k), the pairs (ij, jk, ik)."""
        out = []
        for i, j, k in combinations(range(len(self.bodies)), 3):
            out.append(((i, j, k), (self.index(i, j)[0], self.index(j, k)[0], self.index(i, k)[0])))
        return out

    def as_dict(self, samples=None) -> list[dict]:
        """JSON-ready rows per sample: {pair: [a, b], x, y (m, null at infinity), direction [dx, dy] at infinity,
        kind}."""
        pts, dirs = self.points, self.directions
        idx = range(len(pts)) if samples is None else samples
        out = []
        for s in idx:
            rows = []
            for k, (i, j) in enumerate(self.pairs):
                z, d = pts[s, k], dirs[s, k]
                finite = bool(np.isfinite(z))
                rows.append({"pair": [self.bodies[i], self.bodies[j]],
                             "x": float(z.real) if finite else None, "y": float(z.imag) if finite else None,
                             "direction": None if finite or not np.isfinite(d) else [float(d.real), float(d.imag)],
                             "kind": KINDS[int(self.kind[s, k])]})
            out.append(rows)
        return out


def _body_points(plan) -> list[int]:
    """Per body, the index of one of its points (its first)."""
    g = plan.structure.graph
    return [plan.point_index(b.points[0]) for b in g.bodies]


def _shared_pins(plan) -> dict[tuple[int, int], int]:
    """{(i, j): point index} of every two bodies hinged at a common point."""
    g = plan.structure.graph
    out = {}
    for point, at in g.joints:
        for a, b in combinations(sorted(set(at)), 2):
            out.setdefault((a, b), plan.point_index(point))
    return out


def _slides(plan) -> dict[tuple[int, int], int]:
    """{(i, j): line index} of every two bodies sliding on each other (a prismatic pair or an actuator's slide)."""
    out = {}
    for k, rec in enumerate(plan.lines):
        a, b = sorted((rec[2], rec[3]))
        out[(a, b)] = k
    return out


def _slide_direction(plan, rec, angle, params):
    """(n,) complex unit direction of slide line ``rec`` in the frame: the guide's orientation turned by the line's
    angle parameter (an actuator's slide: along its cylinder)."""
    kind, _, guide, *_ = rec
    theta = angle[:, guide]
    if kind == "actuator":
        return np.exp(1j * theta)
    return np.exp(1j * (theta + params[:, rec[5]]))


def instant_centres(plan, state) -> InstantCentres:
    """All relative instant centres of a planar ``state`` (flattened to its n samples) from its velocities, the
    joints and slides, and Kennedy's theorem for the undetermined ones."""
    n = int(np.prod(state.shape)) if state.shape else 1
    L = plan.length_scale
    z = np.reshape(state.pos, (n, -1, 2))
    v = np.reshape(state.vel, (n, -1, 2))
    z = z[..., 0] + 1j * z[..., 1]
    v = v[..., 0] + 1j * v[..., 1]
    omega = np.reshape(state.body_omega, (n, -1))
    angle = np.reshape(state.body_angle, (n, -1))
    params = np.broadcast_to(np.asarray(state.params, float), tuple(state.shape) + (plan.n_params,)).reshape(n, -1)
    B = plan.n_bodies
    ref = _body_points(plan)
    pins, slides = _shared_pins(plan), _slides(plan)
    pairs = tuple(combinations(range(B), 2))
    H = np.full((n, len(pairs), 3), np.nan)
    kind = np.full((n, len(pairs)), KINDS.index("undetermined"), dtype=np.int8)
    vscale = np.nanmax(np.abs(v), axis=-1) / L + np.nanmax(np.abs(omega), axis=-1)        # (n,) 1/s
    valid = np.reshape(np.asarray(state.valid, bool), (n,))
    with np.errstate(all="ignore"):
        for k, (i, j) in enumerate(pairs):
            if (i, j) in pins:
                H[:, k] = _homogeneous(z[:, pins[(i, j)]], 1.0, L)
                kind[:, k] = KINDS.index("pin")
                continue
            if (i, j) in slides:
                u = _slide_direction(plan, plan.lines[slides[(i, j)]], angle, params)
                H[:, k] = _homogeneous(1j * u * L, 0.0, L)
                kind[:, k] = KINDS.index("slide")
                continue
            Pi, Pj = z[:, ref[i]], z[:, ref[j]]
            w0 = v[:, ref[j]] + 1j * omega[:, j] * (Pi - Pj) - v[:, ref[i]]
            dw = omega[:, j] - omega[:, i]
            h = np.stack([np.real(Pi * dw + 1j * w0) / L, np.imag(Pi * dw + 1j * w0) / L, dw], axis=-1)
            moving = np.abs(w0) / L + np.abs(dw) > STILL * vscale
            H[:, k] = np.where(moving[:, None], _normalised(h), np.nan)
            kind[:, k] = np.where(moving, KINDS.index("velocity"), KINDS.index("undetermined"))
    ic = InstantCentres(tuple(plan.body_names), pairs, H, kind, L)
    _kennedy_fill(ic)
    H[~valid] = np.nan
    return ic


def _kennedy_fill(ic: InstantCentres) -> None:
    """Fill each undetermined centre (i, j) with the intersection of the Kennedy lines through the centres
    (i, k), (k, j) of two third bodies (in place); repeated while it finds new ones."""
    B = len(ic.bodies)
    H, kind = ic.homogeneous, ic.kind
    und = KINDS.index("undetermined")
    for _ in range(B):
        todo = np.argwhere(kind == und)
        if not len(todo):
            return
        found = False
        for s, k in todo:
            i, j = ic.pairs[k]
            lines = []
            for m in range(B):
                if m in (i, j):
                    continue
                a, b = H[s, ic.index(i, m)[0]], H[s, ic.index(m, j)[0]]
                if kind[s, ic.index(i, m)[0]] == und or kind[s, ic.index(m, j)[0]] == und:
                    continue
                line = np.cross(a, b)
                if np.linalg.norm(line) > 1e-9:
                    lines.append(line / np.linalg.norm(line))
            best = None
            for la, lb in combinations(lines, 2):
                p = np.cross(la, lb)
                if np.linalg.norm(p) > 1e-6 and (best is None or np.linalg.norm(p) > np.linalg.norm(best)):
                    best = p
            if best is not None:
                H[s, k] = best / np.linalg.norm(best)
                kind[s, k] = KINDS.index("kennedy")
                found = True
        if not found:
            return


def velocities_from_centres(ic: InstantCentres, sample: int, reference: int, omega_ref: float, point_ref: complex,
                            velocity_ref: complex, frame: int = 0):
    """The instant-centre method at one ``sample``: from the ``reference`` body's motion (its angular velocity and one
    point's velocity) and the centres, every body's angular velocity ω (B,) and a function X, body → the velocity of
    the body's point at X (complex). Bodies are reached from the reference through finite relative centres."""
    B = len(ic.bodies)
    pts = ic.points[sample]
    omega = {reference: float(omega_ref)}
    field_of = {reference: (complex(point_ref), complex(velocity_ref))}    # (a point, its velocity) of each body

    def vel(b, X):
        P, vP = field_of[b]
        return vP + 1j * omega[b] * (X - P)

    changed = True
    while changed and len(omega) < B:
        changed = False
        for j in range(B):
            if j in omega:
                continue
            for r in list(omega):
                rj = pts[ic.index(r, j)[0]]
                if not np.isfinite(rj):
                    continue
                vX = vel(r, rj)                                   # the common point's velocity, on r and on j
                jf = pts[ic.index(j, frame)[0]] if j != frame else None
                if j == frame:
                    omega[j], field_of[j] = 0.0, (rj, 0j)
                elif jf is not None and np.isfinite(jf):
                    d = rj - jf
                    if abs(d) <= 1e-12 * ic.length_scale:
                        continue
                    omega[j] = float(np.real(vX / (1j * d)))
                    field_of[j] = (rj, vX)
                else:                                              # j translates against the frame
                    omega[j], field_of[j] = 0.0, (rj, vX)
                changed = True
                break
    return np.array([omega.get(b, np.nan) for b in range(B)]), (lambda X, b: vel(b, X) if b in omega else np.nan)
