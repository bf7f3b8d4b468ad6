"""numba's parfor wrapper libraries without machine code of their own unless asked for
(screwkit/engine/_kernels/_linking.py).

The change only skips optimisation and machine code nothing runs: a kernel must compute as
it does without it.  Checked against numba as it is (``SCREWKIT_NUMBA_LINKING=0``, another
process): a ``prange`` kernel's floating-point operations carry no flag that lets LLVM
change a result, and it gives the same results bit for bit (which equal a numpy
derivation); its loop's libraries were deferred and never made; a library that is asked
for a pointer (numba's ``guvectorize``, whose wrapper library has the deferred kind's
name) gets its machine code then and computes right."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np

_PROGRAM = textwrap.dedent("""
    import json, re
    import numpy as np
    from screwkit.engine._kernels import _configure
    _configure()
    from numba import guvectorize, njit, prange
    from screwkit.engine._kernels import _linking

    @njit
    def weight(x, k):
        return x * x + k if x > 0 else k - x

    @njit(parallel=True)
    def kernel(A, k):
        out = np.empty(A.shape[0])
        for r in prange(A.shape[0]):
            s = 0.0
            for q in range(A.shape[1]):
                s += weight(A[r, q], k)
            out[r] = s
        return out

    A = np.linspace(-3.0, 3.0, 60).reshape(12, 5)
    out = kernel(A, 0.5)
    sig = kernel.signatures[0]
    after_kernel = _linking.counts()

    @guvectorize(["void(float64[:], float64[:])"], "(n)->()")
    def total(x, res):
        s = 0.0
        for i in range(x.shape[0]):
            s += weight(x[i], 0.25)
        res[0] = s

    llvm = kernel.inspect_llvm(sig)
    fast = "fast|nnan|ninf|nsz|arcp|contract|afn|reassoc"
    ops = re.findall(r"= (?:fadd|fsub|fmul|fdiv|frem|fneg|fcmp|call)((?: (?:%s))*) " % fast, llvm)
    flags = sorted({f.strip() for f in ops if f.strip()})
    fp = len(re.findall(r"= (?:fadd|fsub|fmul|fdiv|frem|fneg|fcmp) ", llvm))
    print(json.dumps({"installed": _linking.installed(), "fp": fp, "flags": flags,
                      "out": out.tolist(), "total": total(A).tolist(),
                      "after_kernel": after_kernel, "after_gufunc": _linking.counts()}))
