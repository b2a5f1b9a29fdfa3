"""A Monte Carlo of the tolerances on the batched engine: where the first-order envelope holds, and where not.

Each sample is a design p₀ + δ with every δ_k drawn uniformly in its zone ±t_k (or normally, σ = t_k/3); the run's
inputs are solved for a whole population at once (``assur.solve`` with params (S, 1, P) and inputs (1, n, 1): the
compiled backend for large batches), in chunks so that memory stays bounded, keeping only what the comparison needs:
per input, the smallest and largest deviation of the point from its nominal position along the path's normal, and
how many samples leave the worst-case band. A sample that cannot be assembled somewhere on the run is not buildable;
the buildable fraction is reported and those samples are left out of the deviations.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...engine import solve
from .tolerance import PathBand, Tolerances


@dataclass(frozen=True)
class MonteCarlo:
    """``samples`` drawn, ``buildable`` of them assembled over the whole run; per input (n,): ``low``, ``high`` the
    extreme deviations along the path's normal (m), ``outside`` the fraction of buildable samples beyond the
    worst-case band, ``ratio`` = max |deviation| / worst-case half-width."""
    point: str
    samples: int
    buildable: int
    low: np.ndarray
    high: np.ndarray
    outside: np.ndarray
    ratio: np.ndarray

    @property
    def buildable_fraction(self) -> float:
        return self.buildable / self.samples if self.samples else float("nan")

    def failures(self, q) -> list[float]:
        """The inputs (rad or m) where some sample leaves the first-order worst-case band."""
        return [float(x) for x in np.asarray(q)[self.outside > 0]]


def monte_carlo(study, band: PathBand, tol: Tolerances, samples: int = 10000, *, seed: int = 1,
                distribution: str = "uniform", chunk: int = 20000, backend: str = "auto") -> MonteCarlo:
    """The Monte Carlo of ``tol`` on ``band.point``'s path over ``study``'s run (see the module docstring)."""
    plan = study.plan
    rng = np.random.default_rng(seed)
    i = plan.point_index(band.point)
    inputs = study.inputs
    n = len(inputs)
    low, high = np.full(n, np.inf), np.full(n, -np.inf)
    beyond = np.zeros(n)
    good = 0
    p0 = np.asarray(study.params, dtype=float)
    eps = 1e-12 * plan.length_scale
    for start in range(0, samples, chunk):
        S = min(chunk, samples - start)
        if distribution == "normal":
            d = rng.normal(0.0, 1.0, (S, plan.n_params)) * (tol.half / 3.0)
        else:
            d = rng.uniform(-1.0, 1.0, (S, plan.n_params)) * tol.half
        st = solve(plan, (p0 + d)[:, None, :], inputs[None, :, :], order=0, backend=backend,
                   on_unbuildable="nan")
        ok = np.all(np.asarray(st.valid), axis=1)
        good += int(ok.sum())
        z = st.pos[ok, :, i, 0] + 1j * st.pos[ok, :, i, 1]                    # (S_ok, n)
        dev = np.real(np.conj(band.normal)[None, :] * (z - band.path[None, :]))
        if len(dev):
            low = np.minimum(low, dev.min(axis=0))
            high = np.maximum(high, dev.max(axis=0))
            beyond += np.sum(np.abs(dev) > band.worst[None, :] + eps, axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.maximum(np.abs(low), np.abs(high)) / band.worst
        outside = beyond / good if good else np.full(n, np.nan)
    return MonteCarlo(band.point, samples, good, low, high, outside, ratio)
