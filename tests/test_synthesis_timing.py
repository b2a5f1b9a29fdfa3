"""Free timing solved inside the evaluation (assur.synthesis.timing, assur.kernels.ordered).

References, all written here: the four-bar's coupler point in closed form (docs/papers/synthesis_benchmarks.md §1.2,
geometric form), a dense search over the crank angle for each target (20 000 angles, then scipy's bounded scalar
minimisation around the best), the ordered assignment by brute force over every start and every non-decreasing
path, and a dense ordered search by dynamic programming over all starts.
"""
import itertools
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from assur.errors import SpecError
from assur.kernels import ordered
from assur.synthesis import Evaluator, load_problem, problem_from_dict, synthesize
from assur.synthesis.space import SearchSpace

ROOT = Path(__file__).resolve().parents[1]
C1 = ROOT / "examples" / "synthesis" / "c1_six_points_line.toml"
TWO_PI = 2 * np.pi


def c1_problem(_use=None, **targets):
    """C1's problem file with free timing solved per design (unless ``free_timing`` is given)."""
    targets.setdefault("free_timing", "inner")
    data = tomllib.loads(C1.read_text(encoding="utf-8"))
    data["targets"].update(targets)
    data.pop("solver", None)
    use = _use
    if use is not None:
        data["constraints"]["use"] = use
    return problem_from_dict(data, base_dir=C1.parent, source=str(C1))


def coupler(x, theta):
    """Coupler point (…, 2) of canonical vectors x = [r1, r2, r3, r4, rcx, rcy, x0, y0, θ0] at crank angles theta
    (the "+" branch; NaN where the linkage cannot assemble)."""
    r1, r2, r3, r4, rcx, rcy, x0, y0, t0 = x[:9]
    ax, ay = r2 * np.cos(theta), r2 * np.sin(theta)
    dx, dy = r1 - ax, -ay
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore"):
        t3 = np.arctan2(dy, dx) + np.arccos((r3 * r3 + d * d - r4 * r4) / (2 * r3 * d))
    px = ax + rcx * np.cos(t3) - rcy * np.sin(t3)
    py = ay + rcx * np.sin(t3) + rcy * np.cos(t3)
    return np.stack([np.cos(t0) * px - np.sin(t0) * py + x0, np.sin(t0) * px + np.cos(t0) * py + y0], axis=-1)


def dense_nearest(x, target, n=20_000):
    """The crank angle nearest the target and its distance: a dense grid, then a bounded 1-D minimisation."""
    grid = np.linspace(0, TWO_PI, n, endpoint=False)
    d = np.linalg.norm(coupler(x, grid) - target, axis=-1)
    k = int(np.nanargmin(d))
    h = TWO_PI / n

    def dist(t):
        v = np.linalg.norm(coupler(x, np.array(t)) - target)
        return v if np.isfinite(v) else 1e300
    r = minimize_scalar(dist, bounds=(grid[k] - h, grid[k] + h), method="bounded", options={"xatol": 1e-13})
    return (r.x, r.fun) if r.fun < d[k] else (grid[k], d[k])


def crank_rockers(rng, n):
    """n Grashof crank-rockers (the crank r2 the shortest link, so it turns fully) with a random coupler point and
    frame pose, as C1 design vectors (the six crank angles left 0: the evaluation solves them)."""
    out = []
    while len(out) < n:
        r = rng.uniform(5, 50, 4)
        s = np.sort(r)
        if not (r[1] == s[0] and s[0] + s[3] < s[1] + s[2] - 1.0):
            continue
        out.append(np.concatenate([r, rng.uniform(-40, 40, 2), rng.uniform(-20, 40, 2), [rng.uniform(0, TWO_PI)],
                                   np.zeros(6)]))
    return np.array(out)


# -- the ordered assignment on the samples ------------------------------------------------------------------------
def brute_cyclic(C):
    """Least cost over every start s and every non-decreasing path s = x_0 ≤ … ≤ x_{N−1} ≤ s + M."""
    N, M = C.shape
    best = np.inf
    for s in range(M):
        for rest in itertools.combinations_with_replacement(range(s, s + M + 1), N - 1):
            best = min(best, C[0, s] + sum(C[i + 1, u % M] for i, u in enumerate(rest)))
    return best


