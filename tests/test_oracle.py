"""Layer L2: differential tests of the closed-form dyad solvers.

For one mechanism of every dyad kind (written as TOML text, sketch computed here by plain
geometry) and 50 random designs around it (batched in one solve call with a leading design
axis), the closed forms must equal the batched Newton oracle (``method="newton"``) in positions
and in the analogues dpos_dq, d2pos_dq2; the decomposition must find the expected group kinds;
the solved positions must satisfy every constraint of the description (link lengths, placements,
slide lines, driver angles, actuator lengths), checked here from the file's meaning; and
velocities and accelerations must equal central differences of positions (and of dpos_dq).
"""
from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

import assur
from assur import GroupKind

RNG_SEED = 20260601
N_DESIGNS = 50


# -- sketch geometry (independent of the engine: textbook formulas) ------------------------------------------
def circle_circle(c1, r1, c2, r2, left=True):
    """Intersection of two circles; `left`: to the left of the directed line c1 → c2."""
    d = abs(c2 - c1)
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = math.sqrt(r1 * r1 - a * a)
    u = (c2 - c1) / d
    return c1 + u * (a + (1j * h if left else -1j * h))


def line_line(q1, u1, q2, u2):
    """Intersection of q1 + t·u1 and q2 + s·u2 (Cramer's rule)."""
    den = (u1.conjugate() * u2).imag
    t = ((q2 - q1).conjugate() * u2).imag / den
    return q1 + t * u1


def xy(z) -> str:
    return f"[{z.real!r}, {z.imag!r}]"


HEAD = 'format = "assur/1"\n[units]\nlength = "m"\nangle = "rad"\n'


def crank_driver(pivot="O", arm="A", link="crank", speed="30 rpm", sense="ccw", zero=0.0):
    return (f'[[drivers]]\nname = "{link}"\nkind = "rotary"\nlink = "{link}"\npivot = "{pivot}"\narm = "{arm}"\n'
            f'speed = "{speed}"\nsense = "{sense}"\nzero = {zero!r}\n')


def fourbar_points(q0=0.6, a=0.3, b=1.0, c=0.8, d=1.0):
    A = a * cmath.exp(1j * q0)
    B = circle_circle(A, b, d + 0j, c, left=True)
    P = A + (B - A) * (0.4 + 0.3j)                        # a coupler point
    return A, B, P


def m_fourbar(hint=""):
    A, B, P = fourbar_points()
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nO1 = [1.0, 0.0]\nA = {xy(A)}\nB = {xy(B)}\nP = {xy(P)}\n"
            '[links]\nframe = ["O", "O1"]\ncrank = ["O", "A"]\ncoupler = ["A", "B", "P"]\nrocker = ["O1", "B"]\n'
            + crank_driver() + hint)


def m_slider():
    # offset slider-crank: crank 0.3, rod 0.9, the pin B slides on the line y = 0.1 (offset to the left of +x)
    A = 0.3 * cmath.exp(0.8j)
    e = 0.1
    B = complex(A.real + math.sqrt(0.9**2 - (e - A.imag) ** 2), e)
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nA = {xy(A)}\nB = {xy(B)}\n"
            '[links]\nframe = ["O"]\ncrank = ["O", "A"]\nrod = ["A", "B"]\n'
            '[[prismatic]]\nname = "slide"\npoint = "B"\nguide = "frame"\nthrough = "O"\nangle = 0.0\noffset = 0.1\n'
            + crank_driver(sense="cw", zero=1.0))          # q = 1 − 0.8 at the sketch, turning clockwise


