"""Linear actuators in a solved state: lengths, rotations and their rates; pairs of rods that share
a joint (paper 002's K_ω and areal velocities); the stroke envelope and the buildable stroke.

For any mechanism with actuators (driven or passive), :func:`actuator_motions` gives each rod's
length L, its change from the sketch, the rotation θ of its direction from the sketch direction,
their analogues (d/dq, d²/dq² by the driving input) and time derivatives (from the state's own
velocities and accelerations, so any time law applies). :func:`rod_pairs` relates a driven rod to each
passive rod hinged at the same joint: K_ω = ω_b/ω_l and the ratio of the rods' areal velocities
(½·L²·ω), which for a joint in a straight guide is the constant h_O/h_A (docs/papers/002.md §6), and the
ratio of the triangles swept since the start. :func:`stroke_envelope` samples a working stroke along
a time law and locates the interior extrema of every quantity by a root solve of its derivative;
:func:`stroke_ranges` names the parts of a stroke that cannot be assembled. Shapes: batch axes
``...`` as the state's; SI units.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SpecError
from ..tolerances import DEFAULT as TOL


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _dot(a, b):
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def _wrap(x):
    return (x + math.pi) % (2 * math.pi) - math.pi


@dataclass(frozen=True)
class ActuatorMotion:
    """One actuator over a batch; every array has the state's batch shape (...).

    ``length`` L (m) and its change ``extension`` = L − L_start; ``angle`` (rad) the rotation of the
    direction ``pivot`` → ``end`` from its start direction, counter-clockwise positive, in (−π, π]
    (the start: the same design at the sketch inputs);
    ``dlength_dq``, ``d2length_dq2``, ``dangle_dq``, ``d2angle_dq2``: analogues by input ``input``;
    ``rate`` = dL/dt (m/s), ``accel`` = d²L/dt², ``omega`` = dθ/dt, ``alpha`` = d²θ/dt² at the
    state's input rates. ``driven``: the actuator is the driver of input ``input``.
    """
    name: str
    pivot: str
    end: str
    driven: bool
    input: int
    start_length: np.ndarray
    length: np.ndarray
    extension: np.ndarray
    angle: np.ndarray
    dlength_dq: np.ndarray
    d2length_dq2: np.ndarray
    dangle_dq: np.ndarray
    d2angle_dq2: np.ndarray
    rate: np.ndarray
    accel: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray

    @property
    def areal_velocity(self) -> np.ndarray:
        """½·L²·ω (m²/s): the rate at which the rod sweeps area about its pivot."""
        return 0.5 * self.length ** 2 * self.omega

    @property
    def lengthening(self) -> np.ndarray:
        """True where the rod grows as the input grows (dL/dq > 0)."""
        return self.dlength_dq > 0


def _length_angle(r, dr, d2r):
    """Length and direction angle of vectors r (..., 2) and their first two derivatives."""
    L = np.hypot(r[..., 0], r[..., 1])
    L2 = L * L
    rd, rx = _dot(r, dr), _cross(r, dr)
    dL = rd / L
    d2L = (_dot(dr, dr) + _dot(r, d2r)) / L - rd * rd / (L2 * L)
    dth = rx / L2
    d2th = _cross(r, d2r) / L2 - 2 * rd * rx / (L2 * L2)
    return L, dL, d2L, dth, d2th


def start_state(state):
    """The state's designs at the sketch inputs (the start of a stroke), positions only, same shape."""
    from ..engine import solve
    plan = state.plan
    q0 = np.broadcast_to(np.asarray(plan.sketch_inputs, dtype=float), state.shape + (plan.n_inputs,))
    return solve(plan, state.params, q0, order=0, backend="numpy")


