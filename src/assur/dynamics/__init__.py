"""Forward dynamics: how a one-degree-of-freedom mechanism runs on a real motor (docs/dynamics.md).

``assur.simulate(plan, …)`` (:func:`.api.simulate`) integrates the reduced equation of motion
J*(q)·q̈ + ½·J*′(q)·q̇² = Q_motor + Q_applied(q) + sign(q̇)·Q_opposing(q) from the exact analogues and the force
analysis (:mod:`.reduced`, :mod:`.equation`), for one design (:mod:`.integrate`, scipy's ``solve_ivp``) or a
batch of designs at once (:mod:`.population`, :mod:`.batch`). :mod:`.mjcf` writes a planar mechanism as a MuJoCo
model. The names below load their module on first use (``import assur`` stays light).
"""
from __future__ import annotations

__all__ = ["PopulationResult", "Simulation", "cycle_simulation", "mjcf_text", "simulate", "write_mjcf"]


def __getattr__(name):
    if name == "simulate":
        from .api import simulate as value
    elif name == "Simulation":
        from .result import Simulation as value
    elif name == "PopulationResult":
        from .population import PopulationResult as value
    elif name == "write_mjcf":
        from .mjcf import write_mjcf as value
    elif name == "mjcf_text":
        from .mjcf import mjcf_text as value
    elif name == "cycle_simulation":
        from .cycle import cycle_simulation as value
    else:
        raise AttributeError(f"module 'assur.dynamics' has no attribute {name!r}")
    globals()[name] = value
    return value
