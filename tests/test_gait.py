"""Gait metrics against the exact closed forms of paper 000 (docs/papers/000.md §3 and §6; the § numbers
below are that page's) and the definitions of the contact arc (§6), plus the walking-module bookkeeping."""
import math

import numpy as np
import pytest

import assur
from assur.analysis.gait import gait_curves, gait_metrics, module_metrics, module_timeline

L1, L2, L5 = 165.0, 193.0, 175.0   # mm, paper 000's printed design (§4)


def crank_slider_text(l1=L1, l2=L2, l5=L5, sketch_deg=30.0, omega="1 rad/s"):
    """Paper 000's mechanism in the paper's frame (§2): C = l5·(sin φ, cos φ)."""
    f = math.radians(sketch_deg)
    cx, cy = l5 * math.sin(f), l5 * math.cos(f)
    yb = l5 * math.cos(f) + math.sqrt(l2 ** 2 - (l5 * math.sin(f)) ** 2)
    ax, ay = (l1 / l2) * (0 - cx), yb + (l1 / l2) * (yb - cy)
    return f"""
format = "assur/1"
[units]
length = "mm"
angle = "deg"
[points]
K = [0, 0]
C = [{cx!r}, {cy!r}]
B = [0, {yb!r}]
A = [{ax!r}, {ay!r}]
[links]
frame = ["K"]
crank = ["K", "C"]
[links.rod]
points = ["C", "B", "A"]
length = {l2!r}
[links.rod.place.A]
from = "B"
toward = "C"
distance = {l1!r}
angle = 180
[[prismatic]]
name = "slider"
point = "B"
guide = "frame"
through = "K"
angle = 90
[[drivers]]
name = "crank"
link = "crank"
pivot = "K"
arm = "C"
zero = 90
sense = "cw"
speed = "{omega}"
[gait]
foot = "A"
ground = [1, 0]
up = [0, 1]
"""


@pytest.fixture(scope="module")
def plan():
    return assur.compile(assur.loads(crank_slider_text()))


def closed_forms(l1=L1, l2=L2, l5=L5):
    """§6 closed forms, in metres (ω = 1 rad/s)."""
    l1, l2, l5 = l1 / 1000, l2 / 1000, l5 / 1000
    k = 1 + l1 / l2
    d = l1 * l5 / l2
    y_min = math.sqrt((k * k - 1) * (l2 * l2 - l5 * l5))
    return {"step": 2 * d, "d": d, "lift": (l1 + l2 + l5) - y_min, "sag": (l1 + l2 - l5) - y_min,
            "vmax": l5}


def test_structure_is_crank_and_rrp(plan):
    # §2: n = 3 (crank, rod, slider block), p5 = 4, W = 1; crank → RRP dyad
    s = plan.structure
    assert (s.n_moving, s.pair_counts["p5"], s.mobility) == (3, 4, 1)
    assert [g.kind for g in s.groups] == [assur.GroupKind.RRP]


def test_contact_arc_is_90_to_270(plan):
    g = gait_metrics(plan, steps=720)
    # §6: x_A ∝ −sin φ, so the contact arc is [90°, 270°] exactly and duty = 0.5
    assert g.contact_start == pytest.approx(math.pi / 2, abs=1e-7)
    assert g.contact_end == pytest.approx(3 * math.pi / 2, abs=1e-7)
    assert g.duty_factor == pytest.approx(0.5, abs=1e-8)


def test_step_lift_sag_closed_forms(plan):
    g = gait_metrics(plan, steps=720)
    ref = closed_forms()
    assert g.step_length == pytest.approx(ref["step"], rel=1e-9)
    assert g.lift == pytest.approx(ref["lift"], rel=1e-9)
    assert g.sag == pytest.approx(ref["sag"], rel=1e-9)


def test_support_speeds_closed_forms(plan):
    g = gait_metrics(plan, steps=720)
    ref = closed_forms()
    # §6: max |v| on the contact arc = l5·ω (at 90° and 270°); max |v_x| = d·ω, min 0
    assert g.support_speed.max == pytest.approx(ref["vmax"], rel=1e-9)
    assert g.support_vx.max == pytest.approx(ref["d"], rel=1e-9)
    assert g.support_vx.min == pytest.approx(0.0, abs=1e-9)
    # a_x = d ω² sin φ ranges over ±d ω² on [90°, 270°]
    assert g.support_ax[0] == pytest.approx(-ref["d"], rel=1e-6)
    assert g.support_ax[1] == pytest.approx(ref["d"], rel=1e-6)
    # time-mean of |v_x| = d·|cos φ| over [90°, 270°]: (1/π)∫|cos| = 2/π (independent integral)
    assert g.support_vx.mean == pytest.approx(ref["d"] * 2 / math.pi, rel=1e-6)


