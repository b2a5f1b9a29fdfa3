"""Synthesis: problem files, the vectorised evaluator, optimisers, executors, the CLI (issue: dimensional synthesis)."""
import json
from pathlib import Path

import numpy as np
import pytest

import assur
from conftest import InterruptingExecutor
from assur.cli.main import main
from assur.errors import SpecError, SynthesisError
from assur.synthesis import (DaskCluster, Evaluator, InProcess, LocalProcesses, load_problem, problem_from_dict,
                             synthesize)
from assur.synthesis.design import mechanism_with_params

ROOT = Path(__file__).resolve().parents[1]
SYN = ROOT / "examples" / "synthesis"
P000 = SYN / "paper000_six_points.toml"
C2 = SYN / "c2_five_points_timed.toml"


def foot_eq4(l1, l2, l5, phi):
    """Paper 000 eq. (4) (docs/papers/000.md §3): the foot A in the paper's frame (mm). C = (l5 sin φ, l5 cos φ),
    B on the vertical through K with |CB| = l2, A on the rod's extension beyond B with |BA| = l1."""
    xc, yc = l5 * np.sin(phi), l5 * np.cos(phi)
    yb = yc + np.sqrt(l2**2 - xc**2)
    t = l1 / l2
    return np.stack([-t * xc, yb + t * (yb - yc)], axis=-1)


def delta1_independent(l1, l2, l5):
    """Eq. (5): Σ of the Euclidean distances to the six targets of docs/papers/000.md §4."""
    phi = np.radians([90, 135, 180, 225, 270, 360])
    xy = np.array([[-150, 130], [-75, 130], [0, 130], [75, 130], [150, 130], [0, 530]])
    return np.linalg.norm(foot_eq4(l1, l2, l5, phi) - xy, axis=-1).sum()


# -- paper 000 -------------------------------------------------------------------------------------
def test_paper000_objective_of_the_printed_design():
    """Δ1(165, 193, 175) through the problem file equals eq. (4)–(5) computed independently here."""
    p = load_problem(P000)
    e = Evaluator(p)(p.to_si([[165, 193, 175]]))
    assert e.feasible[0]
    assert e.objective[0] == pytest.approx(delta1_independent(165.0, 193.0, 175.0), rel=1e-12)
    # the 6th distance is |l1 + l2 + l5 − 530| (docs/papers/000.md §4)
    d = Evaluator(p)(p.to_si([[165, 193, 175]]), detail=True).quantities["distances"][0]
    assert d[5] == pytest.approx(abs(165 + 193 + 175 - 530), abs=1e-9)


@pytest.mark.slow
def test_paper000_synthesis_beats_the_printed_design():
    """docs/papers/000.md §4/E2: the printed 165/193/175 is not a minimum; DE + Nelder–Mead finds a lower Δ1."""
    p = load_problem(P000)
    printed = delta1_independent(165.0, 193.0, 175.0)
    r = synthesize(p, seed=3, budget=20000)
    assert r.feasible
    l1, l2, l5 = r.x_file
    assert r.objective == pytest.approx(delta1_independent(l1, l2, l5), rel=1e-12)   # re-checked independently
    assert r.objective < printed - 50            # 99.85 mm against 172.47 mm (docs/reproduction.md)
    assert l2 > l5                                # the l2 > l5 limit of the problem file


# -- evaluator --------------------------------------------------------------------------------------
def test_infeasible_designs_are_penalised_not_crashing():
    """A random population, most of it unassemblable: finite F, NaN objectives, Deb order preserved."""
    p = load_problem(P000)
    rng = np.random.default_rng(0)
    X = p.to_si(rng.uniform(1, 1000, (500, 3)))
    e = Evaluator(p)(X)
    assert np.all(np.isfinite(e.penalised))
    assert (~e.feasible).sum() > 100 and e.feasible.sum() > 10
    assert np.all(np.isnan(e.objective[~e.feasible]))
    assert e.penalised[~e.feasible].min() > e.penalised[e.feasible].max()      # feasible beats infeasible
    worse = np.argsort(e.violation[~e.feasible])
    assert np.all(np.diff(e.penalised[~e.feasible][worse]) >= 0)               # smaller V wins


