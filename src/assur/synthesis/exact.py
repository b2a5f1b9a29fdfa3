"""Exact synthesis: function generation (Freudenstein) of four-bars and slider-cranks, and motion generation
(Burmester) of four-bars.

``function_generation(inputs, outputs)`` and ``motion_generation(poses)`` return ranked lists of
:class:`~assur.Mechanism` four-bars with ground pivots ``A0`` (crank) and ``B0`` (rocker), moving pivots ``A``
(crank) and ``B`` (rocker), and for motion generation the coupler point ``P``; ``*_candidates`` return the
same as :class:`ExactSolution` records (inputs at the precision points, residual, transmission angle,
Grashof type). Every candidate is re-solved by the engine (``assur.solve`` with ``on_unbuildable="nan"``) along
the whole stretch of the input between its first and last precision point, on the one assembly branch of its
sketch: it is kept only if that stretch is buildable without a toggle (the exact discriminant of
``synthesis.fourbar``) and the engine reaches the precision points in their order. ``assur.synthesis.seeding``
turns these solutions into initial design vectors of a problem (docs/synthesis.md, "Exact methods").
``slider_function_generation(inputs, displacements)`` returns slider-crank function generators (crank ``A0``–``A``,
rod ``A``–``B``, slider ``B`` on a frame line through ``A0`` with an offset), checked by the engine the same way.
"""
from __future__ import annotations

import dataclasses
import functools

import numpy as np

from ..errors import SpecError
from . import fourbar as fb
from .burmester import Poses, burmester_points, centre_curve, snap_to_curve, three_pose_dyads
from .exact_results import Candidates, ExactSolution, Rejections, SliderSolution
from .freudenstein import chebyshev_points, freudenstein, precision_pairs, slider_freudenstein

GRASHOF_TYPES = ("crank-rocker", "double-crank", "rocker-crank", "double-rocker", "triple-rocker")
GRASHOF_FILTERS = GRASHOF_TYPES + ("grashof", "crank")
#: relative tolerance of a precision point reached by the engine (of the task's size)
REACH_TOL = 1e-6


def grashof_type(lengths) -> str:
    """(ground, crank, coupler, rocker) → one of GRASHOF_TYPES (the driver is the crank)."""
    lengths = np.asarray(lengths, float)
    s = np.sort(lengths)
    if s[0] + s[3] > s[1] + s[2] + 1e-12 * s[3]:
        return "triple-rocker"
    return ("double-crank", "crank-rocker", "double-rocker", "rocker-crank")[int(np.argmin(lengths))]


def _grashof_ok(kind: str, wanted) -> bool:
    if wanted is None:
        return True
    if wanted == "grashof":
        return kind != "triple-rocker"
    if wanted == "crank":
        return kind in ("crank-rocker", "double-crank")
    return kind == wanted


def _check_grashof(grashof):
    if grashof is not None and grashof not in GRASHOF_FILTERS:
        raise SpecError([("grashof", f"must be one of {', '.join(GRASHOF_FILTERS)} or None: {grashof!r}")])


# -- the engine's view of a candidate ---------------------------------------------------------------------
@functools.lru_cache(maxsize=4)
def _template(with_point: bool, side: str):
    """A compiled four-bar template (m, rad) whose branch puts B on ``side`` of A → B0."""
    from ..engine import compile as compile_
    from ..io.builder import Builder
    b = (Builder(units="m", angle="rad", name="four-bar template")
         .point("A0", 0, 0).point("B0", 1, 0).point("A", 0, 0.4).point("B", 0.9, 0.9 if side == "left" else -0.9))
    if with_point:
        b.point("P", 0.5, 1.2 if side == "left" else -1.2)
    b.frame("A0", "B0").link("crank", "A0", "A").link("coupler", "A", "B", *(("P",) if with_point else ()))
    b.link("rocker", "B0", "B").crank("crank", pivot="A0", arm="A", zero=0, name="crank")
    b.branch("B", side, ("A", "B0"))
    return compile_(b.build())


