"""Function generation by slider-cranks (assur.synthesis.exact.slider_function_generation), checked against
independent closed-form computations written here.

Reference: the slider-crank loop closure. A crank A0A = a at the angle φ from the slide line's direction, a rod
AB = b, the pin B on the line y = e (A0 at the origin): B = (s, e) with (s − a cos φ)² + (e − a sin φ)² = b², so
s = a cos φ ± √(b² − (e − a sin φ)²), the sign fixing the assembly branch (Uicker, Pennock & Shigley, *Theory of
Machines and Mechanisms*, the offset slider-crank's position analysis; Norton, *Design of Machinery*, §4.6).
The function :func:`slider_position` below computes it without the engine.

Textbook examples: no published worked example of function generation (Freudenstein's equation with three
precision points) or of three-position motion generation could be read here with both its complete data and its
printed result, so none is reproduced; the exact four-bar methods are checked against independent solves in
tests/test_synthesis_exact.py.
"""
import numpy as np
import pytest

import assur
from assur.errors import SpecError
from assur.synthesis import exact
from assur.synthesis.freudenstein import chebyshev_points

# a known offset slider-crank (crank + |offset| < rod: the crank turns fully)
CRANK, ROD, OFFSET = 1.0, 3.0, 0.5


def slider_position(phi, a=CRANK, b=ROD, e=OFFSET, ahead=True):
    """The slider's position along the line (from the foot of A0's perpendicular), closed form."""
    root = np.sqrt(b * b - (e - a * np.sin(phi)) ** 2)
    return a * np.cos(phi) + (root if ahead else -root)


def engine_positions(mechanism, phi):
    st = assur.solve(assur.compile(mechanism), inputs=np.asarray(phi, float), order=0)
    B = st.point("B").pos
    return B[:, 0], B[:, 1]


@pytest.mark.parametrize("ahead", [True, False])
def test_three_pairs_of_a_known_slider_crank_give_it_back(ahead):
    phis = np.array([0.3, 1.0, 1.7])
    sols = exact.slider_candidates(phis, slider_position(phis, ahead=ahead))
    assert len(sols) == 1
    s = sols[0]
    assert np.allclose([s.crank, s.rod, s.offset], [CRANK, ROD, OFFSET], atol=1e-9)
    assert s.kind == "crank-slider" and s.residual < 1e-9
    # the loop closure holds at the precision points with the returned dimensions
    assert np.allclose((slider_position(phis, ahead=ahead) - s.crank * np.cos(phis)) ** 2
                       + (s.offset - s.crank * np.sin(phis)) ** 2, s.rod ** 2, atol=1e-9)
    # the engine's mechanism, driven by φ, reproduces the displacements on the whole stretch, on the slide line
    dense = np.linspace(0.3, 1.7, 29)
    x, y = engine_positions(s.mechanism, dense)
    assert np.allclose(x, slider_position(dense, ahead=ahead), atol=1e-9)
    assert np.allclose(y, OFFSET, atol=1e-12)


def test_mechanism_has_the_documented_names_and_input():
    phis = np.array([0.3, 1.0, 1.7])
    m = exact.slider_function_generation(phis, slider_position(phis))[0]
    pts = dict(m.points)
    assert set(pts) == {"A0", "A", "B"}
    assert np.allclose(pts["A0"], [0, 0]) and np.allclose(pts["B"], [slider_position(0.3), OFFSET])
    assert np.allclose(pts["A"], [CRANK * np.cos(0.3), CRANK * np.sin(0.3)])
    (driver,) = m.drivers
    assert driver.pivot == "A0" and driver.arm == "A" and driver.zero == 0


def test_least_squares_for_more_points_is_exact_on_exact_data():
    phis = np.linspace(-0.4, 2.0, 7)
    s = exact.slider_candidates(phis, slider_position(phis))[0]
    assert np.allclose([s.crank, s.rod, s.offset], [CRANK, ROD, OFFSET], atol=1e-9)
    x, _ = engine_positions(s.mechanism, phis)
    assert np.allclose(x, slider_position(phis), atol=1e-9)


def test_least_squares_on_a_non_slider_crank_task_has_a_residual():
    """Positions that no slider-crank meets exactly (s = 2 + 0.8 φ, a straight line in φ): the least-squares
    design is returned with its engine residual, which is non-zero and equals the largest error at the points."""
    phis = np.linspace(0.2, 1.6, 6)
    want = 2.0 + 0.8 * phis
    sols = exact.slider_candidates(phis, want)
    assert sols
    s = sols[0]
    x, _ = engine_positions(s.mechanism, phis)
    assert s.residual > 1e-6
    assert s.residual == pytest.approx(np.max(np.abs(x - want)), rel=1e-9, abs=1e-12)


