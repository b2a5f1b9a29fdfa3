"""Verification of the planar force solver (``assur.forces``) by independent checks.

Every reference value here is computed in this file from the solved kinematic state alone (point
positions, velocities and accelerations, body angular velocities and accelerations, the analogues
``dpos_dq``), never from :mod:`assur.kinetostatics` itself:

* virtual power: the driving effort equals −Σ(F·v + M·ω)/q̇ over every applied and d'Alembert load;
* per-body residuals: the returned reactions, the applied and the d'Alembert loads balance every body;
* energy: with gravity and inertia only at constant crank speed, ∮T dφ = 0 over a cycle;
* a massless walking leg and a linear actuator: the effort is the load times the point's analogue;
* the group closed forms equal the global Newton–Euler matrix; batches equal per-sample calls; the
  compiled backend equals numpy;
* toggles give NaN and ``singular``, never numbers;
* friction converges and dissipates power (a hand derivation with friction: test_forces_textbook.py).
"""
from __future__ import annotations

import cmath
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import assur
from assur.model.dynamics import Dynamics, Friction, Load, MassProperties

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


# -- mechanisms of every dyad kind (sketch coordinates from plain geometry) ----------------------------------
def circle_circle(c1, r1, c2, r2, left=True):
    """Intersection of two circles; ``left``: to the left of the directed line c1 → c2."""
    d = abs(c2 - c1)
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = math.sqrt(r1 * r1 - a * a)
    u = (c2 - c1) / d
    return c1 + u * (a + (1j * h if left else -1j * h))


def pt(b, name, z):
    return b.point(name, z.real, z.imag)


def fourbar(a=0.3, b=1.0, c=0.8, d=1.0, q0=0.6):
    """RRR: crank O–A, coupler A–B–P, rocker O1–B."""
    A = a * cmath.exp(1j * q0)
    B = circle_circle(A, b, d + 0j, c, left=True)
    P = A + (B - A) * (0.4 + 0.3j)
    bl = assur.Builder(units="m", angle="rad").point("O", 0, 0).point("O1", d, 0)
    pt(pt(pt(bl, "A", A), "B", B), "P", P)
    return (bl.frame("O", "O1").link("crank", "O", "A").link("coupler", "A", "B", "P").link("rocker", "O1", "B")
            .crank("crank", pivot="O", arm="A", zero=0.0, speed="30 rpm", name="crank").build())


def slider_crank():
    """RRP: offset slider-crank, crank 0.3, rod 0.9, the pin B in a slot y = 0.1 of the frame; turning clockwise."""
    A = 0.3 * cmath.exp(0.8j)
    B = complex(A.real + math.sqrt(0.9**2 - (0.1 - A.imag) ** 2), 0.1)
    bl = assur.Builder(units="m", angle="rad").point("O", 0, 0)
    pt(pt(bl, "A", A), "B", B)
    return (bl.frame("O").link("crank", "O", "A").link("rod", "A", "B")
            .slider(name="slot", point="B", guide="frame", through="O", angle=0.0, offset=0.1)
            .crank("crank", pivot="O", arm="A", zero=1.0, sense="cw", speed="30 rpm", name="crank").build())


def whitworth():
    """RPR: the crank pin C slides in a slot of a rocker pivoted on the frame at O2."""
    O2 = -0.5j
    C = 0.2 * cmath.exp(0.5j)
    R = O2 + 1.5 * (C - O2) / abs(C - O2)
    bl = assur.Builder(units="m", angle="rad").point("O1", 0, 0)
    pt(pt(pt(bl, "O2", O2), "C", C), "R", R)
    return (bl.frame("O1", "O2").link("crank", "O1", "C").link("rocker", "O2", "R")
            .slider(name="slot", point="C", guide="rocker", through="O2", angle=0.0)
            .crank("crank", pivot="O1", arm="C", zero=0.0, speed="30 rpm", name="crank").build())


