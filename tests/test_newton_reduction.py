"""The reduced unknowns of a Newton-solved group (assur.engine.planar.newton_group.reduction and expand): a binary
link of two revolutes is one distance equation instead of three unknowns and four joint equations, and its pose
follows from its ends. Checked here against the full loop equations, which the acceptance, the certificate and the
derivatives still use: the reduced equations vanish at the full equations' roots, the expanded poses close every
joint, and a link's angle stays the turn of its reference that it was."""
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.engine.planar.continuation import context_at
from assur.engine.planar.newton_group import _residual, _residual_and_jacobian, expand, reduction
from assur.kernels.jet import Jet

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _group(plan):
    st = next(s for s in plan.steps if s.kind == "newton")
    return st, reduction(plan.structure.graph, plan.lines, st)


def _names(plan, bodies):
    return [plan.structure.graph.bodies[b].name for b in bodies]


def _solved(plan, st, params, q):
    """The group's poses (3k,) solved by the numpy backend at one design and input, and the context before the
    group (its known bodies placed)."""
    i = plan.steps.index(st)
    x = np.asarray(context_at(plan, plan.steps[:i + 1], params, [q]).warm[id(st)], dtype=float).reshape(-1)
    return x, context_at(plan, plan.steps[:i], params, [q])


@pytest.fixture(scope="module", params=["triad_sixbar", "classiv_sixbar"])
def plan(request):
    return assur.compile(assur.load(EXAMPLES / f"{request.param}.toml"))


def test_which_bodies_are_iterated():
    """The triad six-bar iterates on its ternary's pose alone; the class-IV six-bar on its two ternaries (its two
    binary links are rods); a link that slides is never a rod (the slotted triad of test_compiled_newton)."""
    from test_compiled_newton import SLOTTED
    triad = assur.compile(assur.load(EXAMPLES / "triad_sixbar.toml"))
    st, red = _group(triad)
    assert _names(triad, red.kept) == ["tern"]
    assert sorted((_names(triad, [b])[0], p, q) for b, p, q, *_ in red.rods) == [
        ("ab", "A", "B"), ("r1", "P1", "C"), ("r2", "P2", "D")]
    assert list(red.index) == [3 * st.bodies.index(red.kept[0]) + k for k in range(3)]
    classiv = assur.compile(assur.load(EXAMPLES / "classiv_sixbar.toml"))
    st, red = _group(classiv)
    assert len(red.kept) == 2 and len(red.rods) == 2 and len(st.bodies) == 4
    slotted = assur.compile(assur.loads(SLOTTED))
    st, red = _group(slotted)
    sliding = {b for rec in slotted.lines for b in rec[2:4]}
    assert sliding & set(st.bodies) and not sliding & {r[0] for r in red.rods}
    assert _names(slotted, [r[0] for r in red.rods]) == ["ab", "r2"]


def test_the_reduced_equations_vanish_at_the_loops_roots(plan):
    """At solved poses (random designs and inputs, the numpy backend's full-equation result): the reduced residual
    is round-off, its count is the iterated unknowns', and expanding the kept poses gives the solved poses back."""
    st, red = _group(plan)
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(12):
        p = plan.defaults * (1 + 0.02 * rng.standard_normal(plan.n_params))
        x, c = _solved(plan, st, p, rng.uniform(0, 2 * np.pi))
        if not np.all(np.isfinite(x)):
            continue
        checked += 1
        y = x[list(red.index)]
        F, J = _residual_and_jacobian(c, st, y, (), red)
        assert F.shape == y.shape and J.shape == (y.size, y.size)
        assert np.max(np.abs(F)) < 1e-12 * plan.length_scale
        back = np.array([float(np.real(v)) for v in expand(c, st, red, list(y), list(x))])
        np.testing.assert_allclose(back, x, rtol=0, atol=1e-12 * plan.length_scale)
    assert checked >= 6


def test_expanded_poses_close_the_rods_ends(plan):
    """Away from a root (the kept poses perturbed): the expanded rods hold their first ends exactly and miss their
    second by their distance error |P₂ − P₁| − l, which the reduced residual (|P₂ − P₁|² − l²)/(2l) gives to first
    order; each rod's angle is its reference's turn (a reference k turns off gives the angle k turns off)."""
    st, red = _group(plan)
    x, c = _solved(plan, st, plan.defaults, 0.4)
    rng = np.random.default_rng(5)
    y = x[list(red.index)] + 1e-4 * plan.length_scale * rng.standard_normal(len(red.index))
    reduced, _ = _residual_and_jacobian(c, st, y, (), red)
    xf = np.array([float(np.real(v)) for v in expand(c, st, red, list(y), list(x))])
    labels = []
    full = np.array([float(np.real(r.v)) for r in _residual(c, st, [Jet(np.float64(v)) for v in xf], False,
                                                             labels=labels)])
    for k, (b, p1, p2, *_) in enumerate(red.rods):
        # a rod's joints take two rows each (its partner's): its first end held, its second off by the distance error
        first = full[[i for i, name in enumerate(labels) if name == p1]]
        second = full[[i for i, name in enumerate(labels) if name == p2]]
        assert first.size == second.size == 2
        assert np.max(np.abs(first)) < 1e-13 * plan.length_scale
        miss = np.hypot(*second)
        r = abs(reduced[len(reduced) - len(red.rods) + k])
        assert r > 1e-7 * plan.length_scale
        assert abs(miss - r) <= 1e-3 * r
    for b, *_ in red.rods:
        j = 3 * st.bodies.index(b) + 2
        for turns in (-2, 1, 3):
            ref = x.copy()
            ref[j] += 2 * np.pi * turns + 0.3
            got = float(np.real(expand(c, st, red, list(y), list(ref))[j]))
            assert abs(got - xf[j] - 2 * np.pi * turns) < 1e-9
