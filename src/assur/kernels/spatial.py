"""Spatial vector kernels of paper 003 (the vector method), array-first on ``(..., 3)`` vectors.

Every function takes plain arrays (batch axes first, coordinates last) or second-order jets
(:class:`~assur.kernels.jet.Jet` whose ``v``, ``d``, ``dd`` are ``(..., 3)`` vectors or ``(...)``
scalars), so closed forms written with them give exact first and second derivatives.

Primitives (paper 003 eqs. (1)–(3), (8), (9), (23), docs/papers/003.md §2):
``ort`` (unit vector), ``proj``, ``norm_part`` (the paper's Norm: the component normal to V0),
``turn`` (Rodrigues' rotation about V0 by a, right-hand rule, rescaled to length r), ``t_x``,
``t_y``, ``t_z`` (active right-hand rotation matrices), ``axis_frame``/``e_z2`` (the rocker-axis
frame T_Y(γ1)·T_X(γ2)), ``tcos`` (the angle between sides l1, l2 of a triangle with third side l3).

The unit-vector solver p(V1, V2, a1, a2, s) (docs/papers/003.md §3.2): the unit vector p with
angle(V1, p) = a1 and angle(V2, p) = a2 on the side ``s = sign det[V1, V2, p]`` of the plane of
V1 and V2. Coordinate-free (a 2×2 Gram system), it never divides by a coordinate, and the branch
sign s is geometric, so it never jumps. :func:`unit_vector_literal` is the paper's program (10)
kept as a reference: it divides by V3_X = (V1 × V2)_X and reports its own singularity.
"""
from __future__ import annotations

import numpy as np

from .jet import Jet, bilinear as _bilinear, parts as _parts, unary as _unary

#: status codes of :func:`unit_vector`; BRANCH_POINT (|disc| within the tolerance: the two branches
#: meet, derivatives are infinite there) is still a valid assembly
OK, UNDETERMINED, CANNOT_ASSEMBLE, BRANCH_POINT = 0, 1, 2, 3
STATUS_TEXT = {OK: "ok", UNDETERMINED: "undetermined (V1 ∥ V2)", CANNOT_ASSEMBLE: "cannot assemble (disc < 0)",
               BRANCH_POINT: "branch point (disc = 0)"}


def assembled(status):
    """(...) bool: the solver found p (OK or at a branch point)."""
    status = np.asarray(status)
    return (status == OK) | (status == BRANCH_POINT)


def value(x):
    return x.v if isinstance(x, Jet) else np.asarray(x)


def _cross(a, b):
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def dot(a, b):
    """a · b over the last axis: (..., 3), (..., 3) → (...)."""
    return _bilinear(lambda p, q: np.sum(p * q, axis=-1), a, b)


def cross(a, b):
    """a × b: (..., 3), (..., 3) → (..., 3)."""
    return _bilinear(_cross, a, b)


def scale(s, v):
    """s·V: scalar (...) times vector (..., 3)."""
    return _bilinear(lambda p, q: np.asarray(p)[..., None] * q, s, v)


def sqrt(x):
    return _unary(x, np.sqrt, lambda v: 0.5 / np.sqrt(v), lambda v: -0.25 / (v * np.sqrt(v)))


def cos(x):
    return _unary(x, np.cos, lambda v: -np.sin(v), lambda v: -np.cos(v))


def sin(x):
    return _unary(x, np.sin, np.cos, lambda v: -np.sin(v))


def reciprocal(x):
    return _unary(x, lambda v: 1.0 / v, lambda v: -1.0 / (v * v), lambda v: 2.0 / (v * v * v))


def arccos(x):
    return _unary(x, np.arccos, lambda v: -1.0 / np.sqrt(1.0 - v * v),
                  lambda v: -v / (1.0 - v * v) ** 1.5)


