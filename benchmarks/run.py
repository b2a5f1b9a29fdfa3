#!/usr/bin/env python3
"""Side-by-side speed benchmark: assur vs pylinkage vs a plain-Python loop on a four-bar.

Run with ``make bench`` (own venv ``.bench-venv``) or directly with a Python that has assur and
``benchmarks/requirements.txt`` installed. This is a script, not a test: it prints a Markdown
table and writes it to ``benchmarks/results.md``. See ``benchmarks/README.md``.

Cases (the four-bar of the docs: ground 100 mm, crank 30 mm, coupler |AB|, rocker |CB|):
  1. one design at 360, 3 600 and 36 000 crank angles;
  2. a population of 10 000 random Grashof crank-rockers x 360 angles, evaluated in chunks of
     100 designs; each chunk is reduced to a per-design summary (bounding box of the coupler
     midpoint's path, and for the pos+vel+acc engines the peak speed and acceleration of B),
     so no (designs, angles, ...) array larger than one chunk exists.

Engines, timed round-robin inside each repeat so that machine noise hits them alike:
  * assur ``solve(order=2, backend="numba")`` (positions + velocities + accelerations; the
    compiled backend, its kernel compiled before timing) and ``solve(order=0)``, and the numpy
    backend ``solve(order=2, backend="numpy")`` for comparison;
  * pylinkage's numba path: ``Linkage.step_fast()`` (-> ``solver.simulation.simulate``) and
    ``Linkage.step_fast_with_kinematics()`` for one design, ``population.simulate_batch`` (the
    engine of ``Ensemble.simulate``) for the population;
  * a plain-Python loop (``math`` module, closed-form circle intersection), positions + analytic
    velocities + accelerations, and positions only.
"""
from __future__ import annotations

import argparse
import cProfile
import datetime
import gc
import io
import math
import os
import platform
import pstats
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import assur

HERE = Path(__file__).resolve().parent

FOURBAR_TOML = """\
format = "assur/1"
name = "benchmark four-bar"
[units]
length = "mm"
angle = "deg"
[points]
O = [0, 0]
C = [100, 0]
A = [30, 0]
B = [80, 90]
[links]
frame = ["O", "C"]
crank = ["O", "A"]
coupler = ["A", "B"]
rocker = ["C", "B"]
[[drivers]]
name = "crank"
link = "crank"
pivot = "O"
arm = "A"
speed = "60 rpm"
"""

OMEGA = 2.0 * math.pi          # 60 rpm in rad/s (the file's driver speed)
# nominal design (SI): crank a, coupler b, rocker c, ground d
NOMINAL = (0.030, math.hypot(0.050, 0.090), math.hypot(0.020, 0.090), 0.100)


# ------------------------------------------------------------------------------------------------
# designs
# ------------------------------------------------------------------------------------------------

def random_designs(n: int, seed: int = 12345, spread: float = 0.25, margin: float = 0.05) -> np.ndarray:
    """(n, 4) link lengths a, b, c, d: each nominal x U(1-spread, 1+spread), kept only if the
    crank is the shortest link and Grashof holds with a margin (s + l <= p + q - margin*d), i.e. a
    crank-rocker that turns fully and never reaches a toggle (buildable at every angle)."""
    rng = np.random.default_rng(seed)
    out = []
    have = 0
    while have < n:
        x = np.asarray(NOMINAL) * rng.uniform(1 - spread, 1 + spread, size=(2 * n, 4))
        a, b, c, d = x.T
        s = x.min(axis=1)
        l_ = x.max(axis=1)
        ok = (a == s) & (s + l_ <= x.sum(axis=1) - s - l_ - margin * d)
        out.append(x[ok])
        have += int(ok.sum())
    return np.concatenate(out)[:n]


def upper_b(a, b, c, d, theta=0.0):
    """B on the branch to the left of A -> C (above the frame line at theta = 0), scalar floats."""
    ax, ay = a * math.cos(theta), a * math.sin(theta)
    dx, dy = d - ax, -ay
    dist = math.hypot(dx, dy)
    along = (b * b - c * c + dist * dist) / (2.0 * dist)
    h = math.sqrt(b * b - along * along)
    return ax + (along * dx - h * dy) / dist, ay + (along * dy + h * dx) / dist