def _side(A, B, B0) -> np.ndarray:
    w = (B0 - A).conj() * (B - A)
    return np.where(w.imag > 0, "left", "right")


def _solve(geo: dict, q: np.ndarray) -> dict:
    """Population solve. geo: complex arrays A0, B0, A, B (and P) (k,) in the sketch at q[:, 0]; q (k, M)
    crank angles from the ground line → complex positions (k, M) of A, B, (P) with NaN where unbuildable."""
    from ..engine import solve
    k, M = q.shape
    with_point = "P" in geo
    out = {n: np.full((k, M), np.nan + 0j) for n in ("A", "B") + (("P",) if with_point else ())}
    sides = _side(geo["A"], geo["B"], geo["B0"])
    for side in ("left", "right"):
        rows = np.flatnonzero(sides == side)
        if not len(rows):
            continue
        plan = _template(with_point, side)
        A0, B0, A, B = (geo[n][rows] for n in ("A0", "B0", "A", "B"))
        gamma = np.angle(B0 - A0)
        p = np.tile(plan.defaults, (len(rows), 1))
        put = {"A0.x": A0.real, "A0.y": A0.imag, "B0.x": B0.real, "B0.y": B0.imag, "crank.length": np.abs(A - A0),
               "coupler.length": np.abs(B - A), "rocker.length": np.abs(B - B0), "crank.zero": gamma}
        if with_point:
            P = geo["P"][rows]
            put["coupler.P.distance"] = np.abs(P - A)
            put["coupler.P.angle"] = np.angle(P - A) - np.angle(B - A)
        for name, v in put.items():
            p[:, plan.param_index(name)] = v
        # the crank's own offset (a crank pointing away from the ground line at q = 0) is in q
        st = solve(plan, p[:, None, :], q[rows][..., None], order=0, on_unbuildable="nan", backend="numpy")
        for n in out:
            xy = st.pos[..., plan.point_index(n), :]
            out[n][rows] = xy[..., 0] + 1j * xy[..., 1]
    return out


def _stretch(t: np.ndarray, per_gap: int) -> tuple[np.ndarray, np.ndarray]:
    """Target inputs t (k, n) in passing order → dense inputs (k, (n−1)·per_gap + 1) and the targets' columns."""
    k, n = t.shape
    s = np.linspace(0.0, 1.0, per_gap, endpoint=False)
    q = (t[:, :-1, None] + np.diff(t, axis=1)[:, :, None] * s).reshape(k, -1)
    return np.concatenate([q, t[:, -1:]], axis=1), np.arange(n) * per_gap


def _transmission(A, B, B0) -> np.ndarray:
    """Worst transmission angle over each row (k,), folded to [0, π/2]; NaN rows stay NaN."""
    u, v = A - B, B0[:, None] - B
    mu = np.abs(np.angle(u.conj() * v))
    return np.min(np.minimum(mu, np.pi - mu), axis=1)


def _buildable(lengths: np.ndarray, start: np.ndarray, width: np.ndarray) -> np.ndarray:
    """The crank interval [start, start + width] assembles without a toggle (exact discriminant > 0)."""
    scale = lengths.mean(axis=1) ** 4
    return fb.min_discriminant(lengths, start, width) > 1e-10 * scale


def _fourbar(A0, B0, A, B, P=None, *, sense="ccw", units="m", name="four-bar", description=""):
    from ..io.builder import Builder
    b = Builder(units=units, angle="rad", name=name, description=description)
    for n, z in (("A0", A0), ("B0", B0), ("A", A), ("B", B)) + ((("P", P),) if P is not None else ()):
        b.point(n, float(z.real), float(z.imag))
    b.frame("A0", "B0").link("crank", "A0", "A").link("coupler", "A", "B", *(("P",) if P is not None else ()))
    b.link("rocker", "B0", "B")
    b.crank("crank", pivot="A0", arm="A", zero=float(np.angle(B0 - A0)), sense=sense, name="crank")
    b.branch("B", str(_side(np.array([A]), np.array([B]), np.array([B0]))[0]), ("A", "B0"))
    return b.build()