def atan2(y, x):
    """atan2 of two scalar jets: θ' = (x y' − y x')/r², θ'' by differentiating once more."""
    if not isinstance(y, Jet) and not isinstance(x, Jet):
        return np.arctan2(y, x)
    yv, yd, ydd = _parts(y)
    xv, xd, xdd = _parts(x)
    v = np.arctan2(yv, xv)
    if yd is None and xd is None:
        return Jet(v)
    yd = np.zeros_like(yv) if yd is None else yd
    xd = np.zeros_like(xv) if xd is None else xd
    r2 = xv * xv + yv * yv
    num = xv * yd - yv * xd
    d = num / r2
    dd = None
    if ydd is not None or xdd is not None:
        ydd = np.zeros_like(yv) if ydd is None else ydd
        xdd = np.zeros_like(xv) if xdd is None else xdd
        dnum = xv * ydd - yv * xdd
        dr2 = 2.0 * (xv * xd + yv * yd)
        dd = (dnum * r2 - num * dr2) / (r2 * r2)
    return Jet(v, d, dd)


def length(v):
    """|V|: (..., 3) → (...)."""
    return sqrt(dot(v, v))


# -- the paper's primitives, eqs. (1)–(3) -----------------------------------------------------------
def ort(v):
    """(1) Ort(V) = V/|V|: (..., 3) → (..., 3)."""
    return scale(reciprocal(length(v)), v)


def proj(v, v0):
    """(1) Proj(V, V0) = (V·Ort(V0))·Ort(V0), the component of V along V0."""
    e = ort(v0)
    return scale(dot(v, e), e)


def norm_part(v, v0):
    """(2) the paper's Norm(V, V0) = V − Proj(V, V0), the component of V normal to V0."""
    return v - proj(v, v0)


def turn(v, v0, a, r):
    """(3) Turn(V, V0, a, r): V rotated about V0 by the angle a (right-hand rule, counter-clockwise
    seen from the tip of V0), rescaled to length r. v, v0 (..., 3); a, r (...) → (..., 3)."""
    e = ort(v0)
    p = scale(dot(v, e), e)
    n = v - p
    rotated = p + scale(cos(a), n) + scale(sin(a), cross(e, n))
    return scale(r * reciprocal(length(v)), rotated)


def rodrigues(v, axis, a):
    """V rotated about the unit vector ``axis`` by a (right-hand rule), length kept:
    V cos a + (k × V) sin a + k (k·V)(1 − cos a)."""
    c, s = cos(a), sin(a)
    return scale(c, v) + scale(s, cross(axis, v)) + scale((1.0 - c) * dot(axis, v), axis)


def t_x(f):
    """(9) active right-hand rotation about X: (...) → (..., 3, 3)."""
    f = np.asarray(f, dtype=float)
    c, s, o, z = np.cos(f), np.sin(f), np.ones_like(f), np.zeros_like(f)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2)


def t_y(f):
    """(9) active right-hand rotation about Y: (...) → (..., 3, 3)."""
    f = np.asarray(f, dtype=float)
    c, s, o, z = np.cos(f), np.sin(f), np.ones_like(f), np.zeros_like(f)
    return np.stack([np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1)], -2)


def t_z(f):
    """(9) active right-hand rotation about Z: (...) → (..., 3, 3)."""
    f = np.asarray(f, dtype=float)
    c, s, o, z = np.cos(f), np.sin(f), np.ones_like(f), np.zeros_like(f)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)


def axis_frame(gamma1, gamma2):
    """(8) the rocker-axis frame T_Y(γ1)·T_X(γ2): (...) → (..., 3, 3), columns e_X2, e_Y2, e_Z2."""
    return t_y(gamma1) @ t_x(gamma2)


def e_z2(gamma1, gamma2):
    """(8) e_Z2 = (sin γ1 cos γ2, −sin γ2, cos γ1 cos γ2): (...) → (..., 3)."""
    g1, g2 = np.asarray(gamma1, dtype=float), np.asarray(gamma2, dtype=float)
    return np.stack([np.sin(g1) * np.cos(g2), -np.sin(g2), np.cos(g1) * np.cos(g2)], axis=-1)


def axis_angles(axis):
    """(γ1, γ2) of a unit axis: the inverse of :func:`e_z2` (γ1 = 0 for an axis along ±Y)."""
    axis = np.asarray(axis, dtype=float)
    g2 = -np.arcsin(np.clip(axis[..., 1], -1.0, 1.0))
    g1 = np.arctan2(axis[..., 0], axis[..., 2])
    g1 = np.where(np.hypot(axis[..., 0], axis[..., 2]) < 1e-15, 0.0, g1)
    return g1, g2


