"""The triad certificate without roots, compiled (assur.kernels.reductions.triad_alone) and on numpy
(assur.kernels.triad.triad_alone): its lower bound on the distance to the triad's other assemblies holds against a
brute force written here, the two agree, and the certificates it gates give the verdicts of the ones from every root:
the compiled triad_check those of triad_check_roots on random triads, predictions and separations, the numpy
backend's continuation the same samples and numbers as with the roots alone on perturbed triad six-bars."""
import math
from pathlib import Path

import numpy as np
import pytest

import assur

ROOT = Path(__file__).resolve().parents[1]


def random_triad(rng):
    """TA (34,) of triad_check for a random triad solved at a random pose: the ternary's three points w, its pose
    (x, y, θ), three known points Q and the legs' lengths |P_k − Q_k| (so the pose is an exact assembly)."""
    w = rng.uniform(-1.0, 1.0, 3) + 1j * rng.uniform(-1.0, 1.0, 3)
    x, y, th = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-math.pi, math.pi)
    P = x + 1j * y + np.exp(1j * th) * w
    Q = P + rng.uniform(0.3, 2.0, 3) * np.exp(1j * rng.uniform(-math.pi, math.pi, 3))
    TA = np.zeros(34)
    TA[0:6] = np.column_stack([w.real, w.imag]).ravel()
    TA[6:12] = np.column_stack([Q.real, Q.imag]).ravel()
    TA[12:15] = np.abs(P - Q)
    TA[15:18] = x, y, th
    TA[18:21] = x, y, th
    TA[21] = 2.0
    return TA, w, Q, np.abs(P - Q)


def brute_force_assemblies(w, Q, ell, n=200_000):
    """(k, 3) complex joints of every assembly of the triad whose orientation is a sign change of G on a grid of n
    orientations, refined by bisection: for a trial orientation e the two differences of the legs' equations fix the
    origin p (a 2×2 linear solve), and G is the first leg's equation there."""
    def G(phi):
        e = np.exp(1j * phi)[:, None]
        v = e * w[None, :] - Q[None, :]                       # P_k − Q_k = p + v_k
        # |p + v_k|² − |p + v_1|² = ell_k² − ell_1²: 2·Re(p̄·(v_k − v_1)) = ell_k² − ell_1² − |v_k|² + |v_1|²
        A = np.stack([np.stack([2 * (v[:, k] - v[:, 0]).real, 2 * (v[:, k] - v[:, 0]).imag], -1) for k in (1, 2)], -2)
        b = np.stack([ell[k] ** 2 - ell[0] ** 2 - abs(v[:, k]) ** 2 + abs(v[:, 0]) ** 2 for k in (1, 2)], -1)
        sol = np.linalg.solve(A, b[..., None])[..., 0]
        p = sol[:, 0] + 1j * sol[:, 1]
        return abs(p + v[:, 0]) ** 2 - ell[0] ** 2, p
    phi = np.linspace(0.0, 2 * math.pi, n + 1)
    g, _ = G(phi)
    out = []
    for i in np.flatnonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0):
        a, b = phi[i], phi[i + 1]
        ga = g[i]
        for _ in range(60):
            mid = 0.5 * (a + b)
            gm = G(np.array([mid]))[0][0]
            if np.sign(gm) == np.sign(ga):
                a, ga = mid, gm
            else:
                b = mid
        ph = 0.5 * (a + b)
        p = G(np.array([ph]))[1][0]
        out.append(p + np.exp(1j * ph) * w)
    return np.array(out)


def test_the_bound_holds_against_a_brute_force():
    pytest.importorskip("numba")
    from assur.kernels.reductions import _triad_coefficients, triad_alone
    rng = np.random.default_rng(7)
    proven = 0
    for _ in range(60):
        TA, w, Q, ell = random_triad(rng)
        TS = np.zeros(22, dtype=complex)
        _triad_coefficients(TA, TS)
        bound = triad_alone(TA, TS, math.pi)
        assert bound >= 0.0
        joints = brute_force_assemblies(w, Q, ell)
        x, y, th = TA[15:18]
        own = x + 1j * y + np.exp(1j * th) * w
        d = np.max(abs(joints - own[None, :]), axis=1)          # each assembly's distance: its farthest joint
        assert d.min() < 1e-6                                    # the pose itself is found
        others = np.sort(d)[1:]
        if bound > 0:
            proven += 1
            assert others.size == 0 or bound <= others.min() * (1 + 1e-9), (bound, others)
    assert proven >= 50                                          # the bound proves something on most triads


