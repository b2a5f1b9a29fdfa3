"""Compiled Newton groups (assur.engine.planar.newton_kernels): the numba kernels of plans with a class-III triad or
a larger group give the numpy backend's numbers — positions, analogues, body angles and the valid (unbuildable)
samples — under its default continuation (every sample continued from the sketch on its own,
:func:`assur.engine.planar.continuation.execute`) and under its sweep (``solve(..., sweep=True)``): the reference is
always the numpy backend with the same options, on the triad six-bar, perturbed populations and copies scaled by 10⁻³
and 10³. A plan the kernels do not check as numpy does (a class-IV group) falls back to numpy. The traced pieces
(residual, Newton step, branch certificate) are checked against newton_group's own functions at random poses."""
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import assur

pytest.importorskip("numba")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TRIAD = EXAMPLES / "triad_sixbar.toml"
FIELDS = ("pos", "vel", "acc", "dpos_dq", "d2pos_dq2", "body_angle", "body_omega", "body_alpha")

#: the triad six-bar with its binary link P1-C replaced by a pin in a frame slot through P1 (pointing at C in the
#: sketch): a class-III group with a prismatic pair, buildable over part of the turn only
SLOTTED = """
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
P1 = [300, 0]
P2 = [50, 250]
A = [15, 0]
B = [140, 40]
C = [200, 90]
D = [120, 130]
[links]
frame = ["O", "P1", "P2"]
crank = ["O", "A"]
ab = ["A", "B"]
tern = ["B", "C", "D"]
r2 = ["P2", "D"]
[[prismatic]]
name = "slot"
point = "C"
guide = "frame"
through = "P1"
angle = 138.0127875041833
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
"""


@pytest.fixture(scope="module")
def triad():
    return assur.compile(assur.load(TRIAD))


def both(plan, params=None, q=None, order=2, sweep=False):
    """(numpy, numba) solves of the plan with the same options."""
    q = np.linspace(0.0, 2 * np.pi, 90, endpoint=False) if q is None else q
    a = assur.solve(plan, params, q, order=order, backend="numpy", sweep=sweep)
    b = assur.solve(plan, params, q, order=order, backend="numba", sweep=sweep)
    assert b._xyz is not None          # the compiled backend solved it
    return a, b


def same(a, b, fields=FIELDS, rel=1e-11, scale=1.0):
    """Equal valid samples; every field NaN at the same samples and equal to ``rel`` relative (of ``scale`` below
    it: the mechanism's size for lengths)."""
    assert np.array_equal(a.valid, b.valid) and a.n_unbuildable == b.n_unbuildable
    for f in fields:
        x, y = np.asarray(getattr(a, f)), np.asarray(getattr(b, f))
        assert np.array_equal(np.isnan(x), np.isnan(y)), f
        ok = np.isfinite(x)
        floor = scale if f in ("pos", "vel", "acc", "dpos_dq", "d2pos_dq2") else 1.0
        assert np.all(np.abs(x[ok] - y[ok]) <= rel * np.maximum(floor, np.abs(x[ok]))), f


@pytest.mark.slow            # compiles the order-2 kernel (10–30 s with an empty cache)
def test_rates_per_sample_give_the_velocities_and_accelerations_of_the_numpy_route(triad):
    """Input speeds and accelerations given per sample ((N, 1), as the co-design's motor law gives them) scale the
    compiled solve's analogues sample by sample: the same velocities and accelerations as the numpy route."""
    q = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)
    qdot, qddot = (1.0 + 0.5 * np.sin(q))[:, None], np.cos(q)[:, None]
    a = assur.solve(triad, None, q, order=2, speeds=qdot, accels=qddot, backend="numpy")
    b = assur.solve(triad, None, q, order=2, speeds=qdot, accels=qddot, backend="numba")
    assert b._xyz is not None
    same(a, b, fields=("pos", "vel", "acc"), scale=0.3)


def scaled_triad(s: float):
    """The triad six-bar with every length multiplied by ``s`` (tests/test_scale.py's ``scaled``)."""
    from test_scale import scaled
    return assur.compile(scaled(assur.load(TRIAD), s))


