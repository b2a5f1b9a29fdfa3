"""Execute a solve plan on batches: positions, velocities and accelerations of every point.

``solve(plan, params, inputs)`` broadcasts ``params (..., n_params)`` against
``inputs (..., n_inputs)`` (leading axes), so one call covers designs × angles × legs. Each Assur
group is solved by its closed form on second-order jets (:mod:`assur.kernels.jet`), which gives
the papers' analogues d/dq and d²/dq² exactly; time derivatives follow from the driver speeds.
Groups without a closed form (triads) go to the batched Newton solver, which is also the test
oracle of the closed forms (``method="newton"``).
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from .compile import geometry
from .errors import SpecError, UnbuildableError, UnbuildableWarning
from .kernels import planar
from .kernels.jet import Jet, expi
from .plan import SolvePlan, Step
from .state import State
from .tolerances import DEFAULT

ON_UNBUILDABLE = ("nan", "warn", "raise")


class _Context:
    def __init__(self, plan, params, q_jets, order, tol):
        self.plan, self.order, self.tol = plan, order, tol
        self.w, self.lines = geometry(plan, params)
        self.params = params
        self.q = q_jets
        self.pose: dict[int, tuple[Jet, Jet]] = {}
        self.pos: dict[str, Jet] = {}
        self.valid = np.True_
        self.g = plan.structure.graph

    def const(self, v):
        return Jet.const(v, self.order)

    def place(self, body, o, e):
        self.pose[body] = (o, e)
        for p in self.g.bodies[body].points:
            if p not in self.pos:
                self.pos[p] = o + e * self.w[(body, p)]

    def from_two(self, body, p1, p2):
        """Pose of a body from the world positions of two of its points."""
        w1, w2 = self.w[(body, p1)], self.w[(body, p2)]
        e = (self.pos[p2] - self.pos[p1]) * (1.0 / (w2 - w1))
        self.place(body, self.pos[p1] - e * w1, e)

    def radius(self, side, a, j):
        if side.actuator is not None:
            return self.q[side.actuator[2]]
        return np.abs(self.w[(side.body, j)] - self.w[(side.body, a)])

    def place_side(self, side, a, j):
        if side.actuator is None:
            self.from_two(side.body, a, j)
            return
        cyl, rod, k = side.actuator
        e = (self.pos[j] - self.pos[a]) / self.q[k]
        self.place(cyl, self.pos[a], e)
        self.place(rod, self.pos[j], e)

    def world_line(self, idx):
        """World line of slide idx, and the slider's orientation: (Q, U, e_slider, ref, u_slider)."""
        rec = self.plan.lines[idx]
        q, u, ref, us = self.lines[idx]
        og, eg = self.pose[rec[2]]
        return og + eg * q, eg * u, eg * (u / us), ref, us

    def flag(self, valid):
        self.valid = self.valid & valid


def _frame(c: _Context, st: Step):
    c.place(0, c.const(0j), c.const(1 + 0j))
    for p in c.g.bodies[0].points:
        c.pos[p] = c.const(c.w[(0, p)])


def _crank(c: _Context, st: Step):
    pivot, arm, k, izero, sense = st.data
    body = st.bodies[0]
    d = c.w[(body, arm)] - c.w[(body, pivot)]
    theta = c.q[k] * float(sense) + c.params[..., izero]
    e = expi(theta) * np.conj(d / np.abs(d))
    c.place(body, c.pos[pivot] - e * c.w[(body, pivot)], e)


def _rrr(c: _Context, st: Step):
    sa, A, sb, B, J = st.data
    z, ok = planar.circle_circle(c.pos[A], c.radius(sa, A, J), c.pos[B], c.radius(sb, B, J), st.branch, c.tol.radicand)
    c.flag(ok)
    c.pos[J] = z
    c.place_side(sa, A, J)
    c.place_side(sb, B, J)


