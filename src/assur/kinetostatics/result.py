"""The frozen result of a force analysis (:class:`Forces`), batched like a State.

Sign convention (one for the whole package): the reaction of a pair is the force that the pair's
earlier body (the one the plan solves first; the frame first of all) exerts on its later body, in
frame coordinates (N). At a slide it is the normal force N·n (n = the line's direction turned 90°
counter-clockwise), acting at the slider's reference point, with the couple M (N·m, ccw positive).
The body exerts the opposite force on the earlier one (Newton's third law).
The driving effort of an input is the generalised force conjugate to it: a crank's motor torque in
the input's sense (N·m; for ``sense = "cw"`` a clockwise torque is positive), a driven actuator's
force along the actuator (N, positive pushing the rod out). ``power = Σ driver·q̇`` (W): positive
where the motors put energy in.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Forces:
    """Reactions, driving efforts and power of a batch.

    Shapes (``...`` the batch shape of the state): ``reactions (..., n_pairs, 2)``, ``couples``,
    ``normal (..., n_pairs)`` (NaN where a pair has none), ``driver (..., n_inputs)``, ``power``,
    ``condition``, ``valid``, ``singular (...)``; ``frame_force (..., 2)`` and ``frame_moment (...)`` the
    resultant load of the moving links on the frame (the shaking force, and its moment about the origin).

    A spatial plan (:mod:`.spatial`) gives 3-vectors: ``reactions (..., n_pairs, 3)``, ``frame_force`` and
    ``frame_moment (..., 3)``, ``bearing_moments (..., n_pairs, 3)`` each pair's moment (a frame revolute's
    bearing moment perpendicular to its axis, a universal joint's cross moment, zero at a spherical
    joint, a motor's torque vector); its ``couples`` are their magnitudes (a motor's: its signed torque
    about the crank axis). Pair kinds there: 'R' frame revolute, 'S' spherical, 'U' universal, 'T' motor.
    """
    plan: object
    inputs: np.ndarray
    qdot: np.ndarray
    #: (n_pairs,) 'R' revolute, 'P' slide, 'T' motor torque
    pair_kinds: tuple[str, ...]
    #: (n_pairs,) the joint point, the prismatic pair or actuator, or the driver
    pair_names: tuple[str, ...]
    #: (n_pairs, 2) names of the earlier and the later body
    pair_bodies: tuple[tuple[str, str], ...]
    reactions: np.ndarray
    driver: np.ndarray
    power: np.ndarray
    frame_force: np.ndarray
    frame_moment: np.ndarray
    #: (...) the smallest dimensionless condition measure over the groups (1: well conditioned, 0: a toggle)
    condition: np.ndarray
    valid: np.ndarray
    #: (...) assembled but at (or too near) a toggle: its forces are NaN, never numbers
    singular: np.ndarray
    #: friction iterations done (0 without friction) and whether they converged everywhere
    iterations: int = 0
    converged: bool = True
    method: str = "groups"
    state: object = field(repr=False, default=None)
    #: (..., n_pairs, 3) the pairs' moments (spatial plans only; None for planar ones)
    bearing_moments: np.ndarray | None = field(repr=False, default=None)
    #: the slides' and motors' (N, M) in compact form: (pair indices (k,), values (..., k, 2)); ``normal`` and
    #: ``couples`` are built from it on first use (a revolute has no normal force: NaN, and no couple: 0)
    slides: tuple | None = field(repr=False, default=None)
    #: ``couples`` and ``normal`` given in full instead (the spatial solver)
    full_couples: np.ndarray | None = field(repr=False, default=None)
    full_normal: np.ndarray | None = field(repr=False, default=None)
    #: per gear pair name: ``torque`` (the gear's torque on its driven link, N·m), ``tooth_force`` (N, ≥ 0),
    #: ``line_of_action`` (complex unit vector of the force on the driven link), ``pitch_point`` (complex, m),
    #: each of the batch shape (:mod:`assur.kinetostatics.gearing`)
    gears: dict = field(repr=False, default_factory=dict)
    #: per cam pair name: ``contact_force`` (N, ≥ 0 while the cam pushes), ``normal`` (complex unit vector of the
    #: force on the follower), ``contact`` (complex, m), ``pressure_angle`` (rad), ``lost`` (bool: the cam would have
    #: to pull), each of the batch shape (:mod:`assur.kinetostatics.camming`)
    cams: dict = field(repr=False, default_factory=dict)
    _cache: dict = field(repr=False, default_factory=dict, compare=False)

    def _full(self, which: int, fill: float) -> np.ndarray:
        key = ("normal", "couples")[which]
        if key not in self._cache:
            rows, values = self.slides
            out = np.full(self.shape + (len(self.pair_kinds),), fill)
            out[..., list(rows)] = values[..., which]
            out[~np.asarray(self.valid)] = np.nan
            out.setflags(write=False)
            self._cache[key] = out
        return self._cache[key]

    @property
    def normal(self) -> np.ndarray:
        """(..., n_pairs) a slide's normal force N (N); NaN for a pair without one."""
        return self.full_normal if self.full_normal is not None else self._full(0, np.nan)

    @property
    def couples(self) -> np.ndarray:
        """(..., n_pairs) a slide's couple M or a motor's torque (N·m, ccw on the later body); 0 at a revolute."""
        return self.full_couples if self.full_couples is not None else self._full(1, 0.0)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.valid.shape

    def pair(self, name: str, later: str | None = None) -> int:
        """The index of the pair at the joint (or slide) ``name``; ``later`` picks one of the pairs of a
        joint of more than two bodies by its later body's name."""
        hits = [i for i, n in enumerate(self.pair_names)
                if n == name and self.pair_kinds[i] != "T" and (later is None or self.pair_bodies[i][1] == later)]
        if not hits:
            raise KeyError(f"no pair {name!r} (pairs: {', '.join(sorted(set(self.pair_names)))})")
        return hits[0]

    def reaction(self, name: str, later: str | None = None) -> np.ndarray:
        """(..., 2) (spatial: (..., 3)) the reaction at a joint or slide (see the module's sign convention)."""
        return self.reactions[..., self.pair(name, later), :]

    @property
    def magnitudes(self) -> np.ndarray:
        """(..., n_pairs) |reaction| (N)."""
        return np.sqrt(np.sum(self.reactions ** 2, axis=-1))

    @property
    def joint_pairs(self) -> list[int]:
        """The indices of the joint and slide pairs (not the motors' torques)."""
        return [i for i, k in enumerate(self.pair_kinds) if k != "T"]

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        valid = np.asarray(self.valid)
        rows = [("mechanism", self.plan.mechanism.name or "(unnamed)"),
                ("batch shape", " × ".join(map(str, self.shape)) or "()"),
                ("solved", f"{int(valid.sum())} of {valid.size}"), ("singular (toggle)", int(np.sum(self.singular))),
                ("method", self.method), ("pairs", ", ".join(self.pair_names))]
        return html_table("Forces", rows)