def population(plan, n=16, seed=1, spread=0.05):
    """``n`` designs around the plan's, each parameter × (1 + spread·N(0, 1))."""
    rng = np.random.default_rng(seed)
    return plan.defaults * (1 + spread * rng.standard_normal((n, plan.n_params)))


def test_the_traced_group_computes_what_numpy_computes(triad):
    """At random designs, inputs and poses around the sketch's: the traced residual and Newton step of the iterated
    (reduced) unknowns and the branch certificate at the full poses they give (the lines the kernel runs, executed
    here as plain Python) equal newton_group's _residual_and_jacobian, numpy.linalg.solve, expand and
    certificate_det."""
    from assur.engine.planar import traced
    from assur.engine.planar.newton_group import _residual_and_jacobian, certificate_det, expand, reduction
    from assur.engine.planar.newton_kernels import seeds
    from assur.engine.planar.continuation import context_at
    from assur.kernels import trace as T
    plan = triad
    t = traced.trace_plan(plan, 0, row="p[{}]")
    g = t.groups[0]
    st = next(s for s in plan.steps if s.kind == "newton")
    red = reduction(plan.structure.graph, plan.lines, st)
    assert list(g.start) == list(red.index) and len(g.x) == 3      # the ternary's pose: the triad's unknowns
    full = len(g.solved)
    outs = g.F + g.update + [g.certificate]
    names = ["p", "c", "s", "tol", "ls"] + [x.name for x in g.x] + [f"pr0_{i}" for i in range(full)]
    body = "".join(f"    {ln}\n" for ln in t.tracer.needed(outs))
    ns = {"math": SimpleNamespace(cos=math.cos, sin=math.sin, sqrt=math.sqrt, isfinite=math.isfinite, nan=math.nan,
                                  atan2=math.atan2),
          "max": max}
    exec(f"def f({', '.join(names)}):\n{body}    return [{', '.join(T.source(o) for o in outs)}]\n", ns)
    i = plan.steps.index(st)
    rng = np.random.default_rng(4)
    n = len(g.x)
    for _ in range(20):
        p = plan.defaults * (1 + 0.03 * rng.standard_normal(plan.n_params))
        q = rng.uniform(0, 2 * np.pi)
        x = seeds(plan) + 0.02 * rng.standard_normal(full)
        y = x[list(red.index)]
        got = ns["f"](p, math.cos(q), math.sin(q), 1e-12, plan.length_scale, *y, *x)
        c = context_at(plan, plan.steps[:i], p, [q])
        F, J = _residual_and_jacobian(c, st, y, (), red)
        np.testing.assert_allclose(got[:n], F, rtol=0, atol=1e-15)
        np.testing.assert_allclose(got[n:2 * n], y - np.linalg.solve(J, F), rtol=1e-12, atol=1e-14)
        xf = np.array(expand(c, st, red, list(y), list(x)), dtype=float)
        Jf = _residual_and_jacobian(c, st, xf, ())[1]
        assert math.isclose(got[-1], float(certificate_det(c, st, Jf)), rel_tol=1e-11)


@pytest.mark.slow            # compiles the kernel (10–30 s with an empty cache)
def test_a_cycle_of_the_triad_six_bar(triad):
    """The default continuation: every sample continued from the sketch on its own."""
    a, b = both(triad, q=np.linspace(0.0, 2 * np.pi, 72, endpoint=False))
    assert a.valid.all()
    same(a, b, scale=triad.length_scale)


@pytest.mark.slow            # compiles the sweep kernel
def test_a_swept_cycle_of_the_triad_six_bar(triad):
    a, b = both(triad, q=np.linspace(0.0, 2 * np.pi, 72, endpoint=False), sweep=True)
    assert a.valid.all()
    same(a, b, scale=triad.length_scale)


