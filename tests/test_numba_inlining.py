"""numba's IR inlining with one copy of a callee's scope (screwkit/engine/_kernels/_inlining.py).

The change only makes numba's copies of an inlined function's IR cheaper: the code numba
then generates must be the code it generates without it.  Checked against numba as it is
(``SCREWKIT_NUMBA_INLINING=0``, another process): the same LLVM IR and machine code and
the same results for functions inlined into each other; and on the copies themselves:
each block's copy equals the one numba's own ``copy.deepcopy`` makes, and they share one
scope of their own, as the blocks they copy share theirs."""

import copy
import os
import subprocess
import sys
import textwrap

import numpy as np

from screwkit.engine._kernels import _inlining

_PROGRAM = textwrap.dedent("""
    import hashlib, json, sys
    import numpy as np
    from screwkit.engine._kernels import _configure
    _configure()
    from numba import njit
    from screwkit.engine._kernels import _inlining

    @njit(inline="always")
    def clipped(x, lo, hi):
        if x < lo:
            return lo
        if x > hi:
            return hi
        return x

    @njit(inline="always")
    def norm_clipped(v, hi):
        s = 0.0
        for i in range(v.shape[0]):
            c = clipped(v[i], -hi, hi)
            s += c * c
        while s > hi:
            s = s * 0.5
        return s

    @njit
    def kernel(A, hi):
        out = np.empty(A.shape[0])
        for r in range(A.shape[0]):
            t = norm_clipped(A[r], hi)
            out[r] = t + clipped(A[r, 0], 0.0, 1.0) + norm_clipped(A[r, ::-1], 2 * hi)
        return out

    A = np.linspace(-3.0, 3.0, 60).reshape(12, 5)
    out = kernel(A, 1.5)
    sig = kernel.signatures[0]
    print(json.dumps({"installed": _inlining.installed(),
                      "llvm": hashlib.sha1(kernel.inspect_llvm(sig).encode()).hexdigest(),
                      "asm": hashlib.sha1(kernel.inspect_asm(sig).encode()).hexdigest(),
                      "out": out.tolist()}))
""")


def _run(program, flag, tmp_path):
    import json
    env = dict(os.environ, SCREWKIT_NUMBA_INLINING=flag, NUMBA_CACHE_DIR=str(tmp_path / flag))
    r = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_inlined_functions_compile_to_the_same_code_as_with_numbas_own_copies(tmp_path):
    shared = _run(_PROGRAM, "1", tmp_path)
    numbas = _run(_PROGRAM, "0", tmp_path)
    assert shared["installed"] is True and numbas["installed"] is False
    assert shared["llvm"] == numbas["llvm"] and shared["asm"] == numbas["asm"]
    assert shared["out"] == numbas["out"]
    # the results themselves, by hand (numpy)
    A = np.linspace(-3.0, 3.0, 60).reshape(12, 5)

    def norm_clipped(v, hi):
        s = float(np.sum(np.clip(v, -hi, hi) ** 2))
        while s > hi:
            s *= 0.5
        return s
    want = [norm_clipped(a, 1.5) + min(max(a[0], 0.0), 1.0) + norm_clipped(a[::-1], 3.0)
            for a in A]
    assert np.allclose(shared["out"], want, rtol=1e-15, atol=0)


def test_the_blocks_of_one_scope_are_copied_with_one_scope_each_equal_to_numbas_copy():
    from numba.core import ir
    from numba.core.compiler import run_frontend

    def f(x, n):
        s = 0.0
        for i in range(n):
            if x > i:
                s += x * i
            else:
                s -= i
        return s

    func_ir = run_frontend(f)
    blocks = func_ir.blocks
    assert len(blocks) > 4 and len({id(b.scope) for b in blocks.values()}) == 1
    copier = _inlining._SharedScopeCopies(ir.Block)
    _inlining._STATE.memos = {}
    try:
        first = {k: copier.deepcopy(b) for k, b in blocks.items()}
        second = {k: copier.deepcopy(b) for k, b in first.items()}
    finally:
        _inlining._STATE.memos = None
    for k, b in blocks.items():
        assert first[k] == copy.deepcopy(b) and second[k] == copy.deepcopy(b)
        assert first[k] is not b and first[k].body[0] is not b.body[0]
    scopes = [{id(c.scope) for c in cs.values()} for cs in (first, second)]
    original = id(next(iter(blocks.values())).scope)
    assert all(len(s) == 1 for s in scopes)
    assert len({original} | scopes[0] | scopes[1]) == 3      # three scopes, independent
    # the copy's scope holds the function's variables, as the original's
    scope = next(iter(first.values())).scope
    assert set(scope.localvars._con) == set(next(iter(blocks.values())).scope.localvars._con)
    # outside a call of inline_ir: numba's own copies (each block its own scope's copy)
    c1, c2 = (copier.deepcopy(b) for b in list(blocks.values())[:2])
    assert c1.scope is not c2.scope


def test_install_is_made_once_and_never_over_a_numba_it_does_not_know(tmp_path):
    program = textwrap.dedent("""
        import numba.core.inline_closurecall as ic
        from screwkit.engine._kernels import _inlining
        original = ic.InlineWorker.inline_ir
        saved, ic.copy = ic.copy, object()           # a numba whose module differs
        assert _inlining.install() is False and ic.InlineWorker.inline_ir is original
        ic.copy = saved
        assert _inlining.install() is True and _inlining.install() is True
        assert ic.InlineWorker.inline_ir.__wrapped__ is original     # wrapped once
        print("ok")
    """)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    r = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0 and r.stdout.strip() == "ok", r.stderr
