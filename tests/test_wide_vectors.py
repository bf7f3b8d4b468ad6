"""The kernels compiled for 512-bit vectors on a CPU with AVX-512
(``_kernels.wide_vector_features``): the setting itself, a user's own left alone, and the
same bits as LLVM's default 256-bit preference.

Independent reference for the bits: the same lane loops (the QL eigenvalues of a block's
Gram matrices, the LU solves across lanes) compiled in two fresh interpreters, one with the
wide vectors and one with ``SCREWKIT_WIDE_VECTORS=0``, on the same inputs; on a CPU without
AVX-512 both are LLVM's default (the test still checks the two runs agree)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np

from screwkit.engine._kernels import wide_vector_features

_LANES = """
import sys
import numpy as np
from screwkit.engine._kernels import kernels
kernels()                                           # (numba set up as the engine sets it)
import numba
from numba import njit
from screwkit.engine._kernels._eigen import symmetric_eigenvalues_lanes
from screwkit.engine._kernels._layout import BLOCK
from screwkit.engine._kernels._small import lu_apply_block, lu_block

@njit(cache=False)
def run(G, A, b):
    d, e, S = np.zeros((6, BLOCK)), np.zeros((6, BLOCK)), np.zeros((6, BLOCK))
    symmetric_eigenvalues_lanes(G, 6, d, e, S, BLOCK, BLOCK)
    piv = np.zeros((6, BLOCK), np.int64)
    lu_block(A, 6, piv, BLOCK)
    lu_apply_block(A, 6, piv, b, BLOCK)
    return d

rng = np.random.default_rng(3)
R = rng.normal(size=(BLOCK, 6, 6))
R /= np.linalg.norm(R, axis=2, keepdims=True)
G = np.ascontiguousarray(np.einsum("kij,klj->ilk", R, R))     # unit rows' Gram, lanes last
A = np.ascontiguousarray(np.moveaxis(rng.normal(size=(BLOCK, 6, 6)), 0, -1))
b = np.ascontiguousarray(rng.normal(size=(6, BLOCK)))
d = run(G, A, b)
np.savez(sys.argv[1], d=d, b=b, A=A, features=numba.config.CPU_FEATURES or "")
"""


_CONFIG = """
from screwkit.engine._kernels import kernels
kernels()
import numba
print(numba.config.CPU_FEATURES or "")
"""


def _env(tmp_path, **env):
    # (a cache of its own: kernels of other features are not written beside the package's)
    base = {k: v for k, v in os.environ.items()
            if k not in ("NUMBA_CPU_FEATURES", "NUMBA_CPU_NAME", "SCREWKIT_WIDE_VECTORS")}
    return dict(base, NUMBA_CACHE_DIR=str(tmp_path / "numba"), **env)


def _run(tmp_path, name, **env):
    out = tmp_path / f"{name}.npz"
    p = subprocess.run([sys.executable, "-c", _LANES, str(out)], capture_output=True,
                       text=True, timeout=300, env=_env(tmp_path, **env))
    assert p.returncode == 0, p.stderr
    return np.load(out)


def _features(tmp_path, **env):
    p = subprocess.run([sys.executable, "-c", _CONFIG], capture_output=True, text=True,
                       timeout=300, env=_env(tmp_path, **env))
    assert p.returncode == 0, p.stderr
    return p.stdout.strip()


def test_wide_vectors_give_the_default_vectors_bits(tmp_path):
    wide = _run(tmp_path, "wide")
    narrow = _run(tmp_path, "narrow", SCREWKIT_WIDE_VECTORS="0")
    expected = wide_vector_features()
    assert str(wide["features"]) == (expected or "")
    assert str(narrow["features"]) == ""
    for key in ("d", "b", "A"):
        np.testing.assert_array_equal(wide[key], narrow[key])
    # and they are the eigenvalues and solutions (numpy's LAPACK, to rounding; the inputs
    # drawn again from the same seed)
    rng = np.random.default_rng(3)
    R = rng.normal(size=(64, 6, 6))
    R /= np.linalg.norm(R, axis=2, keepdims=True)
    ev = np.linalg.eigvalsh(np.einsum("kij,klj->kil", R, R))
    np.testing.assert_allclose(np.sort(wide["d"].T, axis=1), ev, atol=1e-12)
    A = rng.normal(size=(64, 6, 6))
    b = rng.normal(size=(6, 64)).T
    np.testing.assert_allclose(wide["b"].T, np.linalg.solve(A, b[..., None])[..., 0],
                               rtol=1e-9, atol=1e-9)


def test_the_setting(monkeypatch):
    for off in ("0", "no", " OFF "):
        monkeypatch.setenv("SCREWKIT_WIDE_VECTORS", off)
        assert wide_vector_features() is None
    monkeypatch.delenv("SCREWKIT_WIDE_VECTORS")
    import llvmlite.binding as ll
    host = ll.get_host_cpu_features()
    got = wide_vector_features()
    if host.get("avx512f"):
        assert got == host.flatten() + ",-prefer-256-bit"
    else:
        assert got is None


def test_a_users_cpu_features_are_left_alone(tmp_path):
    assert _features(tmp_path, NUMBA_CPU_FEATURES="+sse2,+sse4.2") == "+sse2,+sse4.2"
    assert _features(tmp_path, NUMBA_CPU_NAME="generic") == ""
    assert _features(tmp_path) == (wide_vector_features() or "")
