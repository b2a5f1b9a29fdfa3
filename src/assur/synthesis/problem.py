"""Synthesis problems: a template mechanism, design variables with bounds, targets, objective terms
and constraints — read from a TOML file (``format = "assur-synth/1"``) or built in Python.

Numbers in a problem file are in the template mechanism file's units (lengths in its length unit,
angles in its angle unit); inside, everything is SI. Objective values are reported in the file's
length unit (a sum of distances in mm for a problem in mm, squared distances in mm²).

    format = "assur-synth/1"
    mechanism = "../walker_crank_slider.toml"      # the template, relative to this file
    [variables]
    "rod.A.distance" = [1, 1000]                     # a mechanism parameter with its bounds …
    theta0 = { bounds = [0, 360], kind = "angle" }   # … or a free variable used by [parameters]
    [parameters]
    "O4.x" = "x0 + r1*cos(theta0)"                   # mechanism parameter = expression (SI)
    [targets]
    point = "A"
    xy = [[-150, 130], [-75, 130]]
    inputs = [90, 135]                               # timing: "prescribed" | "free" | "uniform" | "path"
    [objective]
    deviation = "distance"                           # "distance" | "squared" | "none"
    [[objective.terms]]
    quantity = "gait.sag"                            # weight·quantity, or weight·|quantity − target|
    weight = 1.0
    [constraints]
    use = ["grashof", "assembly"]
    fourbar = { ground = "r1", crank = "r2", coupler = "r3", rocker = "r4" }
    [[constraints.limits]]
    quantity = "gait.step"                           # or expression = "rod.length - crank.length"
    min = 300
"""
from __future__ import annotations

import dataclasses
import math
import os
import re
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np

from ..analysis.transmission import has_transmission
from ..dynamics.quantities import DYNAMICS_QUANTITIES, check_dynamics
from ..engine import PARAM_KINDS
from ..engine import compile as compile_
from ..errors import ExpressionError, SpecError
from ..io.expressions import Expression
from ..io.mechanism_file import load
from ..io.problems import Problems
from ..io.toml_reader import read_toml
from ..io.units import ANGLE, LENGTH
from ..kinetostatics.gait import phase_shifts
from ..model.mechanism import Mechanism
from .solver import read_solver
from .targets import FUNCTION_OUTPUTS, TARGET_KINDS, Targets, parse_targets

FORMAT = "assur-synth/1"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")
DEVIATIONS = ("distance", "squared", "none")
KINDS = PARAM_KINDS
#: quantities a term or a limit may name (besides expressions); units: the file's
QUANTITIES = {
    "deviation": "the deviation sum of [objective].deviation",
    "acceleration": "eq. (6) of paper 000: sum over the targets of (d²x/dq²)² of the target point",
    "gait.step": "step length (x-range of the contact arc)",
    "gait.lift": "foot lift (range of the height over the cycle)",
    "gait.sag": "height range over the contact arc",
    "gait.clearance": "how far the foot rises above its support in the swing: lift − sag (0 for a foot that "
                      "retraces its support)",
    "gait.duty": "contact share of the cycle",
    "gait.speed_spread": "(max − min)/mean of the foot speed over the contact arc",
    "gait.speed_mean": "mean foot speed over the contact arc (length unit per second)",
    "gait.top": "the foot path's highest point along up (a coordinate: P·up in the file's length unit)",
    "gait.vx_spread": "(max − min)/mean of |v_x| over the contact samples in the central 80 % of the stride",
    "gait.vx_spread_90": "(max − min)/mean of |v_x| over the contact samples in the central 90 % of the stride",
    "transmission.min": "smallest transmission angle over the cycle, folded to [0°, 90°] (angle unit)",
    "unbuildable": "share of the cycle that cannot be assembled",
    "forces.torque_peak": "largest |driving torque| over the cycle (N·m; N for a linear driver; a walking "
                          "module's shaft torque)",
    "forces.torque_rms": "RMS of the driving torque over the cycle (N·m; N for a linear driver)",
    "forces.reaction_peak": "largest joint reaction magnitude over all joints and the cycle (N)",
    **DYNAMICS_QUANTITIES,
}
#: the quantity families that sample the whole input cycle (and so imply the buildable constraint)
CYCLE_FAMILIES = ("gait.", "transmission.", "forces.", "dynamics.")
CONSTRAINTS = {
    "assembly": "every target position can be assembled (always active)",
    "buildable": "the whole input cycle can be assembled (sampled at cycle_samples)",
    "grashof": "four-bar: s + l ≤ p + q",
    "continuous_motion": "four-bar: the crank passes the whole interval the targets span",
    "nondegenerate": "four-bar: every link length > 0",
    "r2_shortest": "four-bar: the crank is the shortest link",
    "cyclic_order": "free timing: the targets are passed in order within one counter-clockwise turn",
    "cyclic_order_any": "free timing: in order within one turn, either direction",
    "cidetec_order": "four-bar: r1 + r2 ≤ r3 + r4 and r2 ≤ r3 ≤ r4 ≤ r1",
    "ascending": "free timing: crank angles ascending without wrap-around",
    "defects": "the targets are met in their order (increasing input) on the design's assembly branch, with the "
               "whole stretch between them buildable (on by default for function and poses targets)",
}
FOURBAR_CONSTRAINTS = {"grashof", "continuous_motion", "nondegenerate", "r2_shortest", "cidetec_order"}
FREE_TIMING_CONSTRAINTS = {"cyclic_order", "cyclic_order_any", "ascending"}