def angles(n: int) -> np.ndarray:
    """q_k = (k + 1)·2π/n, k = 0..n-1: the angles pylinkage's crank reaches stepping 2π/n from 0."""
    return (np.arange(n) + 1.0) * (2.0 * math.pi / n)


# ------------------------------------------------------------------------------------------------
# assur
# ------------------------------------------------------------------------------------------------

class AssurBench:
    def __init__(self):
        self.plan = assur.compile(assur.loads(FOURBAR_TOML))
        pn = self.plan.point_names
        self.iA, self.iB = pn.index("A"), pn.index("B")
        self.ix = {k: self.plan.param_index(k) for k in ("C.x", "crank.length", "coupler.length", "rocker.length")}

    def params(self, designs: np.ndarray) -> np.ndarray:
        p = np.tile(self.plan.defaults, (len(designs), 1))
        p[:, self.ix["crank.length"]] = designs[:, 0]
        p[:, self.ix["coupler.length"]] = designs[:, 1]
        p[:, self.ix["rocker.length"]] = designs[:, 2]
        p[:, self.ix["C.x"]] = designs[:, 3]
        return p

    def single(self, q, order, backend="numba"):
        st = assur.solve(self.plan, None, q, order=order, backend=backend)
        if order == 0:
            return st.pos, None, None
        return st.pos, st.vel, st.acc

    def population(self, params, q, order, chunk, backend="numba"):
        n = len(params)
        out = np.empty((n, 6))
        iA, iB = self.iA, self.iB
        for i in range(0, n, chunk):
            st = assur.solve(self.plan, params[i:i + chunk, None, :], q, order=order, backend=backend)
            pos = st.pos                                   # (chunk, n_angles, n_points, 2)
            m = 0.5 * (pos[..., iA, :] + pos[..., iB, :])  # coupler midpoint
            out[i:i + chunk, 0:2] = m.min(axis=1)
            out[i:i + chunk, 2:4] = m.max(axis=1)
            if order >= 2:
                v = st.vel[..., iB, :]
                a = st.acc[..., iB, :]
                out[i:i + chunk, 4] = np.sqrt(np.max(np.sum(v * v, axis=-1), axis=1))
                out[i:i + chunk, 5] = np.sqrt(np.max(np.sum(a * a, axis=-1), axis=1))
            else:
                out[i:i + chunk, 4:6] = np.nan
        return out


# ------------------------------------------------------------------------------------------------
# pylinkage
# ------------------------------------------------------------------------------------------------

class PylinkageBench:
    def __init__(self):
        from assur.kernels.numba_target import configure
        configure()      # numba's target for assur's kernels, before pylinkage fixes it
        import pylinkage
        from pylinkage._numba_compat import HAS_NUMBA
        from pylinkage.actuators import Crank
        from pylinkage.components import Ground
        from pylinkage.dyads import RRRDyad
        from pylinkage.population._batch_sim import simulate_batch
        from pylinkage.simulation import Linkage
        self.version = getattr(pylinkage, "__version__", "?")
        self.has_numba = HAS_NUMBA
        self._Ground, self._Crank, self._RRR, self._Linkage = Ground, Crank, RRRDyad, Linkage
        self._simulate_batch = simulate_batch

    def linkage(self, n_steps, design=NOMINAL, omega=None):
        """The four-bar as pylinkage components; the crank steps 2π/n_steps per iteration from 0."""
        a, b, c, d = design
        bx, by = upper_b(a, b, c, d)
        O = self._Ground(0.0, 0.0, name="O")
        C = self._Ground(d, 0.0, name="C")
        crank = self._Crank(anchor=O, radius=a, angular_velocity=2 * math.pi / n_steps, name="A")
        B = self._RRR(crank.output, C, distance1=b, distance2=c, x=bx, y=by, name="B")
        lk = self._Linkage([O, C, crank, B], name="fourbar")
        if omega is not None:
            lk.set_input_velocity(crank, omega=omega, alpha=0.0)
        lk.compile()
        return lk

    def population_inputs(self, designs, n_steps):
        tmpl = self.linkage(n_steps)
        sd = tmpl._solver_data
        n = len(designs)
        cons = np.ascontiguousarray(designs[:, :3])          # user constraints: crank r, B r0, B r1
        pos0 = np.zeros((n, sd.n_joints, 2))
        pos0[:, 1, 0] = designs[:, 3]                        # C = (d, 0)
        pos0[:, 2, 0] = designs[:, 0]                        # A = (a, 0)
        for k, (a, b, c, d) in enumerate(designs):
            pos0[k, 3] = upper_b(a, b, c, d)                 # B assembled on the same branch as assur
        return sd, cons, pos0

    def population(self, sd, cons, pos0, n_steps, chunk):
        n = len(cons)
        out = np.full((n, 6), np.nan)
        for i in range(0, n, chunk):
            traj = self._simulate_batch(sd, cons[i:i + chunk], pos0[i:i + chunk], n_steps, 1.0)
            m = 0.5 * (traj[:, :, 2, :] + traj[:, :, 3, :])
            out[i:i + chunk, 0:2] = m.min(axis=1)
            out[i:i + chunk, 2:4] = m.max(axis=1)
        return out


