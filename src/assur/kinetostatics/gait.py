"""Walking legs: the body weight carried by the feet on the ground, and the module's driving torque.

The model (documented in docs/format.md, ``[gait] weight``/``friction``):

* the legs of a module turn on one crank shaft, leg k at crank angle q + phases[k];
* a foot carries load only in its contact (support) arc, the arc of :func:`assur.analysis.gait.gait_metrics`;
* the weight W is shared equally by the feet on the ground: each carries N = W / n_on(q), pushed up
  (along ``gait.up``) by the ground;
* with ``friction = μ`` the ground also pushes along the stride axis, against the foot's slip: the
  ground moves under the body at the foot's mean support velocity (the body walks at the stride speed),
  the slip is the foot's stride velocity minus that, and the horizontal reaction is −μ·N·sign(slip)
  (kinetic Coulomb friction; zero where the slip is below 10⁻⁹ of the mean support speed);
* where no foot is on the ground (a module with gaps in support) the weight is carried by nothing and
  the samples are reported with zero foot load.

:func:`population_foot_loads` is the same sharing rule on uniform samples of a population of designs (what
dimensional synthesis uses): the contact arc is the sampled one of
:func:`assur.analysis.gait.population_gait`, and the legs' phases fall on whole samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..kernels.arcs import arc_mask, in_arc, population_contact
from .api import forces
from .result import Forces

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class GaitForces:
    """The forces of every leg of a walking module over one crank turn.

    ``q (n,)`` crank angles of the first leg; ``forces`` a :class:`Forces` of shape (n, n_legs) (leg k at
    q + phases[k]); ``on_ground (n, n_legs)``; ``foot_force (n, n_legs, 2)`` the ground's force on each foot
    (N); ``module_driver (n,)`` the torque the common shaft needs, Σ over the legs (N·m).
    """
    q: np.ndarray
    phases: tuple[float, ...]
    forces: Forces
    on_ground: np.ndarray
    foot_force: np.ndarray
    module_driver: np.ndarray
    weight: float
    friction: float | None


def in_contact(metrics, q) -> np.ndarray:
    """(...) bool: crank angles q (...) inside the contact arc of ``metrics``."""
    return in_arc(q, metrics.contact_start, metrics.contact_end - metrics.contact_start)


def gait_forces(cycle, metrics, *, weight: float | None = None, friction: float | None = None,
                joint_friction: bool = False, phases=None) -> GaitForces:
    """The forces of a walking module carrying its body weight over the turn of ``cycle`` (a Cycle or Study of the
    leg: its solved run), with the leg's contact arc from ``metrics`` (its
    :class:`~assur.analysis.gait.GaitMetrics`; the model of the module docstring). ``weight`` (N) and ``friction``
    default to the file's ``[gait]``; ``phases`` to its legs. A leg whose phase falls on a sample of the run reads
    the run's State shifted by its phase; otherwise the legs are solved at q + phase (one solve)."""
    plan = cycle.plan
    m = plan.mechanism
    if m.gait is None:
        raise SpecError([("gait", "the mechanism has no [gait] table: name its foot to carry a weight")])
    W = m.gait.weight if weight is None else float(weight)
    if W is None:
        raise SpecError([("gait.weight", "no body weight given (in the file's [gait] table or as weight=)")])
    mu = m.gait.friction if friction is None else friction
    foot, ground, up = m.gait.foot, m.gait.ground, m.gait.up_vector
    ph = np.asarray(m.gait.phases if phases is None else phases, dtype=float)
    q, state = cycle.grid()
    n = len(q)
    qq = q[:, None] + ph[None, :]
    try:
        shifts = phase_shifts(ph, n)
        legs = state.take((np.arange(n)[:, None] + shifts[None, :]) % n)
    except SpecError:
        from ..engine import solve
        legs = solve(plan, cycle.params, qq[..., None], order=2)
    on = in_contact(metrics, qq)
    n_on = on.sum(axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        N = np.where(on, W / np.maximum(n_on, 1), 0.0)
    up_v, ground_v = np.asarray(up, dtype=float), np.asarray(ground, dtype=float)
    load = N[..., None] * up_v
    if mu:
        v = legs.point(foot).vel @ ground_v
        mean_support = metrics.support_vx.mean * np.sign(np.nanmean(np.where(on, v, np.nan)))
        slip = v - mean_support
        dead = 1e-9 * max(abs(metrics.support_vx.mean), 1e-300)
        load = load - (mu * N * np.where(np.abs(slip) > dead, np.sign(slip), 0.0))[..., None] * ground_v
    f = forces(plan, cycle.params, qq[..., None], point_loads=[(foot, load)], friction=joint_friction, state=legs)
    return GaitForces(q, tuple(float(p) for p in ph), f, on, load, f.driver[..., 0].sum(axis=1), float(W), mu)


def phase_shifts(phases, samples: int) -> np.ndarray:
    """(n_legs,) int: the legs' phase offsets (rad) in samples of a uniform grid of ``samples`` per turn.
    SpecError when an offset does not fall on a sample (within 10⁻⁹ of a sample)."""
    s = np.asarray(phases, dtype=float) * samples / TWO_PI
    k = np.rint(s)
    if not np.all(np.abs(s - k) <= 1e-9 * max(1.0, float(samples))):
        shown = ", ".join(f"{math.degrees(p):g}°" for p in np.asarray(phases, dtype=float))
        raise SpecError([("gait.phases", f"the legs' phases ({shown}) must fall on the {samples} samples of the "
                                         f"cycle (multiples of {360 / samples:g}°)")])
    return np.mod(k.astype(np.int64), samples)


def population_foot_loads(pos_foot, valid, phases, weight: float, up, ground) -> np.ndarray:
    """The ground's force on every leg's foot of a population of walking modules, from uniform samples.

    pos_foot: (D, M, 2) the foot of one leg at the M inputs ``linspace(0, 2π, M, endpoint=False)`` of D designs;
    valid: (D, M) bool; phases: (n_legs,) rad, each on a sample (:func:`phase_shifts`); weight: W (N); up,
    ground: (2,) directions. The rule of the module docstring: leg k at module sample j stands at input
    q_j + phases[k]; its foot is on the ground where that sample is in the design's contact arc (the sampled arc
    of :func:`assur.analysis.gait.population_contact`); each foot on the ground carries N = W / n_on, pushed
    along ``up``. Returns (D, M, n_legs, 2) forces (N), indexed like :attr:`GaitForces.foot_force` (module
    sample j, leg k); NaN for a design with an unassembled sample (its contact arc is undefined)."""
    pos_foot = np.asarray(pos_foot, dtype=float)
    D, M = pos_foot.shape[:2]
    start, width = population_contact(pos_foot, ground=ground, up=up)
    shifts = phase_shifts(phases, M)
    on = np.stack([arc_mask(start, width, M, s) for s in shifts], axis=-1)          # (D, M, n_legs)
    n_on = on.sum(axis=-1, keepdims=True)
    N = np.where(on, float(weight) / np.maximum(n_on, 1), 0.0)
    N = np.where(np.all(np.asarray(valid, dtype=bool), axis=1)[:, None, None], N, np.nan)
    return N[..., None] * np.asarray(up, dtype=float)
