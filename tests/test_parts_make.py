"""``assur make`` end to end (docs/make.md): every shipped planar example that can be stacked writes its files;
the made parts pass an independent collision test (tests/parts_check.py: no code of assur.parts) on the engine's
poses at 720 inputs between the cycle's samples; the STL files are closed solids of the STEP solids' volumes; the
STEP re-imports with its names and its joint centres on the sketch; the masses are density × volume; the masses
go back into the mechanism and through ``assur forces``; pylinkage's STEP export of the same Jansen leg fails the
same collision test.
"""
import contextlib
import csv
import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import assur
import parts_check as pc
from assur.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
#: the shipped planar examples that can be stacked (walker_sixbar_beta1_60 and watt2 cannot: docs/make.md, and
#: tests/test_parts_conflicts.py checks their refusal)
PLANAR = ["chebyshev_lambda", "crank_rocker", "jansen", "klann", "lever_manipulator", "slider_crank",
          "stephenson3", "triad_sixbar", "walker_crank_slider", "walker_fourbar", "walker_fourbar_adjustable",
          "walker_fourbar_geared", "walker_sixbar"]
#: the examples every check below runs on: links, a slider block, actuators, gears
CHECKED = ["jansen", "slider_crank", "lever_manipulator", "walker_fourbar_geared"]
STEEL = 7850.0

pytestmark = pytest.mark.slow


def run(*args):
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(list(map(str, args)))
    return code, out.getvalue()


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    """{example: (output directory, the --json summary)} of every stackable planar example."""
    base = tmp_path_factory.mktemp("make")
    out = {}
    for name in PLANAR:
        d = base / name
        code, text = run("make", EXAMPLES / f"{name}.toml", "-o", d, "--json")
        assert code == 0, name
        out[name] = (d, json.loads(text))
    return out


def test_every_planar_example_writes_its_files_on_a_proven_minimal_stack(made):
    for name, (d, s) in made.items():
        doc = json.loads((d / "parts.json").read_text())
        assert list(doc) == ["parts"]
        names = [p["name"] for p in doc["parts"]]
        for p in doc["parts"]:
            keys = set(p)
            assert keys == {"name", "link", "layer", "z", "stl", "outline"} or \
                keys == {"name", "joint", "holds", "layer", "z", "stl", "outline"}, (name, p)
            assert (d / p["stl"]).is_file() and (d / "3mf" / f"{p['name']}.3mf").is_file()
            assert p["z"][0] < p["z"][1] and len(p["outline"]) >= 3
        assert (d / "assembly.step").is_file() and (d / "bom.csv").is_file() and (d / "parts.html").is_file()
        cert = s["certificate"]
        assert cert["proven"] and cert["status"] == "optimal", name
        assert cert["layers"] == cert["bound"] or cert["exhaustive"], name
        assert s["mesh_checks"]["assembly_overlaps"] == 0 and s["mesh_checks"]["watertight"] == len(names)
        assert len(set(names)) == len(names)


_STEP: dict = {}


def step_of(path):
    """(the re-imported STEP compound, its meshes) of ``path``, read once per test session (a STEP with gear
    outlines takes seconds to read)."""
    key = str(path)
    if key not in _STEP:
        import build123d as bd
        _STEP[key] = (bd.import_step(key), pc.step_meshes(path))
    return _STEP[key]


def parts_of(name, d):
    """The parts of an output for the independent test: names, bodies, joints and meshes re-imported from the
    STEP file (a pin moves with the first body it holds)."""
    m = assur.load(EXAMPLES / f"{name}.toml")
    plan = assur.compile(m)
    doc = json.loads((d / "parts.json").read_text())
    meshes = {k: v.copy() for k, v in step_of(d / "assembly.step")[1].items()}
    bodies = list(plan.body_names)
    parts = []
    for e in doc["parts"]:
        body = bodies.index(e["holds"][0] if "holds" in e else e["link"])
        parts.append(dict(name=e["name"], body=body, mesh=meshes[e["name"]], joint=e.get("joint"),
                          holds=e.get("holds", [])))
    return m, plan, doc, meshes, parts


