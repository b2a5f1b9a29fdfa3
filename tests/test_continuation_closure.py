"""A crank whose assembly spans more than a turn without closing (engine/planar/continuation.py, "ambiguous").

The fixture is an eight-link leg the atlas's gait search once accepted (tests/data/eightbar_leg_locks_past_a_turn.toml):
its class-IV group, followed from the sketch, locks at a toggle 128.6° counter-clockwise and 282.4° clockwise of
it, so the crank angles between the two toggles (50.52° … 101.58°) are reached both ways round, on two different
assemblies. Every continuation (numpy and compiled, every sample on its own and swept) must flag those samples
unbuildable instead of returning one way's assembly beside the other way's neighbour 1.3 m away, and the gait and
the synthesis must then see a crank that cannot turn fully."""
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.engine.planar.continuation import closes
from assur.tolerances import DEFAULT

DATA = Path(__file__).parent / "data"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
LEG = DATA / "eightbar_leg_locks_past_a_turn.toml"
Q = np.radians(np.arange(0.0, 360.0, 2.0))


@pytest.fixture(scope="module")
def leg():
    return assur.compile(assur.load(LEG))


def _no_jump(state, q):
    """The largest jump between neighbouring valid samples (cyclically), over what the speed allows: each point's
    move at most 1.5 × the step × the larger |dP/dq| of the two samples (plus 1e-9 of the scale)."""
    P, V, ok = state.pos, state.dpos_dq[..., 0], state.valid
    nxt = np.roll(np.arange(len(q)), -1)
    both = ok & ok[nxt]
    dq = np.remainder(q[nxt] - q, 2 * np.pi)[:, None]
    move = np.linalg.norm(P[nxt] - P, axis=-1)
    bound = 1.5 * dq * np.maximum(np.linalg.norm(V, axis=-1), np.linalg.norm(V[nxt], axis=-1)) + 1e-9
    return np.max((move / bound)[both]) if both.any() else 0.0


@pytest.mark.parametrize("sweep", [False, True])
def test_numpy_flags_the_band_reached_both_ways_round(leg, sweep):
    s = assur.solve(leg, inputs=Q, order=1, backend="numpy", sweep=sweep)
    deg = np.degrees(Q)
    band = (deg > 50.52) & (deg < 101.58)
    np.testing.assert_array_equal(s.valid, ~band)
    np.testing.assert_array_equal(s.ambiguous, band)          # not samples without an assembly: with two
    assert _no_jump(s, Q) <= 1.0


def test_the_assembly_closes_on_the_examples_and_not_on_the_leg(leg):
    """``closes``: half a turn each way from the sketch meets on one assembly (a full-turn crank), or not."""
    assert not closes(leg, leg.steps, DEFAULT, "closed")
    for name in ("triad_sixbar", "classiv_sixbar"):
        plan = assur.compile(assur.load(EXAMPLES / f"{name}.toml"))
        assert closes(plan, plan.steps, DEFAULT, "closed")


def test_the_gait_sees_a_crank_that_cannot_turn_fully(leg):
    """Before, every sample was valid and the gait was measured on a foot path with a 0.5 m jump in it."""
    study = assur.Study(leg)
    assert study.gait is None and "cannot turn fully" in study.gait_error
    b = study.buildable
    assert b.ambiguous == b.unbuildable == np.count_nonzero(study.grid()[1].ambiguous) > 0
    assert f"{b.ambiguous} of them ambiguous" in study.gait_error
    s = assur.solve(leg, inputs=Q, backend="numpy")
    F = s.pos[:, leg.point_index("F")]
    ok = s.valid & np.roll(s.valid, -1)
    assert np.max(np.linalg.norm(np.roll(F, -1, axis=0) - F, axis=-1)[ok]) < 0.05


