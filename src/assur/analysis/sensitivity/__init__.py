"""Exact sensitivities: the derivative of every output of a mechanism by every parameter of its plan, over a run.

No finite-difference step: the closure of the whole mechanism in maximal coordinates (:mod:`.closure`) is
differentiated implicitly on truncated series in time and in the parameter directions (:mod:`.series`,
:mod:`.implicit`); its Lagrange multipliers are the reactions and the drivers' efforts (:mod:`.forces`,
:mod:`.reactions`, realised at gear and cam pairs), and the gait metrics follow by the envelope theorem at their
refined extremes (:mod:`.gait`). The tests compare every output kind on every example with complex-step derivatives
of an independent symbolic solver.

Tolerances (:mod:`.tolerance`): ISO 286 grades (:mod:`.iso286`), worst-case and RSS envelopes, a Monte Carlo on the
batched engine; joint clearance by the effective-link model (:mod:`.clearance`). docs/sensitivity.md.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .outputs import Output, Outputs

__all__ = ["Output", "Sensitivity", "sensitivity"]


@dataclass
class Sensitivity:
    """The exact derivatives of a Study's outputs (see :mod:`.outputs` for the names) by its plan's parameters.

    ``outputs[name]`` (or ``self[name]``) is an :class:`~.outputs.Output`; ``param_names`` the plan's parameters;
    ``q`` the run's moving input."""
    study: object
    outputs: Outputs
    _gait: dict | None = field(default=None, repr=False)

    @property
    def plan(self):
        return self.study.plan

    @property
    def param_names(self) -> tuple[str, ...]:
        return self.study.plan.param_names

    @property
    def q(self) -> np.ndarray:
        return self.study.q

    def gait(self) -> dict:
        if self._gait is None:
            from .gait import gait_outputs
            self._gait = gait_outputs(self.study)
        return self._gait

    def __getitem__(self, name: str) -> Output:
        if name.startswith("gait."):
            g = self.gait()
            if name not in g:
                from ...errors import SpecError
                raise SpecError([("--of", f"{name!r}: the mechanism has no walking gait of a full crank turn"
                                  if not g else f"unknown gait output {name!r} (known: {', '.join(g)})")])
            return g[name]
        return self.outputs[name]

    def names(self) -> list[str]:
        return self.outputs.names() + list(self.gait())


def sensitivity(study, *, forces: bool | None = None) -> Sensitivity:
    """The :class:`Sensitivity` of a planar Study's run (``forces``: include the efforts and reactions; default when
    the file has masses or loads and one driver)."""
    if forces is None:
        forces = bool(study.has_loads) and study.plan.n_inputs == 1
    return Sensitivity(study, Outputs(study.plan, study.state, forces=forces))
