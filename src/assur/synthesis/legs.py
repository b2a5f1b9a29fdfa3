"""Walking legs ranked by their gait: type synthesis followed by a short dimensional synthesis of every candidate
(docs/atlas.md, "Walking legs ranked by gait"); the synthesis face of the atlas (:mod:`assur.structure.atlas`, the
mathematics, which knows nothing of it).

A *candidate* is an atlas mechanism of ``links`` links and mobility 1 (:mod:`assur.structure.atlas`), one of its
crank placements (a link hinged to the frame drives it) and a *foot link*: a moving link other than the crank,
one per orbit of the automorphisms that fix the frame and the crank (two links the chain's symmetry exchanges give
the same leg). The foot is a point ``F`` rigidly attached to the foot link, placed by a distance and an angle from
the link's first two joints (both design variables).

Every candidate is dimensioned by the same problem (:func:`leg_problem`), in units of the crank's length
``r`` = :data:`CRANK` mm:

* variables: every frame pivot but the crank's (within ``reach·r`` of the crank's pivot on each axis), every link
  length and point distance (``r/2 … reach·r``; the foot's ``0 … reach·r``), every point angle (a full turn);
* constraints: the crank turns fully (``buildable``), a step of at least ``step·r``, a lift of at least
  ``lift·r``, the whole foot path at least ``below·r`` under the crank's axis (the foot under the body:
  ``gait.top``), a transmission angle of at least ``transmission`` degrees wherever a dyad has one; with
  ``clearance`` > 0, a swing that rises at least ``clearance·r`` above the support's highest point
  (``gait.clearance`` = lift − sag: without it a foot may retrace its own support arc in the swing);
* objective: ``sag / (step·r / 10) + vx_spread``: the support phase's height variation (1 % of the smallest
  step counts as 0.1) plus the spread of the foot's horizontal speed over the central 80 % of the stride
  (``gait.vx_spread``, the body's surge).

Every candidate is dimensioned. One whose decomposition has a group without a closed form (a class III triad, a
class IV group: some Stephenson inversions and many eight-link ones) is evaluated by Newton iterations swept through
the cycle in certified steps (``solve(..., sweep=True)``, :mod:`assur.engine.planar.continuation`), on the numpy
path until the compiled Newton kernels land, and skips the local polish (one design at a time); the search itself is
the same.

The ground is the x axis and up is +y; the frame pivots are free, so the optimiser also chooses the leg's
orientation. Each candidate runs :func:`assur.synthesis.synthesize` from ``starts`` independent starts with a seed
drawn from the run's seed and the candidate's key alone, so a candidate's result does not depend on which
candidates run beside it, nor where: :func:`rank_legs` maps the candidates over an executor
(:mod:`assur.synthesis.executors`: in-process, local processes or a Dask cluster) and gets the same numbers from
each. The ranking puts the feasible designs first, by objective, then the others by their constraint violation;
each entry carries the exact gait metrics of its best design (:func:`assur.gait_metrics`) and its mechanism file.
A design the search found feasible is *refused* (``feasible`` False, ``refused`` the reason) when its exact gait
contradicts the search's samples: its crank does not turn fully on the analysis's 720 samples, or the support arc
the search measured is not the exact gait's (:func:`support_disagreement`).

With the setting ``rank = "window"`` (``assur atlas --walking-legs --rank window``) each feasible design is then
widened for a co-designed gear drive (:func:`assur.synthesis.leg_window.widen_window`: the same variables and gait
constraints, the co-design screen's slack as objective, ``window_budget`` designs) and the entries are ranked by
the widest constant-speed window the screen passes (:func:`window_metrics`, :mod:`assur.codesign.widest`), widest
first.
"""
from __future__ import annotations

import copy
import math
import time
import zlib
from dataclasses import dataclass, field

import numpy as np

from ..errors import SpecError

__all__ = ["CRANK", "DEFAULTS", "RANKS", "LegCandidate", "LegRanking", "leg_candidates", "leg_problem", "rank_legs",
           "run_candidate", "window_metrics"]

