"""Runs of boolean masks (assur.kernels.runs): on a line and on a ring."""
import numpy as np

from assur.kernels.runs import cyclic_runs, runs


def _runs_by_loop(m):
    out, start = [], None
    for i, v in enumerate(m):
        if v and start is None:
            start = i
        if not v and start is not None:
            out.append((start, i - 1))
            start = None
    if start is not None:
        out.append((start, len(m) - 1))
    return out


def test_runs_on_a_line():
    assert runs([False, True, True, False, True]).tolist() == [[1, 2], [4, 4]]
    assert runs([True, True]).tolist() == [[0, 1]]
    assert runs([False, False]).shape == (0, 2)
    assert runs([]).shape == (0, 2)


def test_runs_agree_with_a_loop_over_random_masks():
    rng = np.random.default_rng(7)
    for _ in range(500):
        m = rng.random(int(rng.integers(1, 40))) < rng.random()
        assert [tuple(r) for r in runs(m).tolist()] == _runs_by_loop(m)


def test_cyclic_runs_join_across_the_seam():
    assert cyclic_runs([True, False, False, True, True]) == [(3, 0)]
    assert cyclic_runs([False, True, False, True]) == [(1, 1), (3, 3)]
    assert cyclic_runs([True, True, True]) == [(0, 2)]
    assert cyclic_runs([False, False]) == []


def test_cyclic_runs_cover_exactly_the_true_samples():
    rng = np.random.default_rng(8)
    for _ in range(500):
        m = rng.random(int(rng.integers(1, 40))) < rng.random()
        n = len(m)
        covered = np.zeros(n, dtype=int)
        for a, b in cyclic_runs(m):
            covered[[(a + k) % n for k in range((b - a) % n + 1)]] += 1
            assert m[a] and m[b] and (n == (b - a) % n + 1 or (not m[(a - 1) % n] and not m[(b + 1) % n]))
        assert np.array_equal(covered, m.astype(int))
