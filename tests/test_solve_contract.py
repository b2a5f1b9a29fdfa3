"""Layer L2: the contract of ``assur.solve`` — shapes, broadcasting, NaN/valid, the unbuildable
policy, the fixed assembly branch, structure errors and time derivatives.
"""
from __future__ import annotations

import math
import pickle
import re
import warnings

import numpy as np
import pytest

import assur

# A Grashof crank-rocker (s + l = 0.3 + 1.0 ≤ p + q = 1.0 + 0.8): O = 0, O1 = 1, crank 0.3, coupler 1.0,
# rocker 0.8; the sketch is at crank angle 0.6 rad with B on the left of A → O1.
Q0 = 0.6
A0 = 0.3 * complex(math.cos(Q0), math.sin(Q0))


def _cc(c1, r1, c2, r2, left=True):
    """Circle-circle intersection (textbook formula), left of c1 → c2."""
    d = abs(c2 - c1)
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = math.sqrt(r1 * r1 - a * a)
    u = (c2 - c1) / d
    return c1 + u * (a + (1j if left else -1j) * h)


B0 = _cc(A0, 1.0, 1 + 0j, 0.8)
FOURBAR = f"""
format = "assur/1"
[units]
length = "m"
angle = "rad"
[points]
O = [0.0, 0.0]
O1 = [1.0, 0.0]
A = [{A0.real!r}, {A0.imag!r}]
B = [{B0.real!r}, {B0.imag!r}]
[links]
frame = ["O", "O1"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["O1", "B"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
speed = "30 rpm"
"""
OMEGA = 30 * 2 * math.pi / 60          # 30 rpm in rad/s

# A five-bar with two cranks (W = 2): O1 = 0, O2 = 1, cranks 0.3 and 0.4, couplers 0.8 and 0.7.
QA, QB = 1.0, 2.0
FA = 0.3 * complex(math.cos(QA), math.sin(QA))
FB = 1 + 0.4 * complex(math.cos(QB), math.sin(QB))
FC = _cc(FA, 0.8, FB, 0.7)
FIVEBAR = f"""
format = "assur/1"
[units]
length = "m"
angle = "rad"
[points]
O1 = [0.0, 0.0]
O2 = [1.0, 0.0]
A = [{FA.real!r}, {FA.imag!r}]
B = [{FB.real!r}, {FB.imag!r}]
C = [{FC.real!r}, {FC.imag!r}]
[links]
frame = ["O1", "O2"]
crank1 = ["O1", "A"]
crank2 = ["O2", "B"]
left = ["A", "C"]
right = ["B", "C"]
[[drivers]]
name = "crank1"
link = "crank1"
pivot = "O1"
arm = "A"
speed = 2.0
[[drivers]]
name = "crank2"
link = "crank2"
pivot = "O2"
arm = "B"
speed = -1.5
"""


@pytest.fixture(scope="module")
def fourbar():
    return assur.compile(assur.loads(FOURBAR))


@pytest.fixture(scope="module")
def fivebar():
    return assur.compile(assur.loads(FIVEBAR))


def designs(plan, n, seed=0, rel=0.03):
    rng = np.random.default_rng(seed)
    P = np.tile(plan.defaults, (n, 1))
    for i, name in enumerate(plan.param_names):
        if name.endswith(".length"):
            P[:, i] *= 1 + rel * rng.standard_normal(n)
    return P


def zc(a):
    """(..., 2) → complex."""
    return a[..., 0] + 1j * a[..., 1]


# -- shapes -------------------------------------------------------------------------------------------------------
def test_design_by_input_batch_shapes(fourbar):
    D, N = 4, 7
    P = designs(fourbar, D)[:, None, :]                    # (D, 1, P)
    q = np.linspace(0, 2 * np.pi, N)                       # (N,)
    s = assur.solve(fourbar, P, q)
    n_p, n_b = fourbar.n_points, len(fourbar.body_names)
    assert s.shape == (D, N) and s.valid.shape == (D, N) and s.valid.dtype == bool
    assert s.pos.shape == (D, N, n_p, 2)
    assert s.vel.shape == (D, N, n_p, 2) and s.acc.shape == (D, N, n_p, 2)
    assert s.dpos_dq.shape == (D, N, n_p, 2, 1)
    assert s.d2pos_dq2.shape == (D, N, n_p, 2, 1, 1)
    assert s.body_angle.shape == s.body_omega.shape == s.body_alpha.shape == (D, N, n_b)
    assert s.inputs.shape == (D, N, 1)
    assert s.point("B").pos.shape == (D, N, 2) and s.point("B").dpos_dq.shape == (D, N, 2, 1)


