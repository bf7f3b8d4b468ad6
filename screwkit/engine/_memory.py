"""Large arrays: fresh without numpy's huge-page advice, or recycled (private).

numpy advises the kernel to back every array of 4 MiB or more with transparent huge pages
(``madvise(MADV_HUGEPAGE)``).  Where the kernel's ``defrag`` setting is ``madvise`` (a
common default), the first touch of each 2 MiB page of such an array may then wait while
the kernel compacts memory to find one.  An array written once, piece by piece (the outputs
of a map or of a path gathered from many launches), pays that wait on every page and gains
little from the larger pages afterwards: measured on this project's machines, the copies
into a 1e6-cell map's arrays took 0.13-0.51 s with the advice and 0.10 s without.
:func:`fresh_array` allocates such
an array in anonymous memory of its own, mapped without the advice (small arrays as numpy
does).

The analysis kernel's output buffers (and a path's unknowns) are taken from a
:class:`Recycler` instead: memory of the same size that earlier results handed back once
nothing referred to it any more.  Fresh memory costs the system a page fault a page (and
zeroing it) on first touch: measured on 100,000 poses of the 3RRPRR, 7-83 ms of system time
an analysis (73 MB of outputs; 5-40 % of the analysis), none once the memory is recycled.
"""

from __future__ import annotations

import collections
import mmap
import threading
import weakref

import numpy as np

__all__ = ["fresh_array", "recycled_empty", "Recycler", "RECYCLER", "ADVISED_BYTES",
           "RECYCLED_BYTES", "RECYCLE_LIMIT"]

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


#: Buffers of at least this size (1 MiB) are recycled; smaller ones are numpy's (the C
#: library's allocator reuses those itself).
RECYCLED_BYTES = 1 << 20
#: The most memory of freed buffers kept for reuse (256 MiB: three analyses of 100,000 poses
#: of a 3RRPRR).  A buffer larger than this is never kept, and a buffer of a size not kept
#: releases kept ones until the kept and the new together fit: an analysis never holds more
#: memory than this beside what it uses.
RECYCLE_LIMIT = 256 << 20


class Recycler:
    """Anonymous memory for large buffers, reused once nothing refers to it.

    :meth:`empty` hands out a 1-D array whose memory is a private anonymous mapping; every
    view of it (numpy collapses views to the array that holds the buffer) keeps it alive.
    When the last one goes, the mapping comes back here (``weakref.finalize``), and the next
    buffer of the same size in pages takes it, as it is: its contents are those of the last
    user, so the callers write every element they read (as of :func:`numpy.empty`).  At
    most ``limit`` bytes are kept, oldest released first.  Thread-safe (a reentrant lock: a
    buffer may come back from a garbage collection on the thread taking one)."""

    def __init__(self, limit: int = RECYCLE_LIMIT):
        self.limit = int(limit)
        self._kept = collections.deque()          # (bytes, mapping), oldest first
        self._bytes = 0
        self._lock = threading.RLock()

    @property
    def kept_bytes(self) -> int:
        """The memory kept for reuse now (bytes)."""
        return self._bytes

    def empty(self, n: int, dtype=float) -> np.ndarray:
        """An uninitialised array of ``n`` elements of ``dtype``: recycled memory of its size
        in pages when some is kept, else a fresh mapping (its pages zeroed on first touch,
        without numpy's huge-page advice: see the module)."""
        dtype = np.dtype(dtype)
        nbytes = int(n) * dtype.itemsize
        if nbytes < RECYCLED_BYTES:
            return np.empty(int(n), dtype)
        size = -(-nbytes // mmap.PAGESIZE) * mmap.PAGESIZE
        raw = self._take(size)
        if raw is None:
            raw = mmap.mmap(-1, size, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
        owner = np.frombuffer(raw, np.uint8)       # (writable: the mapping is)
        weakref.finalize(owner, self._give_back, size, raw).atexit = False
        return owner[:nbytes].view(dtype)

    def clear(self) -> None:
        """Release every mapping kept."""
        with self._lock:
            self._kept.clear()
            self._bytes = 0

    def _take(self, size):
        with self._lock:
            for j, (s, raw) in enumerate(self._kept):
                if s == size:
                    del self._kept[j]
                    self._bytes -= s
                    return raw
            # a size not kept: the kept ones go first where it would not fit beside them
            while self._kept and self._bytes + size > self.limit:
                self._bytes -= self._kept.popleft()[0]
        return None

    def _give_back(self, size, raw):
        if size > self.limit:
            return
        with self._lock:
            self._kept.append((size, raw))
            self._bytes += size
            while self._bytes > self.limit:
                self._bytes -= self._kept.popleft()[0]


#: The engine's recycler (the analysis kernel's output buffers, a path's unknowns).
RECYCLER = Recycler()


def recycled_empty(n: int, dtype=float) -> np.ndarray:
    """``RECYCLER.empty(n, dtype)``: an uninitialised 1-D array, in recycled memory when it
    is large (:class:`Recycler`)."""
    return RECYCLER.empty(n, dtype)