def _check_limit(limit) -> None:
    if limit is not None and (isinstance(limit, bool) or not isinstance(limit, (int, np.integer)) or limit < 0):
        raise SpecError([("limit", f"must be a whole number of candidates (0 or None: all): {limit!r:.60}")])


def _check_units(units) -> None:
    from ..io.units import LENGTH
    if not isinstance(units, str) or units not in LENGTH:
        raise SpecError([("units", f"must be a length unit ({', '.join(LENGTH)}): {units!r:.60}")])


def _rank(sols, limit, residual_quantum):
    sols.sort(key=lambda s: (np.floor(s[1] / residual_quantum), -s[2]))
    return sols[:limit] if limit else sols


def _other_branch(A, B, B0):
    """B mirrored about the line A → B0: the rocker pin of the other assembly branch with the same crank pin."""
    d = B0 - A
    return A + d / np.conj(d) * np.conj(B - A)


#: how function generators are ranked (ExactSolution.residual, .transmission)
FUNCTION_CRITERION = ("the output-angle residual at the precision points (in steps of 1e-9 rad), then the worst "
                      "transmission angle (largest first)")
SLIDER_CRITERION = ("the slider-position residual at the precision points (in steps of 1e-9 of the stroke), then the "
                    "worst transmission angle (largest first)")
MOTION_CRITERION = "the worst transmission angle over the stretch (largest first)"


# -- function generation -----------------------------------------------------------------------------------
def _spaced(inputs, outputs, spacing, n, out_name, what):
    """The precision points of a task: as given, or ``n`` points spaced on the interval ``inputs`` = (lo, hi)
    (``spacing`` "chebyshev" or "uniform") with the outputs from the callable ``outputs``."""
    if spacing is None:
        return inputs, outputs
    if spacing not in ("chebyshev", "uniform"):
        raise SpecError([("spacing", f"must be 'chebyshev', 'uniform' or None: {spacing!r}")])
    if not callable(outputs):
        raise SpecError([(out_name, f"with spacing, {out_name} must be a callable giving the {what} of an "
                                    "input angle")])
    try:
        lo, hi = (float(v) for v in inputs)
    except (TypeError, ValueError):
        raise SpecError([("inputs", "with spacing, inputs must be the input interval (lo, hi)")]) from None
    x = (chebyshev_points(n, min(lo, hi), max(lo, hi)) if spacing == "chebyshev"
         else np.linspace(min(lo, hi), max(lo, hi), n))
    x = x if lo < hi else x[::-1]
    try:
        y = np.asarray(outputs(x), dtype=float)
    except (TypeError, ValueError):
        raise SpecError([(out_name, f"the callable must return the {what}s of an array of input angles as "
                                    "numbers")]) from None
    return x, y


def _starts(starts, pair):
    try:
        starts = np.zeros((1, 2)) if starts is None else np.atleast_2d(np.asarray(starts, dtype=float))
    except (TypeError, ValueError):
        raise SpecError([("starts", f"must be {pair} pairs of numbers")]) from None
    if starts.ndim != 2 or starts.shape[1] != 2 or not np.all(np.isfinite(starts)):
        raise SpecError([("starts", f"must be {pair} pairs: shape {starts.shape}")])
    return starts


