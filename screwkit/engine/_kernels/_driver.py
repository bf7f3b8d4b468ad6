"""The engine's batch kernels: N poses through closures, rows, conditioning and statics
(private).

Every pose is computed alone, by the same compiled functions, so a batch equals a loop of
one-pose calls bit for bit, whatever the chunks and threads.  The parallel kernels cut the
poses into ``nchunks`` ranges run in ``prange`` (one workspace per range, allocated once).
The analysis has two loops over the poses: :func:`run_range` (one pose, and every launch
on one thread) solves each pose alone and links no block kernel, so that a one-pose
command never compiles them; :func:`run_parallel` (batches on threads) solves the closures
``BLOCK`` poses at a time (:mod:`._block`), with the same bits.

Arguments (tuples of arrays, see :mod:`screwkit.engine._flat`):

* ``M`` the flattened model (:mod:`._layout`);
* ``Z`` the pose parametrisation and the home predictor: ``unk, xs`` (the dependent
  parameters), ``unk2, xs2`` (the same without alpha and gamma: a representation
  singularity), ``fix, fix2`` (the given ones), ``p6home``, the predictor's ``C``, ``fhome``,
  ``fspan`` and ``degree`` (an array of one integer);
* ``I`` the inputs: ``P6 (N, 6)`` the given parameters (the dependent ones are ignored),
  ``X0 (N or 0, nx or nx + 6)`` warm starts (with six more columns, the parameters of the
  pose each solves: the start moved by the home predictor's change from there,
  :func:`._solve_lanes.moved_starts`), ``side (N or 0,)``, ``F (3,)``, ``T (3,)``,
  ``comp (N or 1 or 0, rows)`` compliances (0 rows: the least-norm default), ``torque (rows,)``, ``rows (N
  or 0,)`` the row of the outputs each pose writes (0: its own, :func:`._pack.out_row`),
  ``stencil (N or 0, _layout.STENCIL_WIDTH)`` a path level's starts (the rows of ``X0``
  formed in the launch from the solved samples' unknowns, rows of ``O``'s, and each
  pose's excess written: :func:`._path_loop.path_starts`, :func:`._path_loop.path_excess`);
* ``O`` the outputs (``_layout.OUT_*``), filled pose by pose (of the rows given: a path's
  level writes its samples' rows of the path's outputs, no copy after the launch);
* ``flags``: solve, rows, statics, continuation, actuated twists, the lines of the
  transmission indices' joints and the platform (1/0 each).
"""

import numpy as np
from numba import prange

from ._jit import borrowed, borrowing, entry, inlined, inner, parallel

from ._block import (K_F, K_FA, K_FP, K_SAME, K_STATE, LANE_ALONE, block_lines, block_rows_into,
                     frames_block, lane_frames, make_block, make_rows_lanes,
                     template_rows_block)
from ._finish import finish_block, pose_rows, reads_frames
from ._geometry import legs_frames_block
from ._layout import (BLOCK, D, DIRS, F_LINES, F_ROWS, F_SOLVE, OUT_LINES, OUT_PLATFORM, OUT_X,
                      MIN_PER_THREAD, PTS, RL_J, RL_SP, ROWS, LH_TEAM, SY_ARRIVED, SY_G, SY_READY,
                      SY_SIZE, SY_TAKEN)
from ._levels import prefetch_stencil
from ._pack import inputs, model, outputs, params, prefetch_outputs
from ._reversed import reversed_block
from ._newton import make_work
from ._rows import make_rows_work
from ._solve_lanes import finish_lane, solve_alone, solve_block, start
from ._threads import arrive, claim, piece_of, piece_span, read_acquire, threads_for
from ._path_loop import (lead_level, level_inputs, level_of, path_excess, path_level,
                         path_starts, path_state)
from ._statics import (CW_D, CW_JN, make_conditioning_work, make_statics_work, normalise_lanes,
                       spread_lanes)


