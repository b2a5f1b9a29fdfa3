"""The loop template of the compiled Newton kernels: a traced plan with Newton-solved groups walked through the inputs
as the numpy backend's certified continuation walks it (:mod:`assur.engine.planar.continuation`,
:mod:`assur.engine.planar.sweep`), Newton's iterations inside.

One kernel solves designs × inputs. Per design (a row ``r`` of the inputs), first the file's design at the sketch's
crank angle, solved from the seeds (the sketch's poses; the certificate there gives each group's branch sign); then

- *every sample on its own* (:func:`_each_walk`, the default continuation, ``continuation.execute``): walked from
  there to the design at the sample's input, parameters and input together, the short way round and, where that
  fails, the long way; the file's design walks in whole steps of crank, which the walks of one direction share (a
  walk starts at the last cached step it passes);
- or *swept* (:func:`_sweep_walk`, ``solve(..., sweep=True)``, ``sweep.execute_cycle``): the parameters walked from the
  file's to the design's at the sketch angle, then the inputs visited by their angle past the sketch's, each walked
  to from the one before, forward and then backward for the inputs the forward walk could not reach.

A walk's last step is at the sample's own input (``cq``, ``sq``): its values, derivatives and certificates are the
sample's (the kernel's ``epilogue``); a sample no walk reaches runs ``missed``.

A walk is a sequence of certified steps in t ∈ [0, 1] along the straight line of inputs (and parameters): a secant
predictor (the first step: the last position), a corrector (Newton, at most ``citers`` iterations, then one step to
polish), and the step's certificate — every group converged and on its branch, every step of the plan assembled,
the groups' poses finite, no point of a group moved by the correction farther than ``corr`` of the length scale, and
for a triad the corrected assembly the nearest of its polynomial's roots to the prediction
(:func:`assur.kernels.reductions.triad_check`, which also gives the sample's separation from the other assemblies).
A certified step lets the next be twice as long (never longer than ``step`` of crank, or a ``stages``-th of the
design change), one that fails is retried at a quarter of its length; a walk whose step falls below ``cmin`` of
crank, or that needs more than :data:`MAX_STEPS` steps, ends there: the design cannot reach that input on its
assembly.

Every traced line runs in the outermost place it may: the design's geometry once per parameter change, the input's
terms once per solve, a group's iteration lines in its iteration loop (the lines of the level bit of its unknowns),
the acceptance, the certificate and the derivatives after the loop, on the loop's last evaluation (at the polished
iterate).
"""
from __future__ import annotations

import math

from .codegen import (_CYCLE_SCRATCH, DESIGN, I4, I8, I12, I16, SAMPLE, _block, _cycle_after, _cycle_reduce, lines_at,
                      loop_of, module)
from .trace import source

#: the arguments every Newton kernel starts with (:func:`newton_source`)
NEWTON_ARGS = ("P, P0, seeds, cs0, sn0, qs, cq, sq, ahead, fwd, bwd, stages, step, tol, ls, rtol, atol, certify, "
               "iters, citers, cmin, corr, asep")
#: steps one walk may try (numpy: ``continuation.MAX_STEPS``)
MAX_STEPS = 1000
#: a walk step's length grows by this factor after a certified step, shrinks by the other after a failed one
GROW, SHRINK = 2.0, 0.25


class _Emitter:
    """The sample-level lines of a traced program, emitted once each in dependency order: :meth:`take` gives the
    lines some values need that no earlier segment emitted (of the sample level or deeper), those of the level bit
    ``inside`` only, or those without the bit ``outside``."""

    def __init__(self, tracer):
        self.tracer, self.done = tracer, set()

    def take(self, values, inside: int = 0, outside: int = 0) -> list[str]:
        out = []
        for ln in self.tracer.needed(values):
            if ln.name in self.done or loop_of(ln.level) < SAMPLE or (inside and not ln.level & inside) \
                    or ln.level & outside:
                continue
            self.done.add(ln.name)
            out.append(str(ln))
        return out


