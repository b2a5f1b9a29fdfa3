"""Walking legs ranked by their gait (assur.synthesis.legs, assur.report.legs, ``assur atlas --walking-legs``).

The candidates are checked against an independent enumeration written here with networkx (every frame, crank and
foot link of every six-link chain, equivalence by the chain's automorphisms found by networkx's isomorphism
search); the ranked designs' metrics against assur.gait_metrics recomputed from the written mechanism files; the
executors against each other (in-process, two local processes, a real Dask LocalCluster).
"""
from __future__ import annotations

import json
import math
import re
import tomllib

import networkx as nx
import numpy as np
import pytest

import assur
from assur.cli.main import main
from assur.structure.atlas.chains import chains
from assur.synthesis.executors import DaskCluster, LocalProcesses
from assur.synthesis.legs import CRANK, DEFAULTS, FOOT, leg_candidates, leg_problem, rank_legs, run_candidate

SMALL = {"budget": 600, "starts": 2, "backend": "numpy"}


@pytest.fixture(scope="module")
def six():
    return leg_candidates(6)


def _automorphisms(n, edges):
    g = nx.Graph()
    g.add_nodes_from(range(n))
    g.add_edges_from(edges)
    return list(nx.algorithms.isomorphism.GraphMatcher(g, g).isomorphisms_iter())


def test_one_candidate_by_its_key_is_the_one_in_the_list(six):
    """leg_candidates(links, key) makes only that candidate: the same key, name, links, template document and solver
    kind as the full enumeration's; an unknown key gives none."""
    for c in six[::5]:
        one, = leg_candidates(6, c.key)
        assert (one.key, one.name, one.crank, one.foot_link, one.newton) == (c.key, c.name, c.crank, c.foot_link,
                                                                             c.newton)
        assert one.document == c.document
    assert leg_candidates(6, "K6-none/f0/c1/foot2") == []


def test_six_link_candidates_are_every_frame_crank_and_foot_once(six):
    """Independent: for each six-link chain (Watt, Stephenson), every (frame, crank hinged to it, foot on another
    moving link) triple, grouped into classes by the chain's automorphisms (networkx). Each class is one candidate,
    and each candidate is one class."""
    expected = set()
    for chain in chains(6, 1):
        g = chain.graph
        autos = _automorphisms(g.n, g.edges)
        adj = {v: {u for e in g.edges for u in e if v in e and u != v} for v in range(g.n)}
        for frame, crank in ((f, c) for f in range(g.n) for c in sorted(adj[f])):
            for foot in range(g.n):
                if foot in (frame, crank):
                    continue
                orbit = frozenset((a[frame], a[crank], a[foot]) for a in autos)
                expected.add((chain.id, orbit))
    got = {}
    for c in six:
        chain_id, frame = c.inversion.split("/")
        triple = (int(frame[1:]), c.crank, c.foot_link)
        key = next(k for k in expected if k[0] == chain_id and triple in k[1])
        assert key not in got, f"{c.key} and {got.get(key)} are the same leg"
        got[key] = c.key
    assert len(got) == len(expected) == len(six)


def test_a_candidate_is_its_atlas_mechanism_with_a_foot(six):
    from assur.io.mechanism_file import from_dict
    from assur.synthesis import Evaluator
    c = six[0]
    doc = c.document
    m = from_dict(doc, c.key)
    assert m.gait.foot == FOOT and doc["links"][c.foot_name][-1] == FOOT
    assert doc["gait"] == {"foot": FOOT, "ground": [1, 0], "up": [0, 1]}
    p = leg_problem(c)
    names = set(p.names)
    pivot = doc["drivers"][0]["pivot"]
    # the crank's length and pivot are fixed: lengths are in crank lengths, the leg may sit anywhere
    assert f"{c.crank_name}.length" not in names and not any(n.startswith(f"{pivot}.") for n in names)
    assert {f"{c.foot_name}.{FOOT}.distance", f"{c.foot_name}.{FOOT}.angle"} <= names
    x = np.mean(p.bounds, axis=1)
    crank = Evaluator(p).params(x[None])[0][p.plan.param_index(f"{c.crank_name}.length")]
    assert crank == pytest.approx(CRANK / 1000)        # mm → m


