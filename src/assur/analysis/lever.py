"""Paper 002's lever manipulator in its own parametrisation, solved in closed form.

Two linear actuators share the joint B, which runs in a straight frame guide: the driving rod
l = A→B (length L = l1 + s1, the input) and the driven rod b = O→B (length b = b1 − s2). The frame
of docs/papers/002.md §2: O = (0, 0), A = (a, 0), B0 above the x axis with interior angles α at O and β at A,
the guide B(σ) = B0 + σ·u with u = (−cos γ, sin γ). :class:`LeverManipulator` holds (a, α, β, γ),
validates them (§2, §9), gives the exact closed form of §3–§4 on arrays, and builds the equivalent
mechanism for the general engine (:meth:`LeverManipulator.mechanism`). The paper's own formulas (eqs.
8–16, as reconstructed in §5) are in :func:`paper_formulas`, clearly apart: they are a comparison,
never an answer. SI units (m, rad, s) throughout.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError
from ..tolerances import DEFAULT as TOL

#: relative tolerance on a square-root (or arcsin) argument below which the paper's formulas are
#: reported singular instead of evaluated (relative to the squared rod length)
LITERAL_TOLERANCE = TOL.literal_singular


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


@dataclass(frozen=True, slots=True)
class LeverManipulator:
    """The manipulator of paper 002 by (a, α, β, γ) (m, rad); see the module docstring.

    Derived quantities (docs/papers/002.md §2): ``b1``, ``l1`` (start lengths of the driven and driving rods),
    ``A_c = sin(α+γ)``, ``C_c = sin(β−γ)``, ``h_O``, ``h_A`` (signed distances of O and A from the
    guide), ``e_O`` (guide coordinate of the foot of the perpendicular from O), ``d_A`` (the foot
    from A is at σ = −d_A). Construction validates and raises one located :class:`SpecError`.
    """
    a: float
    alpha: float
    beta: float
    gamma: float
    mirrored: bool = field(default=False, compare=False)

    def __post_init__(self):
        problems = []
        a, al, be, ga = self.a, self.alpha, self.beta, self.gamma
        if not all(math.isfinite(v) for v in (a, al, be, ga)):
            problems.append(("a, alpha, beta, gamma", f"must be finite numbers: {a!r}, {al!r}, {be!r}, {ga!r}"))
        else:
            if not a > 0:
                problems.append(("a", f"the distance O–A must be positive: {a!r} m"))
            if not (al > 0 and be > 0 and al + be < math.pi):
                problems.append(("alpha, beta", f"the start triangle O A B0 is degenerate: α = {_deg(al)}, "
                                                f"β = {_deg(be)} (need α > 0, β > 0, α + β < 180°)"))
            else:
                bg = be - ga
                if not -math.pi / 2 < bg < math.pi / 2 or abs(math.cos(bg)) < TOL.degenerate_sine:
                    problems.append(("beta - gamma", f"must lie strictly between −90° and 90° (extending the driving "
                                                     f"rod must move B forward along the guide): β − γ = {_deg(bg)}"))
                elif abs(math.sin(bg)) < TOL.degenerate_sine:
                    problems.append(("gamma", f"the guide passes through A (β = γ = {_deg(be)}): the driving rod "
                                              f"cannot turn and K_ω is infinite"))
                if abs(math.sin(al + ga)) < TOL.degenerate_sine:
                    problems.append(("gamma", f"the guide passes through O (α + γ = {_deg(al + ga)}): the driven "
                                              f"rod's angle is undefined where B meets O"))
        if problems:
            raise SpecError(problems)

    # -- other parametrisations (docs/papers/002.md §2, §9) ----------------------------------------------------
    @classmethod
    def from_triangle(cls, b1: float, l1: float, angle_OBB1: float, angle_ABB1: float) -> "LeverManipulator":
        """From the start lengths b1 = |O B0|, l1 = |A B0| and the angles at B0 between the guide
        (towards B1) and B0→O (∠OBB1 = α + γ) and B0→A (∠ABB1 = 180° − (β − γ)); signed angles."""
        problems = []
        if not (b1 > 0 and math.isfinite(b1)):
            problems.append(("b1", f"must be a positive length: {b1!r}"))
        if not (l1 > 0 and math.isfinite(l1)):
            problems.append(("l1", f"must be a positive length: {l1!r}"))
        at_b = angle_ABB1 - angle_OBB1          # the interior angle O B0 A (signed, docs/papers/002.md §2)
        if not 0 < at_b < math.pi:
            problems.append(("angle_ABB1 - angle_OBB1", f"the angle O B0 A must lie in (0°, 180°): {_deg(at_b)}"))
        if problems:
            raise SpecError(problems)
        a = math.sqrt(b1 * b1 + l1 * l1 - 2 * b1 * l1 * math.cos(at_b))
        alpha = math.atan2(l1 * math.sin(at_b), b1 - l1 * math.cos(at_b))
        beta = math.pi - alpha - at_b
        return cls(a, alpha, beta, angle_OBB1 - alpha)

    @classmethod
    def from_points(cls, O, A, B0, u) -> "LeverManipulator":
        """From the pivots O, A, the start B0 of the joint and the travel direction u of the guide
        (any frame). A rigid motion brings O to the origin and A onto +x; when B0 lies below O→A the
        frame is mirrored (``mirrored`` is True: the senses of ψ and φ flip in the user's frame)."""
        O, A, B0, u = (np.asarray(v, dtype=float) for v in (O, A, B0, u))
        d = A - O
        a = float(np.hypot(*d))
        nu = float(np.hypot(*u))
        if not a > 0:
            raise SpecError([("A", f"coincides with O: {A.tolist()}")])
        if not nu > 0:
            raise SpecError([("u", f"the guide direction must not be zero: {u.tolist()}")])
        c, s = d / a

        def to_frame(v):
            return np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1]])
        b = to_frame(B0 - O)
        w = to_frame(u / nu)
        mirrored = bool(b[1] < 0)
        if mirrored:
            b[1], w[1] = -b[1], -w[1]
        if abs(b[1]) <= TOL.degenerate_sine * a:
            raise SpecError([("B0", f"lies on the line O–A: the start triangle is degenerate: {B0.tolist()}")])
        alpha = math.atan2(b[1], b[0])
        beta = math.atan2(b[1], a - b[0])
        gamma = math.atan2(w[1], -w[0])
        return cls(a, alpha, beta, gamma, mirrored)

    # -- derived geometry (docs/papers/002.md §2) --------------------------------------------------------------
    @property
    def b1(self) -> float:
        return self.a * math.sin(self.beta) / math.sin(self.alpha + self.beta)

    @property
    def l1(self) -> float:
        return self.a * math.sin(self.alpha) / math.sin(self.alpha + self.beta)

    @property
    def A_c(self) -> float:
        return math.sin(self.alpha + self.gamma)

    @property
    def C_c(self) -> float:
        return math.sin(self.beta - self.gamma)

    @property
    def h_O(self) -> float:
        return self.b1 * self.A_c

    @property
    def h_A(self) -> float:
        return self.l1 * self.C_c

    @property
    def e_O(self) -> float:
        return self.b1 * math.cos(self.alpha + self.gamma)

    @property
    def d_A(self) -> float:
        return self.l1 * math.cos(self.beta - self.gamma)

    @property
    def B0(self) -> np.ndarray:
        return self.b1 * np.array([math.cos(self.alpha), math.sin(self.alpha)])

    @property
    def u(self) -> np.ndarray:
        return np.array([-math.cos(self.gamma), math.sin(self.gamma)])

    @property
    def area_ratio(self) -> float:
        """S_BOB1 / S_BAB1 = h_O / h_A: the exact, constant ratio of the rods' areal velocities
        (docs/papers/002.md §6)."""
        return self.h_O / self.h_A

    @property
    def foot_stroke(self) -> float:
        """s1* where B passes the foot of the perpendicular from O (s2 is largest there, docs/papers/002.md §8b);
        negative when B starts past it (e_O < 0)."""
        return math.hypot(self.h_A, self.e_O + self.d_A) - self.l1

    @property
    def limits(self) -> dict:
        """ψ, φ and K_ω as s1 → ∞ (docs/papers/002.md §3, §8b)."""
        return {"psi": self.beta - self.gamma,
                "phi": math.atan2(self.A_c, -math.cos(self.alpha + self.gamma)),
                "K_omega": self.h_O / self.h_A}

    # -- the exact closed form (docs/papers/002.md §3, §4) -------------------------------------------------------
    def exact(self, s1, V1=None, dV1=0.0) -> dict:
        """Positions and analogues at the strokes ``s1 (...)`` (m); with ``V1`` (m/s, scalar or (...))
        and ``dV1`` (m/s²) also the time derivatives by the chain rule. Keys: sigma, L, b, s2, psi,
        phi, B (..., 2), dsigma, d2sigma, dpsi, d2psi, dphi, d2phi, ds2, d2s2 (d/ds1, d²/ds1²), and with
        V1: v_B, omega_psi, omega_phi, eps_psi, eps_phi, V2, a2 (= s̈2), K_omega, areal_ratio,
        past_foot. Strokes where the guide is out of the driving rod's reach (L < |h_A|) are NaN."""
        s1 = np.asarray(s1, dtype=float)
        l1, b1, hA, hO, eO, dA = self.l1, self.b1, self.h_A, self.h_O, self.e_O, self.d_A
        L = l1 + s1
        with np.errstate(invalid="ignore", divide="ignore"):
            rad = L * L - hA * hA
            root = np.where(rad >= 0, np.sqrt(np.where(rad >= 0, rad, 0.0)), np.nan)
            sigma = root - dA
            psi = np.arctan2(sigma * self.C_c, l1 + sigma * math.cos(self.beta - self.gamma))
            phi = np.arctan2(sigma * self.A_c, b1 - sigma * math.cos(self.alpha + self.gamma))
            b = np.hypot(hO, sigma - eO)
            ds = L / root
            d2s = -hA * hA / root ** 3
            out = {
                "sigma": sigma, "L": L, "b": b, "s2": b1 - b, "psi": psi, "phi": phi,
                "B": self.B0 + sigma[..., None] * self.u,
                "dsigma": ds, "d2sigma": d2s,
                "dpsi": hA / (L * root),
                "d2psi": -hA * (2 * L * L - hA * hA) / (L * L * root ** 3),
                "dphi": hO * ds / b ** 2,
                "d2phi": hO * (d2s / b ** 2 - 2 * (sigma - eO) * ds ** 2 / b ** 4),
                "ds2": -(sigma - eO) * ds / b,
                "d2s2": -(hO * hO * ds ** 2 / b ** 3 + (sigma - eO) * d2s / b),
                "past_foot": sigma > eO,
            }
            out["K_omega"] = out["dphi"] / out["dpsi"]
            out["areal_ratio"] = b * b * out["dphi"] / (L * L * out["dpsi"])
            if V1 is not None:
                V = np.asarray(V1, dtype=float)
                out.update({
                    "v_B": V * ds,
                    "omega_psi": V * out["dpsi"], "omega_phi": V * out["dphi"],
                    "eps_psi": V * V * out["d2psi"] + dV1 * out["dpsi"],
                    "eps_phi": V * V * out["d2phi"] + dV1 * out["dphi"],
                    "V2": V * out["ds2"], "a2": V * V * out["d2s2"] + dV1 * out["ds2"],
                })
        return out

    # -- the equivalent mechanism for the general engine -------------------------------------------------
    def mechanism(self, *, speed: float = 0.1, stroke: tuple[float, float] | None = None, units=None,
                  name: str = "Lever manipulator with two linear actuators (paper 002)"):
        """The manipulator as an ordinary :class:`~assur.model.mechanism.Mechanism`: frame points O, A and
        G (the foot of the perpendicular from O on the guide, the guide's reference point), the joint B
        at B0 riding in the frame guide ``guide`` of direction u, the driven actuator ``drive_rod``
        (A→B, input = its length, ``speed`` m/s) and the passive actuator ``driven_rod`` (O→B).
        ``stroke``: the driving extension s1 range (m), stored as the driver's length range."""
        from ..model.mechanism import FRAME, Actuator, LinearDriver, Link, Mechanism, Prismatic, Units
        G = self.B0 + self.e_O * self.u
        pts = (("O", (0.0, 0.0)), ("A", (self.a, 0.0)), ("G", tuple(map(float, G))), ("B", tuple(map(float, self.B0))))
        rng = None if stroke is None else (self.l1 + stroke[0], self.l1 + stroke[1])
        return Mechanism(
            name=name, points=pts, links=(Link(FRAME, ("O", "A", "G")),),
            prismatic=(Prismatic("guide", FRAME, "G", math.atan2(self.u[1], self.u[0]), point="B"),),
            actuators=(Actuator("drive_rod", ("A", "B")), Actuator("driven_rod", ("O", "B"))),
            drivers=(LinearDriver("drive", "drive_rod", speed, **({"range": rng} if rng else {})),),
            units=units or Units())


