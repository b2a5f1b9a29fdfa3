"""The sector method of paper 001 (docs/papers/001.md B3/B4): circular-arc sectors and involute flank points,
Tables 1–3.

Notation of this module follows the paper: the **driving** gear's angle is θ, the **driven** gear's φ (the
opposite of :mod:`assur.gears.pitch`, whose ``phi`` is the driving rotation). A law is used through
``law.phi_of`` (driving angle as a function of driven angle), which for the paper's law is explicit.

Sector model (docs/papers/001.md B3): the driven range [φ_1, φ_{N+1}] is cut into N sectors; sector i is a pair of
concentric circular arcs in rolling contact on the line of centres, radii r_i (driving) and r_Hi (driven), with

    r_i + r_Hi = L,   r_i·Δθ_i = r_Hi·Δφ_i = s    ⇒   r_i = L·Δφ_i/(Δφ_i + Δθ_i),  r_Hi = L·Δθ_i/(Δφ_i + Δθ_i)

the same arc s for every sector, and the sector ends on the law θ(φ). s is found by an outer root find so that the
N-th sector ends at φ_{N+1}. Flank points (docs/papers/001.md B4, eqs. 11–14): involutes from the circle r − m
("base circle" of the paper) at radii r + m·f for fractions f (the paper's five: −1, −0.5, 0, 0.5, 1), with backlash
j_n.

All inputs and outputs are SI (m, rad) except the ``table*`` functions, which return the paper's tables in its
units (mm, degrees) for export.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import GearError
from ..tolerances import DEFAULT as TOL
from .law import TransmissionLaw

#: the paper's five flank radii, as fractions of the module from the pitch radius (docs/papers/001.md B4)
PAPER_FRACTIONS = (-1.0, -0.5, 0.0, 0.5, 1.0)


@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class SectorModel:
    """N concentric-arc sectors of a gear pair (docs/papers/001.md B3), SI units.

    driving_angle: (N+1,) θ_i, sector start angles of the driving gear, plus the end θ_{N+1}, rad
    driven_angle: (N+1,) φ_i, the same for the driven gear, rad
    driving_radius: (N,) r_i, m;  driven_radius: (N,) r_Hi, m;  arc: s, m;  centre_distance: L, m
    """
    driving_angle: np.ndarray
    driven_angle: np.ndarray
    driving_radius: np.ndarray
    driven_radius: np.ndarray
    arc: float
    centre_distance: float

    @property
    def n_sectors(self) -> int:
        return int(self.driving_radius.size)

    @property
    def driving_pitch(self) -> np.ndarray:
        """(N,) Δθ_i, rad."""
        return np.diff(self.driving_angle)

    @property
    def driven_pitch(self) -> np.ndarray:
        """(N,) Δφ_i, rad."""
        return np.diff(self.driven_angle)

    @property
    def sector_ratio(self) -> np.ndarray:
        """(N,) k_i = Δθ_i/Δφ_i = r_Hi/r_i (driving turn per driven turn within sector i)."""
        return self.driving_pitch / self.driven_pitch


def _march(law: TransmissionLaw, s: float, L: float, phi0: float, n: int, span: float):
    """Sector ends for a trial arc s: (n+1,) driven angles and (n+1,) driving angles."""
    from scipy.optimize import brentq
    phi = np.empty(n + 1)
    theta = np.empty(n + 1)
    phi[0] = phi0
    theta[0] = float(law.phi_of(phi0))
    for i in range(n):
        def f(d, i=i):
            dth = float(law.phi_of(phi[i] + d)) - theta[i]
            return L * d * dth / (d + dth) - s
        hi = span
        while f(hi) < 0:
            hi *= 2.0
        d = brentq(f, 1e-300, hi, xtol=1e-15, rtol=8.9e-16, maxiter=500)
        phi[i + 1] = phi[i] + d
        theta[i + 1] = float(law.phi_of(phi[i + 1]))
    return phi, theta


def sector_model(law: TransmissionLaw, centre_distance: float, *, driven_start: float, driven_end: float,
                 sectors: int) -> SectorModel:
    """``sectors`` equal-arc concentric-arc sectors covering the driven range [driven_start, driven_end]
    (paper 001, docs/papers/001.md B3).

    law: a TransmissionLaw (its ``phi_of`` gives the driving angle of a driven angle; the paper's
    :class:`~assur.gears.law.WheelStepLaw`); centre_distance L, m; angles in rad. Root-finder tolerances are at
    round-off (docs/papers/001.md B3 asks for 1e-12 rad or tighter). The partition does not depend on L; s and the
    radii scale with L."""
    from scipy.optimize import brentq
    if not (np.isfinite(centre_distance) and centre_distance > 0):
        raise GearError(f"the centre distance must be a finite length > 0 m: {centre_distance!r}")
    if isinstance(sectors, bool) or not isinstance(sectors, (int, np.integer)) or sectors < 1:
        raise GearError(f"the number of sectors must be a whole number ≥ 1: {sectors!r}")
    span = float(driven_end - driven_start)
    if not span > 0:
        raise GearError(f"the driven range must be increasing: [{math.degrees(driven_start):.4f}°, "
                        f"{math.degrees(driven_end):.4f}°]")
    L = float(centre_distance)
    total_theta = float(law.phi_of(driven_end) - law.phi_of(driven_start))
    s_hi = L * span * total_theta / (span + total_theta)   # one sector spanning everything: far too large for N > 1

    def miss(s):
        phi, _ = _march(law, s, L, driven_start, sectors, span)
        return phi[-1] - driven_end

    s = brentq(miss, s_hi * 1e-9, s_hi, xtol=1e-18 * L, rtol=8.9e-16, maxiter=500) if sectors > 1 else s_hi
    phi, theta = _march(law, s, L, driven_start, sectors, span)
    # the last end lies on driven_end to round-off; pin it so the sectors tile the range exactly
    phi[-1] = driven_end
    theta[-1] = float(law.phi_of(driven_end))
    dphi, dtheta = np.diff(phi), np.diff(theta)
    r = L * dphi / (dphi + dtheta)
    return SectorModel(driving_angle=theta, driven_angle=phi, driving_radius=r, driven_radius=L - r,
                       arc=float(s), centre_distance=L)


def mirrored(model: SectorModel) -> bool:
    """True if sectors N..N/2+1 mirror sectors 1..N/2 (θ_{N+2−i} = −θ_i, r_{N+1−i} = r_i) to 1e-9 relative."""
    th, ph = model.driving_angle, model.driven_angle
    L = model.centre_distance
    tol = TOL.sector_symmetry
    return bool(np.allclose(th, -th[::-1], atol=tol) and np.allclose(ph, -ph[::-1], atol=tol)
                and np.allclose(model.driving_radius, model.driving_radius[::-1], rtol=0, atol=tol * L))


# ---- flanks, eqs. (11)–(14) ----------------------------------------------------------------------------------

def involute_function(alpha):
    """inv α = tan α − α, (...) → (...), rad."""
    return np.tan(alpha) - alpha


@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class Flanks:
    """Involute flank points of every sector (docs/papers/001.md B4), SI units; shapes (N, F) for N sectors,
    F fractions.

    radius: r_i + m·f_j (driving) or r_Hi + m·f_j (driven), m; first / second: polar angles of the first and second
    flank, rad. On the driving gear they bound tooth i, on the driven gear tooth space i."""
    radius: np.ndarray
    first: np.ndarray
    second: np.ndarray
    correction: np.ndarray   #: (N,) ΔΩ_i, the backlash angle j_n/(4·(r_i − m)), rad


def _flanks(start, pitch, radius, module, backlash, fractions, sign):
    fractions = np.asarray(fractions, dtype=float)
    base = radius - module
    if np.any(base <= 0):
        i = int(np.flatnonzero(base <= 0)[0]) + 1
        raise GearError(f"module {module * 1e3:.4g} mm is too large for sector {i}: its circle r − m = "
                        f"{base[np.flatnonzero(base <= 0)[0]] * 1e3:.4g} mm ≤ 0")
    r = radius[:, None] + module * fractions[None, :]
    if np.any(r < base[:, None]):
        raise GearError(f"flank radii must not lie below r − m (fractions ≥ −1): {tuple(fractions)}")
    omega = involute_function(np.arccos(np.clip(base[:, None] / r, -1.0, 1.0)))
    omega_pitch = involute_function(np.arccos(base / radius))[:, None]
    d_omega = backlash / (4.0 * base)                    # eq. (11)/(13): j_n·180°/(4π r_b) in degrees
    lo = start[:, None] + 0.25 * pitch[:, None]
    hi = start[:, None] + 0.75 * pitch[:, None]
    # driving tooth (sign +1): narrowed by ΔΩ on each side; driven space (sign −1): widened
    first = lo + sign * (d_omega[:, None] - omega_pitch + omega)
    second = hi - sign * (d_omega[:, None] - omega_pitch + omega)
    return Flanks(radius=r, first=first, second=second, correction=d_omega)


def driving_flanks(model: SectorModel, module: float, backlash: float, fractions=PAPER_FRACTIONS) -> Flanks:
    """Eqs. (11)–(12): tooth flanks of the driving gear, θ_ij = θ_i + Δθ_i/4 + ΔΩ_i − Ω_i3 + Ω_ij and
    θ_sij = θ_i + 3Δθ_i/4 − ΔΩ_i + Ω_i3 − Ω_ij (Ω_i3: at the pitch radius). Any fractions in [−1, …] give dense
    flanks (evaluated analytically, never interpolated)."""
    _check_tooth(module, backlash)
    return _flanks(model.driving_angle[:-1], model.driving_pitch, model.driving_radius, module, backlash,
                   fractions, +1.0)


def driven_flanks(model: SectorModel, module: float, backlash: float, fractions=PAPER_FRACTIONS) -> Flanks:
    """Eqs. (13)–(14): tooth-space flanks of the driven gear, φ_ij = φ_i + Δφ_i/4 − ΔΩ_Hi + Ω_Hi3 − Ω_Hij and
    φ_sij = φ_i + 3Δφ_i/4 + ΔΩ_Hi − Ω_Hi3 + Ω_Hij."""
    _check_tooth(module, backlash)
    return _flanks(model.driven_angle[:-1], model.driven_pitch, model.driven_radius, module, backlash,
                   fractions, -1.0)


def _check_tooth(module, backlash):
    if not (np.isfinite(module) and module > 0):
        raise GearError(f"the module must be a finite length > 0 m: {module!r}")
    if not (np.isfinite(backlash) and backlash >= 0):
        raise GearError(f"the backlash j_n must be a finite length ≥ 0 m: {backlash!r}")


# ---- the paper's tables ----------------------------------------------------------------------------------------

@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class SectorTable:
    """A table in the paper's layout and units: ``columns`` names, ``units`` ('' / 'deg' / 'mm'), ``data`` (rows, cols)."""
    title: str
    columns: tuple
    units: tuple
    data: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return self.data[:, self.columns.index(name)]


