"""Optimisers for synthesis problems: thin adapters over scipy's differential evolution, CMA-ES
(``cma``) and a local polish (least squares, Nelder–Mead or L-BFGS-B), with multi-start, a seed,
a progress bar, a budget of evaluations or of time, and Ctrl-C — none of which loses the best
design found so far: every evaluated population passes through one :class:`Tracker` that keeps it.

    result = synthesize(problem, seed=1)          # the defaults (or method="de", budget=200_000, starts=4, …)

Settings not given come from the problem file's ``[solver]`` table, then from the built-in defaults
(:mod:`assur.synthesis.solver`). The default method, 'restart', runs differential evolution restarted on
stagnation (each restart from a fresh Latin-hypercube population), polishes each restart's best and goes on
until the budget, the time limit or the target ends the run: a converged population does not end the run, it
only starts the next restart.

Designs are compared by Deb's feasibility rules (feasible beats infeasible; two infeasible by total
violation; two feasible by objective), which is exactly the order of the penalised scalar F.
"""
from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from ..errors import SynthesisError, require
from .evaluate import Evaluation, Evaluator
from .executors import InProcess
from .problem import Problem
from .result import SynthesisResult, bounds_reached
from .space import SearchSpace
from .solver import DE_STRATEGIES, METHODS, POLISHES, resolve

#: a restart of the 'restart' method ends when its best improved by less than RESTART_TOL (relative) over
#: RESTART_PATIENCE generations (stagnation)
RESTART_TOL, RESTART_PATIENCE = 1e-3, 60

#: a restart also ends as soon as its best lies within KNOWN_BASIN_RADIUS (a fraction of each variable's range,
#: in every variable) of the design an earlier restart ended on, without being better: it is settling into a basin
#: already searched, and the budget left goes to a fresh population instead
KNOWN_BASIN_RADIUS = 0.05


class _Stop(Exception):
    def __init__(self, reason):
        self.reason = reason


@dataclass
class StartResult:
    """The outcome of one start (picklable, returned by worker processes). ``x`` is None for a start that began
    after the run's deadline had passed (it evaluated nothing). ``longest_batch``: the longest evaluation of one
    population (s); ``first_batch_end``: the wall-clock time (``time.time()``) its first population was done."""
    seed: int
    x: np.ndarray | None
    penalised: float
    evaluations: int
    seconds: float
    stopped: str
    history: list
    restarts: int = 0
    longest_batch: float = 0.0
    first_batch_end: float | None = None


class Tracker:
    """Evaluates populations through an executor, counts them, keeps the best design, records the
    convergence history and stops the run on a budget, a deadline or Ctrl-C.

    ``deadline``: the wall-clock time (``time.time()``, comparable across the processes of one machine and the
    machines of a cluster with synchronised clocks) after which no further population is evaluated; the first
    population is always evaluated, so a run always has a design. A run therefore ends at most one evaluation
    batch (``longest_batch``) after its deadline, or one batch after its first population when that comes later."""

    def __init__(self, evaluator: Evaluator, executor=None, *, budget=None, deadline=None, progress=None,
                 evaluations: int = 0, target=None, space: SearchSpace | None = None):
        self.evaluator, self.executor = evaluator, executor or InProcess()
        self.space = space or SearchSpace(evaluator.problem)   # what the optimiser's vectors hold
        self.budget, self.deadline, self.progress, self.target = budget, deadline, progress, target
        self.evaluations = evaluations
        self.best_x, self.best_F = None, math.inf
        self.restarts = 0                  # restarts begun (the 'restart' method)
        self.history: list[tuple[int, float, float]] = []
        self.t0 = time.monotonic()
        self.longest_batch, self.first_batch_end = 0.0, None

    def __call__(self, X, detail: bool = False) -> Evaluation:
        if self.budget is not None and self.evaluations >= self.budget:
            raise _Stop("budget")
        if self.deadline is not None and self.best_x is not None and time.time() >= self.deadline:
            raise _Stop("time")
        X = self.space.expand(np.atleast_2d(np.asarray(X, dtype=float)))     # search vectors → design vectors
        t = time.monotonic()
        ev = self.executor.evaluate(self.evaluator, X, detail)
        self.longest_batch = max(self.longest_batch, time.monotonic() - t)
        if self.first_batch_end is None:
            self.first_batch_end = time.time()
        self.evaluations += len(X)
        i = int(np.argmin(ev.penalised))
        if ev.penalised[i] < self.best_F:       # the whole design, its solved timing included
            self.best_F = float(ev.penalised[i])
            self.best_x = ev.x[i].copy() if ev.x is not None else self.evaluator.wrap(X[i])
        self.history.append((self.evaluations, time.monotonic() - self.t0, self.best_F))
        if self.progress is not None:
            self.progress(self.evaluations, self.best_F)
        if self.target is not None and self.best_F <= self.target:
            raise _Stop("target")
        return ev

    def F(self, X) -> np.ndarray:
        return self(X).penalised