def m_slotted_crank():
    # RRP on a moving guide: a rod hinged to the frame at F whose end B slides in a slot along the crank
    u = cmath.exp(0.9j)
    F = 0.5 + 0j
    p = (u.conjugate() * F).real
    t = p + math.sqrt(p * p - abs(F) ** 2 + 0.8**2)
    B = t * u
    A = 0.3 * u
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nF = [0.5, 0.0]\nA = {xy(A)}\nB = {xy(B)}\n"
            '[links]\nframe = ["O", "F"]\ncrank = ["O", "A"]\nrod = ["F", "B"]\n'
            '[[prismatic]]\nname = "slot"\npoint = "B"\nguide = "crank"\nthrough = "O"\nangle = 0.0\n'
            + crank_driver())


def m_whitworth():
    # slotted lever: the crank pin C slides in a slot of a rocker pivoted on the frame at O2
    O2 = -0.5j
    C = 0.2 * cmath.exp(0.5j)
    R = O2 + 1.5 * (C - O2) / abs(C - O2)
    return (HEAD + f"[points]\nO1 = [0.0, 0.0]\nO2 = {xy(O2)}\nC = {xy(C)}\nR = {xy(R)}\n"
            '[links]\nframe = ["O1", "O2"]\ncrank = ["O1", "C"]\nrocker = ["O2", "R"]\n'
            '[[prismatic]]\nname = "slot"\npoint = "C"\nguide = "rocker"\nthrough = "O2"\nangle = 0.0\n'
            + crank_driver(pivot="O1", arm="C"))


def m_cylinder(hint=""):
    # a passive hydraulic cylinder hinged to the frame at F and to the crank at A (its length follows)
    A = 0.4 * cmath.exp(0.3j)
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nF = [1.0, -0.3]\nA = {xy(A)}\n"
            '[links]\nframe = ["O", "F"]\ncrank = ["O", "A"]\n[actuators.cyl]\nbetween = ["F", "A"]\n'
            + crank_driver() + hint)


def m_yoke():
    # Scotch yoke: the crank pin A slides in a vertical slot of a yoke that translates along the x axis
    A = 0.3 * cmath.exp(0.7j)
    Y1 = complex(A.real, 0.0)
    Y2 = Y1 + 0.5j
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nA = {xy(A)}\nY1 = {xy(Y1)}\nY2 = {xy(Y2)}\n"
            '[links]\nframe = ["O"]\ncrank = ["O", "A"]\nyoke = ["Y1", "Y2"]\n'
            '[[prismatic]]\nname = "slot"\npoint = "A"\nguide = "yoke"\nthrough = "Y1"\nangle = 0.0\n'
            '[[prismatic]]\nname = "rail"\nlink = "yoke"\nguide = "frame"\nthrough = "O"\nangle = 0.0\n'
            + crank_driver())


def m_yoke_inverted():
    # PPR with the revolute body as the inner guide: an arm hinged at the crank pin guides a slider link
    # that also translates on the frame (the arm therefore translates too)
    A = 0.3 * cmath.exp(0.7j)
    G = A + 0.5
    S1 = complex(A.real, 0.0)
    S2 = S1 + (0.2 - 0.3j)
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nA = {xy(A)}\nG = {xy(G)}\nS1 = {xy(S1)}\nS2 = {xy(S2)}\n"
            '[links]\nframe = ["O"]\ncrank = ["O", "A"]\narm = ["A", "G"]\nslider = ["S1", "S2"]\n'
            f'[[prismatic]]\nname = "inner"\nlink = "slider"\nguide = "arm"\nthrough = "A"\nangle = {math.pi / 2!r}\n'
            '[[prismatic]]\nname = "rail"\nlink = "slider"\nguide = "frame"\nthrough = "O"\nangle = 0.0\n'
            + crank_driver())


def m_cross():
    # PRP cross-slide: J slides in a slot along the crank and in a vertical frame slot x = 1
    u = cmath.exp(0.4j)
    A = 0.3 * u
    J = line_line(0j, u, 1 + 0j, 1j)
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nX = [1.0, 0.0]\nA = {xy(A)}\nJ = {xy(J)}\n"
            '[links]\nframe = ["O", "X"]\ncrank = ["O", "A"]\n'
            '[[prismatic]]\nname = "s1"\npoint = "J"\nguide = "crank"\nthrough = "O"\nangle = 0.0\n'
            f'[[prismatic]]\nname = "s2"\npoint = "J"\nguide = "frame"\nthrough = "X"\nangle = {math.pi / 2!r}\n'
            + crank_driver())