#: the most cycle samples a problem may ask for (each design is solved at every one)
MAX_CYCLE_SAMPLES = 100_000

@dataclass(frozen=True, slots=True)
class Variable:
    """A design variable: bounds in SI; ``periodic`` angles are wrapped into [0, 2π) before use."""
    name: str
    low: float
    high: float
    kind: str = "length"
    periodic: bool = False


@dataclass(frozen=True, slots=True)
class Term:
    """weight·quantity, or weight·|quantity − target| when ``target`` is given."""
    quantity: str
    weight: float = 1.0
    target: float | None = None
    expression: Expression | None = None


@dataclass(frozen=True, slots=True)
class Limit:
    """min ≤ quantity ≤ max (either may be None); violation in the quantity's unit."""
    quantity: str
    low: float | None = None
    high: float | None = None
    expression: Expression | None = None


@dataclass(frozen=True, slots=True)
class Problem:
    """A dimensional-synthesis problem (see the module docstring). Picklable."""
    plan: object                                  # PlanarPlan of the template
    variables: tuple[Variable, ...]
    parameters: tuple[tuple[str, Expression], ...]
    targets: Targets | None = None
    deviation: str = "distance"
    deviation_weight: float = 1.0
    terms: tuple[Term, ...] = ()
    constraints: tuple[str, ...] = ("assembly",)
    limits: tuple[Limit, ...] = ()
    fourbar: tuple[tuple[str, Expression], ...] = ()
    cycle_samples: int = 360
    infeasible_offset: float = 1e7
    violation_weight: float = 1e3
    name: str = ""
    description: str = ""
    source: str | None = None
    mechanism_source: str | None = None
    length_unit: str = "m"
    angle_unit: str = "rad"
    solver: dict = field(default_factory=dict)    # the file's [solver] defaults (synthesis/solver.py)
    placement: object = None                      # synthesis.placement.PlacementVariables, or None

    @property
    def n_vars(self) -> int:
        return len(self.variables)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.variables)

    @property
    def bounds(self) -> np.ndarray:
        """(n_vars, 2) SI bounds."""
        return np.array([[v.low, v.high] for v in self.variables], dtype=float)

    @property
    def length_scale(self) -> float:
        """Multiply an SI length by this to get the file's length unit."""
        return 1.0 / LENGTH[self.length_unit]

    def variable_scale(self) -> np.ndarray:
        """(n_vars,) factor SI → file units for each variable."""
        return np.array([1.0 / LENGTH[self.length_unit] if v.kind == "length" else
                         1.0 / ANGLE[self.angle_unit] if v.kind == "angle" else 1.0 for v in self.variables])

    def to_si(self, x_file) -> np.ndarray:
        """Design vectors in file units (..., n_vars) → SI."""
        from ..errors import float_array
        x = float_array(x_file, "x0", "a design vector of numbers (file units)")
        if x.shape[-1:] != (self.n_vars,):
            raise SpecError([("x0", f"must have {self.n_vars} entries ({', '.join(self.names)}): shape {x.shape}")])
        return x / self.variable_scale()

    def to_file(self, x_si) -> np.ndarray:
        return np.asarray(x_si, dtype=float) * self.variable_scale()

    def needs_cycle(self) -> bool:
        """Whether an evaluation samples the whole input cycle (buildability, gait, transmission, path)."""
        q = {t.quantity for t in self.terms} | {lim.quantity for lim in self.limits}
        return ("buildable" in self.constraints or "defects" in self.constraints
                or (self.targets is not None and self.targets.timing == "path")
                or any(s.startswith(CYCLE_FAMILIES) or s == "unbuildable" for s in q))


