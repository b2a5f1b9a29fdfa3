"""Every assembly of a mechanism (assur.assemblies, issue 26 §2) against an independent brute force written here.

The brute force parameterises each group by another body than the engine does and finds the roots of the cut
link's condition by dense sampling and Brent's method:

- a triad (ternary B-C-D held by A-B, P1-C, P2-D): the angle ψ of the binary link A-B (the engine uses the
  ternary's angle and a degree-6 polynomial); for each ψ, C is the intersection of circles about B and P1 (two
  branches), D follows from B and C, and g = |D − P2| − l3;
- the class-IV group (ternaries t1: A-Q1-Q2 and t2: P-Q3-Q4, binaries Q1-Q3, Q2-Q4): the angle of t2 about P (the
  engine drives t1 about A); Q1 from circles about A and Q3, g = |Q2 − Q4| − l(b2).

Every assembly the engine returns must close its loops to 1e-12 of the size, the sketch's own assembly must be
among them (exactly one marked), and the two must agree in number and positions wherever the brute force's own
sampling is unambiguous (no two roots or a root and a branch end within a few samples of each other).
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import assur

GRID = 20001


def _circle_circle(c1, r1, c2, r2, sign):
    """The intersection left (sign +1) or right of c1 → c2, NaN where the circles do not meet (arrays)."""
    D = c2 - c1
    d2 = np.abs(D) ** 2
    a = (d2 + r1 * r1 - r2 * r2) / (2 * d2)
    h2 = r1 * r1 / d2 - a * a
    with np.errstate(invalid="ignore"):
        return np.where(h2 >= 0, c1 + D * (a + 1j * sign * np.sqrt(h2)), np.nan)


def _roots(f, sign):
    """Roots of f(t, sign) over [0, 2π): sign changes on GRID samples refined by Brent's method, including those
    between the last sample where the branch exists and its end (found by bisection); and whether the sampling is
    unambiguous (roots and branch ends at least 3 samples apart)."""
    t = np.linspace(0.0, 2 * np.pi, GRID)
    v = np.asarray(f(t, sign), dtype=float)
    out, events = [], []
    for i in range(GRID - 1):
        a, b = v[i], v[i + 1]
        if np.isfinite(a) != np.isfinite(b):
            events.append(i)
            inside, outside = (t[i], t[i + 1]) if np.isfinite(a) else (t[i + 1], t[i])
            for _ in range(60):                       # the branch's end, from inside
                mid = 0.5 * (inside + outside)
                inside, outside = (mid, outside) if np.isfinite(float(f(mid, sign))) else (inside, mid)
            start = a if np.isfinite(a) else b
            if start * float(f(inside, sign)) < 0:
                lo, hi = sorted((t[i] if np.isfinite(a) else t[i + 1], inside))
                out.append(brentq(lambda x: float(f(x, sign)), lo, hi, xtol=1e-15))
        elif np.isfinite(a) and a * b < 0:
            out.append(brentq(lambda x: float(f(x, sign)), t[i], t[i + 1], xtol=1e-15))
            events.append(i)
    events = np.array(events)
    clear = len(events) < 2 or np.min(np.diff(np.sort(events))) >= 3
    return out, clear


def _triad_text(pts):
    body = "\n".join(f"{k} = [{v.real:.6f}, {v.imag:.6f}]" for k, v in pts.items())
    return f"""format = "assur/1"