# ------------------------------------------------------------------------------------------------
# plain Python (math module)
# ------------------------------------------------------------------------------------------------

def plain_full(a, b, c, d, n, omega=OMEGA):
    """Positions, velocities and accelerations of A and B at q_k = (k+1)·2π/n (crank at constant
    speed omega): closed-form circle intersection, then the two 2x2 velocity / acceleration
    systems from differentiating |B-C|² = c² and |B-A|² = b² (Cramer's rule)."""
    sqrt, cos, sin = math.sqrt, math.cos, math.sin
    step = 2.0 * math.pi / n
    w2 = omega * omega
    bb, cc = b * b, c * c
    out = []
    append = out.append
    for k in range(n):
        th = (k + 1) * step
        ct, s_ = cos(th), sin(th)
        ax, ay = a * ct, a * s_
        dx, dy = d - ax, -ay
        dist2 = dx * dx + dy * dy
        dist = sqrt(dist2)
        along = (bb - cc + dist2) / (2.0 * dist)
        h = sqrt(bb - along * along)
        bx = ax + (along * dx - h * dy) / dist
        by = ay + (along * dy + h * dx) / dist
        vax, vay = -omega * ay, omega * ax
        aax, aay = -w2 * ax, -w2 * ay
        r1x, r1y = bx - d, by            # B - C
        r2x, r2y = bx - ax, by - ay      # B - A
        det = r1x * r2y - r1y * r2x
        k2 = r2x * vax + r2y * vay
        vbx, vby = -r1y * k2 / det, r1x * k2 / det
        rx, ry = vbx - vax, vby - vay
        k1 = -(vbx * vbx + vby * vby)
        k2 = r2x * aax + r2y * aay - (rx * rx + ry * ry)
        abx = (k1 * r2y - r1y * k2) / det
        aby = (r1x * k2 - k1 * r2x) / det
        append((ax, ay, bx, by, vax, vay, vbx, vby, aax, aay, abx, aby))
    return out


def plain_pos(a, b, c, d, n):
    """Positions of A and B only (same closed form as plain_full)."""
    sqrt, cos, sin = math.sqrt, math.cos, math.sin
    step = 2.0 * math.pi / n
    bb, cc = b * b, c * c
    out = []
    append = out.append
    for k in range(n):
        th = (k + 1) * step
        ax, ay = a * cos(th), a * sin(th)
        dx, dy = d - ax, -ay
        dist2 = dx * dx + dy * dy
        dist = sqrt(dist2)
        along = (bb - cc + dist2) / (2.0 * dist)
        h = sqrt(bb - along * along)
        append((ax, ay, ax + (along * dx - h * dy) / dist, ay + (along * dy + h * dx) / dist))
    return out


