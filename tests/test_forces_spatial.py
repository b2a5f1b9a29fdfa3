"""Forces of the spatial RSSR of paper 003 (docs/papers/003.md): the driving torque by virtual power,
the reactions by each body's Newton–Euler equations, both computed independently here from the solved
kinematics and the mass model stated in :mod:`assur.kinetostatics.spatial`."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import assur
from assur.analysis.spatial import dyads, mu_t
from assur.errors import SpecError
from assur.kinetostatics.spatial import spatial_forces
from assur.model.dynamics import Dynamics, Load, MassProperties
from assur.tolerances import DEFAULT

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ("rssr.toml", "rssr_tilted.toml")
Q = np.linspace(0.0, 2 * np.pi, 37)[:-1] + 0.01


def _spherical_text(name):
    """The example with a spherical joint at P2 and a bare coupler P2–P3 (it then spins idly)."""
    text = (EXAMPLES / name).read_text()
    text = text.replace('P2 = { kind = "universal", axis = [-1, 0, 0] }', 'P2 = "spherical"')
    text = text.replace('points = ["P2", "P3", "C"]', 'points = ["P2", "P3"]')
    return "\n".join(ln for ln in text.splitlines() if not ln.startswith("C = "))


def _mechanism(name, *, spherical=False):
    return assur.loads(_spherical_text(name)) if spherical else assur.load(EXAMPLES / name)


MASSES = {"crank": (0.4, 2e-4), "coupler": (0.9, 5e-4), "rocker": (0.6, 3e-4)}


def _dynamics(coupler_mass: bool, *, spherical=False, com=None, load_at_c=True):
    bodies = [("crank", MassProperties(0.4, 2e-4)), ("rocker", MassProperties(0.6, 3e-4, "mid"))]
    if coupler_mass:
        bodies.append(("coupler", MassProperties(0.9, 5e-4, com)))
    loads = [Load(link="rocker", torque=-1.5)]
    if load_at_c or spherical:           # on the coupler at C; at P3 (on the rocker) for a bare coupler
        loads.append(Load(point="P3", link="rocker", force=(3.0, -2.0, 5.0)) if spherical
                     else Load(point="C", force=(3.0, -2.0, 5.0)))
    return Dynamics(gravity=(0.0, -9.81, 0.0), bodies=tuple(bodies), loads=tuple(loads))


def _loads_on_bodies(plan, state, dyn):
    """The applied loads (gravity, d'Alembert inertia, the file's loads) on each moving body, from the
    state's points and the module's mass model, as (force, moment about the origin, power) per body."""
    P = {n: state.pos[..., i, :] for i, n in enumerate(plan.point_names)}
    V = {n: state.vel[..., i, :] for i, n in enumerate(plan.point_names)}
    A = {n: state.acc[..., i, :] for i, n in enumerate(plan.point_names)}
    g = np.asarray(dyn.gravity)
    m = plan.mechanism
    out = {}
    for b, name in enumerate(plan.body_names[1:], start=1):
        F = np.zeros(state.shape + (3,))
        M = np.zeros(state.shape + (3,))
        power = np.zeros(state.shape)
        mp = dyn.mass_of(name)
        pts = m.link(name).points
        omega = state.body_omega[..., b, :]
        if mp.mass:
            com_pts = pts[:2] if mp.com == "mid" else ((mp.com,) if isinstance(mp.com, str) else pts)
            c = sum(P[p] for p in com_pts) / len(com_pts)
            v = sum(V[p] for p in com_pts) / len(com_pts)
            a = sum(A[p] for p in com_pts) / len(com_pts)
            f = mp.mass * (g - a)
            F += f
            M += np.cross(c, f)
            power += np.sum(f * v, -1)
            if name == "coupler":            # slender bar: H = I·u × u̇, couple −I·u × ü
                d = P["P3"] - P["P2"]
                L = np.linalg.norm(d, axis=-1, keepdims=True)
                u, ud, udd = d / L, (V["P3"] - V["P2"]) / L, (A["P3"] - A["P2"]) / L
                couple = -mp.inertia * np.cross(u, udd)
                w_perp = np.cross(u, ud)
            else:                            # about the hinge axis only
                e = state.body_frame[..., b, :, 2]
                alpha = state.body_alpha[..., b, :]
                couple = -mp.inertia * np.sum(alpha * e, -1)[..., None] * e
                w_perp = omega
            M += couple
            power += np.sum(couple * w_perp, -1)
        for ld in dyn.loads:
            if ld.torque is not None and ld.link == name:
                t = ld.torque * state.body_frame[..., b, :, 2]
                M += t
                power += np.sum(t * omega, -1)
            elif ld.force is not None and ld.point in pts and (ld.link or plan.body_names[
                    plan.point_body[plan.point_index(ld.point)]]) == name:
                f = np.asarray(ld.force)
                F += f
                M += np.cross(P[ld.point], f)
                power += np.sum(f * V[ld.point], -1)
        out[name] = (F, M, power)
    return out


def _case(name, coupler_mass, spherical=False, com=None, load_at_c=True):
    m = _mechanism(name, spherical=spherical)
    dyn = _dynamics(coupler_mass, spherical=spherical, com=com, load_at_c=load_at_c)
    plan = assur.compile(dataclasses.replace(m, dynamics=dyn))
    f = assur.forces(plan, inputs=Q)
    return plan, dyn, f


@pytest.mark.parametrize("name", FILES)
@pytest.mark.parametrize("coupler_mass", [False, True])
@pytest.mark.parametrize("spherical", [False, True])
def test_driving_torque_is_the_virtual_power_torque(name, coupler_mass, spherical):
    plan, dyn, f = _case(name, coupler_mass, spherical)
    loads = _loads_on_bodies(plan, f.state, dyn)
    qdot = float(f.qdot[0])
    expected = -sum(p for _, _, p in loads.values()) / qdot
    assert np.all(f.valid)
    np.testing.assert_allclose(f.driver[..., 0], expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))
    np.testing.assert_allclose(f.power, f.driver[..., 0] * qdot, rtol=1e-12)


@pytest.mark.parametrize("name", FILES)
@pytest.mark.parametrize("coupler_mass", [False, True])
@pytest.mark.parametrize("spherical", [False, True])
def test_every_body_is_in_equilibrium(name, coupler_mass, spherical):
    """Newton–Euler of crank, coupler and rocker with the returned reactions and moments; the frame
    bearings' moments are perpendicular to their axes, the cross moment perpendicular to the pin."""
    plan, dyn, f = _case(name, coupler_mass, spherical)
    st = f.state
    loads = _loads_on_bodies(plan, st, dyn)
    P = {n: st.pos[..., i, :] for i, n in enumerate(plan.point_names)}
    R = {n: f.reactions[..., f.pair(n), :] for n in ("P1", "P2", "P3", "P4")}
    C = {n: f.bearing_moments[..., f.pair(n), :] for n in ("P1", "P2", "P3", "P4")}
    T = f.bearing_moments[..., f.pair_kinds.index("T"), :]
    scale = max(np.max(np.abs(v)) for v in R.values())
    Fk, Mk, _ = loads["crank"]
    Fc, Mc, _ = loads["coupler"]
    Fr, Mr, _ = loads["rocker"]
    residuals = [
        Fk + R["P1"] - R["P2"],
        Fc + R["P2"] + R["P3"],
        Fr - R["P3"] + R["P4"],
    ]
    moments = [
        Mk + np.cross(P["P1"], R["P1"]) + C["P1"] + T - np.cross(P["P2"], R["P2"]) - C["P2"],
        Mc + np.cross(P["P2"], R["P2"]) + C["P2"] + np.cross(P["P3"], R["P3"]) + C["P3"],
        Mr - np.cross(P["P3"], R["P3"]) - C["P3"] + np.cross(P["P4"], R["P4"]) + C["P4"],
    ]
    for r in residuals:
        assert np.max(np.abs(r)) <= 1e-9 * scale
    for r in moments:
        assert np.max(np.abs(r)) <= 1e-9 * scale * plan.length_scale
    e1 = st.body_frame[..., plan.body_names.index("crank"), :, 2]
    e2 = st.body_frame[..., plan.body_names.index("rocker"), :, 2]
    assert np.max(np.abs(np.sum(C["P1"] * e1, -1))) <= 1e-12 * scale
    assert np.max(np.abs(np.sum(C["P4"] * e2, -1))) <= 1e-12 * scale
    np.testing.assert_allclose(np.sum(T * e1, -1), f.couples[..., f.pair_kinds.index("T")], rtol=1e-12)
    assert f.pair_kinds == ("R", "S" if spherical else "U", "S", "R", "T")
    if spherical:
        assert np.all(C["P2"] == 0) and np.all(C["P3"] == 0)
    else:       # the cross moment is perpendicular to the pin (−X on the crank)
        assert np.max(np.abs(C["P2"][..., 0])) <= 1e-12 * scale
        assert np.max(np.abs(C["P2"])) > 0
    np.testing.assert_allclose(f.magnitudes, np.linalg.norm(f.reactions, axis=-1), rtol=1e-15)


