"""Launching the compiled kernels on N poses: outputs allocated once, threads (private).

Every function here allocates the outputs of a kernel, fills them by one call (in
``prange`` on ``workers`` threads when there are enough poses, else in this thread) and
returns them.  The arrays handed to the kernels are C-contiguous float64/int64 arrays of
fixed dimensions, so that one compiled version of each kernel serves every model.
"""

from __future__ import annotations

import os
import threading
from contextlib import contextmanager

import numpy as np

from ._arrays import Packed
from ._kernels import LAUNCH_LOCK, kernels, note_first_compile, set_threads
from ._kernels._layout import LINE_WIDTH, MIN_PER_THREAD, STENCIL_WIDTH
from ._memory import recycled_empty
from ._outputs import OUT_KINDS, OUTPUTS, OnePose, OutputBuffers, rows_of, views_of

__all__ = ["threads", "on_this_thread", "run_poses", "OUTPUTS", "OutputBuffers",
           "output_buffers", "frames",
           "platform_of", "statics_of", "leg_wrenches", "kernel_input"]

#: Fewest poses a launch of the analysis kernel on one thread runs in blocks (the parallel
#: kernel on one thread: its closures solved :data:`._kernels._layout.BLOCK` poses at a time,
#: about 2.5 times less CPU a pose than the serial kernel, which forms each pose alone; the
#: same bits).  Below :data:`BLOCKS_LOADING` poses only where this process has loaded the
#: parallel kernel already: a small batch of a one-pose command neither loads nor compiles it.
BLOCKS_ALONE = 64
BLOCKS_LOADING = 2 * MIN_PER_THREAD

# (MIN_PER_THREAD: the fewest poses a thread worth a parallel launch; a block launch's poses
# are cut into about PIECES_PER_THREAD pieces a thread of at least MIN_PIECE poses, each
# thread taking the next piece when it is done with one: a thread slowed by another process
# or by another Python thread of this one, a map's numpy work, takes fewer; the kernels'
# constants, ``_kernels._layout``, the pieces ``_kernels._threads.piece_of``)
_NO_PATH_F, _NO_PATH_I = np.empty(0), np.empty(0, np.int64)

#: How long the first compile of a parallel kernel takes (the note on stderr).
PARALLEL_COMPILE = "one to four minutes, depending on the machine"

_CORES = min(2, os.cpu_count() or 1)
#: ``on``: this Python thread's launches run on it alone (:func:`on_this_thread`).
_HERE_ONLY = threading.local()