def test_two_input_batch_shapes(fivebar):
    D, N = 3, 5
    P = designs(fivebar, D)[:, None, :]
    q = np.array([QA, QB]) + np.linspace(-0.2, 0.2, N)[:, None]      # (N, 2)
    s = assur.solve(fivebar, P, q)
    n_p = fivebar.n_points
    assert s.pos.shape == (D, N, n_p, 2)
    assert s.dpos_dq.shape == (D, N, n_p, 2, 2)
    assert s.d2pos_dq2.shape == (D, N, n_p, 2, 2, 2)
    assert s.vel.shape == s.acc.shape == (D, N, n_p, 2)


def test_order_controls_which_derivatives_exist(fourbar):
    q = np.linspace(0, 1, 3)
    s0, s1 = assur.solve(fourbar, inputs=q, order=0), assur.solve(fourbar, inputs=q, order=1)
    assert s0.dpos_dq is None and s0.vel is None and s0.d2pos_dq2 is None and s0.acc is None
    assert s1.dpos_dq is not None and s1.vel is not None and s1.d2pos_dq2 is None and s1.acc is None
    s2 = assur.solve(fourbar, inputs=q)
    np.testing.assert_array_equal(s0.pos, s2.pos)
    np.testing.assert_array_equal(s1.dpos_dq, s2.dpos_dq)


def test_bad_arguments_raise_spec_errors(fourbar):
    with pytest.raises(assur.SpecError, match=r"^params: must have a trailing axis of 8 parameters"):
        assur.solve(fourbar, np.zeros(3), 0.0)
    with pytest.raises(assur.SpecError, match=r"on_unbuildable: must be one of nan, warn, raise: 'ignore'"):
        assur.solve(fourbar, inputs=0.0, on_unbuildable="ignore")
    with pytest.raises(assur.SpecError, match=r"method: must be 'closed' or 'newton': 'exact'"):
        assur.solve(fourbar, inputs=0.0, method="exact")
    with pytest.raises(assur.SpecError, match=r"order: must be 0, 1 or 2: 3"):
        assur.solve(fourbar, inputs=0.0, order=3)


@pytest.mark.parametrize("method", ["closed", "newton"])
def test_batched_equals_looped(fourbar, method):
    P = designs(fourbar, 3, seed=1)
    q = np.linspace(0.2, 1.2, 4)
    s = assur.solve(fourbar, P[:, None, :], q, method=method)
    for d in range(3):
        for n in range(4):
            one = assur.solve(fourbar, P[d], q[n], method=method)
            assert one.shape == ()
            np.testing.assert_allclose(one.pos, s.pos[d, n], rtol=0, atol=1e-13)
            np.testing.assert_allclose(one.dpos_dq, s.dpos_dq[d, n], rtol=0, atol=1e-13)
            np.testing.assert_allclose(one.d2pos_dq2, s.d2pos_dq2[d, n], rtol=0, atol=1e-12)
            assert bool(one.valid) == bool(s.valid[d, n])


# -- unbuildable samples --------------------------------------------------------------------------------------------
# With the crank lengthened to 0.9 the four-bar is no longer a crank-rocker: B exists only while
# |b − c| ≤ |O1 − A(q)| ≤ b + c (triangle inequality on coupler b = 1.0 and rocker c = 0.8).
Q_TURN = np.linspace(0, 2 * np.pi, 37)[:-1] + 0.01


def long_crank(plan):
    return plan.params_with(crank__length=0.9)


def expected_valid(q):
    d = np.abs(1.0 - 0.9 * np.exp(1j * q))
    return (d >= 0.2) & (d <= 1.8)


def test_unbuildable_samples_are_nan_and_invalid(fourbar):
    s = assur.solve(fourbar, long_crank(fourbar), Q_TURN)
    want = expected_valid(Q_TURN)
    assert 0 < want.sum() < want.size
    np.testing.assert_array_equal(s.valid, want)
    assert s.n_unbuildable == np.count_nonzero(~want)
    for arr in (s.pos, s.vel, s.acc, s.dpos_dq, s.d2pos_dq2, s.body_angle, s.body_omega):
        assert np.all(np.isnan(arr[~want])), "unbuildable samples must be NaN in every coordinate"
        assert np.all(np.isfinite(arr[want]))


def test_unbuildable_policy_nan_is_silent(fourbar):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = assur.solve(fourbar, long_crank(fourbar), Q_TURN, on_unbuildable="nan")
    assert s.n_unbuildable > 0