@pytest.mark.parametrize("name", FILES)
@pytest.mark.parametrize("spherical", [False, True])
def test_massless_coupler_is_a_two_force_member(name, spherical):
    plan, dyn, f = _case(name, coupler_mass=False, spherical=spherical, load_at_c=False)
    u = f.state.pos[..., plan.point_index("P3"), :] - f.state.pos[..., plan.point_index("P2"), :]
    FA, FB = f.reaction("P2"), f.reaction("P3")
    np.testing.assert_allclose(FA, -FB, rtol=0, atol=1e-12 * np.max(np.abs(FB)))
    along = np.linalg.norm(np.cross(FB, u), axis=-1) / np.linalg.norm(u, axis=-1)
    assert np.max(along) <= 1e-12 * np.max(np.abs(FB))


@pytest.mark.parametrize("name", FILES)
def test_frame_load_is_the_resultant_of_the_applied_loads(name):
    """With ideal joints the moving links load the frame with the sum of their applied loads."""
    plan, dyn, f = _case(name, coupler_mass=True)
    loads = _loads_on_bodies(plan, f.state, dyn)
    F = sum(v[0] for v in loads.values())
    M = sum(v[1] for v in loads.values())
    np.testing.assert_allclose(f.frame_force, F, rtol=0, atol=1e-10 * np.max(np.abs(F)))
    np.testing.assert_allclose(f.frame_moment, M, rtol=0, atol=1e-10 * np.max(np.abs(M)))


