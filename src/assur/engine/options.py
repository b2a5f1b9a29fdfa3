"""What every solve shares, planar or spatial: option checks, the batch preparation, the
continuation schedule of the Newton solvers and the unbuildable policy with its message."""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import SpecError, UnbuildableError, UnbuildableWarning, float_array, one_of
from ..kernels.runs import runs

ON_UNBUILDABLE = ("nan", "warn", "raise")
METHODS = ("closed", "newton")
BACKENDS = ("auto", "numpy", "numba")
#: with backend="auto", batches at least this large use the compiled backend when numba is installed and the
#: plan's kernel is compiled already (in this process or in the disk cache) …
AUTO_COMPILED_MIN_SAMPLES = 20_000
#: … and, for a plan with Newton-solved groups (numpy costs a thousand times more per sample), batches at least this
#: large when, besides, numba is imported already (the kernel then costs nothing to start) …
AUTO_CACHED_MIN_SAMPLES = 16
#: … and batches at least this large compile it first: a new mechanism's kernel takes seconds to compile, which
#: only a batch this size wins back at once (the numpy backend solves about a million samples a second)
AUTO_COMPILE_MIN_SAMPLES = 5_000_000
#: … or, for a plan with Newton-solved groups, this large: the numpy backend continues such a sample from the sketch
#: in about 0.65 ms (one design's cycle; several ms for a population's), so a batch this size costs it about the first
#: compile of the kernel (some 20 s: benchmarks/newton.py measures both)
AUTO_NEWTON_COMPILE_MIN_SAMPLES = 30_000

#: Samples of one input turn shared by the analysis, the report, the figures, the force cycle and the animation's
#: path (:class:`assur.analysis.study.Study`): every command samples one turn at it unless told otherwise.
CYCLE_STEPS = 720


def check_options(on_unbuildable: str, method: str, order: int, backend: str = "auto") -> None:
    """SpecError unless the options of a solve (planar or spatial) are known values."""
    if not one_of(on_unbuildable, ON_UNBUILDABLE):
        raise SpecError([("on_unbuildable", f"must be one of {', '.join(ON_UNBUILDABLE)}: {on_unbuildable!r}")])
    if not one_of(method, METHODS):
        raise SpecError([("method", f"must be 'closed' or 'newton': {method!r}")])
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order not in (0, 1, 2):
        raise SpecError([("order", f"must be 0, 1 or 2: {order!r}")])
    if not one_of(backend, BACKENDS):
        raise SpecError([("backend", f"must be 'auto', 'numpy' or 'numba': {backend!r}")])


def prepare_batch(plan, params, inputs):
    """``params (..., n_params)`` (default: the plan's) and ``inputs (..., n_inputs)`` (default: the
    sketch's) as float arrays; for a one-input plan a scalar or a 1-D array is a batch of values.

    Returns
    -------
    params : ndarray (..., n_params)
    inputs : ndarray (..., n_inputs)
    """
    params = plan.defaults if params is None else float_array(params, "params", "numbers (the design parameters)")
    if params.ndim == 0 or params.shape[-1] != plan.n_params:
        raise SpecError([("params", f"must have a trailing axis of {plan.n_params} parameters "
                                    f"({', '.join(plan.param_names)}): shape {params.shape}")])
    inputs = plan.sketch_inputs if inputs is None else float_array(inputs, "inputs", "numbers (rad or m)")
    if plan.n_inputs == 1 and (inputs.ndim <= 1 or inputs.shape[-1] != 1):
        inputs = inputs[..., None]   # one input: a scalar or a 1-D array is a batch of input values
    if inputs.shape[-1] != plan.n_inputs:
        raise SpecError([("inputs", f"must have a trailing axis of {plan.n_inputs} inputs "
                                    f"({', '.join(plan.input_names)}): shape {inputs.shape}")])
    return params, inputs


def input_rates(plan, speeds, accels):
    """The input rates ``qdot`` and accelerations ``qddot``, each (..., n_inputs): the drivers'
    speeds and zero by default."""
    n = plan.n_inputs
    qdot = plan.speeds if speeds is None else float_array(speeds, "speeds", "numbers (rad/s or m/s)")
    qddot = np.zeros(n) if accels is None else float_array(accels, "accels", "numbers (rad/s² or m/s²)")
    for name, v in (("speeds", qdot), ("accels", qddot)):
        if v.shape[-1:] != (n,):
            raise SpecError([(name, f"needs a trailing axis of {n} input(s) ({', '.join(plan.input_names)}): "
                                    f"shape {v.shape}")])
    return qdot, qddot


