"""The assembly-mode sign of ``det J``: each leg's constraint rows oriented by the leg's own
joint twists (private).

The sign of a constraint row is a convention of the leg's geometry (a reference direction
evaluated at the pose, ``docs/conventions.md``), and a reference direction can pass through
zero inside the workspace (the RRPRR's ``OA x leg`` where the leg lies along ``OA``): the row
then turns over, and ``det J`` changes sign, with no singularity.  A leg whose ``m`` joint
twists and ``k`` constraint rows make six spans the whole space with them (its rows are the
twists' reciprocal complement: in the ``[v; w]``, ``[f; m]`` order the plain orthogonal
complement), so ``det [t_1; ...; t_m; c_1; ...; c_k]`` is not zero while the leg's joints
stay independent, and its sign, times the leg's rows, orients them continuously along any
motion: ``det J`` times those signs changes sign at a singularity only
(:func:`leg_orientation`, which the analysis kernel applies to each pose's sign of ``det
J``: ``_finish.finish_rows``).  The joint twists follow the joints' own axes (no
convention), in chain order, but for an S joint: its three R axes are one representation
of a ball, whose other branch (the same ball, the same link) turns some of them over, so
its twists are the rotations about the world's X, Y and Z axes through its centre,
whatever the branch.  The rows are taken about the model's centroid ``c``, moments and
velocities over ``L`` (the sign of the determinant does not depend on the point or the
length: reciprocity is kept by both changes, and the rows' part along the twists'
complement is moved by a positive definite map; nor on the rows' norms, which are left).

The analysis kernel forms the orientation where it is asked to (a map's analysis), as each
leg's rows are formed; :func:`oriented_range` forms it for an analysis whose run did not,
from its solved unknowns (the legs' joints formed again on a block's lanes), and orients a
leg with idle motions (more joints than ``6 - k``: few legs have both) against its rows at
the model's reference pose.
"""

import numpy as np

from numba import prange

from ._jit import borrowing, entry, inner, parallel
from ._kin import chain, joint_twist
from ._layout import BLOCK, D, LEG, L_BALL, L_SIZE, PLAT, P_C, P_L, TPL, T_CROW, T_K
from ._rows import _normalise_twist, _normalise_wrench, unit_row
from ._small import lu_factor

#: ``|det (C_p C_ref^T)|`` of a leg's unit, length-normalised constraint rows against its
#: reference rows below which their orientation is not defined (a leg with idle motions
#: whose rows turned about a right angle from the reference pose's).
ORIENT_MIN = 1e-3


@borrowing
def orients(leg, tpl):
    """Whether :func:`leg_orientation` orients the leg (rows ``leg`` of ``LEG``, ``tpl`` of
    ``TPL``): it has constraint rows and no idle motion."""
    return tpl[T_K] > 0 and leg[L_SIZE] + tpl[T_K] == 6


@borrowing
def leg_orientation(leg, tpl, plat, TW, J, A, piv):
    """The orientation of a leg's constraint rows ``J[T_CROW:T_CROW + T_K] (k, 6)`` (of ``J
    (mr, 6)``) by its joint twists ``TW (m, 6)`` (unit twists ``[v; w]`` about the base
    origin, the kernels' ``joint_twist``): the sign of ``det [t_1..t_m; c_1..c_k]`` (an S
    joint's three parts, from ``leg[L_BALL]`` on, as the rotations about X, Y, Z through its
    centre), each row about the model's centroid, lengths over ``L`` (``plat``: the model's
    ``PLAT``); 0 where the joints are dependent; 1 for a leg without
    constraint rows or with idle motions (``m + k != 6``: :func:`oriented_range`).  ``leg``,
    ``tpl``: the leg's rows of ``LEG`` and ``TPL``; ``A (6, 6)``, ``piv (6,)`` scratch."""
    k, r0, mj, b = tpl[T_K], tpl[T_CROW], leg[L_SIZE], leg[L_BALL]
    if not orients(leg, tpl):
        return 1.0
    c, L = plat[P_C:P_C + 3], plat[P_L]
    for j in range(mj):
        if b >= 0 and b <= j < b + 3:
            _ball_axis(TW, b, j - b, c, L, A[j])
        else:
            _normalise_twist(TW[j], c, L, A[j])
    for r in range(k):
        w = J[r0 + r]
        _normalise_wrench(w[0], w[1], w[2], w[3], w[4], w[5], c, L, A[mj + r])
    return lu_factor(A, 6, piv)


@borrowing
def _ball_axis(TW, b, part, c, L, out):
    """The rotation about the world axis ``part`` (0, 1, 2: X, Y, Z) through the centre ``s``
    of the S joint whose parts are ``TW[b:b + 3]``, about ``c``, velocities over ``L``:
    ``[(s - c) x e / L; e]``.  ``s`` is where its first two parts' axes meet (``v_j = s x
    w_j``; the two stay at their home angle, a right angle, as the first turns the second
    about itself): ``s = w_1 x v_1 / |w_1|^2 + lambda w_1``, ``lambda`` from the second."""
    w1, v1, w2, v2 = TW[b, 3:], TW[b, :3], TW[b + 1, 3:], TW[b + 1, :3]
    n1 = w1[0] * w1[0] + w1[1] * w1[1] + w1[2] * w1[2]
    s0 = (w1[1] * v1[2] - w1[2] * v1[1]) / n1
    s1 = (w1[2] * v1[0] - w1[0] * v1[2]) / n1
    s2 = (w1[0] * v1[1] - w1[1] * v1[0]) / n1
    x0, x1, x2 = w1[1] * w2[2] - w1[2] * w2[1], w1[2] * w2[0] - w1[0] * w2[2], \
        w1[0] * w2[1] - w1[1] * w2[0]
    r0 = v2[0] - (s1 * w2[2] - s2 * w2[1])
    r1 = v2[1] - (s2 * w2[0] - s0 * w2[2])
    r2 = v2[2] - (s0 * w2[1] - s1 * w2[0])
    lam = (r0 * x0 + r1 * x1 + r2 * x2) / max(x0 * x0 + x1 * x1 + x2 * x2, 1e-300)
    d0, d1, d2 = s0 + lam * w1[0] - c[0], s1 + lam * w1[1] - c[1], s2 + lam * w1[2] - c[2]
    e0, e1, e2 = 1.0 if part == 0 else 0.0, 1.0 if part == 1 else 0.0, 1.0 if part == 2 else 0.0
    out[0], out[1], out[2] = (d1 * e2 - d2 * e1) / L, (d2 * e0 - d0 * e2) / L, \
        (d0 * e1 - d1 * e0) / L
    out[3], out[4], out[5] = e0, e1, e2