def _unit_box(problem):
    lo, hi = problem.bounds.T
    return lo, hi - lo


def initial_population(problem, size, rng) -> np.ndarray:
    """A Latin-hypercube population (size, n_vars) in the bounds. With free timing in cyclic order
    each member's crank angles are sorted, so it passes the targets in order (as the HCDJ code does;
    only 1/N! of unsorted angle sets are in order)."""
    from scipy.stats import qmc
    lo, hi = problem.bounds.T
    X = lo + qmc.LatinHypercube(d=problem.n_vars, rng=rng).random(size) * (hi - lo)
    t = problem.targets
    if (t is not None and t.timing == "free" and {"cyclic_order", "cyclic_order_any", "ascending"} & set(problem.constraints)
            and set(t.input_variables) <= set(problem.names)):          # explicit timing: the angles are searched
        cols = [problem.names.index(n) for n in t.input_variables]
        X[:, cols] = np.sort(X[:, cols], axis=1)
    return X


def _run_de(tracker, problem, rng, popsize, maxiter, tol, patience=100, strategy="best1bin", polish=True,
            known=None):
    """One scipy DE run; returns its best design (SI) when it ends by itself (stagnation or maxiter).

    ``known``: a list of (x (k,), F) the designs earlier restarts ended on; the run stops when its best comes within
    KNOWN_BASIN_RADIUS of one of them without being better; a run that ends by itself appends its end to the list."""
    from scipy.optimize import differential_evolution
    D = problem.n_vars
    bounds = list(map(tuple, problem.bounds))
    pop = max(5, popsize) * D
    if tracker.budget is not None:   # whole generations within the budget, less a fifth for the polish
        share = 0.8 if polish else 1.0
        maxiter = min(maxiter, max(1, int(share * (tracker.budget - tracker.evaluations)) // pop - 1))
    history, repeated = [], False
    _, width = _unit_box(problem)
    periodic = np.array([v.periodic for v in problem.variables], dtype=bool)

    def in_known_basin(x, f) -> bool:
        for xk, fk in known or ():
            d = (x - xk) / width
            d = np.where(periodic, (d + 0.5) % 1.0 - 0.5, d)
            if np.max(np.abs(d)) <= KNOWN_BASIN_RADIUS and f >= fk - tol * max(abs(fk), 1e-300):
                return True
        return False

    def stalled(intermediate_result):
        """Stop when the best has improved by less than tol (relative) over the last ``patience`` generations, or
        when it has settled into a known basin."""
        nonlocal repeated
        history.append(float(intermediate_result.fun))
        if known and in_known_basin(np.asarray(intermediate_result.x, dtype=float), history[-1]):
            repeated = True
            return True
        if len(history) <= patience:
            return False
        old, new = history[-patience - 1], history[-1]
        return old - new <= tol * max(abs(old), 1e-300)
    # scipy's spread test off (atol < 0): all infeasible by one penalty is no convergence; ``stalled`` decides
    out = differential_evolution(lambda x: tracker.F(x.T), bounds, vectorized=True, updating="deferred", popsize=popsize,
                           maxiter=maxiter, tol=0.0, atol=-1.0, rng=rng, polish=False,
                           init=initial_population(problem, pop, rng),
                           mutation=(0.5, 1.0), recombination=0.9, callback=stalled, strategy=strategy)
    x = np.asarray(out.x, dtype=float)
    if known is not None and not repeated:
        known.append((x, float(out.fun)))
    return x


def _run_restarts(tracker, problem, rng, options):
    """The 'restart' method: DE restarted on stagnation until the tracker stops the run (budget, time, target).

    Each restart draws a fresh Latin-hypercube population of ``popsize`` per variable and ends when its best has
    improved by less than RESTART_TOL (relative) over RESTART_PATIENCE generations; its best is then polished
    and the next restart begins. Many short restarts, each polished, find narrow basins (C1's exact optimum) that
    one long run misses; a converged population never ends the run."""
    k, known = 0, []
    while True:
        k += 1
        tracker.restarts = k
        ends = len(known)
        x = _run_de(tracker, problem, rng, options["popsize"], options["maxiter"], RESTART_TOL, RESTART_PATIENCE,
                    options["strategy"], known=known)
        if options["polish"] != "none" and len(known) > ends:      # a restart in a known basin has nothing to polish
            _polish(tracker, problem, x.copy(), options["polish"])

def _run_lshade(tracker, problem, rng, options):
    """The 'lshade' method: L-SHADE (:mod:`assur.synthesis.shade`) restarted until the tracker stops the run, each
    restart's best polished; restart k gets LSHADE_FIRST·2^k evaluations (a sixteenth of the budget for the first,
    at least 10 000), so its population shrinks over a growing span."""
    from .shade import lshade
    first = max(10_000, (tracker.budget or 160_000) // LSHADE_FIRST)
    k = 0
    while True:
        tracker.restarts = k + 1
        span = first * 2 ** k
        if tracker.budget is not None:
            left = tracker.budget - tracker.evaluations
            span = min(span, max(left - left // 5, 1))        # a fifth of what is left for the polish
        x, _ = lshade(tracker.F, problem.bounds, rng, span, initial=initial_population(
            problem, max(4, 18 * problem.n_vars), rng))
        if options["polish"] != "none":
            _polish(tracker, problem, x.copy(), options["polish"])
        k += 1


#: the 'lshade' method's first restart gets this fraction of the budget
LSHADE_FIRST = 16

#: how to install the optional packages of the synthesis
CMA_INSTALL = "pip install cma (or pip install 'assur[synth]')"
TQDM_INSTALL = "pip install tqdm (or pip install 'assur[synth]')"


def _run_cmaes(tracker, problem, rng, popsize, maxiter, tol):
    cma = require("cma", "the CMA-ES method (cmaes)", CMA_INSTALL)
    lo, width = _unit_box(problem)
    D = problem.n_vars
    x0 = rng.uniform(0.2, 0.8, D)
    opts = {"bounds": [0.0, 1.0], "seed": int(rng.integers(1, 2**31 - 1)), "verbose": -9, "maxiter": maxiter,
            "tolfun": tol, "tolx": 1e-13}
    if popsize:
        opts["popsize"] = max(4, popsize * D // 3)
    if tracker.budget is not None:
        opts["maxfevals"] = int(0.8 * (tracker.budget - tracker.evaluations))
    es = cma.CMAEvolutionStrategy(x0, 0.3, opts)
    while not es.stop():
        U = np.asarray(es.ask())
        es.tell(list(U), tracker.F(lo + U * width).tolist())


def _residuals(tracker, problem):
    """Least-squares residuals of the squared-deviation objective (n, 2N), barrier if infeasible."""
    w = math.sqrt(max(problem.deviation_weight, 0.0))

    def res(X):
        ev = tracker(X, detail=True)
        r = ev.quantities["offsets"].reshape(len(X), -1) * w
        bad = ~ev.feasible
        if bad.any():
            r[bad] = np.sqrt(ev.penalised[bad, None] / r.shape[1])
        return r
    return res


def _polish(tracker, problem, x0, kind):
    """Local refinement from x0 (SI); the tracker keeps whatever is best."""
    from scipy.optimize import least_squares, minimize
    if kind == "auto":
        smooth_ls = (problem.deviation == "squared" and not problem.terms and problem.targets is not None
                     and problem.targets.timing != "path")
        kind = "least_squares" if smooth_ls else "nelder-mead"
    periodic = np.array([v.periodic for v in problem.variables])
    lo, hi = problem.bounds.T
    lo = np.where(periodic, -np.inf, lo)
    hi = np.where(periodic, np.inf, hi)
    x0 = np.clip(x0, lo, hi)                      # periodic angles: unbounded
    scale = np.where(np.isfinite(hi - lo), hi - lo, 2 * np.pi)
    if kind == "least_squares":
        res = _residuals(tracker, problem)

        def jac(x):
            h = 1e-7 * np.maximum(np.abs(x), scale * 1e-3)
            X = np.vstack([x + np.diag(h), x - np.diag(h)])
            R = res(X)
            D = len(x)
            return ((R[:D] - R[D:]) / (2 * h[:, None])).T
        best = math.inf
        while True:   # restart trf until a round no longer improves (the tracker's budget/deadline still stop it)
            out = least_squares(lambda x: res(x[None, :])[0], x0, jac=jac, bounds=(lo, hi), method="trf",
                                x_scale=scale, xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=500)
            cost = float(out.cost)
            if not cost < best * (1 - 1e-6) or cost == 0.0:
                break
            best, x0 = cost, np.clip(out.x, lo, hi)
    elif kind == "nelder-mead":
        simplex = np.vstack([x0, x0 + np.diag(0.02 * scale)])
        minimize(lambda x: tracker.F(x[None, :])[0], x0, method="Nelder-Mead",
                 options={"initial_simplex": simplex, "xatol": 1e-10, "fatol": 1e-12, "maxfev": 400 * len(x0),
                          "adaptive": len(x0) > 4})
    elif kind == "l-bfgs-b":
        def fg(x):
            h = 1e-7 * np.maximum(np.abs(x), scale * 1e-3)
            F = tracker.F(np.vstack([x, x + np.diag(h), x - np.diag(h)]))
            D = len(x)
            return F[0], (F[1:D + 1] - F[D + 1:]) / (2 * h)
        minimize(fg, x0, jac=True, method="L-BFGS-B", bounds=list(zip(lo, hi)),
                 options={"maxiter": 500, "ftol": 1e-15, "gtol": 1e-12})


def run_start(problem, method, seed, budget, time_limit, options, evaluator=None, executor=None, progress=None):
    """One independent start: a global search then a polish. Returns a StartResult (picklable).

    ``time_limit``: seconds from now; ``options["deadline"]``, when given, is the run's common wall-clock deadline
    (``time.time()``) instead. A start that begins after that deadline (a start queued behind others on busy
    workers) evaluates nothing and returns ``x = None``, unless ``options["first"]`` says it must give the run its
    first design."""
    deadline = options.get("deadline")
    if deadline is None and time_limit is not None:
        deadline = time.time() + time_limit
    if deadline is not None and time.time() >= deadline and not options.get("first", True):
        return StartResult(int(seed), None, math.inf, 0, 0.0, "time", [])
    evaluator = evaluator or Evaluator(problem, backend=options.get("backend"))
    space = SearchSpace(problem)                 # the optimisers see the searched variables only
    tracker = Tracker(evaluator, executor, budget=budget, deadline=deadline, progress=progress,
                      target=options.get("target"), space=space)
    rng = np.random.default_rng(seed)
    stopped = "converged"
    problem = space
    try:
        if method == "restart":
            _run_restarts(tracker, problem, rng, options)
        elif method == "lshade":
            _run_lshade(tracker, problem, rng, options)
        elif method == "de":
            _run_de(tracker, problem, rng, options["popsize"], options["maxiter"], options["tol"],
                    options["patience"], options["strategy"], polish=options["polish"] != "none")
        elif method == "cmaes":
            _run_cmaes(tracker, problem, rng, options["popsize"], options["maxiter"], options["tol"])
        elif method == "local":
            x0 = None if options.get("x0") is None else space.reduce(options["x0"])
            if x0 is None:
                lo, width = _unit_box(problem)
                x0 = lo + rng.uniform(0.2, 0.8, problem.n_vars) * width
            tracker(np.asarray(x0, dtype=float)[None, :])
        if method not in ("restart", "lshade") and options["polish"] != "none" and tracker.best_x is not None:
            _polish(tracker, problem, space.reduce(tracker.best_x).copy(), options["polish"])
    except _Stop as stop:
        stopped = stop.reason
    except KeyboardInterrupt:
        stopped = "interrupted"
    if tracker.best_x is None:
        raise SynthesisError(f"no design was evaluated (stopped: {stopped}); raise the budget or the time limit")
    return StartResult(int(seed), tracker.best_x, tracker.best_F, tracker.evaluations,
                       time.monotonic() - tracker.t0, stopped, tracker.history, tracker.restarts,
                       tracker.longest_batch, tracker.first_batch_end)


def _check_seed(seed) -> None:
    """SettingError unless ``seed`` is None, a whole number ≥ 0 or a sequence of them (numpy's SeedSequence)."""
    from ..errors import SettingError

    def whole(v):
        return isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 0
    if seed is None or whole(seed) or isinstance(seed, np.random.SeedSequence):
        return
    if isinstance(seed, (list, tuple)) and seed and all(whole(v) for v in seed):
        return
    raise SettingError([("seed", f"must be a whole number ≥ 0 (or None for a random run): {seed!r:.60}")])


def _progress_bar(total, desc):
    """A tqdm bar on stderr (evaluations), or None when tqdm is missing."""
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - installed with the synth extra
        return None, None
    bar = tqdm(total=total, desc=desc, unit="eval", file=sys.stderr, dynamic_ncols=True, leave=True)
    last = [0]

    def update(evaluations, best):
        bar.update(evaluations - last[0])
        last[0] = evaluations
        bar.set_postfix_str(f"best {best:.6g}", refresh=False)
    return bar, update


def synthesize(problem: Problem, method: str | None = None, *, seed: int | None = None, budget: int | None = None,
               time_limit: float | None = None, starts: int | None = None, polish: str | None = None,
               popsize: int | None = None, maxiter: int | None = None, tol: float = 1e-12, executor=None,
               progress: bool = False, x0=None, parallel_starts: bool | None = None, patience: int = 100,
               strategy: str | None = None, target: float | None = None, backend: str | None = None) -> SynthesisResult:
    """Minimise the problem's objective subject to its constraints.

    Every setting left None is taken from the problem file's ``[solver]`` table, else from the built-in
    defaults (:data:`assur.synthesis.solver.DEFAULTS`); ``result.settings`` records the values used and where
    each came from. method: 'restart' (the default: differential evolution restarted on stagnation, each
    restart's best polished, until the budget, the time limit or the target; with neither a budget nor a time
    limit the budget is :data:`~assur.synthesis.solver.DEFAULT_BUDGET`), 'de' (one scipy differential
    evolution per start, vectorised), 'cmaes' (cma), or 'local' (polish only, from ``x0`` in file units or a
    random point). budget: evaluations over all starts; time_limit: a wall-time limit (s) of the whole run —
    every start, on this process or on workers, with its polish and restarts: no population is evaluated after
    it, so the run ends within one evaluation batch of it and the best design's re-check (``result.timing``:
    ``longest_batch``, ``finish``; the first population is always evaluated, so a run whose first batch ends after
    the limit — workers still starting — ends right after that, ``first_batch``). starts:
    independent starts with seeds spawned from ``seed``; with a parallel executor they run as tasks
    (``parallel_starts``, default when starts > 1), otherwise in turn with the population evaluation on the
    executor. Ctrl-C, the budget and the time limit end the run early and return the best design so far. A
    'de' start also ends when its best has improved by less than ``tol`` (relative) over ``patience``
    generations; ``strategy`` is scipy's DE strategy. ``target``: stop as soon as a feasible design with
    objective ≤ target is found (later starts are skipped). ``result.on_bounds`` lists the variables of the
    best design that sit on a bound. ``progress``: True for a tqdm bar on stderr, or a callable
    ``progress(evaluations, best_F)`` called after every evaluated population (evaluations counted over the
    run, best_F the optimiser's penalised scalar); a KeyboardInterrupt raised from it stops the run like Ctrl-C,
    keeping the best design so far. ``backend``: the engine backend of every evaluation ('numba' or 'numpy';
    default :func:`~assur.synthesis.evaluate.run_backend`: numba for a run whose numpy evaluations would take at
    least 10 s by a fixed estimate from the problem's size, or without a budget a time limit of at least 60 s;
    numpy for a shorter one, whose first compile would cost more than it saves)."""
    if not isinstance(problem, Problem):
        from ..errors import ArgumentTypeError
        raise ArgumentTypeError([("problem", f"must be a Problem (assur.synthesis.load_problem(path)), not "
                                             f"{type(problem).__name__}")])
    cfg = resolve(getattr(problem, "solver", None),
                  {"method": method, "budget": budget, "time": time_limit, "target": target, "starts": starts,
                   "popsize": popsize, "strategy": strategy, "polish": polish, "maxiter": maxiter})
    method, budget, time_limit, target = cfg["method"], cfg["budget"], cfg["time"], cfg["target"]
    starts, popsize, strategy, polish, maxiter = (cfg["starts"], cfg["popsize"], cfg["strategy"], cfg["polish"],
                                                  cfg["maxiter"])
    if method not in METHODS:
        raise SynthesisError(f"method must be one of {', '.join(METHODS)}: {method!r}")
    if polish not in POLISHES:
        raise SynthesisError(f"polish must be one of {', '.join(POLISHES)}: {polish!r}")
    if starts < 1:
        raise SynthesisError(f"starts must be at least 1: {starts}")
    if strategy not in DE_STRATEGIES:
        raise SynthesisError(f"strategy must be one of {', '.join(DE_STRATEGIES)}: {strategy!r}")
    for name, v in (("budget", budget), ("time_limit", time_limit)):
        if v is not None and not v > 0:
            raise SynthesisError(f"{name} must be positive: {v!r}")
    if method == "cmaes":   # an optional package: say so before any work
        require("cma", "the CMA-ES method (cmaes)", CMA_INSTALL)
    _check_seed(seed)
    backend_source = "given" if backend is not None else "default"
    if backend is None:                    # the compiled kernels only for a run that wins back their compile
        from .evaluate import run_backend
        backend = run_backend(problem, budget, time_limit)
    executor = executor or InProcess()
    seeds = [int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(starts)]
    options = {"popsize": popsize, "maxiter": maxiter, "tol": tol, "polish": polish, "patience": patience,
               "strategy": strategy, "target": target, "backend": backend,
               "x0": None if x0 is None else problem.to_si(x0)}
    per_budget = None if budget is None else max(1, budget // starts)
    t0, wall0 = time.monotonic(), time.time()
    # one deadline for the whole run, whatever runs where: the starts on workers, their polish and restarts
    options["deadline"] = None if time_limit is None else wall0 + time_limit
    results: list[StartResult] = []
    stopped = "converged"
    evaluator = Evaluator(problem, backend=backend)
    if parallel_starts is None:
        parallel_starts = starts > 1 and executor.workers > 1
    if callable(progress):   # a caller's hook: progress(evaluations, best F) after every evaluated population
        bar, update = None, progress
    else:
        bar, update = _progress_bar(budget, problem.name or "synth") if progress else (None, None)
    try:
        if parallel_starts:
            # the first start always gives a design; a later one that begins past the deadline evaluates nothing
            args = [(problem, method, s, per_budget, time_limit, {**options, "first": k == 0})
                    for k, s in enumerate(seeds)]
            results = [r for r in executor.map_starts(run_start, args) if r.x is not None]
        else:
            done = 0
            for s in seeds:
                if options["deadline"] is not None and results and time.time() >= options["deadline"]:
                    stopped = "time"
                    break
                prog = None if update is None else (lambda e, b, base=done: update(base + e, b))
                r = run_start(problem, method, s, per_budget, time_limit, options, evaluator, executor, prog)
                results.append(r)
                done += r.evaluations
                if r.stopped in ("interrupted", "target"):
                    stopped = r.stopped
                    break
    except KeyboardInterrupt:
        stopped = "interrupted"
    finally:
        if bar is not None:
            bar.close()
    if not results:
        raise SynthesisError(f"the run stopped ({stopped}) before any design was evaluated")
    best = min(results, key=lambda r: r.penalised)
    if stopped == "converged":
        reasons = {r.stopped for r in results}
        stopped = next((s for s in ("target", "interrupted", "time", "budget") if s in reasons), "converged")
    ends = [r.first_batch_end for r in results if r.first_batch_end is not None]
    finish0 = time.monotonic()
    ev = evaluator.recheck(best.x[None, :])
    row = ev.row(0)
    history, offset_e, offset_t = [], 0, 0.0
    for r in results:
        history += [(e + offset_e, t + offset_t, F) for e, t, F in r.history]
        offset_e += r.evaluations
        offset_t += r.seconds
    return SynthesisResult(problem=problem, x=best.x, objective=row["objective"], feasible=row["feasible"],
                           violation=row["violation"], details=row, evaluations=sum(r.evaluations for r in results),
                           seconds=time.monotonic() - t0, stopped=stopped, method=method, seed=seed,
                           starts=[{"seed": r.seed, "best_F": r.penalised, "evaluations": r.evaluations,
                                    "seconds": r.seconds, "stopped": r.stopped, "restarts": r.restarts} for r in results],
                           history=history, executor=executor.name,
                           timing={"first_batch": (max(ends) - wall0) if ends else 0.0,
                                   "longest_batch": max(r.longest_batch for r in results),
                                   "finish": time.monotonic() - finish0},
                           settings={**{k: cfg[k] for k in ("method", "budget", "time", "target", "starts", "popsize",
                                                            "strategy", "polish", "maxiter")}, "backend": backend,
                                     "sources": {**cfg["sources"], "backend": backend_source}},
                           on_bounds=bounds_reached(problem, best.x))


__all__ = ["METHODS", "POLISHES", "StartResult", "SynthesisResult", "Tracker", "bounds_reached", "run_start",
           "synthesize"]
