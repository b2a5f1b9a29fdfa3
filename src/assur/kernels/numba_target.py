"""The CPU features numba compiles assur's kernels for: the host's, without AVX-512.

On a host with AVX-512 (AMD Zen 4, Intel server processors), LLVM 22 (llvmlite 0.50, numba 0.68) miscompiles some
vectorised loops that use its mask registers. A generated Newton kernel (:mod:`assur.kernels.newton_codegen`) whose
last loop stores two flags per sample (``if not reached[u]: valid[d, u] = False; flag[d, u] = 0``) flagged samples 8
to 23 of every 32 as unbuildable, where the same source gives the right answer compiled at ``NUMBA_OPT=0``, without
loop vectorisation, without AVX-512, and run as plain Python: no warning, only wrong samples. (LLVM's X86 back end
has had such bugs in that release: llvm/llvm-project#174871, rust-lang/rust#158622.)

The kernels are scalar code in loops over designs and samples; AVX2's vectors serve them as well (the compiled triad
six-bar cycle is as fast, a dyad six-bar's about a sixth slower: benchmarks/newton_results.md). So :func:`configure`,
called before assur first imports numba, tells numba to compile for the host's own features with every AVX-512
feature turned off (``NUMBA_CPU_FEATURES``, which numba reads once, when it is imported) — unless the user chose a
target (``NUMBA_CPU_NAME`` or ``NUMBA_CPU_FEATURES`` set) or asked to keep AVX-512 (``ASSUR_NUMBA_AVX512=1``).
Child processes (workers, a local Dask cluster) inherit the setting with the environment.

Where numba was imported and has compiled before assur could say so (a library such as pylinkage imported and used
first), its target is fixed with AVX-512 on. The compiled kernels are then not used in that process: the automatic
backend takes numpy, a warning on the ``assur.compile`` log says why once, and a call that asks for the compiled
backend by name is refused with :data:`UNSAFE` (import assur's kernels first — ``import assur.kernels.reductions`` —,
or set ``NUMBA_CPU_FEATURES`` or ``ASSUR_NUMBA_AVX512=1``).
"""
from __future__ import annotations

import logging
import os
import sys

#: set to "1" to let numba use the host's AVX-512 features anyway
KEEP_AVX512 = "ASSUR_NUMBA_AVX512"
#: the environment variables by which a user chooses numba's target (assur then leaves it alone)
USER_CHOICE = ("NUMBA_CPU_NAME", "NUMBA_CPU_FEATURES")

#: why the compiled kernels are not used in a process where numba's target could not be changed in time
UNSAFE = ("numba compiled code for this host's AVX-512 before assur could turn it off for its kernels (LLVM 22 "
          "miscompiles some vectorised loops there), so assur's compiled kernels are not used in this process: import "
          "assur's kernels (import assur.kernels.reductions) before other numba code, or set NUMBA_CPU_FEATURES, or "
          "set ASSUR_NUMBA_AVX512=1 to use them anyway")

_done = False
_safe = True


def features_without_avx512(features) -> tuple[str, bool]:
    """``(flat, changed)``: the LLVM feature string (``+sse2,-avx512f,…``) of a host's feature map (``{name: bool}``,
    as :func:`llvmlite.binding.get_host_cpu_features` gives it) with every AVX-512 feature off, and whether the host
    had any of them on."""
    changed = False
    parts = []
    for name in sorted(features):
        on = bool(features[name])
        if on and name.startswith("avx512"):
            on, changed = False, True
        parts.append(("+" if on else "-") + name)
    return ",".join(parts), changed


def configure() -> bool:
    """Tell numba to compile without AVX-512 (module docstring); once per process, before assur imports numba.
    Costs one query of the host's features (llvmlite, which numba imports anyway). Returns whether the compiled
    kernels may run in this process: False only where numba's target was fixed, with AVX-512, before this call."""
    global _done, _safe
    if _done:
        return _safe
    _done = True
    if os.environ.get(KEEP_AVX512) == "1" or any(v in os.environ for v in USER_CHOICE):
        return _safe
    try:
        import llvmlite.binding as ll
        flat, changed = features_without_avx512(ll.get_host_cpu_features())
    except Exception:           # no llvmlite (numba missing), or a host whose features cannot be read: nothing to do
        return _safe
    if not changed:
        return _safe
    numba = sys.modules.get("numba")
    if numba is not None:
        from numba.core.registry import cpu_target
        if "_toplevel_target_context" in vars(cpu_target):        # it has compiled: too late
            _safe = False
            logging.getLogger("assur.compile").warning(UNSAFE)
            return _safe
        numba.config.CPU_FEATURES = flat                          # imported, not compiled yet: still in time
    os.environ["NUMBA_CPU_FEATURES"] = flat
    return _safe