def brute_ascending(C):
    N, M = C.shape
    return min(sum(C[i, u] for i, u in enumerate(p)) for p in itertools.combinations_with_replacement(range(M), N))


@pytest.mark.parametrize("seed", range(6))
def test_ordered_assignment_is_exact_against_brute_force(seed):
    rng = np.random.default_rng(seed)
    N, M = 4, 7
    C = rng.random((N, M))
    C[rng.random((N, M)) < 0.15] = ordered.BIG        # unassembled samples
    for mode, brute in ((1, brute_cyclic), (3, brute_ascending)):
        cyclic = mode == 1
        path, cost = (ordered.cyclic_assignment if cyclic else ordered.ascending_assignment)(C)
        assert cost == pytest.approx(brute(C), rel=1e-12)
        # the path is admissible and costs what it says
        assert np.all(np.diff(path) >= 0)
        assert path[-1] - path[0] <= (M if cyclic else M - 1) and 0 <= path[0] < M
        assert sum(C[i, u % M] for i, u in enumerate(path)) == pytest.approx(cost, rel=1e-12)


def test_compiled_and_interpreted_assignments_agree():
    if ordered.compiled() is None:
        pytest.skip("numba is not installed")
    rng = np.random.default_rng(3)
    path = rng.normal(size=(6, 36, 2))
    valid = rng.random((6, 36)) > 0.1
    xy = rng.normal(size=(7, 2))
    for mode in range(4):
        a = ordered.compiled()(path, valid, xy, 2, mode, 0.0)
        b = ordered._batch(path, valid, xy, 2, mode, 0.0)
        assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


def test_the_interpreted_route_costs_all_designs_at_once_as_design_by_design(monkeypatch):
    """Without numba, :func:`ordered.assign` computes the costs of every design at once (numpy): the same numbers as
    :func:`ordered._costs` design by design (points and poses, both powers, a NaN sample), and the same assignment."""
    rng = np.random.default_rng(4)
    for K, weight in ((2, 0.0), (3, 0.7)):
        path = rng.normal(size=(5, 30, K)) * [1.0, 1.0, 4.0][:K]
        path[1, 3, 0] = np.nan
        valid = rng.random((5, 30)) > 0.1
        xy = rng.normal(size=(4, K))
        for power in (1, 2):
            C = ordered.costs(path, valid, xy, power, weight)
            for d in range(5):
                one = np.empty((4, 30))
                ordered._costs(path[d], valid[d], xy, power, weight, one)
                assert np.array_equal(C[d], one)
            monkeypatch.setattr(ordered, "compiled", lambda: None)
            for mode in range(4):
                a, b = ordered.assign(path, valid, xy, power, mode, weight), ordered._batch(path, valid, xy, power,
                                                                                           mode, weight)
                assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])


# -- the inner solve against a dense search over the crank angle ---------------------------------------------------
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_inner_timing_is_each_targets_nearest_point_of_the_curve(backend):
    """Without an order constraint each target gets the nearest point of the coupler curve: the same distance as a
    dense search over the crank angle (to 1e-9), at the same angle where the nearest point is well separated."""
    p = c1_problem(_use=["grashof", "assembly", "nondegenerate"])
    assert p.targets.free_timing == "inner"
    ev = Evaluator(p, backend=backend)
    X = crank_rockers(np.random.default_rng(11), 12)
    e = ev(X, detail=True)
    theta = e.x[:, 9:]
    assert np.allclose(e.x[:, :9], X[:, :9])                # the design variables pass through
    checked = 0
    for x, th, dist in zip(X, theta, e.quantities["distances"]):
        for i, target in enumerate(p.targets.xy):
            t_ref, d_ref = dense_nearest(x, target)
            assert dist[i] == pytest.approx(d_ref, rel=1e-9, abs=1e-9)
            # the angle reported gives that distance in the closed form
            assert np.linalg.norm(coupler(x, th[i]) - target) == pytest.approx(d_ref, rel=1e-9, abs=1e-9)
            grid = np.linspace(0, TWO_PI, 720, endpoint=False)
            far = np.abs(np.angle(np.exp(1j * (grid - t_ref)))) > 0.2
            if np.nanmin(np.linalg.norm(coupler(x, grid[far]) - target, axis=-1)) > d_ref + 1e-3:
                assert abs(np.angle(np.exp(1j * (th[i] - t_ref)))) < 1e-6   # a unique nearest point: its angle
                checked += 1
    assert checked > 30