def test_evaluation_is_chunk_independent():
    """Chunking keeps memory bounded and never changes a number."""
    p = load_problem(P000)
    X = p.to_si(np.random.default_rng(1).uniform(50, 400, (300, 3)))
    a = Evaluator(p, chunk=7)(X)
    b = Evaluator(p, chunk=1000)(X)
    assert np.array_equal(a.penalised, b.penalised)


def test_gait_terms_agree_with_the_exact_gait_metrics():
    """The sampled gait quantities of the population agree with analysis.gait's exact metrics."""
    p = load_problem(SYN / "walker_fourbar_gait.toml")
    ev = Evaluator(p)
    x = np.array([v for v in p.plan.defaults[[p.plan.param_index(n) for n in p.names]]])
    e = ev(x[None, :])
    g = assur.gait_metrics(p.plan)
    q = e.quantities
    assert q["gait.step"][0] == pytest.approx(g.step_length, rel=2e-3)
    assert q["gait.lift"][0] == pytest.approx(g.lift, rel=2e-3)
    assert q["gait.sag"][0] == pytest.approx(g.sag, rel=2e-2)
    assert q["gait.duty"][0] == pytest.approx(g.duty_factor, abs=2 / p.cycle_samples)
    spread = (g.support_speed.max - g.support_speed.min) / g.support_speed.mean
    assert q["gait.speed_spread"][0] == pytest.approx(spread, rel=3e-2)


def test_mechanism_with_params_round_trips():
    """The best-design file compiles back to the same parameters and the same assembly."""
    plan = assur.compile(assur.load(ROOT / "examples" / "walker_fourbar.toml"))
    p = plan.defaults.copy()
    p[plan.param_index("crank.length")] *= 0.9
    p[plan.param_index("O1.x")] += 0.02
    m = mechanism_with_params(plan, p)
    again = assur.compile(assur.loads(assur.dumps(m)))
    assert list(again.param_names) == list(plan.param_names)
    assert np.allclose(again.defaults, p, rtol=0, atol=1e-12)
    q = np.linspace(0, 2 * np.pi, 36)
    assert np.allclose(assur.solve(again, inputs=q).pos, assur.solve(plan, p, q).pos, atol=1e-12)


# -- optimisers, seeds, stopping ---------------------------------------------------------------------
@pytest.mark.slow
def test_seed_reproducibility():
    p = load_problem(C2)
    a = synthesize(p, seed=11, budget=3000, polish="none")
    b = synthesize(p, seed=11, budget=3000, polish="none")
    c = synthesize(p, seed=12, budget=3000, polish="none")
    assert np.array_equal(a.x, b.x) and a.evaluations == b.evaluations
    assert [(e, F) for e, _, F in a.history] == [(e, F) for e, _, F in b.history]   # wall times differ, nothing else
    assert not np.array_equal(a.x, c.x)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["de", "cmaes", "local"])
def test_every_method_returns_a_checked_design(method):
    p = load_problem(P000)
    r = synthesize(p, method=method, seed=5, budget=4000, x0=[165, 193, 175] if method == "local" else None)
    assert r.feasible and r.evaluations <= 4000 + 200
    assert r.objective == pytest.approx(delta1_independent(*r.x_file), rel=1e-12)
    if method == "local":
        assert r.objective < delta1_independent(165.0, 193.0, 175.0)


def test_time_limit_returns_the_best_so_far():
    """A run cut by its time limit returns the best design so far and says it stopped for the time (how long
    such a run really takes is measured by benchmarks/time_limit.py)."""
    p = load_problem(C2)
    synthesize(p, seed=1, budget=200, polish="none")          # load the compiled kernels outside the limited run
    # no other stop can come first: no convergence test (tol 0, endless patience), an endless generation cap,
    # many starts, no polish
    r = synthesize(p, seed=1, time_limit=1.0, maxiter=10 ** 9, tol=0.0, patience=10 ** 9, starts=50, polish="none")
    assert r.stopped == "time"
    assert r.x.shape == (6,) and r.evaluations > 0




