"""The decorators of the kernels (private).

``inner`` for functions called only from other kernels (no CPython or C wrapper is built:
a large part of the compile time of functions taking tuples of arrays), ``entry`` for the
ones Python calls, ``parallel`` for the ``prange`` drivers.  Division follows numpy's error
model (no Python exception branch on every division); multiply-adds may be contracted.
"""

from numba import njit

_OPTIONS = dict(cache=True, error_model="numpy", fastmath={"contract"})

inner = njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **_OPTIONS)
entry = njit(**_OPTIONS)
parallel = njit(parallel=True, **_OPTIONS)
