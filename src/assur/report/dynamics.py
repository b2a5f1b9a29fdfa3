"""A run on the motor as text, table rows, CSV and an HTML fragment (the report's dynamics section).

Inputs in the file's units (its angle unit for a crank, its length unit for a linear input); speeds also in rpm for
a crank; forces N, torques N·m, power W, energy J, current A, time s.
"""
from __future__ import annotations

import math

import numpy as np

from .forces import input_unit, pair_label
from .text import format_number

RPM = 60.0 / (2.0 * math.pi)


def _n(v, digits: int = 5) -> str:
    return format_number(v, digits)


def motor_text(motor) -> str:
    """One line naming a motor and its parameters (SI)."""
    if motor is None:
        return "no motor (free motion)"
    k = motor.kind
    parts = {"torque": lambda m: f"constant torque {m.torque:g} N·m",
             "force": lambda m: f"constant force {m.force:g} N",
             "dc": lambda m: (f"DC, stall {m.stall_torque:g} N·m, no-load {m.no_load_speed * RPM:.5g} rpm"
                              if m.stall_torque is not None else
                              f"DC, k = {m.torque_constant:g} N·m/A, R = {m.resistance:g} Ω, V = {m.voltage:g} V"),
             "induction": lambda m: (f"induction (Kloss), breakdown {m.breakdown_torque:g} N·m at slip "
                                     f"{m.breakdown_slip:g}, synchronous {m.synchronous_speed * RPM:.5g} rpm"),
             "table": lambda m: f"{'force' if m.linear_table else 'torque'}–speed table of {len(m.table)} rows",
             "hydraulic": lambda m: (f"hydraulic, {m.pressure / 1e5:g} bar on {m.area * 1e4:g} cm², "
                                     f"{m.flow * 6e4:g} L/min")}[k](motor)
    train = []
    if motor.gear_ratio != 1.0:
        train.append(f"gear ratio {motor.gear_ratio:g}")
    if motor.lead is not None:
        train.append(f"lead {motor.lead * 1e3:g} mm")
    if motor.efficiency != 1.0:
        train.append(f"efficiency {motor.efficiency:g}")
    if motor.rotor_inertia:
        train.append(f"rotor {motor.rotor_inertia:g} kg·m²")
    if motor.flywheel_inertia:
        train.append(f"flywheel {motor.flywheel_inertia:g} kg·m²")
    return parts + (f" ({', '.join(train)})" if train else "") + f" on {motor.driver!r}"


def summary_rows(run) -> list[tuple[str, str, str]]:
    """(quantity, value, unit) rows of a :class:`~assur.dynamics.cycle.MotorRun`."""
    sim, est = run.simulation, run.estimate
    plan = sim.plan
    rotary = plan.input_kinds[0] == "rotary"
    su = "rad/s" if rotary else "m/s"
    eq = sim.equation
    rows = [("motor", motor_text(eq.drive.motor if eq.drive else None), ""),
            ("stop", sim.stop.message if sim.stop else "", ""),
            ("simulated time", _n(sim.t[-1]), "s"), ("turns", str(len(sim.turns)), "")]
    if sim.steady:
        rows.append(("start-up time (to 95 % of the steady speed)", _n(sim.startup_time), "s"))
    if sim.turns:
        w = sim.mean_speed
        rows.append(("steady mean speed" if sim.steady else "mean speed of the last turn", _n(w), su))
        if rotary:
            rows.append(("", _n(w * RPM), "rpm"))
        rows.append(("speed fluctuation δ = (max − min)/mean", _n(sim.delta), ""))
    if est is not None:
        rows += [("kinetostatic estimate of δ (ΔE / (I·ω̄²))", _n(est["delta_estimate"]), ""),
                 ("  its ΔE, I", f"{_n(est['energy_fluctuation'])} J, {_n(est['inertia'])}", "kg·m²"),
                 ("  simulated δ − estimate", _n(est["difference"], 3), ""),
                 ("  neglected motor damping c/(I·ω̄)", _n(est["damping"], 3), "")]
    if sim.effort is not None and sim.effort.size:
        eu = "N" if eq.drive.motor.pushes else "N·m"
        rows += [("peak motor " + ("force" if eq.drive.motor.pushes else "torque"),
                  _n(np.nanmax(np.abs(sim.motor_torque))), eu),
                 ("peak motor power", _n(np.nanmax(np.abs(sim.power))), "W")]
        if sim.current is not None:
            rows.append(("peak current", _n(np.nanmax(np.abs(sim.current))), "A"))
    rows += [(f"peak reaction at {k}", _n(v), "N") for k, v in run.joint_peaks().items()]
    fit = eq.fit
    if fit is not None:
        kind = type(fit.series).__name__.replace("PeriodicSeries", "Fourier series").replace("TableSeries", "table")
        rows.append(("equation's terms", f"{kind} on {fit.samples} inputs, error ≤ {_n(float(np.max(fit.error)), 2)}"
                                         " (relative, at the midpoints)", ""))
    rows.append(("integrator", f"{sim.method}, {sim.nfev} evaluations", ""))
    for note in eq.notes:
        rows.append(("note", note, ""))
    return rows