def function_candidates(inputs, outputs, *, spacing=None, n=3, ground=1.0, starts=None, grashof=None,
                        units="m", limit=20, samples=60) -> Candidates:
    """Four-bar function generators by Freudenstein's equation (module ``freudenstein``), ranked.

    ``inputs``, ``outputs``: the input and output angles (rad, from the ground line A0 → B0) of the precision
    points, exact for three, least squares for more. With ``spacing`` ("chebyshev" or "uniform"),
    ``inputs`` is the input interval (lo, hi), ``outputs`` a callable ψ(φ) and ``n`` the number of points.
    ``starts``: (φ0, ψ0) pairs added to every input and output (the free start angles of a task given as
    angle changes); default (0, 0). ``ground``: the length A0B0 (in ``units``). Each candidate is solved by the
    engine over the stretch between the first and last input (``samples`` per gap) and kept only if that
    stretch is buildable and no precision point lies on the other assembly branch (the engine follows the
    sketch's branch: such a point would be missed; with three points, every point must be met within
    ``REACH_TOL`` rad). Returns :class:`~assur.synthesis.exact_results.Candidates`: the kept ones ranked by the
    residual of the output angles at the precision points (in steps of 1e-9 rad), then by the worst transmission
    angle (``.criterion``), each with its ``residual`` and ``rank``; ``.rejected`` the candidates with a branch
    defect (and their residual), ``.counts`` every reason a candidate was dropped, ``.reason`` why the list is
    empty."""
    _check_grashof(grashof)
    inputs, outputs = _spaced(inputs, outputs, spacing, n, "outputs", "output angle")
    x, y = precision_pairs(inputs, outputs)
    if isinstance(ground, bool) or not isinstance(ground, (int, float, np.integer, np.floating)) \
            or not (np.isfinite(ground) and ground > 0):
        raise SpecError([("ground", f"must be a positive length: {ground!r:.60}")])
    _check_limit(limit)
    _check_units(units)
    starts = _starts(starts, "(φ0, ψ0)")
    out = Rejections()
    fits = []
    for phi0, psi0 in starts:
        phi, psi = x + phi0, y + psi0
        f = freudenstein(phi, psi, ground)
        if f is None:
            out.count("singular fit")
            continue
        lengths = (f["d"], abs(f["a"]), f["b"], abs(f["c"]))
        if not _grashof_ok(grashof_type(lengths), grashof):
            out.count(f"grashof filter ({grashof})")
            continue
        crank = np.angle(f["a"] * np.exp(1j * phi))          # the crank's direction at each point
        width = abs(phi[-1] - phi[0])
        start = crank[0] if phi[-1] > phi[0] else crank[0] - width
        if not _buildable(np.array([lengths]), np.array([start]), np.array([width]))[0]:
            out.count("toggle inside the stretch")
            continue
        fits.append((f, phi, psi, lengths))
    if not fits:
        return Candidates(criterion=FUNCTION_CRITERION, counts=out.counts)
    k = len(fits)
    geo = {"A0": np.zeros(k, complex), "B0": np.array([f["d"] for f, *_ in fits], complex)}
    geo["A"] = np.array([f["a"] * np.exp(1j * phi[0]) for f, phi, *_ in fits])
    geo["B"] = np.array([f["d"] + f["c"] * np.exp(1j * psi[0]) for f, _, psi, _ in fits])
    # the engine's input is the crank's direction from the ground line: φ, or φ + π for a crank with a < 0
    t = np.array([phi + (np.pi if f["a"] < 0 else 0.0) for f, phi, *_ in fits])
    q, cols = _stretch(t, samples)
    pos = _solve(geo, q)
    mu = _transmission(pos["A"], pos["B"], geo["B0"])

    def wrapped(a):
        return np.abs(np.angle(np.exp(1j * a)))

    def make(i, err, m, rank=0, defects=()):
        f, phi, psi, lengths = fits[i]
        note = ("Function generator by Freudenstein's equation: input = crank angle φ from the ground line "
                f"A0→B0, output = rocker angle ψ (B0→B{' + π' if f['c'] < 0 else ''}).")
        mech = _fourbar(geo["A0"][i], geo["B0"][i], geo["A"][i], geo["B"][i], units=units,
                        name="function generator", description=note)
        if f["a"] < 0:      # input = φ: the crank points along φ + π
            mech = dataclasses.replace(mech, drivers=tuple(dataclasses.replace(d, zero=np.pi) for d in mech.drivers))
        return ExactSolution(mech, phi, err, m, grashof_type(lengths), lengths, rank, tuple(defects), "rad")

    sols, rejected_keys = [], set()
    for i, (f, phi, psi, lengths) in enumerate(fits):
        B = pos["B"][i]
        if not np.all(np.isfinite(B)):
            out.count("does not assemble along the stretch")
            continue
        flip = np.pi if f["c"] < 0 else 0.0
        miss = wrapped(np.angle(B[cols] - geo["B0"][i]) + flip - psi)
        # a precision point met on the other assembly branch: the engine, following the sketch's branch, misses it
        other = wrapped(np.angle(_other_branch(pos["A"][i, cols], B[cols], geo["B0"][i]) - geo["B0"][i]) + flip - psi)
        wrong = np.flatnonzero(other < miss - REACH_TOL)
        if len(wrong) or (len(phi) == 3 and np.max(miss) > REACH_TOL):
            where = wrong if len(wrong) else np.flatnonzero(miss > REACH_TOL)
            key = tuple(np.round(np.asarray(lengths) / ground, 9)) + (round(float(np.max(miss)), 12),)
            if key in rejected_keys:          # the same linkage from another start, rejected already
                continue
            rejected_keys.add(key)
            out.add(make(i, float(np.max(miss)), float(mu[i]),
                         defects=[f"branch: point {', '.join(str(j + 1) for j in where)} on the other assembly "
                                  "branch"]), "branch defect")
            continue
        sols.append((i, float(np.max(miss)), float(mu[i])))
    # start angles that differ by a rotation of the whole task fit the same linkage: keep one of each
    seen, unique = set(), []
    for i, err, m in sorted(sols, key=lambda r: (np.floor(r[1] / 1e-9), -r[2])):
        key = tuple(np.round(np.asarray(fits[i][3]) / ground, 9)) + (round(err, 12),)
        if key not in seen:
            seen.add(key)
            unique.append((i, err, m))
    out.count("the same linkage from another start", len(sols) - len(unique))
    result = [make(i, err, m, rank) for rank, (i, err, m) in enumerate(_rank(unique, limit, 1e-9), start=1)]
    out.rejected.sort(key=lambda r: r.residual)
    return Candidates(result, criterion=FUNCTION_CRITERION, rejected=out.rejected, counts=out.counts)


