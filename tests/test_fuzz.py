"""Seeded mutations of every shipped example file of every format (mechanism, gear pair, wheel-step, synthesis
problem): the readers and the engine either accept the mutant or refuse it with an AssurError that says what
and where. Never another exception (a traceback for the user), never a hang, never a finite answer from an
unassemblable position."""
import os
import random
import re
import signal
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.errors import AssurError

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted(p for p in (ROOT / "examples").rglob("*.toml"))
MUTANTS_PER_FILE = 25
#: values substituted for a number, a string or a whole value
WILD = ["-1", "0", "1e400", "-1e308", "1e-320", "nan", "inf", '"x"', '""', "[]", "[1, 2, 3]", "{ a = 1 }", "true",
        '"1e400 rpm"', '"-5 mm"', "2e8", "-2e8", "[[1]]", '"O2"']
NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w.])")


def mutate(text: str, rng: random.Random) -> str:
    """One seeded mutation: a number, a value or a line replaced, deleted, duplicated or truncated."""
    lines = text.splitlines()
    kind = rng.randrange(5)
    i = rng.randrange(len(lines))
    if kind == 0:                                         # a number → a wild value
        nums = list(NUMBER.finditer(text))
        if nums:
            m = rng.choice(nums)
            return text[:m.start()] + rng.choice(WILD) + text[m.end():]
    if kind == 1 and "=" in lines[i] and not lines[i].lstrip().startswith("#"):   # a whole value → a wild value
        key = lines[i].split("=", 1)[0]
        lines[i] = f"{key}= {rng.choice(WILD)}"
    elif kind == 2:                                       # a line deleted
        del lines[i]
    elif kind == 3:                                       # a line duplicated (a duplicate key, a repeated table)
        lines.insert(i, lines[i])
    else:                                                 # truncated
        lines = lines[:i]
    return "\n".join(lines) + "\n"


@contextmanager
def time_limit(seconds: int):
    def fail(signum, frame):
        raise TimeoutError(f"no answer within {seconds} s (a hang)")
    old = signal.signal(signal.SIGALRM, fail)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def exercise(path: Path, text: str):
    """Read the text the way its command would, and use the result a little."""
    tmp = path.parent / f".fuzz-{path.name}"
    if 'format = "assur/1"' in text:
        plan = assur.compile(assur.loads(text, source=str(path)))
        one_crank = plan.n_inputs == 1 and plan.input_kinds[0] == "rotary"
        q = np.linspace(0.0, 2 * np.pi, 24, endpoint=False) if one_crank else plan.sketch_inputs
        st = assur.solve(plan, inputs=q, order=2)
        assert not np.isfinite(st.pos[~st.valid]).any()  # no finite garbage from an unassemblable position
        return
    if "assur-synth/1" in text:
        from assur.synthesis.problem import load_problem
        tmp.write_text(text, encoding="utf-8")
        try:
            load_problem(tmp)
        finally:
            tmp.unlink()
        return
    from assur.io.gear_file import load_design
    tmp.write_text(text, encoding="utf-8")
    try:
        design = load_design(tmp)
    finally:
        tmp.unlink()
    check_design(design)


def check_design(design):
    """The cheap checks of a gear-pair or wheel-step design (what `assur gears` computes first, at few samples;
    not the minute-long outputs): the shoe profile, the pitch curves' closure and curvature, the sector tables and
    outlines, and a short mesh check of the sector scheme at the installation distance."""
    import dataclasses
    import math

    from assur.gears.design import GearDesign
    from assur.gears.mesh import mesh_check, polar_outline
    from assur.gears.pitch import closure_report, curvature_report
    gears = design
    if not isinstance(design, GearDesign):
        phi = np.linspace(-math.pi / 4, math.pi / 4, 19)
        design.shoe.profile(phi)
        design.shoe.curvature_radius(phi)
        gears = design.gears
        if gears is None:
            return
    pair = gears.pair(samples=512)
    closure_report(pair)
    for curve in (pair.driving, pair.driven):
        curvature_report(curve, module=gears.module, pressure_angle=gears.pressure_angle)
    if gears.method == "sectors":
        from assur.gears.sectors import sector_findings, sector_outline, table1, table2, table3
        model = gears.sector_model()
        table1(model, gears.module)
        table2(model, gears.module, gears.backlash)
        table3(model, gears.module, gears.backlash)
        sector_findings(model, gears.law, gears.module)
        so = sector_outline(model, gears.module, gears.backlash, linking="relieved", dedendum=gears.dedendum)
        p1 = polar_outline(so.driving, rays=64 * so.teeth[0])
        p2 = polar_outline(so.driven, rays=64 * so.teeth[1])
        at = dataclasses.replace(pair, centre_distance=gears.installation_distance)
        mesh_check(p1, p2, at, steps=8, pitch=math.pi * gears.module)


