"""The decorators of the kernels (private).

``inner`` for functions called only from other kernels (no CPython or C wrapper is built:
a large part of the compile time of functions taking tuples of arrays), ``entry`` for the
ones Python calls, ``parallel`` for the ``prange`` drivers.  Division follows numpy's error
model (no Python exception branch on every division).

No fast-math flag, not even ``contract``: with it LLVM may fuse a multiply and an add into
one FMA (one rounding instead of two), and which pairs it fuses depends on the IR it is
given, which depends on how the kernel was built: compiled in this process with its callees
or loaded from the on-disk cache, inlined into the serial or the ``prange`` driver.  A
freshly compiled kernel then differed in the last bits from the cached one (a Dask worker's
map from the serial map).  Strict IEEE arithmetic makes every result a function of the
inputs alone, however and wherever the kernel was compiled.
"""

from numba import njit

_OPTIONS = dict(cache=True, error_model="numpy")

inner = njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **_OPTIONS)
entry = njit(**_OPTIONS)
parallel = njit(parallel=True, **_OPTIONS)