#: the crank length every candidate is normalised to (mm)
CRANK = 100.0
#: the default settings of a ranking (lengths in crank lengths r, angles in degrees)
DEFAULTS = {
    "budget": 8000,          # evaluations per candidate, over all its starts
    "starts": 4,             # independent starts per candidate
    "seed": 0,
    "method": "de",
    "cycle_samples": 90,     # crank angles per evaluated design
    "step": 3.0,             # smallest step, in r
    "lift": 0.5,             # smallest lift, in r
    "clearance": 0.0,        # smallest rise of the foot above its support in the swing (lift − sag), in r; 0: none
    "transmission": 30.0,    # smallest transmission angle, degrees
    "reach": 8.0,            # longest link / farthest frame pivot, in r
    "below": 1.0,            # the whole foot path at least this far below the crank's axis, in r
    "backend": None,         # the engine backend of the evaluations: None (numba when installed), "numpy"
    "rank": "gait",          # the ranking key: "gait" (the objective) or "window" (the widest screened window)
    "window_budget": 450,    # rank "window": designs of the window-widening search after the gait search (0: none)
}
#: the ranking keys: by the search's objective, or by the widest constant-speed window the co-design screen passes
RANKS = ("gait", "window")
#: settings that are gone: accepted with a DeprecationWarning and ignored (name → why)
DEPRECATED = {"triads": "every candidate is dimensioned now, those with a Newton-solved group included"}
#: the name of the foot point added to the foot link
FOOT = "F"


@dataclass(frozen=True)
class LegCandidate:
    """One leg topology: ``key`` (stable: ``<inversion id>/c<crank link>/foot<foot link>``), a readable ``name``,
    the inversion's ID and textbook name, the crank and foot links (canonical positions and file names) and the
    ``document`` of its template mechanism file (mm, degrees; the foot ``F`` on the foot link, a ``[gait]``
    table) and the atlas ``sketch`` it was drawn from."""
    key: str
    name: str
    inversion: str
    inversion_name: str | None
    crank: int
    foot_link: int
    crank_name: str
    foot_name: str
    document: dict = field(repr=False, compare=False)
    sketch: object = field(default=None, repr=False, compare=False)
    newton: bool = False      # a group without a closed form (a class III triad): solved by Newton iterations


def leg_candidates(links: int, key: str | None = None) -> list[LegCandidate]:
    """The leg candidates of the 1-DOF atlas of ``links`` links (6 or 8), in the atlas's order: chains,
    inversions, crank placements, foot links; with ``key``, only that candidate (a list of one, or empty when no
    candidate has that key), made without drawing the others."""
    from ..engine import compile as compile_plan
    from ..io.atlas import mechanism_entry
    from ..io.mechanism_file import from_dict
    from ..structure.atlas.chains import chains
    from ..structure.atlas.graphs import automorphism_orbits
    from ..structure.atlas.layout import link_names
    from ..structure.atlas.mechanisms import driver_placements, inversions
    if links not in (4, 6, 8):
        raise SpecError([("links", f"walking legs are ranked for 1-DOF mechanisms of 6 or 8 links: {links}")])
    out = []
    for chain in chains(links, 1):
        for inv in inversions(chain.graph):
            if key is not None and not key.startswith(f"{inv.id}/c"):
                continue
            g, names = inv.chain, link_names(inv)
            for place in driver_placements(inv):
                crank = place.link
                others = [v for v in range(g.n) if v not in (inv.frame, crank)]
                orbits = automorphism_orbits(g.n, g.edges, colours=[[inv.frame], [crank], others])
                entry = None
                for foot in sorted({orbits[v] for v in others}):
                    if key is not None and key != f"{inv.id}/c{crank}/foot{foot}":
                        continue
                    entry = entry or mechanism_entry(inv, crank)
                    doc = _template(entry.document, names[crank], names[foot])
                    newton = compile_plan(from_dict(doc, "leg")).has_newton_groups
                    title = inv.name or inv.id
                    out.append(LegCandidate(f"{inv.id}/c{crank}/foot{foot}",
                                            f"{title}, crank {names[crank]}, foot on {names[foot]}",
                                            inv.id, inv.name, crank, foot, names[crank], names[foot], doc,
                                            entry.sketch, newton))
    return out


def _template(document: dict, crank_name: str, foot_name: str) -> dict:
    """The atlas mechanism's document with the foot point on ``foot_name`` and a ``[gait]`` table."""
    doc = copy.deepcopy(document)
    pts = doc["links"][foot_name]
    xy = np.array([doc["points"][p] for p in pts], dtype=float)
    centre = xy.mean(axis=0)
    doc["points"][FOOT] = [round(float(centre[0]), 2), round(float(centre[1]) - 100.0, 2)]
    doc["links"][foot_name] = [*pts, FOOT]
    doc["gait"] = {"foot": FOOT, "ground": [1, 0], "up": [0, 1]}
    doc["name"] = f"{doc['name']}: walking leg, crank {crank_name}, foot on {foot_name}"
    return doc


