"""Source generation of the compiled (numba) kernels: a plan's closed forms fused into one loop.

The numpy backend evaluates each group on whole arrays of jets; this backend generates, per plan,
a straight-line numba function (``generate_source``) that runs the same closed forms sample by
sample in native code, with every jet held in registers as a tuple:
a complex jet is ``(x, y, dx, dy, ddx, ddy)``, a real jet ``(v, d, dd)`` (derivatives by the
single input q). It is numerically the same computation (tests compare the two backends).

Op table rows (int64, width ``OP_WIDTH``); slots index the per-design complex constants
``G (n_designs, n_slots, 2)``:

====  =========  =============================================================================
code  name       operands
====  =========  =============================================================================
0     FRAMEPT    point, slot                      P[point] = G[slot]
1     CRANK      body, pivot, slot_w_pivot, sense, slot_k (= exp(i·zero)·conj(unit(arm − pivot)))
2     PLACE      body, point, slot_w              P[point] = O[body] + E[body]·w
3     FROM_TWO   body, p1, p2, slot_w1, slot_inv  E = (P2 − P1)·inv, O = P1 − E·w1
4     RRR        A, slot_rA, B, slot_rB, J, branch
5     RRP        A, slot_rA, guide, slot_q, slot_u, slot_k, slot_off, J, branch, slider, slot_wJ
6     RPR        guide, gp, slider, sp, slot_wg, slot_c, slot_invu, slot_invus, slot_ws, branch
====  =========  =============================================================================
"""
from __future__ import annotations

OP_WIDTH = 14
#: output rows written per vectorised loop of a generated kernel (more defeats LLVM's vectoriser)
STREAMS = 12
FRAMEPT, CRANK, PLACE, FROM_TWO, RRR, RRP, RPR = range(7)


# -- straight-line kernels generated per plan ----------------------------------------------------

#: a group's shortfall past its toggle, summed per sample (NaN margins — a group fed by one that
#: failed — add nothing); kernels that do not read ``deficit`` have it removed by LLVM
DEFICIT = "deficit += -margin if margin < 0.0 else 0.0"


def _program(ops):
    """The straight-line body of one sample for an op table: (slots {slot: variable}, lines)."""
    slots: dict[int, str] = {}

    def k(sl: int) -> str:
        """The constant of slot ``sl`` as an (x, y) tuple variable, loaded once per design run."""
        slots[sl] = f"k{sl}"
        return f"k{sl}"

    body = []
    for row in ops:
        code = int(row[0])
        o = [int(x) for x in row]
        if code == FRAMEPT:
            body.append(f"P{o[1]} = ({k(o[2])}[0], {k(o[2])}[1], 0.0, 0.0, 0.0, 0.0)")
        elif code == CRANK:
            b, pivot, sw, sense, sk = o[1], o[2], o[3], o[4], o[5]
            body.append(f"E{b} = crank(c, s, {float(sense)!r}, {k(sk)})")
            body.append(f"O{b} = csub(P{pivot}, cmulk(E{b}, {k(sw)}[0], {k(sw)}[1]))")
        elif code == PLACE:
            b, p, sw = o[1], o[2], o[3]
            body.append(f"P{p} = cadd(O{b}, cmulk(E{b}, {k(sw)}[0], {k(sw)}[1]))")
        elif code == FROM_TWO:
            b, p1, p2, sw1, sinv = o[1], o[2], o[3], o[4], o[5]
            body.append(f"E{b} = cmulk(csub(P{p2}, P{p1}), {k(sinv)}[0], {k(sinv)}[1])")
            body.append(f"O{b} = csub(P{p1}, cmulk(E{b}, {k(sw1)}[0], {k(sw1)}[1]))")
        elif code == RRR:
            body.append(f"P{o[5]}, good, margin = rrr(P{o[1]}, P{o[3]}, {k(o[2])}[0], {k(o[4])}[0], "
                        f"{float(o[6])!r}, tol)")
            body.append("ok = ok & good")
            body.append(DEFICIT)
        elif code == RRP:
            A, sra, gb, sq_, su, sk, soff, J, branch, sb, swj = o[1:12]
            body.append(f"P{J}, E{sb}, good, margin = rrp(P{A}, {k(sra)}[0], O{gb}, E{gb}, {k(sq_)}, {k(su)}, "
                        f"{k(sk)}, {k(soff)}, {float(branch)!r}, tol)")
            body.append("ok = ok & good")
            body.append(DEFICIT)
            body.append(f"O{sb} = csub(P{J}, cmulk(E{sb}, {k(swj)}[0], {k(swj)}[1]))")
        elif code == RPR:
            gb, gp, sb, sp, swg, sc, sinvu, sinvus, sws, branch = o[1:11]
            body.append(f"eu, good, margin = rpr(P{gp}, P{sp}, {k(sc)}[0], {k(sc)}[1], {float(branch)!r}, tol)")
            body.append("ok = ok & good")
            body.append(DEFICIT)
            body.append(f"E{gb} = cmulk(eu, {k(sinvu)}[0], {k(sinvu)}[1])")
            body.append(f"O{gb} = csub(P{gp}, cmulk(E{gb}, {k(swg)}[0], {k(swg)}[1]))")
            body.append(f"E{sb} = cmulk(eu, {k(sinvus)}[0], {k(sinvus)}[1])")
            body.append(f"O{sb} = csub(P{sp}, cmulk(E{sb}, {k(sws)}[0], {k(sws)}[1]))")
        else:  # pragma: no cover - the packer emits only the codes above
            raise ValueError(f"unknown op code {code}")
    return slots, body