def test_interruption_keeps_the_best_design():
    p = load_problem(C2)
    ex = InterruptingExecutor(after=20)
    r = synthesize(p, seed=4, budget=10**6, executor=ex, starts=3)
    assert r.stopped == "interrupted"
    assert len(r.starts) == 1                              # the later starts never ran
    assert r.evaluations == sum(len(F) for F in ex.seen)
    best_seen = min(F.min() for F in ex.seen)              # the best of everything evaluated before Ctrl-C
    assert Evaluator(p)(r.x[None, :]).penalised[0] == pytest.approx(best_seen, rel=1e-12)
    assert r.feasible == (best_seen < p.infeasible_offset)


def test_bad_settings_are_synthesis_errors():
    p = load_problem(C2)
    with pytest.raises(SynthesisError, match="method"):
        synthesize(p, method="pso")
    with pytest.raises(SynthesisError, match="budget"):
        synthesize(p, budget=0)


# -- executors ---------------------------------------------------------------------------------------
def _short_run(problem, executor, starts=1):
    return synthesize(problem, seed=21, budget=2400, popsize=10, polish="nelder-mead", executor=executor,
                      starts=starts)


@pytest.mark.slow
def test_executors_give_identical_results():
    """In-process, two local worker processes and a real Dask LocalCluster: the same design and history."""
    from distributed import Client, LocalCluster
    p = load_problem(C2)
    ref = _short_run(p, InProcess())
    with LocalProcesses(2) as ex:
        local = _short_run(p, ex)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        dask_ex = DaskCluster(client=client)
        on_dask = _short_run(p, dask_ex)
        starts_dask = _short_run(p, dask_ex, starts=2)         # whole starts as Dask tasks
    starts_here = _short_run(p, InProcess(), starts=2)
    for r in (local, on_dask):
        assert np.array_equal(r.x, ref.x) and r.objective == ref.objective and r.evaluations == ref.evaluations
        assert [h[0] for h in r.history] == [h[0] for h in ref.history]
        assert [h[2] for h in r.history] == [h[2] for h in ref.history]
    assert on_dask.executor == "dask" and local.executor == "local processes"
    assert np.array_equal(starts_dask.x, starts_here.x) and starts_dask.objective == starts_here.objective


# -- problem files ---------------------------------------------------------------------------------
def _doc(**changes):
    import tomllib
    data = tomllib.loads(P000.read_text(encoding="utf-8"))
    for k, v in changes.items():
        data[k] = v
    return data


def test_problem_errors_are_located():
    data = _doc(variables={"rod.length": [300, 100], "nosuch": [0, 1]},
                parameters={"crank.length": "rod.length * sinh(2)", "bogus.param": "1"})
    with pytest.raises(SpecError) as exc:
        problem_from_dict(data, base_dir=SYN, source="p.toml")
    text = str(exc.value)
    assert "variables.rod.length: low bound must be below the high bound: [300, 100]" in text
    assert "parameters.crank.length: unknown function 'sinh'" in text
    assert "parameters.bogus.param: not a parameter of the mechanism" in text
    assert "variables.nosuch: is used by no parameter, timing or expression" in text


def test_problem_needs_a_mechanism_and_known_points():
    with pytest.raises(SpecError, match="mechanism .*no such file"):
        problem_from_dict(_doc(mechanism="missing.toml"), base_dir=SYN)
    t = _doc()["targets"]
    t["point"] = "Q"
    with pytest.raises(SpecError, match="targets.point: unknown point 'Q'"):
        problem_from_dict(_doc(targets=t), base_dir=SYN)
    t = _doc()["targets"]
    t["inputs"] = [90, 180]
    with pytest.raises(SpecError, match=r"targets.inputs: must list one input value per target \(6\)"):
        problem_from_dict(_doc(targets=t), base_dir=SYN)


