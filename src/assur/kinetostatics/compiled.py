"""The compiled force backend: a plan's force solve as one straight-line numba loop, traced from :mod:`.kernel`.

The kernel's functions are run once in Python on symbols (the package's tracer, :mod:`assur.kernels.trace`, which
also traces the kinematics kernels): every arithmetic operation on them appends one line of source, and the
program's tables (which only ever decide the branches) are read as plain numbers. The result is the plan's force
solve as straight-line scalar code with every table look-up resolved — the same formulas as the numpy backend, from
the same text — which :mod:`assur.kernels.codegen` wraps with the prologue every kernel shares, and which numba
compiles once per plan and keeps in its disk cache beside the kinematics' kernels.

It covers programs without a generic group, with constant loads and without friction
(:attr:`Program.compiled_ok`); :func:`assur.forces` uses the numpy backend for the rest.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from ..kernels import codegen
from ..kernels.codegen import available  # noqa: F401  (the backend's public name)
from ..kernels.trace import SAMPLE, C, Tracer, isfinite, source
from . import kernel as K

_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def generate_source(prog, n_points: int, n_params: int, n_inputs: int) -> str:
    """The numba source of ``kernel(pos, vel, acc, P, pdiv, pmod, reac, slides, frame, driver, cond)``: per
    sample s, the parameters P[(s // pdiv) % pmod], the outputs as :func:`.kernel.outputs` writes them, and the
    condition measure (NaN where an unknown is not finite). Arrays are sample-last (structure of arrays, the
    layout of the compiled kinematics): ``pos (n_points, 2, N)``, ``reac (n_pairs, 2, N)``, ``frame (3, N)`` …"""
    tr = Tracer()
    z, v, a = [], [], []
    for i in range(n_points):
        for arr, name in ((z, "pos"), (v, "vel"), (a, "acc")):
            arr.append(C(tr.load(f"{name}[{i}, 0, s]", SAMPLE), tr.load(f"{name}[{i}, 1, s]", SAMPLE)))
    p = [tr.load(f"P[r, {k}]", SAMPLE) for k in range(n_params)]
    nb = prog.ang.shape[0]
    orient, omega, alpha = [C(1.0, 0.0)] * nb, [0.0] * nb, [0.0] * nb
    F, M = [C(0.0, 0.0)] * nb, [0.0] * nb
    lam = [0.0] * prog.n_unknowns
    K.body_motion(prog.ang_order, prog.ang, prog.ang_param, prog.ang_off, z, v, a, p, orient, omega, alpha)
    K.mass_loads(prog.massive, prog.mass, prog.inertia, prog.idef, prog.ipts, prog.cpts, prog.cw, prog.coff,
                 prog.gravity, z, v, a, orient, omega, alpha, F, M)
    K.point_loads(prog.lpts, prog.lforce, prog.torque, z, F, M)
    conds = []
    for g in range(prog.gr.shape[0]):
        code = prog.gr[g, K.GR_CODE]
        if code == K.G_CRANK:
            conds.append(K.crank(prog.gr, g, prog.gb, prog.pr, prog.ln, z, p, orient, F, M, lam))
        elif code == K.G_INNER_R:
            conds.append(K.inner_revolute(prog.gr, g, prog.gb, prog.gd, prog.pr, prog.ln, z, p, orient, F, M, lam))
        elif code == K.G_INNER_P:
            conds.append(K.inner_slide(prog.gr, g, prog.gb, prog.gd, prog.pr, prog.ln, z, p, orient, F, M, lam))
        else:
            raise ValueError("a generic group has no compiled form")
    n_pairs = prog.pr.shape[0]
    n_slides = int(np.sum(prog.slide_of >= 0))
    reac, slides = np.empty((n_pairs, 2), object), np.empty((n_slides, 2), object)
    frame, driver = np.zeros(3, object), np.empty(n_inputs, object)
    K.outputs(prog.pr, prog.ln, prog.drv, prog.sense, prog.slide_of, z, p, orient, lam, reac, slides, frame, driver)
    stores = [(f"reac[{k}, {j}, s]", reac[k, j]) for k in range(n_pairs) for j in range(2)]
    stores += [(f"slides[{k}, {j}, s]", slides[k, j]) for k in range(n_slides) for j in range(2)]
    stores += [(f"frame[{j}, s]", frame[j]) for j in range(3)]
    stores += [(f"driver[{i}, s]", driver[i]) for i in range(n_inputs)]
    finite = True
    for x in lam:
        finite = finite & isfinite(x)
    values = [x for _, x in stores] + conds + [finite]
    i8 = " " * 8
    body = ["    r = 0", "    left = pdiv", "    for s in range(pos.shape[2]):", "        if left == 0:",
            "            left = pdiv", "            r = r + 1 if r + 1 < pmod else 0", "        left -= 1",
            *codegen.lines_at(tr, values, SAMPLE, i8), *[f"{i8}{target} = {source(x)}" for target, x in stores],
            f"{i8}c = 1.0"]
    for c in conds:
        body.append(f"{i8}c = c if {source(c)} >= c else {source(c)}")
    body.append(f"{i8}cond[s] = c if {source(finite)} else math.nan")
    return codegen.module("assur.kinetostatics.compiled.generate_source",
                          "pos, vel, acc, P, pdiv, pmod, reac, slides, frame, driver, cond", body)


def _kernel(plan, prog):
    k = _KERNELS.get(plan)
    if k is None:
        k = _KERNELS[plan] = codegen.load(generate_source(prog, plan.n_points, plan.n_params, plan.n_inputs),
                                          "a force kernel")
    return k


def kernel_ready(plan, prog) -> bool:
    """True when the plan's force kernel runs without a compile (compiled in this process or in the disk cache)."""
    if not available():
        return False
    return codegen.ready(_kernel(plan, prog))


def _param_rows(params, shape, n_params):
    """(P (rows, n_params), pdiv, pmod): the parameters of sample s are P[(s // pdiv) % pmod]."""
    params = np.asarray(params, dtype=float)
    lead = params.shape[:-1]
    n = math.prod(shape)
    if math.prod(lead) == 1:
        return np.ascontiguousarray(params.reshape(1, n_params)), 1, 1
    lead = (1,) * (len(shape) - len(lead)) + lead
    for k in range(len(shape) + 1):
        if lead[:k] == shape[:k] and all(x == 1 for x in lead[k:]):
            rows = math.prod(shape[:k])
            return np.ascontiguousarray(params.reshape(rows, n_params)), n // rows, rows
    full = np.broadcast_to(params, shape + (n_params,)).reshape(n, n_params)
    return np.ascontiguousarray(full), 1, n


def solve_compiled(prog, state, *, required: bool = False):
    """The flat result arrays (reac (N, n_pairs, 2), slides (N, n_slides, 2), frame (N, 3), driver (N, n_inputs),
    cond (N,), finite (N, 1); views of sample-last arrays) of the samples of ``state``; None where numba is
    missing and not required."""
    if not (required or available()):
        return None
    plan = state.plan
    kern = _kernel(plan, prog)
    shape = state.shape
    n = math.prod(shape)

    def soa(x):
        """(..., n_points, 2) → (n_points, 2, N): a view for the compiled kinematics' own layout."""
        return np.reshape(np.moveaxis(x, (-2, -1), (0, 1)), x.shape[-2:] + (n,))

    P, pdiv, pmod = _param_rows(state.params, shape, plan.n_params)
    n_pairs, n_slides = prog.pr.shape[0], int(np.sum(prog.slide_of >= 0))
    reac, slides = np.empty((n_pairs, 2, n)), np.empty((n_slides, 2, n))
    frame, driver, cond = np.empty((3, n)), np.empty((plan.n_inputs, n)), np.empty(n)
    kern(soa(state.pos), soa(state.vel), soa(state.acc), P, pdiv, pmod, reac, slides, frame, driver, cond)
    reac, slides = np.moveaxis(reac, -1, 0), np.moveaxis(slides, -1, 0)
    frame, driver = frame.T, driver.T
    return reac, slides, frame, driver, cond, np.isfinite(cond)[:, None]