def m_cross_moving():
    # PRP on two moving links: J slides in slots along the crank and along the rocker of a four-bar
    A, B, P = fourbar_points()
    J = line_line(0j, A / abs(A), 1 + 0j, (B - 1) / abs(B - 1))
    return (HEAD + f"[points]\nO = [0.0, 0.0]\nO1 = [1.0, 0.0]\nA = {xy(A)}\nB = {xy(B)}\nP = {xy(P)}\nJ = {xy(J)}\n"
            '[links]\nframe = ["O", "O1"]\ncrank = ["O", "A"]\ncoupler = ["A", "B", "P"]\nrocker = ["O1", "B"]\n'
            '[[prismatic]]\nname = "s1"\npoint = "J"\nguide = "crank"\nthrough = "O"\nangle = 0.0\n'
            '[[prismatic]]\nname = "s2"\npoint = "J"\nguide = "rocker"\nthrough = "O1"\nangle = 0.0\n'
            + crank_driver())


def m_linear():
    # a driven linear actuator hinged at F whose rod end B slides in the straight frame guide y = 0.5
    return (HEAD + "[points]\nF = [0.0, 0.0]\nG = [0.0, 0.5]\nB = [1.0, 0.5]\n"
            '[links]\nframe = ["F", "G"]\n[actuators.cyl]\nbetween = ["F", "B"]\n'
            '[[prismatic]]\nname = "rail"\npoint = "B"\nguide = "frame"\nthrough = "G"\nangle = 0.0\n'
            '[[drivers]]\nname = "push"\nkind = "linear"\nactuator = "cyl"\nspeed = "50 mm/s"\n')


def m_boom():
    # RRR with a driven actuator as one side: a boom hinged to the frame at O, lifted by a cylinder F-B
    return (HEAD + "[points]\nO = [0.0, 0.0]\nF = [0.4, -0.3]\nB = [0.8, 0.5]\nT = [2.0, 0.9]\n"
            '[links]\nframe = ["O", "F"]\nboom = ["O", "B", "T"]\n[actuators.cyl]\nbetween = ["F", "B"]\n'
            '[[drivers]]\nname = "lift"\nkind = "linear"\nactuator = "cyl"\nspeed = "40 mm/s"\n')


def m_triad():
    # six-bar with a class-III group: a ternary link B-C-D held by the binary links A-B (to the crank),
    # P1-C and P2-D (to the frame); no dyad can be split off
    return (HEAD + "[points]\nO = [0.0, 0.0]\nP1 = [3.0, 0.0]\nP2 = [0.5, 2.5]\nA = [0.4, 0.0]\n"
            "B = [1.4, 0.4]\nC = [2.0, 0.9]\nD = [1.2, 1.3]\n"
            '[links]\nframe = ["O", "P1", "P2"]\ncrank = ["O", "A"]\nab = ["A", "B"]\ntern = ["B", "C", "D"]\n'
            'r1 = ["P1", "C"]\nr2 = ["P2", "D"]\n' + crank_driver())


CASES = {
    "fourbar_RRR": (m_fourbar, [GroupKind.RRR]),
    "slider_RRP": (m_slider, [GroupKind.RRP]),
    "slotted_crank_RRP": (m_slotted_crank, [GroupKind.RRP]),
    "whitworth_RPR": (m_whitworth, [GroupKind.RPR]),
    "scotch_yoke_PPR": (m_yoke, [GroupKind.PPR]),
    "inverted_yoke_PPR": (m_yoke_inverted, [GroupKind.PPR]),
    "cross_slide_PRP": (m_cross, [GroupKind.PRP]),
    "cross_slide_moving_PRP": (m_cross_moving, [GroupKind.RRR, GroupKind.PRP]),
    "linear_actuator_RRP": (m_linear, [GroupKind.RRP]),
    "linear_actuator_RRR": (m_boom, [GroupKind.RRR]),
}
#: design spread (see perturbed_designs); the boom's frame pivots are close together (|OF| = L/4), so it
#: gets a smaller one: far from the file's design the Newton oracle may start in the other branch's basin
#: (see test_newton_oracle_keeps_one_branch_for_a_design_far_from_the_sketch)
SPREAD = {"linear_actuator_RRR": 0.02}