def settings_of(settings: dict | None) -> dict:
    """DEFAULTS overridden by ``settings``; SpecError naming an unknown or bad setting."""
    s = dict(DEFAULTS)
    for k, v in (settings or {}).items():
        if k in DEPRECATED:
            import warnings
            warnings.warn(f"the walking-leg setting {k!r} is deprecated and ignored: {DEPRECATED[k]}",
                          DeprecationWarning, stacklevel=3)
            continue
        if k not in DEFAULTS:
            raise SpecError([(k, f"unknown walking-leg setting; known: {', '.join(DEFAULTS)}")])
        s[k] = v
    if not (isinstance(s["seed"], (int, np.integer)) and not isinstance(s["seed"], bool) and s["seed"] >= 0):
        raise SpecError([("seed", f"must be a whole number ≥ 0: {s['seed']!r}")])
    if not (isinstance(s["window_budget"], (int, np.integer)) and s["window_budget"] >= 0):
        raise SpecError([("window_budget", f"must be a whole number ≥ 0: {s['window_budget']!r}")])
    for k in ("budget", "starts", "cycle_samples"):
        if not (isinstance(s[k], (int, np.integer)) and s[k] >= 1):
            raise SpecError([(k, f"must be a positive integer: {s[k]!r}")])
    if s["rank"] not in RANKS:
        raise SpecError([("rank", f"must be one of {', '.join(RANKS)}: {s['rank']!r}")])
    if s["backend"] not in (None, "numba", "numpy"):
        raise SpecError([("backend", f"must be 'numba' or 'numpy': {s['backend']!r}")])
    for k in ("step", "lift", "reach", "below"):
        if not (isinstance(s[k], (int, float)) and s[k] > 0):
            raise SpecError([(k, f"must be positive: {s[k]!r}")])
    if not (isinstance(s["clearance"], (int, float)) and not isinstance(s["clearance"], bool)
            and 0 <= s["clearance"] < math.inf):
        raise SpecError([("clearance", f"must be a number ≥ 0 (crank lengths): {s['clearance']!r}")])
    return s


def leg_problem(candidate: LegCandidate, settings: dict | None = None):
    """The dimensional-synthesis :class:`~assur.synthesis.problem.Problem` of a candidate (module docstring)."""
    from ..analysis.transmission import has_transmission
    from ..engine import compile as compile_plan
    from ..io.mechanism_file import from_dict
    from .problem import problem_from_dict
    s = settings_of(settings)
    mech = from_dict(candidate.document, candidate.key)
    plan = compile_plan(mech)
    driver = candidate.document["drivers"][0]
    pivot = driver["pivot"]
    px, py = candidate.document["points"][pivot]
    reach = s["reach"] * CRANK
    variables = {}
    for name in plan.param_names:
        owner, _, what = name.rpartition(".")
        if name == f"{driver['name']}.zero" or owner == pivot or name == f"{candidate.crank_name}.length":
            continue
        if what in ("x", "y"):
            c = px if what == "x" else py
            variables[name] = [c - reach, c + reach]
        elif what == "angle":
            variables[name] = {"bounds": [-180, 180], "kind": "angle", "periodic": True}
        elif what == "distance" and owner.endswith(f".{FOOT}"):
            variables[name] = [0.0, reach]
        else:
            variables[name] = [0.5 * CRANK, reach]
    step = s["step"] * CRANK
    data = {
        "format": "assur-synth/1",
        "name": f"walking leg {candidate.key}",
        "description": f"{candidate.name}: gait synthesis of the atlas ranking (docs/atlas.md)",
        "variables": variables,
        "parameters": {f"{candidate.crank_name}.length": repr(CRANK / 1000.0)},   # SI (m)
        "objective": {"deviation": "none",
                      "terms": [{"quantity": "gait.sag", "weight": 10.0 / step},
                                {"quantity": "gait.vx_spread", "weight": 1.0}]},
        "constraints": {"use": ["buildable"],
                        "limits": [{"quantity": "gait.step", "min": step},
                                   {"quantity": "gait.lift", "min": s["lift"] * CRANK},
                                   {"quantity": "gait.top", "max": py - s["below"] * CRANK}]
                                  + ([{"quantity": "gait.clearance", "min": s["clearance"] * CRANK}]
                                     if s["clearance"] > 0 else [])
                                  + ([{"quantity": "transmission.min", "min": s["transmission"]}]
                                     if has_transmission(plan) else [])},
        "options": {"cycle_samples": int(s["cycle_samples"])},
    }
    return problem_from_dict(data, mechanism=plan)


