"""The solved state of a batch: positions, analogues, velocities and accelerations.

:class:`State` (planar) and :class:`SpatialState` share one :class:`PointView`. A state never
imports a solver: where a backend returned points only, the solver hands the state a callable
that completes it (body orientations) on first use.

Shapes (leading batch axes ``...`` as broadcast from params and inputs):
``pos``, ``vel``, ``acc`` (..., n_points, 2); ``dpos_dq`` (..., n_points, 2, n_inputs);
``d2pos_dq2`` (..., n_points, 2, n_inputs, n_inputs); ``valid`` (...);
``body_angle``, ``body_omega``, ``body_alpha`` (..., n_bodies).
``vel``/``acc`` are time derivatives at the input rates ``qdot`` (and input accelerations
``qddot``); ``dpos_dq``/``d2pos_dq2`` are the papers' analogues (derivatives by the inputs).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np


class _Once:
    """A value computed by ``make()`` on first use and kept (a mutable holder outside the frozen state)."""
    __slots__ = ("make", "value")

    def __init__(self, make: Callable):
        self.make, self.value = make, None

    def get(self):
        if self.value is None:
            self.value = self.make()
        return self.value


def _xy(z):
    """(..., m) complex → (..., m, 2) real, as a view where the memory allows."""
    if z is None:
        return None
    try:
        return z[..., None].view(np.float64)
    except ValueError:
        return np.stack([z.real, z.imag], axis=-1)


def _move_xy(a, n_extra):
    """(..., n_points, *extra) complex → (..., n_points, 2, *extra) real."""
    if a is None:
        return None
    out = np.stack([a.real, a.imag], axis=-1 - n_extra) if n_extra else np.stack([a.real, a.imag], axis=-1)
    return out


@dataclass(frozen=True)
class StateBase:
    """What planar and spatial states share: the batch shape, the singular samples and the views."""
    #: the plan solved
    plan: object
    #: (..., n_inputs) the inputs solved, broadcast to the batch
    inputs: np.ndarray
    #: (...) True where the sample assembles
    valid: np.ndarray
    n_unbuildable: int
    #: (n_inputs,) or (..., n_inputs) input rates and accelerations of the time derivatives
    qdot: np.ndarray
    qddot: np.ndarray
    #: (..., n_params) the design parameters solved (SI), as given (broadcast against the inputs)
    params: np.ndarray

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape (...)."""
        return self.valid.shape

    # -- positions and analogues -----------------------------------------------------------------
    @property
    def singular(self) -> np.ndarray | None:
        """(...) bool: assembled (``valid``) but at a singular position — a toggle or a change point,
        where two assemblies meet — so the analogues, velocities and accelerations are not finite
        there; None with order 0."""
        d = self.dpos_dq
        if d is None:
            return None
        with np.errstate(invalid="ignore"):
            finite = np.all(np.isfinite(d), axis=tuple(range(self.valid.ndim, d.ndim)))
        return self.valid & ~finite

    @property
    def ambiguous(self) -> np.ndarray:
        """(...) bool: samples of a crank that the walks from the sketch both ways round reach on different assemblies
        of its Newton-solved groups (the sketch's assembly does not close over a turn: it spans more than one and
        locks at a toggle). Which assembly is meant there is not defined, so they are unbuildable (``valid`` False):
        not samples that have no assembly but samples that have two. All False for a state without such groups."""
        a = getattr(self, "_ambiguous", None)
        return np.zeros(np.shape(self.valid), dtype=bool) if a is None else a

    # -- body orientations: θ = arg e, θ' = Im(e'/e), θ'' = Im(e''/e − (e'/e)²) ------------------------
    def point(self, name: str) -> "PointView":
        """Everything about one point: ``state.point('H').vel`` has shape (..., dim)."""
        return PointView(self, self.plan.point_index(name))

    def body(self, name: str) -> int:
        """The index of a body (into the body axis of ``body_angle`` …)."""
        return self.plan.body_names.index(name)

    def take(self, index) -> "StateBase":
        """The samples ``index`` (an integer array or a slice) of the first batch axis, as a state of the same kind
        and order: nothing is solved again (an animation's frames, a table's rows, a leg's phase-shifted turn)."""
        from dataclasses import fields, replace
        n0 = self.valid.shape[0] if self.valid.ndim else None
        if n0 is None:
            raise ValueError("a state without a batch axis has no samples to take")

        def pick(a):
            return None if a is None else np.asarray(a)[index]

        def pick_broadcast(a):     # parameters and rates: per sample only when they carry the batch axis
            a = np.asarray(a)
            return a[index] if a.ndim > 1 and a.shape[0] == n0 else a

        changes = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("plan", "_xyz_time", "n_unbuildable"):
                continue
            if f.name in ("params", "qdot", "qddot"):
                changes[f.name] = pick_broadcast(v)
            elif f.name == "_complete":
                changes[f.name] = None if v is None else _Once(lambda full=v: full.get().take(index))
            elif f.name == "_xyz":
                changes[f.name] = None if v is None else tuple(pick(a) for a in v)
            elif f.name == "status":
                changes[f.name] = {k: pick(a) for k, a in v.items()}
            else:
                changes[f.name] = pick(v)
        changes["n_unbuildable"] = int(np.count_nonzero(~np.asarray(changes["valid"], dtype=bool)))
        return replace(self, **changes)

    def _repr_html_(self) -> str:
        """A small table for notebooks: the batch, how much of it assembles, the points and the orders solved."""
        from ..model.display import html_table
        valid = np.asarray(self.valid)
        orders = ["pos"] + (["vel"] if self.dpos_dq is not None else []) \
            + (["acc"] if self.d2pos_dq2 is not None else [])
        names = self.plan.point_names
        shape = " × ".join(map(str, self.shape)) or "()"
        rows = [("mechanism", self.plan.mechanism.name or "(unnamed)"), ("batch shape", shape),
                ("assembled", f"{int(valid.sum())} of {valid.size}"), ("cannot be assembled", self.n_unbuildable),
                ("inputs", np.asarray(self.inputs)), ("solved", ", ".join(orders)),
                (f"points ({len(names)})", names)]
        return html_table(type(self).__name__, rows)