def compiled(name):
    maker, kinds = CASES[name]
    m = assur.loads(maker())
    return m, assur.compile(m), kinds


def perturbed_designs(plan, n, rng, rel=0.06):
    """(n, n_params) random designs around the file's: lengths ×(1 ± rel), coordinates and offsets ±rel·L,
    angles ±rel rad."""
    L = plan.length_scale
    out = np.empty((n, plan.n_params))
    for i, name in enumerate(plan.param_names):
        v = plan.defaults[i]
        z = rng.standard_normal(n)
        if name.endswith((".length", ".distance")):
            out[:, i] = v * (1 + rel * z)
        elif name.endswith((".x", ".y", ".offset")):
            out[:, i] = v + rel * L * z
        else:  # .angle, .zero
            out[:, i] = v + rel * z
    return out


def neighbourhood(plan, k):
    """k inputs around the sketch input: ±0.6 rad for a crank, ±12 % for an actuator length."""
    q0 = plan.sketch_inputs[0]
    if plan.input_kinds[0] == "rotary":
        return q0 + np.linspace(-0.6, 0.6, k)
    return q0 * (1 + np.linspace(-0.12, 0.12, k))


def buildable_designs(plan, P):
    """Designs that can be assembled at the sketch input (the others are skipped)."""
    return assur.solve(plan, P, plan.sketch_inputs, order=0).valid


# -- the description's constraints, evaluated on solved positions --------------------------------------------
def constraint_residuals(plan, P, state):
    """Max |residual| per sample of every constraint the file states (link lengths, placements, frame points,
    slide lines, translating links, driver angles, driven actuator lengths). P: (..., n_params)."""
    m = plan.mechanism
    z = state.pos[..., 0] + 1j * state.pos[..., 1]
    Z = {p: z[..., i] for i, p in enumerate(plan.point_names)}
    par = {n: P[..., i] for i, n in enumerate(plan.param_names)}
    q = state.inputs
    res = []
    sk = {p: complex(*m.sketch(p)) for p in m.point_names}
    for lk in m.links:
        pts = lk.points
        if lk.name == "frame":
            for p in pts:
                res.append(Z[p] - (par[f"{p}.x"] + 1j * par[f"{p}.y"]))
            continue
        if len(pts) < 2:
            continue
        res.append(abs(Z[pts[1]] - Z[pts[0]]) - par[f"{lk.name}.length"])
        for p in pts[2:]:
            pl = lk.placement(p)
            org, tow = (pl.origin, pl.toward) if pl is not None else (pts[0], pts[1])
            d = Z[tow] - Z[org]
            want = Z[org] + par[f"{lk.name}.{p}.distance"] * np.exp(1j * par[f"{lk.name}.{p}.angle"]) * d / abs(d)
            res.append(Z[p] - want)

    def link_dir(name):
        lk = m.link(name)
        d = Z[lk.points[1]] - Z[lk.points[0]]
        return d / abs(d)

    for pr in m.prismatic:
        u = np.exp(1j * par[f"{pr.name}.angle"])
        if pr.guide != "frame":
            u = u * link_dir(pr.guide)
        line_q = Z[pr.through] + 1j * u * par[f"{pr.name}.offset"]
        if pr.point is not None:
            res.append(np.imag(np.conj(u) * (Z[pr.point] - line_q)))
        else:
            lk = m.link(pr.link)
            res.append(np.imag(np.conj(u) * (Z[lk.points[0]] - line_q)))
            # the translating link keeps the orientation relative to the guide line that the sketch shows
            u0 = cmath.exp(1j * pr.angle)
            if pr.guide != "frame":
                g = m.link(pr.guide).points
                u0 *= (sk[g[1]] - sk[g[0]]) / abs(sk[g[1]] - sk[g[0]])
            rel0 = (sk[lk.points[1]] - sk[lk.points[0]]) / abs(sk[lk.points[1]] - sk[lk.points[0]]) / u0
            res.append(link_dir(pr.link) / u - rel0)
    for k, d in enumerate(m.drivers):
        if d.kind == "rotary":
            arm = Z[d.arm] - Z[d.pivot]
            res.append(arm / abs(arm) - np.exp(1j * (par[f"{d.name}.zero"] + d.sense * q[..., k])))
        else:
            ac = next(a for a in m.actuators if a.name == d.actuator)
            res.append(abs(Z[ac.between[1]] - Z[ac.between[0]]) - q[..., k])
    return np.max(np.abs(np.stack(np.broadcast_arrays(*res), axis=-1)), axis=-1)