def candidate_seed(seed: int, key: str) -> int:
    """The seed of a candidate: from the run's seed and the candidate's key only."""
    return int(np.random.SeedSequence([int(seed), zlib.crc32(key.encode())]).generate_state(1)[0])


def run_candidate(candidate: LegCandidate, settings: dict | None = None) -> dict:
    """Dimension one candidate (a task of :func:`rank_legs`; picklable arguments, a plain dict back):
    ``key``, ``objective`` (None when no design was feasible), ``feasible`` (the search's verdict, unless
    ``refused``: why the exact gait contradicts it, else None), ``violation``, ``variables`` (file units), ``starts`` (each start's
    penalised best), ``evaluations``, ``seconds``, ``metrics`` (the exact gait of the best design, None when it
    cannot walk) and ``mechanism`` (its file text; for a candidate with no feasible design whose best does not
    assemble at its sketch, the candidate's own start, so that every written file loads)."""
    from ..io.mechanism_writer import dumps
    from .optimize import synthesize
    s = settings_of(settings)
    t0 = time.monotonic()
    problem = leg_problem(candidate, s)
    # a group without a closed form (a triad) is solved by Newton iterations on whole populations: a local polish,
    # one design at a time, would cost as much as the whole search, so those candidates keep the search's best
    res = synthesize(problem, s["method"], seed=candidate_seed(s["seed"], candidate.key), budget=s["budget"],
                     starts=s["starts"], parallel_starts=False, backend=s["backend"],
                     polish="none" if candidate.newton else None)
    widened = None
    if s["rank"] == "window" and res.feasible and s["window_budget"] > 0:
        widened = _widen(problem, res, s, candidate)
        res = widened.pop("result")
    # the metrics are those of the file written (SynthesisResult.design_plan)
    mech = res.mechanism()
    plan = res.design_plan(mech)
    if plan is None and not res.feasible:   # the search's best does not even assemble at its sketch: the file is
        mech = problem.plan.mechanism       # the start's
    metrics, refused = None, None
    g, failure = _exact_gait(plan)
    if res.feasible:
        refused = (support_disagreement(plan, g, int(s["cycle_samples"])) if g is not None
                   else None if failure is None else f"its exact gait fails: {failure}")
    if g is not None:
        metrics = {"step": g.step_length * 1000, "lift": g.lift * 1000, "sag": g.sag * 1000, "duty": g.duty_factor,
                   "vx_spread_80": g.vx_spread["0.8"], "vx_spread_90": g.vx_spread["0.9"],
                   "speed_spread": (g.support_speed.max - g.support_speed.min) / g.support_speed.mean}
    if metrics is not None and s["rank"] == "window":
        metrics.update(window_metrics(plan, plan.defaults))
    q = res.details.get("quantities", {})
    if metrics is not None and q.get("transmission.min") is not None:
        metrics["transmission_min"] = float(q["transmission.min"])
    objective = None if res.objective is None or not np.isfinite(res.objective) else float(res.objective)
    return {"key": candidate.key, "objective": objective, "feasible": bool(res.feasible) and refused is None,
            "refused": refused, "violation": float(res.violation), "variables": res.variables,
            "starts": [float(st["best_F"]) for st in res.starts], "evaluations": int(res.evaluations),
            "seconds": time.monotonic() - t0, "metrics": metrics, "skipped": None, "mechanism": dumps(mech),
            **({"widening": widened} if widened is not None else {})}


def _exact_gait(plan):
    """(the exact :class:`~assur.analysis.gait.GaitMetrics` of a design's own plan, or None; why there is none, or
    None): (None, None) without a plan (a design that does not assemble at its sketch)."""
    from ..analysis.study import Study
    from ..errors import AssurError
    if plan is None:
        return None, None
    try:
        study = Study(plan)
        g = study.gait
    except AssurError as exc:
        return None, str(exc)
    return g, None if g is not None else study.gait_error or "the file has no gait"