def _rrp(c: _Context, st: Step):
    sa, A, slider, line, J = st.data
    Q, U, es, ref, _ = c.world_line(line)
    Qj = Q + es * (c.w[(slider, J)] - ref)
    z, ok = planar.circle_line(c.pos[A], c.radius(sa, A, J), Qj, U, st.branch, c.tol.radicand)
    c.flag(ok)
    c.pos[J] = z
    c.place_side(sa, A, J)
    c.place(slider, z - es * c.w[(slider, J)], es)


def _rpr(c: _Context, st: Step):
    guide, gp, slider, sp, line = st.data
    q, u, ref, us = c.lines[line]
    cvec = (q - c.w[(guide, gp)]) + (u / us) * (c.w[(slider, sp)] - ref)
    cc = cvec / u
    eu, ok = planar.rotation_from_slide(c.pos[sp] - c.pos[gp], np.real(cc), np.imag(cc), st.branch, c.tol.radicand)
    c.flag(ok)
    eg = eu * (1.0 / u)
    c.place(guide, c.pos[gp] - eg * c.w[(guide, gp)], eg)
    es = eu * (1.0 / us)
    c.place(slider, c.pos[sp] - es * c.w[(slider, sp)], es)


def _prp(c: _Context, st: Step):
    a, la, b, lb, J = st.data
    Qa, Ua, ea, refa, _ = c.world_line(la)
    Qb, Ub, eb, refb, _ = c.world_line(lb)
    z, ok = planar.line_line(Qa + ea * (c.w[(a, J)] - refa), Ua, Qb + eb * (c.w[(b, J)] - refb), Ub, c.tol.parallel)
    c.flag(ok)
    c.pos[J] = z
    c.place(a, z - ea * c.w[(a, J)], ea)
    c.place(b, z - eb * c.w[(b, J)], eb)


def _ppr(c: _Context, st: Step):
    a, A, b, lo, li = st.data
    Qo, Uo, eb, refo, _ = c.world_line(lo)
    rec_i = c.plan.lines[li]
    qi, ui, refi, usi = c.lines[li]
    if rec_i[2] == b:        # b guides a: e_a = e_b·u/u_s
        ea = eb * (ui / usi)
    else:                    # a guides b: e_b = e_a·u/u_s
        ea = eb * (usi / ui)
    oa = c.pos[A] - ea * c.w[(a, A)]
    c.place(a, oa, ea)
    if rec_i[2] == b:
        Q2, U2 = oa + ea * refi - eb * qi, eb * ui
    else:
        Q2, U2 = oa + ea * qi - eb * refi, ea * ui
    ob, ok = planar.line_line(Qo - eb * refo, Uo, Q2, U2, c.tol.parallel)
    c.flag(ok)
    c.place(b, ob, eb)


def _newton(c: _Context, st: Step):
    from .kernels.newton import solve_group
    solve_group(c, st)


_EXEC = {"frame": _frame, "crank": _crank, "RRR": _rrr, "RRP": _rrp, "RPR": _rpr, "PRP": _prp, "PPR": _ppr,
         "newton": _newton}




def _run(plan, steps, params, q_jets, order, tol, method, warm):
    c = _Context(plan, params, q_jets, order, tol)
    c.warm = warm
    with np.errstate(all="ignore"):
        for st in steps:
            kind = st.kind
            if method == "newton" and kind in ("RRR", "RRP", "RPR", "PRP", "PPR"):
                kind = "newton"
            _EXEC[kind](c, st)
    return c


