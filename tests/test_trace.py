"""The tracer that writes every compiled kernel (assur.kernels.trace): element-wise numpy code run on symbols gives
straight-line source that computes what numpy computes. The traced lines are run here as plain Python (no numba):
the reference is the same function run by numpy on arrays."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from assur.kernels import codegen, planar
from assur.kernels import trace as T
from assur.kernels.jet import Jet


#: the ``math`` functions a kernel calls, on numpy scalars (so that 0.5/√0 is inf, as in numba's numpy error model)
NUMPY_MATH = SimpleNamespace(sqrt=np.sqrt, exp=np.exp, cos=np.cos, sin=np.sin, atan=np.arctan, atan2=np.arctan2,
                             hypot=np.hypot, isfinite=np.isfinite, nan=math.nan, inf=math.inf)


def as_function(tracer, inputs, outputs):
    """A plain Python function of the free symbols named ``inputs`` returning ``outputs``: the traced lines they
    need, in order."""
    body = "".join(f"    {ln}\n" for ln in tracer.needed(outputs))
    result = ", ".join(T.source(o) for o in outputs)
    namespace = {"math": NUMPY_MATH}
    exec(f"def f({', '.join(inputs)}):\n{body}    return ({result},)\n", namespace)
    return namespace["f"]


def symbolic_jet(tr, name, complex_=True):
    """A second-order jet of free symbols ``{name}v0``, ``{name}v1``, ``{name}d0`` …: (jet, their names)."""
    parts, names = [], []
    for k in ("v", "d", "dd"):
        if complex_:
            re, im = tr.free(f"{name}{k}0"), tr.free(f"{name}{k}1")
            parts.append(T.C(re, im))
            names += [re.name, im.name]
        else:
            parts.append(tr.free(f"{name}{k}"))
            names.append(parts[-1].name)
    return Jet(*parts), names


def array_jet(values, complex_=True):
    """The numpy jet of sampled values (per part, (n,)) in the order of :func:`symbolic_jet`."""
    if complex_:
        return Jet(values[0] + 1j * values[1], values[2] + 1j * values[3], values[4] + 1j * values[5])
    return Jet(values[0], values[1], values[2])


def flat(jet):
    """A jet's parts as a list of reals (complex parts split)."""
    out = []
    for x in (jet.v, jet.d, jet.dd):
        out += [np.real(x), np.imag(x)] if (isinstance(x, T.C) or np.iscomplexobj(x)) else [x]
    return out


