"""Paper 002's section of docs/reproduction.md: the paper's claims against what assur computes.

``section() -> str`` is included by docs/reproduction.py. Every number is computed here from
examples/lever_manipulator.toml through the general engine (assur.solve, analysis.actuators) or
from the closed form of docs/papers/002.md §3–§4 (analysis.lever, checked against the engine in
tests/test_paper002.py). The paper prints no dimensions and no numerical results; the example is
the sharp check P002-1 of docs/papers/002.md §8 (a = 0.6 m, α = β = 53.13°, γ = 0, V1 = 0.1 m/s).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import assur
from assur.analysis.actuators import actuator_motions, rod_pairs, stroke_envelope
from assur.analysis.lever import LeverManipulator, lever_layout, paper_formulas
from assur.analysis.timelaw import ConstantSpeed, driver_law, solve_in_time

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "lever_manipulator.toml"



def _roundoff(x: float) -> str:
    """A deviation at round-off level as its decade bound ("< 1e-15"): its exact digits change with the numpy
    build and the CPU, the bound does not."""
    return f"< 1e{math.ceil(math.log10(x))}" if x > 0 else "0"

def _f(x, d=4):
    return f"{x:.{d}g}"


def rows():
    plan = assur.compile(assur.load(EXAMPLE))
    s = plan.structure
    g = lever_layout(plan).geometry
    V1 = float(plan.speeds[0])
    law = driver_law(plan)
    env = stroke_envelope(plan, law, steps=400)
    K = env.extremes[("drive_rod/driven_rod", "K_omega")]
    (k_top,) = K["interior"]
    t_foot = g.foot_stroke / V1
    foot = g.exact(np.array([g.foot_stroke]), V1)
    st = solve_in_time(plan, law, env.t)
    (pair,) = rod_pairs(st)
    mot = actuator_motions(st)
    areal_dev = float(np.nanmax(np.abs(pair.areal_ratio - g.area_ratio)))
    tri = pair.area_ratio[1:]
    # the invariant on an inclined guide with β < γ (h_A < 0), through the engine
    g2 = LeverManipulator(0.25, math.radians(70), math.radians(60), math.radians(75))
    p2 = assur.compile(g2.mechanism(speed=V1))
    s2_ = assur.solve(p2, inputs=g2.l1 + np.linspace(0.0, 1.0, 201), speeds=[V1])
    (pair2,) = rod_pairs(s2_)
    dev2 = float(np.nanmax(np.abs(pair2.areal_ratio / g2.area_ratio - 1)))
    k2 = pair2.K_omega
    v2 = -mot["driven_rod"].rate
    t = env.t
    lit = paper_formulas(g, t, V1)
    ex = g.exact(V1 * t, V1)
    dev8 = float(np.nanmax(np.abs(lit.values["psi (8)"] - ex["psi"])))
    dev9 = float(np.nanmax(np.abs(lit.values["omega_psi (9)"] / ex["omega_psi"] - 1)))
    dev15 = float(np.nanmax(np.abs(lit.values["eps_psi (15)"] / ex["eps_psi"] - 1)))
    before = ex["sigma"] < g.e_O
    dev11 = float(np.nanmax(np.abs(lit.values["phi (11)"][before] - ex["phi"][before])))
    v2_0 = float(g.exact(np.array([0.0]), V1)["V2"][0])
    frozen = paper_formulas(g, t, V1, v2_0)
    t_sing = (g.b1 - g.h_O) / v2_0               # b1 − V2·t = h_O
    sing = frozen.singular["omega_phi (12)"]
    assert np.array_equal(sing, t >= t_sing - 1e-9), "the literal mode must flag exactly t ≥ (b1 − h_O)/V2"
    lit_end = paper_formulas(g, np.array([t[-1]]), V1)
    at = np.array([1.0, 3.0])
    l14, e14 = paper_formulas(g, at, V1).values["V2 (14)"], g.exact(V1 * at, V1)["V2"]
    g16 = LeverManipulator(1.0, math.radians(60), math.radians(60), 0.0)
    e16 = g16.exact(np.array([0.0]), 0.1)
    l16 = paper_formulas(g16, np.array([0.0]), 0.1, float(e16["V2"][0])).values["eps_phi (16)"][0]
    # K_ω as a function of s1 for the paper's three speeds (E6)
    k_by_speed = []
    for v in (0.08, 0.10, 0.17):
        lw = ConstantSpeed.over(float(plan.sketch_inputs[0]), v, plan.mechanism.drivers[0].range)
        tt = (env.q - lw.start) / v
        (pp,) = rod_pairs(solve_in_time(plan, lw, tt))
        k_by_speed.append(pp.K_omega)
    dk_speed = float(max(np.nanmax(np.abs(k - k_by_speed[0])) for k in k_by_speed))
    w_psi, w_phi = mot["drive_rod"].omega, mot["driven_rod"].omega
    phi_end_11 = math.degrees(float(lit_end.values["phi (11)"][0]))
    phi_end = math.degrees(float(ex["phi"][-1]))
    return [
        ("mobility, eq. (1)", "W = 1 (n = 5, p5 = 7)",
         f"W = 3·{s.n_moving} − 2·{s.pair_counts['p5']} − {s.pair_counts['p4']} = {s.mobility}", "reproduced"),
        ("K_ω = ω_φ/ω_ψ is constant along the whole guide", "constant",
         f"K_ω = {_f(K['min'].value)} at s1 = 0, {_f(float(foot['K_omega'][0]))} at the foot of O (s1 = "
         f"{g.foot_stroke * 1000:.1f} mm, = 1 + a²/y_B0²), interior maximum {_f(k_top.value, 6)} at s1 = "
         f"{(k_top.q - g.l1) * 1000:.1f} mm, → h_O/h_A = {_f(g.area_ratio)} as s1 → ∞",
         "false for every γ (E5, docs/papers/002.md §6): K_ω = (h_O/h_A)·(L/b)²"),
        ("K_ω = 1 for the horizontal guide (Fig. 2)", "1",
         f"1 only where L = b (here at t = 0, l1 = b1); {_f(float(foot['K_omega'][0]))} at t = {t_foot:.3f} s",
         "false"),
        ("S_BOB1/S_BAB1 = 1/K_ω", "inverse of K_ω",
         f"S_BOB1/S_BAB1 = {_f(float(np.nanmin(tri)), 12)} … {_f(float(np.nanmax(tri)), 12)} (the triangles swept "
         f"since the start, {len(tri)} positions) while "
         f"1/K_ω runs {_f(1 / K['max'].value)} … {_f(1 / K['min'].value)}", "false"),
        ("what is constant", "—",
         f"the areal-velocity ratio (b²ω_φ)/(L²ω_ψ) = h_O/h_A: max deviation {areal_dev:.1e} over the stroke; "
         f"on γ = 75°, β = 60° (h_A < 0) relative deviation {dev2:.1e} while K_ω runs "
         f"{_f(float(np.nanmin(k2)))} … {_f(float(np.nanmax(k2)))}", "the paper's idea, corrected (docs/papers/002.md §6)"),
        ("V2 = const, s2 = V2·t", "constant",
         f"V2 = {_f(float(v2[0]))} m/s at t = 0, 0 at t = {t_foot:.3f} s (the foot of O), "
         f"{_f(float(v2[-1]))} m/s at t = {t[-1]:g} s", "false (E2)"),
        ("eq. (14) for V2", "V2 = b1 − A·l1·sin ψ/(C sin φ) − (A sin ψ/(C sin φ))·V1",
         f"t = 1 s: {_f(float(l14[0]))} against the true {_f(float(e14[0]))} m/s; t = 3 s: {_f(float(l14[1]))} against "
         f"{_f(float(e14[1]))} m/s", "wrong, dimensionally inconsistent (E4); V2 = V1·cos(α+γ+φ)/cos(β−γ−ψ)"),
        ("eqs. (8), (9), (15): ψ, ω_ψ, ε_ψ", "—",
         f"max deviation from the exact model over the stroke: ψ {_roundoff(dev8)} rad, ω_ψ {_roundoff(dev9)}, "
         f"ε_ψ {_roundoff(dev15)} (relative)", "exact"),
        ("eq. (11): φ(t) (with the true s2)", "—",
         f"max deviation {dev11:.1e} rad before the foot of O; at t = {t[-1]:g} s (11) gives {phi_end_11:.2f}° "
         f"against {phi_end:.2f}°", "valid only before the foot of O (E3)"),
        ("eq. (12): ω_φ with V2 frozen at V2(0)", "—",
         f"V2(0) = {_f(v2_0)} m/s: singular for t ≥ (b1 − h_O)/V2 = {t_sing:.3f} s ({int(sing.sum())} of {len(t)} "
         f"samples flagged, not evaluated) while the true ω_φ stays "
         f"finite (max {_f(env.extremes[('driven_rod', 'omega')]['max'].value)} rad/s)", "wrong (E2)"),
        ("eq. (16): ε_φ at t = 0 (α = β = 60°, γ = 0, a = 1 m, V1 = 0.1 m/s)", "—",
         f"(16) = {l16:+.4f} against the true {float(e16['eps_phi'][0]):+.5f} rad/s²", "wrong sign (E2)"),
        ("Result 3: ω_ψ > ω_φ for γ = 0", "ω_ψ > ω_φ (and, elsewhere, equal)",
         (f"here ω_φ > ω_ψ at every t > 0 (equal at t = 0, where L = b = 500 mm; L > b after): "
          if bool(np.all(w_phi[1:] > w_psi[1:])) and abs(float(w_phi[0] - w_psi[0])) < 1e-12 else
          f"ω_φ − ω_ψ ranges {_f(float(np.nanmin(w_phi - w_psi)))} … {_f(float(np.nanmax(w_phi - w_psi)))} rad/s: ")
         + "ω_ψ > ω_φ exactly while L < b", "self-contradictory (E5)"),
        ("K_ω = f(V1)", "depends on V1",
         f"K_ω(s1) for V1 = 0.08, 0.10, 0.17 m/s: max difference {dk_speed:.1e}", "false as a function of s1 (E6)"),
        ("operating range (γ = 0)", "pivot distance ≪ rod lengths",
         f"the driven rod shortens only while B travels less than x_B0 = {g.e_O * 1000:.0f} mm < a: s1 < "
         f"{g.foot_stroke * 1000:.1f} mm of the {(plan.mechanism.drivers[0].range[1] - g.l1) * 1000:.0f} mm stroke",
         "clashes with the formulas' validity (E8)"),
        ("Figs. 4–7 (ω_ψ, ω_φ, ε_ψ, ε_φ against t for V1 = 0.08, 0.10, 0.17 m/s)", "curves, no dimensions",
         "`assur report` draws them for the file's geometry (`plot.actuators.actuator_figure(plan, speeds=...)`)",
         "not comparable: no geometry printed"),
    ]


ERRATA = [
    "E1 — eq. (4) gives the guide slope k = tg γ, but the angle relations (6), (7) and A = sin(α + γ) need B to travel "
    "along (−cos γ, sin γ), slope −tg γ; docs/papers/002.md, the toolkit and `examples/lever_manipulator.toml` follow (6)/(7).",
    "E7 — the paper's \"analogues\" (9), (12), (15), (16) contain V1 or V2: they are time derivatives. assur gives both: "
    "the analogues d/ds1, d²/ds1² (`dangle_dq`, `d2angle_dq2`, `dlength_dq`) and the time derivatives (`omega`, `alpha`, "
    "`rate`), with the chain rule for a programmed V1(t) (`analysis.timelaw`).",
    "Eq. (10) and the printed forms of (8), (15), (16) are lost in the OCR; (8), (15), (16) are rebuilt by "
    "differentiation (docs/papers/002.md §5). `analysis.lever.paper_formulas` evaluates them literally, for comparison only, and "
    "reports their singularities instead of numbers.",
]


def section() -> str:
    table = _table
    return "\n".join([
        "## Paper 002 — lever manipulator with linear actuators (`examples/lever_manipulator.toml`)",
        "",
        "The paper prints no dimensions and no numerical results. The example is the sharp check P002-1 of "
        "docs/papers/002.md §8 "
        "(a = 600 mm, α = β = 53.13°, γ = 0, b1 = l1 = 500 mm, V1 = 0.1 m/s, stroke s1 = 0 … 500 mm), solved by the "
        "general engine as an ordinary mechanism file (a driven actuator A→B, a passive actuator O→B, B in a frame "
        "guide); `tests/test_paper002.py` checks its exact values to 1e-9. Errata (E1 …) are those of "
        "[`docs/papers/002.md`](papers/002.md).",
        "",
        table(rows()),
        "",
        *[f"- {e}" for e in ERRATA],
        "",
    ])


def _table(rows_):
    out = ["| claim | printed | computed by assur | verdict |", "|---|---|---|---|"]
    esc = lambda t: str(t).replace("|", "\\|")  # noqa: E731 - a literal pipe inside a cell
    out += [f"| {esc(a)} | {esc(b)} | {esc(c)} | {esc(d)} |" for a, b, c, d in rows_]
    return "\n".join(out)


if __name__ == "__main__":
    print(section())