def test_negative_fitted_crank_points_the_other_way_and_the_input_stays_phi():
    """Positions of the known slider-crank at φ, given against the inputs φ + π: the fit has a < 0, returned as
    the crank a > 0 pointing along φ + π (driver zero = π), so the driver's input is still the given angle."""
    phis = np.array([0.3, 1.0, 1.7])
    s = exact.slider_candidates(phis + np.pi, slider_position(phis))[0]
    assert np.allclose([s.crank, s.rod, s.offset], [CRANK, ROD, OFFSET], atol=1e-9)
    assert s.mechanism.drivers[0].zero == pytest.approx(np.pi)
    x, _ = engine_positions(s.mechanism, phis + np.pi)
    assert np.allclose(x, slider_position(phis), atol=1e-9)


def test_chebyshev_spacing_and_start_offsets():
    lo, hi = 0.2, 1.8
    sols = exact.slider_candidates((lo, hi), slider_position, spacing="chebyshev", n=3)
    assert np.allclose(sols[0].inputs, chebyshev_points(3, lo, hi))
    assert np.allclose([sols[0].crank, sols[0].rod, sols[0].offset], [CRANK, ROD, OFFSET], atol=1e-9)
    # the same task as changes from a start (φ0, s0): positions relative to the first one, angles from φ0
    phis = np.array([0.3, 1.0, 1.7])
    s_abs = slider_position(phis)
    rel = exact.slider_candidates(phis - 0.3, s_abs - s_abs[0], starts=[(0.3, s_abs[0])])
    assert np.allclose([rel[0].crank, rel[0].rod, rel[0].offset], [CRANK, ROD, OFFSET], atol=1e-9)


def test_a_toggle_between_the_precision_points_is_rejected():
    """A rocker-slider (crank 2 > rod 1.2): it assembles only while |e − a sin φ| < b, i.e. sin φ < 0.85 for
    e = 0.5. The points φ = 0, 0.5, π − 0.5 are each buildable, and their positions are met exactly by that
    design, but between 0.5 and π − 0.5 the crank passes sin φ = 1 > 0.85: a toggle, so no design is kept."""
    a, b, e = 2.0, 1.2, 0.5
    phis = np.array([0.0, 0.5, np.pi - 0.5])
    assert np.all(np.abs(e - a * np.sin(phis)) < b)
    assert np.abs(e - a * np.sin(np.pi / 2)) > b
    s = slider_position(phis, a, b, e)
    assert exact.slider_candidates(phis, s) == []
    # the first two points alone, with a third inside the buildable stretch, are kept (a rocker-slider)
    ok = np.array([0.0, 0.3, 0.5])
    kept = exact.slider_candidates(ok, slider_position(ok, a, b, e))
    assert kept and kept[0].kind == "rocker-slider"
    assert np.allclose([kept[0].crank, kept[0].rod, kept[0].offset], [a, b, e], atol=1e-9)


@pytest.mark.parametrize("call, where", [
    (lambda: exact.slider_function_generation([0, 1, 2], [1, 2]), "displacements"),
    (lambda: exact.slider_function_generation([0, 1], [1, 2]), "inputs"),
    (lambda: exact.slider_function_generation([0, 1, 0.5], [1, 2, 3]), "inputs"),
    (lambda: exact.slider_function_generation([0, 1, 2], [1, np.nan, 3]), "inputs"),
    (lambda: exact.slider_function_generation([0, 1, 2], ["a", "b", "c"]), "inputs"),
    (lambda: exact.slider_function_generation((0, 1), [1, 2, 3], spacing="chebyshev"), "displacements"),
    (lambda: exact.slider_function_generation((0, 1), slider_position, spacing="cheb"), "spacing"),
    (lambda: exact.slider_function_generation([0, 1, 2], [1, 2, 3], starts=[1, 2, 3]), "starts"),
])
def test_bad_input_is_a_spec_error_naming_the_argument(call, where):
    with pytest.raises(SpecError, match=where):
        call()


def test_a_branch_defect_is_rejected():
    """Positions of the known slider-crank taken on its two assembly branches (B ahead of A's foot at the first
    two points, behind it at the third): the loop closure fits them exactly, but no single branch carries the
    slider through them, so the design is rejected; all three on one branch are kept."""
    phis = np.array([0.3, 1.0, 1.7])
    mixed = np.array([slider_position(0.3), slider_position(1.0), slider_position(1.7, ahead=False)])
    assert exact.slider_candidates(phis, mixed) == []
    assert exact.slider_candidates(phis, slider_position(phis))
