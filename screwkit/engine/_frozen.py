"""Arrays the results hand out are read-only; the kernels take them as they took them before.

A result keeps its arrays (its ``J``, its statics, its conditioning) and hands out read-only
views of them: written by a user, they would change what the result computes later
(``res.under``) and says (its classification), silently.  numba compiles a kernel apart for
read-only arguments, so a result's array goes to a kernel as a writable view of the same
buffer (:func:`kernel_array`): one compiled version of each kernel, no copy.
"""

from __future__ import annotations

import numpy as np

from ..screws._frozen import freeze_fields, read_only

__all__ = ["freeze_fields", "kernel_array", "read_only"]


def kernel_array(a, dtype=float) -> np.ndarray:
    """``a`` C-contiguous as a kernel's writable-typed argument: a writable view where its
    buffer is writable (a result's read-only view), else a copy."""
    a = np.ascontiguousarray(a, dtype)
    if a.flags.writeable:
        return a
    v = a.view()
    try:
        v.setflags(write=True)
    except ValueError:                  # (a buffer that is read-only itself)
        return a.copy()
    return v