@pytest.mark.slow            # the numpy reference continues 640 samples from the sketch one by one (5 s)
@pytest.mark.parametrize("sweep", [False, True])
def test_a_perturbed_population_of_triad_six_bars(triad, sweep):
    """Designs that turn fully, partly (their walks end at toggles: the other way round takes over) and not at all:
    the same valid samples, the same numbers."""
    P = population(triad)
    a, b = both(triad, P[:, None, :], np.linspace(0.0, 2 * np.pi, 40, endpoint=False)[:, None], sweep=sweep)
    full, some = a.valid.all(axis=1), a.valid.any(axis=1)
    assert full.sum() >= 3 and (some & ~full).sum() >= 2 and (~some).sum() >= 1
    same(a, b, ("pos", "dpos_dq", "d2pos_dq2", "body_angle"), rel=1e-9, scale=triad.length_scale)


@pytest.mark.slow            # the numpy reference on populations (about 10 s)
@pytest.mark.parametrize("s", [1e-3, 1e3])
def test_scaled_copies(triad, s):
    """Scaled by 10⁻³ and 10³: the compiled kernel gives numpy's answer there too (a cycle, a population at ±1 %),
    and the cycle's positions are the unscaled ones times s (the certificate is free of units)."""
    plan = scaled_triad(s)
    q = np.linspace(0.0, 2 * np.pi, 72, endpoint=False)
    a, b = both(plan, q=q)
    assert a.valid.all()
    same(a, b, scale=plan.length_scale)
    ref = assur.solve(triad, inputs=q, order=0, backend="numba")
    np.testing.assert_allclose(b.pos / s, ref.pos, rtol=0, atol=1e-12 * triad.length_scale)
    P = population(plan, 12, seed=3, spread=0.01)
    a, b = both(plan, P[:, None, :], np.linspace(0.0, 2 * np.pi, 24, endpoint=False)[:, None])
    assert a.valid.sum() > 0
    same(a, b, ("pos", "dpos_dq", "d2pos_dq2", "body_angle"), rel=1e-9, scale=plan.length_scale)


@pytest.mark.slow            # compiles the class-IV structure's kernel
def test_a_class_iv_group():
    """The class-IV six-bar: its group's other assemblies are found by the certified reduction, which numpy runs
    where the group's dimensionless determinant is small (one design only); the kernel hands those samples to numpy's
    check (newton_kernels.separate_by_reduction). The same valid samples and numbers, for the file's design and a
    perturbed population."""
    plan = assur.compile(assur.load(EXAMPLES / "classiv_sixbar.toml"))
    assert any(st.kind == "newton" for st in plan.steps)
    a, b = both(plan, q=np.linspace(0.0, 2 * np.pi, 72, endpoint=False))
    same(a, b, scale=plan.length_scale)
    P = population(plan, 8, seed=5, spread=0.03)
    a, b = both(plan, P[:, None, :], np.linspace(0.0, 2 * np.pi, 24, endpoint=False)[:, None])
    assert a.valid.any()
    same(a, b, ("pos", "dpos_dq", "d2pos_dq2", "body_angle"), rel=1e-9, scale=plan.length_scale)


def test_a_sample_next_to_another_assembly_gets_numpys_check(triad, monkeypatch):
    """separate_by_reduction hands exactly the valid samples of a reduction-checked group whose certificate is below
    the gate to numpy's continuation.separate, and writes back its verdict (here: the check flags every second one)."""
    from assur.engine.planar import continuation, newton_kernels
    calls = []

    def fake_separate(plan, steps, c, method, tol, shape, x):
        calls.append((shape, {k: v.copy() for k, v in x.items()}))
        c.valid = np.arange(shape[0]) % 2 == 0
        return c
    monkeypatch.setattr(continuation, "separate", fake_separate)
    from assur.engine.planar import group_assemblies
    monkeypatch.setattr(group_assemblies, "group_method", lambda plan, st: "reduction")
    st = next(s for s in triad.steps if s.kind == "newton")
    q = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
    n = 3 * len(st.bodies)
    xs = np.stack([np.full(8, 0.1 * i) for i in range(n)])            # stand-in poses, handed over as they are
    certs = np.array([[0.5, 1e-3, 0.5, 1e-3, 1e-3, 0.5, 0.5, 1e-3]])
    valid = np.ones(8, dtype=bool)
    valid[4] = False                                                    # an invalid sample is never checked
    from assur.tolerances import DEFAULT
    newton_kernels.separate_by_reduction(triad, triad.defaults, q[:, None], (8,), DEFAULT,
                                         np.concatenate([xs, certs]), valid)
    (shape, x), = calls
    assert shape == (3,)                                                # samples 1, 3 and 7
    np.testing.assert_array_equal(x[id(st)], xs[:, [1, 3, 7]].T)
    np.testing.assert_array_equal(valid, [True, True, True, False, False, True, True, True])


