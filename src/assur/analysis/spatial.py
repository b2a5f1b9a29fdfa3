"""Derived outputs of spatial R–S–S dyads (paper 003, docs/papers/003.md §5): rocker angle θ4, swing,
transmission angles μ_int and μ_T, dead centres (root-solved), buildable ranges, the branch s and
the paper's W, and the closed-form extremes of μ_int. All angles in radians, lengths in metres.

For the dyad solving B (rocker hinged at D with axis e, coupler from A):
- θ4 = atan2(u_r·e_Y2, u_r·e_X2), u_r the unit normal part of B − D, in the axis frame (8);
- μ_int = ∠ABD = arccos((l_c² + l_r² − |A − D|²)/(2 l_c l_r));
- μ_T = asin(|u·t|), u = Ort(A − B), t = Ort(e × (B − D)) the direction of B's velocity;
- dead centres: the rocker stops where (B − A)·A' = 0 (A' = dA/dq), located by Brent's method.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..kernels import spatial as V
from .overview import finite_or_none
from .sampling import CYCLE_STEPS, TWO_PI, Cycle, root_between, sign_changes
from .transmission import buildable_ranges


@dataclass(frozen=True)
class DyadGeometry:
    """Per-sample geometry of one R–S–S dyad: arrays (...) (vectors (..., 3))."""
    point: str
    rocker: str
    coupler: str
    A: np.ndarray
    B: np.ndarray
    D: np.ndarray
    axis_frame: np.ndarray          # (..., 3, 3) columns e_X2, e_Y2, e_Z2
    rocker_length: np.ndarray
    coupler_length: np.ndarray


def dyads(plan, state, params=None) -> list[DyadGeometry]:
    """The R–S–S dyads of a spatial plan with their positions in ``state``."""
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    out = []
    for st in plan.rss_steps():
        D, Ap, Bp, ci = st.pivot, st.start, st.joint, st.coupler
        E = V.axis_frame(params[..., plan.param_index(f"{D}.axis.gamma1")],
                         params[..., plan.param_index(f"{D}.axis.gamma2")])
        out.append(DyadGeometry(Bp, plan.body_names[st.body], plan.body_names[ci],
                                state.pos[..., plan.point_index(Ap), :], state.pos[..., plan.point_index(Bp), :],
                                state.pos[..., plan.point_index(D), :], E,
                                params[..., st.rocker_length_param], params[..., st.coupler_length_param]))
    return out


def rocker_angle(g: DyadGeometry) -> np.ndarray:
    """θ4 (...): the rocker's angle about its axis, from e_X2 towards e_Y2 (docs/papers/003.md §5)."""
    r = g.B - g.D
    e = g.axis_frame[..., :, 2]
    n = r - np.sum(r * e, -1)[..., None] * e
    return np.arctan2(np.sum(n * g.axis_frame[..., :, 1], -1), np.sum(n * g.axis_frame[..., :, 0], -1))


def mu_int(g: DyadGeometry) -> np.ndarray:
    """The classic transmission angle ∠ABD (...) in [0, π]."""
    d2 = np.sum((g.A - g.D) ** 2, -1)
    c = (g.coupler_length ** 2 + g.rocker_length ** 2 - d2) / (2 * g.coupler_length * g.rocker_length)
    return np.arccos(np.clip(c, -1.0, 1.0))


def mu_t(g: DyadGeometry) -> np.ndarray:
    """The effective spatial transmission angle asin(|u·t|) (...) in [0, π/2]; 90° is ideal."""
    u = g.A - g.B
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    t = np.cross(g.axis_frame[..., :, 2], g.B - g.D)
    t = t / np.linalg.norm(t, axis=-1, keepdims=True)
    return np.arcsin(np.clip(np.abs(np.sum(u * t, -1)), 0.0, 1.0))


def branch_s(g: DyadGeometry) -> np.ndarray:
    """s = sign det[A − D, e, B − D] (...)."""
    return V.branch_sign(g.A - g.D, g.axis_frame[..., :, 2], g.B - g.D)


def paper_w(g: DyadGeometry) -> np.ndarray:
    """The W of the paper's eq. (21) for the solved assembly, s·sign(V3_X), V3 = (A − D) × e (NaN at V3_X = 0)."""
    return V.paper_w(g.A - g.D, g.axis_frame[..., :, 2], branch_s(g))


def stopping_function(plan, state, point: str) -> np.ndarray:
    """(B − A)·A' (...): zero where the rocker solving ``point`` stops (a dead centre)."""
    st = next(s for s in plan.rss_steps() if s.key_point == point)
    ia, ib = plan.point_index(st.start), plan.point_index(point)
    dA = state.dpos_dq[..., ia, :, 0]
    return np.sum((state.pos[..., ib, :] - state.pos[..., ia, :]) * dA, -1)


