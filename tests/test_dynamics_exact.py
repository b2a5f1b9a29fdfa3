"""Forward dynamics against independent computations written here: energy and period of a free four-bar, the
closed-form start-up of a constant inertia on a DC motor, the slider-crank and the four-bar by Lagrange's equation
written by hand, virtual power at the simulated motion, and the kinetostatic flywheel estimate.

Every reference is computed in this file: the kinematics of the slider-crank and the four-bar in closed form
(loop closure, differentiated by hand), energies from assur's solved velocities with the centres of mass and
inertias stated here, quadratures with scipy.integrate.quad, and the equations of motion integrated with
scipy.integrate.solve_ivp.
"""
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

import assur
from assur.dynamics.reduced import reduced_terms

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
G = 9.81

# -- the mechanisms ---------------------------------------------------------------------------------------
# crank_rocker.toml: O2 = (0, 0), O4 = (100, 0) mm, crank 40, coupler A-B 120 with P, rocker 80 mm.
FOURBAR_MASS = {"crank": (0.2, 3e-5), "coupler": (0.5, 8e-4), "rocker": (0.3, 2e-4)}


def fourbar_text(motor: str = "") -> str:
    text = (EXAMPLES / "crank_rocker.toml").read_text()
    text = text.replace('length = 40\n', 'length = 40\nmass = 0.2\ncom = "mid"\ninertia = 3e-5\n', 1)
    text = text.replace('length = 80\n', 'length = 80\nmass = 0.3\ncom = "mid"\ninertia = 2e-4\n', 1)
    text = text.replace('length = 120\n', 'length = 120\nmass = 0.5\ncom = "P"\ninertia = 8e-4\n', 1)
    return text + "\n[dynamics]\ngravity = [0, -9.81]\n" + motor


# slider_crank.toml: crank O-A 50 mm, rod A-B 150 mm, B on the line y = +20 mm.
R, L, E = 0.05, 0.15, 0.02
M_ROD, I_ROD, M_BLOCK, I_CRANK = 0.3, 6e-4, 0.4, 5e-4


def slider_text(motor: str = "", extra: str = "") -> str:
    text = (EXAMPLES / "slider_crank.toml").read_text()
    text = text.replace('length = 50\n', f'length = 50\nmass = 0.5\ncom = "O"\ninertia = {I_CRANK}\n', 1)
    text = text.replace('length = 150\n', f'length = 150\nmass = {M_ROD}\ncom = "mid"\ninertia = {I_ROD}\n', 1)
    text = text.replace('offset = 20\n', f'offset = 20\nmass = {M_BLOCK}\n', 1)
    return text + "\n[dynamics]\ngravity = [0, -9.81]\n" + extra + motor


def plan_of(text):
    return assur.compile(assur.loads(text))


# -- independent kinetic and potential energy of the four-bar from assur's solved velocities ---------------
def fourbar_energy(plan, q, w):
    """T + V (J) at inputs q (n,) and rates w (n,): ½Σ m|v_c|² + ½Σ I·ω² + Σ m·g·y_c, the centres of mass and
    the angular velocities computed here from the solved points."""
    st = assur.solve(plan, None, q[:, None], speeds=w[:, None], order=1)
    P = {n: st.point(n).pos for n in ("O2", "A", "B", "P", "O4")}
    V = {n: st.point(n).vel for n in ("O2", "A", "B", "P", "O4")}

    def omega(a, b):
        d, dv = P[b] - P[a], V[b] - V[a]
        return (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]) / np.sum(d * d, axis=1)
    bodies = {"crank": (0.5 * (P["O2"] + P["A"]), 0.5 * (V["O2"] + V["A"]), omega("O2", "A")),
              "coupler": (P["P"], V["P"], omega("A", "B")),
              "rocker": (0.5 * (P["O4"] + P["B"]), 0.5 * (V["O4"] + V["B"]), omega("O4", "B"))}
    T = Vg = 0.0
    for name, (c, v, om) in bodies.items():
        m, inertia = FOURBAR_MASS[name]
        T = T + 0.5 * m * np.sum(v * v, axis=1) + 0.5 * inertia * om * om
        Vg = Vg + m * G * c[:, 1]
    return T + Vg, Vg


def fourbar_inertia(plan, q):
    """J*(q) and V(q) of the four-bar from the energy at unit rate: J* = 2T(q, 1)."""
    E, V = fourbar_energy(plan, q, np.ones_like(q))
    return 2.0 * (E - V), V