[units]
length = "m"
[points]
{body}
[links]
frame = ["O", "P1", "P2"]
crank = ["O", "A"]
ab = ["A", "B"]
tern = ["B", "C", "D"]
r1 = ["P1", "C"]
r2 = ["P2", "D"]
[[drivers]]
name = "crank"
kind = "rotary"
link = "crank"
pivot = "O"
arm = "A"
"""


def random_triad(rng):
    """A random triad six-bar whose sketch is one of its assemblies (the lengths are the sketch's)."""
    c = lambda s=1.0: complex(*rng.normal(0, s, 2))     # noqa: E731
    pts = {"O": 0j, "P1": 3 + c(0.5), "P2": 0.5 + 2.5j + c(0.5), "A": 0.3 * c() + 0.4, "B": 1.2 + 0.5j + c(0.5),
           "C": 2 + 1j + c(0.5), "D": 1 + 1.5j + c(0.5)}
    return pts, assur.compile(assur.loads(_triad_text(pts)))


def triad_brute_force(plan, q):
    """Every assembly of the triad at crank angle q: positions {point: complex} per root; and clear."""
    m = plan.mechanism
    P = {n: complex(*xy) for n, xy in m.points}
    A = P["O"] + abs(P["A"] - P["O"]) * np.exp(1j * q)
    lab, lbc, lbd, l2, l3 = (abs(P[a] - P[b]) for a, b in (("A", "B"), ("B", "C"), ("B", "D"), ("P1", "C"),
                                                             ("P2", "D")))
    k = (P["D"] - P["B"]) / (P["C"] - P["B"])

    def place(psi, sign):
        B = A + lab * np.exp(1j * psi)
        C = _circle_circle(B, lbc, P["P1"], l2, sign)
        return {"A": A, "B": B, "C": C, "D": B + (C - B) * k}

    def g(psi, sign):
        return np.abs(place(psi, sign)["D"] - P["P2"]) - l3

    out, clear = [], True
    for sign in (1, -1):
        roots, ok = _roots(g, sign)
        clear &= ok
        out += [place(r, sign) for r in roots]
    return out, clear


def _match(engine, brute, plan, tol=1e-8):
    """Every brute-force assembly equals one engine assembly (positions of the named points), one to one."""
    idx = {n: plan.point_index(n) for n in brute[0]} if brute else {}
    used = set()
    for z in brute:
        d = [max(abs(complex(*a.pos[i]) - z[n]) for n, i in idx.items()) for a in engine]
        j = int(np.argmin(d))
        assert d[j] < tol * plan.length_scale and j not in used
        used.add(j)


def test_triad_assemblies_agree_with_a_brute_force():
    rng = np.random.default_rng(7)
    compared = total = 0
    while compared < 12:
        pts, plan = random_triad(rng)
        for q in rng.uniform(0, 2 * np.pi, 3):
            found = assur.assemblies(plan, q)[0]
            for a in found:
                assert a.closure <= 1e-12
            brute, clear = triad_brute_force(plan, q)
            total += 1
            if not clear:
                continue
            assert len(found) == len(brute), (pts, q)
            _match(found, brute, plan)
            compared += 1
    assert compared >= 0.8 * total


def test_six_assemblies_of_a_triad():
    """The degree-6 bound is reached: a triad of Gosselin's kind with six real assemblies (searched here among
    random triads; the brute force counts them too)."""
    rng = np.random.default_rng(3)
    for _ in range(400):
        pts, plan = random_triad(rng)
        q = float(rng.uniform(0, 2 * np.pi))
        found = assur.assemblies(plan, q)[0]
        if len(found) == 6:
            brute, clear = triad_brute_force(plan, q)
            assert len(brute) == 6
            _match(found, brute, plan)
            return
        assert len(found) <= 6
    pytest.fail("no triad with six assemblies among 400")


def test_the_sketch_assembly_is_among_them_and_marked_once(triad_sixbar_plan):
    q = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    st = assur.solve(triad_sixbar_plan, inputs=q, order=0)
    for i, found in enumerate(assur.assemblies(triad_sixbar_plan, q)):
        marked = [a for a in found if a.sketch]
        assert len(marked) == 1
        np.testing.assert_allclose(marked[0].pos, st.pos[i], atol=1e-12 * triad_sixbar_plan.length_scale)
        assert all(a.closure <= 1e-12 for a in found)
    # at the sketch's input the marked one is the sketch itself, on the plan's branch sign
    sk = [a for a in assur.assemblies(triad_sixbar_plan)[0] if a.sketch][0]
    m = triad_sixbar_plan.mechanism
    np.testing.assert_allclose(sk.pos, [m.sketch(p) for p in triad_sixbar_plan.point_names], atol=1e-9)
    from assur.engine.planar.compile import newton_branch_signs
    assert [b[0] for b in sk.branches] == list(newton_branch_signs(triad_sixbar_plan).values())


def classiv_brute_force(plan, q):
    m = plan.mechanism
    P = {n: complex(*xy) for n, xy in m.points}
    A = P["O"] + abs(P["A"] - P["O"]) * np.exp(1j * q)
    d = lambda a, b: abs(P[a] - P[b])            # noqa: E731
    w3, w4 = P["Q3"] - P["P"], P["Q4"] - P["P"]
    k2 = (P["Q2"] - P["A"]) / (P["Q1"] - P["A"])

    def place(phi, sign):
        e = np.exp(1j * phi)
        Q3, Q4 = P["P"] + e * w3, P["P"] + e * w4
        Q1 = _circle_circle(A, d("A", "Q1"), Q3, d("Q1", "Q3"), sign)
        return {"A": A, "Q1": Q1, "Q2": A + (Q1 - A) * k2, "Q3": Q3, "Q4": Q4}

    def g(phi, sign):
        z = place(phi, sign)
        return np.abs(z["Q2"] - z["Q4"]) - d("Q2", "Q4")

    out, clear = [], True
    for sign in (1, -1):
        roots, ok = _roots(g, sign)
        clear &= ok
        out += [place(r, sign) for r in roots]
    return out, clear


@pytest.mark.parametrize("seed", [0, 1])
def test_class_four_assemblies_agree_with_a_brute_force(seed):
    from conftest import EXAMPLES
    plan = assur.compile(assur.load(EXAMPLES / "classiv_sixbar.toml"))
    rng = np.random.default_rng(seed)
    params = plan.defaults.copy()
    compared = 0
    for q in rng.uniform(0, 2 * np.pi, 4):
        found = assur.assemblies(plan, q)[0]
        assert all(a.closure <= 1e-12 for a in found) and all(a.certified for a in found)
        assert sum(a.sketch for a in found) == 1
        brute, clear = classiv_brute_force(plan, q)
        if clear:
            assert len(found) == len(brute)
            _match(found, brute, plan)
            compared += 1
    assert compared >= 3 and params is not None


def test_a_dyad_hinged_on_a_group_point_multiplies_its_assemblies():
    """A dyad hinged to a point of the class-IV group (Q1) and to the frame: that point is the group's own, not one
    the group is hinged to; every assembly is a group assembly times the dyad's closing branches."""
    from conftest import EXAMPLES
    text = (EXAMPLES / "classiv_sixbar.toml").read_text(encoding="utf-8")
    text = text.replace('Q4 = [136, -34]\n', 'Q4 = [136, -34]\nR = [60, 160]\nS = [-40, 120]\n')
    text = text.replace('frame = ["O", "P"]', 'frame = ["O", "P", "S"]')
    text = text.replace('b2 = ["Q2", "Q4"]\n', 'b2 = ["Q2", "Q4"]\nd1 = ["Q1", "R"]\nd2 = ["S", "R"]\n')
    plan = assur.compile(assur.loads(text))
    base = assur.compile(assur.load(EXAMPLES / "classiv_sixbar.toml"))
    for q in (0.4, 2.0):
        found = assur.assemblies(plan, q)[0]
        groups = assur.assemblies(base, q)[0]
        assert all(a.closure <= 1e-12 for a in found) and sum(a.sketch for a in found) == 1
        assert len(groups) < len(found) <= 2 * len(groups)
        # each assembly's group part is one of the group's own assemblies
        idx = [plan.point_index(p) for p in ("Q1", "Q2", "Q3", "Q4")]
        jdx = [base.point_index(p) for p in ("Q1", "Q2", "Q3", "Q4")]
        for a in found:
            assert min(np.max(np.abs(a.pos[idx] - g.pos[jdx])) for g in groups) < 1e-9


def test_an_rpr_dyads_branches_that_place_every_point_alike_are_told_apart_by_their_bodies():
    """lever_manipulator.toml: the driven rod O–B is a passive RPR dyad whose slide passes through both hinges, so
    its two branches place B alike and differ only in the rod's orientation (toward B, or half a turn from it). The
    drive rod A–B on the horizontal guide puts B at 600 ± 300 mm (|AB| = 500 mm, 400 mm above A): four
    assemblies in two pairs, and only the one whose rod points as the sketch's is the sketch's."""
    from conftest import EXAMPLES
    plan = assur.compile(assur.load(EXAMPLES / "lever_manipulator.toml"))
    found = assur.assemblies(plan, 0.5)[0]
    b, rod = plan.point_index("B"), plan.body_names.index("driven_rod.cylinder")
    assert len(found) == 4
    xs = sorted(round(float(a.pos[b, 0]), 9) for a in found)
    assert xs == [0.3, 0.3, 0.9, 0.9]
    for a in found:
        twin = [o for o in found if o is not a and np.allclose(o.pos, a.pos, rtol=0, atol=1e-12)]
        assert len(twin) == 1
        toward_b = np.arctan2(a.pos[b, 1], a.pos[b, 0])          # O is the origin
        turns = sorted(abs(np.remainder(x.angles[rod] - toward_b + np.pi, 2 * np.pi) - np.pi) for x in (a, twin[0]))
        np.testing.assert_allclose(turns, [0.0, np.pi], atol=1e-12)
    (sk,) = [a for a in found if a.sketch]
    st = assur.solve(plan, inputs=0.5, order=0)
    np.testing.assert_allclose(sk.angles, np.asarray(st.body_angle).reshape(-1), atol=1e-12)
    assert sk.angles[rod] == pytest.approx(np.arctan2(400, 300), abs=1e-12)
