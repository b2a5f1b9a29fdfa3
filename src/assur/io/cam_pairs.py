"""The ``[[cams]]`` entries of a mechanism file: a cam turning about a frame pivot drives a follower.

::

    [[cams]]
    name = "lift"
    cam = "camshaft"          # turns about a frame pivot: a driven crank, a gear-driven link, another cam's rocker
    follower = "lifter"       # translating (a [[prismatic]] link = "lifter" on the frame) or oscillating (hinged
                              # on the frame)
    point = "R"               # the follower's trace point: the roller's centre, the knife's edge, a point of the face
    contact = "roller"        # "knife" | "roller" | "flat" (default: "roller" with a roller_radius, else "knife")
    roller_radius = 8         # file length unit
    face_angle = 0            # a flat face's direction from across the slide (translating) or along the arm
                              # pivot → point (oscillating), file angle unit
    phase = 0                 # the law's angle at the sketch (file angle unit)
    rotation = "ccw"          # the law advances as the cam turns ccw or cw (default: the cam's crank's sense)
    pressure_limit = 30       # the largest pressure angle the checks accept (file angle unit; default 30°)
    law = [                   # segments over one turn (their angles add up to 360°, their lifts to 0) ...
      { motion = "dwell", angle = 90 },
      { motion = "cycloidal", angle = 90, lift = 25 },     # lift: file length unit (translating), angle
      { motion = "dwell", angle = 90 },                    # unit (oscillating); a return is a negative lift
      { motion = "cycloidal", angle = 90, lift = -25 },
    ]
    # law = { angle = [0, 90, 180, 270], lift = [0, 10, 25, 10] }   ... or a periodic C² cubic spline through
    #                                                                   points of the turn
    # law = { profile = { angle = [...], radius = [...] } }            ... or the cam's own profile, a polar
    #     table in the cam's frame (its pivot at the origin, angles from pivot → arm in the sketch; radii in the
    #     file's length unit, held as a periodic quintic spline): the follower's lift is its contact with it

Motions: ``dwell``, ``harmonic``, ``cycloidal``, ``modified_trapezoid``, ``modified_sine``, ``polynomial_345``
(also ``3-4-5``), ``polynomial_4567`` (``4-5-6-7``). Every problem is reported with its path (``cams[0].law[2]``).
"""
from __future__ import annotations

import math

import numpy as np

from ..kernels.cam_motion import LAWS
from ..model.camming import FOLLOWER_KINDS, TWO_PI, CamLaw, CamPair, CamSegment
from ..model.mechanism import FRAME

_KEYS = ("cam", "contact", "face_angle", "follower", "law", "name", "phase", "point", "pressure_limit", "rotation",
         "roller_radius")
#: motion names a file may use, and the law each means
MOTIONS = {"dwell": None, **{name: name for name in LAWS}, "simple_harmonic": "harmonic", "3-4-5": "polynomial_345",
           "4-5-6-7": "polynomial_4567", "345": "polynomial_345", "4567": "polynomial_4567"}
#: a law's segment angles must add up to a turn within this (rad); its lifts must close within this times the stroke
CLOSURE = 1e-9
#: a given profile is sampled at this many points of its spline, and the lift it imposes at this many cam turns
PROFILE_SAMPLES, LIFT_SAMPLES = 4096, 2048


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and abs(v) < 1e9


