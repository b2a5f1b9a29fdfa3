"""The terms of the reduced equation of motion at given inputs, exactly (no interpolation).

For a one-degree-of-freedom mechanism with input q (a crank's angle or an actuator's length) Lagrange's
equation reduced to q is (docs/dynamics.md)::

    J*(q)·q̈ + ½·J*′(q)·q̇² = Q_motor(q̇) + Q_applied(q) + sign(q̇)·Q_opposing(q)

* J* = Σ m·|c′|² + I·θ′² over the bodies (c the centre of mass, θ the body angle, ′ = d/dq: the exact analogues
  of the solved state), and ½·J*′ = Σ m·c′·c″ + I·θ′·θ″ from the second analogues;
* Q_applied: the generalised force of gravity and of the file's loads (constant, or a law of the input), by
  virtual power: the force analysis at the state's rates (q̇ = w, q̈ = a; w = 1, a = 0 unless a solved state is
  given) needs the driving effort Q_d = J*·a + ½J*′·w² − Q_applied − sign(w)·Q_opposing, so Q_applied + sign(w)·
  Q_opposing = J*·a + ½J*′·w² − Q_d;
* Q_opposing: the generalised force at q̇ > 0 of the loads that act against a point's velocity (``opposes``): the
  force analysis at q̇ = q̈ = 0 (where they vanish) gives Q_applied = −Q_d(0, 0) alone, and the rest is theirs.

Planar plans compute J* and J*′ from the analogues with the force analysis' own mass recipes
(:mod:`assur.kinetostatics.kernel`: com_motion, body_inertia), so the force analysis and the equation of motion
use one mass model. Spatial plans read J* and ½J*′ off the force analysis' response, which is linear in q̈ and
q̇²: J* = Q_d(0, 1) − Q_d(0, 0), ½J*′ = (Q_d(1, 0) + Q_d(−1, 0))/2 − Q_d(0, 0), Q_d(q̇, q̈) the driving effort.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..engine import solve
from ..engine.plan import SpatialPlan
from ..errors import SpecError, StructureError
from ..kinetostatics import kernel as K
from ..kinetostatics.api import forces
from ..kinetostatics.groups import body_rows
from ..kinetostatics.program import program_of


@dataclass(frozen=True)
class Terms:
    """The reduced equation's terms at the inputs ``q (...)`` (SI): ``inertia`` J* (kg·m² for a crank, kg for a
    linear input), ``inertia_rate`` dJ*/dq, ``applied`` Q_applied and ``opposing`` Q_opposing (N·m or N), each
    (...); ``valid (...)``: assembled, not singular, every term finite. Invalid samples hold NaN."""
    q: np.ndarray
    inertia: np.ndarray
    inertia_rate: np.ndarray
    applied: np.ndarray
    opposing: np.ndarray
    valid: np.ndarray

    def stacked(self) -> np.ndarray:
        """(..., 4) J*, J*′, Q_applied, Q_opposing."""
        return np.stack([self.inertia, self.inertia_rate, self.applied, self.opposing], axis=-1)


def check_one_input(plan) -> None:
    """StructureError unless the plan has exactly one input (the coordinate of the equation of motion)."""
    if plan.n_inputs != 1:
        raise StructureError(f"the equation of motion is written in one input; the mechanism has {plan.n_inputs} "
                             f"({', '.join(plan.input_names)})")


def has_opposing(plan) -> bool:
    """True when a load of the file acts against a point's velocity."""
    d = plan.mechanism.dynamics
    return d is not None and any(ld.opposes is not None for ld in d.loads)


def _rows(state, n):
    """Complex rows (n_points, N) of the positions, analogues and second analogues; parameters (n_params, N|1)."""
    def rows(x):
        x = np.reshape(x, (n,) + x.shape[-2:])
        return (x[..., 0] + 1j * x[..., 1]).T
    params = np.asarray(state.params, dtype=float)
    p = params[:, None] if params.ndim == 1 else \
        np.broadcast_to(params, state.shape + params.shape[-1:]).reshape(n, -1).T
    return (rows(state.pos), rows(state.dpos_dq[..., 0]), rows(state.d2pos_dq2[..., 0, 0]), p)


