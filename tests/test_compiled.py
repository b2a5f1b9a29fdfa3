"""The compiled (numba) backend gives the numpy backend's numbers, for every kind it covers."""
from pathlib import Path

import numpy as np

import pytest

import assur

pytest.importorskip("numba")

EXAMPLES = ["walker_fourbar", "walker_crank_slider", "walker_sixbar", "walker_sixbar_beta1_60", "jansen", "klann",
            "chebyshev_lambda", "slider_crank", "crank_rocker"]

WHITWORTH = (Path(__file__).parent / "data" / "whitworth_slotted_lever.toml").read_text(encoding="utf-8")

DOUBLE_ROCKER = """
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
C = [100, 0]
A = [60, 0]
B = [90, 70]
[links]
frame = ["O", "C"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["C", "B"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
"""


def both(plan, params=None, q=None):
    q = np.linspace(0, 2 * np.pi, 97) if q is None else q
    return (assur.solve(plan, params, q, backend="numpy"), assur.solve(plan, params, q, backend="numba"))


def close(a, b, what):
    ok = np.isfinite(a) | np.isfinite(b)
    assert np.array_equal(np.isnan(a), np.isnan(b)), what
    scale = max(1.0, float(np.nanmax(np.abs(a))))
    assert np.nanmax(np.abs(a[ok] - b[ok])) <= 1e-11 * scale, what


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_match(name):
    from pathlib import Path
    plan = assur.compile(assur.load(Path(__file__).resolve().parents[1] / "examples" / f"{name}.toml"))
    a, b = both(plan)
    assert np.array_equal(a.valid, b.valid)
    for attr in ("pos", "vel", "acc", "dpos_dq", "d2pos_dq2", "body_angle", "body_omega", "body_alpha"):
        close(getattr(a, attr), getattr(b, attr), attr)


@pytest.mark.parametrize("text", [WHITWORTH, DOUBLE_ROCKER], ids=["RPR slotted lever", "unbuildable range"])
def test_kinds_and_unbuildable_match(text):
    plan = assur.compile(assur.loads(text))
    a, b = both(plan)
    assert np.array_equal(a.valid, b.valid) and a.n_unbuildable == b.n_unbuildable
    for attr in ("pos", "vel", "acc"):
        close(a.__getattribute__(attr), b.__getattribute__(attr), attr)
    if text is DOUBLE_ROCKER:
        assert 0 < a.n_unbuildable < 97
        assert np.all(np.isnan(b.pos[~b.valid]))


def test_population_broadcast_matches():
    plan = assur.compile(assur.loads(DOUBLE_ROCKER))
    rng = np.random.default_rng(3)
    params = np.tile(plan.defaults, (40, 1, 1))
    params[:, 0, plan.param_index("coupler.length")] *= rng.uniform(0.9, 1.3, 40)
    a, b = both(plan, params)
    assert b.pos.shape == (40, 97, plan.n_points, 2)
    assert np.array_equal(a.valid, b.valid)
    close(a.acc, b.acc, "acc")


def test_uncovered_plan_falls_back_to_numpy():
    # a linear-actuator driver is not covered by the compiled kernels: same answer through numpy
    text = """
format = "assur/1"
[units]
length = "mm"
[points]
O = [0, 0]
C = [300, 0]
B = [200, 250]
[links]
frame = ["O", "C"]
boom = ["O", "B"]
[actuators.cyl]
between = ["C", "B"]
[[drivers]]
name = "cyl"
kind = "linear"
actuator = "cyl"
speed = "20 mm/s"
"""
    plan = assur.compile(assur.loads(text))
    q = np.linspace(0.2, 0.35, 5)
    a = assur.solve(plan, inputs=q, backend="numpy")
    b = assur.solve(plan, inputs=q, backend="numba")
    close(a.pos, b.pos, "pos")