def _execute(plan, steps, params, q_jets, order, tol, method="closed"):
    """Run the steps. With Newton groups, continue every sample from the sketch inputs to its own
    inputs in stages (≤ 10° of crank, ≤ 5 % of the length scale of stroke), warm-starting each stage."""
    uses_newton = method == "newton" or any(st.kind == "newton" for st in steps)
    warm: dict = {}
    if uses_newton and len(q_jets):
        q_s = plan.sketch_inputs
        deltas, stage = [], []
        for k, qj in enumerate(q_jets):
            v = np.asarray(qj.v, dtype=float)
            if plan.input_kinds[k] == "rotary":
                d = (v - q_s[k] + np.pi) % (2 * np.pi) - np.pi
                stage.append(tol.stage_angle)
            else:
                d = v - q_s[k]
                stage.append(tol.stage_length * plan.length_scale)
            deltas.append(d)
        finite = [np.abs(d[np.isfinite(d)]) for d in deltas]
        m = max([int(np.ceil(f.max() / s)) if f.size else 1 for f, s in zip(finite, stage)] + [1])
        # designs other than the file's are reached by continuing in the parameters too
        dp = params - plan.defaults
        moved = bool(np.any(dp != 0))
        if moved:
            m = max(m, tol.stages_for_new_design)
        for i in range(1, m):
            t = i / m
            q_stage = [Jet.const(q_s[k] + t * deltas[k], 0) for k in range(len(q_jets))]
            _run(plan, steps, plan.defaults + t * dp if moved else params, q_stage, 0, tol, method, warm)
    return _run(plan, steps, params, q_jets, order, tol, method, warm)


def run_steps(plan, steps, params, inputs, order=0, upto=None, origins=False):
    """Compile-time helper: after the first ``upto`` steps, (positions by point name, body
    orientations e by body — or (o, e) pairs with ``origins`` —, validity), complex values."""
    q = [Jet.const(np.asarray(inputs[k], dtype=float), order) for k in range(len(inputs))]
    c = _execute(plan, steps[:upto], np.asarray(params, dtype=float), q, order, DEFAULT)
    poses = {b: ((o.v, e.v) if origins else e.v) for b, (o, e) in c.pose.items()}
    return {p: z.v for p, z in c.pos.items()}, poses, c.valid


def _prepare(plan: SolvePlan, params, inputs):
    if params is None:
        params = plan.defaults
    params = np.asarray(params, dtype=float)
    if params.ndim == 0 or params.shape[-1] != plan.n_params:
        raise SpecError([("params", f"must have a trailing axis of {plan.n_params} parameters "
                                    f"({', '.join(plan.param_names)}): shape {params.shape}")])
    if inputs is None:
        inputs = plan.sketch_inputs
    inputs = np.asarray(inputs, dtype=float)
    if plan.n_inputs == 1 and (inputs.ndim <= 1 or inputs.shape[-1] != 1):
        inputs = inputs[..., None]   # one input: a scalar or a 1-D array is a batch of input values
    if inputs.shape[-1] != plan.n_inputs:
        raise SpecError([("inputs", f"must have a trailing axis of {plan.n_inputs} inputs "
                                    f"({', '.join(plan.input_names)}): shape {inputs.shape}")])
    return params, inputs


#: with backend="auto", batches at least this large use the compiled backend when numba is installed
AUTO_COMPILED_MIN_SAMPLES = 20_000


def check_options(on_unbuildable: str, method: str, order: int) -> None:
    """SpecError unless the options of a solve (planar or spatial) are known values."""
    if on_unbuildable not in ON_UNBUILDABLE:
        raise SpecError([("on_unbuildable", f"must be one of {', '.join(ON_UNBUILDABLE)}: {on_unbuildable!r}")])
    if method not in ("closed", "newton"):
        raise SpecError([("method", f"must be 'closed' or 'newton': {method!r}")])
    if order not in (0, 1, 2):
        raise SpecError([("order", f"must be 0, 1 or 2: {order!r}")])