def function_generation(inputs, outputs, *, spacing=None, ground=1.0, **options) -> Candidates:
    """Four-bar function generators (ranked list of Mechanism, with ``.rejected``, ``.criterion`` and ``.reason``
    as :class:`~assur.synthesis.exact_results.Candidates`); see :func:`function_candidates`."""
    c = function_candidates(inputs, outputs, spacing=spacing, ground=ground, **options)
    return c.with_items(s.mechanism for s in c)


# -- slider-crank function generation ----------------------------------------------------------------------
def _slider_crank(a, e, phi0, s0, flip, *, units, name, description):
    """The Mechanism: A0 at the origin, the slide line y = e along +x, sketched at crank angle phi0 (the crank
    points along phi0 + π when ``flip``; the driver's input is phi0 either way) with B at (s0, e)."""
    from ..io.builder import Builder
    t = phi0 + (np.pi if flip else 0.0)
    b_ = (Builder(units=units, angle="rad", name=name, description=description)
          .point("A0", 0.0, 0.0).point("A", a * np.cos(t), a * np.sin(t)).point("B", float(s0), float(e))
          .frame("A0").link("crank", "A0", "A").link("rod", "A", "B")
          .slider(point="B", guide="frame", through="A0", angle=0.0, offset=float(e), name="slide")
          .crank("crank", pivot="A0", arm="A", zero=float(np.pi) if flip else 0.0, name="crank"))
    return b_.build()


