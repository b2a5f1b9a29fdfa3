"""The bodies of a planar plan as rigid frames moving over a solved cycle: which points each body carries, its
pose (x, y, θ) at the sketch and at every sample, and the exact time derivatives of that pose.

A body's frame has its origin at its reference point (a link's first point, a slider block's pin, an actuator
cylinder's or rod's hinge) and turns with the body's angle; the frame body's frame is the sketch frame. A part
is drawn once in its body's frame (:func:`BodyFrames.to_local`) and moved by the body's poses.

A run is any solved cycle with ``plan``, ``params`` and ``grid() -> (q, State)`` (a
:class:`~assur.analysis.sampling.Cycle` or :class:`~assur.analysis.study.Study`; its ``state_at(q)`` refines
between samples).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SpecError, StructureError
from ..model.mechanism import FRAME


def body_points(mechanism, plan) -> dict[int, tuple[str, ...]]:
    """{body index: the points it carries}, in the plan's body order: a link's points, a pin-in-slot block's pin,
    an actuator cylinder's first hinge and its rod's second."""
    out: dict[int, list[str]] = {b: [] for b in range(plan.n_bodies)}
    names = {n: b for b, n in enumerate(plan.body_names)}
    for lk in mechanism.links:
        if lk.name in names:
            out[names[lk.name]].extend(lk.points)
    for pr in mechanism.prismatic:
        if pr.point is not None and f"{pr.name}.block" in names:
            out[names[f"{pr.name}.block"]].append(pr.point)
    for ac in mechanism.actuators:
        for k, part in enumerate(("cylinder", "rod")):
            if f"{ac.name}.{part}" in names:
                out[names[f"{ac.name}.{part}"]].append(ac.between[k])
    return {b: tuple(p) for b, p in out.items()}


def joints(mechanism, plan) -> dict[str, tuple[int, ...]]:
    """{point: the bodies hinged there} for every point that two or more bodies carry (a revolute joint), in the
    mechanism's point order."""
    carried = body_points(mechanism, plan)
    out = {}
    for name in mechanism.point_names:
        bodies = tuple(b for b in range(plan.n_bodies) if name in carried[b])
        if len(bodies) >= 2:
            out[name] = bodies
    return out


@dataclass(frozen=True, eq=False)
class BodyFrames:
    """The poses of every body over a solved run (n samples, B bodies).

    ``q`` (n,) the run's inputs; ``dt`` (n,) the time from sample i to the next (the last to the first + one
    period for a turn, 0 at the end of a stroke); ``closed``: the run is one turn (the last interval wraps).
    ``origin``, ``vel``, ``acc`` (n, B, 2): each body frame's origin and its time derivatives; ``angle``,
    ``omega``, ``alpha`` (n, B): its angle and angular velocity and acceleration (time derivatives at the drivers'
    speeds: the exact velocities the engine solved). ``sketch_origin`` (B, 2),
    ``sketch_angle`` (B,): the pose at the sketch inputs (``sketch_state``: that State). ``ref``: each body's
    reference point (None for the frame)."""
    plan: object
    q: np.ndarray
    dt: np.ndarray
    closed: bool
    origin: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    angle: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    sketch_origin: np.ndarray
    sketch_angle: np.ndarray
    sketch_state: object
    ref: tuple
    #: (n_params,) the design parameters of the run (SI)
    params: np.ndarray = None
    #: (n, n_inputs) the full inputs of the samples, (n_inputs,) the step from the last back to the first of a
    #: turn (2π on the turning input), and the index of the input the run moves (``q`` is its column)
    inputs: np.ndarray = None
    period: np.ndarray = None
    moving: int = 0
    #: ``solve(inputs (m, n_inputs)) -> State`` for refinements between samples: the cycle's ``state_at(q)``
    #: (the moving input's values), else the engine at those inputs
    solve: object = None

    def inputs_between(self, i: int, fractions) -> np.ndarray:
        """(m, n_inputs) the inputs at ``fractions`` (m,) of the way from sample i to the next (the first of the
        next turn after the last sample of a turn)."""
        a = self.inputs[i]
        b = self.inputs[i + 1] if i + 1 < self.n else self.inputs[0] + self.period
        f = np.asarray(fractions, dtype=float)[:, None]
        return a + f * (b - a)

    @property
    def n(self) -> int:
        return self.q.shape[0]

    def to_local(self, body: int, xy) -> np.ndarray:
        """Sketch-pose world points ``xy (..., 2)`` → body ``body``'s frame (..., 2)."""
        c, s = np.cos(self.sketch_angle[body]), np.sin(self.sketch_angle[body])
        d = np.asarray(xy, dtype=float) - self.sketch_origin[body]
        return np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)

    def to_world(self, body: int, xy, origin=None, angle=None) -> np.ndarray:
        """Body-frame points ``xy (k, 2)`` at the poses ``origin (m, 2)``, ``angle (m,)`` (default: every sample of
        the run) → (m, k, 2)."""
        origin = self.origin[:, body] if origin is None else origin
        angle = self.angle[:, body] if angle is None else angle
        xy = np.asarray(xy, dtype=float)
        c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
        return np.stack([origin[:, None, 0] + c * xy[:, 0] - s * xy[:, 1],
                         origin[:, None, 1] + s * xy[:, 0] + c * xy[:, 1]], axis=-1)

    def at_sketch(self, body: int, xy) -> np.ndarray:
        """Body-frame points ``xy (k, 2)`` at the sketch pose (k, 2)."""
        return self.to_world(body, xy, self.sketch_origin[body][None], self.sketch_angle[body][None])[0]