@pytest.mark.slow            # 411 enumerations of every assembly of a class-IV group
def test_the_band_is_where_the_enumerated_assemblies_say(leg):
    """An independent computation: the sketch's assembly tracked through every assembly ``assur.assemblies``
    enumerates (certified one-parameter reduction), 1° at a time, nearest to the one before, each way round until
    it has none near (a toggle: two assemblies merge and vanish). The inputs it reaches both ways are the flagged
    band, to the tracking's degree."""
    q_s = float(leg.sketch_inputs[0])
    ends = []
    for way in (1.0, -1.0):
        here = assur.solve(leg, inputs=[q_s], backend="numpy").pos[0]
        k = 0
        while True:
            k += 1
            found = assur.assemblies(leg, [q_s + way * np.radians(k)])[0]
            d = [np.max(np.linalg.norm(a.pos - here, axis=-1)) for a in found]
            if not d or min(d) > 0.1 * leg.length_scale:
                break
            here = found[int(np.argmin(d))].pos
        ends.append(k - 1)                                 # the last degree still on the assembly
    ccw, cw = ends
    assert ccw + cw > 360                                  # more than a turn, and it does not close: toggles
    lo, hi = np.degrees(q_s) - cw, np.degrees(q_s) + ccw - 360.0   # the band reached both ways (degrees)
    assert lo == pytest.approx(50.52, abs=1.0) and hi == pytest.approx(101.58, abs=1.0)
    deg = np.arange(0.0, 360.0, 0.5)
    s = assur.solve(leg, inputs=np.radians(deg), backend="numpy")
    inside = (deg > lo + 1.0) & (deg < hi - 1.0)
    outside = (deg < lo - 1.0) | (deg > hi + 1.0)
    assert not s.valid[inside].any() and s.valid[outside].all()


@pytest.mark.slow            # compiles this structure's kernels
@pytest.mark.parametrize("sweep", [False, True])
def test_the_compiled_kernels_flag_the_same_band(leg, sweep):
    a = assur.solve(leg, inputs=Q, order=1, backend="numpy", sweep=sweep)
    b = assur.solve(leg, inputs=Q, order=1, backend="numba", sweep=sweep)
    np.testing.assert_array_equal(a.valid, b.valid)
    np.testing.assert_array_equal(a.ambiguous, b.ambiguous)
    assert b.ambiguous.any() and not (b.valid & b.ambiguous).any()
    assert not b.valid.all() and _no_jump(b, Q) <= 1.0
    np.testing.assert_allclose(b.pos[b.valid], a.pos[a.valid], atol=1e-9 * leg.length_scale)


@pytest.mark.slow            # compiles the cycle kernel of that leg
def test_the_synthesis_cycle_kernel_counts_the_band_unbuildable():
    """The walking-leg problem's evaluation of the file's design (what the atlas ranking evaluates): both routes
    count the band's samples unbuildable and the design infeasible, as a full-turn constraint must."""
    import tomllib

    from assur.synthesis.evaluate import Evaluator
    from assur.synthesis.legs import LegCandidate, leg_problem
    doc = tomllib.loads(LEG.read_text("utf-8"))
    c = LegCandidate("K8-b66552958ccf/f4/c7/foot5", "leg", "K8-b66552958ccf/f4", None, 7, 5, "L7", "L5", doc,
                     newton=True)
    problem = leg_problem(c, {"clearance": 0.25})
    start = dict(zip(problem.plan.param_names, problem.plan.defaults))
    x = np.array([start[n] for n in problem.names])[None, :]
    fast = Evaluator(problem, backend="numba")(x, True)
    slow = Evaluator(problem, backend="numpy")(x, True)
    for ev in (fast, slow):
        assert not ev.feasible[0] and ev.quantities["unbuildable"][0] > 0
    assert fast.quantities["unbuildable"][0] == pytest.approx(slow.quantities["unbuildable"][0], rel=1e-12)


def test_analyze_says_the_unbuildable_samples_are_ambiguous(leg):
    """The summary counts them apart from samples that have no assembly (text and JSON)."""
    from assur.analysis.summary import summary_dict as summary
    from assur.report.analysis import analysis_html, analysis_lines
    study = assur.Study(leg)
    n = study.buildable.ambiguous
    line = next(ln for ln in analysis_lines(study) if ln.startswith("buildability"))
    assert f"{n} of {study.buildable.steps} positions cannot be assembled ({n} of them ambiguous" in line
    assert summary(study)["ambiguous"] == n
    assert f"(unbuildable: {study.buildable.unbuildable}; {n} of them ambiguous" in analysis_html(study)
    tri = assur.Study(assur.compile(assur.load(EXAMPLES / "triad_sixbar.toml")))
    assert tri.buildable.ambiguous == 0 and summary(tri)["ambiguous"] == 0


def test_solve_says_how_many_unbuildable_positions_are_ambiguous(capsys):
    from assur.cli.main import main
    assert main(["solve", str(LEG), "--steps", "8"]) == 0
    out = capsys.readouterr()
    # 8 positions 45° apart: only 90° lies in the band 50.52° … 101.58°
    assert "1 cannot be assembled (1 of them ambiguous" in out.out + out.err