def read_cam_pairs(data: dict, P, *, length_factor: float, angle_factor: float, link_points: dict,
                   frame_points: set, prismatic, drivers, points: dict | None = None) -> tuple[CamPair, ...]:
    """The cam pairs of a parsed mechanism file (problems go to ``P``). ``link_points``: link name → its points;
    ``prismatic``: the file's prismatic pairs; ``drivers``: its drivers; ``points``: name → sketch (x, y) in m (a
    profile cam's follower geometry)."""
    cdata = P.section(data, "cams", "must be an array of tables [[cams]]", list)
    out, seen = [], set()
    for i, spec in enumerate(cdata):
        path = f"cams[{i}]"
        if not isinstance(spec, dict):
            P.add(path, "must be a table")
            continue
        P.unknown_keys(spec, _KEYS, path)
        name = spec.get("name", f"cams{i + 1}")
        if not isinstance(name, str) or not name or name in seen:
            P.add(f"{path}.name", f"must be a unique name: {name!r}")
        seen.add(str(name))
        ok = True
        movers = sorted(set(link_points) - {FRAME})
        cam, follower = spec.get("cam"), spec.get("follower")
        for key, link in (("cam", cam), ("follower", follower)):
            if not isinstance(link, str) or link not in link_points or link == FRAME:
                P.add(f"{path}.{key}", f"must be a moving link (known: {', '.join(movers)}): {link!r}")
                ok = False
        if ok and cam == follower:
            P.add(f"{path}.follower", f"must differ from the cam: {follower!r}")
            ok = False
        if ok and not set(link_points[cam]) & frame_points:
            P.add(f"{path}.cam", f"link '{cam}' must turn about a frame pivot (share a point with the frame)")
            ok = False
        motion = None
        if ok:
            slides = [p for p in prismatic if p.link == follower and p.guide == FRAME]
            if set(link_points[follower]) & frame_points:
                motion = "oscillating"
            elif slides:
                motion = "translating"
            else:
                P.add(f"{path}.follower", f"link '{follower}' must oscillate about a frame pivot (share a point with "
                                          f"the frame) or translate on the frame ([[prismatic]] link = '{follower}', "
                                          f"guide = 'frame')")
                ok = False
        point = spec.get("point")
        if ok and (not isinstance(point, str) or point not in link_points[follower]):
            P.add(f"{path}.point", f"must be a point of the follower '{follower}' "
                                   f"({', '.join(link_points[follower])}): {point!r}")
            ok = False
        radius = spec.get("roller_radius", 0.0)
        if not _number(radius) or radius < 0:
            P.add(f"{path}.roller_radius", f"must be a length ≥ 0: {radius!r}")
            radius, ok = 0.0, False
        contact = spec.get("contact", "roller" if radius > 0 else "knife")
        if contact not in FOLLOWER_KINDS:
            P.add(f"{path}.contact", f"must be one of {', '.join(FOLLOWER_KINDS)}: {contact!r}")
            ok = False
        elif contact == "roller" and not radius > 0:
            P.add(f"{path}.roller_radius", "a roller follower needs roller_radius > 0")
            ok = False
        elif contact != "roller" and "roller_radius" in spec:
            P.add(f"{path}.roller_radius", f"applies to a roller follower only (contact = {contact!r})")
            ok = False
        if "face_angle" in spec and contact != "flat":
            P.add(f"{path}.face_angle", f"applies to a flat-faced follower only (contact = {contact!r})")
            ok = False
        angles = {}
        for key, default in (("phase", 0.0), ("face_angle", 0.0), ("pressure_limit", 30.0)):
            v = spec.get(key)
            if v is None:
                angles[key] = math.radians(default)
            elif not _number(v):
                P.add(f"{path}.{key}", f"must be a finite angle: {v!r}")
                ok = False
            else:
                angles[key] = float(v) * angle_factor
        if ok and not 0 < angles["pressure_limit"] < math.pi / 2:
            P.add(f"{path}.pressure_limit", "must be between 0 and 90°")
            ok = False
        rotation = spec.get("rotation")
        if rotation is None:
            d = next((d for d in drivers if d.kind == "rotary" and d.link == cam), None)
            sign = 1 if d is None else int(d.sense)
        elif rotation in ("ccw", "cw"):
            sign = 1 if rotation == "ccw" else -1
        else:
            P.add(f"{path}.rotation", f"must be 'ccw' or 'cw': {rotation!r}")
            sign, ok = 1, False
        lift_factor = length_factor if motion != "oscillating" else angle_factor
        raw = spec.get("law")
        if isinstance(raw, dict) and "profile" in raw:
            for key in ("phase", "rotation"):
                if key in spec:
                    P.add(f"{path}.{key}", "applies to a law; a profile turns with its cam (phase 0, ccw)")
                    ok = False
            law = None
            if ok:
                law = _profile_law(raw, f"{path}.law", P, angle_factor, length_factor,
                                   dict(cam=cam, follower=follower, point=point, motion=motion, contact=contact,
                                        radius=float(radius) * length_factor, face=angles["face_angle"],
                                        link_points=link_points, frame_points=frame_points, prismatic=prismatic,
                                        points=points or {}))
            sign = 1
            angles["phase"] = 0.0
        else:
            law = read_law(raw, f"{path}.law", P, angle_factor, lift_factor)
        if ok and law is not None:
            out.append(CamPair(str(name), cam, follower, point, law, contact, motion, float(radius) * length_factor,
                               angles["face_angle"], angles["phase"], sign, angles["pressure_limit"]))
    return tuple(out)


