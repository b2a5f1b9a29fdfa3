"""Contract tests for every mechanism file in examples/.

For each file: it loads and compiles; its mobility equals its number of drivers; its crank turns
fully (every sample valid over 0..2π on 721 angles, the other inputs held at their sketch values);
every link keeps the distances of all its point pairs over the turn (and they equal the file's
dimensions); frame points stay put; a pin in a slot stays on its line; and the file round-trips
through ``dumps``/``loads``. A few file-specific checks follow (triangle sides of Jansen and Klann,
Grashof conditions, Chebyshev's straight segment).
"""
from __future__ import annotations

import itertools
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import assur

EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "examples"
EXAMPLES = sorted(f for f in EXAMPLES_DIR.glob("*.toml")       # mechanism files (not gear or mover designs)
                  if tomllib.loads(f.read_text(encoding="utf-8")).get("format") == "assur/1")
N_ANGLES = 721
TURN = np.linspace(0.0, 2.0 * math.pi, N_ANGLES)

#: files whose crank is documented NOT to turn fully (file name -> reason); none at present
PARTIAL_TURN: dict[str, str] = {}


def _ids(paths):
    return [p.stem for p in paths]


@pytest.fixture(scope="module", params=EXAMPLES, ids=_ids(EXAMPLES))
def example(request):
    m = assur.load(request.param)
    return request.param, m, assur.compile(m)


def _crank_index(plan) -> int:
    names = plan.input_names
    return names.index("crank") if "crank" in names else 0


def _turn_inputs(plan, angles=TURN, others=None):
    """Inputs (n_angles, n_inputs): the crank over ``angles``, the other inputs at the sketch (or ``others``)."""
    base = np.array(plan.sketch_inputs if others is None else others, dtype=float)
    inp = np.broadcast_to(base, (len(angles), plan.n_inputs)).copy()
    k = _crank_index(plan)
    if plan.input_kinds[k] == "linear":   # a linear driver runs its working stroke (its `range`) instead
        a, b = plan.mechanism.drivers[k].range
        inp[:, k] = a + (b - a) * np.asarray(angles) / (2.0 * math.pi)
        return inp
    inp[:, k] = angles
    return inp


def _solve_turn(plan, **kw):
    return assur.solve(plan, inputs=_turn_inputs(plan, **kw))


def test_examples_exist():
    names = {p.name for p in EXAMPLES}
    expected = {"walker_crank_slider.toml", "walker_fourbar.toml", "walker_fourbar_adjustable.toml",
                "walker_sixbar.toml", "walker_sixbar_beta1_60.toml", "jansen.toml", "klann.toml",
                "chebyshev_lambda.toml", "slider_crank.toml", "crank_rocker.toml"}
    assert expected <= names


def test_loads_compiles_and_mobility(example):
    path, m, plan = example
    s = assur.analyse_structure(m)
    assert s.mobility == len(m.drivers) == plan.n_inputs
    assert plan.structure.mobility == s.mobility
    assert m.description.strip(), f"{path.name} needs a description"
    if m.gait is not None:
        assert m.gait.foot in plan.point_names


def test_crank_turns_fully(example):
    path, m, plan = example
    st = _solve_turn(plan)
    if path.name in PARTIAL_TURN:
        assert not st.valid.all(), PARTIAL_TURN[path.name]
        return
    assert st.valid.all(), f"{path.name}: {np.count_nonzero(~st.valid)} of {N_ANGLES} samples unbuildable"
    assert np.all(np.isfinite(st.pos))
    assert np.all(np.isfinite(st.dpos_dq)) and np.all(np.isfinite(st.d2pos_dq2))


def _pair_distances(plan, pos, link):
    idx = [plan.point_index(p) for p in link.points]
    out = {}
    for a, b in itertools.combinations(range(len(idx)), 2):
        out[(link.points[a], link.points[b])] = np.linalg.norm(pos[..., idx[a], :] - pos[..., idx[b], :], axis=-1)
    return out