def actuator_motions(state, input: int = 0, start=None) -> dict[str, ActuatorMotion]:  # noqa: A002
    """Every actuator of ``state.plan``'s mechanism, by name (see :class:`ActuatorMotion`).

    Needs a state solved with ``order=2``; ``start``: :func:`start_state` (computed when not given).
    Samples that cannot be assembled are NaN."""
    plan = state.plan
    m = plan.mechanism
    if state.dpos_dq is None or state.d2pos_dq2 is None:
        raise SpecError([("order", "actuator motions need a state solved with order=2")])
    start = start_state(state) if start is None else start
    driven = {d.actuator: k for k, d in enumerate(m.drivers) if d.kind == "linear"}
    pos, d1, d2 = state.pos, state.dpos_dq[..., input], state.d2pos_dq2[..., input, input]
    vel, acc = state.vel, state.acc
    out = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for ac in m.actuators:
            i, j = plan.point_index(ac.between[0]), plan.point_index(ac.between[1])
            r = pos[..., j, :] - pos[..., i, :]
            L, dL, d2L, dth, d2th = _length_angle(r, d1[..., j, :] - d1[..., i, :], d2[..., j, :] - d2[..., i, :])
            _, rate, accel, omega, alpha = _length_angle(r, vel[..., j, :] - vel[..., i, :],
                                                         acc[..., j, :] - acc[..., i, :])
            s0 = start.pos[..., j, :] - start.pos[..., i, :]
            L0 = np.hypot(s0[..., 0], s0[..., 1])
            angle = _wrap(np.arctan2(r[..., 1], r[..., 0]) - np.arctan2(s0[..., 1], s0[..., 0]))
            out[ac.name] = ActuatorMotion(ac.name, ac.between[0], ac.between[1], driven.get(ac.name) == input, input,
                                          L0, L, L - L0, angle, dL, d2L, dth, d2th, rate, accel, omega, alpha)
    return out


# -- pairs of rods hinged at one joint (paper 002) ------------------------------------------------------
@dataclass(frozen=True)
class RodPair:
    """A driven rod l (``driving``) and a passive rod b (``driven``) hinged at the same ``joint``.

    ``K_omega`` = ω_b/ω_l = (dθ_b/dq)/(dθ_l/dq), independent of the speed (docs/papers/002.md §6, E6);
    ``areal_ratio`` = (L_b²·ω_b)/(L_l²·ω_l): constant h_O/h_A when the joint runs in a straight guide;
    ``area_ratio`` = S_b/S_l, the signed triangles (pivot, joint at the start, joint now) swept since
    the start (NaN at the start itself, where both are zero; its limit there is ``areal_ratio``);
    ``driven_lengthening``: the passive rod grows as the input grows ("past the foot of O").
    """
    driving: str
    driven: str
    joint: str
    K_omega: np.ndarray
    areal_ratio: np.ndarray
    area_ratio: np.ndarray
    driven_lengthening: np.ndarray


def _pivot_of(ac, joint):
    return ac.between[0] if ac.between[1] == joint else ac.between[1]


def rod_pairs(state, motions=None, start=None) -> list[RodPair]:
    """Every (driven rod, passive rod) pair sharing a joint. ``start``: the state at the start of the
    stroke (default: :func:`start_state`)."""
    plan = state.plan
    m = plan.mechanism
    start = start_state(state) if start is None else start
    motions = motions if motions is not None else actuator_motions(state, start=start)
    acts = {a.name: a for a in m.actuators}
    out = []
    for mo in motions.values():
        if not mo.driven:
            continue
        for other in motions.values():
            if other.driven or other.name == mo.name:
                continue
            shared = set(acts[mo.name].between) & set(acts[other.name].between)
            if len(shared) != 1:
                continue
            joint = shared.pop()
            pl, pb = _pivot_of(acts[mo.name], joint), _pivot_of(acts[other.name], joint)
            J = state.pos[..., plan.point_index(joint), :]
            J0 = start.pos[..., plan.point_index(joint), :]
            with np.errstate(invalid="ignore", divide="ignore"):
                k = other.dangle_dq / mo.dangle_dq
                areal = other.length ** 2 * other.dangle_dq / (mo.length ** 2 * mo.dangle_dq)

                def swept(p):
                    P = state.pos[..., plan.point_index(p), :]
                    return 0.5 * _cross(J0 - P, J - P)
                sl, sb = swept(pl), swept(pb)
                scale = plan.length_scale
                tiny = (np.abs(sl) <= TOL.swept_area * scale * scale)
                ratio = np.where(tiny, np.nan, sb / np.where(tiny, 1.0, sl))
            out.append(RodPair(mo.name, other.name, joint, k, areal, ratio, other.dlength_dq > 0))
    return out


