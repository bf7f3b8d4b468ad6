"""Each thread of the parallel launches on a CPU of its own (private; Linux).

numba's ``workqueue`` layer hands a launch on ``n`` threads to its first ``n`` worker
threads, one range each.  Between launches they sleep; at a launch the main thread wakes
them, and where every CPU the process may use is already taken (two threads on two CPUs)
the scheduler often wakes both on the same CPU and moves one only some milliseconds later:
a launch of a few thousand poses then runs its two ranges one after the other.  Measured on
the 2-CPU machine of the benchmarks (``/tmp`` prototypes, 3RRPRR, launches of 4,096 random
poses on two threads, 20 in a row): CPU over wall time 1.0-1.35 in 12 of 20 launches
unpinned, 1.90-1.96 in all 20 pinned; a 1e6-cell map (61 launches) 3.04-3.17 s unpinned,
2.73-2.95 s pinned (two alternations of three maps each), the same CPU time.

:func:`pin_threads` sets, from inside each worker, the CPU it may run on.  It is called
once per process and thread count (``screwkit.engine._kernels.set_threads``), only where
the CPUs the process may use are no more than the threads (otherwise the scheduler has a
free CPU to spread them on, and pinning could only stand in its way), and never with
``SCREWKIT_PIN_THREADS=0`` in the environment.
"""

from numba import prange, types
from numba.core import cgutils
from numba.extending import intrinsic
from llvmlite import ir

from ._jit import entry, parallel
from ._layout import BLOCK, MIN_PER_THREAD, MIN_PIECE, PIECES_PER_THREAD


@intrinsic
def _set_affinity(typingctx, mask):
    """``sched_setaffinity(0, sizeof mask, mask)`` for the calling thread: the CPUs of the
    bits set in ``mask`` (uint64 words, CPU ``c`` at bit ``c % 64`` of word ``c // 64``);
    returns 0 or -1 (glibc's)."""
    if not (isinstance(mask, types.Array) and mask.dtype == types.uint64
            and mask.ndim == 1):
        return None

    def codegen(context, builder, sig, args):
        i8p = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.IntType(32), [ir.IntType(32), ir.IntType(64), i8p])
        fn = cgutils.get_or_insert_function(builder.module, fnty, "sched_setaffinity")
        ary = context.make_array(mask)(context, builder, args[0])
        nbytes = builder.mul(builder.extract_value(ary.shape, 0),
                             ir.Constant(ir.IntType(64), 8))
        return builder.call(fn, [ir.Constant(ir.IntType(32), 0), nbytes,
                                 builder.bitcast(ary.data, i8p)])
    return types.int32(mask), codegen


@parallel
def pin_threads(masks, status):
    """Worker ``i`` of a launch on ``n = masks.shape[0]`` threads (range ``i`` of the
    ``prange``: the workqueue gives range ``i`` of ``n`` to its worker ``i``) may run on the
    CPUs of ``masks[i] (words,)`` only; ``status[i]`` its call's result (0: done)."""
    for i in prange(masks.shape[0]):
        status[i] = _set_affinity(masks[i])


def _add_one(counter, ordering):
    """The typing and code of ``counter[0] += 1`` done atomically (with ``ordering``),
    returning the value before, for an int64 array ``counter``."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64):
        return None

    def codegen(context, builder, sig, args):
        ary = context.make_array(counter)(context, builder, args[0])
        return builder.atomic_rmw("add", ary.data, ir.Constant(ir.IntType(64), 1), ordering)
    return types.int64(counter), codegen


@intrinsic
def claim(typingctx, counter):
    """The next piece of a launch's poses: atomically adds one to ``counter[0]`` (an int64
    array shared by the launch's threads) and returns its value before.  Each thread takes
    pieces until they run out, so a thread slowed by another process (or by this process's
    own Python thread) takes fewer: a launch of ``n`` equal ranges waits for its slowest."""
    return _add_one(counter, "monotonic")


@entry
def piece_of(N, nw):
    """Poses of each piece the ``nw`` threads of a block launch of ``N`` poses take as they
    are free (``_driver.run_parallel``): about ``PIECES_PER_THREAD`` a thread, whole blocks
    of ``BLOCK`` poses, at least ``MIN_PIECE``; all ``N`` on one thread."""
    if nw <= 1:
        return max(N, 1)
    per = -(-N // (nw * PIECES_PER_THREAD))
    return max(MIN_PIECE, -(-per // BLOCK) * BLOCK)


@entry
def piece_span(c, N, piece, nw):
    """The poses ``start, stop`` of piece ``c`` of a block launch of ``N`` poses on ``nw``
    threads (:func:`claim` hands out ``c``): pieces of ``piece`` poses (:func:`piece_of`)
    while at least ``2 nw`` of them are left, then each ``1 / (2 nw)`` of the poses left
    (whole blocks, at least ``MIN_PIECE``), so that the threads' last pieces are small and
    they finish together (guided self-scheduling: with equal pieces a thread slowed for a
    moment left the other waiting up to a whole piece at the end of every launch and path
    level).  ``start == N``: no such piece.  (Each pose's bits are its own whatever piece
    holds it.)"""
    start = 0
    for i in range(c + 1):
        left = N - start
        if left <= 0:
            return N, N
        size = piece
        if nw > 1:
            guided = -(-left // (2 * nw))
            size = min(piece, max(MIN_PIECE, -(-guided // BLOCK) * BLOCK))
        stop = min(N, start + size)
        if i == c:
            return start, stop
        start = stop
    return N, N


@entry
def threads_for(N, nthreads):
    """Threads of a launch of ``N`` poses given ``nthreads``: as many as have
    ``MIN_PER_THREAD`` poses each, at least one (``_launch.threads``'s rule)."""
    return max(1, min(nthreads, N // MIN_PER_THREAD))


@intrinsic
def arrive(typingctx, counter):
    """One more thread at a barrier: atomically adds one to ``counter[0]``, its writes
    before it seen by the thread that reads the count (acquire-release); returns the count
    before."""
    return _add_one(counter, "acq_rel")


@intrinsic
def read_acquire(typingctx, counter):
    """``counter[0]`` read atomically (acquire: what its writer wrote before it is seen;
    the read is made again on every call, in a waiting loop too)."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64):
        return None

    def codegen(context, builder, sig, args):
        ary = context.make_array(counter)(context, builder, args[0])
        return builder.load_atomic(ary.data, "acquire", 8)
    return types.int64(counter), codegen


@intrinsic
def write_release(typingctx, counter, value):
    """``counter[0] = value`` atomically (release: what this thread wrote before is seen by
    a thread that reads it with :func:`read_acquire`)."""
    if not (isinstance(counter, types.Array) and counter.dtype == types.int64
            and isinstance(value, types.Integer)):
        return None

    def codegen(context, builder, sig, args):
        ary = context.make_array(counter)(context, builder, args[0])
        v = context.cast(builder, args[1], sig.args[1], types.int64)
        builder.store_atomic(v, ary.data, "release", 8)
        return context.get_dummy_value()
    return types.none(counter, value), codegen