def test_links_keep_their_lengths(example):
    path, m, plan = example
    st = _solve_turn(plan)
    ok = st.valid
    pos = st.pos[ok]
    for link in m.links:
        if len(link.points) < 2:
            continue
        for (a, b), d in _pair_distances(plan, pos, link).items():
            np.testing.assert_allclose(d, d[0], rtol=1e-9, err_msg=f"{path.name}: |{a}{b}| of link {link.name}")
        if link.name == "frame":
            continue
        # the first two points keep the declared length (parameter `link.length`)
        d01 = _pair_distances(plan, pos, link)[(link.points[0], link.points[1])]
        np.testing.assert_allclose(d01, plan.defaults[plan.param_index(f"{link.name}.length")], rtol=1e-9)
        if link.length is not None:
            np.testing.assert_allclose(d01, link.length, rtol=1e-9)
        # placed points keep their declared distance from their 'from' point
        for name, pl in link.place:
            i, j = plan.point_index(name), plan.point_index(pl.origin)
            d = np.linalg.norm(pos[:, i, :] - pos[:, j, :], axis=-1)
            np.testing.assert_allclose(d, pl.distance, rtol=1e-9, err_msg=f"{path.name}: {link.name}.{name}")


def test_frame_points_fixed(example):
    path, m, plan = example
    st = _solve_turn(plan)
    for p in m.frame.points:
        xy = st.pos[:, plan.point_index(p), :]
        expected = np.array([plan.defaults[plan.param_index(f"{p}.{c}")] for c in "xyz"[:m.dimension]])
        np.testing.assert_allclose(xy, np.broadcast_to(expected, xy.shape), rtol=0, atol=1e-12)
        np.testing.assert_allclose(expected, m.sketch(p), rtol=0, atol=1e-15)


def test_pins_stay_in_their_slots(example):
    path, m, plan = example
    st = _solve_turn(plan)
    for pr in m.prismatic:
        if pr.point is None or pr.guide != "frame":
            continue
        q = np.array(m.sketch(pr.through))
        u = np.array([math.cos(pr.angle), math.sin(pr.angle)])
        left = np.array([-u[1], u[0]])
        z = st.pos[:, plan.point_index(pr.point), :] - q
        np.testing.assert_allclose(z @ left, pr.offset, rtol=0, atol=1e-12 * m.length_scale + 1e-15)


def test_drivers_reproduce_their_inputs(example):
    """The direction pivot → arm of each rotary driver equals zero + q (ccw) or zero − q (cw)."""
    path, m, plan = example
    st = _solve_turn(plan)
    for k, d in enumerate(m.drivers):
        if d.kind != "rotary":
            continue
        v = st.pos[:, plan.point_index(d.arm), :] - st.pos[:, plan.point_index(d.pivot), :]
        if m.dimension == 3:   # the angle in the pivot's axis frame (e_X2, e_Y2) = T_Y(γ1)·T_X(γ2) (paper 003 (8))
            from assur.kernels.spatial import axis_frame
            E = axis_frame(*(plan.defaults[plan.param_index(f"{d.pivot}.axis.gamma{i}")] for i in (1, 2)))
            v = v @ E[:, :2]
        theta = np.arctan2(v[:, 1], v[:, 0])
        want = d.zero + d.sense * st.inputs[:, k]
        np.testing.assert_allclose(np.exp(1j * theta), np.exp(1j * want), rtol=0, atol=1e-12)


def test_round_trip(example):
    path, m, plan = example
    text = assur.dumps(m)
    assert assur.loads(text) == m
    # and a second round is a fixed point of the text
    assert assur.dumps(assur.loads(text)) == text


# ---------------------------------------------------------------------------------------------------
# file-specific checks


def _load(name):
    m = assur.load(EXAMPLES_DIR / name)
    return m, assur.compile(m)


def test_adjustable_fourbar_turns_at_other_settings():
    """walker_fourbar_adjustable: the adjuster is a setting (speed 0); the crank still turns fully when the
    lever is moved ±30° from its default, and at the default the leg is the plain four-bar."""
    m, plan = _load("walker_fourbar_adjustable.toml")
    k = plan.input_names.index("adjuster")
    assert plan.speeds[k] == 0.0
    for a in np.radians([-30.0, -10.0, 0.0, 10.0, 30.0]):
        others = plan.sketch_inputs.copy()
        others[k] = a
        assert _solve_turn(plan, others=others).valid.all()
    m4, plan4 = _load("walker_fourbar.toml")
    st = _solve_turn(plan)
    st4 = _solve_turn(plan4)
    for p in plan4.point_names:
        np.testing.assert_allclose(st.pos[:, plan.point_index(p)], st4.pos[:, plan4.point_index(p)], atol=1e-12)