def dense_ordered(x, targets, n=1440):
    """Least Σ d² over crank angles on a grid of n per turn, in counter-clockwise order within one turn from any
    start: dynamic programming over all starts at once (n × n per target)."""
    grid = np.linspace(0, TWO_PI, n, endpoint=False)
    P = coupler(x, grid)
    C = np.sum((P[None, :, :] - targets[:, None, :]) ** 2, axis=-1)
    C = np.where(np.isfinite(C), C, np.inf)
    idx = np.arange(n)
    ext = np.concatenate([C, C, C[:, :1]], axis=1)                    # unrolled over two turns
    best = np.full((n, 2 * n + 1), np.inf)
    best[idx, idx] = C[0]                                              # start s at s
    for i in range(1, len(targets)):
        run = np.minimum.accumulate(best, axis=1)
        best = ext[i][None, :] + run
        u = np.arange(2 * n + 1)
        best[u[None, :] > idx[:, None] + n] = np.inf                   # within one turn of the start
        best[u[None, :] < idx[:, None]] = np.inf
    return float(best.min())


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_inner_timing_in_cyclic_order_against_a_dense_ordered_search(backend):
    """With cyclic_order (C1's set) the solved angles pass the targets in order within one counter-clockwise turn.
    Where each target's nearest point already comes in that order, they are those nearest points (exact); where the
    order binds (targets pushed onto one stretch of the curve), Σ d² lies between the unconstrained value and the best
    ordered choice on a dense grid of 1440 angles plus the sampling error of the 360 samples (3 %), and converges to
    the dense value as the samples grow (5760: within 5e-4)."""
    p = c1_problem()
    ev = Evaluator(p, backend=backend)
    free = Evaluator(c1_problem(_use=["grashof", "assembly", "nondegenerate"]), backend=backend)
    data = tomllib.loads(C1.read_text(encoding="utf-8"))
    data.pop("solver")
    data["targets"]["free_timing"] = "inner"
    data["options"] = {"cycle_samples": 5760}
    fine = Evaluator(problem_from_dict(data, base_dir=C1.parent), backend=backend)
    X = crank_rockers(np.random.default_rng(5), 10)
    e = ev(X, detail=True)
    ef = free(X, detail=True)
    f_free = (ef.quantities["distances"] ** 2).sum(axis=1)
    assert np.all(e.violations["cyclic_order"] == 0)
    gaps = np.mod(np.diff(e.x[:, 9:], axis=1), TWO_PI).sum(axis=1)
    assert np.all(gaps <= TWO_PI + 1e-12)
    f = (e.quantities["distances"] ** 2).sum(axis=1)
    f_fine = (fine(X, detail=True).quantities["distances"] ** 2).sum(axis=1)
    in_order = np.mod(np.diff(ef.x[:, 9:], axis=1), TWO_PI).sum(axis=1) <= TWO_PI
    assert in_order.any() and (~in_order).any()
    for x, fi, ff, fv, ok in zip(X, f, f_free, f_fine, in_order):
        ref = dense_ordered(x, p.targets.xy)
        assert fi >= ff * (1 - 1e-9) - 1e-12
        if ok:
            assert fi == pytest.approx(ff, rel=1e-9)
        assert fi <= ref * 1.03 + 1e-9
        assert fv <= ref * (1 + 5e-4) + 1e-9