def slider_candidates(inputs, displacements, *, spacing=None, n=3, starts=None, units="m", limit=20,
                      samples=60) -> Candidates:
    """Slider-crank function generators (module ``freudenstein``, ``slider_freudenstein``), ranked.

    The crank turns about ``A0`` (the origin); the pin ``B`` of the rod ``A``–``B`` slides on a frame line of
    direction +x through A0, offset by ``e`` (to its left, the ``offset`` of a ``[[prismatic]]`` table).
    ``inputs``: the crank angles (rad, from the line's direction) of the precision points; ``displacements``:
    the slider positions along the line, measured from the foot of the perpendicular from A0 (in ``units``).
    Loop closure (s − a cos φ)² + (e − a sin φ)² = b² is linear in (2a, 2ae, a² + e² − b²): exact for three
    points, least squares for more. With ``spacing`` ("chebyshev" or "uniform"), ``inputs`` is the input
    interval (lo, hi), ``displacements`` a callable s(φ) and ``n`` the number of points. ``starts``: (φ0, s0)
    pairs added to every input and position (a task given as changes from a start); default (0, 0). Each
    candidate is solved by the engine over the stretch between the first and last input (``samples`` per gap)
    and kept only if that stretch assembles without a toggle and no precision point lies nearer the other
    assembly branch (B mirrored about the foot of A on the line) than the sketch's; ranked by the residual (in steps of 1e-9 of the stroke), then by the worst
    transmission angle."""
    from ..engine import compile as compile_, solve
    _check_limit(limit)
    _check_units(units)
    inputs, displacements = _spaced(inputs, displacements, spacing, n, "displacements", "slider position")
    x, y = precision_pairs(inputs, displacements, where=("inputs", "displacements"))
    starts = _starts(starts, "(φ0, s0)")
    scale = max(float(np.ptp(y)), float(np.max(np.abs(y))), 1e-300)
    sols, out = [], Rejections()
    for phi0, s0 in starts:
        phi, s = x + phi0, y + s0
        f = slider_freudenstein(phi, s)
        if f is None:
            out.count("singular fit")
            continue
        a, b, e, flip = f["a"], f["b"], f["e"], f["flip"]
        q, cols = _stretch(phi[None, :], samples)
        # assembles without a toggle: |e − a sin θ| < b over the whole stretch (dense check, then the engine)
        th = q[0] + (np.pi if flip else 0.0)
        if not np.all(np.abs(e - a * np.sin(th)) < b * (1 - 1e-9)):
            out.count("toggle inside the stretch")
            continue
        kind = "crank-slider" if a + abs(e) < b else "rocker-slider"
        note = ("Slider-crank function generator (loop closure, exact for three points): input = crank angle φ "
                "from the slide line's direction, output = the slider's position along the line from the foot "
                f"of A0's perpendicular{' (the crank points along φ + π)' if flip else ''}.")
        # the sketch's branch: B ahead of or behind A's foot on the line, as at the first point
        mech = _slider_crank(a, e, float(phi[0]), float(s[0]), flip, units=units,
                             name="slider-crank function generator", description=note)
        st = solve(compile_(mech), inputs=q[0], order=0, on_unbuildable="nan", backend="numpy")
        A, B = st.point("A").pos, st.point("B").pos
        if not (np.all(np.isfinite(B)) and np.all(np.isfinite(A))):
            out.count("does not assemble along the stretch")
            continue
        miss = np.abs(B[cols, 0] - s)
        err = float(np.max(miss))
        rod = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
        mu = float(np.min(np.pi / 2 - np.abs(np.arcsin(np.clip(np.sin(rod), -1.0, 1.0)))))
        # a precision point met better on the other assembly branch (B mirrored about A's foot): branch defect
        other = np.abs(2 * A[cols, 0] - B[cols, 0] - s)
        wrong = np.flatnonzero(other < miss - REACH_TOL * scale)
        if len(wrong):
            out.add(SliderSolution(mech, phi, err, mu, kind, a, b, e, 0, (
                f"branch: point {', '.join(str(j + 1) for j in wrong)} on the other assembly branch",), units),
                "branch defect")
            continue
        sols.append((SliderSolution(mech, phi, err, mu, kind, a, b, e, unit=units), err, mu))
    sols.sort(key=lambda r: (np.floor(r[1] / (1e-9 * scale)), -r[2]))
    kept = [dataclasses.replace(r[0], rank=k) for k, r in enumerate(sols[:limit] if limit else sols, start=1)]
    return Candidates(kept, criterion=SLIDER_CRITERION, rejected=out.rejected, counts=out.counts)