@entry
def oriented_range(M, X, J, legs, ref, centre, L, out, start, stop):
    """``out[p] *=`` the orientation of the constraint rows of ``J[p] (N, mr, 6)`` of each
    leg of ``legs``, poses ``start:stop``: :func:`leg_orientation` at its joint values
    (``X[p] (N, n m)``, the legs' slots in turn), or for a leg with idle motions the sign of
    ``det (C_p C_ref^T)`` of its unit rows about ``centre``, moments over ``L``, against its
    rows at the reference pose ``ref (mr, 6)`` (0 below :data:`ORIENT_MIN`); 0 where
    ``out[p]`` is 0 or not a number (an unreachable pose).  The legs' joints are formed
    ``BLOCK`` poses at a time on the lanes of the frames kernel's ``chain`` (each lane the
    one pose's arithmetic)."""
    mr, nx = J.shape[1], X.shape[1]
    n, m = M[D].shape[0], M[D].shape[1]
    LG, TP, plat = M[LEG], M[TPL], M[PLAT]
    a, b = np.empty((mr, 6)), np.empty((mr, 6))
    A, G = np.empty((6, 6)), np.zeros((3, 3))
    piv = np.zeros(6, np.int64)
    Xb, FA = np.zeros((nx, BLOCK)), np.zeros((n, m, 6, BLOCK))
    fa, TW = np.zeros((m, 6)), np.zeros((m, 6))
    RT, Rsl = np.zeros((12, BLOCK)), np.zeros((m, 12, BLOCK))
    CS, E = np.zeros((2, BLOCK)), np.zeros((3, 3))
    _unit_wrenches(ref, centre, L, b)
    for p0 in range(start, stop, BLOCK):
        nb = min(BLOCK, stop - p0)
        for l in range(nb):
            for k in range(nx):
                Xb[k, l] = X[p0 + l, k]
        for g in range(legs.shape[0]):
            i = legs[g]
            if orients(LG[i], TP[i]):
                chain(M, i, Xb, i * m, FA[i], RT, nb, BLOCK, False, Rsl, E, CS)
        for l in range(nb):
            p = p0 + l
            s = out[p]
            if s == 0.0 or s != s:
                out[p] = 0.0
                continue
            unit = False
            for g in range(legs.shape[0]):
                i = legs[g]
                if orients(LG[i], TP[i]):
                    for j in range(LG[i, L_SIZE]):
                        for q in range(6):
                            fa[j, q] = FA[i, j, q, l]
                        joint_twist(M, i, j, fa, TW[j])
                    d = leg_orientation(LG[i], TP[i], plat, TW, J[p], A, piv)
                else:
                    if not unit:
                        _unit_wrenches(J[p], centre, L, a)
                        unit = True
                    d = _against(a, b, TP[i, T_CROW], TP[i, T_K], G)
                s = s * d
            out[p] = s


@parallel
def oriented_parallel(M, X, J, legs, ref, centre, L, out, nchunks):
    N = J.shape[0]
    for c in prange(nchunks):
        oriented_range(M, X, J, legs, ref, centre, L, out, c * N // nchunks,
                       (c + 1) * N // nchunks)


@inner
def _against(a, b, r0, k, G):
    """The sign of ``det (C C_ref^T)`` of rows ``r0:r0+k`` (at most three) of ``a`` against
    those of ``b``; 0 below :data:`ORIENT_MIN`."""
    for i in range(k):
        for j in range(k):
            x = 0.0
            for q in range(6):
                x += a[r0 + i, q] * b[r0 + j, q]
            G[i, j] = x
    d = G[0, 0]
    if k == 2:
        d = G[0, 0] * G[1, 1] - G[0, 1] * G[1, 0]
    elif k == 3:
        d = (G[0, 0] * (G[1, 1] * G[2, 2] - G[1, 2] * G[2, 1])
             - G[0, 1] * (G[1, 0] * G[2, 2] - G[1, 2] * G[2, 0])
             + G[0, 2] * (G[1, 0] * G[2, 1] - G[1, 1] * G[2, 0]))
    if not abs(d) >= ORIENT_MIN:
        return 0.0
    return 1.0 if d > 0.0 else -1.0


@inner
def _unit_wrenches(W, c, L, out):
    """The wrenches ``W (mr, 6)`` about ``c``, moments over ``L`` (the rows' own
    normalisation, :func:`._rows._normalise_wrench`), at unit norm."""
    for r in range(W.shape[0]):
        _normalise_wrench(W[r, 0], W[r, 1], W[r, 2], W[r, 3], W[r, 4], W[r, 5], c, L, out[r])
        unit_row(out, r)