def _group_block(em: _Emitter, g: int, grp) -> list[str]:
    """One Newton-solved group at one solve, from its prediction ``pr{g}_*``: Newton's iterations as the numpy
    backend's :func:`assur.kernels.newton.newton` runs them (stop where the residual is below rtol, give up on a
    non-finite residual, at most ``maxit`` steps, then one more step to polish), then one more evaluation at the
    result, whose lines (the residual, the Jacobian's factorisation) the acceptance, the branch certificate and the
    derivatives read after the loop. Its result goes to ``W[seeds + i]`` (NaN where it fails). With ``probe`` (the
    first solve of a design) the certificate is evaluated at the prediction first: its sign is the branch's."""
    n = len(grp.x)
    x = [f"x{g}_{i}" for i in range(n)]
    sg = f"sg{g}"
    # the groups solved before it (a dyad's radicand: ``upstream``) are read before the iterations start
    pre = em.take([grp.upstream] + grp.F + grp.update + [grp.converged, grp.finite], outside=grp.bit)
    check = em.take(grp.F + [grp.converged, grp.finite], inside=grp.bit)
    step = em.take(grp.update, inside=grp.bit)
    accept = em.take([grp.ok, grp.certificate] + grp.solved)
    cert = source(grp.certificate)
    return [
        *pre,
        "for pas in range(2):",
        f"{I4}if pas == 0 and not probe:",
        f"{I8}continue",
        *_block([f"{xi} = pr{g}_{k}" for xi, k in zip(x, grp.start)], I4),
        f"{I4}it = 0",
        f"{I4}polished = False",
        f"{I4}if {source(grp.upstream)}:",
        f"{I8}while True:",
        *_block(check, I12),
        f"{I12}if not {source(grp.finite)}:",
        f"{I16}break",
        *_block(step, I12),
        f"{I12}if pas == 0 or polished:",
        f"{I16}break",
        f"{I12}if {source(grp.converged)} or it == maxit:",
        f"{I16}polished = True",
        *_block([f"{xi} = {source(v)}" for xi, v in zip(x, grp.update)], I12),
        f"{I12}it += 1",
        *_block(accept, I4),
        f"{I4}if pas == 0:",
        f"{I8}{sg} = 1.0 if {cert} > 0.0 else (-1.0 if {cert} < 0.0 else 0.0)",
        *[f"W[{grp.seeds + i}] = {source(v)}" for i, v in enumerate(grp.solved)],
        f"good = good and {source(grp.ok)}",
    ]