def slider_function_generation(inputs, displacements, *, spacing=None, **options) -> Candidates:
    """Slider-crank function generators (ranked list of Mechanism, with the rejections of
    :class:`~assur.synthesis.exact_results.Candidates`); see :func:`slider_candidates`."""
    c = slider_candidates(inputs, displacements, spacing=spacing, **options)
    return c.with_items(s.mechanism for s in c)


# -- motion generation -------------------------------------------------------------------------------------
def dyads(poses, *, free=None, samples=None, radius=1.5):
    """The RR dyads of 3, 4 or 5 poses → (centres, circle points) complex arrays in the poses' coordinates
    (circle points in the first pose). The rule for the free choice: 3 poses — the centres ``free`` (m, 2), or
    ``samples`` (default 24) centres on a circle of ``radius`` × the poses' spread about their mean point;
    4 poses — the Burmester centre-point curve sampled on ``samples`` (default 36) lines through the pole
    P_1k, or the points ``free`` moved onto the curve along their lines through that pole; 5 poses — the
    finite set of Burmester points (``free`` not allowed)."""
    P = Poses(poses)
    if free is not None:
        try:
            F = np.asarray(free, dtype=float)
        except (TypeError, ValueError):
            raise SpecError([("free", "must be an (m, 2) array of points")]) from None
        if F.ndim != 2 or F.shape[1] != 2 or not np.all(np.isfinite(F)):
            raise SpecError([("free", f"must be an (m, 2) array of finite points: shape {F.shape}")])
        if P.n == 5:
            raise SpecError([("free", "five poses have a finite set of dyads: there is no free choice")])
        Fl = P.to_local(F[:, 0] + 1j * F[:, 1])
    if P.n == 3:
        if free is None:
            m = samples or 24
            Fl = radius * np.exp(2j * np.pi * np.arange(m) / m)
        G, Z, res = three_pose_dyads(P, Fl)
    elif P.n == 4:
        G, Z, res = snap_to_curve(P, Fl) if free is not None else centre_curve(P, samples or 36)
    else:
        G, Z, res = burmester_points(P)
    ok = np.isfinite(Z) & (res < 1e-7) & (np.abs(Z - G) > 1e-6)
    return P.to_world(G[ok]), P.to_world(Z[ok])