@inlined
def _workspaces(M, O, B, C):
    """A thread's one-pose workspace, rows workspace, statics workspace, conditioning
    workspace of blocks of up to ``C`` lanes and rows workspace of blocks of ``B`` lanes
    (their owners: the caller keeps them alive while it uses borrowed views of them)."""
    n, m, npts, ndirs = M[D].shape[0], M[D].shape[1], M[PTS].shape[1], M[DIRS].shape[1]
    return (make_work(n, m, O[OUT_X].shape[1]), make_rows_work(m, npts, ndirs),
            make_statics_work(M[ROWS].shape[0]), make_conditioning_work(M[ROWS].shape[0], C),
            make_rows_lanes(n, m, M[ROWS].shape[0], npts, ndirs, B))


@inlined
def run_poses(M, Z, I, O, flags, first, stop, L):
    """Poses ``first`` to ``stop`` one at a time with one workspace (borrowed views: no
    reference counts in the loop; returns a number so that the owners visibly outlive it).
    The serial kernel's loop (:func:`run_range`: one pose, a launch on one thread): it
    links no block kernel, so that a one-pose command does not compile them.  ``L``: a
    path's level (:func:`._path_loop.level_of`; empty otherwise)."""
    # (no block: no rows of a block; the conditioning's lanes, as many as a block has poses)
    Wo, RWo, SWo, CWo, RLo = _workspaces(M, O, 0, max(1, min(BLOCK, stop - first)))
    W, RW, SW, CW, RL = borrowed(Wo), borrowed(RWo), borrowed(SWo), borrowed(CWo), borrowed(RLo)
    for p0 in range(first, stop, BLOCK):
        nb = min(BLOCK, stop - p0)
        path_level(L, I, p0 if p0 == first else p0 + BLOCK, min(p0 + 2 * BLOCK, stop))
        path_starts(I, O, p0, nb)
        for l in range(nb):
            p = p0 + l
            res, b = 0.0, -1
            if flags[F_SOLVE]:
                start(Z, I, O, p, W)
                res, b = solve_alone(M, Z, I, O, flags, p, W)
            pose_rows(M, Z, I, O, flags, p, W, RW, SW, b, res, CW, l, True, RL, -1)
        finish_block(M, I, O, flags, p0, nb, SW, CW)
        reversed_block(M, I, O, p0, nb)      # (the unknowns at hand: _reversed)
        path_excess(L, I, O, p0, nb, I[7][:0])
    # the owners are used here, so they live (and keep the buffers) until the loop is done
    return Wo[0].shape[0] + RWo[0].shape[0] + SWo[0].shape[0] + CWo[0].shape[0] + RLo[0].size


@inlined
def run_blocks(M, Z, I, O, flags, piece, nw, taken, L):
    """The pieces this thread takes (:func:`._threads.claim` on ``taken``; ``piece`` poses,
    smaller at the end: :func:`._threads.piece_span` of ``nw`` threads)
    with one workspace, their closures solved ``BLOCK`` at a time (:func:`solve_block`), or
    the frames of their given unknowns formed ``BLOCK`` at a time
    (:func:`._block.frames_block`), as :func:`run_poses` otherwise (the same bits: every lane
    is the pose alone).  The parallel kernel's loop (:func:`run_parallel`): the workspaces
    allocated here, the poses run by :func:`block_poses`."""
    n, m = M[D].shape[0], M[D].shape[1]
    nx = O[OUT_X].shape[1]
    N = I[0].shape[0]
    B = BLOCK if N > 1 else 0
    Wo, RWo, SWo, CWo, RLo = _workspaces(M, O, B, BLOCK)
    Ko = make_block(n, m, nx, B)
    a, b = piece_span(claim(taken), N, piece, nw)
    while a < N:
        block_poses(M, Z, I, O, flags, a, b, borrowed(Wo), borrowed(RWo), borrowed(SWo),
                    borrowed(CWo), borrowed(Ko), borrowed(RLo), L)
        a, b = piece_span(claim(taken), N, piece, nw)
    # the owners are used here, so they live (and keep the buffers) until the loop is done
    return Wo[0].shape[0] + RWo[0].shape[0] + SWo[0].shape[0] + CWo[0].shape[0] + \
        Ko[0].shape[0] + RLo[0].shape[0]