def between_samples(plan, n=720):
    """n inputs half a step off the cycle's samples (where the certificate, not a sample, decides): the turn of
    the moving crank shifted by half a step, or the midpoints of a stroke's samples."""
    from assur.analysis.sampling import sweep_inputs
    q, k, closed = sweep_inputs(plan, n)
    if closed:
        q = q.copy()
        q[:, k] += np.pi / n
        return q
    return 0.5 * (q[1:] + q[:-1])


@pytest.mark.parametrize("name", CHECKED + ["klann", "walker_fourbar_adjustable"])
def test_independent_collision_test_finds_no_collision(made, name):
    d, s = made[name]
    m, plan, doc, _, parts = parts_of(name, d)
    sketch = np.asarray(plan.sketch_inputs, dtype=float)
    contacts = pc.designed_contacts(parts, m, plan, sketch)
    clearance = s["settings"]["clearance"] * 1e3
    hits = pc.find_collisions(parts, plan, between_samples(plan), clearance, sketch_q=sketch, exclude=contacts)
    assert hits == []
    assert pc.same_body_overlaps(parts) == []


def test_the_collision_test_can_fail(made):
    """The same test on Jansen's parts with one plate lifted into another's layer finds them meeting."""
    d, s = made["jansen"]
    m, plan, doc, meshes, parts = parts_of("jansen", d)
    layer = {p["name"]: p["layer"] for p in doc["parts"]}
    a = next(n for n, k in layer.items() if n.startswith("plate") and k == 1)
    b = next(n for n, k in layer.items() if n.startswith("plate") and k == 2)
    moved = next(p for p in parts if p["name"] == b)
    za, zb = meshes[a].bounds[0, 2], meshes[b].bounds[0, 2]
    moved["mesh"] = meshes[b].copy().apply_translation([0, 0, za - zb])
    sketch = np.asarray(plan.sketch_inputs, dtype=float)
    hits = pc.find_collisions(parts, plan, between_samples(plan), s["settings"]["clearance"] * 1e3,
                              sketch_q=sketch, exclude=pc.designed_contacts(parts, m, plan, sketch))
    assert {frozenset(h[:2]) for h in hits} >= {frozenset((a, b))} or any(b in h[:2] for h in hits)


@pytest.mark.parametrize("name", CHECKED)
def test_stl_files_are_the_step_solids(made, name):
    import trimesh
    d, _ = made[name]
    m, plan, doc, _, _ = parts_of(name, d)
    step = step_of(d / "assembly.step")[0]
    volumes = {c.label: sum(s.volume for s in c.solids()) for c in step.children}
    assert sorted(volumes) == sorted(p["name"] for p in doc["parts"])         # same parts, same names
    assert len(step.children) == len(doc["parts"])
    for p in doc["parts"]:
        mesh = trimesh.load_mesh(d / p["stl"])
        assert mesh.is_watertight and mesh.volume > 0
        assert mesh.volume == pytest.approx(volumes[p["name"]], rel=0.005)


def hole_axes(child):
    """(x, y) of the axes of the cylindrical faces of a re-imported part (mm)."""
    import build123d as bd
    out = []
    for s in child.solids():
        for f in s.faces():
            if f.geom_type == bd.GeomType.CYLINDER:
                a = f.axis_of_rotation
                out.append((a.position.X, a.position.Y))
    return np.array(out)