def read_law(v, where: str, P, angle_factor: float, lift_factor: float) -> CamLaw | None:
    """A lift program (a list of segments) or a spline through points (a table ``{angle, lift}``), in SI."""
    if v is None:
        P.add(where, "is required: a list of segments {motion, angle, lift} or a table {angle = [...], lift = [...]}")
        return None
    if isinstance(v, dict):
        return _spline(v, where, P, angle_factor, lift_factor)
    if not isinstance(v, list) or not v:
        P.add(where, f"must be a list of segments {{motion, angle, lift}} or a table {{angle, lift}}: {v!r}")
        return None
    segments, start, base, ok = [], 0.0, 0.0, True
    for k, sg in enumerate(v):
        at = f"{where}[{k}]"
        if not isinstance(sg, dict):
            P.add(at, "must be a table {motion, angle, lift}")
            ok = False
            continue
        P.unknown_keys(sg, ("motion", "angle", "lift"), at)
        motion = sg.get("motion", "dwell")
        if not isinstance(motion, str) or motion not in MOTIONS:
            P.add(f"{at}.motion", f"must be one of {', '.join(MOTIONS)}: {motion!r}")
            ok = False
            continue
        span, lift = sg.get("angle"), sg.get("lift", 0.0)
        if not _number(span) or span <= 0:
            P.add(f"{at}.angle", f"must be a positive angle: {span!r}")
            ok = False
            continue
        if not _number(lift):
            P.add(f"{at}.lift", f"must be a finite lift: {lift!r}")
            ok = False
            continue
        law = MOTIONS[motion]
        if law is None and lift != 0:
            P.add(f"{at}.lift", f"a dwell keeps the lift: {lift!r}")
            ok = False
            continue
        if law is not None and lift == 0:
            P.add(f"{at}.lift", f"a {motion} segment needs a non-zero lift (a rise > 0, a return < 0)")
            ok = False
            continue
        span, lift = float(span) * angle_factor, float(lift) * lift_factor
        segments.append(CamSegment(law, start, span, base, lift))
        start, base = start + span, base + lift
    if not ok:
        return None
    if abs(start - TWO_PI) > CLOSURE:
        P.add(where, f"the segments' angles add up to {math.degrees(start):.9g}°, not a turn (360°)")
        return None
    stroke = max(abs(sg.base) for sg in segments) + max(abs(sg.lift) for sg in segments)
    if abs(base) > CLOSURE * max(stroke, 1e-300):
        P.add(where, f"the lifts do not close over the turn: they add up to {base / lift_factor:.9g}, not 0")
        return None
    return CamLaw("segments", tuple(segments), source="segments")


def _spline(v, where, P, angle_factor, lift_factor) -> CamLaw | None:
    P.unknown_keys(v, ("angle", "lift"), where)
    a, s = v.get("angle"), v.get("lift")
    if not (isinstance(a, list) and isinstance(s, list) and len(a) == len(s) and len(a) >= 4
            and all(_number(c) for c in a + s)):
        P.add(where, "a spline needs angle and lift: two lists of the same length, at least 4 finite numbers")
        return None
    a = np.asarray(a, float) * angle_factor
    if abs(a[0]) > 1e-12 or not np.all(np.diff(a) > 0) or a[-1] >= TWO_PI:
        P.add(f"{where}.angle", "must start at 0 and increase strictly within one turn (< 360°)")
        return None
    return CamLaw("spline", angles=tuple(a.tolist()), lifts=tuple((np.asarray(s, float) * lift_factor).tolist()),
                  source="spline")


