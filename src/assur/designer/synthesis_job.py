"""Path synthesis from the designer's page, run in a separate process so that drags stay responsive.

The page picks a point of the mechanism and clicks target positions; :class:`SynthesisJob` varies the mechanism's
dimensions so that the point's path over one crank turn passes as close as possible to the targets, with the
project's own synthesis (:mod:`assur.synthesis`): a problem built the way :func:`~assur.synthesis.problem_from_dict`
reads a problem file, minimised by :func:`~assur.synthesis.synthesize` with the in-process executor inside one
worker process (``multiprocessing``, "spawn" context, daemon).

**The problem.** Path generation without timing (``[targets] timing = "path"``): the cost is the sum over the
targets of the distance from each target to the point's path, the closed polyline through the path at 360 crank
angles over one turn (``deviation = "distance"``; reported in metres). Path targets imply the ``buildable``
constraint: a design counts only if it assembles over the whole turn; an infeasible design never beats a feasible
one (Deb's rules, ``docs/synthesis.md``).

**The variables and their bounds** (the document's current values v, SI):

- every link length ``link.length`` and coupler-point distance ``link.P.distance`` with v > 0: [v/2, 2v];
- every coupler-point angle ``link.P.angle``: [v − 90°, v + 90°] (not wrapped);
- every frame pivot's coordinates ``O.x``, ``O.y`` and every slide line's ``offset``: v ± s, where s is half the
  largest link length or coupler-point distance of the mechanism (its size);
- fixed: the slide lines' angles and the crank's ``zero`` (a path over a whole turn does not depend on it), the
  lengths and coupler points of a link the page has locked (``lock_link``) and the position of a frame pivot it has
  locked (``lock_point``).

**The run** is deterministic for a given seed and budget: first a local search from the current design (the
problem's ``local`` method: the current design, then Nelder–Mead from it) on up to half of the budget, then the
default global method (``restart``: differential evolution restarted on stagnation, each restart polished, seeded
with ``seed``) on the rest, with a population of 5 to 15 designs per variable (fewer for a small budget, so that
several generations fit). The budget counts objective evaluations; the run may pass it by one population. The best
design of both stages is kept, so the result is never worse than the current design.

**Messages** (:meth:`SynthesisJob.poll`): ``synth_progress`` about every 0.25 s (``best`` is None until a design
that assembles over the whole turn has been evaluated: the first evaluation may wait for the engine's compiled
kernel of a new mechanism), then one ``synth_done`` whose ``toml`` is the document with the best dimensions
written in (``assur.design.mechanism_with_params``: link lengths and coupler points explicit, the sketch
re-solved on the same assembly branches; the document's other tables, such as ``[style]``, kept). Cancel sets an
event that the optimiser's progress hook checks (the run then ends like ``assur synth`` on Ctrl-C, keeping its
best design); a worker that has not answered 3 s later is terminated, and the design it last reported is used.
"""
from __future__ import annotations

import copy
import math
import queue as queue_module
import secrets
import threading
import time
import warnings

from .document import EditRefused
from .worker_process import stop_process


#: how often the worker reports progress (s)
PROGRESS_INTERVAL = 0.25
#: how long a cancelled worker may take to answer before it is terminated (s)
CANCEL_GRACE = 3.0
#: the budget's range (objective evaluations)
BUDGET_RANGE = (100, 10 ** 6)
#: the most targets a run takes
MAX_TARGETS = 1000
#: the share of the budget of the local search from the current design
LOCAL_SHARE = 0.5


# ---------------------------------------------------------------------------------------------------------------
# The problem

def _refuse(message: str, where: str):
    raise EditRefused(message, where)