@dataclass(frozen=True)
class State(StateBase):
    """The solved state of a planar batch (shapes in the module docstring)."""
    dimension = 2
    #: (..., n_points + n_bodies) complex: point positions x + iy, then body orientations exp(iθ)
    _z: np.ndarray = field(repr=False)
    _dz: np.ndarray | None = field(repr=False, default=None)       # (..., m, n_inputs)
    _d2z: np.ndarray | None = field(repr=False, default=None)      # (..., m, n_inputs, n_inputs)
    #: None when the state has its body orientations; else the backend's completion: a callable
    #: returning the full (numpy-backend) state, called once on first use of a body orientation
    _complete: _Once | None = field(repr=False, default=None)
    #: the compiled backend's float views (pos, first, second), each (..., n_points, 2): with
    #: ``_xyz_time`` velocity and acceleration at qdot/qddot, else the analogues d/dq, d²/dq²
    _xyz: tuple | None = field(repr=False, default=None)
    _xyz_time: bool = field(repr=False, default=False)
    #: (...) bool or None: :attr:`ambiguous`, where the continuation looked for such samples
    _ambiguous: np.ndarray | None = field(repr=False, default=None)

    @property
    def _np(self) -> int:
        return len(self.plan.point_names)

    @property
    def pos(self) -> np.ndarray:
        """(..., n_points, 2) positions (m)."""
        if self._xyz is not None:
            return self._xyz[0]
        return _xy(self._z[..., : self._np])

    @property
    def dpos_dq(self) -> np.ndarray | None:
        """(..., n_points, 2, n_inputs) analogues d pos/dq (m/rad or m/m); None with order 0."""
        if self._xyz is not None:
            first = self._xyz[1]
            if first is None:
                return None
            return (first / float(self.qdot[0]) if self._xyz_time else first)[..., None]
        return None if self._dz is None else _move_xy(self._dz[..., : self._np, :], 1)

    @property
    def d2pos_dq2(self) -> np.ndarray | None:
        """(..., n_points, 2, n_inputs, n_inputs) second analogues d² pos/dq²; None below order 2."""
        if self._xyz is not None:
            first, second = self._xyz[1], self._xyz[2]
            if second is None:
                return None
            if self._xyz_time:
                w, a = float(self.qdot[0]), float(self.qddot[0])
                second = (second - first * (a / w)) / (w * w)
            return second[..., None, None]
        return None if self._d2z is None else _move_xy(self._d2z[..., : self._np, :, :], 2)

    # -- time derivatives ------------------------------------------------------------------------------
    def _rate(self, dz, d2z):
        if dz.shape[-1] == 1 and self.qdot.ndim == 1:   # one input: plain products, no einsum
            w, a = float(self.qdot[0]), float(self.qddot[0])
            vel = dz[..., 0] * w
            acc = None if d2z is None else (d2z[..., 0, 0] * (w * w) + (dz[..., 0] * a if a else 0.0))
            return vel, acc
        qd = self.qdot + 0j
        vel = np.einsum("...pk,...k->...p", dz, qd)
        acc = None
        if d2z is not None:
            acc = (np.einsum("...pk,...k->...p", dz, self.qddot + 0j)
                   + np.einsum("...pkl,...k,...l->...p", d2z, qd, qd))
        return vel, acc

    @staticmethod
    def _input_rate(rate) -> np.ndarray:
        """The one input's rate (qdot or qddot: (1,) or per sample (..., 1)) shaped to multiply the float views
        (..., n_points, 2) of a compiled solve (their analogues d/dq, d²/dq²)."""
        return np.asarray(rate, dtype=float)[..., 0][..., None, None]

    @property
    def vel(self) -> np.ndarray | None:
        """(..., n_points, 2) velocities (m/s) at the input rates ``qdot``; None with order 0."""
        if self._xyz is not None:
            first = self._xyz[1]
            if first is None or self._xyz_time:
                return first
            return first * self._input_rate(self.qdot)
        if self._dz is None:
            return None
        return _xy(self._rate(self._dz[..., : self._np, :], None)[0])

    @property
    def acc(self) -> np.ndarray | None:
        """(..., n_points, 2) accelerations (m/s²) at ``qdot`` and ``qddot``; None below order 2."""
        if self._xyz is not None:
            first, second = self._xyz[1], self._xyz[2]
            if second is None or self._xyz_time:
                return second
            w, a = self._input_rate(self.qdot), self._input_rate(self.qddot)
            return second * (w * w) + first * a
        if self._d2z is None:
            return None
        return _xy(self._rate(self._dz[..., : self._np, :], self._d2z[..., : self._np, :, :])[1])

    def _theta_jets(self):
        if self._complete is not None:
            return self._complete.get()._theta_jets()
        e = self._z[..., self._np:]
        th = np.angle(e)
        d1 = d2 = None
        with np.errstate(all="ignore"):
            if self._dz is not None:
                r = self._dz[..., self._np:, :] / e[..., None]
                d1 = r.imag
                if self._d2z is not None:
                    d2 = (self._d2z[..., self._np:, :, :] / e[..., None, None]
                          - r[..., :, None] * r[..., None, :]).imag
        return th, d1, d2

    @property
    def body_angle(self) -> np.ndarray:
        """(..., n_bodies) rad; the frame is 0."""
        return self._theta_jets()[0]

    @property
    def dangle_dq(self) -> np.ndarray | None:
        """(..., n_bodies, n_inputs) angular analogues dθ/dq."""
        return self._theta_jets()[1]

    @property
    def body_omega(self) -> np.ndarray | None:
        """(..., n_bodies) angular velocities (rad/s), counter-clockwise positive."""
        d1 = self._theta_jets()[1]
        return None if d1 is None else np.einsum("...bk,...k->...b", d1, self.qdot)

    @property
    def body_alpha(self) -> np.ndarray | None:
        """(..., n_bodies) angular accelerations (rad/s²)."""
        _, d1, d2 = self._theta_jets()
        if d2 is None:
            return None
        return (np.einsum("...bk,...k->...b", d1, self.qddot)
                + np.einsum("...bkl,...k,...l->...b", d2, self.qdot, self.qdot))

    # -- conveniences ------------------------------------------------------------------------------