def _event_loop(walk: dict, thetas: list[int], sample: list[str], design: list[str], preds: list[str],
                missed: list[str]) -> list[str]:
    """The per-design event loop both continuations share, at 8 spaces: the state reset, one solve per pass — the
    first at the sketch (the file's design at the sketch's angle, from the seeds, its certificate's sign the
    branch's), then one walk step each — and the step's certificate and length (module docstring), then ``missed``
    for every sample no walk reached. ``walk`` holds what a continuation adds (lines at their own indentation):
    ``state`` its variables, ``next`` where a pass that is not the sketch's picks its walk, step and input (under
    ``else:`` at 4 spaces), ``sketch`` what the sketch's solve leaves (under ``if phase == -1:``), ``direct`` lines
    run after it for a solve that is not a walk step, ``grown``/``shrunk`` after a certified/failed step, ``stuck``
    where a walk gives up and ``arrived`` where it reaches its input (each under its own ``if``). ``sample``: the
    groups' blocks and the step certificate's lines, setting ``good`` and ``stepok``; ``design``: the design's lines
    (run where the parameters change); ``preds``: the lines setting the groups' predictions from ``PRED``;
    ``thetas``: the angles among the unknowns."""
    two_pi = repr(2.0 * math.pi)
    return _block([
        "for u in range(N):", f"{I4}reached[u] = False",
        "for i in range(NT):", f"{I4}X[i] = seeds[i]", f"{I4}PRED[i] = seeds[i]",
        "moved = False",
        "for j in range(p.shape[0]):", f"{I4}if P[d, j] != P0[j]:", f"{I8}moved = True",
        *walk["state"],
        "while True:",
        f"{I4}final = False",
        f"{I4}probe = False",
        f"{I4}maxit = citers",
        *_block(walk.get("pass", []), I4),
        f"{I4}if phase == -1:",
        f"{I8}probe = True",
        f"{I8}maxit = iters",
        f"{I8}newp = True",
        f"{I8}for j in range(p.shape[0]):", f"{I12}p[j] = P0[j]",
        f"{I8}c = cs0", f"{I8}s = sn0",
        f"{I4}else:",
        *_block(walk["next"], I8),
        f"{I4}if newp:", *_block(design, I8), f"{I8}newp = False",
        *_block(preds, I4),
        f"{I4}good = True",
        *_block(sample, I4),
        f"{I4}if phase == -1:",
        *_block(walk["sketch"], I8),
        f"{I8}continue",
        *_block(walk.get("direct", []), I4),
        # a walk step: the angles continued (within half a turn of the prediction), the certificate, the step length
        *[f"{I4}W[{i}] = PRED[{i}] + (W[{i}] - PRED[{i}] + math.pi) % {two_pi} - math.pi" for i in thetas],
        f"{I4}ok = stepok",
        f"{I4}for i in range(NT):", f"{I8}ok = ok and math.isfinite(W[i])",
        f"{I4}if ok:",
        f"{I8}for i in range(NT):", f"{I12}L[i] = X[i]", f"{I12}X[i] = W[i]",
        f"{I8}tl = t", f"{I8}t = tn", f"{I8}h = min(h * {GROW!r}, hmax)",
        *_block(walk.get("grown", []), I8),
        f"{I4}else:", f"{I8}h *= {SHRINK!r}",
        *_block(walk.get("shrunk", []), I8),
        f"{I4}tries += 1",
        f"{I4}if (not ok and h < hmin) or tries > {MAX_STEPS}:",
        *_block(walk["stuck"], I8),
        f"{I4}elif t >= 1.0:",
        f"{I8}walking = False",
        *_block(walk["arrived"], I8),
        "for u in range(N):", f"{I4}if not reached[u]:", *_block(missed, I8), f"{I8}pass",
    ], I8)


def _same_pose(a: str, b: str) -> list[str]:
    """Lines setting ``same``: whether the group poses ``a`` and ``b`` (NT values; ``ISANG`` marks the angles) are one
    assembly, as :func:`assur.engine.planar.continuation.same_assembly` decides (``asep`` of the length scale)."""
    two_pi = repr(2.0 * math.pi)
    return ["same = True", "for i in range(NT):", f"{I4}dd = {a}[i] - {b}[i]", f"{I4}if ISANG[i]:",
            f"{I8}dd = ((dd + math.pi) % {two_pi} - math.pi) * ls", f"{I4}if not abs(dd) <= asep * ls:",
            f"{I8}same = False"]


