"""The compiled force backend: a plan's force solve as one straight-line numba loop, traced from :mod:`.kernel`.

The kernel's functions are run once in Python on *symbolic* values (:class:`R` real, :class:`C` complex as two real parts): every arithmetic
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

    def emit(self, expr: str) -> "R":
        name = f"t{self.count}"
        self.count += 1
        self.lines.append(f"{name} = {expr}")
        return R(self, name)


def _lit(x: float) -> str:
    """A real number as source (nan and inf spelled for numba)."""
    x = float(x)
    if math.isnan(x):
        return "np.nan"
    if math.isinf(x):
        return "np.inf" if x > 0 else "-np.inf"
    return repr(x)


def _src(x) -> str:
    return x.name if isinstance(x, R) else _lit(x)


def _tracer(*xs) -> Tracer:
    for x in xs:
        if isinstance(x, R):
            return x.t
        if isinstance(x, C):
            for part in (x.re, x.im):
                if isinstance(part, R):
                    return part.t
    raise AssertionError("no symbolic operand")


# real operations with constant folding: a product with an exact zero is zero, with one the other factor
def _add(a, b):
    if not isinstance(a, R) and not isinstance(b, R):
        return float(a) + float(b)
    if not isinstance(a, R) and a == 0.0:
        return b
    if not isinstance(b, R) and b == 0.0:
        return a
    return _tracer(a, b).emit(f"{_src(a)} + {_src(b)}")


def _neg(a):
    return -float(a) if not isinstance(a, R) else a.t.emit(f"-{a.name}")


def _sub(a, b):
    if not isinstance(a, R) and not isinstance(b, R):
        return float(a) - float(b)
    if not isinstance(b, R) and b == 0.0:
        return a
    if not isinstance(a, R) and a == 0.0:
        return _neg(b)
    return _tracer(a, b).emit(f"{_src(a)} - {_src(b)}")


def _mul(a, b):
    if not isinstance(a, R) and not isinstance(b, R):
        return float(a) * float(b)
    for x, y in ((a, b), (b, a)):
        if not isinstance(x, R):
            if x == 0.0:
                return 0.0
            if x == 1.0:
                return y
            if x == -1.0:
                return _neg(y)
    return _tracer(a, b).emit(f"{_src(a)} * {_src(b)}")


def _div(a, b):
    if not isinstance(a, R) and not isinstance(b, R):
        with np.errstate(all="ignore"):
            return float(np.divide(float(a), float(b)))
    if not isinstance(b, R) and b == 1.0:
        return a
    if not isinstance(a, R) and a == 0.0:
        return 0.0
    return _tracer(a, b).emit(f"{_src(a)} / {_src(b)}")


def _call(fn: str, a):
    return a.t.emit(f"{fn}({a.name})")


def _c(x) -> "C":
    """Any operand as a complex pair."""
    if isinstance(x, C):
        return x
    if isinstance(x, R):
        return C(x, 0.0)
    x = complex(x)
    return C(x.real, x.imag)


def _is_complex(x) -> bool:
    return isinstance(x, (C, complex, np.complexfloating))


class _Ops:
    """Arithmetic shared by real and complex symbols: a complex operand makes the result complex."""
    __array_priority__ = 1000

    def __add__(self, o): return _cadd(self, o)
    def __radd__(self, o): return _cadd(o, self)
    def __sub__(self, o): return _csub(self, o)
    def __rsub__(self, o): return _csub(o, self)
    def __mul__(self, o): return _cmul(self, o)
    def __rmul__(self, o): return _cmul(o, self)
    def __truediv__(self, o): return _cdiv(self, o)
    def __rtruediv__(self, o): return _cdiv(o, self)

    def __bool__(self):
        raise TypeError("a traced force kernel branched on a value (only tables may decide branches)")


class R(_Ops):
    """A real symbol: a named temporary of the generated source."""

    def __init__(self, tracer: Tracer, name: str):
        self.t, self.name = tracer, name

    def __neg__(self): return _neg(self)
    def __abs__(self): return _call("abs", self)

    @property
    def real(self):
        return self

    @property
    def imag(self):
        return 0.0

    def conjugate(self):
        return self

    def sqrt(self):
        return _call("math.sqrt", self)

    def exp(self):
        return _call("math.exp", self)


class C(_Ops):
    """A complex symbol as two real parts (each a symbol or a constant): the generated code is real arithmetic,
    and a zero part costs nothing."""

    def __init__(self, re, im):
        self.re, self.im = re, im

    def __neg__(self): return C(_neg(self.re), _neg(self.im))

    def __abs__(self):
        return _sqrt(_add(_mul(self.re, self.re), _mul(self.im, self.im)))

    @property
    def real(self):
        return self.re

    @property
    def imag(self):
        return self.im

    def conjugate(self):
        return C(self.re, _neg(self.im))

    def sqrt(self):
        raise TypeError("the force kernel takes no complex square roots")

    def exp(self):
        er = 1.0 if not isinstance(self.re, R) and self.re == 0.0 else _exp(self.re)
        if not isinstance(self.im, R):
            return C(_mul(er, math.cos(self.im)), _mul(er, math.sin(self.im)))
        return C(_mul(er, _call("math.cos", self.im)), _mul(er, _call("math.sin", self.im)))


def _sqrt(a):
    return math.sqrt(a) if not isinstance(a, R) else a.sqrt()


def _exp(a):
    return math.exp(a) if not isinstance(a, R) else a.exp()


def _cadd(a, b):
    if not (_is_complex(a) or _is_complex(b)):
        return _add(a, b)
    a, b = _c(a), _c(b)
    return C(_add(a.re, b.re), _add(a.im, b.im))


def _csub(a, b):
    if not (_is_complex(a) or _is_complex(b)):
        return _sub(a, b)
    a, b = _c(a), _c(b)
    return C(_sub(a.re, b.re), _sub(a.im, b.im))


def _cmul(a, b):
    if not (_is_complex(a) or _is_complex(b)):
        return _mul(a, b)
    a, b = _c(a), _c(b)
    return C(_sub(_mul(a.re, b.re), _mul(a.im, b.im)), _add(_mul(a.re, b.im), _mul(a.im, b.re)))


def _cdiv(a, b):
    if not (_is_complex(a) or _is_complex(b)):
        return _div(a, b)
    a, b = _c(a), _c(b)
    if not isinstance(b.im, R) and b.im == 0.0:
        return C(_div(a.re, b.re), _div(a.im, b.re))
    n2 = _add(_mul(b.re, b.re), _mul(b.im, b.im))
    num = _cmul(a, C(b.re, _neg(b.im)))
    return C(_div(num.re, n2), _div(num.im, n2))


def generate_source(prog, n_points: int, n_params: int, n_inputs: int) -> str:
    """The numba source of ``kernel(pos, vel, acc, P, pdiv, pmod, reac, slides, frame, driver, cond)``: per
    sample s, the parameters P[(s // pdiv) % pmod], the outputs as :func:`.kernel.outputs` writes them, and the
    condition measure (NaN where an unknown is not finite). Arrays are sample-last (structure of arrays, the
    layout of the compiled kinematics): ``pos (n_points, 2, N)``, ``reac (n_pairs, 2, N)``, ``frame (3, N)`` …"""
    tr = Tracer()
    head = []
    z, v, a = [], [], []
    for i in range(n_points):
        for arr, name, out in ((z, "pos", "z"), (v, "vel", "v"), (a, "acc", "a")):
            head += [f"{out}x{i} = {name}[{i}, 0, s]", f"{out}y{i} = {name}[{i}, 1, s]"]
            arr.append(C(R(tr, f"{out}x{i}"), R(tr, f"{out}y{i}")))
    p = []
    for k in range(n_params):
        head.append(f"p{k} = P[r, {k}]")
        p.append(R(tr, f"p{k}"))
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
    s_ = _src
    tail = [f"reac[{k}, {j}, s] = {s_(reac[k, j])}" for k in range(n_pairs) for j in range(2)]
    tail += [f"slides[{k}, {j}, s] = {s_(slides[k, j])}" for k in range(n_slides) for j in range(2)]
    tail += [f"frame[{j}, s] = {s_(frame[j])}" for j in range(3)]
    tail += [f"driver[{i}, s] = {s_(driver[i])}" for i in range(n_inputs)]
    tail.append("c = 1.0")
    for c in conds:
        tail.append(f"c = c if {s_(c)} >= c else {s_(c)}")
    for x in lam:
        if isinstance(x, R):
            tail.append(f"if not math.isfinite({x.name}):\n            c = np.nan")
    tail.append("cond[s] = c")
    body = "\n".join("        " + line for line in head + tr.lines + tail)
    return ("import math\nimport numpy as np\nfrom numba import njit\n\n\n"
            "@njit(cache=True, error_model='numpy')\n"
            "def kernel(pos, vel, acc, P, pdiv, pmod, reac, slides, frame, driver, cond):\n"
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