def _loads(slots) -> list[str]:
    """Lines loading a design's constants once per design."""
    return [f"{var} = (G[d, {sl}, 0], G[d, {sl}, 1])" for sl, var in sorted(slots.items())]


def _frame_lines(ops, body) -> list[str]:
    """The body lines that place frame points (constants of a design)."""
    frame_points = {int(row[1]) for row in ops if int(row[0]) == FRAMEPT}
    return [ln for ln in body if ln.split(" = ", 1)[0].strip() in {f"P{p}" for p in frame_points}]


def generate_source(ops, point_out, body_out, order: int = 2) -> str:
    """Python source of a fused, straight-line, branchless numba kernel for one op table.

    ``kernel(G, cq, sq, tol, w1, w2, w3, out, valid)`` solves every design d of ``G (D, n_slots, 2)``
    (its constants loaded once) at every input u whose cosine and sine are ``cq[u]``, ``sq[u]``
    (computed once per input by numpy). It writes ``out (6·n_out, D, N)``: x, y of the value, of
    ``w1·d/dq`` and of ``w2·d²/dq² + w3·d/dq`` for the requested points, then bodies' exp(iθ) —
    with (w1, w2, w3) = (ω, ω², α) position, velocity and acceleration, with (1, 1, 0) the analogues.
    The inner loop is branchless with rows contiguous in u, so LLVM vectorises it. With ``order``
    < 2 the rows of the higher derivatives are not written (LLVM then drops their arithmetic). A sample whose group cannot be
    assembled gets ``valid[i] = False`` (its numbers are meaningless: the caller NaNs them).
    """
    slots, body = _program(ops)
    names = [f"P{int(p)}" for p in point_out] + [f"E{int(b)}" for b in body_out]
    frame_points = {int(row[1]) for row in ops if int(row[0]) == FRAMEPT}
    checks = [f"ok = ok & ({n}[0] - {n}[0] == 0.0) & ({n}[1] - {n}[1] == 0.0)"   # finite, or not valid
              for n, p in zip(names, point_out) if int(p) not in frame_points]
    constant_rows, moving_rows = [], []
    for m, name in enumerate(names):
        is_frame = m < len(point_out) and int(point_out[m]) in frame_points
        for xy in (0, 1):
            rows = [(6 * m + xy, f"{name}[{xy}]"), (6 * m + 2 + xy, f"{name}[{2 + xy}] * w1"),
                    (6 * m + 4 + xy, f"{name}[{4 + xy}] * w2 + {name}[{2 + xy}] * w3")][: order + 1]
            (constant_rows if is_frame else moving_rows).extend(rows)
    loads = _loads(slots)
    frame_body = _frame_lines(ops, body)
    i8 = " " * 8
    lines = [
        '"""Generated by assur.kernels.codegen.generate_source; do not edit."""',
        "from numba import njit",
        "from assur.kernels.compiled import cadd, csub, cmulk, crank, rrr, rrp, rpr",
        "",
        "",
        '@njit(cache=True, error_model="numpy", fastmath={"contract"})',
        "def kernel(G, cq, sq, tol, w1, w2, w3, out, valid):",
        "    E0 = (1.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    O0 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    for d in range(G.shape[0]):",
        *["        " + ln for ln in loads],
        # frame points are constants of the design: fill their rows once
        *["        " + ln for ln in frame_body],
    ]
    for row, expr in constant_rows:
        lines += [f"{i8}value = {expr}", f"{i8}for u in range(cq.shape[0]):", f"{i8}    out[{row}, d, u] = value"]
    # the moving points: LLVM vectorises a loop only with few store streams, so write at most
    # STREAMS rows per loop (each loop recomputes the cheap straight-line body)
    groups = [moving_rows[i:i + STREAMS] for i in range(0, len(moving_rows), STREAMS)] or [[]]
    for k, group in enumerate(groups):
        lines += [
            "        for u in range(cq.shape[0]):",
            f"{i8}    c = cq[u]",
            f"{i8}    s = sq[u]",
            f"{i8}    ok = True",
            f"{i8}    deficit = 0.0",
            *[i8 + "    " + ln for ln in body],
            *[i8 + f"    out[{row}, d, u] = {expr}" for row, expr in group],
        ]
        if k == 0:
            lines += [i8 + "    " + ln for ln in checks] + [f"{i8}    valid[d, u] = ok"]
    lines.append("")
    return "\n".join(lines)


