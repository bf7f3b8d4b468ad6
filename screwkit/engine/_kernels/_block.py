"""Gauss-Newton on the loop closures of a block of poses, compiled (private).

The driver solves its poses ``BLOCK`` at a time (:data:`._layout.BLOCK`): each quantity of a
block is one array with the lane (pose) axis last and innermost (``X (nx, B)``, the frames
``FA (2, n, m, 6, B)``...), so that the forward pass (:func:`._kin.forward_block`) runs its
arithmetic across the lanes, where LLVM vectorises it.  Each lane iterates exactly as one
pose does (:func:`._newton.newton_iterate`: the same test, tolerance, maximum of iterations
and step halving, in the same order of operations: no reduction across lanes), so a lane of
a block equals the pose alone bit for bit; a lane stops when it converges or stalls while the
others go on (the block's passes still compute it: masked, not compacted).  Since a block
iteration costs its whole width, the block stops once at most one lane in
:data:`ALONE_SHARE` is still iterating: those lanes finish their Newton runs alone
(:func:`._newton.newton_from`, from their unknowns, frames and residual: the same
iterations, so the same bits), instead of the block iterating again for them.  The Newton step
of the block's lanes is one (:func:`._newton.step_block`: the lane loops of
:func:`._newton.step_lanes`, the function one pose's step runs on a block of one).

The block workspace ``K`` (:func:`make_block`) holds two buffers of frames of every lane,
the current and the trial ones, which swap roles at each iteration (:func:`block_newton`
returns the current one), the unknowns, the given parameters, and per lane the residual,
the tolerance, the iterations and the state (``LANE_*``).

The block's forward pass also serves the launches on given unknowns (:func:`frames_block`)
and the lines of the transmission indices' joints (:func:`block_lines`).  The rows' leg
frames of a block's lanes (``_geometry.legs_frames_block``) are kept in a workspace of their
own (:func:`make_rows_lanes`), each pose's copied out by :func:`lane_frames_into`.
"""

import math

import numpy as np

from ._jit import borrowing, borrowing_inlined, inlined, inner, lanes
from ._indices import lines_at, rounded_unknowns
from ._kin import forward_block, twist_lane
from ._layout import (A_LINE, A_NONE, BLOCK, D, L_AROW, OUT_J, OUT_SCALE, TPL, T_AKIND,
                      T_CROW, T_GENERIC, T_K)
from ._layout import LEG, L_SIZE, PLAT, RL_CTX, RL_DV, RL_J, RL_PV, RL_SC, RL_SCALE, ROT, TRA, TRN
from ._members import NOT_DONE, NSC, SC_STATUS, template_lanes
from ._rows import RW_CTX, RW_DV, RW_PV, RW_TW
from ._newton import (HALVINGS, W_FA, W_FE, W_FP, W_FROZ, W_XN, closure_sq,
                      platform_columns, step_block)
from ._pack import out_row

(K_X, K_XN, K_P6, K_FA, K_FL, K_FE, K_FP, K_STEP, K_F, K_FN, K_E2, K_TOL, K_ITS, K_STATE,
 K_CS, K_OK, K_S, K_ACC, K_PT, K_T, K_G, K_B, K_XS, K_AR, K_RHS, K_LS, K_PZ,
 K_SAME) = range(28)
#: Lane states: iterating, converged (residual at or below its tolerance), stalled (no
#: decrease, or a non-finite residual), not solved in the block (solved alone).
LANE_ACTIVE, LANE_DONE, LANE_STALLED, LANE_ALONE = 0, 1, 2, 3
#: The block stops iterating when at most ``nb / ALONE_SHARE`` of its lanes are active (the
#: rest of their runs alone): a one-pose Newton iteration costs about as much as 4-8 lanes'
#: share of a block iteration (``benchmarks/bench_closure.py``: a step and a pass 2.7 us
#: alone, 0.7 us a lane in a block, for the 3RRPRR).
ALONE_SHARE = 4