def distance_extremes(plan, params=None, point: str | None = None) -> dict:
    """Closed-form extremes of |A − D| over a crank turn, when A is the crank's arm (docs/papers/003.md §5):
    with the crank circle of centre O' (radius ρ, axis e_c) and w = D − O', |A − D| is least where the
    arm points along the normal part w_n of w, |A − D|² = (ρ ∓ |w_n|)² + (w·e_c)². Returns
    {'q_min', 'q_max', 'd_min', 'd_max', 'mu_int_min', 'mu_int_max'} (rad, m), or {} when A is not a crank arm."""
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    rss = [s for s in plan.rss_steps() if point is None or s.key_point == point]
    if not rss:
        return {}
    st = rss[0]
    D, Ap = st.pivot, st.start
    crank = next((c for c in plan.crank_steps() if c.arm == Ap), None)
    if crank is None:
        return {}
    pivot, il, ih, iz, sense = crank.pivot, crank.length_param, crank.axial_param, crank.zero_param, crank.sense
    pi = plan.param_index
    E = V.axis_frame(params[pi(f"{pivot}.axis.gamma1")], params[pi(f"{pivot}.axis.gamma2")])
    O = np.array([params[pi(f"{pivot}.{c}")] for c in "xyz"])
    Dv = np.array([params[pi(f"{D}.{c}")] for c in "xyz"])
    length, h = params[il], params[ih]
    rho = math.sqrt(max(length * length - h * h, 0.0))
    w = Dv - (O + h * E[:, 2])
    wa = float(w @ E[:, 2])
    wn = w - wa * E[:, 2]
    r = float(np.linalg.norm(wn))
    theta = math.atan2(float(wn @ E[:, 1]), float(wn @ E[:, 0]))
    q_min = (sense * (theta - params[iz])) % TWO_PI
    q_max = (q_min + math.pi) % TWO_PI
    d_min, d_max = math.hypot(rho - r, wa), math.hypot(rho + r, wa)
    lr, lc = params[st.rocker_length_param], params[st.coupler_length_param]

    def mu(d):
        c = (lc * lc + lr * lr - d * d) / (2 * lc * lr)
        return math.acos(c) if abs(c) <= 1 else float("nan")

    return {"q_min": q_min, "q_max": q_max, "d_min": d_min, "d_max": d_max,
            "mu_int_at_d_min": mu(d_min), "mu_int_at_d_max": mu(d_max)}


@dataclass(frozen=True)
class DeadCentre:
    angle: float            # crank input q (rad)
    kind: str               # 'extended' (|A D| ... largest rocker angle side) | 'folded'
    link: str               # the rocker
    rocker_angle: float     # θ4 there (rad)

    def _repr_html_(self) -> str:
        from ..model.display import dataclass_table
        return dataclass_table(self, "Dead centre", units={"angle": "rad", "rocker_angle": "rad"})


@dataclass(frozen=True)
class DyadSummary:
    point: str
    rocker: str
    coupler: str
    branch_s: int
    paper_w: list = field(default_factory=list)      # distinct W values over the turn (NaN dropped)
    rocker_angle_min: float = float("nan")
    rocker_angle_max: float = float("nan")
    swing: float = float("nan")
    mu_int_min: float = float("nan")
    mu_int_max: float = float("nan")
    mu_t_min: float = float("nan")
    mu_t_max: float = float("nan")
    dead_centres: tuple = ()
    v3x_changes_sign: bool = False

    def as_dict(self) -> dict:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__ if k != "dead_centres"}
        d["dead_centres"] = [{"angle": c.angle, "kind": c.kind, "link": c.link, "rocker_angle": c.rocker_angle}
                             for c in self.dead_centres]
        return d

    def _repr_html_(self) -> str:
        from ..model.display import dataclass_table
        units = {k: "rad" for k in self.__dataclass_fields__ if k.startswith(("rocker_angle_", "swing", "mu_"))}
        return dataclass_table(self, f"R–S–S dyad at {self.point}", units=units)


def _unwrap_cyclic(theta):
    """Unwrapped θ over a sampled turn, NaN kept."""
    out = np.array(theta, dtype=float)
    ok = np.isfinite(out)
    out[ok] = np.unwrap(out[ok])
    return out


