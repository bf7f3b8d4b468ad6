"""A pose's closures in the analysis kernel (private): its start, solved alone, or as a
lane of a block of ``BLOCK`` poses and then finished alone (the rest of a Newton run, the
rescue), as :mod:`._driver`'s loops call them; every lane is the pose alone, the same bits.
"""

import math

from ._jit import inlined, lanes, one_lane

from ._block import (K_F, K_ITS, K_P6, K_PT, K_PZ, K_STATE, K_STEP, K_TOL, K_X, K_XN,
                     LANE_ACTIVE, LANE_ALONE,
                     block_newton, lane_frames)
from ._closures import pose_checks, predict, rescue, solve_pose, whole_turns
from ._layout import (ACCEPTED, BLOCK, CONVERGED, F_CONTINUATION, OUT_HOW, OUT_ITS, OUT_SING,
                      OUT_X, ORDER)
from ._newton import W_P6S, W_PZ, W_XB, W_XR, home_vector, newton_from
from ._pack import out_row


#: Largest difference (radians, lengths over ``L``) between a warm start and the home
#: predictor at the warm start's own pose for the start to be moved by the predictor's change
#: (:func:`moved_starts`): the predictor's error within two half-widths of its fit is some
#: 2e-3 (a 3RRPRR), and a warm start of another branch of the closures differs by far more.
SAME_BRANCH = 1e-2


@inlined
def start(Z, I, O, p, W):
    """Pose ``p``'s start into its row of ``O[OUT_X]``: its warm start (moved by the home
    predictor's change from the warm start's pose, where the row of ``X0`` holds that pose
    after the unknowns: :func:`moved_starts`), else the home predictor's."""
    unk, xs, fix, p6home = Z[0], Z[1], Z[4], Z[6]
    P6, X0 = I[0], I[1]
    X = O[OUT_X][out_row(I, p)]
    nx = X.shape[0]
    if X0.shape[0]:
        for k in range(nx):
            X[k] = X0[p, k]
        if X0.shape[1] > nx:
            # the predictor at the pose (row 0 of the singularity's scratch, which the solve
            # writes before it reads) and at the guess's pose (row 1; the pose itself in the
            # continuation's), as the block's lanes
            Xh, g6, A, B = W[W_XB], W[W_P6S][0], W[W_XR][0], W[W_XR][1]
            home_vector(unk, xs, p6home, Xh)
            for k in range(6):
                g6[k] = X0[p, nx + k]
            predict(Z[7], fix, Z[8], Z[9], Z[10][0], one_lane(P6[p]), Xh, one_lane(A),
                    W[W_PZ], 1, 1)
            predict(Z[7], fix, Z[8], Z[9], Z[10][0], one_lane(g6), Xh, one_lane(B), W[W_PZ],
                    1, 1)
            moved_starts(one_lane(X), one_lane(A), one_lane(B), 1, 1)
    else:
        Xh = W[W_XB]                  # (scratch: the home vector, read only here)
        home_vector(unk, xs, p6home, Xh)
        predict(Z[7], fix, Z[8], Z[9], Z[10][0], one_lane(P6[p]), Xh, one_lane(X), W[W_PZ],
                1, 1)


@inlined
def solve_alone(M, Z, I, O, flags, p, W):
    """Pose ``p``'s closures alone from the start in its row of ``O[OUT_X]`` (:func:`solve_pose`).
    Returns ``(residual, b)``: its frames in buffer ``b`` of ``W``."""
    unk, xs, unk2, xs2, fix, fix2, p6home = Z[0], Z[1], Z[2], Z[3], Z[4], Z[5], Z[6]
    sides = I[2]
    side = sides[p] if sides.shape[0] else 0.0
    q = out_row(I, p)
    res, its, how, sing, b = solve_pose(M, unk, xs, unk2, xs2, I[0][p], O[OUT_X][q], side,
                                        p6home, fix, fix2, flags[F_CONTINUATION] == 1, W)
    if _turned(Z, I, O, p, M, res):
        b = -1                        # its frames formed again at the unknowns turned
    O[OUT_ITS][q] = its
    O[OUT_HOW][q] = how
    O[OUT_SING][q] = sing
    return res, b


@inlined
def solve_block(M, Z, I, O, p0, nb, W, K):
    """The closures of the poses ``p0..p0+nb-1`` as the lanes of the block ``K`` (from their
    starts, as one pose alone); a pose near the representation singularity is left to be
    solved alone (``LANE_ALONE``).  Returns the buffer of ``K`` holding the lanes' frames
    (:func:`._block.block_newton`)."""
    unk, xs = Z[0], Z[1]
    order = M[ORDER]
    P6 = I[0]
    Xb, P6b, TOL, ST = K[K_X], K[K_P6], K[K_TOL], K[K_STATE]
    X0 = I[1]
    for l in range(nb):
        for k in range(6):
            P6b[k, l] = P6[p0 + l, k]
    nx = Xb.shape[0]
    if X0.shape[0]:                   # the warm starts
        for l in range(nb):
            for k in range(nx):
                Xb[k, l] = X0[p0 + l, k]
        if X0.shape[1] > nx:          # moved by the predictor's change, as start does
            # (scratch until the Newton run: its trial unknowns, its step, its platform
            # columns, each written before it is read)
            Xh, A, B, G6b = W[W_XB], K[K_XN], K[K_STEP], K[K_PT][0]
            home_vector(unk, xs, Z[6], Xh)
            for l in range(nb):
                for k in range(6):
                    G6b[k, l] = X0[p0 + l, nx + k]
            predict(Z[7], Z[4], Z[8], Z[9], Z[10][0], P6b, Xh, A, K[K_PZ], nb, BLOCK)
            predict(Z[7], Z[4], Z[8], Z[9], Z[10][0], G6b, Xh, B, K[K_PZ], nb, BLOCK)
            moved_starts(Xb, A, B, nb, BLOCK)
    else:                             # the home predictor's, the lanes at once
        Xh = W[W_XB]
        home_vector(unk, xs, Z[6], Xh)
        predict(Z[7], Z[4], Z[8], Z[9], Z[10][0], P6b, Xh, Xb, K[K_PZ], nb, BLOCK)
    for l in range(nb):
        p = p0 + l
        q = out_row(I, p)
        X = O[OUT_X][q]
        if X0.shape[0] and X0.shape[1] == X.shape[0]:   # (the row as it is: no strided read)
            x0 = X0[p]
            for k in range(X.shape[0]):
                X[k] = x0[k]
        else:
            for k in range(X.shape[0]):
                X[k] = Xb[k, l]
        tol, near, sing = pose_checks(order, unk, xs, P6[p], X)
        TOL[l] = tol
        ST[l] = LANE_ALONE if near else LANE_ACTIVE
        # (its singular flag here, at hand: finish_lane leaves it; a lane left to be solved
        # alone writes its own)
        O[OUT_SING][q] = sing
    return block_newton(M, unk, xs, K, nb, 30, W)