def _profile_law(v, where, P, angle_factor, length_factor, f) -> CamLaw | None:
    """The lift table a given profile imposes on the follower as the sketch places it (see the module docstring)."""
    import cmath
    from ..kernels.cam_contact import oscillating_lift, translating_lift
    bad = [k for k in v if k != "profile"]
    if bad:
        P.add(f"{where}.{bad[0]}", "a profile law holds profile = {angle = [...], radius = [...]} only")
        return None
    prof = v["profile"]
    at = f"{where}.profile"
    if not isinstance(prof, dict):
        P.add(at, "must be a table {angle = [...], radius = [...]}")
        return None
    P.unknown_keys(prof, ("angle", "radius"), at)
    a, r = prof.get("angle"), prof.get("radius")
    if not (isinstance(a, list) and isinstance(r, list) and len(a) == len(r) and len(a) >= 8
            and all(_number(c) for c in a + r)):
        P.add(at, "needs angle and radius: two lists of the same length, at least 8 finite numbers")
        return None
    a = np.asarray(a, float) * angle_factor
    r = np.asarray(r, float) * length_factor
    if abs(a[0]) > 1e-12 or not np.all(np.diff(a) > 0) or a[-1] >= TWO_PI or not np.all(r > 0):
        P.add(at, "angles must start at 0 and increase within one turn (< 360°), radii be positive")
        return None
    if f["motion"] == "oscillating" and f["contact"] == "flat":
        P.add(at, "a flat-faced oscillating follower on a given profile is not supported: give its law")
        return None
    pts = f["points"]
    frame = f["frame_points"]
    pivot = next(p for p in f["link_points"][f["cam"]] if p in frame)
    arm = next(p for p in f["link_points"][f["cam"]] if p != pivot)
    O, A, R = (complex(*pts[n]) for n in (pivot, arm, f["point"]))
    e0 = (A - O) / abs(A - O)
    from scipy.interpolate import make_interp_spline
    spline = make_interp_spline(np.append(a, TWO_PI), np.append(r, r[0]), k=5, bc_type="periodic")
    g = np.linspace(0.0, TWO_PI, PROFILE_SAMPLES, endpoint=False)
    curve = spline(g) * np.exp(1j * g)
    xs = np.linspace(0.0, TWO_PI, LIFT_SAMPLES, endpoint=False)
    R0 = np.conj(e0) * (R - O)
    if f["motion"] == "translating":
        pr = next(p for p in f["prismatic"] if p.link == f["follower"] and p.guide == "frame")
        U = cmath.exp(1j * pr.angle)
        sign = 1.0 if ((R - O).conjugate() * U).real > 0 else -1.0
        u = np.conj(e0) * U * sign
        face = 1j * u * cmath.exp(1j * f["face"])          # across the slide, turned by face_angle
        normal = 1j * face
        if (np.conj(normal) * u).real < 0:
            normal = -normal
        lift = translating_lift(curve, xs, R0, u, f["contact"], f["radius"], normal)
    else:
        fpv = next(p for p in f["link_points"][f["follower"]] if p in frame)
        Of = np.conj(e0) * (complex(*pts[fpv]) - O)
        turn = 1.0 if ((R - O).conjugate() * 1j * (R - complex(*pts[fpv]))).real > 0 else -1.0
        lift = oscillating_lift(curve, xs, Of, R0, turn, f["contact"], f["radius"])
    if not np.all(np.isfinite(lift)):
        P.add(at, "the follower does not meet the profile over the whole turn (check the sketch and the radii)")
        return None
    scale = float(np.max(r))
    off = float(lift[0]) * (scale if f["motion"] == "oscillating" else 1.0)
    if abs(off) > 1e-6 * scale:
        unit = "rad" if f["motion"] == "oscillating" else "m"
        P.add(f"{where.rsplit('.', 1)[0]}.point", f"the sketch puts the follower {float(lift[0]):.6g} {unit} off the "
                                                   "profile: draw it touching the profile at the sketch")
        return None
    return CamLaw("table", angles=tuple(xs.tolist()), lifts=tuple((lift - lift.min()).tolist()), source="profile",
                  profile=tuple(zip(a.tolist(), r.tolist())))


def law_table(law: CamLaw, angle_out, lift_out, length_out=None):
    """The ``law`` value a file holds for ``law`` (``angle_out``, ``lift_out``, ``length_out``: SI → file unit
    conversions)."""
    if law.profile:
        lo = length_out or lift_out
        return {"profile": {"angle": [angle_out(a) for a, _ in law.profile],
                            "radius": [lo(r) for _, r in law.profile]}}
    if law.kind == "segments":
        out = []
        names = {v: k for k, v in MOTIONS.items() if k in LAWS}
        for sg in law.segments:
            t = {"motion": "dwell" if sg.motion is None else names.get(sg.motion, sg.motion), "angle": angle_out(sg.span)}
            if sg.motion is not None:
                t["lift"] = lift_out(sg.lift)
            out.append(t)
        return out
    return {"angle": [angle_out(x) for x in law.angles], "lift": [lift_out(x) for x in law.lifts]}