@pytest.mark.slow
@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: str(p.relative_to(ROOT / "examples")))
def test_mutants_are_accepted_or_refused_with_an_assur_error(path):
    text = path.read_text(encoding="utf-8")
    exercise(path, text)                                   # the shipped file itself works
    rng = random.Random(f"fuzz:{path.name}")
    failures = []
    for k in range(MUTANTS_PER_FILE):
        mutant = mutate(text, rng)
        try:
            with time_limit(60):
                exercise(path, mutant)
        except AssurError:
            pass
        except Exception as exc:                           # noqa: BLE001 - any other exception is the finding
            failures.append(f"mutant {k}: {type(exc).__name__}: {exc}\n--- diff: "
                            + "; ".join(sorted(set(mutant.splitlines()) - set(text.splitlines())))[:300])
    assert not failures, "\n".join(failures)


# -- the readers of other tools' files (assur import) -------------------------------------------------------------
CROSS = ROOT / "tests" / "crosscheck" / "data"


def foreign_documents():
    """(id, format, text) of the peers' fixtures: PMKS+ links, four-bar-rs RON, Pyslvs projects, pylinkage JSON."""
    import json

    import yaml
    out = []
    for line in (CROSS / "pmks_fixture_urls.tsv").read_text(encoding="utf-8").splitlines()[3:12]:
        if line.strip() and not line.startswith("#"):
            name, gallery, link = line.split("\t")
            out.append((f"pmks:{name}:{gallery}", "pmks", link))
    for path in sorted((CROSS / "fourbar").glob("*.ron")):
        out.append((f"fourbar:{path.name}", "fourbar", path.read_text(encoding="utf-8")))
    examples = yaml.safe_load((CROSS / "pyslvs" / "examples.yaml").read_text(encoding="utf-8"))
    for name in ("Crank slider (RP joint)", "Inverted slider", "Jansen's linkage (Single)"):
        out.append((f"pyslvs:{name}", "pyslvs", yaml.safe_dump(examples[name])))
    from assur.interop.pylinkage_write import to_dict
    for name in ("crank_rocker.toml", "slider_crank.toml"):
        out.append((f"pylinkage:{name}", "pylinkage",
                    json.dumps(to_dict(assur.load(ROOT / "examples" / name)), indent=1)))
    return out


def mutate_line(text: str, rng: random.Random) -> str:
    """One seeded mutation of a one-line document: a character replaced, deleted or inserted, a stretch cut out or
    repeated, or the end cut off."""
    i = rng.randrange(len(text))
    kind = rng.randrange(5)
    if kind == 0:
        return text[:i] + rng.choice("0aZ_-.,*~%?") + text[i + 1:]
    if kind == 1:
        return text[:i] + text[i + 1:]
    if kind == 2:
        return text[:i] + rng.choice(".,0") + text[i:]
    if kind == 3:
        j = min(len(text), i + rng.randrange(1, 40))
        return text[:i] + text[i:j] * rng.randrange(0, 3) + text[j:]
    return text[:i]


@pytest.mark.slow
@pytest.mark.parametrize("name,fmt,text", foreign_documents(), ids=lambda x: str(x)[:40])
def test_foreign_mutants_are_imported_or_refused_with_an_assur_error(name, fmt, text):
    import warnings

    from assur.interop import import_mechanism
    rng = random.Random(f"fuzz:{name}")
    failures = []
    for k in range(MUTANTS_PER_FILE):
        mutant = mutate_line(text, rng) if "\n" not in text.strip() else mutate(text, rng)
        for given in (fmt, None):                  # named, and told from the content
            try:
                with time_limit(60), warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    plan = assur.compile(import_mechanism(mutant, format=given))
                    st = assur.solve(plan, inputs=plan.sketch_inputs, order=1)
                    assert not np.isfinite(st.pos[~st.valid]).any()
            except AssurError:
                pass
            except Exception as exc:               # noqa: BLE001 - any other exception is the finding
                failures.append(f"mutant {k} ({given}): {type(exc).__name__}: {exc}")
    assert not failures, "\n".join(failures[:10])


# -- the commands on mutants and wild options: an exit status, one error line, never a traceback or a hang ------
SYNTH = sorted((ROOT / "examples" / "synthesis").glob("*.toml"))
LOADED = [ROOT / "examples" / n for n in ("walker_fourbar.toml", "lever_manipulator.toml", "rssr.toml",
                                          "walker_crank_slider.toml", "walker_sixbar.toml")]
CLI_MUTANTS = 4


