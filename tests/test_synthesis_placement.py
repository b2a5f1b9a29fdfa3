"""The placement of a path design solved per design (assur.synthesis.placement): the closed form against a numerical
least-squares fit written here, the compiled kernel against numpy, the bounds, the detection and its refusals."""
import dataclasses
import tomllib
from pathlib import Path

import numpy as np
import pytest

from assur.errors import SpecError
from assur.synthesis import Evaluator, load_problem, problem_from_dict, synthesize
from assur.synthesis.placement import detect, points, reference
from assur.synthesis.space import SearchSpace

ROOT = Path(__file__).resolve().parent.parent
SYN = ROOT / "examples" / "synthesis"
C3 = SYN / "c3_eighteen_points_closed.toml"
BACKENDS = ["numpy", "numba"]


def c3(**targets):
    """C3's problem file (uniform timing, its placement solved by default), with ``[targets]`` keys replaced."""
    data = tomllib.loads(C3.read_text(encoding="utf-8"))
    data["targets"].update(targets)
    return problem_from_dict(data, base_dir=C3.parent, source=str(C3))


def feasible_designs(problem, n, seed=3):
    """n random designs of the box that assemble at every target (the placement explicit: as they stand)."""
    rng = np.random.default_rng(seed)
    lo, hi = problem.bounds.T
    X = lo + rng.random((4000, problem.n_vars)) * (hi - lo)
    ev = Evaluator(dataclasses.replace(problem, placement=None), backend="numpy")(X)
    X = X[ev.feasible]
    assert len(X) >= n
    return X[:n]


