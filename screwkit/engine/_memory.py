"""Large arrays filled once, without numpy's huge-page advice (private).

numpy advises the kernel to back every array of 4 MiB or more with transparent huge pages
(``madvise(MADV_HUGEPAGE)``).  Where the kernel's ``defrag`` setting is ``madvise`` (a
common default), the first touch of each 2 MiB page of such an array may then wait while
the kernel compacts memory to find one.  An array written once, piece by piece (the outputs
of a map or of a path gathered from many launches), pays that wait on every page and gains
little from the larger pages afterwards: measured on this project's machines, the copies
into a 1e6-cell map's arrays took 0.13-0.51 s with the advice and 0.10 s without.  (The
analysis kernel's own output buffers, and a path's outputs, showed no difference either
way on a quiet machine: they are not allocated here.)  :func:`fresh_array` allocates such
an array in anonymous memory of its own, mapped without the advice (small arrays as numpy
does).
"""

from __future__ import annotations

import mmap

import numpy as np

__all__ = ["fresh_array", "ADVISED_BYTES"]

#: numpy's threshold for the huge-page advice (``NPY_HUGEPAGE`` size: 4 MiB).
ADVISED_BYTES = 1 << 22


def fresh_array(shape, dtype=float, order: str = "C") -> np.ndarray:
    """An uninitialised array of ``shape`` and ``dtype`` (``order`` C or F), in anonymous
    memory mapped for it alone without the huge-page advice when it is at least
    :data:`ADVISED_BYTES` (then its pages are the system's default pages, zeroed on first
    touch); as :func:`numpy.empty` below that.  The memory is released with the array."""
    dtype = np.dtype(dtype)
    shape = (int(shape),) if np.ndim(shape) == 0 else tuple(int(s) for s in shape)
    nbytes = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
    if nbytes < ADVISED_BYTES:
        return np.empty(shape, dtype, order=order)
    buf = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    return np.ndarray(shape, dtype, buffer=buf, order=order)