def _helpers_stamp() -> str:
    """A comment line naming the digest of :mod:`assur.kernels.compiled`, the helpers every generated kernel calls:
    numba's disk cache does not follow a callee's changes, so a changed helper must change the kernel's source."""
    global _STAMP
    if _STAMP is None:
        import hashlib
        from pathlib import Path
        text = (Path(__file__).with_name("compiled.py")).read_bytes()
        _STAMP = f"# helpers: assur.kernels.compiled sha1 {hashlib.sha1(text).hexdigest()[:16]}\n"
    return _STAMP


_STAMP = None


def load_kernel(source: str, cache_dir):
    """Import a generated kernel module from ``cache_dir`` (written once per distinct source, so
    numba's on-disk cache is reused across processes; the source carries the helpers' digest,
    :func:`_helpers_stamp`)."""
    import hashlib
    import importlib.util
    import os
    from pathlib import Path
    source = _helpers_stamp() + source
    digest = hashlib.sha1(source.encode()).hexdigest()[:16]
    name = f"assur_kernel_{digest}"
    path = Path(cache_dir) / f"{name}.py"
    if not path.exists() or path.read_text(encoding="utf-8") != source:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(source, encoding="utf-8")
        tmp.replace(path)
    import sys
    if name in sys.modules:
        return sys.modules[name].kernel
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module   # numba's cache re-imports the module by name
    spec.loader.exec_module(module)
    return module.kernel


def _cycle_loop(body, count: str, before=(), after=()) -> list[str]:
    """The loop of a design's kernel over the cycle samples (cosines ``cq``, sines ``sq``): it counts the samples
    that do not assemble (``cbad``) and sums the groups' shortfall past their toggles (``shortfall``).
    ``before``: lines (indented) run once before the loop; ``after``: lines run inside it after each sample."""
    i8, i12 = " " * 8, " " * 12
    return [f"{i8}cbad = 0", f"{i8}shortfall = 0.0", *before, f"{i8}for u in range({count}):", f"{i12}c = cq[u]",
            f"{i12}s = sq[u]", f"{i12}ok = True", f"{i12}deficit = 0.0", *[i12 + ln for ln in body],
            f"{i12}cbad += 0 if ok else 1", f"{i12}shortfall += deficit", *[i12 + ln for ln in after]]