@pytest.mark.parametrize("name", CHECKED)
def test_joint_centres_recovered_from_the_step_match_the_sketch(made, name):
    d, _ = made[name]
    m, plan, doc, _, _ = parts_of(name, d)
    step = {c.label: c for c in step_of(d / "assembly.step")[0].children}
    carried = {lk.name: lk.points for lk in m.links}
    carried |= {f"{pr.name}.block": (pr.point,) for pr in m.prismatic if pr.point}
    carried |= {f"{a.name}.cylinder": (a.between[0],) for a in m.actuators}
    carried |= {f"{a.name}.rod": (a.between[1],) for a in m.actuators}
    count = {}
    for pts in carried.values():
        for p in pts:
            count[p] = count.get(p, 0) + 1
    shared = {p for p, c in count.items() if c >= 2}
    checked = 0
    for e in doc["parts"]:
        if "link" not in e or e["link"] not in carried or e["link"] == "frame":
            continue
        axes = hole_axes(step[e["name"]])
        for point in carried[e["link"]]:
            if point not in shared:
                continue
            if e["name"].startswith("gear") and point not in m.frame.points:
                continue                                        # a gear holds its pivot only
            sketch = np.array(m.sketch(point)) * 1e3
            assert np.min(np.hypot(*(axes - sketch).T)) < 1e-3, (e["name"], point)     # 1 µm
            checked += 1
    for e in doc["parts"]:
        if e["name"].startswith(("pin_", "shaft_")):
            axes = hole_axes(step[e["name"]])
            sketch = np.array(m.sketch(e["joint"])) * 1e3
            assert np.max(np.hypot(*(axes - sketch).T)) < 1e-3
            checked += 1
    assert checked >= 4