def _sweep_walk(final: list[str], ambiguous: list[str]) -> dict:
    """The swept continuation's pieces of :func:`_event_loop` (``solve(..., sweep=True)``,
    :func:`assur.engine.planar.sweep.execute_cycle`): phase 0 walks the parameters from the file's design to the
    design's at the sketch's angle, phase 1 visits the inputs by their angle past the sketch's (``fwd``), each walked
    to from the one before, then (phase 3) on to the sketch's angle a turn later: a design back on its pose there
    (``S``) closes and is done. Otherwise phase 2 walks backward from the sketch (``bwd``) through every input it can
    reach: an input the forward walk did not reach takes its pose, one it reached (``FP[u]``, its pose) on another
    assembly is ambiguous and runs ``ambiguous``. ``final``: the lines run at the certified last step of a walk to a
    sample."""
    two_pi = repr(2.0 * math.pi)
    back = ["phase = 2", "check = True", "for i in range(NT):", f"{I4}X[i] = S[i]", "alive = salive", "qf = qs",
            "m = 0"]
    return {
        "state": ["phase = -1", "alive = True", "walking = False", "newp = True", "m = 0", "u = 0", "t = 0.0",
                  "tn = 0.0", "tl = math.nan", "h = 1.0", "hmax = 1.0", "hmin = 1e-12", "tries = 0", "qf = qs",
                  "dq = 0.0", "target = qs", "check = False"],
        "next": [
            "if not walking:",
            f"{I4}if phase == 0:",
            f"{I8}if not (moved and alive):",
            f"{I8}    phase = 1",
            f"{I8}    for i in range(NT):", f"{I8}        S[i] = X[i]",
            f"{I8}    salive = alive", f"{I8}    qf = qs", f"{I8}    m = 0", f"{I8}    newp = True",
            f"{I8}    for j in range(p.shape[0]):", f"{I8}        p[j] = P[d, j]",
            f"{I8}    continue",
            f"{I8}dq = 0.0", f"{I8}hmax = min(1.0, 1.0 / stages)", f"{I8}hmin = 1e-12",
            f"{I4}else:",
            f"{I8}if phase == 3 or not alive or m >= N:",
            f"{I8}    if phase == 2:",
            f"{I8}        break",
            f"{I8}    if phase == 1 and alive:",
            f"{I8}        phase = 3",
            f"{I8}        target = qs + {two_pi}",
            f"{I8}    else:",
            *_block(back, I16),
            f"{I8}        continue",
            f"{I8}else:",
            f"{I8}    u = fwd[r, m] if phase == 1 else bwd[r, m]",
            f"{I8}    m += 1",
            f"{I8}    if reached[u] and not check:", f"{I8}        continue",
            f"{I8}    target = qs + (ahead[r, u] if phase == 1 else ahead[r, u] - {two_pi})",
            f"{I8}dq = target - qf",
            f"{I8}hmax = min(1.0, step / abs(dq)) if dq != 0.0 else 1.0",
            f"{I8}hmin = cmin / abs(dq) if dq != 0.0 else 1e-12",
            f"{I4}walking = True", f"{I4}t = 0.0", f"{I4}tl = math.nan", f"{I4}h = hmax", f"{I4}tries = 0",
            f"{I4}for i in range(NT):", f"{I8}L[i] = X[i]",
            "tn = min(t + h, 1.0)",
            "ratio = (tn - t) / (t - tl) if tl == tl else 0.0",
            "for i in range(NT):", f"{I4}PRED[i] = X[i] + ratio * (X[i] - L[i])",
            "if phase == 0:",
            f"{I4}newp = True",
            f"{I4}for j in range(p.shape[0]):", f"{I8}p[j] = P0[j] + tn * (P[d, j] - P0[j])",
            "final = (phase == 1 or phase == 2) and tn >= 1.0",
            "if final:",
            f"{I4}c = cq[r, u]", f"{I4}s = sq[r, u]",
            "else:",
            f"{I4}qq = qf + tn * dq", f"{I4}c = math.cos(qq)", f"{I4}s = math.sin(qq)"],
        "sketch": ["alive = good", "for i in range(NT):", f"{I4}X[i] = W[i]", "phase = 0"],
        "stuck": ["alive = False", "walking = False", "for i in range(NT):", f"{I4}X[i] = math.nan"],
        "arrived": ["moved = False",
                    "if phase == 3:",
                    *_block(_same_pose("X", "S"), I4),
                    f"{I4}if same:", f"{I8}break",
                    *_block(back, I4),
                    "elif phase != 0:",
                    f"{I4}qf = target",
                    f"{I4}if reached[u]:",
                    *_block(_same_pose("X", "FP[u]"), I8),
                    f"{I8}if not same:",
                    *_block(list(ambiguous) or ["pass"], I12),
                    f"{I4}else:",
                    f"{I8}reached[u] = True",
                    f"{I8}if phase == 1:", f"{I8}    for i in range(NT):", f"{I8}        FP[u, i] = X[i]",
                    *_block(final, I8)],
    }