@pytest.mark.slow            # compiles two kernels of another structure
@pytest.mark.parametrize("sweep", [False, True])
def test_a_group_with_a_slot(sweep):
    """A class-III group with a prismatic pair (its residual's alignment and slide rows), buildable over part of the
    turn."""
    plan = assur.compile(assur.loads(SLOTTED))
    assert [st.kind for st in plan.steps] == ["frame", "crank", "newton"] and plan.lines
    a, b = both(plan, sweep=sweep)
    assert 0 < a.n_unbuildable < 90
    same(a, b, scale=plan.length_scale)


@pytest.mark.slow            # compiles the sweep kernel
def test_batch_layouts(triad):
    """Inputs per design (each design's samples continued one by one: numpy sweeps only inputs shared by every
    design), a design per sample and a single sample: the numpy backend's numbers with and without ``sweep``."""
    rng = np.random.default_rng(2)
    P = triad.defaults * (1 + 0.02 * rng.standard_normal((5, triad.n_params)))
    q = np.sort(rng.uniform(0, 2 * np.pi, (5, 7)), axis=1)
    for sweep in (False, True):
        same(*both(triad, P[:, None, :], q[..., None], sweep=sweep), ("pos", "dpos_dq", "d2pos_dq2"),
             scale=triad.length_scale)
        same(*both(triad, P, q[:, 0], sweep=sweep), ("pos", "dpos_dq", "d2pos_dq2"), scale=triad.length_scale)
    a = assur.solve(triad, inputs=0.7, backend="numpy")
    b = assur.solve(triad, inputs=0.7, backend="numba")
    assert b.pos.shape == a.pos.shape == (triad.n_points, 2)
    same(a, b, scale=triad.length_scale)


def test_the_kernel_source_depends_on_the_structure_only(triad):
    """Another design and another sketch of the same structure (the triad six-bar scaled and redrawn) give the same
    kernel source: the file's numbers, the seeds and the tolerances are the kernel's arguments, so a plan dragged in
    the designer reuses its compiled kernel (and its source, kept by structure)."""
    from assur.engine.planar.newton_kernels import _solve_source, structure_key
    text = TRIAD.read_text().replace("B = [140, 40]", "B = [141, 41]").replace('length = "mm"', 'length = "cm"')
    other = assur.compile(assur.loads(text))
    assert not np.allclose(other.defaults, triad.defaults)
    assert _solve_source(other, 2) == _solve_source(triad, 2)          # traced afresh, each
    # so a structure is traced once: its key is the same, another structure's is not
    assert structure_key(other) == structure_key(triad)
    assert structure_key(assur.compile(assur.loads(SLOTTED))) != structure_key(triad)


def test_a_new_plan_of_a_known_structure_takes_the_loaded_kernel(triad, monkeypatch):
    """A designer's drag compiles a new plan per move: its kernel is the one loaded for an earlier plan of the same
    generated source (numba_backend._LOADED), not looked up, read and hashed again; another source is loaded anew.
    (codegen.load is replaced by a counter here: nothing compiles.)"""
    from assur.engine.planar import numba_backend
    loads = []
    monkeypatch.setattr(numba_backend, "_LOADED", {})
    monkeypatch.setattr(numba_backend.codegen, "load", lambda source, what="": loads.append(source) or object())
    moved = assur.compile(assur.loads(TRIAD.read_text().replace("B = [140, 40]", "B = [141, 41]")))
    a = numba_backend._load(triad, "test_key", lambda: "source one")
    b = numba_backend._load(moved, "test_key", lambda: "source one")
    c = numba_backend._load(moved, "other_key", lambda: "source two")
    assert a is b and c is not a and loads == ["source one", "source two"]
    assert numba_backend._load(moved, "test_key", lambda: pytest.fail("traced again")) is a   # kept per plan too
    for plan in (triad, moved):                        # the stand-ins go with this test
        for key in ("test_key", "other_key"):
            numba_backend._KERNELS.get(plan, {}).pop(key, None)