def test_the_gated_check_gives_the_verdicts_from_every_root():
    pytest.importorskip("numba")
    from assur.kernels.reductions import _triad_coefficients, triad_alone, triad_check, triad_check_roots
    rng = np.random.default_rng(11)
    gated = 0
    for _ in range(400):
        TA, *_ = random_triad(rng)
        # a prediction off the pose, from nothing to far; a separation from nothing to the triad's size
        TA[18:21] = TA[15:18] + rng.standard_normal(3) * 10.0 ** rng.uniform(-8, 0)
        sep = 10.0 ** rng.uniform(-6, 0.5)
        TS = np.zeros(22, dtype=complex)
        got = triad_check(TA.copy(), TS, np.zeros(7, dtype=complex), sep)
        TS2 = np.zeros(22, dtype=complex)
        _triad_coefficients(TA, TS2)
        gated += triad_alone(TA, TS2, math.pi) > sep
        want = triad_check_roots(TA.copy(), TS2, np.zeros(7, dtype=complex), sep)
        assert got == want
    assert gated >= 100                                          # the gate decides a good share of them


def test_the_numpy_bound_holds_against_a_brute_force():
    from assur.kernels.triad import triad_alone, triad_polynomial
    rng = np.random.default_rng(7)
    proven = 0
    for _ in range(60):
        TA, w, Q, ell = random_triad(rng)
        coeff, _ = triad_polynomial(w, Q, ell)
        bound = float(triad_alone(coeff, TA[17], w))
        assert bound >= 0.0
        joints = brute_force_assemblies(w, Q, ell)
        own = TA[15] + 1j * TA[16] + np.exp(1j * TA[17]) * w
        d = np.sort(np.max(abs(joints - own[None, :]), axis=1))
        assert d[0] < 1e-6
        if bound > 0:
            proven += 1
            assert d.size == 1 or bound <= d[1] * (1 + 1e-9), (bound, d)
    assert proven >= 50


def test_the_numpy_bound_is_the_compiled_one():
    """The batched numpy twin against the compiled bound, sample by sample, over random triads and reaches."""
    pytest.importorskip("numba")
    from assur.kernels import reductions, triad
    rng = np.random.default_rng(5)
    rows = [random_triad(rng) for _ in range(300)]
    w = np.array([r[1] for r in rows])
    Q = np.array([r[2] for r in rows])
    ell = np.array([r[3] for r in rows])
    theta = np.array([r[0][17] for r in rows])
    reach = 10.0 ** rng.uniform(-3, 0.6, len(rows))
    coeff, _ = triad.triad_polynomial(w, Q, ell)
    got = triad.turn_alone(coeff, theta, reach)
    want = []
    for i, (TA, *_) in enumerate(rows):
        TS = np.zeros(22, dtype=complex)
        reductions._triad_coefficients(TA, TS)
        want.append(reductions._turn_alone(TS, complex(math.cos(theta[i]), math.sin(theta[i])), reach[i]))
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)
    assert np.count_nonzero(got) >= 250


def test_the_numpy_continuation_certifies_as_the_roots_alone(monkeypatch):
    """The numpy backend's step and sample certificates of a triad with the bound and with the roots deciding every
    sample (the bound replaced by 0, which proves nothing): the same valid samples and the same numbers, bit for bit,
    on the triad six-bar and on designs perturbed by up to 15 % per parameter (some of which lock or pass near
    another assembly). On the file's design, which turns fully, the bound decides every check: no root is found."""
    from assur.engine.planar import continuation
    plan = assur.compile(assur.load(ROOT / "examples" / "triad_sixbar.toml"))
    rng = np.random.default_rng(2)
    P = plan.defaults * (1 + 0.15 * rng.uniform(-1, 1, (6, plan.n_params)))
    q = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)
    real_roots = continuation._root_joints
    rooted = []                                        # rows whose roots were found, per solve

    def counted(w, Q, ell):
        rooted[-1] += len(w)
        return real_roots(w, Q, ell)

    def solve(*args, **kw):
        rooted.append(0)
        return assur.solve(plan, *args, order=1, backend="numpy", **kw)

    monkeypatch.setattr(continuation, "_root_joints", counted)
    runs = []
    for gate in (True, False):
        if not gate:
            monkeypatch.setattr(continuation, "_alone", lambda w, Q, ell, theta: np.zeros(len(theta)))
        runs.append([solve(inputs=q[:, None]), solve(P[:, None, :], inputs=q[None, :, None]),
                     solve(P[2], inputs=q[:, None], sweep=True)])
    for gated, roots in zip(*runs):
        np.testing.assert_array_equal(gated.valid, roots.valid)
        np.testing.assert_array_equal(gated.pos, roots.pos)
        np.testing.assert_array_equal(gated.vel, roots.vel)
    assert runs[0][0].valid.all() and not runs[0][1].valid.all()   # the file's design turns; a perturbed one not
    assert rooted[0] == 0 and rooted[3] > 0
    assert sum(rooted[:3]) < 0.7 * sum(rooted[3:])