def _each_walk(final: list[str], ambiguous: list[str]) -> dict:
    """The default continuation's pieces of :func:`_event_loop` (:func:`assur.engine.planar.continuation.execute`):
    after the solve at the sketch, every input ``u`` walked on its own from there — the file's design at the sketch's
    angle — to the design at the input, parameters and input together along the straight line, the short way round
    (``ahead[r, u]``: the input's angle from the sketch's in [−π, π)); where that walk fails, the long way (a turn the
    other way). An input at the sketch's angle of the file's design is solved from the sketch directly (with the full
    iteration cap). The file's design walks in whole steps of crank, which the walks of one direction share (a walk
    starts at the last cached step it passes); it first walks half a turn each way (``m`` = −2, −1: the whole steps
    to the opposite angle, ``EF`` and ``EB``), and its assembly closes where the two meet on one assembly
    (``continuation.closes``). Where it does not (and for every other design) an input the short way reached is
    walked the long way too: reached there on another assembly (than ``FP[u]``), it is ambiguous and runs
    ``ambiguous``. ``final`` as :func:`_sweep_walk`."""
    two_pi = repr(2.0 * math.pi)
    return {
        "state": ["phase = -1", "salive = False", "walking = False", "direct = False", "newp = True", "leg = 0",
                  "m = 0", "nf = 0", "nb = 0", "uniform = False", "kk = 0", "fwdir = True", "u = 0", "t = 0.0",
                  "tn = 0.0", "tl = math.nan", "h = 1.0", "hmax = 1.0", "hmin = 1e-12", "tries = 0", "dq = 0.0",
                  "closed = False"],
        "pass": ["direct = False"],
        "next": [
            "if not walking:",
            f"{I4}if m >= N or not salive:",
            f"{I8}break",
            f"{I4}if m < 0:",
            f"{I8}u = 0",
            f"{I8}dq = math.pi if m == -2 else -math.pi",
            f"{I4}else:",
            f"{I8}u = m",
            f"{I8}dq = ahead[r, u] if leg == 0 else ahead[r, u] - math.copysign({two_pi}, ahead[r, u])",
            f"{I4}for i in range(NT):", f"{I8}X[i] = S[i]", f"{I8}L[i] = S[i]",
            f"{I4}if dq == 0.0 and not moved:",
            # at the sketch: no walk, the sample's solve from the sketch's poses
            f"{I8}direct = True",
            f"{I4}else:",
            f"{I8}hmax = min(1.0, step / abs(dq)) if dq != 0.0 else 1.0",
            f"{I8}if moved:", f"{I8}    hmax = min(hmax, 1.0 / stages)",
            f"{I8}hmin = cmin / abs(dq) if dq != 0.0 else 1e-12",
            f"{I8}walking = True", f"{I8}t = 0.0", f"{I8}tl = math.nan", f"{I8}h = hmax", f"{I8}tries = 0",
            # the file's design walked in whole steps of ``step``: the walks of one direction pass the same inputs,
            # so a walk starts at the last of them it shares with the walks before (cached, C[k - 1] at the k-th step)
            f"{I8}uniform = (not moved) and hmax < 1.0",
            f"{I8}kk = 0",
            f"{I8}fwdir = dq > 0.0",
            f"{I8}if uniform:",
            f"{I8}    kk = min(nf if fwdir else nb, int(math.ceil(1.0 / h)) - 1)",
            f"{I8}    if kk > 0:",
            f"{I8}        for i in range(NT):",
            f"{I8}            X[i] = CF[kk - 1, i] if fwdir else CB[kk - 1, i]",
            f"{I8}            if kk >= 2:",
            f"{I8}                L[i] = CF[kk - 2, i] if fwdir else CB[kk - 2, i]",
            f"{I8}        t = kk * h", f"{I8}        tl = (kk - 1) * h", f"{I8}        tries = kk",
            "if direct:",
            f"{I4}tn = 1.0", f"{I4}ratio = 0.0", f"{I4}maxit = iters",
            "else:",
            f"{I4}tn = min(t + h, 1.0)",
            f"{I4}ratio = (tn - t) / (t - tl) if tl == tl else 0.0",
            "for i in range(NT):", f"{I4}PRED[i] = X[i] + ratio * (X[i] - L[i])",
            "final = tn >= 1.0 and m >= 0",
            "if moved:",
            f"{I4}newp = True",
            f"{I4}for j in range(p.shape[0]):",
            f"{I8}p[j] = P[d, j] if final else P0[j] + tn * (P[d, j] - P0[j])",
            "if final:",
            f"{I4}c = cq[r, u]", f"{I4}s = sq[r, u]",
            "else:",
            f"{I4}qq = qs + tn * dq", f"{I4}c = math.cos(qq)", f"{I4}s = math.sin(qq)"],
        # the file's design first walks half a turn each way (m = -2, -1); any other is not known to close
        "sketch": ["salive = good", "for i in range(NT):", f"{I4}S[i] = W[i]", "phase = 1", "closed = False",
                   "m = 0 if moved else -2"],
        "direct": ["if direct:", f"{I4}reached[u] = True", *_block(final, I4), f"{I4}m += 1", f"{I4}continue"],
        "grown": ["if uniform and t < 1.0:",
                  f"{I4}kk += 1",
                  f"{I4}if kk > (nf if fwdir else nb):",
                  f"{I8}for i in range(NT):",
                  f"{I8}    if fwdir:", f"{I8}        CF[kk - 1, i] = X[i]",
                  f"{I8}    else:", f"{I8}        CB[kk - 1, i] = X[i]",
                  f"{I8}if fwdir:", f"{I8}    nf = kk",
                  f"{I8}else:", f"{I8}    nb = kk"],
        "shrunk": ["uniform = False"],
        "stuck": ["walking = False",
                  "if m < 0:", f"{I4}m = 0",                        # half a turn cannot be walked: not closed
                  "elif leg == 0 and dq != 0.0 and not reached[u]:", f"{I4}leg = 1",
                  "else:", f"{I4}leg = 0", f"{I4}m += 1"],
        "arrived": ["if m < 0:",
                    f"{I4}for i in range(NT):",
                    f"{I8}if m == -2:", f"{I8}    EF[i] = X[i]", f"{I8}else:", f"{I8}    EB[i] = X[i]",
                    f"{I4}if m == -1:", *_block(_same_pose("EF", "EB"), I8), f"{I8}closed = same",
                    f"{I4}m += 1",
                    "elif leg == 1 and reached[u]:",
                    *_block(_same_pose("X", "FP[u]"), I4),
                    f"{I4}if not same:", *_block(list(ambiguous) or ["pass"], I8),
                    f"{I4}leg = 0", f"{I4}m += 1",
                    "else:",
                    f"{I4}reached[u] = True", *_block(final, I4),
                    f"{I4}if leg == 0 and not closed and dq != 0.0:",
                    f"{I8}for i in range(NT):", f"{I8}    FP[u, i] = X[i]",
                    f"{I8}leg = 1",
                    f"{I4}else:", f"{I8}leg = 0", f"{I8}m += 1"],
    }