def _poses(plan, state, refs):
    """(origin, vel, acc (..., B, 2), angle, omega, alpha (..., B)) of a State; zeros for the frame."""
    pos = np.asarray(state.pos)
    shape = pos.shape[:-2]
    B = plan.n_bodies
    origin, vel, acc = (np.zeros(shape + (B, 2)) for _ in range(3))
    angle = np.array(state.body_angle, dtype=float).reshape(shape + (B,))
    omega = np.array(state.body_omega, dtype=float).reshape(shape + (B,))
    alpha = np.array(state.body_alpha, dtype=float).reshape(shape + (B,))
    v, a = np.asarray(state.vel), np.asarray(state.acc)
    for b, r in enumerate(refs):
        if r is None:
            angle[..., b] = omega[..., b] = alpha[..., b] = 0.0
            continue
        origin[..., b, :] = pos[..., r, :]
        vel[..., b, :] = v[..., r, :]
        acc[..., b, :] = a[..., r, :]
    return origin, vel, acc, angle, omega, alpha


def reference_points(mechanism, plan) -> tuple:
    """Each body's reference point index (its frame's origin), None for the frame."""
    carried = body_points(mechanism, plan)
    refs = []
    for b, name in enumerate(plan.body_names):
        if name == FRAME:
            refs.append(None)
        elif not carried[b]:
            raise StructureError(f"body {name!r} carries no point: assur make cannot place it")
        else:
            refs.append(plan.point_index(carried[b][0]))
    return tuple(refs)


def body_frames(cycle) -> BodyFrames:
    """The body poses over the solved run of ``cycle`` (a Study or Cycle: ``plan``, ``params``,
    ``grid()``), and at the sketch inputs (one solve). SpecError when a sample does not assemble (parts need the
    whole run)."""
    plan = cycle.plan
    q, st = cycle.grid()
    valid = np.asarray(st.valid)
    if not valid.all():
        bad = np.asarray(q)[~valid]
        raise SpecError([("drivers", f"the mechanism does not assemble at {int((~valid).sum())} of {valid.size} "
                                     f"inputs of its run (first at {_input_text(plan, bad[0])}): assur make needs "
                                     "the whole run")])
    refs = reference_points(plan.mechanism, plan)
    origin, vel, acc, angle, omega, alpha = _poses(plan, st, refs)
    angle = np.unwrap(angle, axis=0)
    inputs = np.asarray(st.inputs, dtype=float).reshape(len(q), -1)
    qdot = np.broadcast_to(np.asarray(st.qdot, dtype=float), inputs.shape)
    spread = np.ptp(inputs, axis=0)
    k = int(np.argmax(spread))                 # the input the run moves
    closed = getattr(cycle, "cyclic", None)
    if closed is None:                         # a turn of a crank, else a stroke
        closed = plan.input_kinds[k] == "rotary"
    period = np.zeros(inputs.shape[1])
    if closed:
        period[k] = 2.0 * np.pi
    step = np.diff(inputs, axis=0, append=inputs[:1] + period)
    if not closed:
        step[-1] = 0.0
    moving = np.abs(qdot) > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        per = np.where(moving, np.abs(step) / np.abs(qdot), np.where(np.abs(step) > 0, np.inf, 0.0))
    dt = per.max(axis=1)
    if not np.all(np.isfinite(dt)):
        j = int(np.argmax(~np.isfinite(per).all(axis=0)))
        raise SpecError([("drivers", f"the input {plan.input_names[j]!r} moves over the run but its driver's "
                                     "speed is 0: give it a speed (the parts' certificate uses the velocities)")])
    params = np.asarray(getattr(cycle, "params", plan.defaults), dtype=float)
    if hasattr(cycle, "state_at") and not np.any(np.ptp(inputs, axis=0)[np.arange(inputs.shape[1]) != k]):
        def refine(x):                         # the cycle's own refinement: the moving input's values
            return cycle.state_at(np.asarray(x, dtype=float)[:, k])
    else:
        def refine(x):
            return solve_at(plan, params, x)
    sketch = refine(np.asarray(plan.sketch_inputs, dtype=float)[None, :])
    s_origin, _, _, s_angle, _, _ = _poses(plan, sketch, refs)
    s_origin = s_origin.reshape(plan.n_bodies, 2)
    s_angle = s_angle.reshape(plan.n_bodies)
    return BodyFrames(plan, inputs[:, k].copy(), dt, bool(closed), origin, vel, acc, angle, omega, alpha,
                      s_origin, s_angle, sketch, refs, params, inputs, period, k, refine)


def solve_at(plan, params, inputs):
    """The State (order 2) of ``plan`` at a few full input vectors ``inputs (m, n_inputs)``: the sketch pose and
    the refinements between two samples (never a whole cycle)."""
    from ..engine import solve
    return solve(plan, params, np.asarray(inputs, dtype=float), order=2)


def _input_text(plan, q, k: int | None = None) -> str:
    """A value of input ``k`` (default: the first that moves) in the file's units, with its name when the plan has
    several inputs."""
    from ..io.units import ANGLE, LENGTH
    u = plan.mechanism.units
    q = float(np.ravel(q)[0])
    if k is None:
        k = next((j for j in range(plan.n_inputs) if plan.speeds[j] != 0), 0)
    name = f"{plan.input_names[k]} = " if plan.n_inputs > 1 else ""
    if plan.input_kinds[k] == "rotary":
        return f"{name}{q / ANGLE[u.angle]:.6g} {u.angle}"
    return f"{name}{q / LENGTH[u.length]:.6g} {u.length}"


__all__ = ["BodyFrames", "body_frames", "body_points", "joints", "reference_points", "solve_at"]
