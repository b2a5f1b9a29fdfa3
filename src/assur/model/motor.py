"""The motor of a driver: what turns the crank (or pushes the actuator) in a forward-dynamics run.

All numbers are SI (N·m, N, rad/s, m/s, V, Ω, A, Pa, m², m³/s, kg·m²). A motor is tied to one driver of the
mechanism by name. Its characteristic gives the effort at the motor's own shaft (or rod) as a function of its
speed; a gearbox (``gear_ratio``, or a screw ``lead`` for a rotary motor on a linear driver) and its
``efficiency`` carry it to the driver's input. Nothing here evaluates the characteristic: see
:mod:`assur.dynamics.motors`.

Kinds (the keys each needs):

=============  =======================================================================================
``torque``     a constant torque ``torque`` (N·m)
``dc``         a permanent-magnet DC motor: ``stall_torque`` and ``no_load_speed`` (optional
               ``stall_current`` to report the current), or ``torque_constant``, ``resistance`` and
               ``voltage``
``induction``  an induction motor by Kloss's formula: ``breakdown_torque``, ``breakdown_slip`` and
               ``synchronous_speed``
``table``      torque against speed (``table``: (speed rad/s, torque N·m) rows), or on a linear driver
               force against speed ((m/s, N) rows)
``force``      a constant force ``force`` (N) on a linear driver
``hydraulic``  a valve-controlled cylinder on a linear driver: supply ``pressure`` on the piston ``area``,
               the valve passing the rated ``flow`` at the full pressure drop
=============  =======================================================================================
"""
from __future__ import annotations

from dataclasses import dataclass

#: the motor kinds; those that turn a shaft and those that push along the actuator
MOTOR_KINDS = ("torque", "dc", "induction", "table", "force", "hydraulic")
ROTARY_MOTOR_KINDS = ("torque", "dc", "induction")
LINEAR_MOTOR_KINDS = ("force", "hydraulic")


@dataclass(frozen=True, slots=True)
class Motor:
    """A motor tied to the driver named ``driver``; the fields a ``kind`` does not use are None.

    ``linear_table``: a ``table`` kind whose rows are (m/s, N) on the actuator itself rather than (rad/s, N·m)
    at a motor shaft. ``gear_ratio``: motor turns per turn of a rotary driver; ``lead``: metres of a linear
    driver per motor turn (a rotary motor on a screw). ``efficiency`` in (0, 1]: the share of the motor's power
    the mechanism receives (and, driven backwards, the motor receives 1/η of it as torque). ``rotor_inertia``
    (kg·m², at the motor shaft) and ``flywheel_inertia`` (kg·m², on the driver's crank)."""
    kind: str
    driver: str
    torque: float | None = None
    force: float | None = None
    stall_torque: float | None = None
    no_load_speed: float | None = None
    stall_current: float | None = None
    torque_constant: float | None = None
    resistance: float | None = None
    voltage: float | None = None
    breakdown_torque: float | None = None
    breakdown_slip: float | None = None
    synchronous_speed: float | None = None
    table: tuple[tuple[float, float], ...] = ()
    linear_table: bool = False
    pressure: float | None = None
    area: float | None = None
    flow: float | None = None
    gear_ratio: float = 1.0
    lead: float | None = None
    efficiency: float = 1.0
    rotor_inertia: float = 0.0
    flywheel_inertia: float = 0.0

    @property
    def pushes(self) -> bool:
        """True when the motor acts along a linear driver itself (force, hydraulic, a force–speed table)."""
        return self.kind in LINEAR_MOTOR_KINDS or (self.kind == "table" and self.linear_table)


__all__ = ["LINEAR_MOTOR_KINDS", "MOTOR_KINDS", "Motor", "ROTARY_MOTOR_KINDS"]
