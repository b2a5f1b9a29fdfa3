"""Every mistake made through the Python API is an AssurError that names the argument: text where numbers belong,
a path where a plan belongs, an empty batch for the forces, a setting of the wrong kind.

Each public call is made with every value of ``BAD`` in one argument (the others valid): it either works (an empty
batch of a solve is a valid empty answer) or raises an AssurError whose message names that argument. Once 200 of
720 such calls ended in a bare ValueError, TypeError, AttributeError or KeyError.
"""
import warnings
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import AssurError

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
BAD = ["x", "", None, [], [[]], np.array([]), float("nan"), [1, 2, 3], {"a": 1}, True, -1, np.zeros((2, 3, 4, 5)),
       b"x", object(), "1e9"]


@pytest.fixture(scope="module")
def ctx():
    from assur.synthesis import load_problem
    plan = assur.compile(assur.load(EXAMPLES / "walker_fourbar.toml"))
    return {"plan": plan, "rssr": assur.compile(assur.load(EXAMPLES / "rssr.toml")),
            "state": assur.solve(plan, inputs=[0.1]),
            "problem": load_problem(EXAMPLES / "synthesis" / "paper000_six_points.toml")}


def _calls(c):
    """(label, the argument the message must name, call of one bad value)."""
    from assur.synthesis import Evaluator, exact, load_problem, synthesize
    plan, rssr, problem = c["plan"], c["rssr"], c["problem"]
    fg = ([0.1, 0.5, 0.9], [2.1, 2.4, 2.9])
    mech = [("compile", "mechanism", lambda v: assur.compile(v)),
            ("solve plan", "plan", lambda v: assur.solve(v, inputs=[0.1])),
            ("solve params", "params", lambda v: assur.solve(plan, v, [0.1])),
            ("solve inputs", "inputs", lambda v: assur.solve(plan, inputs=v)),
            ("solve order", "order", lambda v: assur.solve(plan, inputs=[0.1], order=v)),
            ("solve on_unbuildable", "on_unbuildable", lambda v: assur.solve(plan, inputs=[0.1], on_unbuildable=v)),
            ("solve backend", "backend", lambda v: assur.solve(plan, inputs=[0.1], backend=v)),
            ("spatial inputs", "inputs", lambda v: assur.solve(rssr, inputs=v)),
            ("forces plan", "plan", lambda v: assur.forces(v, inputs=[0.1])),
            ("forces params", "params", lambda v: assur.forces(plan, v, [0.1])),
            ("forces inputs", "inputs", lambda v: assur.forces(plan, inputs=v)),
            ("forces speeds", "speeds", lambda v: assur.forces(plan, inputs=[0.1], speeds=v)),
            ("forces accels", "accels", lambda v: assur.forces(plan, inputs=[0.1], accels=v)),
            ("forces method", "method", lambda v: assur.forces(plan, inputs=[0.1], method=v)),
            ("forces backend", "backend", lambda v: assur.forces(plan, inputs=[0.1], backend=v)),
            ("forces point_loads", "point_loads", lambda v: assur.forces(plan, inputs=[0.1], point_loads=v)),
            ("spatial forces inputs", "inputs", lambda v: assur.forces(rssr, inputs=v)),
            ("gait_metrics plan", "plan", lambda v: assur.gait_metrics(v)),
            ("gait_metrics params", "params", lambda v: assur.gait_metrics(plan, v)),
            ("gait_metrics steps", "steps", lambda v: assur.gait_metrics(plan, steps=v)),
            ("transmission_angles state", "state", lambda v: assur.transmission_angles(plan, v)),
            ("dead_centres plan", "plan", lambda v: assur.dead_centres(v)),
            ("dead_centres steps", "steps", lambda v: assur.dead_centres(plan, steps=v)),
            ("summarize plan", "plan", lambda v: assur.summarize(v)),
            ("load", "path", lambda v: assur.load(v)),
            ("loads", "text", lambda v: assur.loads(v)),
            ("dumps", "mechanism", lambda v: assur.dumps(v)),
            ("param_index", "parameter", lambda v: plan.param_index(v)),
            ("point", "point", lambda v: c["state"].point(v)),
            ("analyse_structure", "mechanism", lambda v: assur.analyse_structure(v)),
            ("Builder point", "points", lambda v: assur.Builder().point(v, 0, 0).build()),
            ("plot", "plot", lambda v: assur.plot.mechanism(v))]
    synth = [("load_problem", "path", lambda v: load_problem(v)),
             ("Evaluator problem", "problem", lambda v: Evaluator(v)),
             ("Evaluator X", "X", lambda v: Evaluator(problem)(v)),
             ("synthesize problem", "problem", lambda v: synthesize(v, budget=50))]
    synth += [(f"synthesize {k}", "time_limit" if k == "time" else k,
               (lambda k: lambda v: synthesize(problem, **{"budget": 50, "polish": "none",
                                                           "time_limit" if k == "time" else k: v}))(k))
              for k in ("method", "seed", "time", "starts", "popsize", "polish", "maxiter", "target", "strategy")]
    synth += [("synthesize budget", "budget", lambda v: synthesize(problem, budget=v)),
              ("synthesize x0", "x0", lambda v: synthesize(problem, "local", x0=v, budget=50)),
              ("function_generation inputs", "inputs", lambda v: exact.function_generation(v, fg[1])),
              ("function_generation outputs", "inputs", lambda v: exact.function_generation(fg[0], v)),
              ("function_generation ground", "ground", lambda v: exact.function_generation(*fg, ground=v)),
              ("function_generation limit", "limit", lambda v: exact.function_generation(*fg, limit=v)),
              ("function_generation units", "units", lambda v: exact.function_generation(*fg, units=v)),
              ("motion_generation poses", "poses", lambda v: exact.motion_generation(v))]
    return mech + synth


def test_every_api_mistake_is_an_assur_error_naming_the_argument(ctx):
    failures = []
    for label, arg, call in _calls(ctx):
        for v in BAD:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    call(v)
                except AssurError as exc:
                    # a path or a text is named by the argument, or by itself where it was read as one (a file
                    # that does not exist, a text that is not a mechanism: the message is about that file or text)
                    read = arg in ("path", "text", "plot") and isinstance(v, str)
                    if arg not in str(exc) and not read:
                        failures.append(f"{label}({v!r:.30}): the message does not name {arg!r}: {exc}")
                except Exception as exc:                     # noqa: BLE001 - any other exception is the finding
                    failures.append(f"{label}({v!r:.30}): {type(exc).__name__}: {exc}"[:200])
    assert not failures, f"{len(failures)} calls:\n" + "\n".join(failures[:40])


def test_errors_keep_their_builtin_kinds(ctx):
    """The new errors are still the built-in exceptions a caller may catch: a wrong type is a TypeError, an
    unknown name a KeyError, a bad value a ValueError."""
    with pytest.raises(TypeError):
        assur.solve("examples/crank_rocker.toml", inputs=[0.1])
    with pytest.raises(KeyError):
        ctx["plan"].point_index("nope")
    with pytest.raises(ValueError):
        assur.solve(ctx["plan"], inputs="x")
    with pytest.raises(assur.SpecError, match=r"inputs: no sample to analyse"):
        assur.forces(ctx["plan"], inputs=[])
    msg = str(pytest.raises(assur.SpecError, assur.compile, "examples/crank_rocker.toml").value)
    assert "assur.load(path)" in msg