def tcos(l1, l2, l3):
    """(23) the angle between sides l1 and l2 of a triangle whose third side is l3
    (NaN when no such triangle exists)."""
    c = (l1 * l1 + l2 * l2 - l3 * l3) * reciprocal(2.0 * l1 * l2)
    cv = value(c)
    ok = np.abs(cv) <= 1.0
    if isinstance(c, Jet):
        c = Jet(np.where(ok, cv, np.nan), c.d, c.dd)
    else:
        c = np.where(ok, cv, np.nan)
    return arccos(c)


# -- the unit-vector solver --------------------------------------------------------------------------
def unit_vector(v1, v2, cos_a1, cos_a2, s, *, parallel_tol: float = 1e-12, disc_tol: float = 1e-12):
    """The robust p-solver of docs/papers/003.md §3.2, on cosines: the unit p with V1·p = |V1| cos a1 and
    V2·p = |V2| cos a2 on the side s = sign det[V1, V2, p] (±1, scalar or (...)).

    v1, v2: (..., 3) arrays or jets; cos_a1, cos_a2: (...) arrays or jets.
    Returns ``(p, status)``: p (..., 3) (NaN where not :func:`assembled`), status (...) int:
    OK, UNDETERMINED (|V1 × V2| ≤ parallel_tol·|V1||V2|), CANNOT_ASSEMBLE
    (1 − |q|² < −disc_tol) or BRANCH_POINT (|1 − |q|²| ≤ disc_tol, clamped to 0: p lies in the plane
    of V1 and V2, valid, but the two branches meet there).
    """
    n = cross(v1, v2)
    a, b, c = dot(v1, v1), dot(v1, v2), dot(v2, v2)
    det = dot(n, n)                      # = a·c − b², the Gram determinant
    r1 = sqrt(a) * cos_a1
    r2 = sqrt(c) * cos_a2
    with np.errstate(all="ignore"):
        undetermined = ~(np.sqrt(value(det)) > parallel_tol * np.sqrt(value(a) * value(c)))
        inv = reciprocal(det)
        x = (c * r1 - b * r2) * inv
        y = (a * r2 - b * r1) * inv
        q = scale(x, v1) + scale(y, v2)
        disc = 1.0 - dot(q, q)
        dv = value(disc)
        cannot = dv < -disc_tol
        clamped = np.where(cannot | undetermined, np.nan, np.maximum(dv, 0.0))
        disc = Jet(clamped, disc.d, disc.dd) if isinstance(disc, Jet) else clamped
        z = np.asarray(s, dtype=float) * sqrt(disc) * reciprocal(sqrt(det))
        p = q + scale(z, n)
    status = np.where(undetermined, UNDETERMINED, np.where(cannot, CANNOT_ASSEMBLE,
                                                           np.where(np.abs(dv) <= disc_tol, BRANCH_POINT, OK)))
    return _nan_where(p, ~assembled(status)), status


def unit_vector_angles(v1, v2, a1, a2, s, **tol):
    """p(V1, V2, a1, a2, s) of the paper with angles a1, a2 (rad); see :func:`unit_vector`."""
    return unit_vector(v1, v2, cos(a1), cos(a2), s, **tol)


def _nan_where(x, bad):
    bad = np.asarray(bad)
    if not bad.any():
        return x
    m = bad[..., None]
    if isinstance(x, Jet):
        return Jet(np.where(m, np.nan, x.v), None if x.d is None else np.where(m, np.nan, x.d),
                   None if x.dd is None else np.where(m, np.nan, x.dd))
    return np.where(m, np.nan, x)


def branch_sign(v1, v2, p):
    """s = sign det[V1, V2, p] = sign(p·(V1 × V2)) (...); 0 on the plane of V1 and V2."""
    return np.sign(np.sum(np.asarray(p) * _cross(np.asarray(v1), np.asarray(v2)), axis=-1))


def paper_w(v1, v2, s):
    """The paper's W of eq. (21) for the branch s: W = s·sign(V3_X), V3 = V1 × V2 (NaN where V3_X is
    zero to round-off, |V3_X| ≤ 1e-12·|V3|: W is undefined there)."""
    v3 = _cross(np.asarray(v1, dtype=float), np.asarray(v2, dtype=float))
    regular = np.abs(v3[..., 0]) > 1e-12 * np.linalg.norm(v3, axis=-1)
    return np.where(regular, np.asarray(s) * np.sign(v3[..., 0]), np.nan)