# -- reading ------------------------------------------------------------------------------------------
_TOP = {"format", "name", "description", "mechanism", "variables", "parameters", "targets", "objective",
        "constraints", "options", "solver"}


def load_problem(path) -> Problem:
    """Read a problem file. Raises SpecError listing every problem with its location."""
    if not isinstance(path, str) and not hasattr(path, "__fspath__") or str(path) == "":
        from ..errors import ArgumentTypeError
        raise ArgumentTypeError([("path", f"must be a problem file's path (text or a pathlib.Path): {path!r:.60}")])
    path = Path(path)
    return problem_from_dict(read_toml(path), base_dir=path.parent, source=str(path))


def problem_from_dict(data: dict, *, base_dir=".", source: str | None = None, mechanism=None) -> Problem:
    """Build a Problem from a parsed document. ``mechanism`` (a Mechanism or a PlanarPlan) replaces
    the document's ``mechanism`` path (the Python route).

    Each section has its reader below, called in turn; every reader adds its problems to one list, raised at
    the end (a template that does not read stops the reading there: the rest depends on its parameters)."""
    P = Problems()
    P.unknown_keys(data, sorted(_TOP))
    if data.get("format") != FORMAT:
        P.add("format", f"must be '{FORMAT}': {data.get('format')!r}")
    mechanism, plan, mech_source = _read_template(data, P, base_dir, source, mechanism)
    units = mechanism.units
    L, A = LENGTH[units.length], ANGLE[units.angle]
    params = set(plan.param_names)
    number = partial(_number, P)
    variables = _read_variables(data, P, plan, {"length": L, "angle": A, "number": 1.0}, number)
    var_names = {v.name for v in variables}
    expression = partial(_expression, P, var_names | params)
    mapping = _read_parameters(data, P, plan, variables, var_names | params, expression)
    unused = var_names - params - {n for _, e in mapping for n in e.names}
    targets = parse_targets(data.get("targets"), plan, L, A, number, P)
    if targets is not None:
        for vn in (*targets.input_variables, *([targets.start] if targets.start else [])):
            unused.discard(vn)
            if vn not in var_names:
                P.add("targets", f"timing names {vn!r}, which is not a design variable")
    obj = _with_array_of_tables(P.section(data, "objective"), "objective", "terms", P)
    deviation, dev_weight, terms = _read_objective(obj, P, targets, expression, number)
    con = _with_array_of_tables(P.section(data, "constraints"), "constraints", "limits", P)
    constraints, fourbar, limits = _read_constraints(con, obj, P, plan, targets, expression, number)
    samples, offset, vw = _read_options(data, P, number)
    _check_quantities(mechanism, plan, obj, con, samples, P)
    if not (deviation != "none" or terms):
        P.add("objective", "nothing to minimise: give a deviation or terms")
    for vn in sorted(unused):
        P.add(f"variables.{vn}", "is used by no parameter, timing or expression")
    if plan.n_inputs != 1 and targets is not None:
        P.add("targets", f"target timing needs a mechanism with one input; this one has {plan.n_inputs}")
    solver = read_solver(data.get("solver"), P)
    targets = _settle_free_timing(data, P, plan, targets, mapping, terms, limits, fourbar)
    if P:
        raise P.error(source)
    problem = Problem(plan=plan, variables=tuple(variables), parameters=tuple(mapping), targets=targets,
                      deviation=deviation, deviation_weight=dev_weight, terms=tuple(terms), constraints=constraints,
                      limits=tuple(limits), fourbar=tuple(fourbar), cycle_samples=samples, infeasible_offset=offset,
                      violation_weight=vw, name=str(data.get("name", "")), description=str(data.get("description", "")),
                      source=source, mechanism_source=mech_source, length_unit=units.length, angle_unit=units.angle,
                      solver=solver)
    from .placement import settle
    return settle(data, problem, source)