def _command(argv, limit: int = 120) -> str:
    """Run ``assur argv`` in this process: its exit status must be a documented one (0 done, 1 bad input, 2 usage,
    3 no feasible design) and a failure prints one ``error:`` line; any exception escaping the command is the
    finding. Returns a failure description or ''."""
    import contextlib
    import io

    from assur.cli.main import main
    err = io.StringIO()
    try:
        with time_limit(limit), contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main([str(a) for a in argv])
    except Exception as exc:                               # noqa: BLE001 - the finding
        return f"{' '.join(map(str, argv))}: {type(exc).__name__}: {exc}"[:300]
    lines = [ln for ln in err.getvalue().splitlines() if ln.startswith("error:")]
    if code not in (0, 1, 2, 3):
        return f"{' '.join(map(str, argv))}: exit status {code}"
    if code == 1 and len(lines) != 1:
        return f"{' '.join(map(str, argv))}: exit 1 with {len(lines)} error lines: {err.getvalue()[-300:]}"
    if "Traceback" in err.getvalue():
        return f"{' '.join(map(str, argv))}: a traceback"
    return ""


def _mutants(path: Path, n: int):
    """The file itself, then ``n`` seeded mutants, each written beside the original (a problem file names its
    template relative to itself) and removed after use."""
    text = path.read_text(encoding="utf-8")
    rng = random.Random(f"cli-fuzz:{path.name}")
    for k in range(n + 1):
        tmp = path.parent / f".fuzz-cli-{os.getpid()}-{path.name}"
        tmp.write_text(text if k == 0 else mutate(text, rng), encoding="utf-8")
        try:
            yield k, tmp
        finally:
            tmp.unlink()


@pytest.mark.slow
@pytest.mark.parametrize("path", SYNTH, ids=lambda p: p.name)
def test_synth_of_every_problem_kind_on_mutants(path, tmp_path):
    """Every shipped problem (points, function, poses, gait, forces, six-bars) and its mutants, through a short
    run, the exact method (a function or pose task, or the error that says it has none) and -o."""
    failures = []
    for k, tmp in _mutants(path, CLI_MUTANTS):
        out = tmp_path / f"best{k}.toml"
        for argv in (["synth", tmp, "--budget", "40", "--polish", "none", "--seed", "1", "--quiet", "-o", out],
                     ["synth", tmp, "--exact", "--limit", "2"]):
            failures.append(_command(argv))
    failures = [f for f in failures if f]
    assert not failures, "\n".join(failures)


@pytest.mark.slow
@pytest.mark.parametrize("path", LOADED, ids=lambda p: p.name)
def test_forces_on_mutants_of_the_loaded_examples(path, tmp_path):
    failures = []
    for k, tmp in _mutants(path, CLI_MUTANTS):
        for argv in (["forces", tmp, "--steps", "24"], ["forces", tmp, "--at", "30", "--at", "1e9", "--json"],
                     ["forces", tmp, "--steps", "12", "--friction", "--csv", tmp_path / f"f{k}.csv"]):
            failures.append(_command(argv))
    failures = [f for f in failures if f]
    assert not failures, "\n".join(failures)


@pytest.mark.slow
def test_codesign_on_mutants_and_wild_options(tmp_path):
    leg = ROOT / "examples" / "walker_fourbar.toml"
    cheap = ["--frames", "0", "--mesh-steps", "8", "--optimize", "none"]
    failures = []
    for k, tmp in _mutants(leg, CLI_MUTANTS):
        failures.append(_command(["codesign", tmp, "-o", tmp_path / f"m{k}", *cheap]))
    for k, extra in enumerate((["--window", "1.5"], ["--window", "1e-9"], ["--module", "1e9"],
                               ["--centre-distance", "1e-9"], ["--ratio-bounds", "3", "0.5"],
                               ["--direction", "nan"], ["--max-pressure-angle", "89.9"], ["--module", "x"])):
        failures.append(_command(["codesign", leg, "-o", tmp_path / f"w{k}", *cheap, *extra]))
    for other in ("jansen.toml", "rssr.toml", "slider_crank.toml", "walker_fourbar_geared.toml"):
        failures.append(_command(["codesign", ROOT / "examples" / other, "-o", tmp_path / other, *cheap]))
    failures = [f for f in failures if f]
    assert not failures, "\n".join(failures)


@pytest.mark.slow
def test_atlas_with_wild_options(tmp_path):
    failures = [_command(["atlas", *argv]) for argv in (
        ["--links", "0", "--dof", "1"], ["--links", "-3", "--dof", "1"], ["--links", "7", "--dof", "1"],
        ["--links", "60", "--dof", "1"], ["--links", "6", "--dof", "0"], ["--links", "6", "--dof", "99"],
        ["--links", "6"], ["--links", "x", "--dof", "1"], ["--assur-groups", "--links", "1"],
        ["--assur-groups", "--links", "99"], ["--walking-legs", "--links", "7"],
        ["--walking-legs", "--links", "6", "--limit", "0"], ["--walking-legs", "--links", "6", "--budget", "-5"],
        ["--links", "6", "--dof", "1", "--budget", "10"], ["--links", "6", "--dof", "1", "-o", "/dev/null"],
        ["--links", "6", "--dof", "1", "--json", "-o", tmp_path / "a" / "b" / "c"])]
    failures = [f for f in failures if f]
    assert not failures, "\n".join(failures)