@pytest.mark.parametrize("fraction", [0.8, 0.9])
def test_central_vx_spread_closed_form(plan, fraction):
    """§6: x_A = −d·sin φ, |v_x| = d·ω·|cos φ| on the contact arc [90°, 270°]. The central fraction f of the stride
    [−d, d] is |sin φ| ≤ f, i.e. φ = π ± asin f: there |v_x| runs from d·√(1 − f²) (the window's ends) to d (φ = π)
    and its mean is d·f/asin f (independent integral of cos over ±asin f), so the spread is
    (1 − √(1 − f²))·asin f / f. The metric finds the window's ends exactly (the roots of x(φ) ∓ f·d between the
    samples), so a coarse grid already gives it; the sampled form misses the ends by up to a sample and stays
    below it (it underestimates the spread)."""
    from assur.analysis.gait import central_vx_spread
    exact = (1 - math.sqrt(1 - fraction ** 2)) * math.asin(fraction) / fraction
    assert gait_metrics(plan, steps=360).vx_spread[f"{fraction:g}"] == pytest.approx(exact, rel=1e-9)
    assert gait_metrics(plan, steps=64).vx_spread[f"{fraction:g}"] == pytest.approx(exact, rel=1e-6)
    curves = gait_curves(plan, steps=360)
    d = closed_forms()["d"]
    sampled = float(central_vx_spread(curves.x, curves.vx, curves.contact, fraction, -d, d))
    assert sampled < exact


def test_population_vx_spread_is_the_same_window(plan):
    """The sampled (synthesis) form at 0.8 and 0.9 equals the definition applied by hand to the same samples."""
    from assur.analysis.gait import population_gait
    M = 720
    q = np.linspace(0, 2 * math.pi, M, endpoint=False)
    st = assur.solve(plan, inputs=q[:, None], order=1)
    i = plan.point_index("A")
    pg = population_gait(st.pos[None, :, i], st.valid[None], st.dpos_dq[None, :, i, :, 0], ground=(1, 0), up=(0, 1))
    x, vx = st.pos[:, i, 0], np.abs(st.dpos_dq[:, i, 0, 0])
    contact = (q >= math.pi / 2 - 1e-12) & (q <= 3 * math.pi / 2 + 1e-12)      # the closed-form contact arc
    for f, key in ((0.8, "vx_spread"), (0.9, "vx_spread_90")):
        c, half = 0.5 * (x.max() + x.min()), 0.5 * f * (x.max() - x.min())
        w = vx[contact & (np.abs(x - c) <= half)]
        assert pg[key][0] == pytest.approx((w.max() - w.min()) / w.mean(), rel=1e-12)


def test_metrics_converge_with_sampling(plan):
    a = gait_metrics(plan, steps=180)
    b = gait_metrics(plan, steps=1440)
    for field in ("step_length", "lift", "sag", "duty_factor"):
        assert getattr(a, field) == pytest.approx(getattr(b, field), rel=1e-8)
    assert a.support_speed.mean == pytest.approx(b.support_speed.mean, rel=1e-6)


def test_speeds_scale_with_omega():
    slow = gait_metrics(assur.compile(assur.loads(crank_slider_text(omega="1 rad/s"))))
    fast = gait_metrics(assur.compile(assur.loads(crank_slider_text(omega="3 rad/s"))))
    assert fast.support_speed.max == pytest.approx(3 * slow.support_speed.max, rel=1e-9)
    assert fast.support_ax[1] == pytest.approx(9 * slow.support_ax[1], rel=1e-6)
    assert fast.step_length == pytest.approx(slow.step_length, rel=1e-12)


def test_body_path_mirrors_foot(plan):
    c = gait_curves(plan, steps=360)
    # with the foot planted the frame pivot moves by minus the foot's relative displacement
    assert c.body_x[0] == 0 and c.body_v[0] == 0
    assert np.ptp(c.body_x) == pytest.approx(gait_metrics(plan).step_length, rel=1e-6)


def test_unbuildable_crank_raises_clear_error():
    # l2 < l5: the RRP radicand is negative for part of the turn (§2)
    p = assur.compile(assur.loads(crank_slider_text(l2=150.0, sketch_deg=10.0)))
    with pytest.raises(assur.UnbuildableError, match="cannot turn fully"):
        gait_metrics(p)