def test_com_by_coordinates_equals_com_at_the_point():
    """A com given as sketch coordinates fixed to the coupler (the sketch of C) is the point C."""
    m = assur.load(EXAMPLES / "rssr_tilted.toml")
    by_point = assur.forces(assur.compile(dataclasses.replace(m, dynamics=_dynamics(True, com="C"))), inputs=Q)
    by_xyz = assur.forces(assur.compile(dataclasses.replace(m, dynamics=_dynamics(True, com=m.sketch("C")))),
                          inputs=Q)
    np.testing.assert_allclose(by_xyz.driver, by_point.driver, rtol=1e-9)
    np.testing.assert_allclose(by_xyz.reactions, by_point.reactions, rtol=1e-9, atol=1e-9)


def test_batched_designs_and_angles_match_single_samples():
    m = assur.load(EXAMPLES / "rssr_tilted.toml")
    plan = assur.compile(dataclasses.replace(m, dynamics=_dynamics(True)))
    params = np.stack([plan.defaults, plan.params_with(crank__length=0.018, rocker__length=0.047)])[:, None, :]
    q = Q[None, :7]
    f = assur.forces(plan, params, q[..., None])
    assert f.shape == (2, 7) and f.reactions.shape == (2, 7, 5, 3) and f.frame_moment.shape == (2, 7, 3)
    for i in range(2):
        for j in range(7):
            one = assur.forces(plan, params[i, 0], np.array([Q[j]]))
            np.testing.assert_allclose(f.driver[i, j], one.driver[0], rtol=1e-12)
            np.testing.assert_allclose(f.reactions[i, j], one.reactions[0], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("name", FILES)
def test_condition_is_the_sine_of_the_transmission_angle_and_masks(name):
    """For this pin the cross never limits: the condition is sin μ_T (paper 003 §5); samples below the
    threshold are singular with NaN forces."""
    plan, dyn, f = _case(name, coupler_mass=True)
    np.testing.assert_allclose(f.condition, np.sin(mu_t(dyads(plan, f.state)[0])), rtol=1e-12)
    tol = dataclasses.replace(DEFAULT, force_condition=float(np.median(f.condition)))
    g = spatial_forces(plan, inputs=Q, tolerances=tol)
    low = f.condition < tol.force_condition
    assert low.any() and (~low).any()
    assert np.array_equal(g.singular, low) and np.array_equal(g.valid, ~low)
    assert np.all(np.isnan(g.driver[low])) and np.all(np.isnan(g.reactions[low]))
    np.testing.assert_allclose(g.driver[~low], f.driver[~low], rtol=1e-15)


def _freudenstein_phi(f1):
    """Paper 003 §9: the rocker's angle φ = θ + g in the (Y, Z) plane (right-handed about +X) of the
    planar-equivalent RSSR, by Freudenstein's closed form."""
    g = math.atan2(48.0, 36.0)
    a, b, c, d = 20.0, 70.0, 50.0, 60.0
    K1, K2, K3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    t2 = f1 - g
    A = np.cos(t2) - K1 - K2 * np.cos(t2) + K3
    B = -2 * np.sin(t2)
    Cc = K1 - (K2 + 1) * np.cos(t2) + K3
    return 2 * np.arctan2(-B - np.sqrt(B * B - 4 * A * Cc), 2 * A) + g


def test_reproduction_torque_against_a_rocker_load():
    """examples/rssr.toml, massless links, a constant load torque of −1 N·m about the rocker axis
    e2 = +X: by virtual power the motor torque is T = −(−1 N·m)·dφ/df1, φ the rocker angle of
    Freudenstein's closed form (docs/papers/003.md §9), differentiated here by central differences."""
    m = assur.load(EXAMPLES / "rssr.toml")
    plan = assur.compile(dataclasses.replace(m, dynamics=Dynamics(loads=(Load(link="rocker", torque=-1.0),))))
    q = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)
    f = assur.forces(plan, inputs=q)
    h = 1e-5
    step = (_freudenstein_phi(q + h) - _freudenstein_phi(q - h) + np.pi) % (2 * np.pi) - np.pi   # φ wraps
    expected = step / (2 * h)
    np.testing.assert_allclose(f.driver[:, 0], expected, rtol=0, atol=1e-8)
    peak, rms = np.max(np.abs(f.driver)), np.sqrt(np.mean(f.driver ** 2))
    assert peak == pytest.approx(np.max(np.abs(expected)), rel=1e-8)
    assert rms == pytest.approx(np.sqrt(np.mean(expected ** 2)), rel=1e-8)
    # the work of the motor over a turn balances the (conservative) rocker load: zero mean torque
    assert abs(np.mean(f.driver)) <= 1e-9