def threads(N: int, workers=None, per_thread: int = MIN_PER_THREAD) -> int:
    """Threads for ``N`` poses: ``workers``, or by default up to 2 (the cores) when there
    are enough poses (``per_thread`` a thread)."""
    if workers is None:
        workers = _CORES
    return max(1, min(int(workers), N // per_thread or 1))


def _c(a, dtype=float):
    return np.ascontiguousarray(a, dtype)


def kernel_input(a, dtype=float):
    """``a`` contiguous and read-only (a view where it was writable): a kernel's input,
    typed the same whether the caller's array was writable or not (numba compiles a
    read-only array's kernel apart: one more compile of the kernel for nothing)."""
    v = np.ascontiguousarray(a, dtype)
    if v.flags.writeable:
        v = v.view()
        v.setflags(write=False)
    return v


def _launch(serial, par, args, N, workers, per_thread=MIN_PER_THREAD, note=False,
            blocks=False, pieces=False, path=(_NO_PATH_F, _NO_PATH_I)):
    """``serial(*args, 0, N)`` on this thread, or ``par(*args, threads)`` on the threads
    :func:`threads` gives; ``blocks``: ``par`` also on one thread (the analysis kernel's
    parallel version solves its poses in blocks, the serial one each pose alone);
    ``pieces``: the analysis kernel, ``serial(*args, 0, N, *path)`` or ``par(*args,
    threads, *path)`` (its threads take pieces of the poses: ``_kernels._threads.piece_of``;
    ``path``: a path's state, :class:`._path_launch.LevelLaunches`, or none)."""
    nw = threads(N, workers, per_thread)
    if (nw <= 1 and not blocks) or getattr(_HERE_ONLY, "on", False):
        serial(*args, 0, N, *(path if pieces else ()))
        return
    if note:
        # (a one-pose command never runs the parallel analysis kernel: its first compile
        # comes with the first batch that needs threads, and says so)
        note_first_compile(par, "the engine's parallel kernel for batches", PARALLEL_COMPILE)
    with LAUNCH_LOCK:
        # (numba's pool may hold fewer threads: a launch's ranges are as many as its threads)
        nw = set_threads(nw)
        par(*args, nw, *(path if pieces else ()))


@contextmanager
def on_this_thread():
    """Within: the kernels this Python thread launches run on it alone (their serial
    versions, without the GIL), never on numba's threads, which run one launch at a time
    (:data:`LAUNCH_LOCK`).  For a thread that works beside another one's parallel launches
    (a map's arrays of one block while the next is analysed): the same bits."""
    before = getattr(_HERE_ONLY, "on", False)
    _HERE_ONLY.on = True
    try:
        yield
    finally:
        _HERE_ONLY.on = before


class _Plan:
    """What a launch of the analysis kernel on ``N`` poses of one model lays out, made once
    per model and kind of launch (:func:`_plan`): the packed layouts of the inputs and of
    the outputs, where each array starts in its buffer, the flags, and the inputs that do
    not change between calls (the torque rows, in the integer buffer)."""

    __slots__ = ("in_d", "in_nf", "in_f", "in_i", "in_rows", "in_stencil", "out", "out_d",
                 "out_nf", "out_ni", "flags", "one")


def _plan(flat, N, nx0, nside, ncomp, solve, rows, statics, continuation, twists,
          lines=False, nrows=0, nstencil=0, excess=False, nguess=0, orient=False) -> _Plan:
    key = ("plan", N, nx0, nside, ncomp, solve, rows, statics, continuation, twists, lines,
           nrows, nstencil, excess, nguess, orient)
    plan = flat.packed.get(key)
    if plan is not None:
        return plan
    nx, mr, n = flat.nu + flat.n * flat.m, flat.mr, flat.n
    rn = N if rows else 0
    sn = N if (rows and statics) else 0
    plan = _Plan()
    # (the warm starts' rows: the unknowns, then the pose each solves where it is given)
    ins = [(N, 6), (nx0, nx + (6 if nguess else 0)), (nside,), (3,), (3,), (ncomp, mr), (mr,),
           (nrows,), (nstencil, STENCIL_WIDTH)]
    inp = Packed(ins, ("f",) * 6 + ("i", "i", "f"))
    plan.in_d, plan.in_nf = inp.d, inp.f.size
    plan.in_f = [(o, o + size, sh) for (o, size), sh in zip(inp.offsets[:6], ins)]
    plan.in_stencil = (inp.offsets[8][0], inp.offsets[8][0] + inp.offsets[8][1], ins[8])
    plan.in_i = inp.i
    t0 = inp.offsets[6][0]
    plan.in_i[t0:t0 + mr] = flat.torque          # constant: the kernel only reads it
    plan.in_rows = inp.offsets[7][0]
    out = Packed([(N, nx), (N,), (N,), (N,), (N,), (rn, mr, 6), (rn, mr), (rn,), (rn, n),
                  (rn, 3), (rn,), (rn, min(mr, 6)), (rn,), (rn,), (rn,), (rn,), (sn, mr),
                  (sn,), (sn,), (sn,), (N if twists else 0, flat.n_act, 6),
                  (N if lines else 0, n, LINE_WIDTH), (N if lines else 0, 27),
                  (N if excess else 0,), (N,)], OUT_KINDS)
    plan.out_d, plan.out_nf, plan.out_ni = out.d, out.f.size, out.i.size
    plan.out = tuple((kd != "f", kd == "b", o, o + size, sh if len(sh) > 1 else None)
                     for sh, kd, (o, size) in zip(out.shapes, out.kinds, out.offsets))
    plan.flags = np.array([int(solve), int(rows), int(rows and statics), int(continuation),
                           int(twists), int(lines), int(orient)], np.int64)
    plan.one = OnePose(plan.out, plan.out_nf, plan.out_ni) if N == 1 else None
    if len(flat.packed) > 64:              # (maps launch many sizes: keep the cache small)
        for k in [k for k in list(flat.packed) if k[0] == "plan"]:
            flat.packed.pop(k, None)
    flat.packed[key] = plan
    return plan


def output_buffers(flat, N: int, *, rows=True, statics=True, twists=False,
                   lines=False, excess=False) -> OutputBuffers:
    """Empty output buffers of ``N`` poses for launches of :func:`run_poses` with the same
    ``rows``, ``statics``, ``twists`` and ``lines`` on ranges of them; ``excess``: with the
    rows of the excess of a path level's samples (launches given a ``stencil``)."""
    plan = _plan(flat, N, 0, 0, 0, True, bool(rows), bool(statics), True, bool(twists),
                 bool(lines), excess=bool(excess))
    b = OutputBuffers()
    b.f, b.i = recycled_empty(plan.out_nf), recycled_empty(plan.out_ni, np.int64)
    b.d, b.layout, b.N = plan.out_d, plan.out, N
    b.kind = (bool(rows), bool(rows and statics), bool(twists), bool(lines), bool(excess))
    return b


def run_poses(flat, Z, P6, *, X0=None, G6=None, X=None, side=None, F=None, T=None,
              compliance=None, solve=True, rows=True, statics=True, continuation=True,
              twists=False, lines=False, orient=False, workers=None,
              per_thread: int = MIN_PER_THREAD,
              blocks: bool | None = True, out=None, frozen: bool = False) -> dict:
    """The analysis kernel on the poses ``P6 (N, 6)`` (given parameters in place; the
    dependent ones are ignored): closures from the warm starts ``X0 (N, nx)`` (with ``G6 (N,
    6)``, the parameters of the poses they solve: each moved by the home predictor's change
    from there, where it lies on the predictor's branch, ``_kernels/_solve_lanes.
    moved_starts``) or the home predictor (``solve``), or the frames of the given unknowns
    ``X (N, nx)``; then the rows,
    conditioning (``rows``) and statics under ``(F, T)`` at ``o`` (``statics``).  Returns the
    outputs by name (:data:`OUTPUTS`); with ``lines`` also ``lines (N, n, LINE_WIDTH)``, the
    joints the transmission indices read (``_kernels/_indices.pose_lines``), and the platform
    ``platform (N, 27)`` of each pose (empty without); with ``orient`` (and ``statics``)
    ``det_sign`` times each leg's orientation (``_kernels/_orient.py``; the assembly-mode
    sign before its reference, :func:`._quality.det_signs`).  ``per_thread``: the fewest poses
    worth a thread (fewer for poses that cost more, such as closures solved from home).
    ``blocks``: on one thread too, at least :data:`BLOCKS_ALONE` poses run in blocks (see
    there); None: only where this process has loaded the parallel kernel already (nothing
    loaded or compiled for this launch); False: on one thread, the serial kernel (each pose
    alone), whatever ``N``.  The outputs are the same bit for bit either way.  ``out``
    ``(buffers, at)``: the outputs written into rows ``at..at+N`` of ``buffers``
    (:func:`output_buffers`, made with the same ``rows``, ``statics``, ``twists`` and
    ``lines``) and returned as views of those rows; or, ``at`` an integer array ``(N,)``,
    pose ``j``'s outputs into row ``at[j]`` of ``buffers`` (a path's level: its samples'
    rows of the path's outputs), the whole buffers' arrays returned (views; the booleans
    as their integers, :meth:`OutputBuffers.arrays` without ``convert``).  (A path's levels:
    :class:`._path_launch.LevelLaunches`.)  ``frozen``: one pose's outputs of
    :data:`._outputs.FROZEN` read-only (:meth:`._outputs.OnePose.views`)."""
    k = kernels()
    N = len(P6)
    comp = None if compliance is None else np.atleast_2d(compliance)
    scattered = out is not None and np.ndim(out[1]) == 1
    plan = _plan(flat, N, 0 if X0 is None else N,
                 0 if side is None else len(side),
                 0 if comp is None else comp.shape[0], solve and X is None, bool(rows),
                 bool(statics), bool(continuation), bool(twists), bool(lines),
                 N if scattered else 0, 0, out is not None and out[0].kind[-1],
                 N if G6 is not None and X0 is not None else 0, bool(orient))
    # the inputs, packed (the layout is the plan's; the values are copied)
    If = np.empty(plan.in_nf)
    (p0, p1, psh), (x0, x1, xsh), (s0, s1, _), (f0, f1, _), (t0, t1, _), \
        (c0, c1, csh) = plan.in_f
    If[p0:p1].reshape(psh)[...] = P6
    if X0 is not None:
        if G6 is None:
            If[x0:x1].reshape(xsh)[...] = X0
        else:
            rows = If[x0:x1].reshape(xsh)
            rows[:, :-6], rows[:, -6:] = X0, G6
    if side is not None:
        If[s0:s1] = side
    If[f0:f1] = 0.0 if F is None else F
    If[t0:t1] = 0.0 if T is None else T
    if comp is not None:
        If[c0:c1].reshape(csh)[...] = comp
    Ii = plan.in_i
    if out is None:
        Of, Oi = recycled_empty(plan.out_nf), recycled_empty(plan.out_ni, np.int64)
        out_d, layout = plan.out_d, plan.out
    else:
        buffers, at = out
        kind = (bool(rows), bool(rows and statics), bool(twists), bool(lines), buffers.kind[-1])
        if scattered:
            at = np.asarray(at, np.int64)
            if buffers.kind != kind or len(at) != N or (N and not (
                    0 <= at.min() and at.max() < buffers.N)):
                raise ValueError(f"output buffers of {buffers.N} poses {buffers.kind} do not "
                                 f"take the {len(at)} rows given of this launch's outputs")
            Ii = Ii.copy()                   # (the plan's buffer, shared, left as it is)
            Ii[plan.in_rows:] = at
            out_d, layout = buffers.d, buffers.layout
        else:
            if buffers.kind != kind or not 0 <= at <= buffers.N - N:
                raise ValueError(f"output buffers of {buffers.N} poses {buffers.kind} do not "
                                 f"take rows {at}..{at + N} of this launch's outputs")
            out_d, layout = rows_of(buffers, at, N)
        Of, Oi = buffers.f, buffers.i
    if X is not None:
        _, _, o0, o1, sh = layout[0]
        if scattered:
            Of[o0:o1].reshape(sh)[at] = X
        else:
            Of[o0:o1].reshape(sh)[...] = X
    Mp, Zp = flat.pack(Z)
    _launch(k.run_range, k.run_parallel,
            Mp.args + Zp.args + (If, Ii, plan.in_d, Of, Oi, out_d, plan.flags),
            N, workers, per_thread, note=True, pieces=True,
            blocks=blocks is not False and N >= BLOCKS_ALONE and (
                bool(k.run_parallel.overloads) or (blocks and N >= BLOCKS_LOADING)))
    if scattered:                   # (views of the whole buffers: no boolean copied)
        return buffers.arrays(convert=False)
    if out is None and plan.one is not None:       # (one pose: records, see _outputs)
        return plan.one.views(Of, Oi, frozen)
    return views_of(Of, Oi, layout, True)


def frames(flat, Z, P6, X, *, slots=False, bars=False, twists=False, workers=None) -> dict:
    """The frames of the unknowns ``X (N, nx)``: ``axes_points (N, n, m, 6)``, the platform
    ``platform (N, 27)`` (pose parameters, ``Rp``, ``o``, ``E``); with ``slots`` the
    displacement after each slot ``R (N, n, m, 3, 3)``, ``t (N, n, m, 3)``; with ``bars``
    the parallelograms' current bar vectors ``(N, n, m, 3)``; with ``twists`` every joint's
    unit twist ``(N, n, m, 6)`` about O."""
    k = kernels()
    P6, X = _c(P6), _c(X)
    N = P6.shape[0]
    n, m = flat.n, flat.m
    ns = N if slots or bars else 0
    out = (np.zeros((N, n, m, 6)), np.empty((N, 27)), np.zeros((ns, n, m, 3, 3)),
           np.zeros((ns, n, m, 3)), np.zeros((N if bars else 0, n, m, 3)),
           np.zeros((N if twists else 0, n, m, 6)), np.empty(N))
    _launch(k.frames_range, k.frames_parallel, (flat.M, Z[0], Z[1], P6, X) + out, N, workers)
    return {"axes_points": out[0], "platform": out[1], "R": out[2], "t": out[3],
            "bars": out[4], "twists": out[5], "residual": out[6]}


def platform_of(flat, P6, workers=None) -> np.ndarray:
    """The platform ``(N, 27)`` (pose parameters, ``Rp``, ``o``, ``E``) at the six pose
    parameters ``P6 (N, 6)``."""
    given = (np.zeros(0, np.int64), np.zeros(0))
    N = len(P6)
    return frames(flat, given, P6, np.zeros((N, flat.n * flat.m)), workers=workers)["platform"]


def statics_of(J, centre, length, sv, torque, W, o, compliance=None, workers=None):
    """``F_r (N, K, mr)``, equilibrium residuals and force amplifications ``(N, K)`` of the
    Jacobians ``J (N, mr, 6)`` under the workloads ``W (N, K, 6)`` about O."""
    k = kernels()
    ro = kernel_input
    J, W = ro(J), ro(W)
    N, mr = J.shape[0], J.shape[1]
    K = W.shape[1]
    comp = ro(np.zeros((0, mr)) if compliance is None else np.atleast_2d(compliance))
    out = (np.empty((N, K, mr)), np.empty((N, K)), np.empty((N, K)))
    _launch(k.statics_range, k.statics_parallel,
            (J, ro(centre), ro(length), ro(sv), comp, ro(torque, np.int64), W, ro(o))
            + out, N, workers)
    return out


def leg_wrenches(J, values, row_leg, n_act, A, a, *, total=True, workers=None):
    """Each leg's constraint wrench and (``total``) total wrench ``(N, K, n, 6)`` about O,
    and ``T_r (N, K, n)``, from ``J (N, mr, 6)`` and ``values (N, K, mr)``; ``a (N, n, 3)``."""
    k = kernels()
    ro = kernel_input
    J, values = ro(J), ro(values)
    N, K = values.shape[0], values.shape[1]
    n = len(A)
    out = (np.empty((N, K, n, 6)), np.empty((N if total else 0, K, n, 6)), np.empty((N, K, n)))
    _launch(k.leg_wrenches_range, k.leg_wrenches_parallel,
            (J, values, ro(row_leg, np.int64), int(n_act), ro(A), ro(a)) + out, N, workers)
    return out