def test_bad_settings_are_named(six):
    with pytest.raises(assur.SpecError, match="budget"):
        run_candidate(six[0], {"budget": 0})
    with pytest.raises(assur.SpecError, match="unknown walking-leg setting"):
        rank_legs(6, settings={"bugdet": 10}, candidates=[])
    with pytest.raises(assur.SpecError, match="6 or 8"):
        leg_candidates(5)


def _recomputed(entry):
    """The exact gait of an entry's written mechanism file, recomputed here (mm)."""
    plan = assur.compile(assur.loads(entry["mechanism"]))
    g = assur.gait_metrics(plan)
    return {"step": g.step_length * 1000, "lift": g.lift * 1000, "sag": g.sag * 1000,
            "vx_spread_80": g.vx_spread["0.8"], "vx_spread_90": g.vx_spread["0.9"]}


def test_one_candidate_is_dimensioned_and_its_file_walks(six):
    c = next(c for c in six if c.inversion_name == "Watt I" and c.foot_name == "L3")
    r = run_candidate(c, {"budget": 3000, "starts": 2, "backend": "numpy"})
    assert r["feasible"] and r["metrics"] is not None and r["refused"] is None
    again = _recomputed(r)
    for k, v in again.items():
        assert r["metrics"][k] == pytest.approx(v, rel=1e-9, abs=1e-9)
    # the sampled step and lift limits held, and the exact extremes are never inside the sampled ones
    assert again["step"] >= DEFAULTS["step"] * CRANK * (1 - 1e-9)
    assert again["lift"] >= DEFAULTS["lift"] * CRANK * (1 - 1e-9)
    # the objective: sag / (step_min / 10) + vx spread (80 %), here at the sampled values: within the sampling
    # error of the exact values (a 90-sample cycle: a few per cent)
    exact = again["sag"] * 10 / (DEFAULTS["step"] * CRANK) + again["vx_spread_80"]
    assert r["objective"] == pytest.approx(exact, rel=0.15)
    assert len(r["starts"]) == 2 and min(r["starts"]) == pytest.approx(r["objective"])


def test_a_candidate_does_not_depend_on_its_neighbours(six):
    """The seed comes from the run's seed and the candidate's key: alone or among others, the same result."""
    a, b = six[1], six[5]
    alone = rank_legs(6, settings=SMALL, candidates=[b]).as_dict(timings=False)["entries"][0]
    both = rank_legs(6, settings=SMALL, candidates=[a, b]).as_dict(timings=False)["entries"]
    assert next(e for e in both if e["key"] == b.key) | {"rank": 1} == alone
    other_seed = rank_legs(6, settings=SMALL | {"seed": 1}, candidates=[b]).entries[0]
    assert other_seed["variables"] != alone["variables"]


@pytest.mark.slow
def test_executors_give_the_same_ranking(six):
    """In-process, two local processes and a real Dask LocalCluster: the same ranking, number for number, and each
    reports its progress as the candidates' results come in (one call per candidate, counting up to all)."""
    from distributed import Client, LocalCluster
    subset = six[:3]
    seen = {"in": [], "local": [], "dask": []}
    ref = rank_legs(6, settings=SMALL, candidates=subset, progress=lambda d, t: seen["in"].append((d, t)))
    with LocalProcesses(2) as ex:
        local = rank_legs(6, settings=SMALL, candidates=subset, executor=ex,
                          progress=lambda d, t: seen["local"].append((d, t)))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        on_dask = rank_legs(6, settings=SMALL, candidates=subset, executor=DaskCluster(client=client),
                            progress=lambda d, t: seen["dask"].append((d, t)))
    assert ref.executor == "in-process"
    assert local.executor == "local processes" and on_dask.executor == "dask"
    assert local.as_dict(timings=False) == ref.as_dict(timings=False) == on_dask.as_dict(timings=False)
    assert seen["in"] == seen["local"] == seen["dask"] == [(1, 3), (2, 3), (3, 3)]