# -- closed forms against the Newton oracle ---------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(CASES))
def test_groups_found_have_the_expected_kinds(name):
    m, plan, kinds = compiled(name)
    assert [g.kind for g in plan.structure.groups] == kinds
    assert plan.structure.mobility == 1
    # the sketch (computed above by plain geometry) is reproduced at the sketch input
    s = assur.solve(plan, inputs=plan.sketch_inputs[0])      # a scalar input: batch shape ()
    sketch = np.array([m.sketch(p) for p in plan.point_names])
    np.testing.assert_allclose(s.pos, sketch, rtol=0, atol=1e-12 * plan.length_scale)


@pytest.mark.parametrize("name", sorted(CASES))
def test_closed_form_equals_newton_oracle(name):
    m, plan, _ = compiled(name)
    rng = np.random.default_rng([RNG_SEED, sorted(CASES).index(name)])
    P = perturbed_designs(plan, N_DESIGNS, rng, SPREAD.get(name, 0.06))
    keep = buildable_designs(plan, P)
    assert keep.sum() >= 0.6 * N_DESIGNS
    P = P[keep][:, None, :]                                   # (D, 1, n_params)
    q = neighbourhood(plan, 7)                                # (N,)
    closed = assur.solve(plan, P, q, method="closed")
    newton = assur.solve(plan, P, q, method="newton")
    assert closed.pos.shape[:2] == (keep.sum(), 7)
    # both methods agree on what can be assembled, and most samples can
    assert np.count_nonzero(closed.valid != newton.valid) <= 0.01 * closed.valid.size
    both = closed.valid & newton.valid
    assert both.mean() >= 0.5
    L = plan.length_scale
    for attr in ("pos", "dpos_dq", "d2pos_dq2"):
        a, b = getattr(closed, attr)[both], getattr(newton, attr)[both]
        axes = tuple(range(1, a.ndim))
        err = np.max(np.abs(a - b), axis=axes)
        scale = L + np.max(np.abs(b), axis=axes)
        assert np.all(err <= 1e-9 * scale), (attr, float(np.max(err / scale)))
    # body orientations agree too (compared as unit vectors: angles may differ by 2π)
    ea, eb = np.exp(1j * closed.body_angle[both]), np.exp(1j * newton.body_angle[both])
    assert np.max(np.abs(ea - eb)) <= 1e-9


