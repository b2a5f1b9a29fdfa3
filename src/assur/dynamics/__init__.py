"""Forward dynamics: how a one-degree-of-freedom mechanism runs on a real motor (docs/dynamics.md).

``assur.simulate(plan, …)`` (:func:`.api.simulate`) integrates the reduced equation of motion
J*(q)·q̈ + ½·J*′(q)·q̇² = Q_motor + Q_applied(q) + sign(q̇)·Q_opposing(q) from the exact analogues and the force
analysis (:mod:`.reduced`, :mod:`.equation`), for one design (:mod:`.integrate`, scipy's ``solve_ivp``) or a
batch of designs at once (:mod:`.population`). :mod:`.mjcf` writes a planar mechanism as a MuJoCo model.
"""
from __future__ import annotations

import importlib

_LAZY = {
    "simulate": (".api", "simulate"),
    "Simulation": (".result", "Simulation"),
    "PopulationResult": (".population", "PopulationResult"),
    "write_mjcf": (".mjcf", "write_mjcf"),
    "mjcf_text": (".mjcf", "mjcf_text"),
    "cycle_simulation": (".cycle", "cycle_simulation"),
}


def __getattr__(name):
    if name in _LAZY:
        module, attr = _LAZY[name]
        value = getattr(importlib.import_module(module, __name__), attr)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'assur.dynamics' has no attribute {name!r}")


__all__ = sorted(_LAZY)