@pytest.mark.slow            # compiles the kernel
def test_auto_takes_the_kernel_when_ready_or_paid(triad, monkeypatch):
    """backend='auto' on a plan with Newton-solved groups (engine.api._compiled_pays): the compiled kernel when it is
    ready (compiled in this process or cached), or compiled first for a batch that wins the compile back at once
    (AUTO_NEWTON_COMPILE_MIN_SAMPLES); numpy for an ordinary batch otherwise."""
    from assur.engine import api
    from assur.engine.options import AUTO_CACHED_MIN_SAMPLES, AUTO_NEWTON_COMPILE_MIN_SAMPLES
    from assur.engine.planar import numba_backend
    q = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    assur.solve(triad, inputs=q, backend="numba")                            # the default continuation's kernel
    assert numba_backend.newton_cached(triad) and numba_backend.kernel_ready(triad)
    assert assur.solve(triad, inputs=q)._xyz is not None                      # ready: compiled
    assert assur.solve(triad, inputs=q[:AUTO_CACHED_MIN_SAMPLES - 1])._xyz is None   # too small to gain
    monkeypatch.setattr(numba_backend, "newton_cached", lambda plan, each=True: False)
    assert assur.solve(triad, inputs=q)._xyz is None                          # not ready, not paid: numpy
    assert api._compiled_pays(triad, AUTO_NEWTON_COMPILE_MIN_SAMPLES, 2)      # paid: compiled first
    jansen = assur.compile(assur.load(EXAMPLES / "jansen.toml"))
    monkeypatch.setattr(numba_backend, "kernel_ready", lambda *a, **k: False)
    assert not api._compiled_pays(jansen, AUTO_NEWTON_COMPILE_MIN_SAMPLES, 2)  # a dyad plan's numpy is 1000× faster


def test_a_triad_synthesis_compiles_when_numpy_would_take_longer():
    """The first-use rule of synthesis (synthesis.evaluate.run_backend) weighs a Newton-solved group's numpy cost: a
    triad leg's run of an ordinary budget compiles (its kernels then evaluate it), a tiny one stays on numpy."""
    from assur.io.mechanism_file import from_dict
    from assur.synthesis.evaluate import (NUMPY_SECONDS_PER_NEWTON_GROUP, NUMPY_SECONDS_PER_UNIT, PAYBACK_SECONDS,
                                          numpy_seconds, run_backend)
    from assur.synthesis.problem import problem_from_dict
    plan = assur.compile(from_dict(LEG, "leg"))
    length = plan.defaults[plan.param_index("L3.length")] * 1000                # mm, the file's unit
    data = {"format": "assur-synth/1", "variables": {"L3.length": [0.7 * length, 1.3 * length]},
            "objective": {"deviation": "none", "terms": [{"quantity": "gait.sag", "weight": 1.0}]},
            "options": {"cycle_samples": 60}}
    prob = problem_from_dict(data, mechanism=plan)
    newton = sum(st.kind == "newton" for st in plan.steps)
    assert newton == 1
    per = (len(plan.steps) - 1) * NUMPY_SECONDS_PER_UNIT + NUMPY_SECONDS_PER_NEWTON_GROUP
    assert numpy_seconds(prob, 1000) == pytest.approx(1000 * 60 * per)
    assert run_backend(prob, 2000, None) == "numba"              # 36 s of numpy: the compile pays
    assert run_backend(prob, 100, None) == "numpy"               # under PAYBACK_SECONDS: nothing compiled
    assert numpy_seconds(prob, 100) < PAYBACK_SECONDS <= numpy_seconds(prob, 2000)