@pytest.mark.slow
def test_free_fourbar_conserves_energy_over_100_turns():
    plan = plan_of(fourbar_text())
    s = assur.simulate(plan, motor=False, cycles=100, speed0=20.0, rtol=1e-13)
    assert s.stop.kind == "turns" and len(s.turns) == 100
    E, _ = fourbar_energy(plan, s.q, s.speed)
    assert np.ptp(E) <= 1e-10 * np.max(np.abs(E))


def test_free_fourbar_period_is_the_quadrature():
    """T = ∮ √(J*/(2(E − V))) dq, J* and V computed here (assur's velocities at unit rate, the masses above)."""
    plan = plan_of(fourbar_text())
    q0, w0 = float(plan.sketch_inputs[0]), 12.0
    s = assur.simulate(plan, motor=False, cycles=4, speed0=w0, rtol=1e-13)
    E0 = float(fourbar_energy(plan, np.array([q0]), np.array([w0]))[0][0])

    def integrand(q):
        J, V = fourbar_inertia(plan, np.array([q]))
        return math.sqrt(J[0] / (2.0 * (E0 - V[0])))
    T, err = quad(integrand, q0, q0 + 2 * math.pi, epsabs=0, epsrel=1e-13, limit=400)
    assert err < 1e-12 * T
    for turn in s.turns:
        assert abs(turn.period - T) <= 1e-9 * T


def disc_plan():
    """A balanced disc on a crank: J* = 0.05 kg·m² at every angle, no load."""
    m = (assur.Builder(units="m", angle="deg", name="disc")
         .point("O", 0, 0).point("A", 0.1, 0).frame("O").link("disc", "O", "A")
         .crank("disc", pivot="O", arm="A", speed="100 rpm", name="crank")
         .mass("disc", 2.0, inertia=0.05, com="O").build())
    return assur.compile(m)


def test_dc_motor_on_a_constant_inertia_is_the_closed_form_startup():
    """J·ω̇ = T_s(1 − ω/ω₀): ω = ω₀(1 − e^{−t/τ}), τ = J·ω₀/T_s, t₉₅ = τ·ln 20."""
    plan = disc_plan()
    J, Ts, w0 = 0.05, 50.0, 100.0
    s = assur.simulate(plan, motor={"kind": "dc", "stall_torque": Ts, "no_load_speed": f"{w0} rad/s"}, rtol=1e-12)
    tau = J * w0 / Ts
    assert s.steady and s.starts
    assert np.max(np.abs(s.speed - w0 * (1 - np.exp(-s.t / tau)))) <= 1e-9 * w0
    angle = w0 * (s.t - tau * (1 - np.exp(-s.t / tau)))
    assert np.max(np.abs((s.q - s.q[0]) - angle)) <= 1e-8
    assert s.startup_time == pytest.approx(tau * math.log(20.0), rel=1e-6)
    assert s.mean_speed == pytest.approx(w0, rel=1e-6)


# -- the slider-crank by Lagrange's equation, written here ---------------------------------------------------
def slider_terms(phi):
    """J*(φ), dJ*/dφ, dV/dφ of the offset slider-crank (masses above) from its closed-form kinematics."""
    s, c = math.sin(phi), math.cos(phi)
    u, du, d2u = E - R * s, -R * c, R * s
    k = math.sqrt(L * L - u * u)
    dk = -u * du / k
    d2k = -(du * du + u * d2u) / k + u * du * dk / (k * k)
    dxb, d2xb = -R * s + dk, -R * c + d2k
    dth, d2th = (k * du - u * dk) / (L * L), (k * d2u - u * d2k) / (L * L)
    ga = np.array([0.5 * (-R * s + dxb), 0.5 * R * c])          # rod centre (A + B)/2, its analogues
    gaa = np.array([0.5 * (-R * c + d2xb), -0.5 * R * s])
    J = I_CRANK + M_ROD * ga @ ga + I_ROD * dth * dth + M_BLOCK * dxb * dxb
    dJ = 2.0 * (M_ROD * ga @ gaa + I_ROD * dth * d2th + M_BLOCK * dxb * d2xb)
    dV = M_ROD * G * ga[1]
    return J, dJ, dV


DC = {"kind": "dc", "stall_torque": 0.4, "no_load_speed": "3000 rpm", "gear_ratio": 4,
      "rotor_inertia": 2e-5}


def dc_at_crank(w):
    N, Ts, w0 = 4.0, 0.4, 3000 * math.pi / 30
    return N * Ts * (1 - N * w / w0)