def test_band_and_antiphase_support(plan):
    arc = gait_metrics(plan)
    anti = gait_metrics(plan, support="antiphase")
    # antiphase: a leg supports while lower than its twin 180° away; duty is 1/2 for any path
    assert anti.duty_factor == pytest.approx(0.5, abs=2 / 720)
    band = gait_metrics(plan, support="band", band=arc.lift * 2)
    assert band.duty_factor == 1.0  # a band above the whole path holds every sample
    with pytest.raises(assur.SpecError, match="band"):
        gait_metrics(plan, support="band")


def test_walking_module_feet_count(plan):
    g = gait_metrics(plan)
    # two legs in antiphase with duty exactly 0.5: always one or two feet down, never none
    mm = module_metrics(g, (0.0, math.pi))
    assert mm.min_feet >= 1 and mm.airborne_fraction == 0
    q, count = module_timeline(g, (0.0, math.pi))
    assert count.shape == q.shape and count.max() <= 2
    # one leg: airborne exactly during the transfer arc (1 − duty)
    one = module_metrics(g, (0.0,))
    assert one.airborne_fraction == pytest.approx(1 - g.duty_factor, abs=2 / 720)


def test_legs_are_a_batch_axis(plan):
    from assur.analysis.gait import feet_on_ground, legs_state
    q = np.linspace(0, 2 * np.pi, 73)
    phases = (0.0, math.pi)
    s = legs_state(plan, phases, q)
    assert s.pos.shape == (73, 2, plan.n_points, 2)
    # leg 1 at q equals leg 0 at q + π (same leg, shifted crank): an independent single-leg solve
    single = assur.solve(plan, inputs=q + math.pi)
    assert np.allclose(s.pos[:, 1], single.pos, atol=1e-12)
    on = feet_on_ground(gait_metrics(plan), phases, q)
    foot = plan.point_index("A")
    # a foot counted on the ground is on the low side: y within [y_min, y(180°)] (§6)
    y = s.pos[..., foot, 1]
    assert np.all(y[on] <= (L1 + L2 - L5) / 1000 + 1e-9)


def test_walking_module_of_the_paper004_file():
    """The four-bar file's module: two legs in antiphase. Each leg is down a duty share of the cycle,
    so the mean number of feet down is 2·duty (an identity), and antiphase with duty > 0.5 never
    leaves the module airborne."""
    from pathlib import Path
    p = assur.compile(assur.load(Path(__file__).resolve().parents[1] / "examples" / "walker_fourbar.toml"))
    phases = p.mechanism.gait.phases
    assert phases == pytest.approx((0.0, math.pi))
    g = gait_metrics(p)
    mm = module_metrics(g, phases)
    assert mm.mean_feet == pytest.approx(2 * g.duty_factor, abs=2 / 720)
    assert g.duty_factor > 0.5 and mm.min_feet == 1 and mm.airborne_fraction == 0.0


def test_a_solved_state_or_a_shared_cycle_gives_the_same_numbers(plan):
    """gait_metrics/gait_curves of a plan, of a Cycle and of a State solved over the same uniform grid agree
    to the last bit (the State's grid replaces ``steps``)."""
    from assur.analysis.gait import gait_metrics_and_curves
    from assur.analysis.sampling import Cycle
    q = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    state = assur.solve(plan, None, q[:, None], order=2)
    a = gait_metrics(plan, steps=360)
    b, cb = gait_metrics_and_curves(state)
    c = gait_metrics(Cycle(plan, steps=360))
    assert a == b == c and b.samples == 360
    ca = gait_curves(plan, steps=360)
    for name in ("q", "x", "v", "speed", "contact", "body_x"):
        assert np.array_equal(getattr(ca, name), getattr(cb, name))


def test_a_state_off_the_uniform_grid_is_refused(plan):
    from assur.errors import SpecError
    q = np.linspace(0.0, 2 * math.pi, 360)                     # endpoint included: not the uniform grid
    with pytest.raises(SpecError, match="linspace"):
        gait_metrics(assur.solve(plan, None, q[:, None], order=2))
    q = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    with pytest.raises(SpecError, match="order = 2"):
        gait_metrics(assur.solve(plan, None, q[:, None], order=1))