def summary_lines(run) -> list[str]:
    """The rows as aligned text lines."""
    rows = summary_rows(run)
    width = max(len(a) for a, _, _ in rows)
    return [f"  {a:<{width}}  {b} {c}".rstrip() for a, b, c in rows]


def csv_table(run) -> tuple[list[str], list[list]]:
    """(header, rows): per sample the time, the input (file units), its speed and acceleration (SI), the motor's
    effort at the input, torque, current and power, the kinetic energy, and every joint's reaction (N)."""
    sim, f = run.simulation, run.forces
    plan = sim.plan
    fac, iu = input_unit(plan)
    rotary = plan.input_kinds[0] == "rotary"
    su, au, eu = ("rad/s", "rad/s²", "N·m") if rotary else ("m/s", "m/s²", "N")
    header = ["t [s]", f"{plan.input_names[0]} [{iu}]", f"speed [{su}]", f"acceleration [{au}]"]
    cols = [sim.t, sim.q / fac, sim.speed, sim.accel]
    if sim.effort is not None:
        mu = "N" if sim.equation.drive.motor.pushes else "N·m"
        header += [f"motor effort at the input [{eu}]", f"motor torque [{mu}]", "motor power [W]"]
        cols += [sim.effort, sim.motor_torque, sim.power]
        if sim.current is not None:
            header.append("current [A]")
            cols.append(sim.current)
    header.append("kinetic energy [J]")
    cols.append(sim.kinetic)
    if f is not None:
        dim = f.reactions.shape[-1]
        for k in f.joint_pairs:
            for c in range(dim):
                header.append(f"{pair_label(f, k)} R{'xyz'[c]} [N]")
                cols.append(f.reactions[:, k, c])
    data = np.stack([np.asarray(c, dtype=float) for c in cols], axis=1)
    return header, data.tolist()


def dynamics_html(run, *, dpi: int = 80) -> str:
    """The report's dynamics section of a :class:`~assur.dynamics.cycle.MotorRun` (or of a solved cycle, run on the
    file's motor; '' without one): the summary table and the start-up figure."""
    from .page import escape, png_tag, table
    if not hasattr(run, "simulation"):
        from ..dynamics.cycle import cycle_simulation
        from ..errors import AssurError
        try:
            run = cycle_simulation(run)
        except AssurError as exc:
            return f'<p class="note">no simulation on the motor: {escape(exc)}</p>'
        if run is None:
            return ""
    rows = [(a, f"{b} {c}".strip()) for a, b, c in summary_rows(run)]
    out = [table(["run on the motor", "value"], rows, num_cols=())]
    from ..plot.draw import close, figure_png
    from ..plot.dynamics import startup_figure
    fig = startup_figure(run, dpi=dpi)
    out.append(png_tag(figure_png(fig, dpi=dpi), "speed against time at start-up beside the kinetostatic estimate; "
                                                  "the motor's torque"))
    close(fig)
    return "\n".join(out)


__all__ = ["csv_table", "dynamics_html", "motor_text", "summary_lines", "summary_rows"]