def table1(model: SectorModel, module: float) -> SectorTable:
    """Table 1: per sector i its start angles and radii r, r_b = r − m, r_f = r − 1.25m, r_a = r + m (both gears)."""
    mm, deg = 1e3, 180.0 / math.pi
    r, rh = model.driving_radius, model.driven_radius
    i = np.arange(1, model.n_sectors + 1)
    cols = [i, model.driving_angle[:-1] * deg, r * mm, (r - module) * mm, (r - 1.25 * module) * mm,
            (r + module) * mm, model.driven_angle[:-1] * deg, rh * mm, (rh - module) * mm,
            (rh - 1.25 * module) * mm, (rh + module) * mm]
    return SectorTable("Table 1 — circle-arc radii of the non-circular gears",
                       ("i", "theta", "r", "r_b", "r_f", "r_a", "phi", "r_H", "r_Hb", "r_Hf", "r_Ha"),
                       ("", "deg", "mm", "mm", "mm", "mm", "deg", "mm", "mm", "mm", "mm"),
                       np.column_stack(cols).astype(float))


def _flank_table(title, names, fl: Flanks, sectors):
    mm, deg = 1e3, 180.0 / math.pi
    n, f = fl.radius.shape
    ii, jj = np.meshgrid(np.arange(1, n + 1), np.arange(1, f + 1), indexing="ij")
    data = np.column_stack([ii.ravel(), jj.ravel(), fl.first.ravel() * deg, fl.second.ravel() * deg,
                            fl.radius.ravel() * mm]).astype(float)
    keep = np.isin(data[:, 0], np.asarray(sectors))
    return SectorTable(title, ("i", "j") + names, ("", "", "deg", "deg", "mm"), data[keep])