def test_compiled_and_numpy_routes_give_the_same_timing():
    p = c1_problem()
    X = crank_rockers(np.random.default_rng(2), 30)
    a = Evaluator(p, backend="numba")(X)
    b = Evaluator(p, backend="numpy")(X)
    assert np.allclose(a.x[:, :9], b.x[:, :9], rtol=0, atol=0)
    # the same angles to 1e-7 rad (a minimum on a toggle is approached by bisection: the last steps differ) and the
    # same objective to round-off
    assert np.abs(np.angle(np.exp(1j * (a.x[:, 9:] - b.x[:, 9:])))).max() < 1e-7
    assert np.allclose(a.penalised, b.penalised, rtol=1e-9, atol=1e-12)


# -- the formulation: the problem file, the search space, the result ---------------------------------------------
def test_free_timing_option_is_read_and_checked():
    h5 = ROOT / "examples" / "synthesis" / "benchmarks" / "hcdj5_ten_points_ellipse.toml"
    assert load_problem(h5).targets.free_timing == "inner"                # the default for point targets
    assert load_problem(C1).targets.free_timing == "explicit"             # the file asks for it
    assert c1_problem().targets.free_timing == "inner"
    with pytest.raises(SpecError) as exc:
        c1_problem(free_timing="outer")
    assert exc.value.problems[0] == ("targets.free_timing", "must be one of inner, explicit: 'outer'")
    data = tomllib.loads(C1.read_text(encoding="utf-8"))
    data["targets"] = {"point": "P", "xy": [[20, 20], [20, 25]], "inputs": [0, 1], "free_timing": "inner"}
    data["constraints"]["use"] = ["grashof"]
    for k in [f"theta2_{i}" for i in range(1, 7)]:
        del data["variables"][k]
    with pytest.raises(SpecError) as exc:
        problem_from_dict(data, base_dir=C1.parent)
    assert ("targets.free_timing", "applies to free timing only (timing = \"free\"), not 'prescribed'") in \
        exc.value.problems


def test_a_timing_variable_in_an_expression_keeps_the_explicit_formulation():
    data = tomllib.loads(C1.read_text(encoding="utf-8"))
    del data["targets"]["free_timing"]
    data["constraints"]["limits"] = [{"expression": "theta2_2 - theta2_1", "min": 0.1}]
    p = problem_from_dict(data, base_dir=C1.parent)
    assert p.targets.free_timing == "explicit"             # the default falls back where it cannot apply
    data["targets"]["free_timing"] = "inner"
    with pytest.raises(SpecError) as exc:
        problem_from_dict(data, base_dir=C1.parent)
    assert exc.value.problems[0][0] == "targets.free_timing" and "'theta2_1' enters an expression" in exc.value.problems[0][1]


def test_the_optimiser_searches_the_design_variables_only():
    p = c1_problem()
    space = SearchSpace(p)
    assert space.names == ("r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0", "theta0")
    assert SearchSpace(c1_problem(free_timing="explicit", placement="explicit")).n_vars == 15
    # with explicit timing, the placement (x0, y0, θ0) is solved per design by default (synthesis.placement)
    assert SearchSpace(c1_problem(free_timing="explicit")).n_vars == 12
    r = synthesize(p, "de", seed=1, budget=3000, popsize=5)
    assert len(r.x) == 15 and r.feasible
    # the result's angles are the design's own best timing
    e = Evaluator(p)(r.x[None, :])
    assert np.allclose(e.x[0], r.x) and e.objective[0] == pytest.approx(r.objective, rel=1e-12)


# -- pose targets (motion generation): the inner solve against a dense search over the crank angle ---------------
MOTION = ROOT / "examples" / "synthesis" / "motion_three_poses.toml"


def motion_problem(use=None, **targets):
    """The three-pose four-bar problem (examples/synthesis/motion_three_poses.toml), its timing solved per design."""
    data = tomllib.loads(MOTION.read_text(encoding="utf-8"))
    data["targets"].update(targets)
    data.pop("solver", None)
    if use is not None:
        data.setdefault("constraints", {})["use"] = use
    return problem_from_dict(data, base_dir=MOTION.parent, source=str(MOTION))