def _integer(value, name: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or isinstance(value, float) and (
            not math.isfinite(value) or value != int(value)):
        _refuse(f"the synthesis {name} must be an integer: {value!r}", name)
    value = int(value)
    if not low <= value <= high:
        _refuse(f"the synthesis {name} must be from {low} to {high}: {value}", name)
    return value


def _targets(targets) -> list:
    """The targets as [[x, y], …] of finite floats (m)."""
    if not isinstance(targets, (list, tuple)):
        _refuse(f"targets must be a list of [x, y] positions (m): {targets!r}", "targets")
    if len(targets) < 2:
        _refuse(f"path synthesis needs at least 2 target positions (got {len(targets)}): one position is met by "
                "any path through it, so it fixes no dimension; click more targets", "targets")
    if len(targets) > MAX_TARGETS:
        _refuse(f"at most {MAX_TARGETS} target positions (got {len(targets)})", "targets")
    out = []
    for i, t in enumerate(targets):
        try:
            x, y = (float(c) for c in t)
        except (TypeError, ValueError):
            _refuse(f"targets[{i}] must be two numbers [x, y] (m): {t!r}", f"targets[{i}]")
        if not (math.isfinite(x) and math.isfinite(y)) or max(abs(x), abs(y)) >= 1e6:
            _refuse(f"targets[{i}] must be finite and within 1000 km of the origin: {t!r}", f"targets[{i}]")
        out.append([x, y])
    return out


def _locks(doc: dict) -> tuple[set, set]:
    t = doc.get("style", {}).get("designer", {}) if isinstance(doc.get("style"), dict) else {}
    t = t if isinstance(t, dict) else {}
    return set(t.get("locked_points", []) or []), set(t.get("locked_links", []) or [])


def build_problem(doc: dict, point, targets, budget, seed):
    """Validate a request and build its synthesis problem. Returns ``(problem data, problem, x0 (SI), targets,
    budget, seed)``; raises :class:`EditRefused` naming what is wrong."""
    from ..engine import compile as compile_plan
    from ..errors import AssurError, SpecError
    from ..io.mechanism_file import from_dict
    from ..io.units import ANGLE, LENGTH
    from ..synthesis import problem_from_dict

    budget = _integer(budget, "budget", *BUDGET_RANGE)
    seed = _integer(seed, "seed", 0, 2 ** 63 - 1)
    if not isinstance(doc, dict):
        _refuse("the document must be a table", "document")
    if int(doc.get("dimension", 2) or 2) != 2:
        _refuse("synthesis from the designer works on planar mechanisms; this one is spatial", "dimension")
    targets = _targets(targets)
    try:
        with warnings.catch_warnings():          # the page shows the document's own diagnostics
            warnings.simplefilter("ignore")
            mech = from_dict(doc, source="the designer's document")
        plan = compile_plan(mech)
    except AssurError as exc:
        _refuse(f"the document is not a mechanism yet, so there is nothing to synthesise: {exc}", "document")
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        kinds = ", ".join(plan.input_kinds) or "none"
        _refuse(f"path synthesis needs a mechanism with exactly one rotary driver (one crank turn); this one has "
                f"{plan.n_inputs} driver(s) ({kinds})", "drivers")
    frame = set(mech.frame.points)
    if not isinstance(point, str) or point not in plan.point_names:
        moving = [p for p in plan.point_names if p not in frame]
        _refuse(f"unknown point {point!r}: choose a moving point of the mechanism ({', '.join(moving)})", "point")
    if point in frame:
        _refuse(f"{point} is a frame point: it does not move, so it has no path to fit", point)

    L, A = LENGTH[mech.units.length], ANGLE[mech.units.angle]
    locked_points, locked_links = _locks(doc)
    links = {lk.name for lk in mech.links if lk.name != "frame"}
    sliders = {pr.name for pr in mech.prismatic}
    value = {n: float(v) for n, v in zip(plan.param_names, plan.defaults)}
    sizes = [v for n, v in value.items() if (n.endswith(".length") or n.endswith(".distance")) and v > 0]
    s = 0.5 * max(sizes) if sizes else 1.0
    variables, x0 = {}, []

    def add(name, lo, hi, kind):
        f = L if kind == "length" else A
        spec = {"bounds": [lo / f, hi / f], "kind": kind}
        if kind == "angle":
            spec["periodic"] = False
        variables[name] = spec
        x0.append(value[name])

    for name, v in value.items():
        parts = name.split(".")
        if len(parts) == 2 and parts[1] in ("x", "y") and parts[0] in frame:
            if parts[0] not in locked_points:
                add(name, v - s, v + s, "length")
        elif len(parts) == 2 and parts[1] == "length" and parts[0] in links:
            if parts[0] not in locked_links and v > 0:
                add(name, 0.5 * v, 2.0 * v, "length")
        elif len(parts) == 3 and parts[0] in links and parts[2] == "distance":
            if parts[0] not in locked_links and v > 0:
                add(name, 0.5 * v, 2.0 * v, "length")
        elif len(parts) == 3 and parts[0] in links and parts[2] == "angle":
            if parts[0] not in locked_links:
                add(name, v - math.pi / 2, v + math.pi / 2, "angle")
        elif len(parts) == 2 and parts[1] == "offset" and parts[0] in sliders:
            add(name, v - s, v + s, "length")
    if not variables:
        _refuse("nothing to vary: every link and frame pivot is locked (unlock some to synthesise)", "locks")
    data = {"format": "assur-synth/1", "name": f"path of {point} through {len(targets)} targets (designer)",
            "variables": variables,
            "targets": {"point": point, "xy": [[x / L, y / L] for x, y in targets], "timing": "path"},
            "objective": {"deviation": "distance"}}
    try:
        problem = problem_from_dict(data, mechanism=mech)
    except SpecError as exc:
        where, message = exc.problems[0] if exc.problems else ("", str(exc))
        _refuse(f"cannot set up the synthesis: {where}: {message}", where or "synthesis")
    return data, problem, x0, targets, budget, seed


def design_toml(doc: dict, problem, x) -> str:
    """The document with the dimensions of design vector ``x`` (SI) written in, as ``assur/1`` text."""
    import numpy as np

    from ..io.mechanism_writer import as_dict
    from ..io.toml_writer import dumps
    from ..synthesis.design import mechanism_with_params
    from ..synthesis.evaluate import Evaluator
    params = Evaluator(problem).params(np.asarray(x, dtype=float)[None, :])[0]
    new = as_dict(mechanism_with_params(problem.plan, params))
    for key, v in doc.items():          # what the mechanism does not hold ([style]: the page's locks, …)
        if key not in new:
            new[key] = copy.deepcopy(v)
    return dumps(new)


# ---------------------------------------------------------------------------------------------------------------
# The worker process

def _recorder_class():
    from ..synthesis.executors import InProcess

    class Recorder(InProcess):
        """The in-process executor, which also keeps the best design of every population it evaluates (both
        stages of the run, in the optimiser's own order: the penalised scalar F)."""

        def __init__(self):
            self.best_F, self.best_x = math.inf, None

        def evaluate(self, evaluator, X, detail: bool = False):
            import numpy as np
            ev = evaluator(X, detail)
            i = int(np.argmin(ev.penalised))
            if ev.penalised[i] < self.best_F:
                self.best_F, self.best_x = float(ev.penalised[i]), evaluator.wrap(X[i])
            return ev
    return Recorder()


def _worker(job_id, doc, data, x0, budget, seed, created, out, cancel):   # pragma: no cover - runs in a child
    """The worker process: runs the synthesis and puts its messages on ``out``."""
    import signal
    signal.signal(signal.SIGINT, signal.SIG_IGN)       # Ctrl-C in the terminal is the server's to handle
    import multiprocessing as mp
    import traceback

    state = {"evaluations": 0, "best": None, "x": None, "sent_x": None, "stop": False}
    parent = mp.parent_process()

    def progress_message():
        return {"type": "synth_progress", "job": job_id, "evaluations": int(state["evaluations"]),
                "best": state["best"], "elapsed": time.time() - created}

    def send_progress():
        out.put(progress_message())
        x = state["x"]
        if x is not None and x is not state["sent_x"]:
            out.put({"type": "_best", "job": job_id, "x": [float(v) for v in x], "best": state["best"]})
            state["sent_x"] = x

    def heartbeat():
        while not state["stop"]:
            if parent is not None and not parent.is_alive():
                cancel.set()                            # the server is gone: stop, nobody is listening
            send_progress()
            time.sleep(PROGRESS_INTERVAL)

    beat = threading.Thread(target=heartbeat, daemon=True)
    beat.start()
    status, message, toml, best = "failed", "", None, None
    recorder = problem = None
    try:
        import numpy as np

        from ..io.mechanism_file import from_dict
        from ..synthesis import problem_from_dict, synthesize
        from ..synthesis.evaluate import Evaluator
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mech = from_dict(doc, source="the designer's document")
        problem = problem_from_dict(data, mechanism=mech)
        ls = problem.length_scale
        recorder = _recorder_class()

        def hook(base):
            def progress(evaluations, best_F):
                state["evaluations"] = base + evaluations
                F = recorder.best_F
                state["best"] = F / ls if F < problem.infeasible_offset else None
                state["x"] = recorder.best_x
                if cancel.is_set():
                    raise KeyboardInterrupt      # synthesize ends as on Ctrl-C, keeping its best design
            return progress

        local_budget = max(1, int(budget * LOCAL_SHARE))
        r = synthesize(problem, "local", x0=problem.to_file(np.asarray(x0, dtype=float)), budget=local_budget,
                       polish="nelder-mead", executor=recorder, progress=hook(0))
        used, stopped = r.evaluations, r.stopped
        rest = budget - used
        if stopped != "interrupted" and not cancel.is_set() and rest > 0:
            popsize = max(5, min(15, rest // (10 * problem.n_vars)))
            r = synthesize(problem, "restart", seed=seed, budget=rest, popsize=popsize, executor=recorder,
                           progress=hook(used))
            used, stopped = used + r.evaluations, r.stopped
        state["evaluations"] = used
        cancelled = stopped == "interrupted" or cancel.is_set()
        x = recorder.best_x
        row = Evaluator(problem).recheck(x[None, :]).row(0)
        state["x"] = x
        unit = problem.length_unit
        n = len(data["targets"]["xy"])
        if row["feasible"]:
            best = row["objective"] / ls
            state["best"] = best
            d = row["quantities"].get("distances")
            worst = f", the farthest target {max(d):.4g} {unit} away" if d else ""
            message = (f"sum of the {n} targets' distances to the path of {data['targets']['point']}: "
                       f"{row['objective']:.4g} {unit}{worst}")
        else:
            message = "no design found that assembles over the whole crank turn; raise the budget or move the targets"
        status = "cancelled" if cancelled else "finished"
        message = f"{status} after {used} evaluations: {message}"
        toml = design_toml(doc, problem, x)
    except Exception as exc:   # noqa: BLE001 - the page gets the reason, the run its best design so far
        status = "failed"
        message = f"the synthesis failed: {type(exc).__name__}: {exc}"
        traceback.print_exc()
        try:
            if problem is not None and recorder is not None and recorder.best_x is not None:
                toml = design_toml(doc, problem, recorder.best_x)
                best = state["best"]
        except Exception:   # noqa: BLE001
            toml = None
    finally:
        state["stop"] = True
    beat.join(timeout=2 * PROGRESS_INTERVAL + 1.0)
    out.put(progress_message())
    out.put({"type": "synth_done", "job": job_id, "status": status, "best": best,
             "evaluations": int(state["evaluations"]), "toml": toml, "message": message})


# ---------------------------------------------------------------------------------------------------------------
# The job, on the server's side

class SynthesisJob:
    """One synthesis run of the page (see the module docstring): validated at once (:class:`EditRefused`), then
    run in a worker process; :meth:`poll` returns its messages, :meth:`cancel` stops it keeping its best design."""

    def __init__(self, doc: dict, point, targets, budget=3000, seed=1):
        self._data, self._problem, x0, targets, budget, seed = build_problem(doc, point, targets, budget, seed)
        self.id = secrets.token_hex(6)
        self.doc = copy.deepcopy(doc)
        self.point, self.targets, self.budget, self.seed = point, targets, budget, seed
        self.created = time.time()
        self._finished = False
        self._cancel_at: float | None = None
        self._timer: threading.Timer | None = None
        self._last: dict = {"evaluations": 0, "best": None, "x": None}
        self._start(x0)

    def _start(self, x0) -> None:
        import multiprocessing as mp
        ctx = mp.get_context("spawn")
        self._queue = ctx.Queue()
        self._cancel = ctx.Event()
        self._process = ctx.Process(target=_worker, name=f"assur-synthesis-{self.id}", daemon=True,
                                    args=(self.id, self.doc, self._data, list(x0), self.budget, self.seed,
                                          self.created, self._queue, self._cancel))
        self._process.start()

    @property
    def running(self) -> bool:
        """The worker has not finished, or its ``synth_done`` has not been polled yet."""
        return not self._finished

    def poll(self) -> list[dict]:
        """The messages that arrived since the last poll, in order (never blocks)."""
        out: list[dict] = []
        if self._finished:
            return out
        self._drain(out, wait=0.0)
        if self._finished:
            return out
        proc = self._process
        if self._cancel_at is not None and time.monotonic() - self._cancel_at > CANCEL_GRACE and proc.is_alive():
            self._stop_process()
        if not proc.is_alive():
            self._drain(out, wait=0.05)           # what it sent just before it ended
            if not self._finished:
                out.append(self._lost_worker_done())
                self._finished = True
        if self._finished:
            self._reap()
        return out

    def _drain(self, out: list, wait: float) -> None:
        while not self._finished:
            try:
                m = self._queue.get(timeout=wait) if wait else self._queue.get_nowait()
            except queue_module.Empty:
                return
            except Exception:   # noqa: BLE001 - a worker terminated while writing leaves a broken message
                return
            kind = m.get("type")
            if kind == "_best":
                self._last["x"] = m.get("x")
                continue
            if kind == "synth_progress":
                self._last["evaluations"], self._last["best"] = m["evaluations"], m["best"]
            elif kind == "synth_done":
                self._finished = True
            out.append(m)

    def _lost_worker_done(self) -> dict:
        """The ``synth_done`` of a worker that ended without one (terminated after a cancel, or crashed): the
        design it last reported."""
        cancelled = self._cancel_at is not None
        toml, note = None, "no design had been evaluated yet"
        if self._last["x"] is not None:
            try:
                toml = design_toml(self.doc, self._problem, self._last["x"])
                note = "the best design it reported is kept"
            except Exception as exc:   # noqa: BLE001
                note = f"its last design could not be written: {exc}"
        code = self._process.exitcode
        why = (f"the synthesis was cancelled and its process stopped ({note})" if cancelled else
               f"the synthesis process ended unexpectedly (exit code {code}; {note})")
        return {"type": "synth_done", "job": self.id, "status": "cancelled" if cancelled else "failed",
                "best": self._last["best"] if toml is not None else None,
                "evaluations": int(self._last["evaluations"]), "toml": toml, "message": why}

    def cancel(self) -> None:
        """Ask the worker to stop (it answers ``synth_done`` with status "cancelled" and its best design); a worker
        that is still alive :data:`CANCEL_GRACE` s later is terminated. Returns at once."""
        if self._cancel_at is not None or self._finished:
            return
        self._cancel_at = time.monotonic()
        self._cancel.set()
        self._timer = threading.Timer(CANCEL_GRACE + 0.1, self._stop_process)
        self._timer.daemon = True
        self._timer.start()

    def _stop_process(self) -> None:
        stop_process(self._process)

    def _reap(self) -> None:
        """After the last message: no more termination timer; the worker is exiting (never waited for)."""
        if self._timer is not None:
            self._timer.cancel()
        self._process.join(0)


__all__ = ["SynthesisJob", "build_problem", "design_toml"]