def unit_vector_literal(v1, v2, a1, a2, w, *, singular_tol: float = 1e-3):
    """The paper's closed form, program (10) with eqs. (15)–(21), kept as a reference.

    It eliminates p_Y and p_Z by Cramer's rule with determinant V3_X and so divides by V3_X.
    Returns ``(p, singular)``: p (..., 3) — NaN where the form is singular
    (|V3_X| < singular_tol·|V3|, its error grows like 1/V3_X²) or its discriminant is negative —
    and ``singular`` (...) bool. ``w`` = ±1 picks the root of (21), as in the paper.
    """
    v1, v2 = np.asarray(v1, dtype=float), np.asarray(v2, dtype=float)
    v3 = _cross(v1, v2)                                                         # line 1, (15)
    proj1 = np.linalg.norm(v1, axis=-1) * np.cos(a1)                           # line 2, (11)
    proj2 = np.linalg.norm(v2, axis=-1) * np.cos(a2)                           # line 3, (12)
    b1 = v2[..., 2] * proj1 - v1[..., 2] * proj2                               # line 4
    b2 = v1[..., 1] * proj2 - v2[..., 1] * proj1                               # line 5
    n3 = np.sum(v3 * v3, axis=-1)
    h = v3[..., 1] * b1 + v3[..., 2] * b2
    with np.errstate(all="ignore"):
        disc = h * h - n3 * (b1 * b1 + b2 * b2 - v3[..., 0] ** 2)
        px = (-h + np.asarray(w) * np.sqrt(disc)) / n3                        # line 6, (21)
        py = (px * v3[..., 1] + b1) / v3[..., 0]                               # line 7, (16)
        pz = (px * v3[..., 2] + b2) / v3[..., 0]                               # line 8, (17)
    singular = ~(np.abs(v3[..., 0]) >= singular_tol * np.sqrt(n3))
    p = np.stack([px, py, pz], axis=-1)
    return np.where((singular | ~(disc >= 0))[..., None], np.nan, p), singular


def newton_rss(a, d, e, rocker_length, axial, coupler_length, x0, *, tol: float = 1e-12, iterations: int = 30):
    """Batched Newton solve of an R–S–S dyad's loop closure for the rocker point x:
    (x − D)·e = h, |x − D|² = l_r², |x − A|² = l_c² (the test oracle of the closed form).

    a, d, e, x0: (..., 3); rocker_length, axial, coupler_length: (...). Returns ``(x, converged)``:
    the root reached from x0 (the branch connected to the seed) and (...) bool (every residual, in metres, ≤ tol).
    """
    x = np.array(x0, dtype=float)
    lr, lc = np.asarray(rocker_length, dtype=float), np.asarray(coupler_length, dtype=float)
    lr2, lc2 = lr ** 2, lc ** 2
    ok = np.zeros(x.shape[:-1], dtype=bool)
    with np.errstate(all="ignore"):
        for _ in range(iterations):
            r = x - d
            c = x - a
            # each equation in metres (the two distances' squares divided by their lengths), so that one
            # length tolerance holds at any size
            F = np.stack([np.sum(r * e, -1) - axial, 0.5 * (np.sum(r * r, -1) - lr2) / lr,
                          0.5 * (np.sum(c * c, -1) - lc2) / lc], axis=-1)
            done = ok
            ok = np.max(np.abs(F), axis=-1) <= tol
            if (ok & done).all():   # converged, and polished by one more step
                break
            J = np.stack([np.broadcast_to(e, r.shape), r / lr[..., None], c / lc[..., None]], axis=-2)
            bad = ~np.isfinite(np.linalg.cond(J))
            J = np.where(bad[..., None, None], np.eye(3), J)
            step = np.linalg.solve(J, F[..., None])[..., 0]
            x = np.where((ok & done)[..., None], x, x - np.where(bad[..., None], np.nan, step))
    return x, ok & np.all(np.isfinite(x), axis=-1)