def test_slider_crank_follows_lagranges_equation_written_by_hand():
    plan = plan_of(slider_text())
    s = assur.simulate(plan, motor=DC, cycles=10, rtol=1e-12)
    assert len(s.turns) == 10
    J_motor = 16 * 2e-5

    def f(t, y):
        J, dJ, dV = slider_terms(y[0])
        return [y[1], (dc_at_crank(y[1]) - dV - 0.5 * dJ * y[1] ** 2) / (J + J_motor)]
    ref = solve_ivp(f, (0, s.t[-1]), [s.q[0], 0.0], method="DOP853", rtol=1e-13, atol=1e-13, dense_output=True)
    assert np.max(np.abs(ref.sol(s.t)[0] - s.q)) <= 1e-8


# -- the four-bar by Lagrange's equation, written here ------------------------------------------------------
R1, R2, R3, R4 = 0.1, 0.04, 0.12, 0.08
P_DIST, P_ANGLE = 0.06, math.radians(30)


def fourbar_terms(t2):
    """J*(θ2), dJ*/dθ2, dV/dθ2 of crank_rocker.toml with FOURBAR_MASS, from the loop A + r3·e^{iθ3} = O4 +
    r4·e^{iθ4} and its first two derivatives solved by hand."""
    A = R2 * np.exp(1j * t2)
    O4 = complex(R1, 0)
    d = O4 - A
    dist = abs(d)
    along = (R3 * R3 - R4 * R4 + dist * dist) / (2 * dist)
    h = math.sqrt(R3 * R3 - along * along)
    B = A + d / dist * complex(along, h)              # B on the left of A → O4 (the sketch's open assembly)
    t3, t4 = np.angle(B - A), np.angle(B - O4)
    e2, e3, e4 = np.exp(1j * t2), np.exp(1j * t3), np.exp(1j * t4)
    # i r2 e2 + i r3 θ3' e3 = i r4 θ4' e4  →  [r3 e3, −r4 e4] [θ3', θ4'] = −r2 e2
    M = np.array([[(R3 * e3).real, (-R4 * e4).real], [(R3 * e3).imag, (-R4 * e4).imag]])
    w3, w4 = np.linalg.solve(M, [(-R2 * e2).real, (-R2 * e2).imag])
    # −r2 e2 + r3 (i θ3'' − θ3'²) e3 = r4 (i θ4'' − θ4'²) e4
    rhs = R2 * e2 + R3 * w3 * w3 * e3 - R4 * w4 * w4 * e4
    a3, a4 = np.linalg.solve(M, [(rhs / 1j).real, (rhs / 1j).imag])
    dA, d2A = 1j * R2 * e2, -R2 * e2
    u = P_DIST * np.exp(1j * (t3 + P_ANGLE))
    dP, d2P = dA + 1j * w3 * u, d2A + (1j * a3 - w3 * w3) * u
    dG2, d2G2 = 0.5 * dA, 0.5 * d2A
    dG4, d2G4 = 0.5 * 1j * w4 * R4 * e4, 0.5 * (1j * a4 - w4 * w4) * R4 * e4
    (m2, i2), (m3, i3), (m4, i4) = FOURBAR_MASS["crank"], FOURBAR_MASS["coupler"], FOURBAR_MASS["rocker"]
    dot = lambda a, b: (a.conjugate() * b).real  # noqa: E731
    J = m2 * abs(dG2) ** 2 + i2 + m3 * abs(dP) ** 2 + i3 * w3 ** 2 + m4 * abs(dG4) ** 2 + i4 * w4 ** 2
    dJ = 2 * (m2 * dot(dG2, d2G2) + m3 * dot(dP, d2P) + i3 * w3 * a3 + m4 * dot(dG4, d2G4) + i4 * w4 * a4)
    dV = G * (m2 * dG2.imag + m3 * dP.imag + m4 * dG4.imag)
    return J, dJ, dV


@pytest.mark.slow
def test_fourbar_follows_lagranges_equation_written_by_hand():
    plan = plan_of(fourbar_text())
    motor = {"kind": "dc", "stall_torque": 0.3, "no_load_speed": "120 rad/s"}
    s = assur.simulate(plan, motor=motor, cycles=10, rtol=1e-12)
    assert len(s.turns) == 10

    def f(t, y):
        J, dJ, dV = fourbar_terms(y[0])
        return [y[1], (0.3 * (1 - y[1] / 120.0) - dV - 0.5 * dJ * y[1] ** 2) / J]
    ref = solve_ivp(f, (0, s.t[-1]), [s.q[0], 0.0], method="DOP853", rtol=1e-13, atol=1e-13, dense_output=True)
    assert np.max(np.abs(ref.sol(s.t)[0] - s.q)) <= 1e-8