# -- buildable parts of a stroke -----------------------------------------------------------------------
def _valid_at(plan, params, k, q_values):
    from ..engine import solve
    q = np.tile(np.asarray(plan.sketch_inputs, dtype=float), (len(q_values), 1))
    q[:, k] = q_values
    st = solve(plan, params, q, order=1)
    d = st.dpos_dq
    return st.valid & np.all(np.isfinite(d.reshape(len(q_values), -1)), axis=-1)


def stroke_ranges(plan, start: float, stop: float, *, params=None, input: int = 0,  # noqa: A002
                  steps: int = 400) -> dict:
    """Which parts of the run of input ``input`` from ``start`` to ``stop`` (SI) can be assembled.

    Returns ``{"buildable": [(a, b), ...], "unbuildable": [(a, b), ...], "fraction_unbuildable": f}``
    with the interval ends refined by bisection on the validity to ``stroke_edge`` of the stroke (a guide out
    of the driving rod's reach, a rod at a dead point). Other inputs are held at their sketch values."""
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    q = np.linspace(start, stop, max(int(steps), 2))
    ok = _valid_at(plan, params, input, q)
    span = abs(stop - start)

    def edge(a, b, ok_a):
        for _ in range(60):
            if abs(b - a) <= TOL.stroke_edge * max(span, 1e-300):
                break
            mid = 0.5 * (a + b)
            if bool(_valid_at(plan, params, input, np.array([mid]))[0]) == ok_a:
                a = mid
            else:
                b = mid
        return a, b

    runs = {True: [], False: []}
    i0 = 0
    cur_lo = float(q[0])
    for i in range(1, len(q) + 1):
        if i < len(q) and ok[i] == ok[i0]:
            continue
        if i == len(q):
            runs[bool(ok[i0])].append((cur_lo, float(q[-1])))
            break
        a, b = edge(float(q[i - 1]), float(q[i]), bool(ok[i0]))
        hi = a
        runs[bool(ok[i0])].append((cur_lo, hi))
        cur_lo = b
        i0 = i
    bad = sum(abs(b - a) for a, b in runs[False])
    return {"buildable": runs[True], "unbuildable": runs[False],
            "fraction_unbuildable": bad / span if span > 0 else float(not ok[0])}


# -- the stroke envelope ------------------------------------------------------------------------------------
#: quantity name → (description, unit) for the envelope
QUANTITIES = {
    "extension": ("change of length from the start", "m"),
    "rate": ("rate of length dL/dt", "m/s"),
    "accel": ("acceleration of length d²L/dt²", "m/s²"),
    "angle": ("rotation from the start direction", "rad"),
    "omega": ("angular velocity", "rad/s"),
    "alpha": ("angular acceleration", "rad/s²"),
    "K_omega": ("K_ω = ω_driven / ω_driving", ""),
    "areal_ratio": ("ratio of areal velocities (L_b²·ω_b)/(L_l²·ω_l)", ""),
}


@dataclass(frozen=True)
class Extreme:
    """An extreme value ``value`` of a quantity at time ``t`` (s) and input value ``q``; ``interior``:
    a root of the derivative inside the run (not an end point)."""
    value: float
    t: float
    q: float
    interior: bool

    def _repr_html_(self) -> str:
        from ..model.display import dataclass_table
        return dataclass_table(self, "Extreme", units={"t": "s"})