def plain_population(designs, n, full):
    """Per-design summary (bbox of the coupler midpoint, peak |v_B|, |a_B|), reduced on the fly."""
    res = []
    for a, b, c, d in designs.tolist():
        rows = plain_full(a, b, c, d, n) if full else plain_pos(a, b, c, d, n)
        x0 = y0 = math.inf
        x1 = y1 = -math.inf
        vm = am = 0.0
        for r in rows:
            mx, my = 0.5 * (r[0] + r[2]), 0.5 * (r[1] + r[3])
            if mx < x0:
                x0 = mx
            if mx > x1:
                x1 = mx
            if my < y0:
                y0 = my
            if my > y1:
                y1 = my
            if full:
                v2 = r[6] * r[6] + r[7] * r[7]
                a2 = r[10] * r[10] + r[11] * r[11]
                if v2 > vm:
                    vm = v2
                if a2 > am:
                    am = a2
        res.append((x0, y0, x1, y1, math.sqrt(vm) if full else math.nan, math.sqrt(am) if full else math.nan))
    return np.array(res)


# ------------------------------------------------------------------------------------------------
# timing helpers
# ------------------------------------------------------------------------------------------------

def timed(fn, number=1):
    """Wall time of one call of fn, averaged over ``number`` back-to-back calls (gc off)."""
    gc.collect()
    gc.disable()
    try:
        t0 = time.perf_counter()
        for _ in range(number):
            r = fn()
        t = (time.perf_counter() - t0) / number
    finally:
        gc.enable()
    return t, r


def calls_for(fn, budget=0.02):
    """How many back-to-back calls make one timing last about ``budget`` seconds (sub-millisecond
    calls timed one at a time measure the timer and the cold caches, not the engine)."""
    t, _ = timed(fn)
    return max(1, min(1000, int(budget / max(t, 1e-7))))


def rel_err(x, ref):
    x, ref = np.asarray(x, float), np.asarray(ref, float)
    return float(np.max(np.abs(x - ref)) / np.max(np.abs(ref)))


def fmt_rate(r):
    if r >= 1e6:
        return f"{r / 1e6:.2f} M"
    if r >= 1e3:
        return f"{r / 1e3:.1f} k"
    return f"{r:.0f}"


def fmt_ms(t):
    return f"{t * 1e3:.1f}" if t >= 0.01 else f"{t * 1e3:.3f}"


def nproc():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        return os.cpu_count()


def cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


