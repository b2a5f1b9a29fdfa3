"""The certified grid of the one-parameter reduction (assur.kernels.reduction.bracket) on programs small enough to
solve by hand: a sample whose enclosures cannot tighten (a continuum of roots) is given up on its own, the other
samples of the batch keep their clusters, and a batch too large for the cell budget is bracketed in halves with the
same result."""
from __future__ import annotations

import numpy as np

from assur.kernels.reduction import bracket

#: X = P + e^{iφ} (a unit crank about P), cut: |X − Y| = 1
PROGRAM = [("rot", "X", "P", 1 + 0j), ("cut", "X", "Y", 1.0)]


def test_a_continuum_of_roots_is_given_up_alone():
    # Y = P + 0.5: |e^{iφ} − 0.5| = 1 ⇔ cos φ = 1/4, two roots (by hand); Y = P: |e^{iφ}| = 1 for every φ
    y = np.array([0.5, 0.0, 0.5])
    sample, sgn, lo, hi, change, untightened = bracket(PROGRAM, 0, {"P": 0.0, "Y": y}, 3)
    assert untightened.tolist() == [False, True, False]
    assert 1 not in sample.tolist()
    roots = np.sort([np.arccos(0.25), 2 * np.pi - np.arccos(0.25)])
    for s in (0, 2):
        mid = np.sort(0.5 * (lo[sample == s] + hi[sample == s]))
        assert np.allclose(mid, roots, atol=1e-8) and np.all(change[sample == s])


def test_a_batch_over_the_cell_budget_is_bracketed_in_halves():
    y = 0.5 * np.exp(1j * np.linspace(0, 2 * np.pi, 9, endpoint=False))
    whole = bracket(PROGRAM, 0, {"P": 0.0, "Y": y}, 9)
    halves = bracket(PROGRAM, 0, {"P": 0.0, "Y": y}, 9, max_cells=400)
    assert len(whole[0]) == len(halves[0]) == 18
    for a, b in zip(whole, halves):
        assert np.array_equal(a, b)


def test_the_halving_is_taken(monkeypatch):
    """The budget of the test above is below the first grid (9 samples × 64 cells): the halves are what ran."""
    from assur.kernels import reduction
    y = 0.5 * np.exp(1j * np.linspace(0, 2 * np.pi, 9, endpoint=False))
    calls = []
    real = reduction._bracket

    def counting(*args):
        calls.append(args[3])
        return real(*args)
    monkeypatch.setattr(reduction, "_bracket", counting)
    bracket(PROGRAM, 0, {"P": 0.0, "Y": y}, 9, max_cells=400)
    assert calls == [9, 4, 5]