#: the least share of the search's sampled support arc that must lie in the exact gait's support arc
SUPPORT_AGREEMENT = 0.5


def support_disagreement(plan, gait, samples: int) -> str | None:
    """Why the search's verdict on a design does not hold for its exact gait, or None when it does.

    The search judges a design on ``samples`` uniform crank angles, where the support arc is the half of the foot
    path (between the samples of least and greatest stride coordinate) whose sample-mean height is lower
    (:func:`assur.kernels.arcs.sampled_arcs`); the exact gait decides the same on the refined extremes and 720
    samples (:func:`assur.analysis.gait.gait_metrics`). Where the two halves' mean heights are nearly equal the two
    can take different halves, and where the path has two nearly equal extremes of x the two can split it
    elsewhere: the search then measured the sag, the clearance and the speed spread on another part of the path.
    The design is refused when less than :data:`SUPPORT_AGREEMENT` of its sampled support arc (the file's own plan
    solved at the search's angles) lies in the exact one. ``gait``: the exact
    :class:`~assur.analysis.gait.GaitMetrics` of ``plan``'s foot."""
    from ..analysis.gait import resolve_gait
    from ..analysis.sampling import TWO_PI
    from ..engine import solve
    from ..kernels.arcs import arc_mask, in_arc, population_contact
    foot, ground, up = resolve_gait(plan)
    q = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    st = solve(plan, inputs=q, order=0)
    if not np.all(st.valid):
        return (f"the file's own plan does not assemble at {np.count_nonzero(~np.asarray(st.valid))} of the "
                f"search's {samples} crank angles")
    pos = np.asarray(st.pos)[:, plan.point_index(foot)][None]
    start, width = population_contact(pos, ground=ground, up=up)
    sampled = arc_mask(start, width, samples)[0]
    exact = in_arc(q, gait.contact_start, gait.contact_end - gait.contact_start)
    share = np.count_nonzero(sampled & exact) / np.count_nonzero(sampled)
    if share >= SUPPORT_AGREEMENT:
        return None
    deg = np.degrees
    a, b = deg(q[start[0]]), deg(q[(start[0] + width[0]) % samples])
    return (f"the support the search measured on its {samples} samples ({a:.0f}° to {b:.0f}°) is not the exact "
            f"gait's ({deg(gait.contact_start) % 360:.1f}° to {deg(gait.contact_end) % 360:.1f}°): its sag, "
            f"clearance and speed spread were measured on another part of the foot path")


def _widen(problem, res, s: dict, candidate: LegCandidate) -> dict:
    """The window-widening stage (:func:`assur.synthesis.leg_window.widen_window`) from the gait search's best:
    ``result`` (the search's result with the widened design, its objective re-evaluated), ``start_window``,
    ``push``, ``evaluations``, ``sag_limit`` (mm: the start's sampled sag, which the widening keeps) and ``moved``
    (whether the design changed)."""
    import dataclasses

    from .evaluate import Evaluator
    from .leg_window import widen_window
    w = widen_window(problem, res.x, budget=int(s["window_budget"]),
                     seed=candidate_seed(s["seed"] + 1, candidate.key))
    moved = w["x"] is not res.x and not np.array_equal(w["x"], res.x)
    if moved:
        ev = Evaluator(problem)(w["x"][None])
        res = dataclasses.replace(res, x=w["x"], objective=float(ev.objective[0]), feasible=bool(ev.feasible[0]),
                                  violation=float(ev.violation[0]))
    return {"result": res, "start_window": w["start_window"], "push": w["push"], "evaluations": w["evaluations"],
            "sag_limit": w["sag_limit"], "moved": bool(moved)}


def window_metrics(plan, params) -> dict:
    """The widest constant-speed window of a dimensioned leg (:func:`assur.codesign.widest.widest_window` of its
    foot law, 4096 crank angles), as metrics: ``window`` (None when even half the stride fails the screen),
    ``window_k``, ``window_target`` (0.9), ``window_target_slack``, ``window_target_worst``,
    ``window_pressure_bound`` (degrees, at the target) and ``window_stopped_by_pressure``; all None when the
    leg has no foot law (a crank that stops)."""
    from ..codesign.law import foot_law
    from ..codesign.widest import widest_window
    from ..errors import AssurError
    try:
        w = widest_window(foot_law(plan, params)).as_dict()
    except AssurError:
        w = {}
    return {name: w.get(key) for key, name in WINDOW_METRICS.items()}