@borrowing
def block_poses(M, Z, I, O, flags, first, stop, W, RW, SW, CW, K, RL, L):
    """:func:`run_blocks`'s loop over its poses, with its workspaces (borrowed views): a
    function without reference counts (:func:`~._jit.borrowing`).  In a function with them
    (one that allocates, as :func:`run_blocks`), numba takes and drops a reference to every
    array of every tuple an inlined function receives (the model, the parameters, the
    inputs, the outputs, the workspaces: a hundred-odd calls of ``NRT_incref`` and
    ``NRT_decref`` for each of :func:`finish_lane` and :func:`pose_rows`, a pose), even for
    borrowed views, whose counts are null.  The legs' frames of the rows are formed for the
    block's lanes at once (``RL``), but by a lane finished, rescued or solved alone."""
    # a range of one solves alone (its lane loops folded: see _kin); every pose ends in
    # the one finish_rows below (inlined once: its compile is not paid twice), and every
    # block of poses in finish_block, solved in blocks or not
    blocked = flags[F_SOLVE] and stop - first > 1
    # given unknowns (a path's samples, a map's cells): their frames by the block's forward
    # pass too, the lanes at once (the bits of one pose's pass: see _kin)
    given = not flags[F_SOLVE] and stop - first > 1
    inblock = blocked or given
    for p0 in range(first, stop, BLOCK):
        nb = min(BLOCK, stop - p0)
        kb = 0
        # a path level's samples formed a block ahead (the next block's prefetches read
        # them), still in the caches when their block reads them: the first two blocks at
        # the first, then the next one
        path_level(L, I, p0 if p0 == first else p0 + BLOCK, min(p0 + 2 * BLOCK, stop))
        path_starts(I, O, p0, nb)
        if blocked:
            kb = solve_block(M, Z, I, O, p0, nb, W, K)
        elif given:
            frames_block(M, Z[0], Z[1], I, O[OUT_X], p0, nb, K)
        if inblock and flags[F_ROWS]:
            legs_frames_block(M, K[K_FA][kb], K[K_FP][kb], RL, nb)
            template_rows_block(M, K[K_FA][kb], RL, nb)
            spread_lanes(M, K[K_FA][kb], K[K_FP][kb], RL[RL_SP], nb, BLOCK)
            normalise_lanes(RL[RL_J], M[ROWS].shape[0], RL[RL_SP], CW[CW_JN], CW[CW_D], nb,
                            BLOCK)
            block_rows_into(M, I, O, RL, p0, nb)
        for l in range(nb):
            p = p0 + l
            if p + BLOCK < stop:
                # the next block's rows of the outputs (and the unknowns its stencils read),
                # fetched while this one computes
                prefetch_outputs(I, O, p + BLOCK)
                if I[8].shape[0]:
                    prefetch_stencil(I[8], p + BLOCK, O[OUT_X])
            res, b, fr = 0.0, -1, -1
            if given:
                if reads_frames(M, flags, RL, l):
                    lane_frames(K, 0, l, W, 0, False)
                res, b, fr = K[K_F][l], 0, l
            elif flags[F_SOLVE]:
                # one call site of the closure alone: a pose alone, or a lane the block
                # left to it (near the representation singularity)
                if not blocked:
                    start(Z, I, O, p, W)
                if not blocked or K[K_STATE][l] == LANE_ALONE:
                    res, b = solve_alone(M, Z, I, O, flags, p, W)
                else:
                    res, b, same = finish_lane(M, Z, I, O, flags, p, W, K, l, kb,
                                               reads_frames(M, flags, RL, l))
                    fr = l if same else -1
            pose_rows(M, Z, I, O, flags, p, W, RW, SW, b, res, CW, l, not inblock, RL, fr)
            if inblock:
                K[K_SAME][l] = 1 if fr >= 0 else 0
        if flags[F_LINES] and inblock:
            block_lines(M, Z[0], Z[1], I, O[OUT_X], O[OUT_LINES], O[OUT_PLATFORM], p0, nb,
                        W, K, kb)
        finish_block(M, I, O, flags, p0, nb, SW, CW)
        reversed_block(M, I, O, p0, nb)      # (the unknowns at hand: _reversed)
        path_excess(L, I, O, p0, nb, K[K_SAME] if blocked else K[K_SAME][:0])