# -- recognising the manipulator in a compiled mechanism ----------------------------------------------
@dataclass(frozen=True)
class LeverLayout:
    """Where paper 002's manipulator sits in a mechanism: the driving and driven actuators, the
    shared joint, the guide, and the geometry in the paper's frame."""
    geometry: LeverManipulator
    driving: str          # actuator name (l, A→B)
    driven: str           # actuator name (b, O→B)
    joint: str            # B
    pivot_driving: str    # A
    pivot_driven: str     # O
    guide: str            # prismatic pair name
    input_index: int      # the input that drives ``driving``
    sign: int             # +1 when the engine's counter-clockwise rotations are the paper's ψ, φ (−1 mirrored)


def lever_layout(plan, params=None, *, strict: bool = False) -> LeverLayout | None:
    """The paper-002 layout of a one-input plan, or None: a driven actuator A→B and a passive actuator
    O→B (A, O frame points) whose common joint B runs in a straight guide fixed to the frame, and the
    start (the sketch input) a valid triangle. The guide's travel direction is the one that lengthens
    the driving rod (σ ≥ 0 as the input grows). With ``strict``, a layout whose start triangle fails
    :class:`LeverManipulator`'s validation raises that SpecError instead of giving None."""
    m = plan.mechanism
    if plan.n_inputs != 1 or plan.input_kinds[0] != "linear":
        return None
    from ..engine import geometry
    from ..engine import solve
    frame_pts = set(m.frame.points)
    drv = m.drivers[0]
    acts = {a.name: a for a in m.actuators}
    if drv.actuator not in acts:
        return None
    da = acts[drv.actuator]
    params = plan.defaults if params is None else np.asarray(params, dtype=float)
    for joint in da.between:
        pivot_a = da.between[0] if joint == da.between[1] else da.between[1]
        guides = [i for i, rec in enumerate(plan.lines)
                  if rec[0] == "prismatic" and rec[2] == 0 and
                  next(p for p in m.prismatic if p.name == rec[1]).point == joint]
        if pivot_a not in frame_pts or not guides:
            continue
        for other in m.actuators:
            if other.name == da.name or joint not in other.between:
                continue
            pivot_o = other.between[0] if joint == other.between[1] else other.between[1]
            if pivot_o not in frame_pts:
                continue
            st = solve(plan, params, plan.sketch_inputs, order=0)
            if not bool(np.all(st.valid)):
                return None
            P = {n: st.pos[0, plan.point_index(n)] for n in (pivot_o, pivot_a, joint)}
            _, lines = geometry(plan, params)
            uz = complex(lines[guides[0]][1])
            u = np.array([uz.real, uz.imag])
            # the travel direction lengthens the driving rod
            if float(np.dot(P[joint] - P[pivot_a], u)) < 0:
                u = -u
            try:
                g = LeverManipulator.from_points(P[pivot_o], P[pivot_a], P[joint], u)
            except SpecError:
                if strict:
                    raise
                return None
            return LeverLayout(g, da.name, other.name, joint, pivot_a, pivot_o, plan.lines[guides[0]][1], 0,
                               -1 if g.mirrored else 1)
    return None


