"""L-SHADE (assur.synthesis.shade) and the 'lshade' synthesis method.

References: the test functions' known minima (sphere and Rosenbrock: 0, Rastrigin: 0 at the origin, the bound
handling at a box whose optimum sits on a bound), and paper 000's six-point problem (its lowest Δ1 99.85 mm,
docs/reproduction.md)."""
from pathlib import Path

import numpy as np
import pytest

from assur.synthesis import load_problem, synthesize
from assur.synthesis.shade import FINAL_SIZE, lshade

ROOT = Path(__file__).resolve().parents[1]


class Counted:
    """A vectorised objective that records its calls (population sizes) and every point it is given."""

    def __init__(self, f):
        self.f, self.sizes, self.points = f, [], []

    def __call__(self, X):
        self.sizes.append(len(X))
        self.points.append(X.copy())
        return self.f(X)


def rosenbrock(X):
    return np.sum(100 * (X[:, 1:] - X[:, :-1] ** 2) ** 2 + (1 - X[:, :-1]) ** 2, axis=1)


def rastrigin(X):
    return 10 * X.shape[1] + np.sum(X * X - 10 * np.cos(2 * np.pi * X), axis=1)


@pytest.mark.parametrize("f, bounds, budget, tol", [
    (lambda X: np.sum(X * X, axis=1), [(-5, 5)] * 5, 20_000, 1e-12),
    (rosenbrock, [(-5, 5)] * 4, 60_000, 1e-8),
    (rastrigin, [(-5.12, 5.12)] * 4, 60_000, 1e-8),
])
def test_lshade_finds_the_known_minima(f, bounds, budget, tol):
    fc = Counted(f)
    x, fx = lshade(fc, bounds, np.random.default_rng(3), budget)
    assert fx <= tol and f(x[None, :])[0] == fx
    assert sum(fc.sizes) <= budget + fc.sizes[0]                   # the budget holds (one generation over at most)
    assert fc.sizes[0] == 18 * len(bounds)                          # the paper's initial population
    assert fc.sizes[-1] <= max(FINAL_SIZE, 18 * len(bounds) // 4)   # and its linear reduction
    assert all(np.all((P >= np.array(bounds)[:, 0]) & (P <= np.array(bounds)[:, 1])) for P in fc.points)


def test_lshade_reaches_an_optimum_on_a_bound():
    lo, hi = np.full(3, 1.0), np.full(3, 4.0)
    x, fx = lshade(lambda X: np.sum(X * X, axis=1), np.stack([lo, hi], 1), np.random.default_rng(0), 15_000)
    assert np.allclose(x, 1.0, atol=1e-6) and fx == pytest.approx(3.0, abs=1e-5)


@pytest.mark.slow
def test_the_lshade_method_on_paper000():
    r = synthesize(load_problem(ROOT / "examples" / "synthesis" / "paper000_six_points.toml"), "lshade", seed=1)
    assert r.settings["method"] == "lshade" and r.settings["budget"] == 20_000      # the file's [solver] budget
    assert r.feasible and r.objective <= 99.85 and r.evaluations <= 20_000 + 200
    assert r.starts[0]["restarts"] >= 1