def cross_slide():
    """PRP: J slides in a slot along the crank and in a vertical frame slot x = 1."""
    u = cmath.exp(0.4j)
    bl = assur.Builder(units="m", angle="rad").point("O", 0, 0).point("X", 1, 0)
    pt(pt(bl, "A", 0.3 * u), "J", 1 + 1j * math.tan(0.4))
    return (bl.frame("O", "X").link("crank", "O", "A")
            .slider(name="s1", point="J", guide="crank", through="O", angle=0.0)
            .slider(name="s2", point="J", guide="frame", through="X", angle=math.pi / 2)
            .crank("crank", pivot="O", arm="A", zero=0.0, speed="30 rpm", name="crank").build())


def scotch_yoke():
    """PPR: the crank pin A slides in a vertical slot of a yoke that translates along the x axis."""
    A = 0.3 * cmath.exp(0.7j)
    bl = assur.Builder(units="m", angle="rad").point("O", 0, 0)
    pt(pt(pt(bl, "A", A), "Y1", complex(A.real, 0)), "Y2", complex(A.real, 0.5))
    return (bl.frame("O").link("crank", "O", "A").link("yoke", "Y1", "Y2")
            .slider(name="slot", point="A", guide="yoke", through="Y1", angle=0.0)
            .slider(name="rail", link="yoke", guide="frame", through="O", angle=0.0)
            .crank("crank", pivot="O", arm="A", zero=0.0, speed="30 rpm", name="crank").build())


def boom():
    """A driven actuator as one side of an RRR dyad: a boom hinged at O, lifted by a cylinder F–B."""
    return (assur.Builder(units="m", angle="rad").point("O", 0, 0).point("F", 0.4, -0.3).point("B", 0.8, 0.5)
            .point("T", 2.0, 0.9).frame("O", "F").link("boom", "O", "B", "T").actuator("cyl", "F", "B")
            .linear("cyl", speed="40 mm/s", name="lift").build())


def rail_actuator():
    """A driven actuator in an RRP dyad: hinged at F, its rod end B slides in the frame guide y = 0.5."""
    return (assur.Builder(units="m", angle="rad").point("F", 0, 0).point("G", 0, 0.5).point("B", 1.0, 0.5)
            .frame("F", "G").actuator("cyl", "F", "B")
            .slider(name="rail", point="B", guide="frame", through="G", angle=0.0)
            .linear("cyl", speed="50 mm/s", name="push").build())


DYADS = {"RRR": fourbar, "RRP": slider_crank, "RPR": whitworth, "PRP": cross_slide, "PPR": scotch_yoke,
         "actuator_RRR": boom, "actuator_RRP": rail_actuator}
def _is_planar_mechanism(path):
    text = path.read_text(encoding="utf-8")
    return 'format = "assur/1"' in text and assur.load(path).dimension == 2


PLANAR_EXAMPLES = sorted(p.name for p in EXAMPLES.glob("*.toml") if _is_planar_mechanism(p))


# -- independent mechanics from the state -------------------------------------------------------------------
def cz(a):
    """(..., 2) → complex."""
    return a[..., 0] + 1j * a[..., 1]


def dot(a, b):
    return (np.conj(a) * b).real


def cross(a, b):
    return (np.conj(a) * b).imag


def random_dynamics(plan, rng, gravity=(0.0, -9.81), loads=()):
    """Random masses, inertias and centres of mass (off the links' lines) for every moving body."""
    m = plan.mechanism
    bodies = []
    for name in plan.body_names[1:]:
        mass, inertia = rng.uniform(0.2, 5.0), rng.uniform(1e-3, 0.2)
        head, _, part = name.rpartition(".")
        if part in ("cylinder", "rod") and head:
            com = float(rng.uniform(0.05, 0.3))
        elif part == "block" and head:
            com = None
        else:
            pts = plan.structure.graph.bodies[plan.body_names.index(name)].points
            c = np.mean([m.sketch(p)[:2] for p in pts], axis=0) + rng.uniform(-0.1, 0.1, 2)
            com = (float(c[0]), float(c[1]))
        bodies.append((name, MassProperties(float(mass), float(inertia), com)))
    return Dynamics(gravity=gravity, bodies=tuple(bodies), loads=tuple(loads))