@dataclass(frozen=True)
class Envelope:
    """Extremes along a run: ``extremes[(owner, quantity)] = {"min": Extreme, "max": Extreme,
    "interior": [Extreme, ...]}`` where owner is an actuator name or ``"driving/driven"`` for a pair;
    ``t``, ``q`` (n,) the samples; ``samples[(owner, quantity)]`` (n,) the sampled values;
    ``ranges``: :func:`stroke_ranges` of the run; ``past_foot``: for each pair, the first input value
    (m) from which the passive rod lengthens (None if it never does along the run); ``valid`` (n,)."""
    t: np.ndarray
    q: np.ndarray
    valid: np.ndarray
    samples: dict
    extremes: dict
    ranges: dict
    past_foot: dict

    def _repr_html_(self) -> str:
        from ..model.display import html_table
        rows = [(f"{owner} {quantity}", f"min {e['min'].value:.6g} (t {e['min'].t:.6g} s), "
                                        f"max {e['max'].value:.6g} (t {e['max'].t:.6g} s)")
                for (owner, quantity), e in self.extremes.items()]
        return html_table(f"Stroke envelope ({len(self.t)} samples)", rows)


def _evaluate(plan, law, t, params, k):
    from .timelaw import solve_in_time
    laws = [law if i == k else (lambda tt, q0=float(plan.sketch_inputs[i]): (np.full(np.shape(tt), q0),
                                                                               np.zeros(np.shape(tt)),
                                                                               np.zeros(np.shape(tt))))
            for i in range(plan.n_inputs)]
    st = solve_in_time(plan, laws, t, params)
    start = start_state(st)
    mot = actuator_motions(st, k, start)
    vals = {}
    for name, mo in mot.items():
        for qn in ("extension", "rate", "accel", "angle", "omega", "alpha"):
            vals[(name, qn)] = getattr(mo, qn)
    pairs = rod_pairs(st, mot, start)
    for p in pairs:
        vals[(f"{p.driving}/{p.driven}", "K_omega")] = p.K_omega
        vals[(f"{p.driving}/{p.driven}", "areal_ratio")] = p.areal_ratio
        vals[(f"{p.driving}/{p.driven}", "_driven_dlength_dq")] = mot[p.driven].dlength_dq
    return st, vals, pairs


def unbuildable_message(plan, ranges: dict, input: int = 0) -> str | None:  # noqa: A002
    """A message naming the parts of a stroke (:func:`stroke_ranges`) that cannot be assembled, or None."""
    bad = ranges["unbuildable"]
    if not bad:
        return None
    name = plan.input_names[input]
    parts = ", ".join(f"{a:.6g} … {b:.6g} m" for a, b in bad)
    return (f"{name}: the mechanism cannot be assembled for {name} = {parts} "
            f"({100 * ranges['fraction_unbuildable']:.3g} % of the stroke; a guide or joint out of reach); "
            f"NaN with valid=False there")