def _with_array_of_tables(table: dict, path: str, key: str, P) -> dict:
    """``table`` itself when its ``key`` is absent or a list (an array of tables, ``[[path.key]]``); else a problem
    at ``path.key`` and a copy of the table with an empty list there."""
    if isinstance(table.get(key, []), list):
        return table
    P.add(f"{path}.{key}", f"must be an array of tables [[{path}.{key}]]")
    return {**table, key: []}


def _number(P, where, v) -> float | None:
    """``v`` as a float; None with a problem at ``where`` when it is not a finite number."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        P.add(where, f"must be a finite number: {v!r}")
        return None
    return float(v)


def _expression(P, known, where, text) -> Expression | None:
    """An expression over the names ``known``; None with a problem at ``where`` when it does not read."""
    try:
        return Expression(text, known)
    except ExpressionError as exc:
        P.add(where, str(exc))
        return None


def _read_template(data, P, base_dir, source, mechanism):
    """``mechanism``: the template (a file relative to ``base_dir``, or the Mechanism or plan given) as
    (mechanism, plan, the file's path or None); raises the problems so far when it cannot be had."""
    mech_source = None
    if mechanism is None:
        ref = data.get("mechanism")
        if not isinstance(ref, str) or not ref:
            P.add("mechanism", f"must be the path of a mechanism file: {ref!r}")
            raise P.error(source)
        mech_path = (Path(base_dir) / ref)
        mech_source = os.path.normpath(mech_path)     # examples/crank_rocker.toml, not examples/synthesis/../…
        try:
            mechanism = load(mech_path)
        except SpecError as exc:
            P.extend((f"mechanism ({ref})" + (f": {p}" if p else ""), m) for p, m in exc.problems)
            raise P.error(source)
    if isinstance(mechanism, Mechanism):
        plan = compile_(mechanism)
    else:
        plan = mechanism
        mechanism = plan.mechanism
    if P:
        raise P.error(source)
    return mechanism, plan, mech_source


def _read_variables(data, P, plan, scale: dict, number) -> list[Variable]:
    """``[variables]``: name = [low, high] or {bounds, kind, periodic}; bounds in file units (``scale`` per kind
    to SI)."""
    params = set(plan.param_names)
    variables = []
    raw_vars = data.get("variables", {})
    if not isinstance(raw_vars, dict) or not raw_vars:
        P.add("variables", "must be a table of at least one design variable with its bounds")
        raw_vars = {}
    for name, spec in raw_vars.items():
        where = f"variables.{name}"
        kind = plan.param_kind_of(name) if name in params else "length"
        periodic = None
        if isinstance(spec, dict):
            P.unknown_keys(spec, ("bounds", "kind", "periodic"), where)
            kind = spec.get("kind", kind)
            periodic = spec.get("periodic")
            spec = spec.get("bounds")
        if kind not in KINDS:
            P.add(f"{where}.kind", f"must be one of {', '.join(KINDS)}: {kind!r}")
            continue
        if not (isinstance(spec, list) and len(spec) == 2):
            P.add(where, f"bounds must be [low, high]: {spec!r}")
            continue
        lo, hi = number(f"{where}[0]", spec[0]), number(f"{where}[1]", spec[1])
        if lo is None or hi is None:
            continue
        if not lo < hi:
            P.add(where, f"low bound must be below the high bound: [{lo:g}, {hi:g}]")
            continue
        if name in params and (name.endswith(".length") and lo <= 0 or name.endswith(".distance") and lo < 0):
            P.add(where, f"a {'link length' if name.endswith('.length') else 'distance'} must stay "
                         f"{'positive' if name.endswith('.length') else 'non-negative'}: low bound {lo:g} would "
                         "give non-physical designs")
            continue
        if not _NAME.match(name):
            P.add(where, f"a variable name must be an identifier or a parameter name: {name!r}")
            continue
        if periodic is None:
            periodic = kind == "angle"
        variables.append(Variable(name, lo * scale[kind], hi * scale[kind], kind, bool(periodic)))
    return variables


def _read_parameters(data, P, plan, variables, known, expression) -> list[tuple[str, Expression]]:
    """``[parameters]``: parameter = "expression"; after the identity of each variable that is a parameter."""
    params = set(plan.param_names)
    var_names = {v.name for v in variables}
    mapping = [(v.name, Expression(v.name, known)) for v in variables if v.name in params]
    raw_params = P.section(data, "parameters", "must be a table: parameter = \"expression\"")
    for name, text in raw_params.items():
        where = f"parameters.{name}"
        if name not in params:
            shown = ", ".join(plan.param_names[:14]) + (", …" if len(plan.param_names) > 14 else "")
            P.add(where, f"not a parameter of the mechanism{_did_you_mean(name, plan.param_names)} (its parameters: "
                         f"{shown})")
            continue
        if name in var_names:
            P.add(where, "is already a design variable")
            continue
        if not isinstance(text, (str, int, float)) or isinstance(text, bool):
            P.add(where, f"must be an expression string or a number: {text!r}")
            continue
        e = expression(where, str(text))
        if e is not None:
            mapping.append((name, e))
    return mapping


def _read_objective(obj, P, targets, expression, number):
    """``[objective]``: the deviation of the targets, its weight and the terms, as (deviation, weight, terms)."""
    P.unknown_keys(obj, ("deviation", "weight", "terms"), "objective")
    deviation = obj.get("deviation", "distance" if targets is not None else "none")
    if deviation not in DEVIATIONS:
        P.add("objective.deviation", f"must be one of {', '.join(DEVIATIONS)}: {deviation!r}")
    elif deviation != "none" and targets is None:
        P.add("objective.deviation", "needs [targets]")
    dev_weight = number("objective.weight", obj.get("weight", 1.0)) or 0.0
    terms = []
    for i, t in enumerate(obj.get("terms", [])):
        item = _quantity_item(t, f"objective.terms[{i}]", ("weight", "target"), expression, number, P, targets)
        if item is not None:
            q, e, extra = item
            w = extra.get("weight", 1.0)
            terms.append(Term(q, 1.0 if w is None else w, extra.get("target"), e))
    return deviation, dev_weight, terms


def _read_constraints(con, obj, P, plan, targets, expression, number):
    """``[constraints]``: the constraints used (named, and implied by the targets and quantities), the four-bar's
    link lengths and the limits, as (constraints, fourbar, limits)."""
    P.unknown_keys(con, ("use", "fourbar", "limits", "defects"), "constraints")
    use = con.get("use", [])
    if not isinstance(use, list):
        P.add("constraints.use", "must be a list of constraint names")
        use = []
    for i, c in enumerate(use):
        if not isinstance(c, str) or c not in CONSTRAINTS:
            P.add(f"constraints.use[{i}]", f"unknown constraint {c!r} (known: {', '.join(CONSTRAINTS)})")
    use = [c for c in use if isinstance(c, str) and c in CONSTRAINTS]
    implied = []   # a path without timing, gait and transmission quantities need the whole cycle
    named = {str(x.get("quantity")) for x in [*obj.get("terms", []), *con.get("limits", [])] if isinstance(x, dict)}
    if (targets is not None and targets.timing == "path") or any(q.startswith(CYCLE_FAMILIES) for q in named):
        implied.append("buildable")
    defects = con.get("defects", targets is not None and targets.kind != "points")
    if not isinstance(defects, bool):
        P.add("constraints.defects", f"must be true or false: {defects!r}")
        defects = False
    if defects:
        implied.append("defects")
    elif "defects" in use and "defects" in con:
        P.add("constraints.defects", "is false, but constraints.use lists 'defects'")
    constraints = tuple(dict.fromkeys(["assembly", *use, *implied]))
    fourbar = _read_fourbar(con.get("fourbar"), P, expression)
    _check_constraints_apply(constraints, use, con.get("fourbar") is not None, P, plan, targets)
    limits = []
    for i, t in enumerate(con.get("limits", [])):
        item = _quantity_item(t, f"constraints.limits[{i}]", ("min", "max"), expression, number, P, targets)
        if item is not None:
            q, e, extra = item
            if extra.get("min") is None and extra.get("max") is None:
                P.add(f"constraints.limits[{i}]", "needs min or max")
            limits.append(Limit(q, extra.get("min"), extra.get("max"), e))
    return constraints, fourbar, limits


def _read_fourbar(raw_fb, P, expression) -> list[tuple[str, Expression]]:
    """``constraints.fourbar``: the expressions of the ground, crank, coupler and rocker lengths."""
    fourbar = []
    if raw_fb is not None:
        if not isinstance(raw_fb, dict) or set(raw_fb) != {"ground", "crank", "coupler", "rocker"}:
            P.add("constraints.fourbar", "must give ground, crank, coupler and rocker (expressions)")
        else:
            for role in ("ground", "crank", "coupler", "rocker"):
                e = expression(f"constraints.fourbar.{role}", str(raw_fb[role]))
                if e is not None:
                    fourbar.append((role, e))
    return fourbar


def _check_constraints_apply(constraints, use, has_fourbar: bool, P, plan, targets) -> None:
    """Each constraint has what it needs: the four-bar's lengths, free timing, timed targets, one rotary input."""
    for c in constraints:
        if c in FOURBAR_CONSTRAINTS and not has_fourbar:
            P.add("constraints.use", f"{c!r} needs constraints.fourbar (the four link lengths)")
        if c in FREE_TIMING_CONSTRAINTS and (targets is None or targets.timing != "free"):
            P.add("constraints.use", f"{c!r} applies to free timing only ([targets] timing = \"free\")")
        if c == "continuous_motion" and targets is not None and targets.timing == "path":
            P.add("constraints.use", "'continuous_motion' needs timed targets; use 'buildable' for a path")
        if c == "defects" and (targets is None or plan.n_inputs != 1 or plan.input_kinds[0] != "rotary"):
            P.add("constraints.use" if "defects" in use else "constraints.defects",
                  "'defects' needs [targets] and a mechanism with one rotary input")


def _read_options(data, P, number) -> tuple[int, float, float]:
    """``[options]``: (cycle_samples, infeasible_offset, violation_weight)."""
    opts = P.section(data, "options")
    P.unknown_keys(opts, ("cycle_samples", "infeasible_offset", "violation_weight"), "options")
    samples = opts.get("cycle_samples", 360)
    if isinstance(samples, bool) or not isinstance(samples, int) or not 16 <= samples <= MAX_CYCLE_SAMPLES:
        P.add("options.cycle_samples", f"must be an integer from 16 to {MAX_CYCLE_SAMPLES}: {samples!r}")
        samples = 360
    offset = number("options.infeasible_offset", opts.get("infeasible_offset", 1e7)) or 1e7
    vw = number("options.violation_weight", opts.get("violation_weight", 1e3)) or 1e3
    return samples, offset, vw


def _check_quantities(mechanism, plan, obj, con, samples, P) -> None:
    """The forces.* and dynamics.* quantities of the terms and limits can be computed for this mechanism."""
    items = [(f"objective.terms[{i}]", t) for i, t in enumerate(obj.get("terms", []))] \
        + [(f"constraints.limits[{i}]", t) for i, t in enumerate(con.get("limits", []))]
    _check_forces(mechanism, items, samples, P)
    why = check_dynamics(plan)
    for where, t in items:
        q = t.get("quantity") if isinstance(t, dict) else None
        if why is not None and isinstance(q, str) and q in DYNAMICS_QUANTITIES:
            P.add(f"{where}.quantity", f"{q} {why}")
        if q == "transmission.min" and not has_transmission(plan):
            P.add(f"{where}.quantity", "transmission.min: the mechanism has no dyad with a transmission angle (its "
                                       "groups: " + ", ".join(dict.fromkeys(st.kind for st in plan.steps)) + ")")


def _settle_free_timing(data, P, plan, targets, mapping, terms, limits, fourbar):
    """The targets with free_timing 'inner' kept where it applies: refused when the file asks for it and it
    cannot be used, else (the default) replaced by the explicit formulation."""
    if targets is not None and targets.free_timing == "inner":
        why = _inner_timing_refusal(plan, targets, mapping, terms, limits, fourbar)
        if why and isinstance(data.get("targets"), dict) and "free_timing" in data["targets"]:
            P.add("targets.free_timing", f"'inner' cannot be used here: {why} (use \"explicit\")")
        elif why:                          # the default where it applies: else the explicit formulation
            targets = dataclasses.replace(targets, free_timing="explicit")
    return targets


def _inner_timing_refusal(plan, targets, mapping, terms, limits, fourbar) -> str | None:
    """Why free timing cannot be solved inside the evaluation (None when it can): it needs one rotary input and
    timing variables that enter the objective only through the targets' distances."""
    if plan.n_inputs != 1 or plan.input_kinds[0] != "rotary":
        return "it needs a mechanism with one rotary input"
    timing = set(targets.input_variables)
    exprs = [e for _, e in mapping] + [e for _, e in fourbar] + [t.expression for t in (*terms, *limits)
                                                                 if t.expression is not None]
    used = sorted(timing & {n for e in exprs for n in e.names})
    if used:
        return f"the timing variable {used[0]!r} enters an expression"
    if any(t.quantity == "acceleration" for t in (*terms, *limits)):
        return "the 'acceleration' quantity depends on the timing beyond the distances"
    return None


def _did_you_mean(name: str, known) -> str:
    """' (did you mean 'x'?)' for the closest known name, or ''."""
    import difflib
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _check_forces(mechanism, items, samples, P) -> None:
    """A forces.* quantity needs something to carry (masses, loads or a walking leg's body weight), a planar
    mechanism, and a walking module's leg phases on the cycle samples."""
    dyn, gait = mechanism.dynamics, mechanism.gait
    loaded = (dyn is not None and (dyn.has_mass or bool(dyn.loads))) or (gait is not None and gait.weight is not None)
    used = False
    for where, t in items:
        q = t.get("quantity") if isinstance(t, dict) else None
        if not (isinstance(q, str) and q.startswith("forces.") and q in QUANTITIES):
            continue
        used = True
        if mechanism.dimension != 2:
            P.add(f"{where}.quantity", f"{q} needs a planar mechanism")
        elif not loaded:
            P.add(f"{where}.quantity", f"{q} needs masses, loads or [gait] weight in the mechanism (mass on "
                                       "[links.X], [[loads]], [gait] weight); without them every force is zero")
    if used and gait is not None and isinstance(samples, int) and samples > 0:
        try:
            phase_shifts(gait.phases, samples)
        except SpecError as exc:
            P.add("options.cycle_samples", f"forces.* quantities: {exc.problems[0][1]}")


def _quantity_item(t, where, keys, expression, number, P, targets):
    if not isinstance(t, dict):
        P.add(where, "must be a table with quantity (or expression)")
        return None
    P.unknown_keys(t, ("quantity", "expression", *keys), where)
    q, text = t.get("quantity"), t.get("expression")
    if (q is None) == (text is None):
        P.add(where, "give exactly one of quantity or expression")
        return None
    e = None
    if text is not None:
        e = expression(f"{where}.expression", str(text))
        if e is None:
            return None
        q = f"expression:{text}"
    elif not isinstance(q, str) or q not in QUANTITIES:
        hint = _did_you_mean(q, QUANTITIES) if isinstance(q, str) else ""
        P.add(f"{where}.quantity", f"unknown quantity {q!r}{hint} (known: {', '.join(QUANTITIES)})")
        return None
    if q in ("deviation", "acceleration") and targets is None:
        P.add(f"{where}.quantity", f"{q!r} needs [targets]")
    elif q == "acceleration" and targets.kind == "function":
        P.add(f"{where}.quantity", "'acceleration' needs targets of a point (kind points or poses)")
    extra = {}
    for k in keys:
        if k in t:
            extra[k] = number(f"{where}.{k}", t[k])
    return q, e, extra


__all__ = ["CONSTRAINTS", "FORMAT", "FUNCTION_OUTPUTS", "Limit", "Problem", "QUANTITIES", "TARGET_KINDS", "Targets",
           "Term", "Variable",
           "load_problem", "problem_from_dict"]