# -- the paper's formulas (docs/papers/002.md §5), for comparison only ------------------------------------------------
@dataclass(frozen=True)
class PaperFormulas:
    """The paper's eqs. (8), (9), (11)–(16) as reconstructed in docs/papers/002.md §5, evaluated literally.

    ``values[name]`` (...,) arrays, NaN where the formula is singular; ``singular[name]`` boolean
    masks of those samples (a square-root argument within ``LITERAL_TOLERANCE`` of zero or below it,
    an arcsine argument beyond ±1, a zero denominator); ``reading`` is "frozen V2" (V2 held at the
    given constant, as printed) or "instantaneous" (the true b and V2 put into (11), (12), (16));
    ``notes`` names each singularity found, with its first time."""
    t: np.ndarray
    reading: str
    values: dict
    singular: dict
    notes: tuple[str, ...]


def paper_formulas(geom: LeverManipulator, t, V1: float, V2: float | None = None) -> PaperFormulas:
    """Evaluate the paper's formulas at times ``t (...)`` (s) for the constant driving speed ``V1``
    (m/s). With ``V2`` (m/s) the driven rod's speed is frozen at that value (s2 = V2·t, the paper's
    assumption, erratum E2); without it the instantaneous reading uses the true b(t) and V2(t).
    Eq. (14) is evaluated as printed (dimensionally inconsistent, E4), with the exact ψ and φ."""
    t = np.asarray(t, dtype=float)
    l1, b1, C, A = geom.l1, geom.b1, geom.C_c, geom.A_c
    al, be, ga = geom.alpha, geom.beta, geom.gamma
    ex = geom.exact(V1 * t, V1)
    L = l1 + V1 * t
    if V2 is None:
        b, v2, reading = ex["b"], ex["V2"], "instantaneous"
    else:
        b, v2, reading = b1 - V2 * t, np.full_like(t, float(V2)), "frozen V2"
    tol_l, tol_b = LITERAL_TOLERANCE * l1 * l1, LITERAL_TOLERANCE * b1 * b1
    rad_l = L * L - (l1 * C) ** 2
    rad_b = b * b - (b1 * A) ** 2
    bad_l = ~(rad_l > tol_l)
    bad_b = ~(rad_b > tol_b)
    values, singular = {}, {}
    with np.errstate(all="ignore"):
        arg8 = l1 * C / L
        singular["psi (8)"] = ~(np.abs(arg8) <= 1)
        values["psi (8)"] = (be - ga) - np.arcsin(arg8)
        singular["omega_psi (9)"] = bad_l | (L == 0)
        values["omega_psi (9)"] = l1 * C * V1 / (L * np.sqrt(rad_l))
        arg11 = b1 * A / b
        singular["phi (11)"] = ~(np.abs(arg11) <= 1)
        values["phi (11)"] = np.arcsin(arg11) - (al + ga)
        singular["omega_phi (12)"] = bad_b | (b == 0)
        values["omega_phi (12)"] = b1 * A * v2 / (b * np.sqrt(rad_b))
        singular["K_omega (13)"] = singular["omega_phi (12)"] | singular["omega_psi (9)"]
        values["K_omega (13)"] = values["omega_phi (12)"] / values["omega_psi (9)"]
        ratio = A * np.sin(ex["psi"]) / (C * np.sin(ex["phi"]))
        singular["V2 (14)"] = ~(np.abs(np.sin(ex["phi"])) > TOL.degenerate_sine)
        values["V2 (14)"] = b1 - l1 * ratio - ratio * V1
        singular["eps_psi (15)"] = singular["omega_psi (9)"]
        values["eps_psi (15)"] = -l1 * C * V1 ** 2 * (2 * L * L - (l1 * C) ** 2) / (L * L * rad_l ** 1.5)
        singular["eps_phi (16)"] = singular["omega_phi (12)"]
        values["eps_phi (16)"] = b1 * A * v2 ** 2 * (2 * b * b - (b1 * A) ** 2) / (b * b * rad_b ** 1.5)
    notes = []
    for k in values:
        mask = np.broadcast_to(singular[k], values[k].shape)
        values[k] = np.where(mask | ~np.isfinite(values[k]), np.nan, values[k])
        singular[k] = mask
        if mask.any():
            t_first = float(np.broadcast_to(t, mask.shape)[mask].min())
            notes.append(f"{k} is singular at {int(mask.sum())} of {mask.size} samples (first at t = {t_first:.6g} s)")
    return PaperFormulas(t, reading, values, singular, tuple(notes))