def test_reduced_terms_match_the_hand_written_ones():
    q = np.linspace(0.1, 6.2, 7)
    t = reduced_terms(plan_of(slider_text()), None, q)
    hand = np.array([slider_terms(x) for x in q])
    assert np.allclose(t.inertia, hand[:, 0], rtol=1e-12, atol=0)
    assert np.allclose(t.inertia_rate, hand[:, 1], rtol=1e-10, atol=1e-14)
    assert np.allclose(t.applied, -hand[:, 2], rtol=1e-10, atol=1e-13)
    t = reduced_terms(plan_of(fourbar_text()), None, q)
    hand = np.array([fourbar_terms(x) for x in q])
    assert np.allclose(t.inertia, hand[:, 0], rtol=1e-12, atol=0)
    assert np.allclose(t.inertia_rate, hand[:, 1], rtol=1e-10, atol=1e-14)
    assert np.allclose(t.applied, -hand[:, 2], rtol=1e-10, atol=1e-13)


def test_reactions_at_the_simulated_motion_satisfy_virtual_power():
    """At each sample the force analysis at (q, q̇, q̈) needs exactly the motor's torque at the crank (less what
    accelerates the rotor), and its power balances the kinetic energy's rate computed here:
    Q·q̇ + Σ m·g·v_c = Σ (m·a_c·v_c + I·α·ω)."""
    plan = plan_of(slider_text())
    s = assur.simulate(plan, motor=DC, cycles=3, rtol=1e-12, samples=400)
    f = s.forces()
    Q = f.driver[:, 0]
    expected = s.effort - 16 * 2e-5 * s.accel
    scale = np.max(np.abs(Q))
    assert np.max(np.abs(Q - expected)) <= 1e-9 * scale
    st = assur.solve(plan, None, s.q[:, None], speeds=s.speed[:, None], accels=s.accel[:, None], order=2)
    A, B = st.point("A"), st.point("B")
    vc, ac = 0.5 * (A.vel + B.vel), 0.5 * (A.acc + B.acc)
    d = B.pos - A.pos
    n2 = np.sum(d * d, axis=1)
    dv, da = B.vel - A.vel, B.acc - A.acc
    om = (d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]) / n2
    # α = d/dt ω = (d × a_rel)/|d|² − 2ω(d·v_rel)/|d|²
    al = (d[:, 0] * da[:, 1] - d[:, 1] * da[:, 0]) / n2 - 2 * om * np.sum(d * dv, axis=1) / n2
    rate = (M_ROD * np.sum(ac * vc, axis=1) + I_ROD * al * om + M_BLOCK * np.sum(B.acc * B.vel, axis=1)
            + I_CRANK * s.accel * s.speed)
    power = Q * s.speed - G * (M_ROD * vc[:, 1] + M_BLOCK * B.vel[:, 1])
    assert np.max(np.abs(power - rate)) <= 1e-9 * np.max(np.abs(rate))
    assert np.all(np.isfinite(f.reactions))


@pytest.mark.slow
def test_steady_fluctuation_against_the_kinetostatic_flywheel_estimate():
    """A flywheel sized by the kinetostatic estimate for δ = 0.05 at the steady speed: the simulated δ agrees
    within the estimate's stated approximations (order δ, and the motor's damping (c/(Iω))²)."""
    from assur.dynamics.compare import kinetostatic_estimate
    load = '[[loads]]\npoint = "B"\nforce = [-60, 0]\nopposes = "velocity"\n'
    motor = '\n[motor]\nkind = "dc"\nstall_torque = "1 N*m"\nno_load_speed = "3000 rpm"\ngear_ratio = 5\n'
    first = assur.simulate(plan_of(slider_text(motor, load)))
    e = kinetostatic_estimate(first)
    flywheel = e["energy_fluctuation"] / (0.05 * e["speed"] ** 2) - e["inertia"]
    s = assur.simulate(plan_of(slider_text(motor + f"flywheel_inertia = {flywheel!r}\n", load)))
    e = kinetostatic_estimate(s)
    assert s.steady
    assert 0.04 < e["delta_estimate"] < 0.06
    assert e["difference"] == pytest.approx(s.delta - e["delta_estimate"])
    assert abs(e["difference"]) <= e["delta_estimate"] * (e["delta_estimate"] + e["damping"] ** 2)