def motion_candidates(poses, *, free=None, grashof=None, samples=None, radius=1.5, units="m", limit=20,
                      per_gap=30) -> Candidates:
    """Four-bars that carry the coupler through the poses (n, 3) = (x, y, angle rad), ranked by the worst
    transmission angle over the stretch. The dyads come from :func:`dyads`; every ordered pair (crank,
    rocker) with distinct ground pivots is a candidate, kept only if its Grashof type passes ``grashof``, the
    crank angles of the poses come in one turning sense within one turn, the stretch between the first and
    last pose is buildable without a toggle, and the engine, driven along it, reaches every pose on the
    branch of the sketch (positions of A, B and P within 1e-6 of the task's size). Returns
    :class:`~assur.synthesis.exact_results.Candidates` (``.counts``: how many pairs each defect removed)."""
    _check_grashof(grashof)
    _check_limit(limit)
    _check_units(units)
    out = Rejections()
    P = Poses(poses)
    G, Z = dyads(poses, free=free, samples=samples, radius=radius)
    poses = np.asarray(poses, float)
    d = poses[:, 0] + 1j * poses[:, 1]
    R = np.exp(1j * (poses[:, 2] - poses[0, 2]))
    moving = R[None, :] * (Z[:, None] - d[0]) + d[None, :]          # (m, n) circle points in every pose
    m = len(G)
    ii, jj = (g.ravel() for g in np.meshgrid(np.arange(m), np.arange(m), indexing="ij"))
    keep = (ii != jj) & (np.abs(G[jj] - G[ii]) > 1e-6 * P.scale) & (np.abs(Z[jj] - Z[ii]) > 1e-9 * P.scale)
    ii, jj = ii[keep], jj[keep]
    lengths = np.stack([np.abs(G[jj] - G[ii]), np.abs(Z[ii] - G[ii]), np.abs(Z[jj] - Z[ii]),
                        np.abs(Z[jj] - G[jj])], axis=1)
    kinds = np.array([grashof_type(row) for row in lengths], dtype=object)
    keep = np.array([_grashof_ok(kd, grashof) for kd in kinds], dtype=bool)
    out.count(f"grashof filter ({grashof})", int(np.count_nonzero(~keep)))
    ii, jj, lengths = ii[keep], jj[keep], lengths[keep]
    theta = np.angle(moving[ii] - G[ii, None]) - np.angle(G[jj] - G[ii])[:, None]      # (k, n) crank angles
    cand, passed = [], np.zeros(len(ii), dtype=bool)
    for sense, sign in (("ccw", 1.0), ("cw", -1.0)):
        gaps = np.mod(sign * np.diff(theta, axis=1), 2 * np.pi)
        total = gaps.sum(axis=1)
        t = theta[:, :1] + sign * np.concatenate([np.zeros((len(theta), 1)), np.cumsum(gaps, axis=1)], axis=1)
        ok = np.all(gaps > 1e-9, axis=1) & (total < 2 * np.pi)
        ok &= _buildable(lengths, t[:, 0] if sign > 0 else t[:, -1], total)
        passed |= ok
        cand += [(ii[r], jj[r], sense, t[r], lengths[r]) for r in np.flatnonzero(ok)]
    out.count("order defect or toggle inside the stretch", int(np.count_nonzero(~passed)))
    if not cand:
        return Candidates(criterion=MOTION_CRITERION, counts=out.counts)
    ii = np.array([c[0] for c in cand])
    jj = np.array([c[1] for c in cand])
    geo = {"A0": G[ii], "B0": G[jj], "A": Z[ii], "B": Z[jj], "P": np.full(len(cand), d[0])}
    q, cols = _stretch(np.array([c[3] for c in cand]), per_gap)
    pos = _solve(geo, q)
    mu = _transmission(pos["A"], pos["B"], geo["B0"])
    tol = REACH_TOL * P.scale
    sols = []
    for r, (i, j, sense, t, lengths) in enumerate(cand):
        if not all(np.all(np.isfinite(pos[n][r])) for n in ("A", "B", "P")):
            continue
        err = max(np.max(np.abs(pos["P"][r, cols] - d)), np.max(np.abs(pos["A"][r, cols] - moving[i])),
                  np.max(np.abs(pos["B"][r, cols] - moving[j])))
        if err <= tol:
            sols.append((r, float(err), float(mu[r])))
        else:
            out.count("a pose not reached on the sketch's branch")
    result = []
    for rank, (r, err, mu_r) in enumerate(_rank(sols, limit, np.inf), start=1):
        i, j, sense, t, lengths = cand[r]
        note = (f"Motion generator (Burmester, {len(d)} poses), sketched in the first pose; the crank turns "
                f"{sense} from the first pose to the last.")
        mech = _fourbar(G[i], G[j], Z[i], Z[j], d[0], sense=sense, units=units, name="motion generator",
                        description=note)
        result.append(ExactSolution(mech, t if sense == "ccw" else -t, err, mu_r,
                                    grashof_type(lengths), tuple(float(v) for v in lengths), rank, (), units))
    return Candidates(result, criterion=MOTION_CRITERION, counts=out.counts)


def motion_generation(poses, *, free=None, **options) -> Candidates:
    """Four-bar motion generators (ranked list of Mechanism, with the counts of
    :class:`~assur.synthesis.exact_results.Candidates`); see :func:`motion_candidates`."""
    c = motion_candidates(poses, free=free, **options)
    return c.with_items(s.mechanism for s in c)


__all__ = ["Candidates", "ExactSolution", "GRASHOF_FILTERS", "GRASHOF_TYPES", "SliderSolution", "chebyshev_points",
           "dyads", "function_candidates", "function_generation", "grashof_type", "motion_candidates", "motion_generation",
           "slider_candidates", "slider_function_generation"]