def continuation(plan, input_values, params, tol):
    """The continuation schedule of a Newton solve: every sample walks from the sketch inputs to
    its own in ``m`` stages of at most ``tol.stage_angle`` of crank (``tol.stage_length`` of the
    length scale of stroke), and in at least ``tol.stages_for_new_design`` stages when the design
    differs from the file's.

    Parameters
    ----------
    input_values : list of ndarray
        Per input, the requested values (any batch shape).
    params : ndarray (..., n_params)

    Returns
    -------
    m : int
        The number of stages (the last one is the requested inputs).
    deltas : list of ndarray
        Per input, the signed way from the sketch input (rotary inputs the short way round).
    dp : ndarray or None
        ``params − defaults`` when the design moved, else None.
    """
    q_s = plan.sketch_inputs
    deltas = []
    for k, v in enumerate(input_values):
        v = np.asarray(v, dtype=float)
        if plan.input_kinds[k] == "rotary":
            deltas.append((v - q_s[k] + np.pi) % (2 * np.pi) - np.pi)
        else:
            deltas.append(v - q_s[k])
    m = stage_count(plan, deltas, tol)
    dp = params - plan.defaults
    moved = bool(np.any(dp != 0))
    if moved:
        m = max(m, tol.stages_for_new_design)
    return m, deltas, (dp if moved else None)


def stage_count(plan, deltas, tol) -> int:
    """The stages a continuation along ``deltas`` (per input, the signed way from the sketch input) needs:
    at most ``tol.stage_angle`` of crank and ``tol.stage_length`` of the length scale of stroke each."""
    stage = [tol.stage_angle if kind == "rotary" else tol.stage_length * plan.length_scale
             for kind in plan.input_kinds]
    finite = [np.abs(d[np.isfinite(d)]) for d in deltas]
    return max([int(np.ceil(f.max() / s)) if f.size else 1 for f, s in zip(finite, stage)] + [1])


def format_input(plan, k: int, value: float) -> str:
    """An input value as text: degrees for a crank, metres for an actuator."""
    if plan.input_kinds[k] == "rotary":
        return f"{np.degrees(value):.6g}°"
    return f"{value:.6g} m"


def ambiguous_note(n: int) -> str:
    """The words every report uses for ``n`` ambiguous samples among the unbuildable ones (``State.ambiguous``)."""
    return (f"{n} of them ambiguous: reached on one assembly going forward from the sketch and on another going back, "
            f"since its assembly does not close over a turn")


def unbuildable_message(plan, inputs, valid, causes=None, ambiguous=None) -> str:
    """'k of n samples cannot be assembled (…); they are NaN with valid=False'.

    Parameters
    ----------
    inputs : ndarray (..., n_inputs)
        The inputs of the batch (broadcast to ``valid.shape``).
    valid : ndarray (...)
    causes : dict or None
        Per solved point, a bool array (...) of the samples its group failed at and the reasons
        (point → (failed, reasons)). For a 1-D sweep of one input the message then names the input
        ranges each group fails over; otherwise it names the first failing sample.
    ambiguous : ndarray (...) bool or None
        The samples on two assemblies, one each way round (``State.ambiguous``): counted in the message.
    """
    n_bad = int(np.count_nonzero(~valid))
    head = f"{n_bad} of {valid.size} samples cannot be assembled"
    n_amb = 0 if ambiguous is None else int(np.count_nonzero(ambiguous))
    tail = "; they are NaN with valid=False"
    if n_amb:
        tail = f"; {ambiguous_note(n_amb)} (state.ambiguous)" + tail
    n = plan.n_inputs
    if causes and valid.ndim == 1 and n == 1:
        q = inputs[..., 0]
        order = np.argsort(q, kind="stable")
        parts = []
        for point, (failed, reasons) in causes.items():
            bad = failed[order]
            if not bad.any():
                continue
            qs = q[order]
            rng = ", ".join(f"{math.degrees(qs[a]):.4g}°…{math.degrees(qs[b]):.4g}°" for a, b in runs(bad))
            parts.append(f"the dyad solving {point} ({'; '.join(reasons)}) at {plan.input_names[0]} {rng}")
        return head + (": " + "; ".join(parts) if parts else "") + tail
    flat = np.broadcast_to(inputs, valid.shape + (n,)).reshape(-1, n)[~valid.reshape(-1)]
    first = ", ".join(f"{plan.input_names[k]}={format_input(plan, k, flat[0, k])}" for k in range(n))
    sep = " (first at " if causes is None else ": first at "
    return head + sep + first + (")" if causes is None else "") + tail


def report_unbuildable(plan, inputs, valid, on_unbuildable: str, causes=None, stacklevel: int = 4,
                       ambiguous=None) -> int:
    """Apply the unbuildable policy: count the invalid samples; with 'warn' warn and with 'raise'
    raise :class:`~assur.errors.UnbuildableError`, with :func:`unbuildable_message`. Returns the count."""
    n_bad = int(np.count_nonzero(~valid))
    if n_bad and on_unbuildable != "nan":
        msg = unbuildable_message(plan, inputs, valid, causes, ambiguous)
        if on_unbuildable == "raise":
            raise UnbuildableError(msg, n_bad, valid.size)
        warnings.warn(msg, UnbuildableWarning, stacklevel=stacklevel)
    return n_bad
