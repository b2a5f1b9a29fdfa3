"""numba compiles assur's kernels without AVX-512 (assur/kernels/numba_target.py): on AVX-512 hosts LLVM 22
miscompiles a loop with two conditional stores, which a generated Newton kernel has."""
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from assur.kernels.numba_target import features_without_avx512

#: the smallest loop found that the miscompile breaks: every sample is reached, so nothing may be written; on an
#: AVX-512 host compiled for AVX-512, 352 of the 720 flags came out False (the Newton kernel's last loop, cut down)
TWO_STORES = textwrap.dedent("""
    import numpy as np
    from numba import njit

    @njit(error_model="numpy")
    def unreached(reached, valid, flag):
        for u in range(reached.shape[0]):
            if not reached[u]:
                valid[u] = False
                flag[u] = 0.0

    valid, flag = np.ones(720, np.bool_), np.ones(720)
    unreached(np.ones(720, np.bool_), valid, flag)
    print(int((~valid).sum()), int((flag != 1.0).sum()))
""")


def _run(code: str, **env) -> str:
    full = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_CPU")} | env
    return subprocess.run([sys.executable, "-c", code], env=full, capture_output=True, encoding="utf-8",
                          check=True, cwd=Path(__file__).resolve().parents[1]).stdout


def test_only_the_avx512_features_are_turned_off():
    flat, changed = features_without_avx512({"avx2": True, "avx512f": True, "avx512vl": True, "sse4.2": True,
                                             "avx512bw": False, "amx-tile": False})
    assert changed
    assert flat.split(",") == ["-amx-tile", "+avx2", "-avx512bw", "-avx512f", "-avx512vl", "+sse4.2"]
    assert features_without_avx512({"avx2": True, "avx512f": False}) == ("+avx2,-avx512f", False)


def test_the_loop_the_miscompile_broke_is_right_in_a_process_that_imported_assurs_kernels():
    pytest.importorskip("numba")
    out = _run("import assur.kernels.reductions\n" + TWO_STORES)
    assert out.split() == ["0", "0"]


def test_numba_is_told_to_leave_out_avx512_on_a_host_that_has_it():
    pytest.importorskip("numba")
    code = textwrap.dedent("""
        import llvmlite.binding as ll
        host = {k for k, v in ll.get_host_cpu_features().items() if v and k.startswith("avx512")}
        import assur.kernels.reductions
        import numba
        told = set((numba.config.CPU_FEATURES or "").split(","))
        print(bool(host), all("-" + k in told for k in host), any(f.startswith("+avx512") for f in told))
    """)
    has, all_off, any_on = _run(code).split()
    assert any_on == "False"
    assert all_off == "True"
    if has == "False":                    # nothing to turn off: numba keeps the host's own features
        assert _run("import assur.kernels.reductions, numba; print(numba.config.CPU_FEATURES)").strip() == "None"


def test_a_users_own_choice_of_target_is_kept():
    pytest.importorskip("numba")
    code = "import assur.kernels.reductions, numba; print(numba.config.CPU_FEATURES)"
    assert _run(code, NUMBA_CPU_FEATURES="+sse2").strip() == "+sse2"
    assert _run(code, NUMBA_CPU_NAME="generic").strip() == ""          # numba's own default for a generic target
    keep = _run("import assur.kernels.reductions, os; print(os.environ.get('NUMBA_CPU_FEATURES'))",
                ASSUR_NUMBA_AVX512="1")
    assert keep.strip() == "None"


def test_kernels_are_not_used_where_numba_compiled_for_avx512_first():
    """A process where other numba code compiled before assur's kernels were imported: numba's target is fixed. On an
    AVX-512 host the automatic backend then takes numpy (the same numbers) and the compiled one by name is refused
    with the reason; on another host nothing changes."""
    pytest.importorskip("numba")
    code = textwrap.dedent("""
        import logging
        import llvmlite.binding as ll
        import numpy as np
        from numba import njit
        njit(lambda x: x + 1)(1)                          # numba's target is fixed now
        import assur
        from assur.kernels import codegen
        logging.disable(logging.WARNING)
        avx512 = ll.get_host_cpu_features().get("avx512f", False)
        plan = assur.compile(assur.load("examples/triad_sixbar.toml"))
        q = np.linspace(0.0, 2 * np.pi, 720, endpoint=False)
        st = assur.solve(plan, inputs=q)
        ref = assur.solve(plan, inputs=q, backend="numpy")
        same = bool(np.array_equal(st.valid, ref.valid) and np.allclose(st.pos, ref.pos, atol=1e-12, equal_nan=True))
        try:
            assur.solve(plan, inputs=q, backend="numba")
            refused = "no"
        except RuntimeError as e:
            refused = "ASSUR_NUMBA_AVX512" in str(e)
        print(bool(avx512), codegen.available(), same, refused)
    """)
    avx512, available, same, refused = _run(code).split()
    assert same == "True"
    if avx512 == "True":
        assert (available, refused) == ("False", "True")
    else:
        assert (available, refused) == ("True", "no")