def coupler_pose(x, theta):
    """P (…, 2) and the coupler line A → B's angle ψ (…) of the template examples/crank_rocker.toml (open assembly:
    B on the "+" side of A → O4) for SI design vectors x = [x0, y0, r1, crank, coupler, rocker, px, py, …] at crank
    angles theta (measured from the ground line O2 → O4, along x); NaN where it cannot assemble."""
    x0, y0, r1, r2, r3, r4, px, py = x[:8]
    ax, ay = x0 + r2 * np.cos(theta), y0 + r2 * np.sin(theta)
    dx, dy = x0 + r1 - ax, y0 - ay
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore"):
        psi = np.arctan2(dy, dx) + np.arccos((r3 * r3 + d * d - r4 * r4) / (2 * r3 * d))
    P = np.stack([ax + px * np.cos(psi) - py * np.sin(psi), ay + px * np.sin(psi) + py * np.cos(psi)], axis=-1)
    return P, psi


def dense_nearest_pose(x, pose, w, n=20_000):
    """The least pose deviation |P − T| + w·|ψ − ψ_T| over the crank angle: a dense grid, then a bounded 1-D
    minimisation around the best."""
    def dev(t):
        P, psi = coupler_pose(x, np.asarray(t, dtype=float))
        v = np.linalg.norm(P - pose[:2], axis=-1) + w * np.abs(np.angle(np.exp(1j * (psi - pose[2]))))
        return np.where(np.isfinite(v), v, np.inf)
    grid = np.linspace(0, TWO_PI, n, endpoint=False)
    d = dev(grid)
    k = int(np.argmin(d))
    h = TWO_PI / n
    r = minimize_scalar(lambda t: float(dev(t)), bounds=(grid[k] - h, grid[k] + h), method="bounded",
                        options={"xatol": 1e-13})
    return min(float(r.fun), float(d[k]))


def motion_designs(rng, n):
    """n Grashof crank-rockers (crank shortest) in SI with a random coupler point and frame position, as the
    problem's design vectors (the three crank angles left 0: the evaluation solves them)."""
    out = []
    while len(out) < n:
        r1, r2, r3, r4 = rng.uniform([0.1, 0.02, 0.05, 0.05], [0.6, 0.4, 0.6, 0.6])
        s = np.sort([r1, r2, r3, r4])
        if not (r2 == s[0] and s[0] + s[3] < s[1] + s[2] - 0.01):
            continue
        out.append(np.concatenate([rng.uniform(-0.3, 0.3, 2), [r1, r2, r3, r4], rng.uniform(-0.3, 0.3, 2),
                                   np.zeros(3)]))
    return np.array(out)


def test_pose_targets_solve_their_free_timing_per_design_by_default():
    p = load_problem(MOTION)
    assert p.targets.kind == "poses" and p.targets.free_timing == "inner"
    assert SearchSpace(p).n_vars == 8                       # the three crank angles leave the search
    assert motion_problem(free_timing="explicit").targets.free_timing == "explicit"


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_inner_timing_of_poses_is_each_poses_least_deviation(backend):
    """Without an order constraint each pose gets the crank angle of its least deviation |Δp| + w·|Δψ|: the same
    value as a dense search over the crank angle on the closed-form four-bar (to 1e-9 of the size), and the angle
    reported gives it in the closed form."""
    p = motion_problem(use=["assembly"])
    ev = Evaluator(p, backend=backend)
    X = motion_designs(np.random.default_rng(4), 12)
    e = ev(X, detail=True)
    ls, w = p.length_scale, p.targets.angle_weight
    poses = np.column_stack([p.targets.xy, p.targets.angles])
    assert np.allclose(e.x[:, :8], X[:, :8])
    for x, th, dist in zip(X, e.x[:, 8:], e.quantities["distances"]):
        for i, pose in enumerate(poses):
            ref = dense_nearest_pose(x, pose, w)
            assert dist[i] / ls == pytest.approx(ref, rel=1e-9, abs=1e-12)
            P, psi = coupler_pose(x, th[i])
            mine = np.linalg.norm(P - pose[:2]) + w * abs(np.angle(np.exp(1j * (psi - pose[2]))))
            assert mine == pytest.approx(ref, rel=1e-9, abs=1e-12)