@pytest.mark.slow
def test_six_link_ranking_end_to_end(tmp_path, six):
    """Every six-link candidate dimensioned with a small budget, ranked and written: the page, the data and a
    mechanism file and drawing per entry, each file walking with the metrics the ranking reports."""
    from assur.report.legs import write_leg_ranking
    # every closed-form candidate and one with a Newton-solved (class III) group: all of them dimensioned and ranked
    # together (a class III candidate costs 15-30 s at this budget on the numpy path; the others are dimensioned by
    # test_a_triad_candidate_is_dimensioned_by_default and the local-process ranking below)
    subset = [c for c in six if not c.newton] + [c for c in six if c.newton][:1]
    ranking = rank_legs(6, settings={"budget": 600, "starts": 1, "backend": "numpy"}, candidates=subset)
    out = tmp_path / "legs"
    write_leg_ranking(ranking, out, subset)
    entries = ranking.entries
    n = len(subset)
    assert len(entries) == n == 23
    assert [e["rank"] for e in entries] == list(range(1, n + 1))
    # each start's search runs whole generations within its share of the budget (a population is 15 per variable)
    assert not any(e["skipped"] for e in entries) and all(e["evaluations"] >= 0.8 * 600 for e in entries)
    ok = [bool(e["feasible"] and e["metrics"]) for e in entries]
    assert ok == sorted(ok, reverse=True) and sum(ok) >= 10          # feasible first
    objectives = [e["objective"] for e, good in zip(entries, ok) if good]
    assert objectives == sorted(objectives)
    data = json.loads((out / "ranking.json").read_text(encoding="utf-8"))
    assert data["format"] == "assur-legs/1" and len(data["entries"]) == n
    page = (out / "index.html").read_text(encoding="utf-8")
    assert page.count("<svg") == n and page.count('class="foot"') == n
    for e, row in zip(entries, data["entries"]):
        text = (out / row["file"]).read_text(encoding="utf-8")
        assert text == e["mechanism"]
        assert (out / row["file"].replace(".toml", ".svg")).read_text(encoding="utf-8").startswith("<svg")
        assert tomllib.loads(text)["gait"]["foot"] == FOOT
        assur.compile(assur.loads(text))       # every file loads, that of a candidate with no feasible design too
        if e["metrics"] is not None:
            again = _recomputed(e)
            assert e["metrics"]["step"] == pytest.approx(again["step"], rel=1e-9)
            assert e["metrics"]["sag"] == pytest.approx(again["sag"], rel=1e-9, abs=1e-9)
    # the foot on a link hinged to the frame swings on a circle: its support arc sags as much as it lifts,
    # so such legs rank below the best one (a property of the geometry, not of the optimiser)
    rocker_feet = [e for e in entries if e["metrics"] and math.isclose(e["metrics"]["sag"], e["metrics"]["lift"],
                                                                      rel_tol=1e-6)]
    assert all(e["rank"] > 1 for e in rocker_feet)


def test_the_newton_candidates_are_the_class_iii_decompositions(six):
    """Independent: a candidate needs Newton iterations exactly when its structural analysis (assur.analyse, the
    Assur decomposition) has a group of class III or higher."""
    from assur.io.mechanism_file import from_dict
    from assur.structure.assur import analyse
    for c in six:
        classes = [g.group_class for g in analyse(from_dict(c.document, c.key)).groups]
        assert c.newton == (max(classes) >= 3), c.key
    assert sum(c.newton for c in six) > 0


@pytest.mark.slow
def test_a_class_iii_candidate_ranks_the_same_on_local_processes(six):
    """A candidate with a Newton-solved group: in-process and on two local processes, the same numbers."""
    subset = [c for c in six if c.newton][:1] + six[:1]
    settings = {"budget": 200, "starts": 2, "backend": "numpy"}
    ref = rank_legs(6, settings=settings, candidates=subset)
    with LocalProcesses(2) as ex:
        local = rank_legs(6, settings=settings, candidates=subset, executor=ex)
    assert local.as_dict(timings=False) == ref.as_dict(timings=False)