@pytest.mark.parametrize("backend", ["numpy", "numba"])
@pytest.mark.parametrize("sweep", [False, True])
@pytest.mark.parametrize("example", ["walker_fourbar.toml", "triad_sixbar.toml"])
def test_a_non_finite_input_is_an_unassembled_sample_without_warnings(example, backend, sweep):
    """inf, −inf and NaN inputs (a dyad four-bar, a triad six-bar; numpy and the compiled kernels, swept or not):
    those samples are invalid and NaN, the others as solved alone, and numpy warns of nothing."""
    pytest.importorskip("numba") if backend == "numba" else None
    from conftest import EXAMPLES
    plan = assur.compile(assur.load(EXAMPLES / example))
    q = np.array([0.1, np.inf, 0.2, -np.inf, np.nan, 0.3])
    finite = np.isfinite(q)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = assur.solve(plan, inputs=q, backend=backend, sweep=sweep)
    np.testing.assert_array_equal(s.valid, finite)
    assert np.all(np.isnan(s.pos[~finite])) and np.all(np.isnan(s.acc[~finite]))
    alone = assur.solve(plan, inputs=q[finite], backend=backend)
    np.testing.assert_allclose(s.pos[finite], alone.pos, rtol=0, atol=1e-9 * plan.length_scale)


def test_unbuildable_policy_warn(fourbar):
    k = int(np.count_nonzero(~expected_valid(Q_TURN)))
    with pytest.warns(assur.UnbuildableWarning, match=rf"^{k} of {Q_TURN.size} samples cannot be assembled"):
        s = assur.solve(fourbar, long_crank(fourbar), Q_TURN, on_unbuildable="warn")
    assert s.n_unbuildable == k


def test_unbuildable_policy_raise(fourbar):
    k = int(np.count_nonzero(~expected_valid(Q_TURN)))
    with pytest.raises(assur.UnbuildableError) as info:
        assur.solve(fourbar, long_crank(fourbar), Q_TURN, on_unbuildable="raise")
    e = info.value
    assert isinstance(e, ArithmeticError) and isinstance(e, assur.AssurError)
    assert (e.count, e.total) == (k, Q_TURN.size)
    first = np.degrees(Q_TURN[~expected_valid(Q_TURN)][0])
    assert str(e) == (f"{k} of {Q_TURN.size} samples cannot be assembled (first at crank={first:.6g}°); "
                      f"they are NaN with valid=False")
    e2 = pickle.loads(pickle.dumps(e))
    assert type(e2) is assur.UnbuildableError and str(e2) == str(e) and (e2.count, e2.total) == (k, Q_TURN.size)


def test_buildable_range_does_not_warn_or_raise(fourbar):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = assur.solve(fourbar, inputs=Q_TURN, on_unbuildable="raise")
    assert s.n_unbuildable == 0 and np.all(s.valid)


# -- the assembly branch never switches ------------------------------------------------------------------------------
def _side_of_B(s):
    A, B, O1 = zc(s.point("A").pos), zc(s.point("B").pos), zc(s.point("O1").pos)
    return np.sign(np.imag(np.conj(O1 - A) * (B - A)))


@pytest.mark.parametrize("method", ["closed", "newton"])
def test_branch_is_fixed_over_many_turns_and_any_order(fourbar, method):
    base = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    turns = np.concatenate([base + 2 * np.pi * k for k in range(-1, 3)])   # four turns
    perm = np.random.default_rng(5).permutation(turns.size)
    s = assur.solve(fourbar, inputs=turns, method=method)
    sh = assur.solve(fourbar, inputs=turns[perm], method=method)
    assert np.all(s.valid) and np.all(sh.valid)
    # shuffled order gives the same point for the same angle (no "nearest previous" dependency)
    np.testing.assert_allclose(sh.pos, s.pos[perm], rtol=0, atol=1e-12)
    # the same angle one turn later gives the same assembly
    pos = s.pos.reshape(4, 24, -1, 2)
    for k in range(1, 4):
        np.testing.assert_allclose(pos[k], pos[0], rtol=0, atol=1e-11)
    # and B stays on the sketch's side (left) of A → O1 all the way round
    assert np.all(_side_of_B(s) == 1)