# ------------------------------------------------------------------------------------------------
# main
# ------------------------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5, help="repeats of every timing (>= 5 for the record)")
    ap.add_argument("--designs", type=int, default=10_000, help="population size")
    ap.add_argument("--chunk", type=int, default=100,
                    help="designs per chunk in the population case (100 × 360 angles ≈ 7 MB of outputs per chunk)")
    ap.add_argument("--plain-designs", type=int, default=250,
                    help="designs the plain-Python loop runs in the population case (rate extrapolated)")
    ap.add_argument("--sizes", type=int, nargs="+", default=[360, 3600, 36_000], help="crank angles, one design")
    ap.add_argument("--out", type=Path, default=HERE / "results.md", help="Markdown file to write ('-' for none)")
    ap.add_argument("--profile", action="store_true", help="also print a cProfile of assur.solve (order=2)")
    args = ap.parse_args(argv)
    t_start = time.perf_counter()
    failures = []

    ab = AssurBench()
    pb = PylinkageBench()
    if not pb.has_numba:
        print("warning: numba is not installed; pylinkage runs its pure-Python fallback", file=sys.stderr)
    a0, b0, c0, d0 = NOMINAL

    # ---- correctness, once ------------------------------------------------------------------------
    checks = []
    n_chk = 360
    q = angles(n_chk)
    pos, vel, acc = ab.single(q, 2)
    lk = pb.linkage(n_chk, omega=OMEGA)
    traj = pb.linkage(n_chk).step_fast(iterations=n_chk)
    e = rel_err(traj[:, 2:4, :], pos[:, ab.iA:ab.iB + 1, :])
    checks.append(("pylinkage step_fast A, B positions vs assur", e, 1e-9))
    kp, kv, ka = lk.step_fast_with_kinematics(iterations=n_chk)
    checks.append(("pylinkage step_fast_with_kinematics A, B positions vs assur",
                   rel_err(kp[:, 2:4, :], pos[:, 2:4, :]), 1e-9))
    checks.append(("pylinkage step_fast_with_kinematics A, B velocities vs assur",
                   rel_err(kv[:, 2:4, :], vel[:, 2:4, :]), 1e-9))
    checks.append(("pylinkage step_fast_with_kinematics A, B accelerations vs assur",
                   rel_err(ka[:, 2:4, :], acc[:, 2:4, :]), 1e-9))
    pf = np.array(plain_full(a0, b0, c0, d0, n_chk))
    checks.append(("plain loop A, B positions vs assur", rel_err(pf[:, 0:4], pos[:, 2:4, :].reshape(-1, 4)), 1e-9))
    checks.append(("plain loop A, B velocities vs assur", rel_err(pf[:, 4:8], vel[:, 2:4, :].reshape(-1, 4)), 1e-9))
    checks.append(("plain loop A, B accelerations vs assur",
                   rel_err(pf[:, 8:12], acc[:, 2:4, :].reshape(-1, 4)), 1e-9))
    designs = random_designs(args.designs)
    params = ab.params(designs)
    sd, cons, pos0 = pb.population_inputs(designs, 360)
    q360 = angles(360)
    n_small = min(args.chunk, args.designs)
    ref = ab.population(params[:n_small], q360, 2, args.chunk)
    # per-design trajectories of B agree (not only the summaries)
    st_small = assur.solve(ab.plan, params[:20, None, :], q360, order=0)
    tr_small = pb._simulate_batch(sd, cons[:20], pos0[:20], 360, 1.0)
    checks.append(("population: pylinkage B paths vs assur (20 designs)",
                   rel_err(tr_small[:, :, 3, :], st_small.pos[:, :, ab.iB, :]), 1e-9))
    checks.append((f"population: pylinkage summaries vs assur ({n_small} designs)",
                   rel_err(pb.population(sd, cons[:n_small], pos0[:n_small], 360, args.chunk)[:, :4], ref[:, :4]),
                   1e-9))
    checks.append(("population: plain-loop summaries vs assur (50 designs)",
                   rel_err(plain_population(designs[:50], 360, True), ref[:50]), 1e-9))
    checks.append(("population: assur samples valid", float(not bool(np.all(np.isfinite(ref)))), 0.5))
    for name, err, tol in checks:
        if not err <= tol:
            failures.append(f"{name}: {err:.3g} > {tol:g}")

    # ---- warm-up (numba JIT, numpy caches) ---------------------------------------------------------
    for n in args.sizes:
        lk_n = pb.linkage(n)
        lk_n.step_fast(iterations=n)
        lkk_n = pb.linkage(n, omega=OMEGA)
        lkk_n.step_fast_with_kinematics(iterations=n)
        ab.single(angles(n), 2)
        ab.single(angles(n), 0)
        ab.single(angles(n), 2, "numpy")

    # ---- timings --------------------------------------------------------------------------------
    rows = []   # (case, engine, what, samples, times, note)

    def run_case(case, engines, repeats):
        times = {name: [] for name, *_ in engines}
        number = {name: calls_for(fn) for name, fn, *_ in engines}
        for _ in range(repeats):
            for name, fn, *_ in engines:
                t, _r = timed(fn, number[name])
                times[name].append(t)
        for name, fn, what, samples, note in engines:
            rows.append((case, name, what, samples, times[name], note))

    for n in args.sizes:
        q = angles(n)
        lk_n = pb.linkage(n)
        lkk_n = pb.linkage(n, omega=OMEGA)
        d4 = NOMINAL
        engines = [
            ("assur order=2", lambda q=q: ab.single(q, 2), "pos+vel+acc", n, ""),
            ("assur order=0", lambda q=q: ab.single(q, 0), "pos", n, ""),
            ("assur numpy order=2", lambda q=q: ab.single(q, 2, "numpy"), "pos+vel+acc", n, "numpy backend"),
            ("pylinkage step_fast", lambda lk=lk_n, n=n: lk.step_fast(iterations=n), "pos", n, "numba"),
            ("pylinkage step_fast_with_kinematics", lambda lk=lkk_n, n=n: lk.step_fast_with_kinematics(iterations=n),
             "pos+vel+acc", n, "numba"),
            ("plain Python", lambda n=n: plain_full(*d4, n), "pos+vel+acc", n, ""),
            ("plain Python", lambda n=n: plain_pos(*d4[:4], n), "pos", n, ""),
        ]
        # the engines of one case share a name+what key; make names unique for the dict
        engines = [(f"{e[0]}|{e[2]}", e[1], e[2], e[3], e[4]) for e in engines]
        run_case(f"1 design × {n} angles", engines, args.repeats)

    nd, npl = args.designs, min(args.plain_designs, args.designs)
    ns = nd * 360
    results = {}

    def keep(key, fn):
        def g():
            results[key] = fn()
        return g

    pop_engines = [
        ("assur order=2|pos+vel+acc", keep("a2", lambda: ab.population(params, q360, 2, args.chunk)),
         "pos+vel+acc", ns, f"chunks of {args.chunk}"),
        ("assur order=0|pos", keep("a0", lambda: ab.population(params, q360, 0, args.chunk)),
         "pos", ns, f"chunks of {args.chunk}"),
        ("assur numpy order=2|pos+vel+acc", lambda: ab.population(params, q360, 2, args.chunk, "numpy"),
         "pos+vel+acc", ns, f"chunks of {args.chunk}; numpy backend"),
        ("pylinkage simulate_batch|pos", keep("pl", lambda: pb.population(sd, cons, pos0, 360, args.chunk)),
         "pos", ns, f"chunks of {args.chunk}; numba"),
        ("plain Python|pos+vel+acc", lambda: plain_population(designs[:npl], 360, True),
         "pos+vel+acc", npl * 360, f"{npl} designs, rate extrapolated to {nd}"),
        ("plain Python|pos", lambda: plain_population(designs[:npl], 360, False),
         "pos", npl * 360, f"{npl} designs, rate extrapolated to {nd}"),
    ]
    run_case(f"{nd} designs × 360 angles", pop_engines, args.repeats)
    e_pop = rel_err(results["pl"][:, :4], results["a2"][:, :4])
    checks.append((f"population: pylinkage vs assur summaries, all {nd} designs (timed runs)", e_pop, 1e-9))
    e_pop0 = rel_err(results["a0"][:, :4], results["a2"][:, :4])
    checks.append(("population: assur order=0 vs order=2 summaries (timed runs)", e_pop0, 1e-12))
    for name, err, tol in checks[-2:]:
        if not err <= tol:
            failures.append(f"{name}: {err:.3g} > {tol:g}")

    # ---- report ---------------------------------------------------------------------------------
    try:
        import numba
        numba_version = numba.__version__
    except ImportError:
        numba_version = "not installed (pure-Python fallback)"
    md = []
    md.append("# assur benchmark: four-bar kinematics\n")
    md.append(f"- date: {datetime.datetime.now().astimezone().isoformat(timespec='seconds')}")
    md.append(f"- python {platform.python_version()}, numpy {np.__version__}, assur {assur.__version__}, "
              f"pylinkage {pb.version}, numba {numba_version}")
    md.append(f"- machine: `nproc` = {nproc()}, {cpu_model()}, {platform.machine()}, {platform.system()}")
    md.append(f"- repeats: {args.repeats} per timing, engines interleaved within each repeat; "
              f"min and median wall time (`time.perf_counter`, gc off); a timing of a short call "
              f"averages back-to-back calls lasting about 20 ms, for every engine alike")
    md.append("- samples = crank-angle evaluations (one sample = every point of the mechanism at one angle)")
    md.append("- pylinkage path: numba-compiled `pylinkage.solver.simulation.simulate` through "
              "`Linkage.step_fast()` (one design) and `pylinkage.population._batch_sim.simulate_batch` "
              "(the engine of `Ensemble.simulate`, one compiled `simulate` call per design) for the population; "
              "pos+vel+acc through `Linkage.step_fast_with_kinematics()` "
              "(`solver.simulation.simulate_with_kinematics`)")
    md.append("- plain Python: `math`-module loop, closed-form circle intersection; pos+vel+acc = positions plus "
              "analytic velocities and accelerations (2×2 linear systems by Cramer's rule), pos = positions only")
    md.append("")
    md.append("| case | engine | computes | samples | min ms | median ms | samples/s at min | samples/s at median | note |")
    md.append("|---|---|---|---:|---:|---:|---:|---:|---|")
    rates = {}
    for case, name, what, samples, ts, note in rows:
        tmin, tmed = min(ts), statistics.median(ts)
        rates[(case, name)] = (samples / tmin, samples / tmed)
        if "extrapolated" in note:
            note += f" (≈ {tmin * nd / npl:.1f} s for all)"
        md.append(f"| {case} | {name.split('|')[0]} | {what} | {samples:,} | {fmt_ms(tmin)} | {fmt_ms(tmed)} | "
                  f"{fmt_rate(samples / tmin)} | {fmt_rate(samples / tmed)} | {note} |")
    md.append("")
    md.append("Ratios (assur samples/s ÷ other samples/s; from the min times, and from the medians):\n")
    md.append("| case | assur pos+vel+acc ÷ pylinkage pos | assur pos ÷ pylinkage pos | "
              "assur pos+vel+acc ÷ pylinkage pos+vel+acc | assur pos+vel+acc ÷ plain pos+vel+acc | "
              "assur pos ÷ plain pos |")
    md.append("|---|---:|---:|---:|---:|---:|")
    cases = list(dict.fromkeys(r[0] for r in rows))

    def ratio(case, a, b):
        if (case, a) not in rates or (case, b) not in rates:
            return "–"
        ra, rb = rates[(case, a)], rates[(case, b)]
        return f"{ra[0] / rb[0]:.2f} / {ra[1] / rb[1]:.2f}"

    for case in cases:
        pl_pos = "pylinkage step_fast|pos" if (case, "pylinkage step_fast|pos") in rates else "pylinkage simulate_batch|pos"
        md.append(f"| {case} | {ratio(case, 'assur order=2|pos+vel+acc', pl_pos)} | "
                  f"{ratio(case, 'assur order=0|pos', pl_pos)} | "
                  f"{ratio(case, 'assur order=2|pos+vel+acc', 'pylinkage step_fast_with_kinematics|pos+vel+acc')} | "
                  f"{ratio(case, 'assur order=2|pos+vel+acc', 'plain Python|pos+vel+acc')} | "
                  f"{ratio(case, 'assur order=0|pos', 'plain Python|pos')} |")
    worst = min(rates[(c, "assur order=2|pos+vel+acc")][0] /
                rates[(c, "pylinkage step_fast|pos" if (c, "pylinkage step_fast|pos") in rates
                       else "pylinkage simulate_batch|pos")][0] for c in cases)
    md.append("")
    md.append(f"Project target: assur (pos+vel+acc) ≥ 10× pylinkage's fastest path (positions). "
              f"Worst case here: {worst:.2f}× → {'met' if worst >= 10 else 'NOT met'}.")
    md.append("")
    md.append("Correctness (checked once, max |difference| / max |reference|):\n")
    md.append("| check | relative error | tolerance | |")
    md.append("|---|---:|---:|---|")
    for name, err, tol in checks:
        md.append(f"| {name} | {err:.2e} | {tol:g} | {'ok' if err <= tol else 'FAIL'} |")
    md.append("")
    md.append(f"Designs: {nd} random Grashof crank-rockers, each of crank/coupler/rocker/ground = nominal × U(0.75, 1.25) "
              f"(nominal {', '.join(f'{x * 1e3:.2f}' for x in NOMINAL)} mm), kept if the crank is the shortest link and "
              f"s + l ≤ p + q − 0.05·ground; per design the chunk is reduced to the coupler midpoint's path bounding box "
              f"(and peak |v_B|, |a_B| for the pos+vel+acc engines). Total run time: "
              f"{time.perf_counter() - t_start:.0f} s.")
    text = "\n".join(md) + "\n"
    print(text)
    if str(args.out) != "-":
        args.out.write_text(text)
        print(f"written to {args.out}")

    if args.profile:
        for label, fn in (("1 design × 36000 angles, order=2", lambda: ab.single(angles(36_000), 2)),
                          (f"population chunk {args.chunk} × 360, order=2",
                           lambda: ab.population(params[:args.chunk], q360, 2, args.chunk))):
            pr = cProfile.Profile()
            pr.enable()
            for _ in range(3):
                fn()
            pr.disable()
            s = io.StringIO()
            pstats.Stats(pr, stream=s).sort_stats("tottime").print_stats(25)
            print(f"## cProfile: {label} (3 calls)\n")
            print(s.getvalue())

    if failures:
        print("CORRECTNESS FAILURES:\n  " + "\n  ".join(failures), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
