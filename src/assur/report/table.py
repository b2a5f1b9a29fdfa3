"""The table of ``assur solve``, planar or spatial: every point's position, velocity, acceleration and
analogues at each input, as CSV columns in SI or in the file's units, and the excerpt printed on the
terminal (the tracked point's position and speeds).
"""
from __future__ import annotations

import math

import numpy as np

from ..io.units import LENGTH


def solve_columns(plan, file_units: bool):
    """Column names of the solve CSV, the length factor kL (SI → output) and the factor of each input
    ``ik (n_inputs,)``. Per point: coordinates, velocities, accelerations (x, y[, z]), then the first and
    second analogues by each input (pair). Then per moving link (after every point's columns): a planar link's
    angle (in (−180°, 180°], or (−π, π]), angular velocity and acceleration (``.theta``, ``.omega``,
    ``.alpha``); a spatial link's angular velocity and acceleration vectors (``.omega_x`` …, ``.alpha_x`` …)."""
    u = plan.mechanism.units
    L = u.length if file_units else "m"
    kL = 1.0 / LENGTH[u.length] if file_units else 1.0
    kA = 180.0 / math.pi if file_units else 1.0
    A = "deg" if file_units else "rad"
    axes = "xyz"[:plan.dimension]
    n = plan.n_inputs
    iu = [A if plan.input_kinds[k] == "rotary" else L for k in range(n)]
    ik = [kA if plan.input_kinds[k] == "rotary" else kL for k in range(n)]
    cols = [f"{plan.input_names[k]}.q [{iu[k]}]" for k in range(n)] + ["valid"]
    for p in plan.point_names:
        cols += [f"{p}.{c} [{L}]" for c in axes] + [f"{p}.v{c} [{L}/s]" for c in axes]
        cols += [f"{p}.a{c} [{L}/s^2]" for c in axes]
        for k in range(n):
            sfx = "" if n == 1 else f"_{plan.input_names[k]}"
            cols += [f"{p}.d{c}_dq{sfx} [{L}/{iu[k]}]" for c in axes]
        for i in range(n):
            for j in range(i, n):
                if n == 1:
                    cols += [f"{p}.d2{c}_dq2 [{L}/{iu[0]}^2]" for c in axes]
                else:
                    den = f"{iu[i]}^2" if iu[i] == iu[j] else f"({iu[i]}·{iu[j]})"
                    cols += [f"{p}.d2{c}_dq_{plan.input_names[i]}_dq_{plan.input_names[j]} [{L}/{den}]"
                             for c in axes]
    for b in plan.body_names[1:]:
        if plan.dimension == 2:
            cols += [f"{b}.theta [{A}]", f"{b}.omega [{A}/s]", f"{b}.alpha [{A}/s^2]"]
        else:
            cols += [f"{b}.omega_{c} [{A}/s]" for c in axes] + [f"{b}.alpha_{c} [{A}/s^2]" for c in axes]
    return cols, kL, ik


def solve_table(plan, q, state, file_units: bool) -> np.ndarray:
    """(n, n_columns) values of the solve CSV at inputs ``q (n, n_inputs)`` (see :func:`solve_columns`);
    a row that cannot be assembled is NaN but for its inputs and ``valid``."""
    cols, kL, ik = solve_columns(plan, file_units)
    n = plan.n_inputs
    rows = len(q)
    blocks = [q * np.asarray(ik)[None, :], state.valid.astype(float)[:, None]]
    pos, vel, acc = state.pos, state.vel, state.acc
    d1, d2 = state.dpos_dq, state.d2pos_dq2
    for pi in range(plan.n_points):
        blocks += [pos[:, pi] * kL, vel[:, pi] * kL, acc[:, pi] * kL]
        for k in range(n):
            blocks.append(d1[:, pi, :, k] * kL / ik[k])
        for i in range(n):
            for j in range(i, n):
                blocks.append(d2[:, pi, :, i, j] * kL / (ik[i] * ik[j]))
    kA = 180.0 / math.pi if file_units else 1.0
    if plan.dimension == 2:
        blocks += [np.stack([state.body_angle[:, b], state.body_omega[:, b], state.body_alpha[:, b]], axis=-1) * kA
                   for b in range(1, plan.n_bodies)]
    else:
        blocks += [np.concatenate([state.body_omega[:, b], state.body_alpha[:, b]], axis=-1) * kA
                   for b in range(1, plan.n_bodies)]
    out = np.concatenate([np.asarray(b, dtype=float).reshape(rows, -1) for b in blocks], axis=1)
    out[~state.valid, n + 1:] = np.nan
    return out


def excerpt(plan, state, table, point: str, file_units: bool):
    """The terminal excerpt of a solve table: (column heads, ``row(r)`` → the values of row r): the inputs,
    ``valid``, the coordinates of ``point`` and its speed and acceleration magnitudes."""
    u = plan.mechanism.units
    L = u.length if file_units else "m"
    kL = 1.0 / LENGTH[u.length] if file_units else 1.0
    fi = plan.point_index(point)
    iu = [("°" if file_units else "rad") if k == "rotary" else L for k in plan.input_kinds]
    heads = ([f"{n} [{v}]" for n, v in zip(plan.input_names, iu)] + ["valid"]
             + [f"{point}.{c} [{L}]" for c in "xyz"[:plan.dimension]] + [f"|v| [{L}/s]", f"|a| [{L}/s²]"])

    def magnitude(v):
        return float(np.hypot(*(v * kL))) if plan.dimension == 2 else float(np.linalg.norm(v)) * kL

    def row(r):
        return (list(table[r, :plan.n_inputs]) + [int(state.valid[r])] + list(state.pos[r, fi] * kL)
                + [magnitude(state.vel[r, fi]), magnitude(state.acc[r, fi])])
    return heads, row


def excerpt_lines(heads, row, n_rows: int, all_in_csv: bool) -> list[str]:
    """The excerpt as text: every row up to 10, else 8 spread over the run, then how many were shown
    (``all_in_csv``: the full table goes to a CSV file)."""
    width = [max(11, len(h) + 1) for h in heads]
    out = ["".join(f"{h:>{w}}" for h, w in zip(heads, width))]
    rows_at = range(n_rows) if n_rows <= 10 else np.unique(np.linspace(0, n_rows - 1, 8).round().astype(int))
    for r in rows_at:
        cells = [str(v) if isinstance(v, int) else ("nan" if not np.isfinite(v) else f"{v:.5g}") for v in row(r)]
        out.append("".join(f"{c:>{w}}" for c, w in zip(cells, width)))
    if n_rows > 10:
        out.append(f"({len(rows_at)} of {n_rows} rows shown" + (")" if all_in_csv else ", all points in --csv)"))
    return out


def cell(v: float) -> str:
    """A CSV cell: an integral value as an integer, else the shortest round-trip text; 'nan'."""
    if math.isnan(v):
        return "nan"
    if v == int(v) and abs(v) < 1e15:
        return str(int(v)) if v != 0 or math.copysign(1, v) > 0 else "0"
    return repr(float(v))


def write_csv(path, cols, table) -> None:
    """Write the solve table atomically: the column names, then one line per row."""
    from ..io.output import atomic_file
    with atomic_file(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(",".join(cols) + "\n")
            for line in table:
                fh.write(",".join(cell(v) for v in line) + "\n")