def newton_source(tracer, groups, values, epilogue, missed, *, valid, generator: str, signature: str, head=(),
                  tail=(), before=(), imports=(), fastmath=("contract",), each: bool = False,
                  ambiguous=()) -> str:
    """Python source of a numba kernel that solves a plan with Newton-solved groups at designs × inputs, following
    each design's assembly from the sketch's (module docstring), and runs ``epilogue`` at every sample it reaches.

    ``groups``: the traced groups (:class:`assur.engine.planar.traced_newton.TracedGroup`), in solve order;
    ``values``: the traced values the ``epilogue`` lines read (source lines that may read ``d``, ``u`` and those
    values' sources, and ``sepok``: no other assembly of a triad within ``asep`` of the length scale, the numpy
    backend's ``continuation.separate``); ``missed``: lines run for every sample the walks cannot reach; ``valid``: the
    traced flag of every step assembled (a walk step's certificate). ``head``/``tail``: lines run per design before
    and after its walks (8 spaces of indentation), ``before``: once per call. The traced program's selects call
    :func:`assur.kernels.reductions.select` (trace with ``Tracer(select="select")``). ``each``: every sample walked
    from the sketch on its own (:func:`_each_walk`, the default continuation), else each design swept through its
    inputs (:func:`_sweep_walk`; both in :func:`_event_loop`); ``ambiguous``: lines run at a sample found ambiguous
    after its ``epilogue`` ran (reached by the other walk on another assembly). The kernel's first arguments are
    :data:`NEWTON_ARGS`,
    the rest ``signature``:

    - ``P (D, n_params)`` the designs, ``P0 (n_params,)`` the file's (the parameters are read from a scratch row
      ``p``: the traced program loads ``p[k]``), ``seeds`` the groups' unknowns at the sketch (their x, y, θ, in solve
      order); ``cs0, sn0, qs``: the sketch's crank angle's cosine, sine and value;
    - ``cq, sq (Dq, N)`` the inputs' cosines and sines (Dq = 1: the same N inputs for every design, or D), ``ahead
      (Dq, N)`` each input's angle past the sketch's in [0, 2π) (with ``each``: from the sketch's the short way, in
      [−π, π)), ``fwd``, ``bwd (Dq, N)`` the inputs in the order the forward and the backward walks visit them;
    - ``stages`` (a step changes a design by at most its ``stages``-th part), ``step`` the longest crank step (rad),
      ``cmin`` the shortest, ``corr`` the largest correction (of the length scale ``ls``, m); ``tol`` the radicand
      tolerance of the closed forms, ``rtol``, ``atol`` the iterations' and the acceptance's residual tolerances
      (m), ``certify`` the certificate's least magnitude, ``iters`` the iteration cap of a sample's solve,
      ``citers`` of a walk step's.
    """
    em = _Emitter(tracer)
    checks = [valid] + [grp.moved for grp in groups]
    everything = list(values) + checks + [v for grp in groups for v in grp.F + grp.update + grp.solved
                                          + [grp.ok, grp.certificate, grp.converged, grp.finite, grp.upstream]
                                          + (grp.triad or [])]
    call = lines_at(tracer, everything, 0, I4)
    design = lines_at(tracer, everything, DESIGN, "")
    sample = []
    for g, grp in enumerate(groups):
        sample += _group_block(em, g, grp)
    sample += em.take(checks)
    triads = [g for g, grp in enumerate(groups) if grp.triad is not None]
    for g in triads:
        sample += em.take(groups[g].triad)
        sample += [f"TA[{k}] = {source(v)}" for k, v in enumerate(groups[g].triad)]
        # only where the step assembled (near a toggle most steps fail before: their roots, merging, are costly)
        sample += [f"if {source(valid)}:", f"{I4}tok{g}, tsep{g} = triad_check(TA, TS, RT{g}, asep * ls)",
                   "else:", f"{I4}tok{g}, tsep{g} = False, True"]
    sample.append("stepok = " + " and ".join([source(valid)] + [f"{source(grp.moved)} <= corr * ls" for grp in groups]
                                             + [f"tok{g}" for g in triads]))
    sample.append("sepok = " + " and ".join(["True"] + [f"tsep{g}" for g in triads]))
    final = em.take(values) + list(epilogue)
    preds = [f"pr{g}_{i} = PRED[{grp.seeds + i}]" for g, grp in enumerate(groups) for i in range(len(grp.solved))]
    ntot = sum(len(grp.solved) for grp in groups)
    thetas = [grp.seeds + i for grp in groups for i in range(2, len(grp.solved), 3)]
    body = [
        *call, *_block(before, I4),
        f"{I4}p = np.empty(P.shape[1])", f"{I4}N = cq.shape[1]", f"{I4}NT = {ntot}",
        f"{I4}per = 1 if cq.shape[0] > 1 else 0",
        f"{I4}reached = np.zeros(N, dtype=np.bool_)",
        *[f"{I4}{a} = np.empty(NT)" for a in ("X", "L", "S", "W", "PRED")],
        f"{I4}KC = int(math.ceil({2.0 * math.pi!r} / step)) + 2",
        f"{I4}CF = np.empty((KC, NT))", f"{I4}CB = np.empty((KC, NT))", f"{I4}FP = np.empty((N, NT))",
        f"{I4}EF = np.empty(NT)", f"{I4}EB = np.empty(NT)",
        f"{I4}ISANG = np.zeros(NT, dtype=np.bool_)", *[f"{I4}ISANG[{i}] = True" for i in thetas],
        f"{I4}TA = np.empty(34)", f"{I4}TS = np.empty(22, dtype=np.complex128)",
        *[f"{I4}RT{g} = np.zeros(7, dtype=np.complex128)" for g, grp in enumerate(groups) if grp.triad is not None],
        *[f"{I4}sg{g} = math.nan" for g in range(len(groups))],
        f"{I4}salive = True",
        f"{I4}for d in range(P.shape[0]):", f"{I8}r = d * per",
        *[f"{I8}sg{g} = math.nan" for g in range(len(groups))],
        *[f"{I8}RT{g}[6] = 0.0" for g, grp in enumerate(groups) if grp.triad is not None],
        *_block(head, I8),
        *_event_loop((_each_walk if each else _sweep_walk)(final, ambiguous), thetas, sample, design, preds, missed),
        *_block(tail, I8),
    ]
    return module(generator, NEWTON_ARGS + ", " + signature, body, fastmath=fastmath,
                  imports=["from assur.kernels.reductions import select, triad_check", *imports])


