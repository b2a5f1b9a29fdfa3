"""The placement of a path-synthesis design solved in closed form: its position, orientation and size.

Many path problems place the whole mechanism with design variables: a frame pivot's coordinates (x0, y0), the
frame line's angle θ0, and lengths that only set its size. Their best values for a given shape have a closed form:
the target points t_i are matched by a similarity s·R(φ)·q_i + d of the points q_i that the design traces with
x0 = y0 = θ0 = 0, and least squares gives (orthogonal Procrustes analysis with scaling; Umeyama, IEEE PAMI 13(4),
1991, for the general case), with a_i = q_i − q̄, b_i = t_i − t̄ over the n assembled targets,

    A = Σ|a_i|²,  D = Σ a_i·b_i,  C = Σ a_i × b_i,
    φ = atan2(C, D),  s = √(C² + D²)/A,  d = t̄ − s·R(φ)·q̄,
    Σ|t_i − s·R(φ)·q_i − d|² = Σ|b_i|² − (C² + D²)/A.

The optimiser then searches the shape alone (C3: seven variables instead of ten) and every design it tries stands
for its best-placed copy; a small design in a large box is found at any size the box allows. The bounds stay
exact: s is clipped to the interval that keeps every size variable in its bounds (the objective is a quadratic in s
for a fixed φ, which does not depend on s), and d is clipped to the translation variables' bounds (exact given s
and φ; when a translation bound is active, the joint optimum may differ, and the design is still honest: it is
evaluated where it is placed).

Which variables place the mechanism is found on the problem, not declared: :func:`detect` solves the template at
random designs of the box and keeps a variable pair (x, y) whose change translates every target point by exactly
that change, an angle variable whose change rotates them about (x, y), and the length variables whose common
factor scales them about (x, y) — each checked to 1e-9 of the points' size on every trial design. A problem where
these do not hold, or whose objective or constraints would change under a placement (a term other than the
squared deviation, a limit other than transmission or buildability, four-bar constraint lengths that do not follow
the size), keeps every variable searched (``[targets] placement = "explicit"``, which a file can also ask for).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kernels.similarity import similarity

TWO_PI = 2.0 * np.pi
#: trial designs drawn from the box to check a placement; the fewest of them that must assemble at every target
TRIALS, ASSEMBLED = 64, 4
#: a placement holds when the predicted points agree with the solved ones to this fraction of the points' size
AGREEMENT = 1e-9
#: the quantities a placement leaves unchanged (the limits and terms that can stand beside it)
INVARIANT = frozenset({"transmission.min", "unbuildable"})


@dataclass(frozen=True, slots=True)
class PlacementVariables:
    """The variables that place a design: ``x``, ``y`` translate it, ``angle`` (or None) turns it about (x, y),
    ``scale`` (possibly empty) are lengths whose common factor sizes it about (x, y). Indices into the problem's
    variables."""
    x: int
    y: int
    angle: int | None
    scale: tuple[int, ...]

    @property
    def solved(self) -> tuple[int, ...]:
        """The variables each evaluation finds (not searched): the translation and the angle."""
        return (self.x, self.y) + (() if self.angle is None else (self.angle,))


def settle(data, problem, source):
    """The problem with its placement solved per design where it applies and the file does not ask for
    "explicit" (``[targets] placement``); a file that asks for "inner" where it cannot apply gets the reason."""
    import dataclasses
    t = problem.targets
    if t is None or t.kind != "points" or t.placement != "inner":
        return problem
    found, why = detect(problem)
    if found is not None:
        return dataclasses.replace(problem, placement=found)
    if isinstance(data.get("targets"), dict) and "placement" in data["targets"]:
        from ..errors import SpecError
        raise SpecError([("targets.placement", f"'inner' cannot be used here: {why} (use \"explicit\")")],
                        source=source)
    return problem


def refusal(problem) -> str | None:
    """Why the placement cannot be solved per design on this problem, before any trial (None when it may)."""
    t = problem.targets
    if t is None or t.kind != "points":
        return "it needs point targets"
    if t.timing == "path":
        return "it needs timed targets (prescribed, uniform or free), not timing = \"path\""
    if t.timing == "free" and t.free_timing == "inner":
        return "free timing solved per design depends on the placement (use free_timing = \"explicit\")"
    if problem.deviation != "squared":
        return "it needs deviation = \"squared\" (the closed form is a least-squares fit)"
    if problem.terms:
        return f"the objective term {problem.terms[0].quantity!r} may change with the placement"
    for lim in problem.limits:
        if lim.expression is not None or lim.quantity not in INVARIANT:
            return f"the limit on {lim.quantity!r} may change with the placement"
    return None


def detect(problem, rng_seed: int = 0) -> tuple[PlacementVariables | None, str | None]:
    """(the problem's placement, None) or (None, why there is none), from trial designs of the box (module
    docstring). Deterministic: the trials come from a fixed seed."""
    why = refusal(problem)
    if why:
        return None, why
    timing = set(problem.targets.input_variables) | ({problem.targets.start} if problem.targets.start else set())
    lo, hi = problem.bounds.T
    periodic = np.array([v.periodic for v in problem.variables], dtype=bool)

    def wrap(X):
        return np.where(periodic, np.mod(X, TWO_PI), X)
    from scipy.stats import qmc
    X = wrap(lo + qmc.LatinHypercube(d=problem.n_vars, rng=np.random.default_rng(rng_seed)).random(TRIALS)
             * (hi - lo))
    q0, ok = points(problem, X, "numpy")
    keep = ok.all(axis=1)
    if keep.sum() < ASSEMBLED:
        return None, f"fewer than {ASSEMBLED} of {TRIALS} trial designs assemble at every target"
    X, q0 = X[keep], q0[keep]
    size = np.abs(q0).max() + np.ptp(q0, axis=1).max()

    def moved(X1, predicted) -> bool:
        q1, ok1 = points(problem, X1, "numpy")
        return bool(ok1.all() and np.abs(q1 - predicted).max() <= AGREEMENT * max(size, np.abs(predicted).max()))
    names = problem.names
    lengths = [i for i, v in enumerate(problem.variables) if v.kind == "length" and names[i] not in timing]
    step = 0.37 * max(float(np.max(hi[lengths] - lo[lengths])) if lengths else 1.0, 1e-300)
    translation = {}
    for axis in (0, 1):
        for i in lengths:
            if i in translation.values():
                continue
            X1 = X.copy()
            X1[:, i] += step
            shift = np.zeros(2)
            shift[axis] = step
            if moved(X1, q0 + shift):
                translation[axis] = i
                break
    if len(translation) < 2:
        return None, "no pair of variables translates the mechanism"
    x, y = translation[0], translation[1]
    centre = X[:, [x, y]][:, None, :]                                   # (k, 1, 2)
    angle = None
    turn = 0.61
    c, s = np.cos(turn), np.sin(turn)
    for i, v in enumerate(problem.variables):
        if not v.periodic or names[i] in timing:
            continue
        X1 = X.copy()
        X1[:, i] += turn
        a = q0 - centre
        if moved(wrap(X1), centre + np.stack([c * a[..., 0] - s * a[..., 1], s * a[..., 0] + c * a[..., 1]], -1)):
            angle = i
            break
    scale = tuple(i for i in lengths if i not in (x, y))
    if scale:
        X1 = X.copy()
        X1[:, list(scale)] *= 0.73
        if not moved(X1, centre + 0.73 * (q0 - centre)):
            scale = ()
    if problem.fourbar:             # the four-bar constraints' lengths must follow the size and ignore the rest
        from .design import expression_env, fourbar_lengths, parameters
        X1 = X.copy()
        X1[:, [x, y]] += 0.29 * step
        if angle is not None:
            X1[:, angle] += turn
        factor = 0.73 if scale else 1.0
        X1[:, list(scale)] *= factor
        L0, L1 = (fourbar_lengths(problem, expression_env(problem, parameters(problem, Z), Z), len(Z))
                  for Z in (X, wrap(X1)))
        if not np.allclose(L1, factor * L0, rtol=AGREEMENT, atol=0.0):
            return None, "the four-bar constraints' lengths do not scale with the mechanism"
    return PlacementVariables(x, y, angle, scale), None


def points(problem, X, backend) -> tuple[np.ndarray, np.ndarray]:
    """(q (n, N, 2) the target point at the targets' inputs, ok (n, N) assembled and finite) of wrapped designs X
    (n, n_vars), solved on ``backend``."""
    from ..engine import solve
    from .design import parameters, target_inputs
    params = parameters(problem, X)
    finite = np.all(np.isfinite(params), axis=1)
    params = np.where(finite[:, None], params, problem.plan.defaults)
    theta = target_inputs(problem, X)
    st = solve(problem.plan, params[:, None, :], theta[..., None], order=0, backend=backend)
    q = st.pos[:, :, problem.plan.point_index(problem.targets.point), :]
    ok = st.valid & finite[:, None] & np.all(np.isfinite(q), axis=-1)
    return np.where(ok[..., None], q, 0.0), ok


def reference(placement: PlacementVariables, X) -> np.ndarray:
    """Designs X (n, n_vars) with the translation and the angle at 0: the designs whose points :func:`fit` places."""
    R = np.array(X, dtype=float, copy=True)
    R[:, list(placement.solved)] = 0.0
    return R


def limits(placement: PlacementVariables, X, bounds) -> np.ndarray:
    """(n, 6) per design: the interval of the size factor s that keeps every size variable in its bounds, then
    the bounds of x and of y. X (n, n_vars), bounds (n_vars, 2)."""
    n = len(X)
    s_lo, s_hi = np.full(n, 0.0), np.full(n, np.inf)
    for i in placement.scale:
        v, (lo, hi) = X[:, i], bounds[i]
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = np.where(v > 0, lo / v, hi / v), np.where(v > 0, hi / v, lo / v)
        nz = v != 0
        s_lo = np.where(nz, np.maximum(s_lo, a), s_lo)
        s_hi = np.where(nz, np.minimum(s_hi, b), s_hi)
    if not placement.scale:
        s_lo, s_hi = np.ones(n), np.ones(n)
    out = np.empty((n, 6))
    out[:, 0], out[:, 1] = s_lo, s_hi
    out[:, 2:4], out[:, 4:6] = bounds[placement.x], bounds[placement.y]
    return out


def fit(q, ok, txy, lim, rotate: bool):
    """The best placement of each design: q (n, N, 2) the points at the reference, ok (n, N) the assembled ones,
    txy (N, 2) the targets, lim (n, 6) :func:`limits`. Returns (s, φ, dx, dy), each (n,)."""
    w = ok.astype(float)
    n = w.sum(axis=1)
    m = np.maximum(n, 1.0)
    qc = (q * w[..., None]).sum(axis=1) / m[:, None]                     # (n, 2)
    tc = (w[..., None] * txy[None]).sum(axis=1) / m[:, None]
    a, b = (q - qc[:, None]) * w[..., None], (txy[None] - tc[:, None]) * w[..., None]
    A = (a * a).sum(axis=(1, 2))
    C = (a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]).sum(axis=1)
    D = (a * b).sum(axis=(1, 2))
    return similarity(qc[:, 0], qc[:, 1], tc[:, 0], tc[:, 1], A, C, D, lim.T, float(rotate))


def place(placement: PlacementVariables, X, bounds, s, phi, dx, dy) -> np.ndarray:
    """The reference designs X (n, n_vars) placed: the size variables times s (kept in their ``bounds`` (n_vars, 2):
    at the end of s's interval the product may pass a bound by a rounding), the angle φ (wrapped into [0, 2π)), the
    translation (dx, dy)."""
    P = np.array(X, dtype=float, copy=True)
    if placement.scale:
        cols = list(placement.scale)
        P[:, cols] = np.clip(P[:, cols] * s[:, None], bounds[cols, 0], bounds[cols, 1])
    P[:, placement.x], P[:, placement.y] = dx, dy
    if placement.angle is not None:
        P[:, placement.angle] = np.mod(phi, TWO_PI)
    return P


__all__ = ["PlacementVariables", "detect", "settle", "fit", "limits", "place", "points", "reference", "refusal"]