def dyad_summaries(plan, params=None, steps: int = CYCLE_STEPS) -> list[DyadSummary]:
    """Every R–S–S dyad's outputs over one crank turn (needs one rotary input).

    plan: a plan (sampled here at ``steps`` inputs and ``params``) or a
    :class:`~assur.analysis.sampling.Cycle` (its solved grid and parameters)."""
    cyc = Cycle.of(plan, params, steps)
    plan = cyc.plan
    q, st = cyc.grid()
    out = []
    for g in dyads(plan, st, cyc.params):
        th = rocker_angle(g)
        thu = _unwrap_cyclic(th)
        f = stopping_function(plan, st, g.point)

        def stop(t, point=g.point):
            s1 = cyc.state_at(np.array([t]), order=1)
            return float(stopping_function(plan, s1, point)[0])

        dcs = []
        for i in sign_changes(q, f):
            a = q[i]
            b = q[i + 1] if i + 1 < len(q) else TWO_PI
            r = root_between(stop, a, b) % TWO_PI
            s1 = cyc.state_at(np.array([r]), order=0)
            g1 = next(d for d in dyads(plan, s1, cyc.params) if d.point == g.point)
            dcs.append((r, float(rocker_angle(g1)[0]), _extended(plan, s1, g1)))
        ok = np.isfinite(th)
        s_vals = branch_s(g)[ok]
        w_vals = paper_w(g)[ok]
        v3x = np.cross(g.A - g.D, g.axis_frame[..., :, 2])[..., 0][ok]
        swing = float(np.nanmax(thu) - np.nanmin(thu)) if ok.any() else float("nan")
        kinds = []
        if len(dcs) == 2:
            # the two stops: the swing is the (wrapped) difference of θ4 there
            d = (dcs[0][1] - dcs[1][1] + math.pi) % TWO_PI - math.pi
            swing = abs(d)
        kinds = [c[2] for c in dcs]
        centres = tuple(DeadCentre(c[0], k, g.rocker, c[1]) for c, k in zip(dcs, kinds))
        lo, hi = (float(np.nanmin(thu)), float(np.nanmax(thu))) if ok.any() else (float("nan"),) * 2
        if len(dcs) == 2:
            lo, hi = sorted([dcs[0][1], dcs[1][1]])
            if hi - lo > math.pi:
                lo, hi = hi - TWO_PI, lo
        mi, mt = mu_int(g), mu_t(g)
        out.append(DyadSummary(
            g.point, g.rocker, g.coupler, int(s_vals[0]) if len(s_vals) else 0,
            sorted({float(w) for w in w_vals[np.isfinite(w_vals)]}),
            lo, hi, swing, _nanmin(mi), _nanmax(mi), _nanmin(mt), _nanmax(mt), centres,
            bool(np.any(v3x > 0) and np.any(v3x < 0))))
    return out


def _extended(plan, state, g) -> str:
    """'extended' when the coupler points away from the crank's axis along the crank arm
    ((B − A)·u_r > 0, u_r the crank's radial unit vector), 'folded' when towards it; 'stop' when
    A is not a crank's arm."""
    start = next(s for s in plan.rss_steps() if s.key_point == g.point).start
    crank = next((c for c in plan.crank_steps() if c.arm == start), None)
    if crank is None:
        return "stop"
    u_r = state.body_frame[..., crank.body, :, 0]
    return "extended" if float(np.sum((g.B - g.A) * u_r, -1).ravel()[0]) > 0 else "folded"


def _nanmin(x):
    return float(np.nanmin(x)) if np.isfinite(x).any() else float("nan")


def _nanmax(x):
    return float(np.nanmax(x)) if np.isfinite(x).any() else float("nan")


def spatial_summary(cycle, out: dict) -> dict:
    """The cycle entries of a spatial plan's JSON summary into ``out`` (``assur analyze``): buildability with the
    buildable crank ranges, and every dyad's branch, swing, transmission angles and dead centres, from the one
    solved turn of ``cycle`` (a Cycle or Study of a one-input plan; ``cycle.buildable`` and ``cycle.spatial`` when
    it is a Study)."""
    b = getattr(cycle, "buildable", None)
    ranges, bad, _ = (b.ranges, b.unbuildable, b.steps) if b is not None else buildable_ranges(cycle)
    out["unbuildable"] = bad
    out["buildable_ranges"] = [{"start": a, "end": b} for a, b in ranges]
    out["full_rotation"] = bad == 0
    sums = getattr(cycle, "spatial", None)
    sums = dyad_summaries(cycle) if sums is None else sums
    out["transmission_angles"] = {}
    out["dead_centres"] = []
    for s in sums:
        out["transmission_angles"][f"{s.point} (μ_T)"] = {
            "min": finite_or_none(s.mu_t_min), "max": finite_or_none(s.mu_t_max),
            "worst_deviation_from_90": finite_or_none(math.pi / 2 - s.mu_t_min)}
        out["transmission_angles"][f"{s.point} (μ_int)"] = {
            "min": finite_or_none(s.mu_int_min), "max": finite_or_none(s.mu_int_max),
            "worst_deviation_from_90": finite_or_none(max(abs(s.mu_int_min - math.pi / 2), abs(s.mu_int_max - math.pi / 2)))}
        out["dead_centres"] += [{"angle": c.angle, "kind": c.kind, "link": c.link} for c in s.dead_centres]
    out["dyads"] = [_json(s.as_dict()) for s in sums]
    return out


def _json(d):
    return {k: (finite_or_none(v) if isinstance(v, float) else v) for k, v in d.items()}