def with_dynamics(m, dyn):
    return dataclasses.replace(m, dynamics=dyn)


def body_points(plan, name):
    return plan.structure.graph.bodies[plan.body_names.index(name)].points


def com_motion(plan, state, name, mp):
    """Centre of mass of body ``name``: its position, velocity, acceleration (complex (...)) and analogues
    d/dq (..., n_inputs), from the state's point motion and the body's angular motion (rigid-body formulas)."""
    m = plan.mechanism
    b = plan.body_names.index(name)
    z, v, a, dz = cz(state.pos), cz(state.vel), cz(state.acc), point_analogues(state)
    w, al, dth = state.body_omega[..., b], state.body_alpha[..., b], state.dangle_dq[..., b, :]
    ix = plan.point_index
    head, _, part = name.rpartition(".")
    if part in ("cylinder", "rod") and head:
        act = next(x for x in m.actuators if x.name == head)
        h0, h1 = ix(act.between[0]), ix(act.between[1])
        u = (z[..., h1] - z[..., h0]) / np.abs(z[..., h1] - z[..., h0])
        base, r = (h0, float(mp.com) * u) if part == "cylinder" else (h1, -float(mp.com) * u)
    elif mp.com is None:
        pts = [ix(p) for p in body_points(plan, name)]
        c = np.mean([z[..., p] for p in pts], axis=0)
        base = pts[0]
        r = c - z[..., base]
    else:
        p0, p1 = body_points(plan, name)[:2]
        s0, s1 = complex(*m.sketch(p0)[:2]), complex(*m.sketch(p1)[:2])
        turn = (z[..., ix(p1)] - z[..., ix(p0)]) / (s1 - s0)
        base = ix(p0)
        r = (complex(*mp.com) - s0) * turn / np.abs(turn)
    return (z[..., base] + r, v[..., base] + 1j * w * r, a[..., base] + (1j * al - w * w) * r,
            dz[..., base, :] + 1j * dth * r[..., None])


def point_analogues(state):
    """(..., n_points, n_inputs) complex d pos/dq."""
    d = state.dpos_dq
    return d[..., 0, :] + 1j * d[..., 1, :]


def applied_loads(plan, state, dyn, point_loads=()):
    """Every applied and d'Alembert load as (body, force complex, point complex, couple, the point's velocity,
    its analogues (..., n_inputs))."""
    z, v, dz = cz(state.pos), cz(state.vel), point_analogues(state)
    g = complex(*dyn.gravity[:2])
    out = []
    for name, mp in dyn.bodies:
        b = plan.body_names.index(name)
        c, vc, ac, dc = com_motion(plan, state, name, mp)
        out.append((b, mp.mass * (g - ac), c, -mp.inertia * state.body_alpha[..., b], vc, dc))
    zero = np.zeros(dz.shape[:-2] + dz.shape[-1:], complex)
    for load in dyn.loads:
        if load.torque is not None:
            b = plan.body_names.index(load.link)
            out.append((b, 0j, 0j, load.torque + 0 * state.body_alpha[..., b], 0j, zero))
            continue
        k = plan.point_index(load.point)
        f = complex(*load.force)
        if load.opposes == "velocity":
            f = -abs(f) * v[..., k] / np.abs(v[..., k])
        out.append((plan.body_names.index(load.link), f, z[..., k], 0.0, v[..., k], dz[..., k, :]))
    for point, force, body in point_loads:
        k = plan.point_index(point)
        out.append((plan.body_names.index(body), complex(*force), z[..., k], 0.0, v[..., k], dz[..., k, :]))
    return out