def solve(plan: SolvePlan, params=None, inputs=None, *, speeds=None, accels=None, order: int = 2,
          on_unbuildable: str = "nan", method: str = "closed", backend: str = "auto",
          tolerances=DEFAULT) -> State:
    """Solve positions (and, with ``order`` ≥ 1/2, velocities and accelerations) of every point.

    params: (..., n_params) design parameters (default: the file's); inputs: (..., n_inputs)
    input values (crank angles in rad, actuator lengths in m; for a single-input plan a scalar or
    a 1-D array is a batch of values); speeds/accels: (..., n_inputs) input rates (default: the
    drivers' speeds, zero input acceleration). Leading axes broadcast. Returns a :class:`State`.
    on_unbuildable: 'nan' (NaN + ``valid`` mask), 'warn' (also warn with the count), 'raise'.
    backend: 'numpy', 'numba' (the fused compiled loop of :mod:`assur.compiled_backend`; plans it
    does not cover fall back to numpy) or 'auto' (numba for batches of at least
    ``AUTO_COMPILED_MIN_SAMPLES`` samples when numba is installed). Both give the same numbers.
    """
    check_options(on_unbuildable, method, order)
    if getattr(plan, "dimension", 2) == 3:   # a spatial plan (assur.spatial_plan)
        from .spatial_plan import solve_spatial
        return solve_spatial(plan, params, inputs, speeds=speeds, accels=accels, order=order,
                             on_unbuildable=on_unbuildable, method=method, tolerances=tolerances)
    if backend not in ("auto", "numpy", "numba"):
        raise SpecError([("backend", f"must be 'auto', 'numpy' or 'numba': {backend!r}")])
    params, inputs = _prepare(plan, params, inputs)
    shape = np.broadcast_shapes(params.shape[:-1], inputs.shape[:-1])
    size = math.prod(shape)
    if method == "closed" and (backend == "numba" or (backend == "auto" and size >= AUTO_COMPILED_MIN_SAMPLES)):
        state = _solve_compiled(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tolerances,
                                required=backend == "numba")
        if state is not None:
            return state
    return _solve_numpy(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tolerances, method)


def _solve_compiled(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, required):
    """The compiled backend, or None where it does not apply (numba missing and not required,
    a plan or batch layout it does not cover)."""
    from . import compiled_backend
    if not (required or compiled_backend.available()):
        return None
    n = plan.n_inputs
    qdot = plan.speeds if speeds is None else np.asarray(speeds, dtype=float)
    qddot = np.zeros(n) if accels is None else np.asarray(accels, dtype=float)
    # one scalar nonzero speed: the kernel writes velocities and accelerations directly
    time_mode = qdot.shape == (1,) and qddot.shape == (1,) and qdot[0] != 0
    rates = (qdot[0], qdot[0] ** 2, qddot[0]) if time_mode else (1.0, 1.0, 0.0)
    compiled = compiled_backend.solve_compiled(plan, params, inputs, tol.radicand, rates, order=order, shape=shape)
    if compiled is None:
        return None
    buffer, (pos, first, second), valid = compiled   # valid includes "every position is finite"
    if not valid.all():
        buffer[:, ~valid.reshape(buffer.shape[1:])] = np.nan
    xyz = (pos, first if order >= 1 else None, second if order >= 2 else None)
    return _finish(plan, params, inputs, shape, None, None, None, valid, speeds, accels, on_unbuildable,
                   has_bodies=False, xyz=xyz, xyz_time=time_mode)