def least_squares_placement(q, t, s_bounds, x_bounds, y_bounds):
    """The best (s, φ, dx, dy) by scipy's bounded least squares from four starting angles: the residuals
    t_i − (s·R(φ)·q_i + d), written here without the closed form."""
    from scipy.optimize import least_squares

    def res(z):
        s, phi, dx, dy = z
        c, sn = np.cos(phi), np.sin(phi)
        return np.concatenate([t[:, 0] - (s * (c * q[:, 0] - sn * q[:, 1]) + dx),
                               t[:, 1] - (s * (sn * q[:, 0] + c * q[:, 1]) + dy)])
    lo = [s_bounds[0], -np.inf, x_bounds[0], y_bounds[0]]
    hi = [s_bounds[1], np.inf, x_bounds[1], y_bounds[1]]
    best = None
    for phi in (0.0, 1.6, 3.1, 4.7):
        z0 = np.clip([min(max(1.0, s_bounds[0]), s_bounds[1]), phi, 0.0, 0.0], np.array(lo) + 1e-12,
                     np.array(hi) - 1e-12)
        r = least_squares(res, z0, bounds=(lo, hi), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if best is None or r.cost < best.cost:
            best = r
    return 2.0 * best.cost


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_closed_form_placement_is_the_bounded_least_squares_optimum(backend):
    """On 12 assembled C3 designs: the objective of the placed design equals the bounded least-squares optimum over
    (s, φ, dx, dy) found numerically (the size factor kept in the interval where every length stays in [0, 50])."""
    p = c3()
    X = feasible_designs(p, 12)
    ev = Evaluator(p, backend=backend)(X)
    assert ev.feasible.all()
    R = reference(p.placement, X)
    q, ok = points(p, R, "numpy")
    assert ok.all()
    for k in range(len(X)):
        lengths = X[k, list(p.placement.scale)]
        lo, hi = p.bounds[list(p.placement.scale)].T
        s_hi = np.min(np.where(lengths > 0, hi / lengths, lo / lengths))
        s_lo = np.max(np.where(lengths > 0, lo / lengths, hi / lengths))
        f_num = least_squares_placement(q[k], p.targets.xy, (s_lo, s_hi), p.bounds[6], p.bounds[7])
        assert ev.objective[k] == pytest.approx(f_num, rel=1e-8)
        assert ev.objective[k] <= f_num * (1 + 1e-9)


def test_compiled_and_numpy_placements_agree():
    p = c3()
    rng = np.random.default_rng(7)
    lo, hi = p.bounds.T
    X = lo + rng.random((3000, p.n_vars)) * (hi - lo)
    a, b = Evaluator(p, backend="numpy")(X), Evaluator(p, backend="numba")(X)
    assert np.array_equal(a.feasible, b.feasible) and a.feasible.sum() > 100
    ok = a.feasible
    assert np.allclose(a.objective[ok], b.objective[ok], rtol=1e-10, atol=0)
    assert np.allclose(a.x[ok], b.x[ok], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_placed_design_is_evaluated_where_it_stands_and_is_no_worse(backend):
    """The evaluation returns the placed design (``x``): evaluated as given (the placement explicit) it has the same
    objective, which is no larger than that of the design as it was proposed."""
    p = c3()
    given = dataclasses.replace(p, placement=None)
    X = feasible_designs(p, 40)
    ev = Evaluator(p, backend=backend)(X)
    again = Evaluator(given, backend=backend)(ev.x)
    before = Evaluator(given, backend=backend)(X)
    assert again.feasible.all() and ev.feasible.all()
    assert np.allclose(again.objective, ev.objective, rtol=1e-12, atol=0)
    assert np.all(ev.objective <= before.objective * (1 + 1e-12))
    searched = [i for i in range(p.n_vars) if i not in p.placement.solved]
    ratio = ev.x[:, list(p.placement.scale)] / X[:, list(p.placement.scale)]
    assert np.allclose(ratio, ratio[:, :1], rtol=1e-12)      # one size factor per design: the shape is kept
    assert np.allclose(ev.x[:, searched[-1]], X[:, searched[-1]])    # the timing start is not touched


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_size_stays_in_its_bounds_at_its_bounded_optimum(backend):
    """Targets 400 times larger about their centroid: the best size is outside the box, so each placed design has
    its largest length on the bound 50 and passes no bound; where its position is inside the box, its objective is
    the bounded optimum over the size factor with the best position for each size (a 1-D search written here, at
    the design's angle)."""
    from scipy.optimize import minimize_scalar
    base = c3()
    xy0 = np.array(tomllib.loads(C3.read_text(encoding="utf-8"))["targets"]["xy"])
    p = c3(xy=(xy0.mean(axis=0) + 400 * (xy0 - xy0.mean(axis=0))).tolist())
    X = feasible_designs(base, 30)
    ev = Evaluator(p, backend=backend)(X)
    assert ev.feasible.all() and ev.violations["bounds"].max() == 0.0
    scale = list(p.placement.scale)
    assert np.allclose(np.abs(ev.x[:, scale]).max(axis=1), 50.0, rtol=1e-15)
    q, _ = points(p, reference(p.placement, X), "numpy")
    t = p.targets.xy
    inside = np.flatnonzero(np.all(np.abs(ev.x[:, 6:8]) < 50.0, axis=1))     # the position free (not clipped)
    assert len(inside) >= 3
    for k in inside:
        c, sn = np.cos(ev.x[k, 8]), np.sin(ev.x[k, 8])

        def f(s):
            px, py = s * (c * q[k, :, 0] - sn * q[k, :, 1]), s * (sn * q[k, :, 0] + c * q[k, :, 1])
            dx, dy = np.mean(t[:, 0] - px), np.mean(t[:, 1] - py)
            return float(np.sum((t[:, 0] - px - dx) ** 2 + (t[:, 1] - py - dy) ** 2))
        s_hi = 50.0 / np.abs(X[k, scale]).max()
        best = minimize_scalar(f, bounds=(0.0, s_hi), method="bounded", options={"xatol": 1e-12})
        assert ev.objective[k] == pytest.approx(f(s_hi), rel=1e-10)      # the optimum is on the bound
        assert f(s_hi) <= best.fun


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_position_outside_the_box_is_clipped_to_its_bound(backend):
    """Targets moved 4000 to the right: x0 is placed on its bound 50, no bound is passed, and the design is no worse
    than as it was proposed (where a translation bound is active the joint optimum may differ: docs/synthesis.md)."""
    xy0 = np.array(tomllib.loads(C3.read_text(encoding="utf-8"))["targets"]["xy"])
    p = c3(xy=(xy0 + [4000.0, 0.0]).tolist())
    X = feasible_designs(c3(), 10)
    ev = Evaluator(p, backend=backend)(X)
    before = Evaluator(dataclasses.replace(p, placement=None), backend=backend)(X)
    assert ev.feasible.all() and ev.violations["bounds"].max() == 0.0
    assert np.all(ev.x[:, 6] == 50.0)
    assert np.all(ev.objective <= before.objective)
    # the command's warning names the placed variable on its bound
    r = synthesize(p, seed=0, budget=2000)
    assert "x0" in [b["variable"] for b in r.on_bounds] and "x0 = 50" in r.bound_warning()


def test_the_optimiser_searches_the_shape_and_returns_the_whole_design():
    p = c3()
    assert SearchSpace(p).names == ("r1", "r2", "r3", "r4", "rcx", "rcy", "theta2_1")
    assert SearchSpace(c3(placement="explicit")).n_vars == 10
    r = synthesize(p, seed=0, budget=6000)
    assert r.feasible and len(r.x) == 10
    e = Evaluator(dataclasses.replace(p, placement=None))(r.x[None, :])
    assert e.objective[0] == pytest.approx(r.objective, rel=1e-12)


def test_the_placement_variables_are_found_on_the_problem():
    p = load_problem(C3)
    names = p.names
    assert [names[i] for i in p.placement.solved] == ["x0", "y0", "theta0"]
    assert [names[i] for i in p.placement.scale] == ["r1", "r2", "r3", "r4", "rcx", "rcy"]
    # C2's frame is given: no variable moves the mechanism
    c2 = load_problem(SYN / "c2_five_points_timed.toml")
    assert c2.placement is None
    assert "translates" in detect(c2)[1]
    # free timing solved per design depends on the placement: H5 keeps its variables
    h5 = load_problem(SYN / "benchmarks" / "hcdj5_ten_points_ellipse.toml")
    assert h5.placement is None and "free timing" in detect(h5)[1]
    # a sum of distances has no closed-form placement
    assert c3(placement="explicit").placement is None
    data = tomllib.loads(C3.read_text(encoding="utf-8"))
    data["objective"]["deviation"] = "distance"
    assert problem_from_dict(data, base_dir=C3.parent).placement is None


def test_a_placement_that_cannot_be_solved_is_refused_where_the_file_asks_for_it():
    data = tomllib.loads(C3.read_text(encoding="utf-8"))
    data["objective"]["deviation"] = "distance"
    data["targets"]["placement"] = "inner"
    with pytest.raises(SpecError) as e:
        problem_from_dict(data, base_dir=C3.parent, source="c3.toml")
    assert e.value.problems[0][0] == "targets.placement" and "squared" in e.value.problems[0][1]
    c2 = tomllib.loads((SYN / "c2_five_points_timed.toml").read_text(encoding="utf-8"))
    c2["targets"]["placement"] = "inner"
    with pytest.raises(SpecError, match="translates the mechanism"):
        problem_from_dict(c2, base_dir=SYN)
    with pytest.raises(SpecError) as e:
        c3(placement="solved")
    assert e.value.problems == [("targets.placement", "must be one of inner, explicit: 'solved'")]


def test_four_bar_constraint_lengths_that_do_not_follow_the_size_keep_the_placement_searched():
    """A four-bar constraint read on a length plus a constant (not scaled with the mechanism) would change
    feasibility under a placement: the placement is not solved."""
    data = tomllib.loads(C3.read_text(encoding="utf-8"))
    data["constraints"]["fourbar"]["ground"] = "r1 + 5"
    p = problem_from_dict(data, base_dir=C3.parent)
    assert p.placement is None
    assert "do not scale" in detect(p)[1]


def test_the_command_says_what_each_evaluation_solves(capsys):
    import json

    from assur.cli.main import main
    assert main(["synth", str(C3), "--seed", "0", "--budget", "300"]) == 0
    out = capsys.readouterr().out
    assert "solved per design: x0, y0, theta0 (placement); the size through r1, r2, r3, r4, rcx, rcy" in out
    assert main(["synth", str(C3), "--seed", "0", "--budget", "300", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["solved_per_design"] == {"placement": ["x0", "y0", "theta0"],
                                      "size": ["r1", "r2", "r3", "r4", "rcx", "rcy"]}
    h5 = SYN / "benchmarks" / "hcdj5_ten_points_ellipse.toml"
    assert main(["synth", str(h5), "--seed", "0", "--budget", "300"]) == 0
    assert "theta2_10 (free timing)" in capsys.readouterr().out


@pytest.mark.parametrize("backend", BACKENDS)
def test_without_the_turn_a_mirrored_fit_keeps_its_size_and_the_run_ends_well(backend):
    """C3 with the crank's zero not tied to θ0: θ0 no longer turns the mechanism, so only the position and the size
    are solved (θ0 is searched). A shape that fits best mirrored (D ≤ 0) would be shrunk to a point by the
    unturned fit: it keeps its size instead, every placed design has positive lengths, and a default run ends on a
    feasible design without an error."""
    data = tomllib.loads(C3.read_text(encoding="utf-8"))
    del data["parameters"]["crank.zero"]
    p = problem_from_dict(data, base_dir=C3.parent)
    assert [p.names[i] for i in p.placement.solved] == ["x0", "y0"] and p.placement.angle is None
    rng = np.random.default_rng(0)
    lo, hi = p.bounds.T
    X = lo + rng.random((3000, p.n_vars)) * (hi - lo)
    ev = Evaluator(p, backend=backend)(X)
    assert np.all(np.isfinite(ev.penalised))
    assert np.all(ev.x[:, :4].max(axis=1) > 0)
    given = Evaluator(dataclasses.replace(p, placement=None), backend=backend)
    before, again = given(X), given(ev.x)
    ok = ev.feasible & before.feasible
    assert ok.sum() > 100 and np.all(ev.objective[ok] <= before.objective[ok] * (1 + 1e-12))
    assert np.allclose(again.objective[ev.feasible], ev.objective[ev.feasible], rtol=1e-12, atol=0)
    r = synthesize(p, seed=0, budget=20000, backend=backend)
    assert r.feasible and np.isfinite(r.objective)