def test_bad_input_is_reported_where_it_is():
    m = assur.load(EXAMPLES / "rssr.toml")
    bad = [
        (Dynamics(loads=(Load(link="coupler", torque=1.0),)), "loads[0].link"),
        (Dynamics(loads=(Load(point="C", force=(1.0, 2.0)),)), "loads[0].force"),
        (Dynamics(gravity=(0.0, -9.81)), "dynamics.gravity"),
        (Dynamics(bodies=(("coupler", MassProperties(1.0, None, (0.0, 0.0))),)), "links.coupler.com"),
    ]
    for dyn, path in bad:
        plan = assur.compile(dataclasses.replace(m, dynamics=dyn))
        with pytest.raises(SpecError) as e:
            assur.forces(plan, inputs=Q)
        assert e.value.problems[0][0] == path
    idle = assur.loads(_spherical_text("rssr_tilted.toml"))
    off_line = Dynamics(bodies=(("coupler", MassProperties(1.0, None, (0.02, 0.04, 0.03))),))
    with pytest.raises(SpecError, match="spins idly") as e:
        assur.forces(assur.compile(dataclasses.replace(idle, dynamics=off_line)), inputs=Q)
    assert e.value.problems[0][0] == "links.coupler.com"
    plan = assur.compile(dataclasses.replace(m, dynamics=_dynamics(True)))
    with pytest.raises(SpecError) as e:
        assur.forces(plan, inputs=Q, state=assur.solve(plan, inputs=Q, order=1))
    assert e.value.problems[0][0] == "state"


def test_load_laws_and_loads_against_the_velocity():
    """A law of the first input with equal values is the constant load; a force of 4 N against C's
    velocity costs the motor, by virtual power, 4·|v_C|/q̇ of torque."""
    from assur.model.dynamics import LoadLaw
    m = assur.load(EXAMPLES / "rssr_tilted.toml")

    def driver(*loads):
        plan = assur.compile(dataclasses.replace(m, dynamics=Dynamics(loads=loads)))
        return assur.forces(plan, inputs=Q)

    const = driver(Load(point="C", force=(1.0, -2.0, 0.5)), Load(link="rocker", torque=0.7))
    law = driver(Load(point="C", law=LoadLaw((0.0, 3.0), ((1.0, -2.0, 0.5), (1.0, -2.0, 0.5)))),
                 Load(link="rocker", law=LoadLaw((0.0, 3.0), ((0.7,), (0.7,)))))
    np.testing.assert_allclose(law.driver, const.driver, rtol=1e-12)
    np.testing.assert_allclose(law.reactions, const.reactions, rtol=1e-12, atol=1e-15)
    f = driver(Load(point="C", force=(0.0, 4.0, 0.0), opposes="velocity"))
    v = f.state.vel[..., f.plan.point_index("C"), :]
    np.testing.assert_allclose(f.driver[..., 0], 4.0 * np.linalg.norm(v, axis=-1) / f.qdot[0], rtol=1e-9)