def virtual_power_effort(plan, state, dyn, point_loads=()):
    """The driving efforts by virtual power, (..., n_inputs): Q_i = −Σ(F·∂r/∂q_i + M·∂θ/∂q_i), and their
    scale Σ|F·∂r/∂q_i| + |M·∂θ/∂q_i|. With one input also −Σ(F·v + M·ω)/q̇ from the velocities."""
    w, dth = state.body_omega, state.dangle_dq
    total = scale = 0.0
    power = 0.0
    for b, f, _, couple, vel, dvel in applied_loads(plan, state, dyn, point_loads):
        fq = dot(np.asarray(f)[..., None], dvel)
        mq = np.asarray(couple)[..., None] * dth[..., b, :]
        total, scale = total - fq - mq, scale + np.abs(fq) + np.abs(mq)
        power = power + dot(f, vel) + couple * w[..., b]
    if plan.n_inputs == 1:
        by_power = -power / float(state.qdot[0])
        np.testing.assert_allclose(by_power, total[..., 0], rtol=1e-9, atol=1e-9 * np.nanmax(scale))
    return total, scale


def body_residuals(plan, f, dyn, point_loads=()):
    """(force residual, moment residual) per moving body (..., n_bodies), from the returned reactions (the
    earlier body's force on the later one), the driver and every applied and d'Alembert load."""
    state = f.state
    z = cz(state.pos)
    shape = f.shape
    F = np.zeros(shape + (plan.n_bodies,), complex)
    M = np.zeros(shape + (plan.n_bodies,))
    lines = {rec[1]: rec for rec in plan.lines}
    acts = {a.name: a for a in plan.mechanism.actuators}

    def add(b, force, at, couple=0.0):
        F[..., b] += force
        M[..., b] += cross(at, force) + couple

    for k, (kind, name, (early, late)) in enumerate(zip(f.pair_kinds, f.pair_names, f.pair_bodies)):
        i, j = plan.body_names.index(early), plan.body_names.index(late)
        if kind == "R":
            force, at, couple = cz(f.reactions[..., k, :]), z[..., plan.point_index(name)], 0.0
        elif kind == "P":
            at = z[..., plan.point_index(lines[name][7])]
            force, couple = cz(f.reactions[..., k, :]), f.couples[..., k]
            if name in acts and any(d.kind == "linear" and d.actuator == name for d in plan.mechanism.drivers):
                h0, h1 = (z[..., plan.point_index(p)] for p in acts[name].between)
                i_in = next(n for n, d in enumerate(plan.mechanism.drivers) if d.actuator == name)
                force = force + f.driver[..., i_in] * (h1 - h0) / np.abs(h1 - h0)
        else:
            force, at, couple = 0j, 0j, f.couples[..., k]
        add(j, force, at, couple)
        add(i, -force, at, -couple)
    for b, force, at, couple, *_ in applied_loads(plan, state, dyn, point_loads):
        add(b, force, at, couple)
    return np.abs(F[..., 1:]), np.abs(M[..., 1:])


def input_range(plan, rng, n):
    """(n, n_inputs) inputs: a crank's full turn, an actuator's ±10 % about the sketch."""
    cols = [rng.uniform(0, 2 * np.pi, n) if kind == "rotary" else q0 * rng.uniform(0.9, 1.1, n)
            for kind, q0 in zip(plan.input_kinds, plan.sketch_inputs)]
    return np.stack(cols, axis=-1)


# -- 1. virtual power ---------------------------------------------------------------------------------------
def extra_loads(plan, rng):
    """A point force, a link torque and a velocity-opposing force on the last-solved links."""
    links = [n for n in plan.body_names[1:] if "." not in n]
    loads = []
    if links:
        link = links[-1]
        p = body_points(plan, link)[-1]
        loads += [Load(point=p, link=link, force=tuple(rng.uniform(-50, 50, 2))),
                  Load(link=links[0], torque=float(rng.uniform(-20, 20))),
                  Load(point=body_points(plan, links[0])[-1], link=links[0], force=(float(rng.uniform(5, 30)), 0.0),
                       opposes="velocity")]
    else:   # only actuators: a force at the rod's end
        rod = next(n for n in plan.body_names if n.endswith(".rod"))
        loads.append(Load(point=body_points(plan, rod)[0], link=rod, force=tuple(rng.uniform(-50, 50, 2))))
    return loads