def newton_cycle_source(tracer, groups, ok, valid, *, transmission=None, foot=None, path=None) -> str:
    """Python source of a fused numba kernel that reduces the whole-cycle quantities of each design of a plan with
    Newton-solved groups: :func:`assur.kernels.codegen.cycle_source`'s columns (the groups' shortfall is 0: a
    Newton-solved group has no margin, so the buildability measure is the unassembled share) from the samples
    :func:`newton_source` reaches; a sample it cannot reach does not assemble.

    ``kernel(*NEWTON_ARGS, g, up, omega, scale, txy, out)``: the inputs ``cq, sq (1, M)`` one uniform turn."""
    after = _cycle_after(transmission, foot, path)
    values = [ok] + [v for _, v in after]
    epilogue = [f"cgood[u] = {source(ok)} and sepok", "cbad += 0 if cgood[u] else 1",
                *[f"{target} = {source(v)}" for target, v in after]]
    # a sample found ambiguous after it counted as assembled (newton_source) no longer does
    ambiguous = ["if cgood[u]:", f"{I4}cbad += 1", f"{I4}cgood[u] = False"] \
        + ([f"ft[u] = math.inf"] if transmission is not None else [])
    if transmission is not None:
        epilogue.append("ft[u] = ft[u] if sepok else math.inf")
    missed = ["cbad += 1"] + (["ft[u] = math.inf"] if transmission is not None else [])
    return newton_source(tracer, groups, values, epilogue, missed, valid=valid,
                         generator="assur.kernels.newton_codegen.newton_cycle_source",
                         signature="g, up, omega, scale, txy, out",
                         before=["M = cq.shape[1]", *[f"{a} = np.empty(M)" for a in _CYCLE_SCRATCH],
                                 "cgood = np.zeros(M, dtype=np.bool_)"], ambiguous=ambiguous,
                         head=["cbad = 0", "shortfall = 0.0"],
                         tail=_cycle_reduce(transmission is not None, foot is not None, path is not None),
                         imports=["from assur.kernels.reductions import gait_reduce, polyline_distance"],
                         fastmath=("contract", "reassoc"))