@dataclass(frozen=True)
class SpatialState(StateBase):
    """The solved state of a spatial batch. Shapes: ``pos``, ``vel``, ``acc`` (..., n_points, 3);
    ``dpos_dq`` (..., n_points, 3, n_inputs); ``d2pos_dq2`` (..., n_points, 3, n_inputs, n_inputs);
    ``valid`` (...); ``body_frame`` (..., n_bodies, 3, 3) with columns the body's unit axes (NaN for
    a coupler that spins idly); ``body_omega``, ``body_alpha`` (..., n_bodies, 3) angular velocity
    and acceleration vectors; ``status`` maps each dyad point to its solver status (...)."""
    dimension = 3
    pos: np.ndarray
    dpos_dq: np.ndarray | None
    d2pos_dq2: np.ndarray | None
    body_frame: np.ndarray
    dframe_dq: np.ndarray | None = field(repr=False, default=None)
    d2frame_dq2: np.ndarray | None = field(repr=False, default=None)
    status: dict = field(repr=False, default_factory=dict)

    @property
    def vel(self):
        """(..., n_points, 3) velocities (m/s) at the input rates ``qdot``; None with order 0."""
        if self.dpos_dq is None:
            return None
        return np.einsum("...k,...k->...", self.dpos_dq, self.qdot)

    @property
    def acc(self):
        """(..., n_points, 3) accelerations (m/s²) at ``qdot`` and ``qddot``; None below order 2."""
        if self.d2pos_dq2 is None:
            return None
        return (np.einsum("...k,...k->...", self.dpos_dq, self.qddot)
                + np.einsum("...kl,...k,...l->...", self.d2pos_dq2, self.qdot, self.qdot))

    def _frame_rate(self, d1, d2=None):
        R = self.body_frame
        # ω× = R'Rᵀ; α× = the skew part of R''Rᵀ (R'R'ᵀ is symmetric)
        W = (d1 if d2 is None else d2) @ np.swapaxes(R, -1, -2)
        return np.stack([W[..., 2, 1] - W[..., 1, 2], W[..., 0, 2] - W[..., 2, 0], W[..., 1, 0] - W[..., 0, 1]],
                        axis=-1) * 0.5

    @property
    def body_omega(self):
        """(..., n_bodies, 3) angular velocity vectors (rad/s): ω× = R'Rᵀ."""
        if self.dframe_dq is None:
            return None
        d1 = np.einsum("...ijk,...k->...ij", self.dframe_dq, self.qdot)
        return self._frame_rate(d1)

    @property
    def body_alpha(self):
        """(..., n_bodies, 3) angular acceleration vectors (rad/s²): the skew part of R''Rᵀ."""
        if self.d2frame_dq2 is None:
            return None
        d1 = np.einsum("...ijk,...k->...ij", self.dframe_dq, self.qddot)
        d2 = np.einsum("...ijkl,...k,...l->...ij", self.d2frame_dq2, self.qdot, self.qdot) + d1
        return self._frame_rate(None, d2)

@dataclass(frozen=True)
class PointView:
    """One point of a planar or spatial state: ``pos``, ``vel``, ``acc`` (..., dim),
    ``dpos_dq`` (..., dim, n_inputs), ``d2pos_dq2`` (..., dim, n_inputs, n_inputs)."""
    state: object
    index: int

    @property
    def pos(self):
        return self.state.pos[..., self.index, :]

    @property
    def vel(self):
        v = self.state.vel
        return None if v is None else v[..., self.index, :]

    @property
    def acc(self):
        a = self.state.acc
        return None if a is None else a[..., self.index, :]

    @property
    def dpos_dq(self):
        """(..., dim, n_inputs)"""
        d = self.state.dpos_dq
        return None if d is None else d[..., self.index, :, :]

    @property
    def d2pos_dq2(self):
        """(..., dim, n_inputs, n_inputs)"""
        d = self.state.d2pos_dq2
        return None if d is None else d[..., self.index, :, :, :]


#: the former name of the spatial point view
SpatialPointView = PointView