def check_virtual_power(m, rng, params_rel=None, qdot=None, qddot=0.0, n=6, tol=1e-9):
    plan0 = assur.compile(m)
    dyn = random_dynamics(plan0, rng, loads=extra_loads(plan0, rng))
    plan = assur.compile(with_dynamics(m, dyn))
    params = plan.defaults.copy()
    if params_rel is not None:
        params = params * (1 + params_rel) + (params == 0) * params_rel * plan.length_scale
    qdot = plan.speeds if qdot is None else np.broadcast_to(qdot, (plan.n_inputs,))
    qddot = np.broadcast_to(qddot, (plan.n_inputs,))
    f = assur.forces(plan, params, input_range(plan, rng, n), speeds=qdot, accels=qddot)
    ok = f.valid
    ref, scale = virtual_power_effort(plan, f.state, dyn)
    assert np.all(np.abs(f.driver[ok] - ref[ok]) <= tol * scale[ok]), (f.driver[ok], ref[ok])
    return f, plan, dyn


@pytest.mark.parametrize("kind", sorted(DYADS))
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31 - 1), spread=st.floats(0.0, 0.08), qdot=st.floats(0.5, 30.0),
       reverse=st.booleans(), qddot=st.floats(-100.0, 100.0))
def test_virtual_power_on_random_dyads(kind, seed, spread, qdot, reverse, qddot):
    m = DYADS[kind]()
    plan = assur.compile(m)
    rng = np.random.default_rng(seed)
    rel = spread * rng.standard_normal(plan.n_params)
    if plan.input_kinds[0] == "linear":
        qdot, qddot = qdot / 100, qddot / 100        # m/s and m/s² for an actuator
    f, *_ = check_virtual_power(m, rng, rel, -qdot if reverse else qdot, qddot)
    assume(np.any(f.valid))      # reject unbuildable draws


@pytest.mark.parametrize("name", PLANAR_EXAMPLES + ["triad"])
def test_virtual_power_on_examples(name):
    rng = np.random.default_rng(7)
    m = assur.load(EXAMPLES / (name if name != "triad" else "triad_sixbar.toml"))
    plan = assur.compile(m)
    speed = np.where(plan.speeds != 0, plan.speeds, 1.0)
    f, _, _ = check_virtual_power(m, rng, qdot=1.3 * speed, qddot=0.7 * speed * np.abs(speed), n=24)
    assert np.count_nonzero(f.valid) >= 12


def test_triad_is_solved_by_the_linear_group():
    """The triad example really exercises a class-III group (not only dyads)."""
    assert "newton" in [st.kind for st in assur.compile(assur.load(EXAMPLES / "triad_sixbar.toml")).steps]


# -- 2. per-body residuals ----------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(DYADS) + ["triad_sixbar.toml", "lever_manipulator.toml", "jansen.toml"])
def test_every_body_is_in_equilibrium(name):
    rng = np.random.default_rng(11)
    m = DYADS[name]() if name in DYADS else assur.load(EXAMPLES / name)
    plan0 = assur.compile(m)
    dyn = random_dynamics(plan0, rng, loads=extra_loads(plan0, rng))
    plan = assur.compile(with_dynamics(m, dyn))
    speed = np.where(plan.speeds != 0, plan.speeds, 1.0)
    links = [n for n in plan.body_names[1:] if "." not in n]
    # a point load at a moving joint of the last link (not at a frame point)
    frame_points = set(body_points(plan, "frame"))
    extra = [(next(p for p in body_points(plan, links[-1]) if p not in frame_points), (3.0, -40.0))] \
        if links else []
    for method in ("groups", "matrix"):
        # the point load acts on the last link (named: the joint may join several bodies)
        f = assur.forces(plan, inputs=input_range(plan, rng, 20), speeds=speed, accels=0.5 * speed,
                         point_loads=[(p, np.array(F), links[-1]) for p, F in extra] if extra else None,
                         method=method)
        ok = f.valid
        assert np.count_nonzero(ok) >= 10
        extra_b = [(p, F, links[-1]) for p, F in extra]
        rf, rm = body_residuals(plan, f, dyn, extra_b)
        scale = max(np.nanmax(f.magnitudes[ok]), np.nanmax(np.abs(f.driver[ok])) / plan.length_scale, 1.0)
        assert np.nanmax(rf[ok]) <= 1e-10 * scale, method
        assert np.nanmax(rm[ok]) <= 1e-10 * scale * plan.length_scale, method