def test_layouts_designs_by_inputs_and_per_sample():
    """Designs × inputs (separable) runs compiled; one design per sample (not separable) falls back
    to numpy: both give the numpy backend's numbers."""
    from assur.engine.planar.numba_backend import separable
    assert separable((40, 1), (97,), (40, 97)) == 1
    assert separable((), (97,), (97,)) == 0
    assert separable((97,), (97,), (97,)) is None
    plan = assur.compile(assur.loads(DOUBLE_ROCKER))
    rng = np.random.default_rng(5)
    params = np.tile(plan.defaults, (30, 1))
    params[:, plan.param_index("coupler.length")] *= rng.uniform(0.9, 1.3, 30)
    q = rng.uniform(0, 2 * np.pi, 30)
    a = assur.solve(plan, params, q, backend="numpy")
    b = assur.solve(plan, params, q, backend="numba")
    assert np.array_equal(a.valid, b.valid)
    close(a.pos, b.pos, "pos")
    close(a.acc, b.acc, "acc")


def test_the_kernel_key_carries_the_generator_digest_and_a_changed_generator_recompiles(tmp_path, monkeypatch):
    """numba's disk cache does not follow a callee's changes: every generated kernel's source (and so its file name
    and its numba cache) starts with the digest of the generator and the functions its kernels call
    (assur.kernels.codegen, .newton_codegen, .trace, .reductions), computed here independently from the files' bytes. A second
    process loads the cached kernel; after a change of the generator (its digest), the same source is a new kernel
    that numba compiles afresh: never the stale one."""
    import hashlib
    import sys
    from pathlib import Path

    from assur.kernels import codegen
    folder = Path(codegen.__file__).parent
    digest = hashlib.sha1(b"".join((folder / f).read_bytes()
                                   for f in ("codegen.py", "newton_codegen.py", "trace.py", "reductions.py",
                                             "similarity.py"))
                          ).hexdigest()[:16]
    assert codegen.generator_digest() == digest
    source = "from numba import njit\n\n\n@njit(cache=True)\ndef kernel(x):\n    return x + 1.0\n"

    def fresh_load():
        """The kernel as a new process loads it (no module of it imported yet)."""
        for name in [n for n in sys.modules if n.startswith("assur_kernel_")]:
            if Path(getattr(sys.modules[name], "__file__", "")).parent == tmp_path:
                del sys.modules[name]
        k = codegen.load_kernel(source, tmp_path)
        assert k(1.0) == 2.0
        return k, sum(k.stats.cache_hits.values()), sum(k.stats.cache_misses.values())

    k, hits, misses = fresh_load()
    assert (hits, misses) == (0, 1)                          # compiled and cached
    (written,) = tmp_path.glob("assur_kernel_*.py")
    assert written.read_text(encoding="utf-8").splitlines()[0].endswith(digest)
    assert written.name == ("assur_kernel_" + hashlib.sha1(written.read_text(encoding="utf-8").encode())
                            .hexdigest()[:16] + ".py")
    k, hits, misses = fresh_load()
    assert (hits, misses) == (1, 0)                          # the next process loads it from numba's cache
    monkeypatch.setattr(codegen, "_DIGEST", "0" * 16)         # the generator changed
    k, hits, misses = fresh_load()
    assert (hits, misses) == (0, 1)                          # a new kernel, compiled: not the stale one
    assert len(list(tmp_path.glob("assur_kernel_*.py"))) == 2


def test_the_kernels_are_traced_from_the_numpy_backends_closed_forms(monkeypatch):
    """One text per formula: a change to a closed form of assur.kernels.planar (here circle ∩ circle moved by a
    made-up offset) changes the numpy backend and the generated kernel alike. The kernel's source is run as plain
    Python (numba's decorator replaced by the identity), so nothing is compiled."""
    from assur.engine.planar import numba_backend
    from assur.kernels import planar
    plan = assur.compile(assur.loads(DOUBLE_ROCKER))
    q = np.linspace(0, 2 * np.pi, 13)
    base = assur.solve(plan, None, q, backend="numpy")
    original = planar.circle_circle

    def shifted(*args, **kwargs):
        z, ok = original(*args, **kwargs)
        return z + (0.25 - 0.5j), ok

    monkeypatch.setattr(planar, "circle_circle", shifted)
    ref = assur.solve(plan, None, q, backend="numpy")
    joint = plan.point_index(plan.steps_of("RRR")[0].joint)
    assert np.allclose(ref.pos[ref.valid, joint] - base.pos[base.valid, joint], [0.25, -0.5], atol=1e-12)
    source = numba_backend.solve_source(plan, False, 2)
    # numba's numpy error model (0.5/√0 is inf, not an exception): the kernel's math on numpy scalars
    from types import SimpleNamespace
    namespace: dict = {"math": SimpleNamespace(sqrt=np.sqrt, cos=np.cos, sin=np.sin, isfinite=np.isfinite,
                                               nan=np.nan, inf=np.inf)}
    exec(source.replace("import math\n", "").replace("from numba import njit", "njit = lambda **kw: (lambda f: f)"),
         namespace)
    n = len(plan.point_names)
    out, valid = np.full((6 * n, 1, q.size), np.nan), np.zeros((1, q.size), bool)
    with np.errstate(all="ignore"):
        namespace["kernel"](plan.defaults[None, :].copy(), np.cos(q), np.sin(q), 1e-12, 1.0, 1.0, 0.0, out, valid)
    assert np.array_equal(valid[0], ref.valid) and 0 < ref.valid.sum() < q.size
    rows = out[:, 0].reshape(n, 6, q.size)
    for j, attr in enumerate(("pos", "dpos_dq", "d2pos_dq2")):
        got = np.moveaxis(rows[:, 2 * j:2 * j + 2], -1, 0)[valid[0]]          # (assembled samples, points, 2)
        assert np.allclose(got, getattr(ref, attr)[ref.valid].reshape(got.shape), rtol=0, atol=1e-12), attr