#: the metrics of :func:`window_metrics`: WidestWindow.as_dict's key → the metric's name
WINDOW_METRICS = {"window": "window", "window_k": "window_k", "target": "window_target",
                  "target_slack": "window_target_slack", "target_worst": "window_target_worst",
                  "pressure_bound_deg": "window_pressure_bound", "stopped_by_pressure": "window_stopped_by_pressure"}


@dataclass
class LegRanking:
    """A ranking: ``links``, the ``settings`` used, ``entries`` (one dict per candidate, best first: the
    candidate's key, name, inversion, crank and foot names and :func:`run_candidate`'s result, with ``rank``),
    the ``executor``'s name and the wall-clock ``seconds``."""
    links: int
    settings: dict
    entries: list
    executor: str
    seconds: float

    def as_dict(self, timings: bool = True) -> dict:
        """The ranking as plain data (``timings`` False: without the seconds, for comparisons)."""
        drop = set() if timings else {"seconds"}
        return {"format": "assur-legs/1", "links": self.links, "settings": self.settings,
                **({"executor": self.executor, "seconds": self.seconds} if timings else {}),
                "entries": [{k: v for k, v in e.items() if k not in drop} for e in self.entries]}


#: how the ``skipped`` reason of a candidate that failed inside assur begins
FAILED = "failed: "


def run_candidate_guarded(candidate: LegCandidate, settings: dict | None = None) -> dict:
    """:func:`run_candidate`, except that a failure inside assur on one candidate does not lose the others' work:
    that candidate comes back undimensioned, its ``skipped`` the failure (``failed: TYPE: message``) and its file
    the candidate's start. (Bad settings still raise: they are every candidate's.)"""
    from ..errors import SpecError
    from ..io.mechanism_file import from_dict
    from ..io.mechanism_writer import dumps
    t0 = time.monotonic()
    try:
        return run_candidate(candidate, settings)
    except SpecError:
        raise
    except Exception as exc:                     # noqa: BLE001 — an internal failure, reported with the candidate
        return {"key": candidate.key, "objective": None, "feasible": False, "refused": None, "violation": 0.0,
                "variables": {},
                "starts": [], "evaluations": 0, "seconds": time.monotonic() - t0, "metrics": None,
                "skipped": f"{FAILED}{type(exc).__name__}: {exc}",
                "mechanism": dumps(from_dict(candidate.document, candidate.key))}


def _order(entry: dict, rank: str = "gait"):
    if entry.get("skipped"):                     # after every dimensioned candidate
        return (2, 0.0, 0.0, entry["key"])
    bad = not entry["feasible"] or entry["metrics"] is None       # refused by the exact gait: not feasible
    if rank == "window" and not bad:      # the widest window first; legs without one after, by objective
        window = entry["metrics"].get("window")
        return (0, -(window or 0.0), entry["objective"], entry["key"])
    return (int(bad), entry["violation"] if bad else entry["objective"], 0.0, entry["key"])


def rank_legs(links: int, *, settings: dict | None = None, executor=None, candidates=None,
              progress=None) -> LegRanking:
    """Rank the walking legs of ``links`` links (module docstring). ``candidates``: a subset of
    :func:`leg_candidates` (default all of them); ``executor``: where the candidates run (default in-process);
    ``progress(done, total)`` as each candidate's result comes in, whatever the executor."""
    from .executors import InProcess
    s = settings_of(settings)
    cands = leg_candidates(links) if candidates is None else list(candidates)
    executor = executor or InProcess()
    t0 = time.monotonic()
    todo = cands
    results = executor.map_starts(run_candidate_guarded, [(c, s) for c in todo], progress=progress) if todo else []
    by_key = {c.key: c for c in cands}
    entries = []
    for r in results:
        c = by_key[r["key"]]
        entries.append({"key": c.key, "name": c.name, "inversion": c.inversion, "inversion_name": c.inversion_name,
                        "crank": c.crank_name, "foot_link": c.foot_name, **r})
    entries.sort(key=lambda e: _order(e, s["rank"]))
    for i, e in enumerate(entries):
        e["rank"] = i + 1
    return LegRanking(links, s, entries, executor.name, time.monotonic() - t0)