def _solve_rank(plan, body):
    """The index of the plan step that first solves ``body``."""
    b = plan.body_names.index(body)
    return next(i for i, st in enumerate(plan.steps) if b in st.bodies)


# -- 3. energy over a cycle ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["crank_rocker.toml", "slider_crank.toml", "triad_sixbar.toml", "jansen.toml"])
def test_cycle_work_of_gravity_and_inertia_is_zero(name):
    """At constant crank speed the kinetic and potential energies are periodic, so ∮T dφ = 0.

    T(φ) is smooth and 2π-periodic, so the periodic trapezoid rule converges geometrically: on 720 points
    its error is far below rounding; the tolerance 1e-9·∮|T|dφ allows for the rounding of the forces."""
    m = assur.load(EXAMPLES / name)
    dyn = random_dynamics(assur.compile(m), np.random.default_rng(3))
    plan = assur.compile(with_dynamics(m, dyn))
    n = 720
    phi = np.arange(n) * (2 * np.pi / n)
    f = assur.forces(plan, inputs=phi, speeds=[2.5 * plan.speeds[0]], accels=[0.0])
    assert f.valid.all()
    T = f.driver[:, 0]
    work, size = T.sum() * (2 * np.pi / n), np.abs(T).sum() * (2 * np.pi / n)
    assert size > 1.0                       # a real load, not an empty check
    assert abs(work) <= 1e-9 * size
    # the same integral by scipy's adaptive quadrature on the Fourier-interpolated torque
    from scipy.integrate import quad
    c = np.fft.rfft(T) / n
    interp = lambda x: (c[0] + 2 * sum((c[k] * np.exp(1j * k * x)).real for k in range(1, 40))).real  # noqa: E731
    assert abs(quad(interp, 0, 2 * np.pi, limit=200)[0]) <= 1e-7 * size


# -- 4. a massless leg loaded at the foot ----------------------------------------------------------------------
def test_walking_leg_torque_is_the_load_times_the_foot_analogue():
    """A massless leg, a vertical ground load W at the foot H: T·dφ + W·dy_H = 0, so T = −W·dy_H/dφ."""
    plan = assur.compile(dataclasses.replace(assur.load(EXAMPLES / "walker_fourbar.toml"), dynamics=None))
    phi = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    W = 200.0 + 50.0 * np.sin(phi)           # a load that varies along the batch
    f = assur.forces(plan, inputs=phi, point_loads=[("H", np.stack([0 * W, W], axis=-1))])
    assert f.valid.all()
    dy = f.state.dpos_dq[:, plan.point_index("H"), 1, 0]
    np.testing.assert_allclose(f.driver[:, 0], -W * dy, rtol=1e-10, atol=1e-10 * W.max() * plan.length_scale)


# -- 5. a linear actuator ------------------------------------------------------------------------------------
def test_actuator_force_is_the_load_times_the_analogue():
    """Massless lever manipulator, a force P at the joint B: F·ds + P·dr_B = 0, so F = −P·∂r_B/∂s."""
    plan = assur.compile(dataclasses.replace(assur.load(EXAMPLES / "lever_manipulator.toml"), dynamics=None))
    s = np.linspace(0.5, 1.0, 41)
    P = np.array([120.0, -300.0])
    f = assur.forces(plan, inputs=s, point_loads=[("B", P)])
    ok = f.valid
    assert ok.sum() >= 35
    drdS = f.state.dpos_dq[:, plan.point_index("B"), :, 0]
    np.testing.assert_allclose(f.driver[ok, 0], -(drdS[ok] @ P), rtol=1e-10, atol=1e-10 * np.abs(P).sum())


# -- 7. oracle, batches and backends -------------------------------------------------------------------------
def _effort_scale(f):
    return max(np.nanmax(f.magnitudes), np.nanmax(np.abs(f.driver)) / f.plan.length_scale)