""")


def _run(flag, tmp_path):
    env = dict(os.environ, SCREWKIT_NUMBA_LINKING=flag, NUMBA_CACHE_DIR=str(tmp_path / flag))
    r = subprocess.run([sys.executable, "-c", _PROGRAM], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def _weight(x, k):
    return np.where(x > 0, x * x + k, k - x)


def test_a_prange_kernel_compiles_to_the_same_code_without_its_wrappers_machine_code(tmp_path):
    deferred = _run("1", tmp_path)
    numbas = _run("0", tmp_path)
    assert deferred["installed"] is True and numbas["installed"] is False
    # the kernel's code is optimised once instead of once a library (LLVM's passes may
    # unroll and addressing may differ), never with a flag that lets LLVM change a
    # floating-point result (fast-math, contract, reassoc...): the same results, bit for bit
    assert deferred["fp"] >= 10 and numbas["fp"] >= 10
    assert deferred["flags"] == [] and numbas["flags"] == []
    assert deferred["out"] == numbas["out"] and deferred["total"] == numbas["total"]
    # the loop's libraries (its body, the gufunc's and the launcher's wrappers) deferred,
    # never made; the body's environment set in the kernel's module
    assert deferred["after_kernel"]["deferred"] >= 3
    assert deferred["after_kernel"]["made"] == 0
    assert deferred["after_kernel"]["pending_envs"] == 0
    # guvectorize's wrapper library (the gufunc wrapper's kind) asked for its pointer
    gained = {k: deferred["after_gufunc"][k] - deferred["after_kernel"][k]
              for k in ("deferred", "made")}
    assert gained["deferred"] >= 1 and gained["made"] == gained["deferred"]
    assert numbas["after_gufunc"] == {"deferred": 0, "made": 0, "pending_envs": 0}
    # the results themselves, by hand (numpy)
    A = np.linspace(-3.0, 3.0, 60).reshape(12, 5)
    assert np.allclose(deferred["out"], _weight(A, 0.5).sum(axis=1), rtol=1e-15, atol=0)
    assert np.allclose(deferred["total"], _weight(A, 0.25).sum(axis=1), rtol=1e-15, atol=0)


def test_install_is_made_once_and_never_over_a_numba_it_does_not_know(tmp_path):
    program = textwrap.dedent("""
        from numba.core import codegen
        from screwkit.engine._kernels import _linking
        from numba.parfors import parfor_lowering
        original = codegen.JITCodeLibrary.get_pointer_to_function
        body = parfor_lowering._create_gufunc_for_parfor_body
        saved = codegen.CPUCodeLibrary._verify_declare_only_symbols
        from screwkit.engine._kernels import _loading
        tested, _loading.TESTED = _loading.TESTED, ()          # a numba release not tested
        assert _linking.install() is False
        assert codegen.JITCodeLibrary.get_pointer_to_function is original
        _loading.TESTED = tested
        del codegen.CPUCodeLibrary._verify_declare_only_symbols     # a numba that differs
        assert _linking.install() is False
        assert codegen.JITCodeLibrary.get_pointer_to_function is original
        assert parfor_lowering._create_gufunc_for_parfor_body is body
        codegen.CPUCodeLibrary._verify_declare_only_symbols = saved
        assert _linking.install() is True and _linking.install() is True
        assert codegen.JITCodeLibrary.get_pointer_to_function.__wrapped__ is original
        assert parfor_lowering._create_gufunc_for_parfor_body.__wrapped__ is body
        print("ok")
    """)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    r = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                       env=env, timeout=600)
    assert r.returncode == 0 and r.stdout.strip() == "ok", r.stderr


_CALLEE = textwrap.dedent("""
    import json, sys
    import numpy as np
    from screwkit.engine._kernels import _configure
    _configure()
    from numba import njit, prange
    from screwkit.engine._kernels import _linking, _small

    @njit
    def turned(d, a):
        R = np.empty((3, 3))
        _small.rodrigues(d[0], d[1], d[2], a, R)
        return R

    @njit(parallel=True)
    def turned_all(D, A):
        out = np.empty((D.shape[0], 3, 3))
        for i in prange(D.shape[0]):
            _small.rodrigues(D[i, 0], D[i, 1], D[i, 2], A[i], out[i])
        return out

    D = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.48, 0.6, 0.64]])
    A = np.array([0.3, -1.2, 2.5])
    one = turned(D[0], A[0])
    lib = next(iter(_small.rodrigues.overloads.values())).library
    got = {"loaded": sum(_small.rodrigues._cache_hits.values()),
           "deferred": _linking.deferred(lib), "one": one.tolist()}
    if sys.argv[1] == "parallel":
        got["all"] = turned_all(D, A).tolist()
        got["deferred_after"] = _linking.deferred(lib)
    got["counts"] = _linking.counts()
    print(json.dumps(got))
""")


def _callee_run(tmp_path, what):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    r = subprocess.run([sys.executable, "-c", _CALLEE, what], capture_output=True,
                       text=True, env=env, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_a_kernels_callee_makes_no_machine_code_and_is_cached_for_linking(tmp_path):
    """A kernel only other code calls (``_small.rodrigues``) is optimised but makes no
    machine code, and is cached as its module's bitcode: a process compiling a function
    against it then loads it so, and links it in; a parallel kernel links it after its
    machine code is made (numba's own order), in the process that compiled it and in one
    that loads it.  The results equal scipy's rotation matrices."""
    from scipy.spatial.transform import Rotation
    D = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.48, 0.6, 0.64]])
    A = np.array([0.3, -1.2, 2.5])
    want = Rotation.from_rotvec(D * A[:, None]).as_matrix()
    first = _callee_run(tmp_path, "parallel")          # (compiled here, an empty cache)
    assert first["loaded"] == 0 and first["deferred"] is True
    assert first["deferred_after"] is False and first["counts"]["made"] >= 1
    np.testing.assert_allclose(first["one"], want[0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(first["all"], want, rtol=0, atol=1e-15)
    later = _callee_run(tmp_path, "serial")            # (loaded from the cache: bitcode)
    assert later["loaded"] == 1 and later["deferred"] is True
    assert later["counts"]["made"] == 0 and later["one"] == first["one"]
    again = _callee_run(tmp_path, "parallel")          # (loaded, then made for the kernel)
    assert again["loaded"] == 1 and again["deferred"] is True
    assert again["deferred_after"] is False and again["counts"]["made"] >= 1
    assert again["one"] == first["one"] and again["all"] == first["all"]