def generate_objective_source(ops, point: int) -> str:
    """Python source of a fused numba kernel that reduces a path-synthesis objective per design.

    ``kernel(G, tc, ts, txy, cq, sq, tol, out)``: for every design d of ``G (D, n_slots, 2)``, solve
    point ``point`` at the design's target inputs (cosines/sines ``tc, ts`` (D or 1, N)) and sum the
    squared and the plain distances to ``txy (N, 2)``; then count the inputs of ``cq, sq (M,)`` (the
    whole cycle, M may be 0) at which a group cannot be assembled (a point of groups that assemble
    with finite constants is finite, so only the groups' own tests run there), and sum the groups'
    shortfalls past their toggles over the cycle (a smooth measure of how far from buildable). ``out (D, 4)`` gets
    (Σ squared distance, Σ distance, targets not assembled, cycle samples not assembled). Nothing per
    sample is stored, so the cost is the arithmetic alone (LLVM drops the unused derivative parts).
    """
    slots, body = _program(ops)
    P = f"P{int(point)}"
    i8, i12 = " " * 8, " " * 12
    lines = [
        '"""Generated by assur.kernels.codegen.generate_objective_source; do not edit."""',
        "import math",
        "from numba import njit",
        "from assur.kernels.compiled import cadd, csub, cmulk, crank, rrr, rrp, rpr",
        "",
        "",
        # reassoc lets LLVM vectorise the sums over the inputs (their order is fixed by the input count,
        # so a design's sums never depend on the batch it is evaluated in)
        '@njit(cache=True, error_model="numpy", fastmath={"contract", "reassoc"})',
        "def kernel(G, tc, ts, txy, cq, sq, tol, out):",
        "    E0 = (1.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    O0 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    per = 1 if tc.shape[0] > 1 else 0",
        "    for d in range(G.shape[0]):",
        *[i8 + ln for ln in _loads(slots)],
        *[i8 + ln for ln in _frame_lines(ops, body)],
        f"{i8}e2sum = 0.0",
        f"{i8}esum = 0.0",
        f"{i8}bad = 0.0",
        f"{i8}for u in range(tc.shape[1]):",
        f"{i12}c = tc[d * per, u]",
        f"{i12}s = ts[d * per, u]",
        f"{i12}ok = True",
        f"{i12}deficit = 0.0",
        *[i12 + ln for ln in body],
        f"{i12}dx = {P}[0] - txy[u, 0]",
        f"{i12}dy = {P}[1] - txy[u, 1]",
        f"{i12}e2 = dx * dx + dy * dy",
        f"{i12}ok = ok & (e2 - e2 == 0.0)",
        f"{i12}e2sum += e2 if ok else 0.0",
        f"{i12}esum += math.sqrt(e2) if ok else 0.0",
        f"{i12}bad += 0.0 if ok else 1.0",
        *_cycle_loop(body, "cq.shape[0]"),
        f"{i8}out[d, 0] = e2sum",
        f"{i8}out[d, 1] = esum",
        f"{i8}out[d, 2] = bad",
        f"{i8}out[d, 3] = cbad",
        f"{i8}out[d, 4] = shortfall",
        "",
    ]
    return "\n".join(lines)


#: columns of the cycle kernel's output (``generate_cycle_source``); the path distances follow from PATH_COLUMN
CYCLE_COLUMNS = ("unassembled", "shortfall", "transmission", "gait.step", "gait.lift", "gait.sag", "gait.duty",
                 "gait.speed_mean", "gait.speed_spread", "gait.vx_spread", "gait.vx_spread_90", "gait.top")
PATH_COLUMN = len(CYCLE_COLUMNS)