@pytest.mark.parametrize("name", sorted(DYADS) + PLANAR_EXAMPLES)
def test_groups_equal_the_global_matrix(name):
    m = DYADS[name]() if name in DYADS else assur.load(EXAMPLES / name)
    rng = np.random.default_rng(5)
    plan0 = assur.compile(m)
    dyn = random_dynamics(plan0, rng, loads=extra_loads(plan0, rng))
    plan = assur.compile(with_dynamics(m, dyn))
    q = input_range(plan, rng, 40)
    speed = np.where(plan.speeds != 0, plan.speeds, 1.0)
    a = assur.forces(plan, inputs=q, speeds=speed, accels=0.3 * speed, method="groups")
    b = assur.forces(plan, inputs=q, speeds=speed, accels=0.3 * speed, method="matrix")
    ok = a.valid & b.valid
    assert ok.sum() >= 20
    scale = _effort_scale(a)
    np.testing.assert_allclose(a.reactions[ok], b.reactions[ok], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(a.couples[ok], b.couples[ok], rtol=0, atol=1e-9 * scale * plan.length_scale)
    np.testing.assert_allclose(a.driver[ok], b.driver[ok], rtol=1e-9, atol=1e-9 * scale * plan.length_scale)


@pytest.mark.parametrize("name", sorted(DYADS) + ["triad_sixbar.toml", "jansen.toml"])
def test_matrix_flags_the_same_samples_singular_as_the_groups(name):
    """A pose that every group solves well (condition ≥ 0.15 here) is not a toggle of the whole mechanism."""
    m = DYADS[name]() if name in DYADS else assur.load(EXAMPLES / name)
    plan = assur.compile(m)
    q = input_range(plan, np.random.default_rng(5), 40)
    a = assur.forces(plan, inputs=q, method="groups")
    b = assur.forces(plan, inputs=q, method="matrix")
    assert np.array_equal(a.valid, b.valid) and np.array_equal(a.singular, b.singular)


@pytest.mark.parametrize("name", ["RRP", "actuator_RRR",
                                  pytest.param("triad_sixbar.toml", marks=pytest.mark.slow)])
def test_batched_designs_and_inputs_equal_single_calls(name):
    m = DYADS[name]() if name in DYADS else assur.load(EXAMPLES / name)
    rng = np.random.default_rng(9)
    plan0 = assur.compile(m)
    dyn = random_dynamics(plan0, rng, loads=extra_loads(plan0, rng))
    plan = assur.compile(with_dynamics(m, dyn))
    params = plan.defaults * (1 + 0.01 * rng.standard_normal((3, 1, plan.n_params)))
    q = input_range(plan, rng, 50)[None, :, 0]          # (1, 50)
    f = assur.forces(plan, params, q)
    assert f.shape == (3, 50) and f.valid.sum() >= 100
    for i in range(3):
        for j in range(0, 50, 7):
            one = assur.forces(plan, params[i, 0], q[:, j])
            assert one.shape == (1,)
            if not f.valid[i, j]:
                assert not one.valid[0]
                continue
            np.testing.assert_allclose(one.reactions[0], f.reactions[i, j], rtol=1e-12, atol=1e-12 * _effort_scale(f))
            np.testing.assert_allclose(one.driver[0], f.driver[i, j], rtol=1e-12, atol=1e-12 * _effort_scale(f))


@pytest.mark.slow          # compiles the numba kernels
@pytest.mark.parametrize("name", ["RRR", "RRP", "RPR", "actuator_RRP", "jansen.toml"])
def test_compiled_backend_equals_numpy(name):
    pytest.importorskip("numba")
    m = DYADS[name]() if name in DYADS else assur.load(EXAMPLES / name)
    rng = np.random.default_rng(13)
    plan0 = assur.compile(m)
    dyn = random_dynamics(plan0, rng, loads=extra_loads(plan0, rng))
    plan = assur.compile(with_dynamics(m, dyn))
    q = input_range(plan, rng, 64)
    a = assur.forces(plan, inputs=q, backend="numpy")
    b = assur.forces(plan, inputs=q, backend="numba")
    assert np.array_equal(a.valid, b.valid) and a.valid.sum() >= 32
    ok = a.valid
    scale = _effort_scale(a)
    np.testing.assert_allclose(b.reactions[ok], a.reactions[ok], rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(b.driver[ok], a.driver[ok], rtol=1e-9, atol=1e-9 * scale * plan.length_scale)


# -- 8. toggles ----------------------------------------------------------------------------------------------
def rocker_driven_fourbar():
    """The four-bar of :func:`fourbar` driven at its rocker O1–B: the crank O–A and the coupler A–B form the
    dyad, which toggles (O, A, B collinear) where |OB| = a + b = 1.3, at the rocker's angle ψ* with
    |1 + 0.8·e^{iψ*}|² = 1.3², cos ψ* = (1.69 − 1 − 0.64)/1.6 (and again at |OB| = b − a = 0.7,
    ψ ≈ 2.37)."""
    A = 0.3 * cmath.exp(0.6j)
    B = circle_circle(A, 1.0, 1 + 0j, 0.8, left=True)
    bl = assur.Builder(units="m", angle="rad").point("O", 0, 0).point("O1", 1, 0)
    pt(pt(bl, "A", A), "B", B)
    m = (bl.frame("O", "O1").link("crank", "O", "A").link("coupler", "A", "B").link("rocker", "O1", "B")
         .crank("rocker", pivot="O1", arm="B", zero=0.0, speed="30 rpm", name="rocker").build())
    return m, math.acos((1.69 - 1 - 0.64) / 1.6)


def test_forces_at_a_toggle_are_nan_and_singular():
    m, psi_star = rocker_driven_fourbar()
    dyn = random_dynamics(assur.compile(m), np.random.default_rng(17))
    plan = assur.compile(with_dynamics(m, dyn))
    near = psi_star + np.array([0.0, 1e-14, 1e-13])
    away = psi_star + np.array([0.2, 0.4, 0.6])        # inside the rocker's range [ψ*, 2.37]
    f = assur.forces(plan, inputs=np.concatenate([near, away]))
    at = f.state.valid[:3]
    assert at.any()                            # assembled at the toggle, so the forces must say so
    assert f.singular[:3][at].all()
    assert np.isnan(f.driver[:3][at]).all() and np.isnan(f.reactions[:3][at]).all()
    assert not f.valid[:3].any()
    assert f.valid[3:].all() and not f.singular[3:].any()
    assert np.isfinite(f.driver[3:]).all() and np.isfinite(f.reactions[3:]).all()
    for method in ("groups", "matrix"):
        g = assur.forces(plan, inputs=near, method=method)
        assert np.isnan(g.driver[g.state.valid]).all() and g.singular[g.state.valid].all()


# -- 9. friction ---------------------------------------------------------------------------------------------
def test_friction_converges_and_dissipates_power():
    """Slide friction and revolute friction circles on the example slider-crank (gravity, inertia and a
    resisting force on the slider): the iteration converges and the mean motor power over a cycle rises."""
    m = assur.load(EXAMPLES / "slider_crank.toml")
    base = random_dynamics(assur.compile(m), np.random.default_rng(23),
                           loads=(Load(point="B", link="slot.block", force=(800.0, 0.0), opposes="velocity"),))
    n = 360
    phi = np.arange(n) * (2 * np.pi / n) + 1e-3     # off the dead centres, where the slider stops
    mean = {}
    for mu, radius in ((0.0, 0.0), (0.15, 0.002), (0.3, 0.004)):
        dyn = dataclasses.replace(base, friction=Friction(joint_radius=radius, slide=mu))
        plan = assur.compile(with_dynamics(m, dyn))
        f = assur.forces(plan, inputs=phi, friction=True)
        assert f.converged and f.valid.all()
        assert (f.iterations > 0) == bool(mu)
        mean[mu] = f.power.mean()
    assert mean[0.0] > 0                     # the motor drives a resisting load
    assert mean[0.0] < mean[0.15] < mean[0.3]
