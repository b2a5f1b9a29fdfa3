"""Design quantities from the forces over one working cycle: what sizes a motor, a flywheel, the bearings.

On a uniform grid of one crank turn (or samples of a stroke):

* peak and RMS driving effort (torque N·m or force N), its mean;
* the motor power at the file's speed: P = Q·q̇ (W), its peak and mean;
* the energy per cycle ∮Q dq (J; zero for gravity and inertia alone, the work done on the loads otherwise);
* the fluctuation of kinetic energy ΔE = max − min of ∫(Q − Q̄) dq (J): with a motor of constant
  torque Q̄, the work the flywheel must store and give back; the flywheel inertia for a coefficient of
  speed fluctuation δ = (ω_max − ω_min)/ω_mean is I = ΔE / (δ·ω²) (kg·m²);
* the shaking force and moment on the frame (peak magnitudes);
* the peak load of every joint (N), for bearing and pin sizing.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .result import Forces

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class DriveSummary:
    """Design quantities of one driver over one cycle or stroke (SI). ``rotary``: a crank (turn), else a stroke."""
    driver: str
    rotary: bool
    speed: float
    peak: float
    rms: float
    mean: float
    power_peak: float
    power_mean: float
    energy: float
    energy_fluctuation: float
    shaking_force_peak: float
    shaking_moment_peak: float
    joint_peaks: dict = field(default_factory=dict)
    samples: int = 0
    singular: int = 0

    def flywheel_inertia(self, delta: float) -> float:
        """The flywheel inertia (kg·m²) that keeps the coefficient of speed fluctuation at ``delta``:
        I = ΔE / (δ·ω²)."""
        if not self.rotary:
            raise ValueError("a flywheel needs a crank (a rotary driver)")
        if not delta > 0:
            raise ValueError(f"the coefficient of speed fluctuation must be positive: {delta!r}")
        return self.energy_fluctuation / (delta * self.speed ** 2)

    def as_dict(self) -> dict:
        d = {k: getattr(self, k) for k in ("driver", "rotary", "speed", "peak", "rms", "mean", "power_peak",
                                            "power_mean", "energy", "energy_fluctuation", "shaking_force_peak",
                                            "shaking_moment_peak", "samples", "singular")}
        d["joint_peaks"] = dict(self.joint_peaks)
        return d


def drive_summary(f: Forces, q, *, driver: int = 0, turn: bool | None = None) -> DriveSummary:
    """The design quantities of ``f`` (shape (n,), one design) solved at the inputs ``q (n,)``: a uniform
    grid of one turn (``turn`` True, the default for a crank: periodic integrals) or a stroke (trapezoids).
    Samples that are singular or do not assemble are left out of peaks and reported in ``singular``;
    the integrals then are NaN (they need the whole cycle)."""
    plan = f.plan
    q = np.asarray(q, dtype=float)
    Q = np.asarray(f.driver[..., driver], dtype=float)
    if Q.shape != q.shape or Q.ndim != 1:
        raise ValueError(f"drive_summary needs one design's forces along q: shapes {Q.shape} and {q.shape}")
    rotary = plan.input_kinds[driver] == "rotary"
    turn = rotary if turn is None else turn
    ok = np.isfinite(Q)
    speed = float(np.broadcast_to(f.qdot, f.driver.shape)[0, driver]) if Q.size else 0.0
    P = Q * speed
    if turn:
        mean = float(np.mean(Q)) if ok.all() else math.nan
        energy = mean * TWO_PI
        dq = TWO_PI / len(q)
        work = np.concatenate([[0.0], np.cumsum((Q - mean) * dq)])
        fluct = float(np.ptp(work)) if ok.all() else math.nan
        rms = float(np.sqrt(np.mean(Q ** 2))) if ok.all() else math.nan
        power_mean = mean * speed
    else:
        energy = float(np.trapezoid(Q, q)) if ok.all() else math.nan
        span = q[-1] - q[0] if len(q) > 1 else math.nan
        mean = energy / span
        rms = float(np.sqrt(np.trapezoid(Q ** 2, q) / span)) if ok.all() else math.nan
        work = np.concatenate([[0.0], np.cumsum(0.5 * (Q[1:] + Q[:-1] - 2 * mean) * np.diff(q))])
        fluct = float(np.ptp(work)) if ok.all() else math.nan
        power_mean = mean * speed
    with np.errstate(invalid="ignore"):
        mags = f.magnitudes
    joints = {}
    for k in f.joint_pairs:
        key = f"{f.pair_names[k]} ({f.pair_bodies[k][0]}–{f.pair_bodies[k][1]})"
        joints[key] = float(np.nanmax(mags[..., k])) if np.isfinite(mags[..., k]).any() else math.nan
    shake = np.sqrt(np.sum(f.frame_force ** 2, axis=-1))
    moment = np.abs(f.frame_moment) if np.ndim(f.frame_moment) == np.ndim(shake) \
        else np.sqrt(np.sum(f.frame_moment ** 2, axis=-1))
    return DriveSummary(plan.input_names[driver], rotary, speed,
                        peak=float(np.nanmax(np.abs(Q))) if ok.any() else math.nan, rms=rms, mean=mean,
                        power_peak=float(np.nanmax(np.abs(P))) if ok.any() else math.nan, power_mean=power_mean,
                        energy=energy, energy_fluctuation=fluct,
                        shaking_force_peak=float(np.nanmax(shake)) if ok.any() else math.nan,
                        shaking_moment_peak=float(np.nanmax(moment)) if ok.any() else math.nan,
                        joint_peaks=joints, samples=int(q.size), singular=int(np.sum(~ok)))
