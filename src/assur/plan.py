"""The compiled solve plan: frozen, design-independent, shared by a whole population.

A :class:`SolvePlan` holds the Assur-group order, the step kinds and indices, the branch signs
fixed from the sketch, the parameter map (names and sketch defaults) and name tables. It holds
no numbers that a design changes: those come in ``params (..., n_params)`` at solve time.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .model.mechanism import Mechanism
from .structure.assur import Structure

# step kinds (the order of this tuple is the integer code in SolvePlan.step_kind)
STEP_KINDS = ("frame", "crank", "RRR", "RRP", "RPR", "PRP", "PPR", "newton")


@dataclass(frozen=True, slots=True)
class Side:
    """One side of a dyad: a body, or a driven actuator (cylinder + rod of input length)."""
    body: int
    actuator: tuple[int, int, int] | None = None   # (cylinder, rod, input index)


@dataclass(frozen=True, slots=True)
class Step:
    kind: str
    bodies: tuple[int, ...]
    key_point: str | None = None          # the point a branch refers to
    branch: int = 1
    data: tuple = ()                       # kind-specific (see solve.py)


class PlanLookups:
    """Counts and name look-ups shared by the planar :class:`SolvePlan` and the spatial plan
    (both hold ``param_names``, ``input_names``, ``point_names``, ``defaults`` and ``steps``)."""
    __slots__ = ()

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    @property
    def n_inputs(self) -> int:
        return len(self.input_names)

    @property
    def n_points(self) -> int:
        return len(self.point_names)

    @property
    def branch_signs(self) -> np.ndarray:
        a = np.array([s.branch for s in self.steps], dtype=np.int8)
        a.setflags(write=False)
        return a

    def param_index(self, name: str) -> int:
        try:
            return self.param_names.index(name)
        except ValueError:
            raise KeyError(f"unknown parameter {name!r} (known: {', '.join(self.param_names)})") from None

    def point_index(self, name: str) -> int:
        try:
            return self.point_names.index(name)
        except ValueError:
            raise KeyError(f"unknown point {name!r} (known: {', '.join(self.point_names)})") from None

    def params_with(self, **changes) -> np.ndarray:
        """A copy of the defaults with named parameters changed (SI), e.g. ``crank.length=0.2``;
        dots in names are written as double underscores: ``params_with(crank__length=0.2)``."""
        p = self.defaults.copy()
        for k, v in changes.items():
            p[self.param_index(k.replace("__", "."))] = v
        return p


@dataclass(frozen=True)
class SolvePlan(PlanLookups):
    #: 2 for a planar plan (the spatial plan has 3)
    dimension = 2
    mechanism: Mechanism
    structure: Structure
    steps: tuple[Step, ...]
    param_names: tuple[str, ...]
    defaults: np.ndarray                   # (n_params,) sketch values, SI
    point_names: tuple[str, ...]
    body_names: tuple[str, ...]
    input_names: tuple[str, ...]
    input_kinds: tuple[str, ...]           # 'rotary' | 'linear'
    sketch_inputs: np.ndarray              # (n_inputs,)
    speeds: np.ndarray                     # (n_inputs,) rad/s or m/s from the file
    point_body: tuple[int, ...]            # body whose pose gives each point's position
    geometry_program: tuple = field(repr=False, default=())
    lines: tuple = field(repr=False, default=())
    length_scale: float = 1.0
    #: (x, y, θ) of every body at the sketch inputs — assembled by the plan's own steps when the
    #: sketch assembles, else as drawn: the Newton solver's seed
    sketch_poses: tuple = field(repr=False, default=())

    def __getstate__(self):
        """Pickle the description only: caches that backends keep on the plan (``_``-prefixed:
        op tables, loaded kernels) are rebuilt where the plan is used (e.g. a worker process)."""
        return {k: v for k, v in self.__dict__.items() if not k.startswith("_")}

    def __setstate__(self, state):
        self.__dict__.update(state)

    @property
    def step_kind(self) -> np.ndarray:
        """(n_steps,) integer codes into STEP_KINDS (read-only)."""
        a = np.array([STEP_KINDS.index(s.kind) for s in self.steps], dtype=np.int8)
        a.setflags(write=False)
        return a