@pytest.mark.slow
def test_a_triad_candidate_is_dimensioned_by_default(six):
    """A candidate whose only group after the crank is solved by Newton iterations (no dyad, so no transmission
    angle and no transmission limit) runs like any other (a swept Newton cycle, no polish) and finds a walking
    design at a small budget; its metrics are those of the file it writes, recomputed here."""
    from assur.analysis.transmission import TRANSMISSION_KINDS
    c = next(c for c in six if c.newton and c.inversion_name == "Stephenson II" and c.crank_name == "L1"
             and c.foot_name == "L2")
    problem = leg_problem(c)
    assert not any(st.kind in TRANSMISSION_KINDS for st in problem.plan.steps)
    assert "transmission.min" not in {lim.quantity for lim in problem.limits}
    r = run_candidate(c, {"budget": 600, "starts": 1, "backend": "numpy"})
    assert r["skipped"] is None and r["evaluations"] >= 0.8 * 600
    assert r["feasible"] and r["objective"] is not None and r["metrics"] is not None
    again = _recomputed(r)
    for k, v in again.items():
        assert r["metrics"][k] == pytest.approx(v, rel=1e-9, abs=1e-9)
    assert again["step"] >= 300 * (1 - 1e-3)              # the step limit (3 crank lengths), sampled at 90 angles