#: a Stephenson II walking leg whose driven chain is a class-III group: the first 6-link candidate with a Newton-solved
#: group of the atlas (assur.synthesis.legs.leg_candidates(6), key K6-0f8373df6ffa/f0/c1/foot2), as it writes it
LEG = {
    "format": "assur/1", "units": {"length": "mm", "angle": "deg"},
    "points": {"J0": [122.34, 50.0], "J1": [547.27, 50.0], "J2": [50.0, 201.67], "J3": [667.78, 624.32],
               "J4": [317.73, 886.68], "J5": [779.29, 461.14], "J6": [515.19, 705.59], "F": [492.75, 655.5]},
    "links": {"frame": ["J1", "J0"], "L1": ["J0", "J2"], "L2": ["J3", "J4", "F"], "L3": ["J5", "J6"],
              "L4": ["J1", "J5", "J3"], "L5": ["J2", "J6", "J4"]},
    "drivers": [{"name": "crank", "kind": "rotary", "link": "L1", "pivot": "J0", "arm": "J2", "speed": "60 rpm"}],
    "gait": {"foot": "F", "ground": [1, 0], "up": [0, 1]},
}


@pytest.mark.slow            # compiles the cycle kernel of another structure
def test_the_synthesis_cycle_route_runs_compiled():
    """The synthesis evaluator's whole-cycle quantities of a triad leg (buildability, the sampled gait) come from the
    compiled cycle reduction, equal to the numpy route's (the cycle swept by solve(..., sweep=True)) on a perturbed
    population, infeasible designs included."""
    from assur.io.mechanism_file import from_dict
    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.problem import problem_from_dict
    plan = assur.compile(from_dict(LEG, "leg"))
    names = ["L2.length", "L3.length", "L4.length", "L5.length", "L2.F.distance"]
    values = [plan.defaults[plan.param_index(n)] * 1000 for n in names]
    data = {"format": "assur-synth/1", "variables": {n: [0.7 * v, 1.3 * v] for n, v in zip(names, values)},
            "objective": {"deviation": "none", "terms": [{"quantity": "gait.sag", "weight": 10.0},
                                                         {"quantity": "gait.vx_spread", "weight": 1.0}]},
            "constraints": {"use": ["buildable"], "limits": [{"quantity": "gait.step", "min": 0.05}]},
            "options": {"cycle_samples": 60}}
    prob = problem_from_dict(data, mechanism=plan)
    numpy_route, compiled = Evaluator(prob, backend="numpy"), Evaluator(prob, backend="numba")
    assert compiled._cycle_fast and not numpy_route._cycle_fast
    rng = np.random.default_rng(6)
    X = np.array(values) / 1000 * (1 + 0.06 * rng.standard_normal((40, len(names))))
    a, b = numpy_route(X), compiled(X)
    assert 0 < a.feasible.sum() < len(X) and np.array_equal(a.feasible, b.feasible)
    np.testing.assert_allclose(b.violation, a.violation, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(b.penalised, a.penalised, rtol=1e-9, atol=1e-12)
    for k, v in a.quantities.items():
        np.testing.assert_allclose(b.quantities[k], v, rtol=1e-9, atol=1e-12, err_msg=k)


def test_the_designer_compiles_a_triads_kernel_in_the_background(monkeypatch):
    """A designer session on a mechanism with Newton-solved groups starts the kernel's compile in a background thread
    (its previews run on numpy until the kernel is ready, then on it); a dyad mechanism starts none."""
    from assur.designer.server import _prepare_kernels
    from assur.designer.session import Session, document_of
    from assur.engine.planar import numba_backend
    seen = []
    monkeypatch.setattr(numba_backend, "prepare_newton", lambda plan: seen.append(plan.n_points))
    doc, _ = document_of(TRIAD)
    thread = _prepare_kernels(Session(doc, None))
    assert thread is not None and thread.daemon
    thread.join(10)
    assert seen == [assur.compile(assur.load(TRIAD)).n_points]
    doc, _ = document_of(EXAMPLES / "jansen.toml")
    assert _prepare_kernels(Session(doc, None)) is None


def test_prepare_newton_loads_the_kernel_and_says_whether_it_compiled(triad, monkeypatch):
    from assur.engine.planar import numba_backend
    loaded = []
    monkeypatch.setattr(numba_backend, "solve_newton", lambda plan, *a, **k: loaded.append(plan))
    monkeypatch.setattr(numba_backend, "newton_cached", lambda plan, each=True: True)
    assert numba_backend.prepare_newton(triad) is False and loaded == [triad]          # cached: loaded only
    monkeypatch.setattr(numba_backend, "newton_cached", lambda plan, each=True: False)
    assert numba_backend.prepare_newton(triad) is True and loaded == [triad, triad]    # compiled
    assert numba_backend.prepare_newton(assur.compile(assur.load(EXAMPLES / "jansen.toml"))) is False
    assert loaded == [triad, triad]


@pytest.mark.slow            # compiles this structure's kernels
@pytest.mark.parametrize("sweep", [False, True])
def test_a_newton_group_after_a_dyad(sweep):
    """A crank, a dyad, then a Newton-solved group that reads the dyad's point (an eight-link atlas leg,
    tests/data/dyad_then_newton_eightbar.toml): the group's iterations start only where the dyad closes, so the
    kernel reads the dyad's validity first (its generated source once read it before computing it and did not
    compile). The same valid samples and numbers as numpy."""
    plan = assur.compile(assur.load(Path(__file__).parent / "data" / "dyad_then_newton_eightbar.toml"))
    assert [st.kind for st in plan.steps] == ["frame", "crank", "RRR", "newton"]
    a, b = both(plan, q=np.linspace(0.0, 2 * np.pi, 72, endpoint=False), sweep=sweep)
    assert a.valid.any()
    same(a, b, scale=plan.length_scale)


@pytest.mark.slow            # compiles the cycle kernel of that leg
def test_the_gait_cycle_kernel_of_a_newton_group_after_a_dyad():
    """The compiled cycle reduction of the walking-leg problem on that leg (what the atlas ranking evaluates) gives
    the numpy route's gait quantities."""
    import tomllib

    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.legs import LegCandidate, leg_problem
    doc = tomllib.loads((Path(__file__).parent / "data" / "dyad_then_newton_eightbar.toml").read_text("utf-8"))
    c = LegCandidate("K8-f84c3d8e3fa6/f2/c4/foot3", "leg", "K8-f84c3d8e3fa6/f2", None, 4, 3, "L4", "L3", doc,
                     newton=True)
    problem = leg_problem(c)
    plan = problem.plan
    start = dict(zip(plan.param_names, plan.defaults))
    x = np.array([start[n] for n in problem.names])
    X = x * (1 + 0.02 * np.random.default_rng(3).standard_normal((6, len(x))))
    fast = Evaluator(problem, backend="numba")(np.vstack([x, X]), True)
    slow = Evaluator(problem, backend="numpy")(np.vstack([x, X]), True)
    assert np.array_equal(fast.feasible, slow.feasible)
    for k in ("unbuildable", "gait.step", "gait.lift", "gait.sag", "gait.top"):
        a, b = slow.quantities[k], fast.quantities[k]
        assert np.array_equal(np.isnan(a), np.isnan(b)), k
        ok = np.isfinite(a)
        assert np.allclose(a[ok], b[ok], rtol=1e-9, atol=1e-9), k


@pytest.mark.slow            # compiles this structure's kernel
def test_a_newton_group_without_a_rod():
    """A group whose binary links are none of them held by exactly one known or kept body at each end (an
    eight-link atlas leg, K8-d2bbc4129cb8/f0/c1/foot5, as the ranking writes its start): every body is iterated.
    Its trace once read the full Jacobian that only a group with rods builds, and the kernel did not generate."""
    from assur.engine.planar.newton_group import reduction
    from assur.io.mechanism_file import from_dict
    from assur.synthesis.legs import leg_candidates
    c, = leg_candidates(8, key="K8-d2bbc4129cb8/f0/c1/foot5")
    plan = assur.compile(from_dict(c.document, c.key))
    newton = [st for st in plan.steps if st.kind == "newton"]
    assert newton and all(not reduction(plan.structure.graph, plan.lines, st).rods for st in newton)
    a, b = both(plan, q=np.linspace(0.0, 2 * np.pi, 36, endpoint=False))
    assert a.valid.any()
    same(a, b, scale=plan.length_scale)