CASES = {
    # name: (closed form, argument kinds: "c" complex jet, "r" real jet, "k" real constant of the call)
    "circle_circle": (lambda a, b, c, d, m, tol: planar.circle_circle(a, b, c, d, 1, tol, m), "crcr"),
    "circle_line": (lambda a, b, c, d, m, tol: planar.circle_line(a, b, c, d, -1, tol, m), "crcc"),
    "rotation_from_slide": (lambda a, b, c, m, tol: planar.rotation_from_slide(a, b, c, 1, tol, m), "ckk"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_traced_closed_forms_compute_what_numpy_computes(name):
    """Each closed form of assur.kernels.planar on second-order jets, with margins (as the kernels trace them): the
    traced lines, run per sample, give numpy's point, derivatives, validity and margin (random arguments, some of
    them past a toggle)."""
    from assur.kernels.jet import expi
    f, kinds = CASES[name]
    rng = np.random.default_rng(7)
    n = 300
    tr = T.Tracer()
    sym_args, names, num_args, samples = [], [], [], []      # samples: per free name, its n values
    for i, kind in enumerate(kinds):
        if kind == "k":
            sym_args.append(tr.free(f"k{i}"))
            names.append(f"k{i}")
            num_args.append(rng.uniform(-0.8, 0.8, n))
            samples.append(num_args[-1])
            continue
        jet, jn = symbolic_jet(tr, f"a{i}", complex_=kind == "c")
        values = [rng.uniform(0.3, 1.2, n) if (kind == "r" and k == 0) else rng.uniform(-1, 1, n)
                  for k in range(len(jn))]
        if name == "circle_line" and i == 3:                    # a unit direction and its derivatives
            e = expi(Jet(rng.uniform(0, 2 * np.pi, n), rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)))
            values = [np.real(e.v), np.imag(e.v), np.real(e.d), np.imag(e.d), np.real(e.dd), np.imag(e.dd)]
        sym_args.append(jet)
        names += jn
        num_args.append(array_jet(values, complex_=kind == "c"))
        samples += values
    margins, ref_margins = [], []
    z, ok = f(*sym_args, margins, tr.free("tol"))
    fn = as_function(tr, names + ["tol"], flat(z) + [ok] + margins)
    with np.errstate(all="ignore"):
        zr, okr = f(*num_args, ref_margins, 1e-12)
        rows = [fn(*[v[s] for v in samples], 1e-12) for s in range(n)]
    ref = [np.broadcast_to(x, (n,)) for x in flat(zr)]
    got = np.array([r[:len(ref)] for r in rows], dtype=float).T
    valid = np.array([r[len(ref)] for r in rows], dtype=bool)
    assert np.array_equal(valid, okr) and 0 < valid.sum() < n
    for g, r in zip(got, ref):
        assert np.allclose(g[valid], r[valid], rtol=1e-11, atol=1e-11)
    for g, r in zip(got[:2], ref[:2]):      # past a toggle, with margins: the toggle's continuation, as numpy's
        assert np.all(np.isfinite(g[~valid])) and np.allclose(g[~valid], r[~valid], rtol=1e-11, atol=1e-11)
    margin = np.array([r[len(ref) + 1] for r in rows])
    assert np.allclose(margin, ref_margins[0], rtol=1e-12, atol=1e-15)
    assert np.array_equal(margin >= 0, valid)


def test_constants_fold_and_identical_operations_are_shared():
    tr = T.Tracer()
    x, y = tr.free("x"), tr.free("y")
    assert x * 0.0 == 0.0 and x * 1.0 is x and x + 0.0 is x and 0.0 - x is not x
    assert -(-x) is x
    assert x * y is y * x and x + y is y + x
    assert str(tr.lines[-1]) == f"{tr.lines[-1].name} = x + y"
    ny = -y
    n = len(tr.lines)
    assert x - ny is x + y and len(tr.lines) == n    # a − (−b) is a + b: the line already written
    p = x * (-y)                                     # x·(−y) is −(x·y)
    assert tr.lines[-1].expr == f"-{(x * y).name}" and p is -(x * y)
    z = T.C(x, 0.0) * T.C(y, 0.0)                    # a complex product with zero imaginary parts: one line
    assert z.im == 0.0 and z.re is x * y


def test_levels_place_each_line_in_the_outermost_loop_it_may_run_in():
    tr = T.Tracer()
    p = tr.load("P[d, 0]", T.DESIGN)
    c = tr.free("c", T.SAMPLE)
    g = tr.load("g[0]")
    a = p * 2.0 + g                                  # a design's value
    b = a * c                                        # a sample's value
    assert (p.level, a.level, b.level, g.level) == (T.DESIGN, T.DESIGN, T.DESIGN | T.SAMPLE, 0)
    assert codegen.lines_at(tr, [b], 0, "") == [f"{g.name} = g[0]"]
    assert [ln.split(" = ")[0] for ln in codegen.lines_at(tr, [b], T.DESIGN, "")] == [p.name, (p * 2.0).name, a.name]
    assert codegen.lines_at(tr, [b], T.SAMPLE, "") == [f"{b.name} = {' * '.join(sorted((a.name, 'c')))}"]
    # a further loop inside the sample loop (Newton's iterations: the unknowns change per iteration) is one more bit
    iterate = 2 * T.SAMPLE
    x = tr.free("x", iterate)
    r = x * b + a * a
    assert codegen.loop_of(r.level) == iterate and codegen.loop_of((a * a).level) == T.DESIGN
    assert [ln.split(" = ")[0] for ln in codegen.lines_at(tr, [r], iterate, "")] == [(x * b).name, r.name]


def test_a_kernel_keeps_only_the_lines_its_outputs_read():
    tr = T.Tracer()
    x, y = tr.free("x"), tr.free("y")
    wanted = np.sqrt(x * x + 1.0)
    unused = np.exp(y) * x
    kept = {ln.name for ln in tr.needed([wanted])}
    assert unused.name not in kept and len(kept) == 3


def test_numpys_functions_on_symbols_are_traced():
    tr = T.Tracer()
    x, y = tr.free("x"), tr.free("y")
    z = T.C(x, y)
    f = as_function(tr, ["x", "y"], [np.abs(z), np.real(np.conj(z) * 1j), np.imag(np.exp(1j * x)),
                                     np.where(x > 0.0, x, np.nan), np.maximum(y, 0.0), np.isfinite(x / y)])
    for xv, yv in ((0.3, -1.7), (-2.0, 0.0), (1e-3, 4.0)):
        zv = complex(xv, yv)
        with np.errstate(all="ignore"):
            expect = (abs(zv), (np.conj(zv) * 1j).real, math.sin(xv), xv if xv > 0 else math.nan, max(yv, 0.0),
                      bool(np.isfinite(np.float64(xv) / yv)))
        with np.errstate(all="ignore"):
            got = f(np.float64(xv), np.float64(yv))         # numpy scalars: division by zero as in numba
        assert np.allclose(got[:5], expect[:5], equal_nan=True, rtol=1e-15) and got[5] == expect[5]
    assert tr.lines[tr.by_name[np.abs(z).name].index].expr.startswith("math.sqrt(")


def test_what_cannot_be_traced_is_refused_with_a_clear_error():
    tr = T.Tracer()
    x = tr.free("x")
    with pytest.raises(TypeError, match="branched on a traced value"):
        if x > 0:
            pass
    with pytest.raises(TypeError, match="does not implement numpy.sum"):
        np.sum(x)
    with pytest.raises(TypeError, match="scalars"):
        np.add(x, np.ones(3))
    with pytest.raises(TypeError):
        float(x)
    with pytest.raises(TypeError, match="complex square root"):
        np.sqrt(T.C(x, x))