@pytest.mark.slow
def test_cli_walking_legs_prints_and_writes(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["atlas", "--walking-legs", "--links", "6", "--limit", "2", "--budget", "300", "--starts", "1",
                 "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert re.search(r"^\s+1\s+Watt I", text, re.M) and "wrote" in text
    assert sorted(p.suffix for p in out.iterdir() if not p.name.startswith(".")) == \
        [".html", ".json", ".svg", ".svg", ".toml", ".toml"]
    assert main(["atlas", "--walking-legs", "--links", "6", "--limit", "1", "--budget", "300", "--starts", "1",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["format"] == "assur-legs/1" and "mechanism" not in data["entries"][0]


@pytest.mark.parametrize("argv, where", [
    (["--walking-legs", "--links", "7"], "--links"),
    (["--walking-legs", "--links", "6", "--dof", "2"], "--dof"),
    (["--links", "6", "--dof", "1", "--budget", "10"], "--budget"),
    (["--walking-legs", "--assur-groups", "--links", "6"], "--walking-legs"),
])
def test_cli_walking_leg_mistakes_are_one_line(argv, where, capsys):
    assert main(["atlas", *argv]) != 0
    err = capsys.readouterr().err
    assert err.startswith("error:") and where in err and "Traceback" not in err


def test_cli_refuses_a_foreign_output_directory_before_any_work(tmp_path, capsys):
    keep = tmp_path / "mine"
    keep.mkdir()
    (keep / "notes.txt").write_text("mine", encoding="utf-8")
    assert main(["atlas", "--walking-legs", "--links", "6", "-o", str(keep)]) != 0
    err = capsys.readouterr().err
    assert "not an earlier output" in err and "candidates" not in err
    assert (keep / "notes.txt").read_text(encoding="utf-8") == "mine"


def test_the_triads_setting_is_deprecated_and_ignored(six):
    from assur.synthesis.legs import settings_of
    with pytest.warns(DeprecationWarning, match="every candidate is dimensioned"):
        s = settings_of({"triads": True, "budget": 10})
    assert "triads" not in s and s["budget"] == 10


#: a design of 'Stephenson II, crank L1, foot on L4' (a class IV group) that the six-link ranking found (default
#: settings, seed 0), in file units (mm, degrees): input data, far from the candidate's sketch
FAR_CLASS_IV = {"J1.x": -62.6574833226064, "J1.y": -231.8758787332542, "L2.length": 497.69371267741616,
                "L3.length": 725.1887087323719, "L4.length": 749.720439628425, "L4.J3.distance": 616.8899038469768,
                "L4.J3.angle": 241.81855524695297, "L4.F.distance": 408.0601446102763,
                "L4.F.angle": 172.8195762166967, "L5.length": 314.50937539232746,
                "L5.J4.distance": 194.09121877428564, "L5.J4.angle": 92.46652425163718}


@pytest.mark.slow            # about 12 s
def test_a_far_newton_design_is_studied_in_its_own_assembly(six):
    """The search sweeps each design through the turn from its own assembly at the sketch's angle; the template's
    plan continued to a design this far from its sketch loses its way on part of the turn. The result's Study is
    that of the file it writes (the design sketched in its own assembly): the whole turn, the sweep's positions."""
    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.optimize import SynthesisResult
    c = next(c for c in six if c.key == "K6-0f8373df6ffa/f0/c1/foot4")
    problem = leg_problem(c)
    x = problem.to_si(np.array([[FAR_CLASS_IV[n] for n in problem.names]]))[0]
    ev = Evaluator(problem, backend="numpy")(x[None, :], True)
    assert ev.feasible[0] and ev.quantities["unbuildable"][0] == 0
    res = SynthesisResult(problem, x, float(ev.objective[0]), True, 0.0, ev.row(0), 1, 0.0, "budget", "de", 0)
    template = assur.Study(problem.plan, res.params())
    assert not np.all(template.state.valid)                      # the template's continuation: part of the turn
    own = res.study()
    assert np.all(own.state.valid)
    # the sweep of the search, from the template at the design's numbers, solves the same positions
    plan = res.design_plan()
    turn = plan.sketch_inputs[0] + np.linspace(0, 2 * np.pi, 90, endpoint=False)
    swept = assur.solve(problem.plan, res.params(), turn, order=0, sweep=True, backend="numpy")
    mine = assur.solve(plan, None, turn, order=0, backend="numpy")
    assert np.all(swept.valid) and np.all(mine.valid)
    assert np.max(np.abs(swept.pos - mine.pos)) < 1e-9 * plan.length_scale


@pytest.mark.slow
def test_a_candidate_failing_inside_assur_does_not_lose_the_others(six, monkeypatch, tmp_path, capsys):
    """A long ranking keeps going past one candidate that fails inside assur (here made to by a stand-in
    run_candidate): that candidate comes last, undimensioned, with the failure; its file is its start and loads;
    the CLI warns of it by name."""
    from assur.synthesis import legs
    real = legs.run_candidate
    bad_key = six[1].key

    def flaky(c, s=None):
        if c.key == bad_key:
            raise ValueError("The function value at x=1.9 is NaN")
        return real(c, s)
    monkeypatch.setattr(legs, "run_candidate", flaky)
    ranking = rank_legs(6, settings={"budget": 150, "starts": 1, "backend": "numpy"}, candidates=six[:3])
    last = ranking.entries[-1]
    assert last["key"] == bad_key and last["skipped"] == "failed: ValueError: The function value at x=1.9 is NaN"
    assert all(e["skipped"] is None for e in ranking.entries[:-1])
    assur.compile(assur.loads(last["mechanism"]))
    monkeypatch.setattr(legs, "leg_candidates", lambda links: six[:3])
    assert main(["atlas", "--walking-legs", "--links", "6", "--budget", "150", "--starts", "1",
                 "-o", str(tmp_path / "legs")]) == 0
    err = capsys.readouterr().err
    assert f"warning: {six[1].name} ({bad_key}) failed inside assur" in err
    assert (tmp_path / "legs" / "ranking.json").exists()


# -- the swing's clearance above the support (lift − sag) ---------------------------------------------------------
def test_bad_clearance_settings_are_named(six):
    for bad in (-0.1, "1", True, math.inf):
        with pytest.raises(assur.SpecError, match="clearance"):
            leg_problem(six[0], {"clearance": bad})


def test_the_clearance_quantity_is_lift_less_sag_on_both_routes(six):
    """gait.clearance = gait.lift − gait.sag on the compiled cycle reduction and on the general numpy route, for the
    same designs (a population around the candidate's sketch)."""
    from assur.synthesis.evaluate import Evaluator
    c = next(c for c in six if c.inversion_name == "Watt I" and c.foot_name == "L3")
    problem = leg_problem(c, {"clearance": 0.3})
    limit, = [lim for lim in problem.limits if lim.quantity == "gait.clearance"]
    assert limit.low == pytest.approx(0.3 * CRANK) and limit.high is None     # the file unit, mm
    assert not any(lim.quantity == "gait.clearance" for lim in leg_problem(c).limits)   # none by default
    rng = np.random.default_rng(3)
    lo, hi = problem.bounds.T
    X = lo + (hi - lo) * rng.random((40, problem.n_vars))
    for backend in ("numpy", "numba"):
        q = Evaluator(problem, backend=backend)(X).quantities
        ok = np.isfinite(q["gait.lift"])
        assert ok.any()
        np.testing.assert_allclose(q["gait.clearance"][ok], (q["gait.lift"] - q["gait.sag"])[ok], rtol=0, atol=1e-12)


def test_a_foot_on_a_rocker_cannot_lift_clear_of_its_support(six):
    """A point of a link hinged to the frame moves on a circle about the hinge: the swing retraces the support arc,
    so lift = sag for every design (clearance 0), and a clearance limit leaves no feasible design."""
    c = next(c for c in six if c.inversion_name == "Watt I" and c.crank_name == "L4" and c.foot_name == "L1")
    r = run_candidate(c, {**SMALL, "clearance": 0.1})
    assert not r["feasible"] and r["violation"] > 0


def test_a_clearance_limit_makes_the_foot_lift_off(six):
    """With a clearance of 0.3 r the best design's foot rises above its support in the swing: the limit holds on
    the search's own samples and the exact gait of the written file shows a swing above the support."""
    c = next(c for c in six if c.inversion_name == "Watt I" and c.foot_name == "L3")
    r = run_candidate(c, {"budget": 3000, "starts": 2, "backend": "numpy", "clearance": 0.3})
    assert r["feasible"]
    again = _recomputed(r)
    assert again["lift"] - again["sag"] > 0.2 * CRANK


@pytest.mark.slow
def test_an_eight_link_ranking_dimensions_its_newton_candidates_without_flags():
    """The eight-link ranking on a small budget, default settings otherwise (no flag: candidates with a class-III or
    class-IV group are dimensioned like the rest): a dyad leg, a class-III leg and a class-IV leg of the atlas, each
    run to its budget and none skipped; the class of each is the structural analysis's (independent of the
    ranking's own ``newton`` mark)."""
    from assur.io.mechanism_file import from_dict
    from assur.structure.assur import analyse
    keys = ["K8-8d44cd84c724/f2/c4/foot3",       # dyads only
            "K8-75c6f90aa409/f7/c3/foot5",       # class III (docs/atlas.md, "Eight links")
            "K8-b66552958ccf/f4/c7/foot5"]       # class IV (tests/data/eightbar_leg_locks_past_a_turn.toml)
    subset = [leg_candidates(8, key)[0] for key in keys]
    classes = [max(g.group_class for g in analyse(from_dict(c.document, c.key)).groups) for c in subset]
    assert classes == [2, 3, 4]
    ranking = rank_legs(8, settings={"budget": 600, "starts": 1}, candidates=subset)
    assert sorted(e["key"] for e in ranking.entries) == sorted(keys)
    for e in ranking.entries:
        assert e["skipped"] is None and e["evaluations"] >= 0.8 * 600, e["key"]
    assert any(e["feasible"] for e in ranking.entries)


#: the best design of K8-8d44cd84c724/f7/c6/foot2 (crank L7, foot on L3) in the eight-link ranking with a clearance,
#: ``assur atlas --walking-legs --links 8 --clearance 0.25`` (default settings, seed 0; gait rank 120 of that run),
#: in file units (mm, degrees): input data, a design whose two halves of the foot path have nearly equal mean heights
TIED_HALVES = {"J8.x": -30.567249604425932, "J8.y": -302.32710369325184, "J7.x": 384.03069838571355,
               "J7.y": -331.912158100208, "L1.length": 344.8481975490019, "L2.length": 583.6724029254323,
               "L3.length": 331.0178233756084, "L3.F.distance": 547.0778434395099, "L3.F.angle": 87.84327950726791,
               "L4.length": 686.1762052221648, "L5.length": 714.568536419471, "L5.J1.distance": 571.1141201592095,
               "L5.J1.angle": 41.107547856344986, "L6.length": 696.409258639124,
               "L6.J2.distance": 170.19013378667245, "L6.J2.angle": 49.17522970446667,
               "L7.J6.distance": 64.66206482895898, "L7.J6.angle": 284.2577437341948}


def test_a_design_whose_search_took_the_swing_for_the_support_is_refused(monkeypatch, tmp_path, capsys):
    """On the search's 90 samples the design is feasible with a swing 28 mm above its support; on its exact gait the
    support is the other half of the foot path, the one holding its top, and the clearance is none. The ranking
    refuses it (not feasible, the reason given) instead of listing it as meeting the clearance."""
    from assur.synthesis import optimize
    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.optimize import SynthesisResult
    c, = leg_candidates(8, key="K8-8d44cd84c724/f7/c6/foot2")
    settings = {"clearance": 0.25, "backend": "numpy"}
    problem = leg_problem(c, settings)
    x = problem.to_si(np.array([[TIED_HALVES[n] for n in problem.names]]))[0]
    ev = Evaluator(problem, backend="numpy")(x[None, :], True)
    assert ev.feasible[0] and ev.quantities["gait.clearance"][0] >= 0.25 * CRANK
    res = SynthesisResult(problem, x, float(ev.objective[0]), True, 0.0, ev.row(0), 1, 0.0, "budget", "de", 0)
    # the same on the file's foot path sampled here: of the two halves between the samples of least and greatest x,
    # the one of lower sample-mean height does not hold the path's highest sample
    plan = res.design_plan()
    q = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    P = assur.solve(plan, inputs=q, order=0).point(FOOT).pos
    a, b = int(np.argmin(P[:, 0])), int(np.argmax(P[:, 0]))
    halves = [np.arange(a, a + (b - a) % 90 + 1) % 90, np.arange(b, b + (a - b) % 90 + 1) % 90]
    lower = min(halves, key=lambda k: P[k, 1].mean())
    assert int(np.argmax(P[:, 1])) not in lower
    monkeypatch.setattr(optimize, "synthesize", lambda *args, **kwargs: res)
    r = run_candidate(c, settings)
    assert not r["feasible"] and "is not the exact gait's" in r["refused"]
    g = assur.Study(assur.compile(assur.loads(r["mechanism"]))).gait
    assert g.lift - g.sag < 1e-9 * g.lift                 # the exact support holds the top: no clearance
    assert r["metrics"]["sag"] == pytest.approx(g.sag * 1000, rel=1e-12)
    ranking = rank_legs(8, settings=settings, candidates=[c])
    assert ranking.entries[0]["refused"] == r["refused"]
    from assur.report.legs import leg_rows, write_leg_ranking
    assert leg_rows(ranking.entries)[0][2] == "refused"
    files = write_leg_ranking(ranking, tmp_path / "legs", [c])
    assert json.loads(files["ranking.json"])["entries"][0]["refused"] == r["refused"]
    page = (tmp_path / "legs" / "index.html").read_text(encoding="utf-8")
    assert "refused: the support the search measured on its 90 samples" in page
    from assur.cli.legs import _print
    capsys.readouterr()
    _print(ranking)
    printed = capsys.readouterr().out
    assert re.search(r"^\s+1\s+K8-8d44cd84c724/f7, crank L7, foot on L3\s+refused", printed, re.M)
    assert "1 design the search found feasible is refused" in printed