@pytest.mark.parametrize("name", sorted(CASES))
def test_solved_positions_satisfy_every_constraint_of_the_file(name):
    m, plan, _ = compiled(name)
    rng = np.random.default_rng([RNG_SEED, 100 + sorted(CASES).index(name)])
    P = perturbed_designs(plan, N_DESIGNS, rng, SPREAD.get(name, 0.06))
    P = P[buildable_designs(plan, P)][:, None, :]
    if plan.input_kinds[0] == "rotary":
        q = plan.sketch_inputs[0] + np.linspace(-np.pi, np.pi, 73)     # a full turn for cranks
    else:
        q = neighbourhood(plan, 25)
    s = assur.solve(plan, P, q, order=0)
    assert s.valid.mean() >= 0.3
    with np.errstate(invalid="ignore"):                       # unbuildable samples are NaN; excluded below
        r = constraint_residuals(plan, P, s)
    assert np.all(r[s.valid] <= 1e-10 * plan.length_scale), float(np.max(r[s.valid]))
    # and the link lengths are constant over the motion (distance of every pair of points of a link)
    z = s.pos[..., 0] + 1j * s.pos[..., 1]
    for lk in m.links:
        ix = [plan.point_index(p) for p in lk.points]
        for i in ix:
            for j in ix:
                d = np.abs(z[..., i] - z[..., j])
                d = np.where(s.valid, d, np.nan)
                spread = np.nanmax(d, axis=1) - np.nanmin(d, axis=1)
                assert np.all(spread[np.isfinite(spread)] <= 1e-10 * plan.length_scale)


def _richardson(f_m2, f_m1, f_p1, f_p2, h):
    """First derivative from values at −h, −h/2, +h/2, +h (error O(h⁴))."""
    return (4 * (f_p1 - f_m1) / h - (f_p2 - f_m2) / (2 * h)) / 3


def _fd_check(plan, P, q, h):
    """Compare dpos_dq, d2pos_dq2, vel and acc with central differences in the input."""
    offsets = np.array([-h, -h / 2, 0.0, h / 2, h])
    qq = q[:, None] + offsets                                  # (N, 5)
    s = assur.solve(plan, P[:, None, None, :], qq)             # (D, N, 5)
    ok = np.all(s.valid, axis=-1)                              # the whole stencil can be assembled
    L = plan.length_scale
    pos, d1, d2 = s.pos, s.dpos_dq[..., 0], s.d2pos_dq2[..., 0, 0]
    # leave out samples next to a singular position (|dpos/dq| > 100·L, e.g. nearly parallel slide lines),
    # where finite differences of any step say nothing
    with np.errstate(invalid="ignore"):
        ok &= np.nan_to_num(np.max(np.abs(d1), axis=(-1, -2, -3)), nan=np.inf) < 100 * L
    assert ok.mean() >= 0.5
    vel, acc = s.vel, s.acc
    st = lambda a, k: a[:, :, k]                               # noqa: E731
    fd1 = _richardson(st(pos, 0), st(pos, 1), st(pos, 3), st(pos, 4), h)
    fd2 = _richardson(st(d1, 0), st(d1, 1), st(d1, 3), st(d1, 4), h)
    w = plan.speeds[0]
    assert w != 0
    fdv = w * fd1                                              # d/dt pos(q0 + w·t) at t = 0
    fda = w * _richardson(st(vel, 0), st(vel, 1), st(vel, 3), st(vel, 4), h)   # d/dt vel, constant speed
    for exact, fd, tol in ((st(d1, 2), fd1, 1e-7), (st(d2, 2), fd2, 1e-6),
                           (st(vel, 2), fdv, 1e-7), (st(acc, 2), fda, 1e-6)):
        e, f = exact[ok], fd[ok]
        scale = L * max(1.0, abs(w)) ** 2 + np.max(np.abs(e), axis=(-1, -2), keepdims=True)
        assert np.all(np.abs(e - f) <= tol * scale), float(np.max(np.abs(e - f) / scale))


@pytest.mark.parametrize("name", sorted(CASES))
def test_velocities_and_accelerations_equal_central_differences(name):
    m, plan, _ = compiled(name)
    rng = np.random.default_rng([RNG_SEED, 200 + sorted(CASES).index(name)])
    P = perturbed_designs(plan, 20, rng, SPREAD.get(name, 0.06))
    P = P[buildable_designs(plan, P)]
    q = neighbourhood(plan, 5)
    h = 2e-4 if plan.input_kinds[0] == "rotary" else 2e-4 * plan.length_scale
    _fd_check(plan, P, q, h)


