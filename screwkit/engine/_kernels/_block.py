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

The block workspace ``K`` (:func:`make_block`) holds the current (buffer 0) and trial
(buffer 1) frames of every lane, the unknowns, the given parameters, and per lane the
residual, the tolerance, the iterations and the state (``LANE_*``).
"""

import math

import numpy as np

from ._jit import borrowing, inlined, inner, lanes
from ._kin import closure_sq, forward_block, platform_columns
from ._layout import BLOCK
from ._layout import LEG, PLAT, ROT, TRN
from ._newton import HALVINGS, W_FA, W_FE, W_FL, W_FP, W_FROZ, step_block

(K_X, K_XN, K_P6, K_FA, K_FL, K_FE, K_FP, K_STEP, K_F, K_FN, K_E2, K_TOL, K_ITS, K_STATE,
 K_CS, K_OK, K_S, K_ACC, K_PT, K_T, K_G, K_B, K_XS, K_AR, K_RHS, K_LS, K_PZ) = range(27)
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
            np.zeros((8, B)))


@inlined
def lane_frames(K, b, l, W, wb):
    """Lane ``l``'s frames in buffer ``b`` of the block into buffer ``wb`` of the one-pose
    workspace ``W``."""
    FA, FL, FE, FP = K[K_FA][b], K[K_FL][b], K[K_FE][b], K[K_FP][b]
    WA, WL, WE, WP = W[W_FA][wb], W[W_FL][wb], W[W_FE][wb], W[W_FP][wb]
    for i in range(WA.shape[0]):
        for j in range(WA.shape[1]):
            for k in range(6):
                WA[i, j, k] = FA[i, j, k, l]
        for k in range(12):
            WL[i, k] = FL[i, k, l]
        for k in range(6):
            WE[i, k] = FE[i, k, l]
    for k in range(27):
        WP[k] = FP[k, l]


@inlined
def _take(A, half, acc, nb):
    """In each lane ``k < nb`` with ``acc[k]``, the trial half of ``A`` (its second half: buffer
    1, or ``Xn`` after ``X``) becomes the current one (the first half), row by row of
    ``BLOCK`` lanes: a select per lane that LLVM vectorises."""
    p, t = lanes(A), lanes(acc)
    for r in range(half // BLOCK):
        o = r * BLOCK
        for k in range(nb):
            p[o + k] = p[half + o + k] if t[k] else p[o + k]


@inlined
def _accept(K, nb):
    """The trial (buffer 1) of the lanes whose ``K[K_OK]`` is set becomes their current state
    (buffer 0)."""
    acc = K[K_OK]
    X = K[K_X]
    p, q, t = lanes(X), lanes(K[K_XN]), lanes(acc)
    for r in range(X.shape[0]):
        o = r * BLOCK
        for k in range(nb):
            p[o + k] = q[o + k] if t[k] else p[o + k]
    _take(K[K_FA], K[K_FA].size // 2, acc, nb)
    _take(K[K_FL], K[K_FL].size // 2, acc, nb)
    _take(K[K_FE], K[K_FE].size // 2, acc, nb)
    _take(K[K_FP], K[K_FP].size // 2, acc, nb)


@borrowing
def forward_lanes(M, unk, xs, K, X, b, res, nb):
    """The block's forward pass (:func:`._kin.forward_block`, inlined here once) of the
    unknowns ``X`` into buffer ``b``, each lane's residual into ``res``."""
    forward_block(M, unk, xs, K[K_P6], X, K[K_FA], K[K_FL], K[K_FE], K[K_FP], b, K[K_S], nb,
                  BLOCK, res, K[K_CS])


@borrowing
def block_newton(M, unk, xs, K, nb, max_iter, W):
    """Gauss-Newton on the lanes ``0..nb-1`` of the block ``K`` whose state is
    ``LANE_ACTIVE``, from ``K[K_X]`` (in place) at the given parameters ``K[K_P6]`` to the
    tolerances ``K[K_TOL]``: each lane's residual, iterations and state into ``K[K_F]``,
    ``K[K_ITS]``, ``K[K_STATE]``, its accepted steps into ``K[K_ACC]``; the frames of its
    final unknowns in buffer 0.  Lanes left ``LANE_ACTIVE`` (at most ``nb / ALONE_SHARE``,
    or all after ``max_iter`` iterations) are to finish alone from there, ``max_iter`` less
    their iterations to go (:func:`._newton.newton_from`).  ``W`` a one-pose workspace (the
    lanes' Newton steps)."""
    X, Xn, STEP, FE = K[K_X], K[K_XN], K[K_STEP], K[K_FE]
    F, FN, E2, TOL, ITS, ST, OK = K[K_F], K[K_FN], K[K_E2], K[K_TOL], K[K_ITS], K[K_STATE], \
        K[K_OK]
    nu = unk.shape[0]
    nx = X.shape[0]
    forward_lanes(M, unk, xs, K, X, 0, F, nb)
    for l in range(nb):
        ITS[l] = 0
        K[K_ACC][l] = 0
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
        # every lane's step at once (the stopped lanes' too: masked, not read)
        Pt = K[K_PT]
        for l in range(nb):
            platform_columns(M, K[K_FP][0, :, l], unk, Pt[:, :, l])
        step_block(M[LEG], M[ROT], M[TRN], M[PLAT], K[K_FA], FE, Pt, K[K_T], K[K_G], K[K_B],
                   K[K_XS], K[K_AR], STEP, K[K_RHS], K[K_LS], 0, nu, W[W_FROZ], nb)
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            E2[l] = closure_sq(FE, 0, l)
            OK[l] = 0
        for h in range(HALVINGS + 1):
            for l in range(nb):
                if ST[l] != LANE_ACTIVE or OK[l]:
                    continue
                if h:
                    for k in range(nx):
                        STEP[k, l] *= 0.5
                for k in range(nx):
                    Xn[k, l] = X[k, l] + STEP[k, l]
            forward_lanes(M, unk, xs, K, Xn, 1, FN, nb)
            pending = False
            for l in range(nb):
                if ST[l] != LANE_ACTIVE or OK[l]:
                    continue
                if closure_sq(FE, 1, l) < E2[l]:      # False for NaN and inf
                    OK[l] = 1
                else:
                    pending = True
            if not pending:
                break
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                OK[l] = 0                   # (not accepted below)
                continue
            ITS[l] += 1
            if OK[l]:
                K[K_F][l] = K[K_FN][l]
                K[K_ACC][l] += 1
            else:
                ST[l] = LANE_STALLED
        _accept(K, nb)