def test_jansen_holy_numbers():
    """The triangle sides of the ternary links equal Jansen's numbers (the placement angles are derived)."""
    m, plan = _load("jansen.toml")
    holy = dict(a=38, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7, i=49, j=50, k=61.9, l=7.8, m=15)
    cm = 0.01
    pos = assur.solve(plan, inputs=TURN).pos
    pairs = {"b": "PU", "d": "PE", "e": "UE", "g": "LG", "h": "GF", "i": "LF", "j": "CU", "k": "CL",
             "c": "PL", "f": "EG", "m": "OC"}
    for key, (p, q) in pairs.items():
        dist = np.linalg.norm(pos[:, plan.point_index(p)] - pos[:, plan.point_index(q)], axis=-1)
        np.testing.assert_allclose(dist, holy[key] * cm, rtol=1e-12, err_msg=key)
    np.testing.assert_allclose(m.sketch("P"), (-holy["a"] * cm, -holy["l"] * cm), atol=1e-15)
    # standard assembly: the foot is the lowest point, the upper joint above the lower one
    s = assur.solve(plan, inputs=TURN).pos
    y = s[..., 1]
    assert np.all(np.argmin(y, axis=-1) == plan.point_index("F"))
    assert np.all(s[:, plan.point_index("U"), 1] > s[:, plan.point_index("L"), 1])


def test_klann_triangles():
    m, plan = _load("klann.toml")
    mm = 1e-3
    pos = assur.solve(plan, inputs=TURN).pos
    sides = {"CH": 38.8, "CF": 73.4, "HF": 35.2, "EF": 57.7, "EG": 111.7, "FG": 59, "BH": 23.7, "DE": 34.1,
             "OC": 17.5}
    for (p, q), v in sides.items():
        dist = np.linalg.norm(pos[:, plan.point_index(p)] - pos[:, plan.point_index(q)], axis=-1)
        np.testing.assert_allclose(dist, v * mm, rtol=1e-12, err_msg=p + q)
    kinds = [g.kind.value for g in plan.structure.groups]
    assert kinds == ["RRR", "RRR"] and plan.structure.n_moving == 5


def _grashof(s, l, p, q):
    return s + l <= p + q


def test_crank_rocker_is_grashof():
    m, plan = _load("crank_rocker.toml")
    ground = math.dist(m.sketch("O2"), m.sketch("O4"))
    lengths = [m.link("crank").length, m.link("coupler").length, m.link("rocker").length, ground]
    s, l = min(lengths), max(lengths)
    p, q = sorted(lengths)[1:3]
    assert _grashof(s, l, p, q) and min(lengths) == m.link("crank").length
    st = assur.solve(plan, inputs=TURN)
    # the rocker oscillates (does not turn): its direction spans less than 180°
    v = st.pos[:, plan.point_index("B")] - st.pos[:, plan.point_index("O4")]
    ang = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    assert np.ptp(ang) < math.pi and abs(ang[-1] - ang[0]) < 1e-9


def test_slider_crank_stroke():
    """Offset slider-crank: the stroke is sqrt((l+r)² − e²) − sqrt((l−r)² − e²) (textbook closed form)."""
    m, plan = _load("slider_crank.toml")
    r, l, e = 0.050, 0.150, 0.020
    st = assur.solve(plan, inputs=np.linspace(0, 2 * math.pi, 20001))
    x = st.pos[:, plan.point_index("B"), 0]
    stroke = math.sqrt((l + r) ** 2 - e ** 2) - math.sqrt((l - r) ** 2 - e ** 2)
    assert abs(np.ptp(x) - stroke) < 1e-8
    np.testing.assert_allclose(st.pos[:, plan.point_index("B"), 1], e, atol=1e-15)


def test_chebyshev_lambda_straight_segment():
    """Ratios 1 : 2.5 : 2.5 : 2 with |BP| = 5; P moves nearly straight for about half a turn."""
    m, plan = _load("chebyshev_lambda.toml")
    st = assur.solve(plan, inputs=TURN[:-1])
    P = st.pos[:, plan.point_index("P")]
    B = st.pos[:, plan.point_index("B")]
    np.testing.assert_allclose(np.linalg.norm(P - B, axis=-1), 5.0, rtol=1e-12)
    y = P[:, 1]
    half = (N_ANGLES - 1) // 2
    window = min(np.ptp(np.roll(y, -k)[:half]) for k in range(N_ANGLES - 1))
    assert window < 0.02                      # nearly straight over 180° of crank (≈ 0.01 of a 4-long segment)
    lowest = np.argsort(y)[:half]
    assert np.ptp(P[lowest, 0]) > 3.5         # a long segment, parallel to the ground line O–D
    assert np.ptp(y) > 0.8                    # and a real lift on the return