def _solve_numpy(plan, params, inputs, shape, speeds, accels, order, on_unbuildable, tol, method):
    """The numpy backend: every group on whole arrays of jets, one pass per input direction
    (and one per pair of inputs for the mixed second derivatives)."""
    n = plan.n_inputs
    names = plan.point_names
    n_bodies = len(plan.body_names)

    def run(direction):
        q = []
        for k in range(n):
            d = np.full(inputs.shape[:-1], float(direction[k])) if order >= 1 else None
            dd = np.zeros(inputs.shape[:-1]) if order >= 2 else None
            q.append(Jet(inputs[..., k], d, dd))
        return _execute(plan, plan.steps, params, q, order, tol, method)

    def stack(ctx, attr):
        """(..., n_points + n_bodies) complex: point positions, then body orientations e = exp(iθ)."""
        jets = [ctx.pos[p] for p in names] + [ctx.pose[b][1] for b in range(n_bodies)]
        return np.stack([np.broadcast_to(getattr(j, attr), shape) for j in jets], axis=-1)

    eye = np.eye(n)
    passes = [run(eye[k]) for k in range(n)] if order >= 1 and n > 0 else [run(np.zeros(n))]
    base = passes[0]
    z = stack(base, "v")
    valid = np.broadcast_to(base.valid, shape) & np.all(np.isfinite(z), axis=-1)
    dz = d2z = None
    if order >= 1:
        dz = np.stack([stack(p, "d") for p in passes], axis=-1)             # (..., n_points + n_bodies, n_inputs)
    if order >= 2:
        d2z = np.empty(shape + (z.shape[-1], n, n), dtype=complex)
        for i in range(n):
            d2z[..., i, i] = stack(passes[i], "dd")
        for i in range(n):
            for j in range(i + 1, n):
                mixed = run(eye[i] + eye[j])
                d2z[..., i, j] = d2z[..., j, i] = 0.5 * (stack(mixed, "dd") - d2z[..., i, i] - d2z[..., j, j])
    return _finish(plan, params, inputs, shape, z, dz, d2z, valid, speeds, accels, on_unbuildable)


def _finish(plan, params, inputs, shape, z, dz, d2z, valid, speeds, accels, on_unbuildable,
            has_bodies: bool = True, xyz=None, xyz_time: bool = False) -> State:
    """NaN out the unbuildable samples, report them as asked, and wrap the arrays in a State.
    ``xyz``: the compiled backend's (pos, first, second) float views instead of z, dz, d2z."""
    n = plan.n_inputs
    # invalid samples: NaN everywhere, never finite garbage
    inv = ~valid
    if xyz is None and inv.any():
        cnan = complex(np.nan, np.nan)   # both coordinates NaN (a plain nan would give nan + 0j)
        z = np.where(inv[..., None], cnan, z)
        if dz is not None:
            dz = np.where(inv[..., None, None], cnan, dz)
        if d2z is not None:
            d2z = np.where(inv[..., None, None, None], cnan, d2z)
    n_bad = int(np.count_nonzero(inv))
    if n_bad and on_unbuildable != "nan":
        total = int(np.prod(shape)) if shape else 1
        flat = np.broadcast_to(inputs, shape + (n,)).reshape(-1, n)[inv.reshape(-1)]
        first = ", ".join(f"{plan.input_names[k]}={_fmt_input(plan, k, flat[0, k])}" for k in range(n))
        msg = (f"{n_bad} of {total} samples cannot be assembled (first at {first}); "
               f"they are NaN with valid=False")
        if on_unbuildable == "raise":
            raise UnbuildableError(msg, n_bad, total)
        warnings.warn(msg, UnbuildableWarning, stacklevel=4)
    qdot = plan.speeds if speeds is None else np.asarray(speeds, dtype=float)
    qddot = np.zeros(n) if accels is None else np.asarray(accels, dtype=float)
    if qdot.shape[-1:] != (n,) or qddot.shape[-1:] != (n,):
        raise SpecError([("speeds", f"speeds and accels need a trailing axis of {n} inputs")])
    full_inputs = inputs if inputs.shape[:-1] == shape else np.broadcast_to(inputs, shape + (n,))
    return State(plan=plan, inputs=full_inputs, valid=valid, n_unbuildable=n_bad,
                 qdot=qdot, qddot=qddot, _z=z, _dz=dz, _d2z=d2z, _params=params, _has_bodies=has_bodies,
                 _xyz=xyz, _xyz_time=xyz_time)


def _fmt_input(plan, k, v):
    if plan.input_kinds[k] == "rotary":
        return f"{np.degrees(v):.6g}°"
    return f"{v:.6g} m"