@inlined
def moved_starts(X, A, B, nb, ls):
    """The warm starts ``X (nx, ls)`` of the lanes ``0..nb-1`` moved by the home predictor's
    change ``A - B`` (``A`` at the poses to solve, ``B`` at the poses the warm starts solve),
    where the warm start lies within :data:`SAME_BRANCH` of ``B`` (the predictor's branch).
    A warm start from a neighbouring pose is off by the pose's first-order change, which the
    predictor's change gives to within its derivative's error: one Newton step fewer from a
    neighbour (three to two for the benchmarks' warm poses)."""
    nx = X.shape[0]
    xf, af, bf = lanes(X), lanes(A), lanes(B)
    for l in range(nb):
        near = True
        for k in range(nx):
            near = near and abs(xf[k * ls + l] - bf[k * ls + l]) <= SAME_BRANCH  # (not NaN)
        for k in range(nx):
            near = near and math.isfinite(af[k * ls + l])
        if near:
            for k in range(nx):
                xf[k * ls + l] = xf[k * ls + l] + (af[k * ls + l] - bf[k * ls + l])


@inlined
def finish_lane(M, Z, I, O, flags, p, W, K, l, kb, reads):
    """Pose ``p`` (lane ``l`` of the block ``K``, a lane the block solved) after the block's
    Newton run (its frames in buffer ``kb`` of ``K``): its unknowns; a lane the block left
    active, the rest of its Newton run alone; where the run did not converge, the rescue
    (continuation, polish), as :func:`._closures.solve_pose`; its frames into buffer ``b``
    of ``W`` (``b < 0``: to be formed again at its unknowns; for a lane whose frames stay
    the block's, only where its rows ``reads`` them: :func:`._finish.reads_frames`).  Returns
    ``(residual, b, same)``: ``same``, its frames are the block's (no step alone, no
    rescue)."""
    unk, xs, unk2, xs2, fix, fix2, p6home = Z[0], Z[1], Z[2], Z[3], Z[4], Z[5], Z[6]
    p6fix = I[0][p]
    q = out_row(I, p)
    X = O[OUT_X][q]
    res, its = K[K_F][l], K[K_ITS][l]
    if its:                           # (else its unknowns are the start solve_block wrote)
        Xb = K[K_X]
        for k in range(X.shape[0]):
            X[k] = Xb[k, l]
    how = 0
    # the lane's frames (at its unknowns) into buffer 0 (its closure errors only for the
    # rest of a Newton run: nothing after the solve reads them); after any Newton run of
    # its rescue b < 0: they are formed again at the unknowns the rescue returns
    b = 0
    more_steps = K[K_STATE][l] == LANE_ACTIVE
    if more_steps:
        lane_frames(K, kb, l, W, b, True)
        # one of the few lanes the block left iterating: the rest of its run alone, from
        # its unknowns, frames and residual (the iterations it has left of the pose's 30)
        res, more, _, b = newton_from(M, unk, xs, p6fix, X, K[K_TOL][l], 30 - its, W, res)
        its += more
    same = not more_steps and res <= CONVERGED
    if not more_steps and (reads or not same):
        lane_frames(K, kb, l, W, b, False)
    if not same:
        res, its, how, b = rescue(M, unk, xs, p6fix, X, p6home, fix,
                                  flags[F_CONTINUATION] == 1, W, res, its, b)
    # (a lane with no step from its warm start holds that start: no whole turn from it)
    if not (same and its == 0 and I[1].shape[0] > 0) and _turned(Z, I, O, p, M, res):
        b, same = -1, False
    O[OUT_ITS][q] = its
    O[OUT_HOW][q] = how
    return res, b, same


@inlined
def _turned(Z, I, O, p, M, res):
    """Pose ``p``'s solved unknowns without whole turns (:func:`._closures.whole_turns`,
    against its warm start where it has one); True where they changed.  A pose not solved
    (residual ``res`` above ``ACCEPTED``, or the infinite one of a representation
    singularity with a side out of reach) keeps its unknowns and its verdict."""
    if not res <= ACCEPTED:
        return False
    X0 = I[1]
    warm = X0.shape[0] > 0
    X = O[OUT_X][out_row(I, p)]
    return whole_turns(M, Z[0], X, X0[p] if warm else X, warm)