CHAIN = """
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
C = [80, 0]
D = [62, 60]
A = [30, 0]
B = [62, 24]
E = [80, 42]
[links]
frame = ["O", "C", "D"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["C", "B"]
link = ["B", "E"]
hanger = ["D", "E"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
"""


def test_the_shortfall_of_a_chain_counts_every_group_past_its_toggle():
    """The synthesis's smooth buildability measure (path_objective's last column): Σ over the cycle and the groups of
    max(0, −(h² + tol)), h² the normalised radicand of circle ∩ circle, a group past its toggle continuing at it
    (the point on the line of centres), so that the group it feeds adds its own shortfall. Computed here
    independently for a crank, an RRR dyad B and an RRR dyad E hung from B: past the first dyad's toggle (the crank
    pulls A too far from C) B is off its circles and the second dyad fails too."""
    from assur.engine.planar.numba_backend import path_objective
    plan = assur.compile(assur.loads(CHAIN))
    q = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    tol = 1e-12
    r = path_objective(plan, plan.defaults[None, :], np.zeros((1, 0)), np.zeros((0, 2)), "E", q, tol)
    st = assur.solve(plan, None, q, backend="numpy", on_unbuildable="nan")
    crank, first = plan.steps_of("crank")[0], plan.steps_of("RRR")[0]    # θ = sense·q + zero; B's assembly
    A = 0.030 * np.exp(1j * (crank.sense * q + plan.defaults[crank.zero_param]))
    C, D = 0.080 + 0j, 0.062 + 0.060j
    ab, cb, be, de = 0.040, 0.030, abs(0.018 + 0.018j), abs(0.018 + 0.018j)

    def circles(c1, r1, c2, r2, branch=1):
        """(normalised radicand h², the point: on the circles where h² ≥ 0, else on the line of centres)"""
        d2 = abs(c2 - c1) ** 2
        a = (d2 + r1 * r1 - r2 * r2) / (2 * d2)
        h2 = r1 * r1 / d2 - a * a
        return h2, c1 + (c2 - c1) * (a + 1j * branch * np.sqrt(np.maximum(h2, 0.0)))

    assert (first.point_a, first.point_b) == ("C", "A")
    h1, B = circles(C, cb, A, ab, first.branch)
    h2, _ = circles(B, be, D, de)
    assert np.allclose(B[st.valid], st.pos[st.valid, plan.point_index("B"), 0]
                       + 1j * st.pos[st.valid, plan.point_index("B"), 1], atol=1e-15)
    shortfall = np.maximum(0.0, -(h1 + tol)) + np.maximum(0.0, -(h2 + tol))
    both = (h1 < -tol) & (h2 < -tol)
    assert both.sum() > 20 and (h1 >= -tol).sum() > 20                     # the case the test is about occurs
    assert r[0, 3] == np.count_nonzero(~st.valid) == np.count_nonzero((h1 < -tol) | (h2 < -tol))
    assert np.isclose(r[0, 4], shortfall.sum(), rtol=1e-10)
    assert np.maximum(0.0, -(h2 + tol))[both].sum() > 0.1 * shortfall.sum()
