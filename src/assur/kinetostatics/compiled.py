"""The compiled force backend: a plan's force solve as one straight-line numba loop, traced from :mod:`.kernel`.

The kernel's functions are run once in Python on *symbolic* values (:class:`Sym`): every arithmetic
operation on them appends one line of source, and the program's tables (which only ever decide the
branches) are read as plain numbers. The result is the plan's force solve as straight-line scalar code
with every table look-up resolved — the same formulas as the numpy backend, from the same text — which
numba compiles once per plan and keeps in its disk cache beside the kinematics' kernels.

It covers programs without a generic group, with constant loads and without friction
(:attr:`Program.compiled_ok`); :func:`assur.forces` uses the numpy backend for the rest.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from . import kernel as K

_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


class Tracer:
    """Collects the lines of the traced source and numbers its temporaries."""

    def __init__(self):
        self.lines: list[str] = []
        self.count = 0

    def emit(self, expr: str, kind: str) -> "Sym":
        name = f"t{self.count}"
        self.count += 1
        self.lines.append(f"{name} = {expr}")
        return Sym(self, name, kind)


def _lit(x) -> str:
    """A number as source (complex, float; nan and inf spelled for numba)."""
    if isinstance(x, (complex, np.complexfloating)):
        x = complex(x)
        return f"complex({_lit(x.real)}, {_lit(x.imag)})"
    x = float(x)
    if math.isnan(x):
        return "np.nan"
    if math.isinf(x):
        return "np.inf" if x > 0 else "-np.inf"
    return repr(x)


def _kind(*xs) -> str:
    return "c" if any((isinstance(x, Sym) and x.kind == "c") or isinstance(x, (complex, np.complexfloating))
                      for x in xs) else "r"


class Sym:
    """A symbolic scalar (kind 'r' real or 'c' complex): operations append source lines to the tracer."""
    __array_priority__ = 1000

    def __init__(self, tracer: Tracer, name: str, kind: str):
        self.t, self.name, self.kind = tracer, name, kind

    @staticmethod
    def _s(x) -> str:
        return x.name if isinstance(x, Sym) else _lit(x)

    def _bin(self, op, other, reverse=False):
        a, b = (other, self) if reverse else (self, other)
        return self.t.emit(f"{self._s(a)} {op} {self._s(b)}", _kind(a, b))

    def __add__(self, o): return self._bin("+", o)
    def __radd__(self, o): return self._bin("+", o, True)
    def __sub__(self, o): return self._bin("-", o)
    def __rsub__(self, o): return self._bin("-", o, True)
    def __mul__(self, o): return self._bin("*", o)
    def __rmul__(self, o): return self._bin("*", o, True)
    def __truediv__(self, o): return self._bin("/", o)
    def __rtruediv__(self, o): return self._bin("/", o, True)
    def __neg__(self): return self.t.emit(f"-{self.name}", self.kind)
    def __abs__(self): return self.t.emit(f"abs({self.name})", "r")

    @property
    def real(self):
        return self.t.emit(f"{self.name}.real", "r") if self.kind == "c" else self

    @property
    def imag(self):
        return self.t.emit(f"{self.name}.imag", "r") if self.kind == "c" else 0.0

    def conjugate(self):
        return self.t.emit(f"{self.name}.conjugate()", "c") if self.kind == "c" else self

    def sqrt(self):
        return self.t.emit(f"math.sqrt({self.name})" if self.kind == "r" else f"np.sqrt({self.name})", self.kind)

    def exp(self):
        return self.t.emit(f"np.exp({self.name})", self.kind)

    def arctan2(self, other):
        return self.t.emit(f"math.atan2({self.name}, {self._s(other)})", "r")

    def __bool__(self):
        raise TypeError("a traced force kernel branched on a value (only tables may decide branches)")


def generate_source(prog, n_points: int, n_params: int, n_inputs: int) -> str:
    """The numba source of ``kernel(pos, vel, acc, P, pdiv, pmod, reac, nrm, cpl, frame, driver, cond)``: per
    sample s, the parameters P[(s // pdiv) % pmod], the outputs as :func:`.kernel.outputs` writes them, and the
    condition measure (NaN where an unknown is not finite). Arrays are sample-last (structure of arrays, the
    layout of the compiled kinematics): ``pos (n_points, 2, N)``, ``reac (n_pairs, 2, N)``, ``frame (3, N)`` …"""
    tr = Tracer()
    head = []
    z, v, a = [], [], []
    for i in range(n_points):
        for arr, name, out in ((z, "pos", "z"), (v, "vel", "v"), (a, "acc", "a")):
            head.append(f"{out}{i} = complex({name}[{i}, 0, s], {name}[{i}, 1, s])")
            arr.append(Sym(tr, f"{out}{i}", "c"))
    p = []
    for k in range(n_params):
        head.append(f"p{k} = P[r, {k}]")
        p.append(Sym(tr, f"p{k}", "r"))
    nb = prog.ang.shape[0]
    orient, omega, alpha = [1 + 0j] * nb, [0.0] * nb, [0.0] * nb
    F, M = [0j] * nb, [0.0] * nb
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
    reac, nrm, cpl = np.empty((n_pairs, 2), object), np.empty(n_pairs, object), np.empty(n_pairs, object)
    frame, driver = np.zeros(3, object), np.empty(n_inputs, object)
    K.outputs(prog.pr, prog.ln, prog.drv, prog.sense, z, p, orient, lam, reac, nrm, cpl, frame, driver)
    s_ = Sym._s
    tail = [f"reac[{k}, {j}, s] = {s_(reac[k, j])}" for k in range(n_pairs) for j in range(2)]
    tail += [f"nrm[{k}, s] = {s_(nrm[k])}" for k in range(n_pairs)]
    tail += [f"cpl[{k}, s] = {s_(cpl[k])}" for k in range(n_pairs)]
    tail += [f"frame[{j}, s] = {s_(frame[j])}" for j in range(3)]
    tail += [f"driver[{i}, s] = {s_(driver[i])}" for i in range(n_inputs)]
    tail.append("c = 1.0")
    for c in conds:
        tail.append(f"c = c if {s_(c)} >= c else {s_(c)}")
    for x in lam:
        if isinstance(x, Sym):
            tail.append(f"if not math.isfinite({x.name}):\n            c = np.nan")
    tail.append("cond[s] = c")
    body = "\n".join("        " + line for line in head + tr.lines + tail)
    return ("import math\nimport numpy as np\nfrom numba import njit\n\n\n"
            "@njit(cache=True, error_model='numpy')\n"
            "def kernel(pos, vel, acc, P, pdiv, pmod, reac, nrm, cpl, frame, driver, cond):\n"
            "    r = 0\n"
            "    left = pdiv\n"
            "    for s in range(pos.shape[2]):\n"
            "        if left == 0:\n"
            "            left = pdiv\n"
            "            r = r + 1 if r + 1 < pmod else 0\n"
            "        left -= 1\n" + body + "\n")


def available() -> bool:
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _kernel(plan, prog):
    k = _KERNELS.get(plan)
    if k is None:
        import os
        import tempfile
        from pathlib import Path

        from ..engine.planar.numba_backend import LOG, cache_dir
        from ..kernels.codegen import load_kernel
        src = generate_source(prog, plan.n_points, plan.n_params, plan.n_inputs)
        try:
            k = load_kernel(src, cache_dir())
        except OSError:
            k = load_kernel(src, Path(tempfile.gettempdir()) / "assur-kernels")
        module = Path(k.py_func.__code__.co_filename)
        if not any((module.parent / "__pycache__").glob(f"{module.stem}.*.nbi")):
            LOG.info("compiling a force kernel for this mechanism (once, cached in %s)", os.path.dirname(module))
        _KERNELS[plan] = k
    return k


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
    """The flat result arrays (reac (N, n_pairs, 2), nrm, cpl (N, n_pairs), frame (N, 3), driver (N, n_inputs),
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
    n_pairs = prog.pr.shape[0]
    reac, nrm, cpl = np.empty((n_pairs, 2, n)), np.empty((n_pairs, n)), np.empty((n_pairs, n))
    frame, driver, cond = np.empty((3, n)), np.empty((plan.n_inputs, n)), np.empty(n)
    kern(soa(state.pos), soa(state.vel), soa(state.acc), P, pdiv, pmod, reac, nrm, cpl, frame, driver, cond)
    reac, nrm, cpl = np.moveaxis(reac, -1, 0), nrm.T, cpl.T
    frame, driver = frame.T, driver.T
    return reac, nrm, cpl, frame, driver, cond, np.isfinite(cond)[:, None]