def test_branch_hint_flips_the_assembly(fourbar):
    q = np.linspace(0, 2 * np.pi, 19)
    hinted = assur.compile(assur.loads(FOURBAR + '[branches]\nB = { side = "right", of = ["A", "O1"] }\n'))
    same = assur.compile(assur.loads(FOURBAR + '[branches]\nB = { side = "left", of = ["A", "O1"] }\n'))
    s, h, k = (assur.solve(p, inputs=q) for p in (fourbar, hinted, same))
    assert np.all(_side_of_B(h) == -1)
    # the flipped B is the mirror image of the default B across the line A → O1 (independent reflection)
    A, B, O1 = zc(s.point("A").pos), zc(s.point("B").pos), zc(s.point("O1").pos)
    mirror = A + (O1 - A) * np.conj((B - A) / (O1 - A))
    np.testing.assert_allclose(zc(h.point("B").pos), mirror, rtol=0, atol=1e-12)
    # a hint that agrees with the sketch changes nothing
    np.testing.assert_array_equal(k.pos, s.pos)
    assert list(same.branch_signs) == list(fourbar.branch_signs) != list(hinted.branch_signs)


def test_branch_hint_on_an_unbranched_point_is_an_error():
    with pytest.raises(assur.SpecError) as info:
        assur.compile(assur.loads(FOURBAR + '[branches]\nA = { side = "right", of = ["B", "O1"] }\n'))
    assert str(info.value) == "branches.A: 'A' is not the point a branched group solves (branched points: B)"


COLLINEAR = """
format = "assur/1"
[units]
length = "m"
angle = "rad"
[points]
O = [0.0, 0.0]
O1 = [1.0, 0.0]
A = [0.3, 0.0]
B = [{bx}, {by}]
[links]
frame = ["O", "O1"]
crank = ["O", "A"]
rocker = ["O1", "B"]
[links.coupler]
points = ["A", "B"]
{length}
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
"""


def test_a_sketch_that_does_not_tell_the_branch_is_an_error():
    # B on the line A–O1 beyond O1 (coupler 1.2 = |A − O1| + rocker 0.5): the circles about A and O1 touch,
    # both assemblies coincide
    with pytest.raises(assur.SpecError) as info:
        assur.compile(assur.loads(COLLINEAR.format(bx=1.5, by=0.0, length="")))
    assert str(info.value) == ("points.B: the sketch does not tell the assembly branch of 'B' (both branches "
                               "coincide); move it off the line or set [branches.B]")


def test_a_hint_settles_a_collinear_sketch():
    plan = assur.compile(assur.loads(COLLINEAR.format(bx=1.5, by=0.0, length="")
                                     + '[branches]\nB = { side = "left", of = ["A", "O1"] }\n'))
    s = assur.solve(plan, inputs=0.5)
    assert np.all(_side_of_B(s) == 1)


def test_a_sketch_that_cannot_be_assembled_is_an_error():
    # coupler 5 m: |A − O1| + rocker = 0.7 + 0.63 < 5, no assembly at the sketch input (triangle inequality)
    with pytest.raises(assur.SpecError) as info:
        assur.compile(assur.loads(COLLINEAR.format(bx=0.6, by=0.2, length="length = 5.0")))
    assert str(info.value) == ("points.B: the group solving 'B' cannot be assembled in the sketch position "
                               "(check the dimensions and the sketch)")


# -- structure errors ------------------------------------------------------------------------------------------------
def _drivers_removed(text, keep):
    head, *drivers = text.split("[[drivers]]")
    return head + "".join("[[drivers]]" + d for d in drivers[:keep])


@pytest.mark.parametrize("text, keep, W, counts, names", [
    (FOURBAR, 0, 1, "3·3 − 2·4", "none"),           # W = 3n − 2p5 = 9 − 8 = 1 (Chebyshev)
    (FIVEBAR, 1, 2, "3·4 − 2·5", "crank1"),         # W = 12 − 10 = 2
])
def test_mobility_not_equal_to_drivers_is_a_structure_error(text, keep, W, counts, names):
    m = assur.loads(_drivers_removed(text, keep))
    with pytest.raises(assur.StructureError) as info:
        assur.compile(m)
    msg = str(info.value)
    assert f"W = {counts} = {W}" in msg
    assert f"{keep} driver(s) are given ({names})" in msg
    assert isinstance(info.value, ValueError)


def test_too_many_drivers_is_a_structure_error():
    extra = '[[drivers]]\nname = "rocker"\nlink = "rocker"\npivot = "O1"\narm = "B"\n'
    with pytest.raises(assur.StructureError, match=re.escape("W = 3·3 − 2·4 = 1 but 2 driver(s) are given (crank, rocker)")):
        assur.compile(assur.loads(FOURBAR + extra))