@entry
def run_range(Mf, Mi, Md, Zf, Zi, Zd, If, Ii, Id, Of, Oi, Od, flags, first, stop, Lf, Li):
    """Poses ``first`` to ``stop`` (the tuples packed: :mod:`._pack`); with a path's state
    ``Lf, Li`` (:mod:`._path_loop`; empty otherwise), the path's levels one after the other
    (as :func:`run_parallel`, on this thread)."""
    M, Z, I, O = model(Mf, Mi, Md), params(Zf, Zi, Zd), inputs(If, Ii, Id), \
        outputs(Of, Oi, Od)
    H, V, P6, res, comp = path_state(Lf, Li)
    path = Li.shape[0] > 0
    sync = np.zeros(SY_SIZE, np.int64)
    G = lead_level(H, V, res, I, P6, comp, sync, 0) if path else stop - first
    level = 0
    while G > 0:
        Iv = level_inputs(I, G, comp.shape[0] > 0) if path else I
        p0 = 0 if path else first
        # (one call of the inlined loop: its code compiled once)
        run_poses(M, Z, Iv, O, flags, p0, p0 + G, level_of(H, V, P6, res, comp, sync, G))
        level += 1
        G = lead_level(H, V, res, I, P6, comp, sync, level) if path else 0


@inner
def team_levels(M, Z, I, O, flags, t, nt, sync, H, V, P6, res, comp):
    """Thread ``t`` of a team of ``nt`` running a path's levels (:func:`run_parallel`): the
    threads stay in the launch from level to level, waiting for each other instead of being
    woken for each level's launch (on a virtual machine the second thread of a launch often
    started a millisecond late, most of a small level).  The lead thread (``t`` 0) forms
    each level (:func:`._path_loop.lead_level`) while the others wait for its release; all
    take the level's pieces (:func:`block_poses`, as :func:`run_blocks`), then arrive at the
    level's end, where the lead waits for them all.  One workspace a thread for all levels.
    Each pose is computed as in any launch: the same bits.  (A function of its own, not
    typed into the ``prange`` body: numba hoists out of a ``prange`` loop the reads of an
    array its body writes only through calls, and ``sync`` is such an array.)"""
    n_legs, m = M[D].shape[0], M[D].shape[1]
    Wo, RWo, SWo, CWo, RLo = _workspaces(M, O, BLOCK, BLOCK)
    Ko = make_block(n_legs, m, O[OUT_X].shape[1], BLOCK)
    own = comp.shape[0] > 0
    level = 0
    G = 1
    while G > 0:
        if t == 0:
            G = lead_level(H, V, res, I, P6, comp, sync, level)
        else:
            while read_acquire(sync[SY_READY:SY_READY + 1]) <= level:
                pass
            G = sync[SY_G]
        if G > 0:
            Iv = level_inputs(I, G, own)
            L = level_of(H, V, P6, res, comp, sync, G)
            nw, piece = team_pieces(G, nt)
            taken = sync[SY_TAKEN:SY_TAKEN + 1]
            a, b = piece_span(claim(taken), G, piece, nw)
            while a < G:
                block_poses(M, Z, Iv, O, flags, a, b, borrowed(Wo), borrowed(RWo),
                            borrowed(SWo), borrowed(CWo), borrowed(Ko), borrowed(RLo), L)
                a, b = piece_span(claim(taken), G, piece, nw)
            arrive(sync[SY_ARRIVED:SY_ARRIVED + 1])
            level += 1
            if t == 0:
                while read_acquire(sync[SY_ARRIVED:SY_ARRIVED + 1]) < level * nt:
                    pass
    # the owners are used here, so they live (and keep the buffers) until the loop is done
    return Wo[0].shape[0] + RWo[0].shape[0] + SWo[0].shape[0] + CWo[0].shape[0] + \
        Ko[0].shape[0] + RLo[0].shape[0]