def test_compiled_and_numpy_pose_timing_agree():
    p = motion_problem()
    X = motion_designs(np.random.default_rng(8), 40)
    a = Evaluator(p, backend="numba")(X)
    b = Evaluator(p, backend="numpy")(X)
    both = a.feasible & b.feasible
    assert both.sum() > 10 and np.array_equal(a.feasible, b.feasible)
    # the golden section compares values: at a smooth minimum the deviation is flat, known to round-off (1e-16
    # relative), so the angle only to about its square root; at an exact pose (a corner) to round-off
    assert np.abs(np.angle(np.exp(1j * (a.x[both, 8:] - b.x[both, 8:])))).max() < 1e-6
    assert np.allclose(a.penalised, b.penalised, rtol=1e-9, atol=1e-15)


def test_pose_assignment_costs_on_the_samples():
    """The ordered assignment's pose cost (kernels.ordered, K = 3) against the same cost written here: each target's
    nearest sample, compiled and interpreted."""
    rng = np.random.default_rng(6)
    path = np.concatenate([rng.normal(size=(5, 40, 2)), rng.uniform(-10, 10, (5, 40, 1))], axis=-1)
    valid = rng.random((5, 40)) > 0.1
    poses = np.column_stack([rng.normal(size=(3, 2)), rng.uniform(-4, 4, 3)])
    w = 0.7
    d = (np.linalg.norm(path[:, None, :, :2] - poses[None, :, None, :2], axis=-1)
         + w * np.abs(np.angle(np.exp(1j * (path[:, None, :, 2] - poses[None, :, None, 2])))))
    ref = np.argmin(np.where(valid[:, None, :], d, np.inf), axis=-1)
    got = ordered._batch(path, valid, poses, 2, 0, w)[0]
    assert np.array_equal(got, ref)
    if ordered.compiled() is not None:
        assert np.array_equal(ordered.compiled()(path, valid, poses, 2, 0, w)[0], ref)


def test_an_unassembled_start_of_the_pose_refinement_is_left_as_it_is_on_both_routes():
    """A crank that cannot turn fully (crank 0.3 m, coupler 0.2, rocker 0.25, ground 0.4: not Grashof), θ0 just
    inside a stretch that does not assemble (the closed form above says where it ends), with the golden section's
    second point past that end: the compiled kernel leaves θ0 as it is, and the numpy route does the same instead of
    taking the assembled point."""
    from assur.engine.planar.numba_backend import available, pose_timing_refine
    from assur.synthesis.timing import refine_poses
    from assur.tolerances import DEFAULT
    p = motion_problem(use=["assembly"])
    x = np.array([0.0, 0.0, 0.4, 0.3, 0.2, 0.25, 0.05, 0.05, 0.0, 0.0, 0.0])
    params = Evaluator(p, backend="numpy").params(x[None])
    grid = np.linspace(0, TWO_PI, 3600, endpoint=False)
    ok = np.isfinite(coupler_pose(x, grid)[1])
    edge = grid[np.nonzero(ok & ~np.roll(ok, 1))[0][0]]           # the first assembled angle after a dead stretch
    h = TWO_PI / 120
    theta0 = np.array([[edge - 0.1 * h]])
    assert not np.isfinite(coupler_pose(x, theta0[0, 0])[1])                     # θ0 does not assemble …
    assert np.isfinite(coupler_pose(x, theta0[0, 0] + (2 * 0.6180339887498949 - 1) * h)[1])   # … the second point does
    poses = np.column_stack([p.targets.xy, p.targets.angles])[:1]
    body = p.plan.body_names.index("coupler")
    assert np.array_equal(refine_poses(p.plan, params, "P", "coupler", poses, p.targets.angle_weight, theta0, h,
                                       "numpy"), theta0)
    if available():
        assert np.array_equal(pose_timing_refine(p.plan, params, "P", body, theta0, h, poses, p.targets.angle_weight,
                                                 DEFAULT.radicand), theta0)
