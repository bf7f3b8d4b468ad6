"""Gauss-Newton on the loop closures of a block of poses, compiled (private).

The driver solves its poses ``BLOCK`` at a time (:data:`._layout.BLOCK`): each quantity of a
block is one array with the lane (pose) axis last and innermost (``X (nx, B)``, the frames
``FA (2, n, m, 6, B)``...), so that the forward pass (:func:`._kin.forward_block`) runs its
arithmetic across the lanes, where LLVM vectorises it.  Each lane iterates exactly as one
pose does (:func:`._newton.newton_iterate`: the same test, tolerance, maximum of iterations
and step halving, in the same order of operations: no reduction across lanes), so a lane of
a block equals the pose alone bit for bit; a lane stops when it converges or stalls while the
others go on (the block's passes still compute it: masked, not compacted).  The Newton step
is still solved lane by lane (:func:`._newton.newton_step` on the lane's frames, copied into
the one-pose workspace): a block step is the next stage.

The block workspace ``K`` (:func:`make_block`) holds the current (buffer 0) and trial
(buffer 1) frames of every lane, the unknowns, the given parameters, and per lane the
residual, the tolerance, the iterations and the state (``LANE_*``).
"""

import math

import numpy as np

from ._jit import inlined, inner
from ._kin import closure_sq, forward_block, platform_columns
from ._layout import BLOCK
from ._newton import HALVINGS, W_FA, W_FE, W_FL, W_FP, W_FROZ, W_PT, W_STEP, newton_step

(K_X, K_XN, K_P6, K_FA, K_FL, K_FE, K_FP, K_STEP, K_F, K_FN, K_E2, K_TOL, K_ITS, K_STATE,
 K_CS, K_OK, K_S, K_P6S, K_ACC) = range(19)
#: Lane states: iterating, converged (residual at or below its tolerance), stalled (no
#: decrease, or a non-finite residual), not solved in the block (solved alone).
LANE_ACTIVE, LANE_DONE, LANE_STALLED, LANE_ALONE = 0, 1, 2, 3


@inner
def make_block(n, m, nx, B):
    """A thread's block workspace for ``B`` lanes of a model of ``n`` legs, ``m`` slots and
    ``nx`` unknowns."""
    return (np.zeros((nx, B)), np.zeros((nx, B)), np.zeros((6, B)), np.zeros((2, n, m, 6, B)),
            np.zeros((2, n, 12, B)), np.zeros((2, n, 6, B)), np.zeros((2, 27, B)),
            np.zeros((nx, B)), np.zeros(B), np.zeros(B), np.zeros(B), np.zeros(B),
            np.zeros(B, np.int64), np.zeros(B, np.int64), np.zeros((2, B)),
            np.zeros(B, np.int64), np.zeros((6, 3, 3)), np.zeros(6), np.zeros(B, np.int64))


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
def _accept(K, l):
    """Lane ``l``'s trial (buffer 1) becomes its current state (buffer 0)."""
    X, Xn = K[K_X], K[K_XN]
    for k in range(X.shape[0]):
        X[k, l] = Xn[k, l]
    FA, FL, FE, FP = K[K_FA], K[K_FL], K[K_FE], K[K_FP]
    for i in range(FA.shape[1]):
        for j in range(FA.shape[2]):
            for k in range(6):
                FA[0, i, j, k, l] = FA[1, i, j, k, l]
        for k in range(12):
            FL[0, i, k, l] = FL[1, i, k, l]
        for k in range(6):
            FE[0, i, k, l] = FE[1, i, k, l]
    for k in range(27):
        FP[0, k, l] = FP[1, k, l]
    K[K_F][l] = K[K_FN][l]
    K[K_ACC][l] += 1


@inner
def forward_lanes(M, unk, xs, K, X, b, res, nb):
    """The block's forward pass (:func:`._kin.forward_block`, inlined here once) of the
    unknowns ``X`` into buffer ``b``, each lane's residual into ``res``."""
    forward_block(M, unk, xs, K[K_P6], X, K[K_FA], K[K_FL], K[K_FE], K[K_FP], b, K[K_S],
                  K[K_P6S], nb, BLOCK, res, K[K_CS])


@inner
def block_newton(M, unk, xs, K, nb, max_iter, W):
    """Gauss-Newton on the lanes ``0..nb-1`` of the block ``K`` whose state is
    ``LANE_ACTIVE``, from ``K[K_X]`` (in place) at the given parameters ``K[K_P6]`` to the
    tolerances ``K[K_TOL]``: each lane's residual, iterations and state into ``K[K_F]``,
    ``K[K_ITS]``, ``K[K_STATE]``, its accepted steps into ``K[K_ACC]``; the frames of its
    final unknowns in buffer 0.  ``W`` a one-pose workspace (the lanes' Newton steps)."""
    X, Xn, STEP, FE = K[K_X], K[K_XN], K[K_STEP], K[K_FE]
    F, FN, E2, TOL, ITS, ST, OK = K[K_F], K[K_FN], K[K_E2], K[K_TOL], K[K_ITS], K[K_STATE], \
        K[K_OK]
    nu = unk.shape[0]
    nx = X.shape[0]
    step = W[W_STEP]
    forward_lanes(M, unk, xs, K, X, 0, F, nb)
    for l in range(nb):
        ITS[l] = 0
        K[K_ACC][l] = 0
    for _ in range(max_iter):
        active = False
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            if not math.isfinite(F[l]):
                ST[l] = LANE_STALLED
            elif F[l] <= TOL[l]:
                ST[l] = LANE_DONE
            else:
                active = True
        if not active:
            break
        for l in range(nb):
            if ST[l] != LANE_ACTIVE:
                continue
            lane_frames(K, 0, l, W, 0)
            platform_columns(M, W[W_FP][0], unk, W[W_PT])
            newton_step(M, W, 0, nu, W[W_FROZ])
            for k in range(nx):
                STEP[k, l] = step[k]
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
                continue
            ITS[l] += 1
            if OK[l]:
                _accept(K, l)
            else:
                ST[l] = LANE_STALLED