def stroke_envelope(plan, law, *, params=None, input: int = 0, steps: int = 400,  # noqa: A002
                    on_unbuildable: str = "nan") -> Envelope:
    """Sample the run of ``law`` (a time law of input ``input``, e.g. :func:`~assur.analysis.timelaw.driver_law`)
    from ``law.t_start`` to ``law.t_end`` at ``steps`` times and locate the interior extrema of every
    actuator quantity (:data:`QUANTITIES`) by a root solve (brentq) of its time derivative (central
    differences of the exact solution). Samples that cannot be assembled are left out; with
    ``on_unbuildable`` 'warn' (UnbuildableWarning) or 'raise' (UnbuildableError) the message names
    the stroke ranges concerned (:func:`unbuildable_message`)."""
    from scipy.optimize import brentq
    if on_unbuildable not in ("nan", "warn", "raise"):
        raise SpecError([("on_unbuildable", f"must be one of nan, warn, raise: {on_unbuildable!r}")])
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    t = np.linspace(law.t_start, law.t_end, max(int(steps), 3))
    q = law(t)[0]
    st, vals, pairs = _evaluate(plan, law, t, params, input)
    ok = st.valid
    span = law.t_end - law.t_start
    h = TOL.stroke_step * span

    def value(key, x):
        return float(_evaluate(plan, law, np.array([x]), params, input)[1][key][0])

    def slope(key, x):
        v = _evaluate(plan, law, np.array([x - h, x + h]), params, input)[1][key]
        return float((v[1] - v[0]) / (2 * h))

    def root(key, a, b, f):
        """The root of f(key, x) on [a, b] (brentq), or None without a sign change."""
        try:
            fa, fb = f(key, a), f(key, b)
            if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0:
                return None
            return float(brentq(lambda x: f(key, x), a, b, xtol=TOL.stroke_root * span))
        except ValueError:
            return None

    # rounding noise is not an extremum: steps below ``rounding_noise`` of the largest value of that quantity
    # over all actuators (or pairs) count as flat
    ref: dict = {}
    for (owner, qn), v in vals.items():
        a = np.abs(np.where(ok, v, np.nan))
        if np.isfinite(a).any():
            ref[qn] = max(ref.get(qn, 0.0), float(np.nanmax(a)))
    extremes = {}
    for key, v in vals.items():
        if key[1].startswith("_"):
            continue
        v = np.where(ok, v, np.nan)
        good = np.isfinite(v)
        if not good.any():
            continue
        noise = TOL.rounding_noise * ref.get(key[1], 0.0) + 1e-300
        found = []
        idx = np.flatnonzero(good)
        dv = np.diff(v[idx])
        sig = [(i, d) for i, d in zip(idx[:-1], dv) if abs(d) > noise]
        for (i0, d0), (i1, d1) in zip(sig, sig[1:]):
            if d0 * d1 < 0 and i1 - i0 <= 4 and np.all(good[i0:i1 + 2]):
                a, b = t[i0], t[min(i1 + 1, len(t) - 1)]
                x = root(key, a + h, b - h, slope)
                x = float(t[i1]) if x is None else x
                found.append(Extreme(value(key, x), x, float(law(np.array([x]))[0][0]), True))
        ends = [Extreme(float(v[i]), float(t[i]), float(q[i]), False) for i in idx[[0, -1]]]
        cands = ends + found
        extremes[key] = {"min": min(cands, key=lambda e: e.value), "max": max(cands, key=lambda e: e.value),
                         "interior": found}
    lo, hi = float(np.nanmin(q)), float(np.nanmax(q))
    ranges = stroke_ranges(plan, lo, hi, params=params, input=input, steps=steps)
    msg = unbuildable_message(plan, ranges, input)
    if msg and on_unbuildable != "nan":
        from ..errors import UnbuildableError, UnbuildableWarning
        if on_unbuildable == "raise":
            raise UnbuildableError(msg, int(np.count_nonzero(~ok)), len(t))
        import warnings
        warnings.warn(msg, UnbuildableWarning, stacklevel=2)
    past = {}
    for p in pairs:
        key = (f"{p.driving}/{p.driven}", "_driven_dlength_dq")
        d = np.where(ok, vals[key], np.nan)
        if not np.any(d > 0):
            past[key[0]] = None
            continue
        i = int(np.argmax(d > 0))
        x = root(key, float(t[i - 1]), float(t[i]), value) if i > 0 else None
        past[key[0]] = float(law(np.array([x]))[0][0]) if x is not None else float(q[i])
    samples = {k: np.where(ok, v, np.nan) for k, v in vals.items() if not k[1].startswith("_")}
    return Envelope(t, q, np.asarray(ok, dtype=bool), samples, extremes, ranges, past)


# -- a JSON-ready summary (``assur analyze`` and the report) -------------------------------------------
def _extreme_dict(e: Extreme) -> dict:
    return {"value": e.value, "t": e.t, "q": e.q, "interior": e.interior}