def test_population_gait_samples_the_exact_metrics(plan):
    """The sampled population form agrees with the exact metrics to the sampling step, design by design,
    and marks a design with an unbuildable sample NaN."""
    from assur.analysis.gait import population_gait, resolve_gait
    foot, ground, up = resolve_gait(plan)
    i = plan.point_index(foot)
    p = np.stack([plan.defaults, plan.defaults])
    p[1, plan.param_index("crank.length")] *= 10.0               # the crank cannot turn
    q = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    s = assur.solve(plan, p[:, None, :], q[:, None], order=1)
    out = population_gait(s.pos[:, :, i, :], s.valid, s.dpos_dq[:, :, i, :, 0], ground=ground, up=up,
                          omega=abs(float(plan.speeds[0])))
    g = gait_metrics(plan)
    assert out["step"][0] == pytest.approx(g.step_length, rel=1e-4)
    assert out["lift"][0] == pytest.approx(g.lift, rel=1e-4)
    assert out["duty"][0] == pytest.approx(g.duty_factor, abs=2 / 720)
    assert out["speed_mean"][0] == pytest.approx(g.support_speed.mean, rel=5e-3)   # sample mean vs time mean
    assert all(np.isnan(v[1]) for v in out.values())


def test_an_extreme_refined_across_an_unplaced_position_keeps_the_grid_sample():
    """The exact extreme is a root of the derivative between two grid samples; where the foot is not placed
    somewhere inside that bracket (a position the solver could not certify: NaN), the grid's sample stands instead
    of the refinement failing (it ended an eight-link leg ranking with scipy's 'function value is NaN')."""
    from assur.analysis.gait import _extreme_location, _extremes

    class Foot:             # x(q) = 1 − (q − 1)², placed everywhere but on (0.99, 1.01)
        @staticmethod
        def eval(q):
            q = np.atleast_1d(np.asarray(q, dtype=float))
            off = (q > 0.99) & (q < 1.01)
            return {"x": np.where(off, np.nan, 1 - (q - 1) ** 2), "dx": np.where(off, np.nan, -2 * (q - 1))}

        def scalar(self, key):
            return lambda q: float(self.eval(q)[key][0])

    q = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    vals = Foot.eval(q)
    i = int(np.argmax(vals["x"]))
    assert _extreme_location(Foot(), "x", "dx", q, vals, "max") == (float(q[i]), float(vals["x"][i]))
    lo, hi = _extremes(Foot(), "x", "dx", q, vals, 0.5, 1.5)
    # the ends (x = 0.75) and the refined root's neighbourhood: the root itself is not placed, so it is left out
    assert np.isfinite(lo) and np.isfinite(hi) and lo == pytest.approx(0.75) and hi < 1.0


class _Arc:
    """A foot whose stride coordinate is x(q) = −cos q on q ∈ [0, π] (dx = sin q), with NaN (an input where the foot is
    not placed) at the inputs listed in ``holes``: the evaluator :func:`window_vx_spread` takes."""

    def __init__(self, holes=()):
        self.holes = np.asarray(holes, dtype=float)

    def eval(self, q):
        q = np.atleast_1d(np.asarray(q, dtype=float))
        out = {"x": -np.cos(q), "dx": np.sin(q), "absdx": np.abs(np.sin(q)), "dabsdx": np.sign(np.sin(q)) * np.cos(q)}
        bad = np.isin(q, self.holes)
        return {k: np.where(bad, np.nan, v) for k, v in out.items()}


@pytest.mark.parametrize("fraction", [0.8, 0.9])
def test_the_window_spread_of_a_closed_form_arc_and_an_unplaced_neighbour(fraction):
    """x = −cos q, |dx| = sin q on [0, π]: the central fraction f of the stride [−1, 1] is q ∈ [acos f, π − acos f],
    where sin q runs from √(1 − f²) up to 1 and its mean is 2f / (π − 2 acos f) (independent integral), so the
    spread is (1 − √(1 − f²))·(π − 2 acos f)/(2f). A sample next to the window's end where the foot is not placed
    (NaN) leaves that end unrefined (its run ends at its own sample): a finite value, not an error."""
    from assur.analysis.gait import window_vx_spread
    exact = (1 - math.sqrt(1 - fraction ** 2)) * (math.pi - 2 * math.acos(fraction)) / (2 * fraction)
    q = np.linspace(0, math.pi, 181)
    assert window_vx_spread(_Arc(), q, _Arc().eval(q), -1.0, 1.0, fraction) == pytest.approx(exact, rel=1e-7)
    first_inside = int(np.argmax(np.abs(np.cos(q)) <= fraction))
    holed = _Arc(holes=[q[first_inside - 1]])
    got = window_vx_spread(holed, q, holed.eval(q), -1.0, 1.0, fraction)
    assert math.isfinite(got) and got < exact       # the lower end stays a sample inside the window: a smaller range
