"""The solved state of a batch: positions, analogues, velocities and accelerations.

Shapes (leading batch axes ``...`` as broadcast from params and inputs):
``pos``, ``vel``, ``acc`` (..., n_points, 2); ``dpos_dq`` (..., n_points, 2, n_inputs);
``d2pos_dq2`` (..., n_points, 2, n_inputs, n_inputs); ``valid`` (...);
``body_angle``, ``body_omega``, ``body_alpha`` (..., n_bodies).
``vel``/``acc`` are time derivatives at the input rates ``qdot`` (and input accelerations
``qddot``); ``dpos_dq``/``d2pos_dq2`` are the papers' analogues (derivatives by the inputs).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def _xy(z):
    return None if z is None else np.stack([z.real, z.imag], axis=-1)


def _move_xy(a, n_extra):
    """(..., n_points, *extra) complex → (..., n_points, 2, *extra) real."""
    if a is None:
        return None
    out = np.stack([a.real, a.imag], axis=-1 - n_extra) if n_extra else np.stack([a.real, a.imag], axis=-1)
    return out


@dataclass(frozen=True)
class State:
    plan: object
    inputs: np.ndarray
    valid: np.ndarray
    n_unbuildable: int
    qdot: np.ndarray
    qddot: np.ndarray
    _pos: np.ndarray = field(repr=False)
    _dz: np.ndarray | None = field(repr=False, default=None)
    _d2z: np.ndarray | None = field(repr=False, default=None)
    _theta: np.ndarray | None = field(repr=False, default=None)
    _dtheta: np.ndarray | None = field(repr=False, default=None)
    _d2theta: np.ndarray | None = field(repr=False, default=None)

    # -- positions and analogues -----------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, ...]:
        return self.valid.shape

    @property
    def pos(self) -> np.ndarray:
        return _xy(self._pos)

    @property
    def dpos_dq(self) -> np.ndarray | None:
        return _move_xy(self._dz, 1)

    @property
    def d2pos_dq2(self) -> np.ndarray | None:
        return _move_xy(self._d2z, 2)

    # -- time derivatives ------------------------------------------------------------------------------
    def _vel_c(self):
        if self._dz is None:
            return None
        return np.einsum("...pk,...k->...p", self._dz, self.qdot + 0j)

    def _acc_c(self):
        if self._d2z is None:
            return None
        qd = self.qdot + 0j
        return (np.einsum("...pk,...k->...p", self._dz, self.qddot + 0j)
                + np.einsum("...pkl,...k,...l->...p", self._d2z, qd, qd))

    @property
    def vel(self) -> np.ndarray | None:
        return _xy(self._vel_c())

    @property
    def acc(self) -> np.ndarray | None:
        return _xy(self._acc_c())

    @property
    def body_angle(self) -> np.ndarray:
        return self._theta

    @property
    def body_omega(self) -> np.ndarray | None:
        if self._dtheta is None:
            return None
        return np.einsum("...bk,...k->...b", self._dtheta, self.qdot)

    @property
    def body_alpha(self) -> np.ndarray | None:
        if self._d2theta is None:
            return None
        return (np.einsum("...bk,...k->...b", self._dtheta, self.qddot)
                + np.einsum("...bkl,...k,...l->...b", self._d2theta, self.qdot, self.qdot))

    # -- conveniences ------------------------------------------------------------------------------
    def point(self, name: str) -> "PointView":
        """Everything about one point: ``state.point('H').vel`` has shape (..., 2)."""
        return PointView(self, self.plan.point_index(name))

    def body(self, name: str) -> int:
        return self.plan.body_names.index(name)


@dataclass(frozen=True)
class PointView:
    state: State
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
        """(..., 2, n_inputs)"""
        d = self.state.dpos_dq
        return None if d is None else d[..., self.index, :, :]

    @property
    def d2pos_dq2(self):
        """(..., 2, n_inputs, n_inputs)"""
        d = self.state.d2pos_dq2
        return None if d is None else d[..., self.index, :, :, :]