@inner
def make_block(n, m, nx, B):
    """A thread's block workspace for ``B`` lanes of a model of ``n`` legs, ``m`` slots and
    ``nx`` unknowns."""
    return (np.zeros((nx, B)), np.zeros((nx, B)), np.zeros((6, B)), np.zeros((2, n, m, 6, B)),
            np.zeros((2, n, 12, B)), np.zeros((2, n, 6, B)), np.zeros((2, 27, B)),
            np.zeros((nx, B)), np.zeros(B), np.zeros(B), np.zeros(B), np.zeros(B),
            np.zeros(B, np.int64), np.zeros(B, np.int64), np.zeros((2, B)),
            np.zeros(B, np.int64), np.zeros((6, 3, 3)), np.zeros(B, np.int64),
            # the Newton step's arrays (_newton.step_lanes)
            np.zeros((6, 6, B)), np.zeros((m, 6, B)), np.zeros((m, m, B)), np.zeros((m, 7, B)),
            np.zeros((n, m, 7, B)), np.zeros((6, 7, B)), np.zeros((6, 1, B)), np.zeros((4, B)),
            # the home predictor's scratch (_closures.predict)
            np.zeros((12, B)),
            # per lane: its frames in the block are those of its unknowns (block_lines)
            np.zeros(B, np.int64))


@inlined
def lane_frames(K, b, l, W, wb, errors):
    """Lane ``l``'s frames in buffer ``b`` of the block into buffer ``wb`` of the one-pose
    workspace ``W``: the joints' axes and points and the platform, which the rows read, and
    with ``errors`` the closure errors, which a Newton run continued alone reads (its first
    step and decrease test).  Not the legs' end displacements ``FL``: only the forward pass
    that writes them reads them."""
    # flat loops through pointers: an entry's four indices (and numba's wraparound of each)
    # cost more than its load
    FA, FE, FP = lanes(K[K_FA][b]), lanes(K[K_FE][b]), lanes(K[K_FP][b])
    WA, WE, WP = lanes(W[W_FA][wb]), lanes(W[W_FE][wb]), lanes(W[W_FP][wb])
    for q in range(W[W_FA][wb].size):
        WA[q] = FA[q * BLOCK + l]
    if errors:
        for q in range(W[W_FE][wb].size):
            WE[q] = FE[q * BLOCK + l]
    for q in range(27):
        WP[q] = FP[q * BLOCK + l]


@inlined
def _accept(K, nb):
    """The trial unknowns ``K[K_XN]`` of the lanes ``0..nb-1`` become their unknowns
    ``K[K_X]``: a plain copy, since every lane not accepted already has its trial equal to
    its unknowns (:func:`block_newton`).  The frames are not copied: the trial buffer
    becomes the current one."""
    p, q = lanes(K[K_X]), lanes(K[K_XN])
    for r in range(K[K_X].shape[0]):
        o = r * BLOCK
        for k in range(nb):
            p[o + k] = q[o + k]