def planar_inertia(plan, state):
    """(J*, ½·J*′) of a planar state (...) from its analogues (the state may be solved at any input rates)."""
    shape = state.shape
    n = math.prod(shape)
    z, v, a, p = _rows(state, n)
    prog = program_of(plan)
    orient, omega, alpha = body_rows(prog, z, v, a, p)
    J, half_rate = np.zeros(n), np.zeros(n)
    with np.errstate(all="ignore"):
        for b in prog.massive:
            c, cv, ca = K.com_motion(b, prog.cpts, prog.cw, prog.coff, z, v, a, orient, omega, alpha)
            inertia = K.body_inertia(b, prog.mass, prog.inertia, prog.idef, prog.ipts, z, c)
            m = prog.mass[b]
            J = J + m * (cv.real * cv.real + cv.imag * cv.imag) + inertia * omega[b] * omega[b]
            half_rate = half_rate + m * (cv.real * ca.real + cv.imag * ca.imag) + inertia * omega[b] * alpha[b]
    return J.reshape(shape), half_rate.reshape(shape)


def _driver(plan, params, inputs, speed, accel, backend):
    f = forces(plan, params, inputs, speeds=[speed], accels=[accel], backend=backend)
    return np.asarray(f.driver[..., 0], dtype=float), np.asarray(f.valid)


def reduced_terms(plan, params=None, q=None, *, state=None, backend: str = "auto") -> Terms:
    """The exact terms of the reduced equation at the inputs ``q (...)`` of a one-input plan, for the
    parameters ``params (..., n_params)`` (default: the file's; leading axes broadcast against q).

    ``state``: an already solved state of the same plan, params and inputs (order 2; its analogues are used,
    whatever rates it was solved at). The force analysis is solved at the rates it needs (q̇ = 0, ±1)."""
    check_one_input(plan)
    q = np.asarray(q, dtype=float)
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    inputs = q[..., None]
    if isinstance(plan, SpatialPlan):
        d00, ok = _driver(plan, params, inputs, 0.0, 0.0, backend)
        d01, _ = _driver(plan, params, inputs, 0.0, 1.0, backend)
        dp, _ = _driver(plan, params, inputs, 1.0, 0.0, backend)
        dm, _ = _driver(plan, params, inputs, -1.0, 0.0, backend)
        J = d01 - d00
        half_rate = 0.5 * (dp + dm) - d00
        applied, opposing = -d00, 0.5 * (dm - dp)
    else:
        if state is None:
            state = solve(plan, params, inputs, speeds=[1.0], accels=[0.0], order=2, backend=backend)
        elif state.d2pos_dq2 is None:
            raise SpecError([("state", "the equation of motion needs the second analogues: solve with order=2")])
        J, half_rate = planar_inertia(plan, state)
        # the force analysis at the state's own rates (q̇ = w, q̈ = a): Q_d = J*·a + ½J*′·w² − Q_applied − sign(w)·Q_opp
        w = np.asarray(state.qdot, dtype=float)[..., 0]
        acc = np.asarray(state.qddot, dtype=float)[..., 0]
        f = forces(plan, state=state, backend=backend)
        dw, ok = np.asarray(f.driver[..., 0], dtype=float), np.asarray(f.valid)
        loads = J * acc + half_rate * w * w - dw              # Q_applied + sign(w)·Q_opposing
        if has_opposing(plan):
            d00, _ = _driver(plan, params, inputs, 0.0, 0.0, backend)
            applied = -d00
            with np.errstate(invalid="ignore"):
                opposing = np.sign(w) * (loads - applied)
        else:
            applied, opposing = loads, np.zeros_like(loads)
    shape = np.broadcast_shapes(np.shape(J), np.shape(applied))
    J, half_rate, applied, opposing = (np.broadcast_to(x, shape).astype(float) for x in
                                       (J, half_rate, applied, opposing))
    with np.errstate(invalid="ignore"):
        valid = np.broadcast_to(ok, shape) & np.isfinite(J) & np.isfinite(half_rate) & np.isfinite(applied) \
            & np.isfinite(opposing)
    nan = np.where(valid, 1.0, np.nan)
    return Terms(np.broadcast_to(q, shape), J * nan, 2.0 * half_rate * nan, applied * nan, opposing * nan,
                 valid)


__all__ = ["Terms", "check_one_input", "has_opposing", "planar_inertia", "reduced_terms"]