def stroke_summary(plan, params=None, *, steps: int = 400, stroke=None) -> dict:
    """The working stroke of a one-input plan driven by a linear actuator, as a JSON-ready dict:
    ``stroke`` (input range, time law, times), ``unbuildable`` (samples that cannot be assembled),
    ``buildable_ranges`` / ``unbuildable_ranges`` (input values, m), ``rods`` (per actuator the
    min/max and interior extrema of :data:`QUANTITIES`), ``rod_pairs`` (K_ω, areal-velocity ratio, where
    the passive rod starts lengthening) and, for paper 002's layout, ``lever`` (its (a, α, β, γ) and
    derived constants). ``stroke`` (SI) overrides the driver's ``range``/``law``; SpecError without one."""
    from .lever import lever_layout
    from .timelaw import ConstantSpeed, driver_law
    if plan.n_inputs != 1 or plan.input_kinds[0] != "linear":
        raise SpecError([("drivers", "a stroke summary needs a single linear driver")])
    d = plan.mechanism.drivers[0]
    speed = float(plan.speeds[0])
    analogue = False
    if speed == 0 and (d.law is None or stroke is not None):
        rng = stroke if stroke is not None else d.range
        if rng is None:
            driver_law(plan)   # raises the SpecError naming the missing range
        law, analogue = ConstantSpeed.over(float(plan.sketch_inputs[0]), 1.0, rng), True
    else:
        law = driver_law(plan, 0, stroke)
    env = stroke_envelope(plan, law, params=params, steps=steps)
    q = env.q
    law_text = ("table of times and lengths, " + law.interpolation + " interpolation" if hasattr(law, "times") else
                ("analogues per metre of stroke (the driver's speed is 0)" if analogue else
                 f"constant speed {speed:g} m/s"))
    bad = int(np.count_nonzero(~env.valid))
    out = {
        "stroke": {"driver": d.name, "actuator": d.actuator, "start": float(q[0]), "stop": float(q[-1]),
                   "min": float(np.nanmin(q)), "max": float(np.nanmax(q)), "law": law_text,
                   "analogues": analogue, "t_start": float(law.t_start), "t_end": float(law.t_end),
                   "samples": int(len(q))},
        "unbuildable": bad,
        "buildable_ranges": [{"start": a, "end": b} for a, b in env.ranges["buildable"]],
        "unbuildable_ranges": [{"start": a, "end": b} for a, b in env.ranges["unbuildable"]],
    }
    acts = {}
    for (owner, qn), ex in env.extremes.items():
        if "/" in owner:
            continue
        acts.setdefault(owner, {})[qn] = {"min": _extreme_dict(ex["min"]), "max": _extreme_dict(ex["max"]),
                                          "interior": [_extreme_dict(e) for e in ex["interior"]]}
    m = plan.mechanism
    out["rods"] = {a.name: {"between": list(a.between), "driven": a.name == d.actuator,
                                 "quantities": acts.get(a.name, {})} for a in m.actuators}
    pairs = []
    for owner in sorted({o for o, _ in env.extremes if "/" in o}):
        l, b = owner.split("/")
        entry = {"driving": l, "driven": b, "past_foot_from": env.past_foot.get(owner)}
        for qn in ("K_omega", "areal_ratio"):
            ex = env.extremes.get((owner, qn))
            if ex is None:
                continue
            v = env.samples[(owner, qn)]
            spread = float(np.nanmax(v) - np.nanmin(v))
            entry[qn] = {"min": _extreme_dict(ex["min"]), "max": _extreme_dict(ex["max"]),
                         "interior": [_extreme_dict(e) for e in ex["interior"]],
                         "constant": spread <= TOL.rounding_noise * max(float(np.nanmax(np.abs(v))), 1e-300)}
        pairs.append(entry)
    out["rod_pairs"] = pairs
    try:
        lay = lever_layout(plan, params, strict=True)
    except SpecError as exc:   # the paper's layout, but its start triangle is degenerate
        lay = None
        out["lever_note"] = f"the paper-002 parametrisation does not apply: {exc}"
    if lay is not None:
        g = lay.geometry
        out["lever"] = {"driving": lay.driving, "driven": lay.driven, "joint": lay.joint, "O": lay.pivot_driven,
                        "A": lay.pivot_driving, "a": g.a, "alpha": g.alpha, "beta": g.beta, "gamma": g.gamma,
                        "mirrored": g.mirrored, "b1": g.b1, "l1": g.l1, "h_O": g.h_O, "h_A": g.h_A, "e_O": g.e_O,
                        "d_A": g.d_A, "area_ratio": g.area_ratio, "foot_stroke": g.foot_stroke,
                        "s2_max": g.b1 - abs(g.h_O) if g.foot_stroke >= 0 else None, "limits": g.limits}
    return out