def m_fivebar():
    # two cranks (O1: 0.3, O2: 0.4) and two couplers (0.8, 0.7) meeting at C
    A = 0.3 * cmath.exp(1.0j)
    B = 1 + 0.4 * cmath.exp(2.0j)
    C = circle_circle(A, 0.8, B, 0.7)
    return (HEAD + f"[points]\nO1 = [0.0, 0.0]\nO2 = [1.0, 0.0]\nA = {xy(A)}\nB = {xy(B)}\nC = {xy(C)}\n"
            '[links]\nframe = ["O1", "O2"]\ncrank1 = ["O1", "A"]\ncrank2 = ["O2", "B"]\nleft = ["A", "C"]\n'
            'right = ["B", "C"]\n' + crank_driver("O1", "A", "crank1") + crank_driver("O2", "B", "crank2", "-20 rpm"))


def test_two_input_closed_form_equals_newton_oracle():
    plan = assur.compile(assur.loads(m_fivebar()))
    assert [g.kind for g in plan.structure.groups] == [GroupKind.RRR] and plan.n_inputs == 2
    rng = np.random.default_rng([RNG_SEED, 400])
    P = perturbed_designs(plan, N_DESIGNS, rng)
    P = P[buildable_designs(plan, P)][:, None, :]
    q = plan.sketch_inputs + rng.uniform(-0.4, 0.4, (6, 2))             # (N, 2)
    closed = assur.solve(plan, P, q)
    newton = assur.solve(plan, P, q, method="newton")
    both = closed.valid & newton.valid
    assert both.mean() >= 0.5 and np.count_nonzero(closed.valid != newton.valid) <= 0.01 * both.size
    for attr in ("pos", "dpos_dq", "d2pos_dq2"):                       # d2pos_dq2 includes the mixed ∂²/∂q1∂q2
        a, b = getattr(closed, attr)[both], getattr(newton, attr)[both]
        axes = tuple(range(1, a.ndim))
        scale = plan.length_scale + np.max(np.abs(b), axis=axes)
        assert np.all(np.max(np.abs(a - b), axis=axes) <= 1e-9 * scale), attr


# -- class-III group (no closed form: solved by Newton) -------------------------------------------------------
def test_triad_sixbar_is_decomposed_into_a_class_three_group():
    m = assur.loads(m_triad())
    plan = assur.compile(m)
    s = plan.structure
    assert [g.kind for g in s.groups] == [GroupKind.TRIAD]
    g = s.groups[0]
    assert g.group_class == 3 and len(g.bodies) == 4 and g.order == 3      # three outer pairs: A, P1, P2
    assert s.structural_formula == "I(frame, crank) → III(ab, tern, r1, r2)"
    assert s.mobility == 1                                                 # W = 3·5 − 2·7 (Chebyshev)
    assert [st.kind for st in plan.steps] == ["frame", "crank", "newton"]


@pytest.mark.slow
def test_triad_sixbar_solution_satisfies_constraints_and_differences():
    m = assur.loads(m_triad())
    plan = assur.compile(m)
    sk = assur.solve(plan, inputs=plan.sketch_inputs[0])
    np.testing.assert_allclose(sk.pos, np.array([m.sketch(p) for p in plan.point_names]), rtol=0, atol=1e-12)
    rng = np.random.default_rng([RNG_SEED, 300])
    P = perturbed_designs(plan, 8, rng, rel=0.03)
    P = P[buildable_designs(plan, P)]
    q = neighbourhood(plan, 5) * 0.5 + plan.sketch_inputs[0] * 0.5        # ±0.3 rad
    s = assur.solve(plan, P[:, None, :], q, order=0)
    assert s.valid.mean() >= 0.8
    r = constraint_residuals(plan, P[:, None, :], s)
    assert np.all(r[s.valid] <= 1e-10 * plan.length_scale)
    _fd_check(plan, P, q, 2e-4)