def test_fourbar_constraints_need_the_fourbar_lengths():
    with pytest.raises(SpecError, match="'grashof' needs constraints.fourbar"):
        problem_from_dict(_doc(constraints={"use": ["grashof"]}), base_dir=SYN)


# -- CLI ---------------------------------------------------------------------------------------------
def test_cli_synth_writes_a_working_best_design(tmp_path, capsys):
    out = tmp_path / "best.toml"
    assert main(["synth", str(P000), "--seed", "2", "--budget", "6000", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "objective: " in text and "evaluations: " in text and "wall time" in text and "gait (exact)" in text
    reached = float(text.split("objective: ")[1].split()[0])
    m = assur.load(out)
    plan = assur.compile(m)
    l1 = plan.defaults[plan.param_index("rod.A.distance")] * 1000
    l2 = plan.defaults[plan.param_index("rod.length")] * 1000
    l5 = plan.defaults[plan.param_index("crank.length")] * 1000
    assert delta1_independent(l1, l2, l5) == pytest.approx(reached, rel=1e-8)


def test_cli_synth_json(capsys):
    assert main(["synth", str(C2), "--seed", "1", "--budget", "2000", "--json", "--polish", "none"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["feasible"] and d["evaluations"] <= 2100 and set(d["variables"]) == {"r1", "r2", "r3", "r4", "rcx", "rcy"}
    assert d["objective"] == pytest.approx(sum(x * x for x in d["details"]["quantities"]["distances"]), rel=1e-9)


def test_cli_synth_bad_input(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "assur-synth/1"\nmechanism = "nowhere.toml"\n', encoding="utf-8")
    assert main(["synth", str(bad)]) == 1
    assert capsys.readouterr().err.startswith("error: ")
    # an output in a missing directory fails before the run, and nothing is written
    assert main(["synth", str(P000), "-o", str(tmp_path / "no" / "best.toml")]) == 1
    assert "does not exist" in capsys.readouterr().err
    assert not (tmp_path / "no").exists()
    assert main(["synth", str(P000), "--workers", "2", "--dask", "tcp://x:1"]) == 2


@pytest.mark.parametrize("address, says", [
    ("", "dask: the address of the Dask scheduler is empty"),
    ("0", "dask: not the address of a Dask scheduler (tcp://host:port): '0'"),
    ("tcp://", "dask: not the address of a Dask scheduler"),
    ("tcp://127.0.0.1:1", "no Dask scheduler answers at tcp://127.0.0.1:1"),
])
def test_cli_synth_bad_dask_address_is_one_error_line(address, says, tmp_path, capsys, monkeypatch):
    """A malformed address was a traceback, an empty one ran in-process, and an unreachable scheduler said
    'cannot write'; now each is one error line and nothing is written."""
    pytest.importorskip("distributed")
    from assur.synthesis import executors
    monkeypatch.setattr(executors, "CONNECT_TIMEOUT", "1s")
    out = tmp_path / "best"
    assert main(["synth", str(P000), "--budget", "20", "--dask", address, "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: ") and says in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_progress_bar_reports_evaluations(capsys):
    """A long run shows a tqdm bar on stderr with the evaluations and the best so far."""
    synthesize(load_problem(C2), seed=1, budget=1500, polish="none", progress=True)
    err = capsys.readouterr().err
    assert "eval" in err and "best" in err and "1500" in err


def test_buildability_penalty_is_smooth():
    """Past the full-rotation limit the 'buildable' violation grows continuously from 0 (it is the
    groups' mean shortfall past their toggles), so an optimiser is led back, not left on a plateau."""
    p = load_problem(P000)                    # buildable: the crank–slider must turn fully (l5 < l2)
    l5 = np.linspace(180, 200, 401)           # rod l2 = 193 mm: the crank turns fully only for l5 ≤ 193
    X = p.to_si(np.column_stack([np.full_like(l5, 165), np.full_like(l5, 193), l5]))
    V = Evaluator(p)(X).violations["buildable"]
    assert np.all(V[l5 <= 193 - 1e-9] == 0) and np.all(V[l5 > 193 + 1e-9] > 0)
    assert np.all(np.diff(V[l5 >= 193]) >= -1e-12)                    # grows with the overshoot
    assert np.max(np.abs(np.diff(V))) < 5 * np.median(np.abs(np.diff(V[l5 > 193])))   # no jump


def test_expressions_are_checked_once_and_pickle():
    """The shared expression evaluator: dotted parameter names, functions with their argument counts, a
    located error for anything else, and pickling for worker processes (re-parsed on the other side)."""
    import pickle
    from assur.errors import ExpressionError
    from assur.io.expressions import Expression
    e = Expression("hypot(crank.length, x) + 2*pi", {"crank.length", "x"})
    assert e.names == {"crank.length", "x"}
    env = {"crank.length": np.array([3.0, 5.0]), "x": np.array([4.0, 12.0])}
    np.testing.assert_array_equal(e(env), np.hypot(env["crank.length"], env["x"]) + 2 * np.pi)
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(e))(env), e(env))
    for bad, why in (("atan2(x)", "takes 2 arguments"), ("y + 1", "unknown name 'y'"), ("x < 1", "not allowed"),
                     ("", "non-empty")):
        with pytest.raises(ExpressionError, match=why):
            Expression(bad, {"x"})


def test_the_former_expressions_module_warns_and_serves_the_same_names():
    """assur.synthesis.expressions is a shim for one release: importing it warns with a DeprecationWarning naming
    assur.io.expressions and serves the very same objects; no module of the package imports it."""
    import importlib
    import sys
    import assur.io.expressions as current
    sys.modules.pop("assur.synthesis.expressions", None)
    with pytest.warns(DeprecationWarning, match=r"assur\.synthesis\.expressions is deprecated: import from "
                                                r"assur\.io\.expressions"):
        old = importlib.import_module("assur.synthesis.expressions")
    for name in ("CONSTANTS", "Expression", "ExpressionError", "FUNCTIONS"):
        assert getattr(old, name) is getattr(current, name)
    src = Path(assur.__file__).parent
    shim_uses = ("synthesis.expressions", "synthesis import expressions")
    users = [str(p.relative_to(src)) for p in src.rglob("*.py") if p.name != "expressions.py"
             and (any(use in (text := p.read_text(encoding="utf-8")) for use in shim_uses)
                  or "from .expressions" in text and p.parent.name == "synthesis")]
    assert not users, users


def test_cli_synth_writes_no_file_that_would_not_load(tmp_path, capsys):
    """No design in the box assembles (a crank 20–30 times the other links): the run ends without a feasible design
    (exit 3) and, since the best design's mechanism file would not load, writes none and says so."""
    text = C2.read_text(encoding="utf-8")
    text = text.replace('mechanism = "fourbar_benchmark.toml"',
                        f'mechanism = {json.dumps(str(SYN / "fourbar_benchmark.toml"))}')
    for name, bounds in (("r1", "[1, 2]"), ("r2", "[40, 50]"), ("r3", "[1, 2]"), ("r4", "[1, 2]")):
        text = text.replace(f"{name} = [0, 50]", f"{name} = {bounds}")
    problem_file = tmp_path / "never.toml"
    problem_file.write_text(text, encoding="utf-8")
    out = tmp_path / "best.toml"
    assert main(["synth", str(problem_file), "--seed", "1", "--budget", "300", "--polish", "none",
                 "-o", str(out)]) == 3
    printed = capsys.readouterr().out
    assert "no feasible design found" in printed and f"not written: {out}" in printed
    assert not out.exists() and list(tmp_path.iterdir()) == [problem_file]