@pytest.mark.parametrize("name", CHECKED)
def test_masses_are_density_times_volume(made, name):
    import trimesh
    d, s = made[name]
    density = s["settings"]["density"]
    with open(d / "bom.csv", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    for row in rows:
        if not row["mass [g]"]:
            continue
        names = row["part"].split()
        rho = STEEL if row["material"] == "steel" else density
        volume = sum(trimesh.load_mesh(d / "stl" / f"{n}.stl").volume for n in names) * 1e-9
        assert float(row["mass [g]"]) * 1e-3 == pytest.approx(rho * volume, rel=1e-3, abs=2e-6), row["part"]


def test_step_is_ap214(made):
    d, _ = made["slider_crank"]
    head = (d / "assembly.step").read_text(errors="replace")[:2000]
    assert "AUTOMOTIVE_DESIGN" in head                      # the AP214 schema


def test_mass_back_writes_the_parts_masses_and_forces_use_them(made, tmp_path):
    """Each body's mass, centre of mass and inertia in the copy equal the sum over its parts' meshes (trimesh's
    mass properties of the STEP solids at the sketch pose: an independent integration); ``assur forces`` reads
    the copy."""
    name = "jansen"
    d, s = made[name]
    out = tmp_path / "out"
    back = tmp_path / "jansen_parts.toml"
    code, _ = run("make", EXAMPLES / f"{name}.toml", "-o", out, "--mass-back", back, "--json")
    assert code == 0
    m, plan, doc, meshes, parts = parts_of(name, out)
    mb = assur.load(back)
    bodies = dict(mb.dynamics.bodies)
    density = s["settings"]["density"]
    for body in plan.body_names[1:]:
        own = [p for p in parts if plan.body_names[p["body"]] == body]
        ms, cs, js = [], [], []
        for p in own:
            mesh = meshes[p["name"]].copy()
            rho = STEEL if p["name"].startswith(("pin_", "shaft_", "washer_")) else density
            mesh.density = rho * 1e-9                      # kg/mm³: the mesh is in mm
            ms.append(mesh.mass)
            cs.append(mesh.center_mass[:2] * 1e-3)
            js.append(mesh.moment_inertia[2, 2] * 1e-6)
        mass = sum(ms)
        com = sum(mi * ci for mi, ci in zip(ms, cs)) / mass
        inertia = sum(j + mi * np.sum((c - com) ** 2) for j, mi, c in zip(js, ms, cs))
        mp = bodies[body]
        assert mp.mass == pytest.approx(mass, rel=2e-3)
        assert np.allclose(mp.com, com, atol=1e-4 * m.length_scale)    # tessellated arcs: 0.1 mm on a 1.2 m leg
        assert mp.inertia == pytest.approx(inertia, rel=5e-3)
    assert mb.make == m.make and [lk.points for lk in mb.links] == [lk.points for lk in m.links]
    code, text = run("forces", back, "--json")
    assert code == 0
    summary = json.loads(text)
    assert "note" not in summary                          # the masses are there now
    assert summary["peak"] > 0 and summary["shaking_force_peak"] > 0


def test_missing_cad_packages_exit_1_with_the_install_command_before_any_work(tmp_path):
    fake = tmp_path / "fake"
    for name in ("build123d", "trimesh", "manifold3d"):         # none of the make extra can be imported
        (fake / name).mkdir(parents=True)
        (fake / name / "__init__.py").write_text(f"raise ImportError('no CAD here', name='{name}')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(fake), str(ROOT / "src")]))
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "assur", "make", str(EXAMPLES / "slider_crank.toml"), "-o", str(out)]
    res = subprocess.run(cmd, capture_output=True, encoding="utf-8", env=env, timeout=300)
    assert res.returncode == 1
    assert res.stderr.strip().splitlines() == [res.stderr.strip()]        # one line
    assert "pip install 'assur[make]'" in res.stderr and res.stderr.startswith("error: ")
    assert not out.exists()
    # the stack alone needs none of them
    res = subprocess.run(cmd + ["--layers-only"], capture_output=True, encoding="utf-8", env=env, timeout=300)
    assert res.returncode == 0, res.stderr
    assert (out / "parts.json").is_file() and (out / "parts.html").is_file()


def test_an_unstackable_limit_names_the_parts_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code, _ = run("make", EXAMPLES / "jansen.toml", "-o", out, "--max-layers", "2")
    assert code == 1
    line = err.getvalue().strip()
    assert line.startswith("error: max_layers: the parts cannot be stacked in 2 layers")
    for part in ("plate_crank", "plate_j", "plate_k"):
        assert part in line
    assert " deg (gap " in line
    assert not out.exists() and not any(tmp_path.glob(".out.*"))


def test_layers_only_writes_the_stack_without_solids(tmp_path):
    out = tmp_path / "out"
    code, text = run("make", EXAMPLES / "slider_crank.toml", "-o", out, "--layers-only", "--json",
                     "--clearance", "2 mm", "--process", "laser-cut")
    assert code == 0
    s = json.loads(text)
    assert s["settings"]["clearance"] == pytest.approx(0.002) and s["settings"]["process"] == "laser-cut"
    assert sorted(p.name for p in out.iterdir()) == [".assur-output", "certificate.json", "parts.html", "parts.json"]
    assert all(p["stl"] is None for p in json.loads((out / "parts.json").read_text())["parts"])


def pylinkage_jansen(tmp_path):
    """Jansen's leg built in pylinkage from the same file's sketch (a real pylinkage run solves its first
    position) and exported by pylinkage's own STEP writer (visualizer/step_export.py)."""
    import pylinkage as pl
    from pylinkage.visualizer.step_export import save_linkage_step
    m = assur.load(EXAMPLES / "jansen.toml")
    pos = {n: np.array(xy) * 1e3 for n, xy in m.points}            # mm

    def dist(a, b):
        return float(np.hypot(*(pos[a] - pos[b])))
    O, P = pl.Ground(*pos["O"], name="O"), pl.Ground(*pos["P"], name="P")
    crank = pl.Crank(anchor=O, radius=dist("O", "C"), angular_velocity=0.01, initial_angle=0.0, name="C")
    U = pl.RRRDyad(crank.output, P, dist("C", "U"), dist("P", "U"), x=pos["U"][0], y=pos["U"][1], name="U")
    E = pl.RRRDyad(P, U, dist("P", "E"), dist("U", "E"), x=pos["E"][0], y=pos["E"][1], name="E")
    L = pl.RRRDyad(crank.output, P, dist("C", "L"), dist("P", "L"), x=pos["L"][0], y=pos["L"][1], name="L")
    G = pl.RRRDyad(E, L, dist("E", "G"), dist("L", "G"), x=pos["G"][0], y=pos["G"][1], name="G")
    F = pl.RRRDyad(L, G, dist("L", "F"), dist("G", "F"), x=pos["F"][0], y=pos["F"][1], name="F")
    linkage = pl.Linkage([O, P, crank, U, E, L, G, F], name="jansen")
    loci = list(linkage.step(iterations=1, dt=0))                    # pylinkage solves the sketch position
    for comp, xy in zip([O, P, crank, U, E, L, G, F], loci[0]):
        assert np.allclose(xy, pos[comp.name], atol=1e-6)
    path = tmp_path / "jansen_pylinkage.step"
    save_linkage_step(linkage, path, loci=loci)
    return m, path


def test_pylinkage_step_export_of_jansen_overlaps(made, tmp_path):
    """pylinkage ≥ 1.3 staggers its bars by a tenth of their thickness, so bars that share a joint overlap in z and
    in plan: the independent test that passes assur's Jansen finds them colliding, already at the sketch pose."""
    m, path = pylinkage_jansen(tmp_path)
    plan = assur.compile(m)
    meshes = pc.step_meshes(path)
    pos = {n: np.array(xy) * 1e3 for n, xy in m.points}
    bodies = list(plan.body_names)
    links = {lk.name: lk.points for lk in m.links if lk.name != "frame"}
    segments = [(lk, a, b) for lk, pts in links.items() for i, a in enumerate(pts) for b in pts[i + 1:]]
    parts = []
    for name, mesh in meshes.items():
        foot = pc.footprint(mesh)
        c = np.array(foot.centroid.coords[0])
        lo, hi = np.array(foot.bounds[:2]), np.array(foot.bounds[2:])
        joint = min(pos, key=lambda p: np.hypot(*(pos[p] - c)))
        round_ = foot.area > 0.95 * np.pi * (0.5 * (hi - lo).max()) ** 2
        lk, a, b = min(segments, key=lambda s: np.hypot(*(0.5 * (pos[s[1]] + pos[s[2]]) - c)))
        if round_ and np.hypot(*(pos[joint] - c)) < 1.0:           # a pin at a joint
            holds = [k for k, pts in links.items() if joint in pts] + (["frame"] if joint in m.frame.points else [])
            parts.append(dict(name=name, body=bodies.index(holds[0]), mesh=mesh, joint=joint, holds=holds))
        elif np.hypot(*(0.5 * (pos[a] + pos[b]) - c)) < 1.0:       # a bar between two points of one link
            parts.append(dict(name=name, body=bodies.index(lk), mesh=mesh, joint=None, holds=[]))
        else:                                                      # a ground symbol
            parts.append(dict(name=name, body=0, mesh=mesh, joint=None, holds=[]))
    bars = [p for p in parts if p["joint"] is None and p["body"] != 0]
    assert len(bars) >= 9
    sketch = np.asarray(plan.sketch_inputs, dtype=float)
    contacts = pc.designed_contacts(parts, m, plan, sketch)
    hits = pc.find_collisions(parts, plan, between_samples(plan, 72), 1.0, sketch_q=sketch, exclude=contacts)
    bar_names = {p["name"] for p in bars}
    bar_hits = [h for h in hits if h[0] in bar_names and h[1] in bar_names]
    assert len(bar_hits) >= 5
    assert all(h[2] == 0.0 for h in bar_hits)                      # they intersect, not merely come close
    # assur's own Jansen passes the same test (test_independent_collision_test_finds_no_collision[jansen])
    assert made["jansen"][1]["certificate"]["proven"]


def test_the_page_renders_in_chromium(made, tmp_path):
    import browser
    if browser.BROWSER is None:
        pytest.skip("headless Chromium not installed")
    d, _ = made["slider_crank"]
    page = d / "parts.html"
    res = browser.run_browser(tmp_path, "--dump-dom", "--virtual-time-budget=8000", page.as_uri(), webgl=True,
                              timeout=180)
    dom = res.stdout
    assert dom.count("js-plotly-plot") >= 4                   # the layer chart, both 3D views, the clearance
    assert "Minimality certificate" in dom and "Bill of materials" in dom and "play" in dom
    assert "gl-container" in dom
    import re
    assert not re.search(r"CONSOLE.*(Uncaught|TypeError|ReferenceError|SyntaxError)", res.stderr)


def test_report_section_is_a_fragment_of_the_page():
    from assur.parts import report_section
    from assur.analysis.study import Study
    plan = assur.compile(assur.load(EXAMPLES / "slider_crank.toml"))
    html = report_section(Study(plan), include_plotlyjs=False)
    assert "<html" not in html and "Minimality certificate" in html and "Bill of materials" in html
    assert html.count("plotly-graph-div") >= 4
