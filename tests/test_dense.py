"""The element-wise dense solve the compiled Newton kernels trace (assur.kernels.dense): Gaussian elimination with
partial pivoting on rows of numbers, batched arrays or traced symbols. References: numpy.linalg.solve and det
(LAPACK) on the same matrices; the traced lines run as plain Python (tests/test_trace.py's as_function)."""
import math

import numpy as np
import pytest

from assur.kernels import dense
from assur.kernels import trace as T
from test_trace import as_function


def _structured(rng, n, batch):
    """A batch of random n × n matrices whose structure a traced Jacobian has: some entries the number 0, some ±1
    (the same for every sample), the rest varying. Returns (rows of entries, the (batch, n, n) array)."""
    A = rng.standard_normal((batch, n, n))
    rows = [[A[:, i, j] for j in range(n)] for i in range(n)]
    kind = rng.uniform(size=(n, n))
    for i in range(n):
        for j in range(n):
            if i != j and kind[i, j] < 0.35:
                c = float(rng.choice([0.0, 1.0, -1.0]))
                rows[i][j] = c
                A[:, i, j] = c
    return rows, A


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 12])
def test_solve_and_determinant_equal_lapack_on_batches(n):
    rng = np.random.default_rng(n)
    rows, A = _structured(rng, n, 200)
    b = rng.standard_normal((200, n))
    lu = dense.factor(rows)
    x = np.stack(np.broadcast_arrays(*lu.solve([b[:, i] for i in range(n)])), axis=-1)
    ref = np.linalg.solve(A, b[..., None])[..., 0]
    cond = np.linalg.cond(A)
    assert np.all(np.abs(x - ref) <= 1e-13 * cond[:, None] * np.maximum(1.0, np.abs(ref)))
    det = np.broadcast_to(lu.det, (200,))
    np.testing.assert_allclose(det, np.linalg.det(A), rtol=1e-12 * n)


def test_columns_of_numbers_are_pivoted_without_a_select():
    """A matrix whose x columns hold only numbers (the ±1 of loop equations) and one varying column: the numbers'
    columns are eliminated first on a pivot chosen now, so the traced program has no select at all; it computes
    numpy's solution."""
    tr = T.Tracer()
    a, b = tr.free("a"), tr.free("b")
    rows = [[1.0, 0.0, a], [-1.0, 1.0, b], [0.0, -1.0, 1.0]]
    f = [tr.free("f0"), tr.free("f1"), tr.free("f2")]
    lu = dense.factor(rows)
    x = lu.solve(f)
    lines = tr.needed(x + [lu.det])
    assert not any(" if " in ln.expr for ln in lines)
    fn = as_function(tr, ["a", "b", "f0", "f1", "f2"], x + [lu.det])
    rng = np.random.default_rng(1)
    for _ in range(20):
        av, bv, *fv = rng.standard_normal(5)
        M = np.array([[1.0, 0.0, av], [-1.0, 1.0, bv], [0.0, -1.0, 1.0]])
        got = fn(av, bv, *fv)
        np.testing.assert_allclose(got[:3], np.linalg.solve(M, fv), rtol=1e-12, atol=1e-12)
        assert math.isclose(got[3], np.linalg.det(M), rel_tol=1e-12, abs_tol=1e-14)


def test_traced_pivoting_picks_the_largest_entry_per_sample():
    """Varying pivots are chosen per sample by selects: the traced program solves every sample of random 4 × 4
    systems, including ones whose first candidate pivot is 0 (where an elimination without pivoting divides by 0)."""
    n = 4
    tr = T.Tracer()
    names = [f"a{i}{j}" for i in range(n) for j in range(n)] + [f"f{i}" for i in range(n)]
    syms = [tr.free(nm) for nm in names]
    rows = [syms[i * n:(i + 1) * n] for i in range(n)]
    lu = dense.factor(rows)
    x = lu.solve(syms[n * n:])
    fn = as_function(tr, names, x + [lu.det])
    rng = np.random.default_rng(2)
    for k in range(50):
        M = rng.standard_normal((n, n))
        if k % 5 == 0:
            M[0, 0] = 0.0
        f = rng.standard_normal(n)
        got = fn(*M.ravel(), *f)
        np.testing.assert_allclose(got[:n], np.linalg.solve(M, f), rtol=1e-10, atol=1e-12)
        assert math.isclose(got[n], np.linalg.det(M), rel_tol=1e-12)


def test_a_column_without_any_entry_is_singular():
    lu = dense.factor([[1.0, 0.0], [2.0, 0.0]])
    assert lu.singular and lu.det == 0.0
    assert all(math.isnan(v) for v in lu.solve([1.0, 1.0]))