# -- engine bugs found ------------------------------------------------------------------------------------------
def test_passive_cylinder_is_structurally_an_rpr_dyad():
    m = assur.loads(m_cylinder())
    assert [g.kind for g in assur.analyse_structure(m).groups] == [GroupKind.RPR]


def test_passive_cylinder_compiles_and_matches_newton():
    plan = assur.compile(assur.loads(m_cylinder()))
    q = neighbourhood(plan, 7)
    closed, newton = assur.solve(plan, inputs=q), assur.solve(plan, inputs=q, method="newton")
    np.testing.assert_allclose(closed.pos, newton.pos, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.exp(1j * closed.body_angle), np.exp(1j * newton.body_angle), rtol=0, atol=1e-12)


def test_passive_cylinder_with_hint_points_from_F_to_A():
    # A = 0.4·e^{0.3i} is on the left of O → F (cross product > 0), so the hint is satisfiable
    plan = assur.compile(assur.loads(m_cylinder('[branches]\nA = { side = "left", of = ["O", "F"] }\n')))
    q = neighbourhood(plan, 5)
    s = assur.solve(plan, inputs=q)
    F, A = s.point("F").pos, s.point("A").pos
    direction = np.angle((A[:, 0] - F[:, 0]) + 1j * (A[:, 1] - F[:, 1]))     # the cylinder axis F → A
    cyl = s.body_angle[:, plan.body_names.index("cyl.cylinder")]
    np.testing.assert_allclose(np.exp(1j * cyl), np.exp(1j * direction), rtol=0, atol=1e-12)


def test_branch_hint_is_honoured_by_the_newton_oracle():
    hint = '[branches]\nB = { side = "right", of = ["A", "O1"] }\n'
    plan = assur.compile(assur.loads(m_fourbar(hint)))
    q = neighbourhood(plan, 5)
    closed, newton = assur.solve(plan, inputs=q), assur.solve(plan, inputs=q, method="newton")
    # the hint puts B on the right of A → O1 (independent check on the closed form)
    A, B, O1 = closed.point("A").pos, closed.point("B").pos, closed.point("O1").pos
    side = (O1[:, 0] - A[:, 0]) * (B[:, 1] - A[:, 1]) - (O1[:, 1] - A[:, 1]) * (B[:, 0] - A[:, 0])
    assert np.all(side < 0)
    np.testing.assert_allclose(newton.pos, closed.pos, rtol=0, atol=1e-9)


def test_newton_oracle_keeps_one_branch_for_a_design_far_from_the_sketch():
    plan = assur.compile(assur.loads(m_boom()))
    # frame pivots moved (O by 0.11, F by 0.13 of |OF| = 0.5), boom 13 % longer; the stroke range
    # [r − |OF|, r + |OF|] ≈ [0.82, 1.32] m contains every input below
    P = plan.params_with(O__x=0.1, O__y=-0.45, F__x=0.27, F__y=-0.25, boom__length=1.07)
    q = np.array([0.894427191, 0.93, 0.96, 1.0])
    closed, newton = assur.solve(plan, P, q), assur.solve(plan, P, q, method="newton")
    assert np.all(closed.valid) and np.all(newton.valid)

    def side(s):
        O, F, B = (s.point(n).pos for n in "OFB")
        return np.sign((F[:, 0] - O[:, 0]) * (B[:, 1] - O[:, 1]) - (F[:, 1] - O[:, 1]) * (B[:, 0] - O[:, 0]))

    assert np.all(side(closed) == side(closed)[0])          # the closed form keeps its sign
    assert np.all(side(newton) == side(newton)[0])          # so must the oracle
    np.testing.assert_allclose(newton.pos, closed.pos, rtol=0, atol=1e-9)
