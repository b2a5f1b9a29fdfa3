"""Motor characteristics and the drive train, as seen from the driver's input coordinate.

A :class:`~assur.model.motor.Motor` gives the effort at the motor's own shaft (N·m) or rod (N) as a function of
the motor's speed; the drive train turns it into the generalised force at the input q (a crank's angle or an
actuator's length):

* the motor turns ``ratio`` radians per unit of q: a crank's gearbox ``gear_ratio`` (motor turns per crank
  turn), a screw's 2π/``lead`` (rad per metre), 1 for a motor that pushes the actuator itself;
* its speed is ω_m = ratio·q̇ and the generalised force Q = ratio·τ·η when the motor delivers power (τ·ω_m ≥ 0,
  including at rest) and ratio·τ/η when the mechanism drives it backwards (η the ``efficiency``);
* the rotor's inertia adds ratio²·J_rotor to the reduced inertia J*, a flywheel on the crank its own.

Characteristics (each exact for its model; the assumptions are stated in docs/dynamics.md):

* ``torque``/``force``: constant;
* ``dc``: τ = T_s·(1 − ω/ω₀) (stall torque T_s, no-load speed ω₀), or from the torque constant k, the winding
  resistance R and the supply voltage V: i = (V − k·ω)/R, τ = k·i (T_s = kV/R, ω₀ = V/k; no inductance, no
  friction, no current limit). The current is reported when it is known (k, or ``stall_current``: k = T_s/I_s);
* ``induction``: Kloss's formula τ = 2·T_b/(s/s_b + s_b/s), slip s = (ω_s − ω)/ω_s;
* ``table``: linear interpolation of the (speed, effort) rows, continued linearly beyond the first and last rows;
* ``hydraulic``: F = p·A·(1 − (v/v_max)·|v/v_max|), v_max = Q_rated/A: the valve's pressure drop grows with the
  square of the flow and takes the whole supply pressure p at the rated flow.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..model.motor import Motor

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class DriveTrain:
    """A motor and its gearbox as the input q sees them. ``ratio``: motor rad (or m) per unit of q;
    ``inertia``: ratio²·J_rotor + J_flywheel (kg·m², or kg for a linear input) added to J*."""
    motor: Motor
    ratio: float
    inertia: float
    rotary_input: bool

    # -- the motor's own characteristic ------------------------------------------------------------------
    def effort(self, motor_speed):
        """The effort at the motor's shaft (N·m) or rod (N) at ``motor_speed`` (rad/s or m/s), array-wise."""
        mo, w = self.motor, np.asarray(motor_speed, dtype=float)
        k = mo.kind
        if k == "torque":
            return np.full_like(w, mo.torque)
        if k == "force":
            return np.full_like(w, mo.force)
        if k == "dc":
            stall, free = self.dc_constants()
            return stall * (1.0 - w / free)
        if k == "induction":
            s = (mo.synchronous_speed - w) / mo.synchronous_speed
            sb = mo.breakdown_slip
            with np.errstate(divide="ignore", invalid="ignore"):
                tau = 2.0 * mo.breakdown_torque / (s / sb + sb / s)
            return np.where(s == 0, 0.0, tau)
        if k == "table":
            xs, ys = (np.array(c, dtype=float) for c in zip(*mo.table))
            out = np.interp(w, xs, ys)
            lo = ys[0] + (w - xs[0]) * (ys[1] - ys[0]) / (xs[1] - xs[0])
            hi = ys[-1] + (w - xs[-1]) * (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
            return np.where(w < xs[0], lo, np.where(w > xs[-1], hi, out))
        if k == "hydraulic":
            r = w / self.free_speed()
            return mo.pressure * mo.area * (1.0 - r * np.abs(r))
        raise SpecError([("motor.kind", f"unknown motor kind {k!r}")])

    def dc_constants(self) -> tuple[float, float]:
        """(stall torque N·m, no-load speed rad/s) of a DC motor."""
        mo = self.motor
        if mo.stall_torque is not None:
            return mo.stall_torque, mo.no_load_speed
        return mo.torque_constant * mo.voltage / mo.resistance, mo.voltage / mo.torque_constant

    def torque_constant(self) -> float | None:
        """k (N·m/A) of a DC motor when the file gives it or its stall current; else None."""
        mo = self.motor
        if mo.kind != "dc":
            return None
        if mo.torque_constant is not None:
            return mo.torque_constant
        return mo.stall_torque / mo.stall_current if mo.stall_current else None

    def current(self, effort):
        """The motor current (A) at the motor effort ``effort`` (N·m), or None when it is not defined."""
        k = self.torque_constant()
        return None if k is None else np.asarray(effort, dtype=float) / k

    def free_speed(self) -> float:
        """The motor speed (rad/s or m/s) where its effort falls to zero (inf for a constant effort)."""
        mo = self.motor
        if mo.kind == "dc":
            return self.dc_constants()[1]
        if mo.kind == "induction":
            return mo.synchronous_speed
        if mo.kind == "hydraulic":
            return mo.flow / mo.area
        if mo.kind == "table":
            xs, ys = (np.array(c, dtype=float) for c in zip(*mo.table))
            return _table_zero(xs, ys)
        return math.inf

    # -- at the input ------------------------------------------------------------------------------------
    def generalised(self, qdot):
        """(Q (N·m or N) at the input, motor effort, motor speed), each shaped like ``qdot`` (rad/s or m/s)."""
        w = self.ratio * np.asarray(qdot, dtype=float)
        tau = self.effort(w)
        eta = self.motor.efficiency
        if eta == 1.0:
            return self.ratio * tau, tau, w
        delivering = tau * w >= 0
        return self.ratio * tau * np.where(delivering, eta, 1.0 / eta), tau, w

    def damping(self) -> float:
        """−dQ/dq̇ at zero speed (N·m·s/rad or N·s/m), the motor's speed regulation seen at the input (0 for a
        constant effort): a measure of how stiff the equation of motion is."""
        h = 1e-6 * (self.free_speed() if math.isfinite(self.free_speed()) else 1.0) / self.ratio
        q = np.array([0.0, h])
        Q = self.generalised(q)[0]
        return float(max(0.0, -(Q[1] - Q[0]) / h))

    def input_free_speed(self) -> float:
        """The input speed (rad/s or m/s) at which the motor's effort falls to zero."""
        return self.free_speed() / self.ratio


def _table_zero(xs, ys) -> float:
    """The speed where a table's effort first falls to zero going up (linear), else inf."""
    for j in range(len(xs) - 1):
        if ys[j] > 0 >= ys[j + 1]:
            return float(xs[j] + (xs[j + 1] - xs[j]) * ys[j] / (ys[j] - ys[j + 1]))
    if ys[-1] > 0 and ys[-1] < ys[-2]:
        return float(xs[-1] + ys[-1] * (xs[-1] - xs[-2]) / (ys[-2] - ys[-1]))
    return math.inf


def drive_train(motor: Motor, plan) -> DriveTrain:
    """The drive train of ``motor`` on its driver of ``plan``; SpecError when the driver is not an input of the
    plan."""
    names = list(plan.input_names)
    if motor.driver not in names:
        raise SpecError([("motor.driver", f"unknown driver {motor.driver!r} (known: {', '.join(names)})")])
    rotary = plan.input_kinds[names.index(motor.driver)] == "rotary"
    if motor.pushes:
        ratio = 1.0
    elif rotary:
        ratio = motor.gear_ratio
    else:
        ratio = TWO_PI / motor.lead
    inertia = ratio * ratio * (0.0 if motor.pushes else motor.rotor_inertia) + motor.flywheel_inertia
    return DriveTrain(motor, float(ratio), float(inertia), rotary)


__all__ = ["DriveTrain", "drive_train"]