@inner
def team_pieces(G, nt):
    """``(threads, piece)`` of a path's level of ``G`` samples on a team of ``nt``
    (:func:`team_levels`): a launch's (:func:`._threads.threads_for`,
    :func:`._threads.piece_of`), except for a level below ``2 MIN_PER_THREAD`` samples,
    which those leave to one thread (the cost of waking another for it): the team's
    threads are awake, so such a level (the bisection's first) is shared in pieces of
    about ``1 / (4 nt)`` of it, whole vectors of lanes (each pose's bits are its own
    whatever piece holds it)."""
    if nt > 1 and G < 2 * MIN_PER_THREAD:
        return nt, max(8, -(-G // (4 * nt * 8)) * 8)
    nw = threads_for(G, nt)
    return nw, piece_of(G, nw)


@parallel
def run_parallel(Mf, Mi, Md, Zf, Zi, Zd, If, Ii, Id, Of, Oi, Od, flags, nthreads, Lf, Li):
    """:func:`run_blocks` on the launch's ``nthreads`` threads (``prange`` over them), the
    poses in pieces (:func:`._threads.piece_of`) each thread takes as it is free (the pieces'
    bits are the poses' own).  (The threads are given: numba's ``get_num_threads`` in a
    kernel is a call through a pointer of this process, which keeps the kernel out of the
    cache.)  With a path's state ``Lf, Li`` (:mod:`._path_loop`; empty otherwise): the
    path's levels one after the other, each a launch of its samples on as many of the
    threads as it has poses for, the inputs' buffers holding the level's rows."""
    M, Z, I, O = model(Mf, Mi, Md), params(Zf, Zi, Zd), inputs(If, Ii, Id), \
        outputs(Of, Oi, Od)
    H, V, P6, res, comp = path_state(Lf, Li)
    path = Li.shape[0] > 0
    if path and H[LH_TEAM] == 1 and nthreads > 1:
        # a path's levels on a team of threads that stays in the launch (each range of the
        # prange on a thread of its own: numba's workqueue layer)
        team = np.zeros(SY_SIZE, np.int64)
        for t in prange(nthreads):
            # (the index as int64: numba types this call once with the loop's index as
            # int64, and once more in the prange body, where it is uint64; two versions of
            # team_levels, some 26 s of LLVM each, for the same code)
            team_levels(M, Z, I, O, flags, np.int64(t), nthreads, team, H, V, P6, res, comp)
        return
    sync = np.zeros(SY_SIZE, np.int64)
    G = lead_level(H, V, res, I, P6, comp, sync, 0) if path else I[0].shape[0]
    level = 0
    while G > 0:
        Iv = level_inputs(I, G, comp.shape[0] > 0) if path else I
        L = level_of(H, V, P6, res, comp, sync, G)
        nw = threads_for(G, nthreads) if path else nthreads
        piece = piece_of(G, nw)
        nt = max(1, min(nw, -(-G // piece)))
        taken = np.zeros(1, np.int64)
        for t in prange(nt):
            run_blocks(M, Z, Iv, O, flags, piece, nw, taken, L)
        level += 1
        G = lead_level(H, V, res, I, P6, comp, sync, level) if path else 0