def generate_cycle_source(ops, foot: int = -1, path: int = -1, rrr=()) -> str:
    """Python source of a fused numba kernel that reduces the whole-cycle quantities of each design.

    ``kernel(G, cq, sq, tol, g, up, omega, scale, txy, out)``: for every design d of ``G (D, n_slots, 2)``,
    solve the plan at the M inputs of ``cq, sq (M,)`` (cosines and sines of one uniform turn) and write
    ``out[d]`` (columns :data:`CYCLE_COLUMNS`, then one per target of ``txy (N, 2)``):

    - the number of samples at which a group cannot be assembled and the sum of the groups' shortfalls past
      their toggles (as :func:`generate_objective_source`);
    - with ``rrr`` ((A, J, B) point indices of each RRR dyad): the smallest transmission angle over the
      assembled samples, folded to [0, π/2]: the arctangent of the smallest |cross|/|dot| of J→A and J→B
      (monotone in the angle, so one arctangent per design), NaN when no sample assembles;
    - with ``foot`` ≥ 0 (a point index): the sampled gait terms of :func:`assur.kernels.compiled.gait_reduce`
      of the foot's stride ``x = P·g·scale``, height ``v = P·up·scale`` and speed ``|dP/dq|·omega·scale``;
    - with ``path`` ≥ 0: the distance of each target to the closed polyline of that point's samples.

    Gait terms and distances are NaN for a design with an unassembled sample (as the sampled numpy forms).
    Only a few samples per design are stored (scratch arrays of M values reused for every design).
    """
    slots, body = _program(ops)
    i8, i12 = " " * 8, " " * 12
    sample = []
    for a, j, b in rrr:
        sample += [f"ax = P{a}[0] - P{j}[0]", f"ay = P{a}[1] - P{j}[1]",
                   f"bx = P{b}[0] - P{j}[0]", f"by = P{b}[1] - P{j}[1]",
                   "tc = abs(ax * by - ay * bx)", "td = abs(ax * bx + ay * by)",
                   # tan of the folded angle (0/0, J on A or B: 0; an unassembled sample: +inf)
                   "tr = tc / td if tc > 0.0 else 0.0",
                   "tr = tr if ok else math.inf",
                   "ft[u] = tr if tr < ft[u] else ft[u]"]
    if foot >= 0:
        F = f"P{int(foot)}"
        sample += [f"fx[u] = ({F}[0] * g[0] + {F}[1] * g[1]) * scale",
                   f"fv[u] = ({F}[0] * up[0] + {F}[1] * up[1]) * scale",
                   f"fs[u] = math.sqrt({F}[2] * {F}[2] + {F}[3] * {F}[3]) * omega * scale",
                   f"fw[u] = ({F}[2] * g[0] + {F}[3] * g[1]) * omega * scale"]
    if path >= 0:
        sample += [f"px[u] = P{int(path)}[0]", f"py[u] = P{int(path)}[1]"]
    lines = [
        '"""Generated by assur.kernels.codegen.generate_cycle_source; do not edit."""',
        "import math",
        "import numpy as np",
        "from numba import njit",
        "from assur.kernels.compiled import cadd, csub, cmulk, crank, rrr, rrp, rpr, gait_reduce, polyline_distance",
        "",
        "",
        # reassoc lets LLVM vectorise the sums and the minimum over the samples (their order is fixed by M, so a
        # design's values never depend on the batch it is evaluated in)
        '@njit(cache=True, error_model="numpy", fastmath={"contract", "reassoc"})',
        "def kernel(G, cq, sq, tol, g, up, omega, scale, txy, out):",
        "    E0 = (1.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    O0 = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)",
        "    M = cq.shape[0]",
        "    fx = np.empty(M)",
        "    fv = np.empty(M)",
        "    fs = np.empty(M)",
        "    fw = np.empty(M)",
        "    px = np.empty(M)",
        "    py = np.empty(M)",
        "    ft = np.empty(M)",
        "    for d in range(G.shape[0]):",
        *[i8 + ln for ln in _loads(slots)],
        *[i8 + ln for ln in _frame_lines(ops, body)],
        *_cycle_loop(body, "M", before=[f"{i8}ft[:] = math.inf"] if rrr else [], after=sample),
        f"{i8}out[d, 0] = cbad",
        f"{i8}out[d, 1] = shortfall",
        f"{i8}tmin = math.inf",
        *([f"{i8}for u in range(M):", f"{i12}tmin = min(tmin, ft[u])"] if rrr else []),
        f"{i8}out[d, 2] = math.atan(tmin) if cbad < M else math.nan",
        f"{i8}for k in range(3, out.shape[1]):",
        f"{i12}out[d, k] = math.nan",
        f"{i8}if cbad == 0:",
    ]
    if foot >= 0:
        lines.append(f"{i12}gait_reduce(fx, fv, fs, fw, out, d, 3)")
    if path >= 0:
        lines.append(f"{i12}polyline_distance(px, py, txy, out, d, {PATH_COLUMN})")
    lines += [f"{i12}pass", ""]
    return "\n".join(lines)
