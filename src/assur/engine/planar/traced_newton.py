"""Newton-solved groups traced for the compiled kernels: the numpy backend's own loop equations, run on symbols.

A group without a closed form (a class-III triad, a larger group) is solved by :func:`.newton_group.solve_group`:
Newton's method on the loop equations of :func:`.newton_group._residual`, the branch certified by the sign and size
of the equilibrated Jacobian determinant, velocities and accelerations by implicit differentiation. This module runs
the same ``_residual`` on symbols (:mod:`assur.kernels.trace`) and gives the kernel generator
(:func:`assur.kernels.codegen.newton_source`) the pieces of one Newton solve:

* the iterated unknowns ``x{g}_{i}`` (the poses x, y, θ of the group's kept bodies, :func:`.newton_group.reduction`:
  a triad's ternary) are free names of one more level, :data:`ITER`, so that every line that reads them runs inside
  the iteration loop while the design's geometry and the input's terms stay outside it; they start at the
  prediction ``pr{g}_{k}`` of their place k among the group's poses (``TracedGroup.start``);
* the residual F(x), its Jacobian by forward-mode jets (one direction per unknown, as the numpy code builds it) and
  the Newton step −J⁻¹F by the element-wise elimination of :mod:`assur.kernels.dense` (its pivots on the ±1 of the
  bodies' x and y cost nothing; the angles' columns are pivoted per sample);
* at the iteration's result (the same lines, run once more at the polished iterate: the kernel's last evaluation):
  the full poses (:func:`.newton_group.expand`: the left-out links from their ends) and the full equations'
  Jacobian and factorisation there, the acceptance test, the branch certificate (:func:`certificate`, the numpy backend's ``_equilibrated_det``)
  against the sign ``sg{g}`` the kernel found at the seed, and the flag ``ok``;
* the solved poses (NaN where not ``ok``) and their derivatives by the input: the residual's jets at the solution give
  the implicit-differentiation right-hand sides, solved with the same factorisation; the group's bodies are placed on
  the context as jets, so the steps after it read them as they read any other.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kernels import dense
from ...kernels.jet import Jet, expi
from ...kernels.trace import ITER, SAMPLE, isfinite, maximum, where
from .newton_group import _residual, expand, reduction

__all__ = ["TracedGroup", "certificate", "trace_group"]


@dataclass
class TracedGroup:
    """One Newton-solved group of a traced plan (names as in the module's docstring): the iterated unknowns ``x``
    (free names of the level ``bit``; the kept bodies' poses), the residual ``F`` there and its flags ``converged``
    (every |F| below the kernel's ``rtol``) and ``finite``, the iterate after one Newton step ``update`` (x − J⁻¹F);
    at x as the result, on the full poses it gives: their ``certificate`` (the signed equilibrated determinant),
    ``ok`` (the group's inputs assembled, every residual of the iterated and of the full equations below ``atol``,
    the poses finite, the certificate of the seed's sign ``sign`` and above ``certify``) and ``solved`` (the group's
    full poses where ok, else NaN); ``seeds``: the group's first pose's index in the kernel's seed array; ``start``:
    each iterated unknown's place among the group's poses (its prediction's); ``upstream``: whether the group's
    inputs assembled (the steps before it)."""
    x: list
    F: list
    converged: object
    finite: object
    update: list
    certificate: object
    sign: object
    ok: object
    solved: list
    seeds: int
    upstream: object
    bit: int
    start: list
    moved: object = 0.0
    triad: list | None = None


def _residual_and_jacobian(ctx, st, x, red=None):
    """(F, J) of the group's loop equations at the unknowns ``x`` (symbols): F a list of n values, J its n rows, each
    column the residual's derivative along one unknown (a forward-mode jet per direction, as
    :func:`.newton_group._residual_and_jacobian`). ``red``: the reduced equations, ``x`` the kept bodies' poses."""
    n = len(x)
    F, cols = None, []
    for j in range(n):
        X = [Jet(x[i], 1.0 if i == j else 0.0, None) for i in range(n)]
        r = _residual(ctx, st, X, derivs=False, red=red)
        if len(r) != n:
            from ...errors import StructureError
            raise StructureError(f"group of {len(st.bodies)} bodies gave {len(r)} equations, expected {n}")
        if F is None:
            F = [ri.v for ri in r]
        cols.append([ri.d for ri in r])
    return F, [[cols[j][i] for j in range(n)] for i in range(n)]


def body_scales(ctx, st) -> list:
    """Per body of the group its own length scale, element-wise (:func:`.newton_group.body_scales`): the largest
    distance of one of its points from its first in its local frame; a body with one point takes the group's largest,
    and a group without any size the plan's length scale."""
    sizes = []
    for b in st.bodies:
        ws = [ctx.w[(b, p)] for p in ctx.g.bodies[b].points]
        size = 0.0
        for w in ws[1:]:
            size = maximum(size, np.abs(w - ws[0]))
        sizes.append(size)
    largest = 0.0
    for size in sizes:
        largest = maximum(largest, size)
    ls = ctx.plan.length_scale
    largest = where(largest > 0.0, largest, ls)
    return [where(size > 0.0, size, largest) for size in sizes]


def certificate(ctx, st, J, det):
    """The branch certificate of a Newton-solved group from its Jacobian's rows ``J`` and determinant ``det``
    (:func:`.newton_group.certificate_det`): the determinant of J with each body's θ column divided by the body's own
    length scale and then every row scaled to unit length (a zero row left as it is): a pure number, |det| ≤ 1;
    element-wise, det(J)·Π(1/size) / Π‖row‖ of the scaled rows."""
    factors = []
    for s in body_scales(ctx, st):
        factors += [1.0, 1.0, 1.0 / s]
    out = det
    for f in factors:
        out = out * f
    for row in J:
        sq = 0.0
        for v, f in zip(row, factors):
            sq = sq + (v * f) * (v * f)
        norm = np.sqrt(sq)
        out = out / np.where(norm > 0.0, norm, 1.0)
    return out


def _triad_values(ctx, st, x, pred):
    """The values :func:`assur.kernels.reductions.triad_check` reads for a triad of revolutes (the layout of
    :func:`.group_assemblies.triad_layout`), or None for another group."""
    from .group_assemblies import triad_layout
    lay = triad_layout(ctx.plan._plan, st)
    if lay is None:
        return None
    t, legs = lay
    ti = st.bodies.index(t)
    out = []
    for _, p, _ in legs:
        w = ctx.w[(t, p)]
        out += [np.real(w), np.imag(w)]
    for _, _, far in legs:
        z = ctx.pos[far].v
        out += [np.real(z), np.imag(z)]
    out += [np.abs(ctx.w[(leg, far)] - ctx.w[(leg, p)]) for leg, p, far in legs]
    out += list(x[3 * ti:3 * ti + 3]) + list(pred[3 * ti:3 * ti + 3]) + [ctx.plan.length_scale]
    return out


def _all(flags):
    out = True
    for f in flags:
        out = out & f
    return out


def trace_group(ctx, st) -> TracedGroup:
    """Trace one Newton-solved group on the traced context ``ctx`` (:class:`.traced.TracedContext`): the pieces of
    its solve (module docstring) are appended to ``ctx.groups``, its validity to ``ctx.valid`` and its bodies placed
    as jets of the solved poses. The g-th group's unknowns are of the level ``ITER << g`` (one iteration loop per
    group)."""
    tr = ctx.tracer
    g = len(ctx.groups)
    bit = ITER << g
    n = 3 * len(st.bodies)
    rtol, atol, certify = tr.free("rtol"), tr.free("atol"), tr.free("certify")
    upstream = ctx.valid
    pred = [tr.free(f"pr{g}_{i}", SAMPLE) for i in range(n)]
    red = reduction(ctx.g, ctx.plan.lines, st)
    # the iteration's unknowns: the kept bodies' poses (every body's where the group has no rod), from the prediction
    start = list(red.index)
    y = [tr.free(f"x{g}_{i}", SAMPLE | bit) for i in range(len(start))]
    Fy, Jy = _residual_and_jacobian(ctx, st, y, red)
    luy = dense.factor(Jy)
    update = [yi + dy for yi, dy in zip(y, luy.solve([-f for f in Fy]))]
    if red.rods:
        x = expand(ctx, st, red, y, pred)
        F, J = _residual_and_jacobian(ctx, st, x)
        lu = dense.factor(J)
    else:
        x, F, J, lu = y, Fy, Jy, luy
    # the iteration's stop: Σ F² < rtol² (a little stricter than numpy's every |F| < rtol, so at most one more
    # step: the root is the same to round-off) and a finite Σ F² (every F finite), in 25 lines instead of 58
    squares = 0.0
    for f in Fy:
        squares = squares + f * f
    converged = squares < rtol * rtol
    finite = isfinite(squares)
    cert = certificate(ctx, st, J, lu.det)
    sign = tr.free(f"sg{g}", SAMPLE)        # found by the kernel at the seed; never a design-level line
    # accepted: the iterated equations' residuals (numpy's ``newton``) and, with rods, the full equations' too
    accepted = _all(np.abs(f) < atol for f in Fy)
    if red.rods:
        accepted = accepted & _all(np.abs(f) < atol for f in F)
    ok = upstream & accepted & _all(isfinite(v) for v in x) & (cert * sign > 0.0) & (np.abs(cert) > certify)
    solved = [where(ok, v, np.nan) for v in x]
    moved = 0.0
    for i, b in enumerate(st.bodies):
        for p in ctx.g.bodies[b].points:
            w = ctx.w[(b, p)]
            z = (x[3 * i] + x[3 * i + 1] * 1j) + expi(x[3 * i + 2]) * w
            zp = (pred[3 * i] + pred[3 * i + 1] * 1j) + expi(pred[3 * i + 2]) * w
            moved = maximum(moved, np.abs(z - zp)) if not isinstance(moved, float) else np.abs(z - zp)
    seeds = sum(3 * len(grp_st.bodies) for grp_st in ctx.group_steps)
    ctx.group_steps.append(st)
    ctx.groups.append(TracedGroup(y, Fy, converged, finite, update, cert, sign, ok, solved, seeds, upstream, bit,
                                  start, moved, _triad_values(ctx, st, x, pred)))
    ctx.flag(ok)
    # implicit differentiation: F_x·x' = −F', F_x·x'' = −(F'' at x'' = 0), on the solution's factorisation
    order = ctx.order
    X = [Jet(v, 0.0 if order >= 1 else None, 0.0 if order >= 2 else None) for v in solved]
    if order >= 1:
        xd = lu.solve([-ri.d for ri in _residual(ctx, st, X, derivs=True)])
        X = [Jet(v, d, 0.0 if order >= 2 else None) for v, d in zip(solved, xd)]
        if order >= 2:
            xdd = lu.solve([-ri.dd for ri in _residual(ctx, st, X, derivs=True)])
            X = [Jet(v, d, dd) for v, d, dd in zip(solved, xd, xdd)]
    for i, b in enumerate(st.bodies):
        ctx.place(b, X[3 * i] + X[3 * i + 1] * 1j, expi(X[3 * i + 2]))
    return ctx.groups[-1]