@inlined
def _copy_lane(A, src, dst, l):
    """Lane ``l`` of buffer ``src`` of the frames ``A (2, ..., BLOCK)`` into buffer ``dst``."""
    a = lanes(A)
    half = A.size // 2
    s, d = src * half, dst * half
    for r in range(half // BLOCK):
        a[d + r * BLOCK + l] = a[s + r * BLOCK + l]


@inlined
def _keep_lane(K, src, dst, l):
    """Lane ``l``'s frames in buffer ``src`` of the block copied into buffer ``dst`` (a lane
    that stalled: the frames of its unknowns are in the buffer that stops being current)."""
    _copy_lane(K[K_FA], src, dst, l)
    _copy_lane(K[K_FL], src, dst, l)
    _copy_lane(K[K_FE], src, dst, l)
    _copy_lane(K[K_FP], src, dst, l)


@borrowing
def forward_lanes(M, unk, xs, K, X, b, res, nb):
    """The block's forward pass (:func:`._kin.forward_block`, inlined here once) of the
    unknowns ``X`` into buffer ``b``, each lane's residual into ``res``."""
    forward_block(M, unk, xs, K[K_P6], X, K[K_FA], K[K_FL], K[K_FE], K[K_FP], b, K[K_S], nb,
                  BLOCK, res, K[K_CS])


@inlined
def block_newton(M, unk, xs, K, nb, max_iter, W):
    """Gauss-Newton on the lanes ``0..nb-1`` of the block ``K`` whose state is
    ``LANE_ACTIVE``, from ``K[K_X]`` (in place) at the given parameters ``K[K_P6]`` to the
    tolerances ``K[K_TOL]``: each lane's residual, iterations and state into ``K[K_F]``,
    ``K[K_ITS]``, ``K[K_STATE]``, its accepted steps into ``K[K_ACC]``.  Returns the buffer
    (0 or 1) holding the frames of every lane's final unknowns.  Lanes left
    ``LANE_ACTIVE`` (at most ``nb / ALONE_SHARE``, or all after ``max_iter`` iterations) are
    to finish alone from there, ``max_iter`` less their iterations to go
    (:func:`._newton.newton_from`).  ``W`` a one-pose workspace (the lanes' Newton steps).

    The two frame buffers alternate: each iteration's trial pass writes the other buffer,
    which then becomes the current one (no copy of the accepted lanes' frames).  This holds
    for every lane because a lane not iterating keeps its trial unknowns ``K[K_XN]`` equal
    to its unknowns: the trial pass, which runs across all the lanes, forms its frames again
    (the same bits: each lane's pass is its own arithmetic) in the trial buffer.  A lane
    that stalls has its trial reset to its unknowns and its frames copied into the trial
    buffer (once: the frames of its unknowns are in the buffer that stops being current).
    A lane's sum of squared closure errors at its unknowns (the decrease test's reference)
    is that of the trial it accepted, kept from the test, not summed again."""
    X, Xn, STEP, FE = K[K_X], K[K_XN], K[K_STEP], K[K_FE]
    F, FN, E2, TOL, ITS, ST, OK = K[K_F], K[K_FN], K[K_E2], K[K_TOL], K[K_ITS], K[K_STATE], \
        K[K_OK]
    nu = unk.shape[0]
    nx = X.shape[0]
    cur = 0
    forward_lanes(M, unk, xs, K, X, cur, F, nb)
    for l in range(nb):
        ITS[l] = 0
        K[K_ACC][l] = 0
    first = True
    for _ in range(max_iter):
        active = 0
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            if not math.isfinite(F[l]):
                ST[l] = LANE_STALLED
            elif F[l] <= TOL[l]:
                ST[l] = LANE_DONE
            else:
                active += 1
        if active * ALONE_SHARE <= nb:       # none, or a few: they finish alone
            break
        if first:                       # (the trial unknowns, once the lanes iterate)
            for k in range(nx):
                for l in range(nb):
                    Xn[k, l] = X[k, l]
        new = 1 - cur
        # every lane's step at once (the stopped lanes' too: masked, not read)
        Pt = K[K_PT]
        platform_columns(M, K[K_FP][cur], unk, Pt, nb, BLOCK)
        step_block(M[LEG], M[ROT], M[TRN], M[PLAT], K[K_FA], FE, Pt, K[K_T], K[K_G], K[K_B],
                   K[K_XS], K[K_AR], STEP, K[K_RHS], K[K_LS], cur, nu, W[W_FROZ], nb)
        sq = K[K_LS][3]                 # (the step's scratch row it leaves free)
        if first:                       # (later, the sum of the trial it accepted: below)
            closure_sq(FE, cur, sq, nb, BLOCK)
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            if first:
                E2[l] = sq[l]
            OK[l] = 0
        first = False
        for h in range(HALVINGS + 1):
            for l in range(nb):
                if ST[l] != LANE_ACTIVE or OK[l]:
                    continue
                if h:
                    for k in range(nx):
                        STEP[k, l] *= 0.5
                for k in range(nx):
                    Xn[k, l] = X[k, l] + STEP[k, l]
            forward_lanes(M, unk, xs, K, Xn, new, FN, nb)
            closure_sq(FE, new, sq, nb, BLOCK)
            pending = False
            for l in range(nb):
                if ST[l] != LANE_ACTIVE or OK[l]:
                    continue
                e2n = sq[l]
                if e2n < E2[l]:                 # False for NaN and inf
                    OK[l] = 1
                    E2[l] = e2n                 # the next iteration's, if the lane goes on
                else:
                    pending = True
            if not pending:
                break
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            ITS[l] += 1
            if OK[l]:
                K[K_F][l] = K[K_FN][l]
                K[K_ACC][l] += 1
            else:
                ST[l] = LANE_STALLED
                for k in range(nx):
                    Xn[k, l] = X[k, l]
                _keep_lane(K, cur, new, l)
        _accept(K, nb)
        cur = new
    return cur


@inlined
def frames_block(M, unk, xs, I, X, p0, nb, K):
    """The frames of the given unknowns of the poses ``p0..p0+nb-1`` (their rows of ``X (.,
    nx)``, :func:`._pack.out_row`) at their given parameters (``I[0] (N, 6)``) as the lanes
    of the block ``K`` (buffer 0), each lane's residual into ``K[K_F]`` (the bits of each
    pose's one-pose pass)."""
    Xb, P6b = K[K_X], K[K_P6]
    P6 = I[0]
    for l in range(nb):
        q = out_row(I, p0 + l)
        for k in range(6):
            P6b[k, l] = P6[p0 + l, k]
        for k in range(Xb.shape[0]):
            Xb[k, l] = X[q, k]
    forward_lanes(M, unk, xs, K, Xb, 0, K[K_F], nb)


@inlined
def block_lines(M, unk, xs, I, X, lines, platform, p0, nb, W, K, kb):
    """The lines (:func:`._indices.pose_lines`) and platforms of the poses ``p0..p0+nb-1``
    (given parameters ``I[0]``) into their rows of ``lines`` and ``platform``, at their
    unknowns, their rows of ``X`` (:func:`._pack.out_row`), as the solution hands them back
    (:func:`._indices.rounded_unknowns`).  As :func:`._indices.pose_lines` does for a pose
    alone: from the block's frames in buffer ``kb`` where they are the lane's (``K[K_SAME]``:
    no step alone, no rescue) and the rounding changes neither the unknowns nor the
    platform's parameters (nine poses in ten of a 3RRPRR's map); the other lanes' frames
    formed again, gathered into the first lanes of the other buffer (a forward pass of those
    lanes alone).  Each lane's frames are those of the pose alone: the same bits either
    way.  ``W`` a one-pose workspace."""
    nu = unk.shape[0]
    Xr, P6b, SAME = K[K_XN], K[K_P6], K[K_SAME]
    Xp = W[W_XN]
    P6 = I[0]
    fp = K[K_FP][kb]
    again = 0                     # lanes to form again; SAME[j] becomes the j-th one's lane
    for l in range(nb):
        p = p0 + l
        x = X[out_row(I, p)]
        rounded_unknowns(M, nu, x, Xp)
        exact = SAME[l] != 0
        for k in range(Xp.shape[0]):
            exact = exact and Xp[k] == x[k]
        for k in range(6):
            v = P6[p, k]
            for u in range(nu):
                if unk[u] == k:
                    v = x[u] * xs[u]
            exact = exact and v == fp[k, l]
        if exact:
            _lines_of_lane(M, I, K, kb, l, p, W, lines, platform)
        else:
            for k in range(Xr.shape[0]):
                Xr[k, again] = Xp[k]
            for k in range(6):
                P6b[k, again] = P6[p, k]
            SAME[again] = l               # (lane ``again`` <= l: its flag already read)
            again += 1
    if again:
        forward_lanes(M, unk, xs, K, Xr, 1 - kb, K[K_FN], again)
        for j in range(again):
            _lines_of_lane(M, I, K, 1 - kb, j, p0 + SAME[j], W, lines, platform)


@inlined
def _lines_of_lane(M, I, K, b, l, p, W, lines, platform):
    """Pose ``p``'s lines and platform from lane ``l`` of the block's buffer ``b``."""
    lane_frames(K, b, l, W, 1, False)
    q = out_row(I, p)
    lines_at(M, W[W_FA], 1, lines[q])
    fw, out = W[W_FP][1], platform[q]
    for k in range(fw.shape[0]):
        out[k] = fw[k]


@inner
def make_rows_lanes(n, m, mr, npts, ndirs, B):
    """A thread's rows workspace of a block of ``B`` lanes: every leg's context ``(n, 4, 3,
    B)``, named points ``(n, p, 3, B)``, directions ``(n, d, 3, B)`` and twists ``(n, m, 6,
    B)`` (``_geometry.legs_frames_block``); the rows ``(mr, 6, B)`` and scales ``(mr, B)`` of
    the legs that follow their templates, each leg's scratch and status ``(n, NSC, B)``, and
    the scratch of :func:`._members.template_lanes` (:func:`template_rows_block`), and the
    lanes' centroids, spreads and origins ``(8, B)`` (``_statics.spread_lanes``)."""
    return (np.zeros((n, 4, 3, B)), np.zeros((n, max(npts, 1), 3, B)),
            np.zeros((n, max(ndirs, 1), 3, B)), np.zeros((n, m, 6, B)),
            np.zeros((max(mr, 1), 6, B)), np.zeros((max(mr, 1), B)), np.zeros((n, NSC, B)),
            np.zeros((max(m, 1), 3, B)), np.zeros((3, B)), np.zeros((3, 3, B)),
            np.zeros((8, B)))


@inlined
def template_rows_block(M, FA, RL, nb):
    """The rows of every leg that follows its template (``_rows.template_rows``) for the
    ``nb`` lanes of a block at once, from their frames ``FA (n, m, 6, BLOCK)`` and the legs'
    lanes in ``RL`` (:func:`._geometry.legs_frames_block`): into ``RL``'s rows and scales,
    each leg's status per lane in its scratch (``SC_STATUS``; ``NOT_DONE`` for a leg without
    a template, and where the template does not hold: those rows are formed pose by pose)."""
    CTX, PV, DV, TW, JL, SL, SC, R, V, BASIS = RL[:10]
    for i in range(M[D].shape[0]):
        tpl = M[TPL][i]
        akind = tpl[T_AKIND]
        if tpl[T_GENERIC] or (akind != A_LINE and akind != A_NONE):
            for k in range(nb):
                SC[i, SC_STATUS, k] = NOT_DONE
            continue
        template_lanes(M, i, CTX[i], PV[i], DV[i], FA[i], TW[i], JL, SL, SC[i], R, V, BASIS,
                       True, 1, nb, BLOCK)


@borrowing
def block_rows_into(M, I, O, RL, p0, nb):
    """The rows and scales :func:`template_rows_block` formed for the lanes ``0..nb-1`` (of
    the legs whose status is not ``NOT_DONE``) into the rows of ``O``'s ``J`` and ``scale`` of
    the poses ``p0..p0+nb-1`` (:func:`._pack.out_row`), all lanes at once: each of the
    block's rows read along its lanes (a lane at a time, each value of the pose's rows sat in
    another cache line of the lanes' rows, fetched again for every lane).  A pose whose rows
    are formed again later (frames of its own, or a template that does not hold there)
    writes them over."""
    JL, SL, SC = RL[RL_J], RL[RL_SCALE], RL[RL_SC]
    J, S = O[OUT_J], O[OUT_SCALE]
    for i in range(M[D].shape[0]):
        crow, k, arow = M[TPL][i, T_CROW], M[TPL][i, T_K], M[LEG][i, L_AROW]
        for j in range(k + (1 if arow >= 0 else 0)):
            r = crow + j if j < k else arow
            for l in range(nb):
                if SC[i, SC_STATUS, l] != NOT_DONE:
                    q = out_row(I, p0 + l)
                    S[q, r] = SL[r, l]
                    for c in range(6):
                        J[q, r, c] = JL[r, c, l]


@borrowing_inlined
def lane_frames_into(M, i, RL, l, RW, fa):
    """Leg ``i``'s context, points and directions of lane ``l`` of the block's rows
    workspace ``RL`` (:func:`make_rows_lanes`) into ``RW``, and its twists at that lane's
    frames ``fa``: what ``_rows.leg_frames`` would form there, the same bits.  Flat loops
    through pointers (an entry's indices and numba's wraparound of each cost more than its
    load)."""
    CTX, PV, DV = RL[RL_CTX], RL[RL_PV], RL[RL_DV]
    B = CTX.shape[3]
    _lane_copy(CTX, i, 12, B, l, RW[RW_CTX])
    _lane_copy(PV, i, PV.shape[1] * 3, B, l, RW[RW_PV])
    _lane_copy(DV, i, DV.shape[1] * 3, B, l, RW[RW_DV])
    # the twists (a dozen operations each: less than copying them out of a lane)
    rot, tra, tw = M[ROT], M[TRA], RW[RW_TW]
    for j in range(M[LEG][i, L_SIZE]):
        twist_lane(rot[i, j], tra[i, j], fa[j], tw[j], 0, 1)


@borrowing_inlined
def _lane_copy(S, i, per, B, l, dst):
    """The ``per`` entries of leg ``i`` of lane ``l`` of ``S (n, ..., B)`` into ``dst``
    (C-contiguous)."""
    src, out = lanes(S), lanes(dst)
    o = i * per * B + l
    for q in range(per):
        out[q] = src[o + q * B]