def table2(model: SectorModel, module: float, backlash: float, sectors=None) -> SectorTable:
    """Table 2: driving-gear involute points (i, j, θ_ij, θ_sij, r_ij); the paper prints sectors 1..N/2."""
    sectors = range(1, model.n_sectors // 2 + 1) if sectors is None else sectors
    return _flank_table("Table 2 — polar coordinates of the driving-wheel involute points",
                        ("theta", "theta_s", "r"), driving_flanks(model, module, backlash), sectors)


def table3(model: SectorModel, module: float, backlash: float, sectors=None) -> SectorTable:
    """Table 3: driven-gear involute points (i, j, φ_ij, φ_sij, r_Hij); the paper prints sectors 1..N/2."""
    sectors = range(1, model.n_sectors // 2 + 1) if sectors is None else sectors
    return _flank_table("Table 3 — polar coordinates of the driven-wheel involute points",
                        ("phi", "phi_s", "r_H"), driven_flanks(model, module, backlash), sectors)


# ---- mesh findings of docs/papers/001.md B6 that follow from the sector data ---------------------------------

@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class SectorFindings:
    """The findings of docs/papers/001.md B6.4–B6.8 for a sector model with module m and centre distance L (SI)."""
    radial_steps: np.ndarray          #: (N−1,) r_i − r_{i+1} of the driving gear, m
    driven_radial_steps: np.ndarray   #: (N−1,) r_Hi − r_H,i+1, m
    working_depth: float              #: 2m, m
    steps_exceeding: tuple            #: sector pairs (i, i+1) (1-based) where |driving or driven step| > 2m
    pitch_pressure_angle: np.ndarray  #: (N,) arccos((r_i − m)/r_i), rad
    driven_pitch_pressure_angle: np.ndarray  #: (N,) arccos((r_Hi − m)/r_Hi), rad
    working_pressure_angle: float     #: arccos((L − 2m)/L), rad
    involute_ratio_excess: np.ndarray  #: (N,) ((r_Hi − m)/(r_i − m)) / (r_Hi/r_i) − 1
    speed_ripple_sector: tuple        #: (min, max) of mover speed / nominal, k(φ)/k_i, over all sectors
    speed_ripple_involute: tuple      #: (min, max) of k(φ)·(r_i − m)/(r_Hi − m)


def sector_findings(model: SectorModel, law: TransmissionLaw, module: float, samples: int = 201) -> SectorFindings:
    """Radial steps vs 2m, pressure angles, involute-pair ratios and the speed ripple (docs/papers/001.md B6.4–B6.8).

    Speed ripple: with the driving gear at constant speed, within sector i the driven angle advances at 1/k_i
    (sector) or (r_i − m)/(r_Hi − m) (involute pair) per driving radian, while constant mover speed needs 1/k(φ),
    k = dθ/dφ of the law; the mover speed relative to nominal is k(φ)/k_i resp. k(φ)(r_i − m)/(r_Hi − m)."""
    r, rh, L, m = model.driving_radius, model.driven_radius, model.centre_distance, module
    steps, hsteps = -np.diff(r), -np.diff(rh)
    exceed = tuple((int(i) + 1, int(i) + 2) for i in np.flatnonzero((np.abs(steps) > 2 * m) | (np.abs(hsteps) > 2 * m)))
    t = np.linspace(0.0, 1.0, samples)
    phi = model.driven_angle[:-1, None] + model.driven_pitch[:, None] * t      # (N, samples)
    k = 1.0 / law.ratio_of_theta(phi)                                         # dθ/dφ in this module's notation
    sector = k / model.sector_ratio[:, None]
    involute = k * ((r - m) / (rh - m))[:, None]
    return SectorFindings(
        radial_steps=steps, driven_radial_steps=hsteps, working_depth=2 * m, steps_exceeding=exceed,
        pitch_pressure_angle=np.arccos((r - m) / r), driven_pitch_pressure_angle=np.arccos((rh - m) / rh),
        working_pressure_angle=math.acos((L - 2 * m) / L),
        involute_ratio_excess=((rh - m) / (r - m)) / (rh / r) - 1.0,
        speed_ripple_sector=(float(sector.min()), float(sector.max())),
        speed_ripple_involute=(float(involute.min()), float(involute.max())))


def paper_sector_model(law: TransmissionLaw, centre_distance: float, sectors: int = 24) -> SectorModel:
    """The paper's partition: one hub step φ ∈ [−π/4, π/4] in ``sectors`` sectors (Table 1 uses 24)."""
    return sector_model(law, centre_distance, driven_start=-math.pi / 4, driven_end=math.pi / 4, sectors=sectors)


# ---- closed outlines of the paper's scheme (reproduction mode) ------------------------------------------------

@dataclass(frozen=True, slots=True, eq=False)   # array fields: compare by identity
class SectorOutline:
    """Closed outlines of the paper's sector scheme, in the body frames of :mod:`assur.gears.pitch` (m).

    driving: (M, 2) counter-clockwise polygon of the whole driving gear (first point not repeated), centre at the
    origin; body angle a = −θ of the paper's driver angle θ. driven: (K, 2) the same for the driven gear, body
    angle β = π + φ of the paper's driven angle φ (docs/papers/001.md B4 placement mirrored so that the driver turns
    counter-clockwise). teeth: (driving teeth, driven teeth); linking: "relieved" or "chord"."""
    driving: np.ndarray
    driven: np.ndarray
    teeth: tuple
    linking: str
    pitch: float      #: the sector arc s, the circular pitch of the scheme on its arcs, m


def _arc(r, a0, a1, step):
    n = max(2, int(math.ceil(abs(a1 - a0) / step)) + 1)
    a = np.linspace(a0, a1, n)
    return np.full(n, float(r)), a


def _flank(start, pitch, radius, m, jn, sign, first, f_hi, n):
    """One flank of one sector from fraction −1 up to f_hi (≤ 1): (ρ, angle) arrays in increasing ρ, with the
    paper's five fractions among the vertices."""
    f = np.linspace(-1.0, f_hi, n)
    f = np.unique(np.concatenate([f, [x for x in PAPER_FRACTIONS if x < f_hi]]))   # the printed points are vertices
    fl = _flanks(np.array([start]), np.array([pitch]), np.array([radius]), m, jn, f, sign)
    return fl.radius[0], (fl.first if first else fl.second)[0]


def sector_outline(model: SectorModel, module: float, backlash: float, *, linking: str = "relieved",
                   dedendum: float = 1.25, steps_per_turn: int | None = None, flank_points: int = 33,
                   arc_step: float = math.radians(0.1)) -> SectorOutline:
    """Closed tooth outlines of the paper's scheme (docs/papers/001.md B6.9 set-up, B7.1–B7.5), analytic flanks,
    dense.

    Driving gear, per sector i (angles θ increasing): radial segment at θ_i1 from the root r_i − dedendum·m up to
    r_i − m; first flank eq. (12) from r_i − m to r_i + m; tip arc at r_i + m; second flank down to r_i − m; radial
    segment down to the root. Between teeth i and i+1 the space bottom ("linking line", undefined in the paper):
    "relieved" = an arc at the lower of the two root radii, the higher side's radial segment extended down to it;
    "chord" = a straight chord between the two root corners.

    Driven gear, per sector i (angles φ increasing): first flank eq. (14) of space i from r_Hi + m down to r_Hi − m;
    radial segment to the root r_Hi − dedendum·m; root arc; radial segment up; second flank up to r_Hi + m. Between
    spaces i and i+1 the tooth top: "relieved" = an arc at the lower of the two tip radii, the higher side's flank
    cut off at that radius (if that radius lies below its circle r − m, the cut falls on its radial segment);
    "chord" = a straight chord between the two tip corners.

    Assembly (docs/papers/001.md B7.5): the N sectors of one hub step are repeated ``steps_per_turn`` times per gear
    turn by rotation (driver: 2 for the paper, i.e. 180°; driven: 4, i.e. 90°); default: from the model's angle
    spans.
    """
    if linking not in ("relieved", "chord"):
        raise GearError(f"linking must be 'relieved' or 'chord': {linking!r}")
    _check_tooth(module, backlash)
    m, jn = module, backlash
    th, ph = model.driving_angle, model.driven_angle
    span_th, span_ph = th[-1] - th[0], ph[-1] - ph[0]
    reps_th = int(round(2 * math.pi / span_th)) if steps_per_turn is None else int(steps_per_turn)
    reps_ph = int(round(2 * math.pi / span_ph))
    if abs(reps_th * span_th - 2 * math.pi) > TOL.sector_symmetry or \
            abs(reps_ph * span_ph - 2 * math.pi) > TOL.sector_symmetry:
        raise GearError(f"the sectors must tile a whole number of steps per turn: driving span "
                        f"{math.degrees(span_th):.4f}°, driven span {math.degrees(span_ph):.4f}°")
    n = model.n_sectors
    r, rh = model.driving_radius, model.driven_radius
    dth, dph = model.driving_pitch, model.driven_pitch
    if np.any(r - dedendum * m <= 0) or np.any(rh - dedendum * m <= 0):
        raise GearError(f"module {m * 1e3:.4g} mm is too large for the sector radii: a root radius r − "
                        f"{dedendum:g}·m is ≤ 0")
    relieved = linking == "relieved"

    # ---- driving gear: teeth on the sectors -------------------------------------------------------------------
    root = r - dedendum * m
    first_root = np.array([_flank(th[i], dth[i], r[i], m, jn, +1.0, True, 1.0, 2)[1][0] for i in range(n)])
    one_step_r, one_step_a = [], []
    for i in range(n):
        j = (i + 1) % n
        rho1, a1 = _flank(th[i], dth[i], r[i], m, jn, +1.0, True, 1.0, flank_points)
        rho2, a2 = _flank(th[i], dth[i], r[i], m, jn, +1.0, False, 1.0, flank_points)
        tip_r, tip_a = _arc(r[i] + m, a1[-1], a2[-1], arc_step)
        pr = [[root[i]], rho1, tip_r, rho2[::-1], [root[i]]]
        pa = [[a1[0]], a1, tip_a, a2[::-1], [a2[0]]]
        if relieved:                       # space bottom: arc at the lower root radius up to the next tooth
            next_corner = first_root[j] + (span_th if j == 0 else 0.0)
            br, ba = _arc(min(root[i], root[j]), a2[0], next_corner, arc_step)
            pr.append(br)
            pa.append(ba)
        one_step_r += [np.asarray(x, dtype=float) for x in pr]
        one_step_a += [np.asarray(x, dtype=float) for x in pa]
    step_r, step_a = np.concatenate(one_step_r), np.concatenate(one_step_a)
    drv_rho = np.tile(step_r, reps_th)
    drv_ang = np.concatenate([step_a + k * span_th for k in range(reps_th)])
    a_body = -drv_ang[::-1]                 # body frame a = −θ; reversed to stay counter-clockwise
    driving = np.stack([drv_rho[::-1] * np.cos(a_body), drv_rho[::-1] * np.sin(a_body)], axis=-1)

    # ---- driven gear: tooth spaces on the sectors ---------------------------------------------------------------
    hroot = rh - dedendum * m
    tip = rh + m
    one_step_r, one_step_a = [], []
    for i in range(n):
        prev, j = (i - 1) % n, (i + 1) % n
        cut1 = min(tip[i], tip[prev]) if relieved else tip[i]     # top of the tooth before space i
        cut2 = min(tip[i], tip[j]) if relieved else tip[i]        # top of the tooth after space i
        base1 = _flank(ph[i], dph[i], rh[i], m, jn, -1.0, True, 1.0, 2)[1][0]
        base2 = _flank(ph[i], dph[i], rh[i], m, jn, -1.0, False, 1.0, 2)[1][0]
        pr, pa = [], []
        f1 = (cut1 - rh[i]) / m
        if f1 >= -1.0:                      # first flank from its (cut) top down to r_H − m, then radial
            rho1, a1 = _flank(ph[i], dph[i], rh[i], m, jn, -1.0, True, min(f1, 1.0), flank_points)
            pr += [rho1[::-1]]
            pa += [a1[::-1]]
        else:                               # the cut falls on the radial segment below r_H − m
            pr += [[max(cut1, hroot[i])]]
            pa += [[base1]]
        root_r, root_a = _arc(hroot[i], base1, base2, arc_step)
        pr += [root_r]
        pa += [root_a]
        f2 = (cut2 - rh[i]) / m
        if f2 >= -1.0:
            rho2, a2 = _flank(ph[i], dph[i], rh[i], m, jn, -1.0, False, min(f2, 1.0), flank_points)
            pr += [rho2]
            pa += [a2]
            end_a = a2[-1]
        else:
            pr += [[max(cut2, hroot[i])]]
            pa += [[base2]]
            end_a = base2
        if relieved:                        # tooth top: arc at the lower tip radius to the next space's flank
            f_next = (cut2 - rh[j]) / m
            if f_next >= -1.0:
                start_next = _flank(ph[j], dph[j], rh[j], m, jn, -1.0, True, min(f_next, 1.0), 2)[1][-1]
            else:
                start_next = _flank(ph[j], dph[j], rh[j], m, jn, -1.0, True, 1.0, 2)[1][0]
            top_r, top_a = _arc(max(cut2, min(hroot[i], hroot[j])), end_a,
                                start_next + (span_ph if j == 0 else 0.0), arc_step)
            pr += [top_r]
            pa += [top_a]
        one_step_r += [np.asarray(x, dtype=float) for x in pr]
        one_step_a += [np.asarray(x, dtype=float) for x in pa]
    step_r, step_a = np.concatenate(one_step_r), np.concatenate(one_step_a)
    dvn_rho = np.tile(step_r, reps_ph)
    dvn_ang = np.concatenate([step_a + k * span_ph for k in range(reps_ph)])
    b_body = math.pi + dvn_ang              # body frame β = π + φ
    driven = np.stack([dvn_rho * np.cos(b_body), dvn_rho * np.sin(b_body)], axis=-1)
    return SectorOutline(driving=_dedupe(driving), driven=_dedupe(driven), teeth=(reps_th * n, reps_ph * n),
                         linking=linking, pitch=model.arc)


def _dedupe(xy):
    """Drop consecutive duplicate points (and a closing duplicate of the first)."""
    keep = np.ones(len(xy), dtype=bool)
    close = TOL.outline_point * float(np.max(np.linalg.norm(xy, axis=1))) if len(xy) else 0.0
    keep[1:] = np.linalg.norm(np.diff(xy, axis=0), axis=1) > close
    xy = xy[keep]
    if np.linalg.norm(xy[-1] - xy[0]) <= close:
        xy = xy[:-1]
    return xy