# -- time derivatives ------------------------------------------------------------------------------------------------
def test_velocity_and_acceleration_at_constant_speed(fourbar):
    q = np.linspace(0, 2 * np.pi, 13)
    s = assur.solve(fourbar, inputs=q)
    np.testing.assert_allclose(fourbar.speeds, [OMEGA], rtol=1e-15)        # "30 rpm" = π rad/s
    np.testing.assert_allclose(s.vel, OMEGA * s.dpos_dq[..., 0], rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(s.acc, OMEGA**2 * s.d2pos_dq2[..., 0, 0], rtol=1e-14, atol=1e-15)
    # the body rates follow the same rule; the crank turns at the driver speed with no angular acceleration
    ci = fourbar.body_names.index("crank")
    np.testing.assert_allclose(s.body_omega[:, ci], OMEGA, rtol=1e-14)
    np.testing.assert_allclose(s.body_alpha[:, ci], 0.0, atol=1e-12)
    # A moves on a circle: |v_A| = ω·r, a_A = −ω²·(A − O) (centripetal)
    np.testing.assert_allclose(np.linalg.norm(s.point("A").vel, axis=-1), OMEGA * 0.3, rtol=1e-13)
    np.testing.assert_allclose(s.point("A").acc, -OMEGA**2 * s.point("A").pos, rtol=0, atol=1e-13)


def test_speed_and_acceleration_overrides(fourbar):
    q = np.linspace(0, 2 * np.pi, 13)
    w, alpha = -2.5, 4.0
    base = assur.solve(fourbar, inputs=q)
    s = assur.solve(fourbar, inputs=q, speeds=[w], accels=[alpha])
    np.testing.assert_allclose(s.vel, w * base.dpos_dq[..., 0], rtol=1e-14, atol=1e-15)
    np.testing.assert_allclose(s.acc, w**2 * base.d2pos_dq2[..., 0, 0] + alpha * base.dpos_dq[..., 0],
                               rtol=1e-13, atol=1e-14)
    # a per-sample speed broadcasts against the batch
    ws = np.linspace(-1, 1, 13)[:, None]
    sv = assur.solve(fourbar, inputs=q, speeds=ws)
    np.testing.assert_allclose(sv.vel, ws[:, :, None] * base.dpos_dq[..., 0], rtol=1e-14, atol=1e-15)


def _time_path(q0, qdot, qddot, t):
    return q0 + qdot * t[:, None] + 0.5 * qddot * t[:, None] ** 2


def test_two_inputs_vel_is_jacobian_times_rates_and_acc_matches_differences(fivebar):
    q0 = np.array([QA, QB]) + np.array([0.05, -0.1])
    qdot, qddot = np.array([1.3, -0.7]), np.array([0.4, 2.0])
    s = assur.solve(fivebar, inputs=q0[None, :], speeds=qdot, accels=qddot)
    Jac = s.dpos_dq[0]                                                      # (n_points, 2, 2)
    np.testing.assert_allclose(s.vel[0], Jac @ qdot, rtol=1e-14, atol=1e-15)
    # the default speeds are the file's (2 rad/s and −1.5 rad/s)
    np.testing.assert_allclose(assur.solve(fivebar, inputs=q0[None, :]).vel[0], Jac @ np.array([2.0, -1.5]),
                               rtol=1e-14, atol=1e-15)
    # along q(t) = q0 + q̇ t + ½ q̈ t²: central differences (Richardson) of the positions in t
    h = 1e-3
    t = np.array([-h, -h / 2, 0.0, h / 2, h])
    p = assur.solve(fivebar, inputs=_time_path(q0, qdot, qddot, t), order=0).pos
    v_fd = (4 * (p[3] - p[1]) / h - (p[4] - p[0]) / (2 * h)) / 3
    a_fd = (4 * (p[3] - 2 * p[2] + p[1]) / (h / 2) ** 2 - (p[4] - 2 * p[2] + p[0]) / h**2) / 3
    np.testing.assert_allclose(s.vel[0], v_fd, rtol=0, atol=1e-9)
    np.testing.assert_allclose(s.acc[0], a_fd, rtol=0, atol=1e-6)
    # the mixed second analogues are symmetric and equal differences of dpos_dq
    d2 = s.d2pos_dq2[0]
    np.testing.assert_allclose(d2[..., 0, 1], d2[..., 1, 0], rtol=0, atol=1e-14)
    e1 = np.array([0.0, 1.0])
    dp = assur.solve(fivebar, inputs=np.stack([q0 + h * e1, q0 - h * e1])).dpos_dq
    np.testing.assert_allclose(d2[..., :, 1], (dp[0] - dp[1]) / (2 * h), rtol=0, atol=1e-6)
    # C depends on both cranks; A only on the first, B only on the second
    iA, iB = fivebar.point_index("A"), fivebar.point_index("B")
    np.testing.assert_array_equal(Jac[iA, :, 1], 0.0)
    np.testing.assert_array_equal(Jac[iB, :, 0], 0.0)
