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
motion: ``det J`` times those signs changes sign at a singularity only.  The joint twists
follow the joints' own axes (no convention), in chain order, but for an S joint: its three
R axes are one representation of a ball, whose other branch (the same ball, the same link)
turns some of them over, so its twists are the rotations about the world's X, Y and Z axes
through its centre, whatever the branch.  A leg with idle motions (more
joints than that) is oriented against its rows at the model's reference pose instead.  The
rows are taken about the normalisation centre ``c``, moments and velocities over ``L``, at
unit norm: a determinant whose sign a move of the base frame or a change of units keeps.
"""

import math

import numpy as np

from numba import prange

from ._jit import entry, inner, one_lane, parallel
from ._kin import chain, joint_twist
from ._layout import BLOCK, D
from ._rows import _normalise_twist, _normalise_wrench
from ._small import lu_factor

#: ``|det (C_p C_ref^T)|`` of a leg's unit, length-normalised constraint rows against its
#: reference rows below which their orientation is not defined (a leg with idle motions
#: whose rows turned about a right angle from the reference pose's).
ORIENT_MIN = 1e-3


@entry
def oriented_range(M, X, J, ball, groups, ref, centre, L, det, out, start, stop):
    """``out[p] = det[p]`` times the orientation of each leg's constraint rows of ``J[p]
    (N, mr, 6)``, poses ``start:stop``; ``groups[g] = (leg, first row, stop row, joints)``:
    with ``joints + rows == 6`` the sign of ``det`` of the leg's joint twists (at the joint
    values ``X[p] (N, n m)``, the legs' slots in turn; an S joint's part ``ball[leg, j] = 1,
    2, 3``: the rotation about X, Y, Z through its centre) over its rows, else the sign of
    ``det (C_p C_ref^T)`` against ``ref (mr, 6)`` (0 below :data:`ORIENT_MIN`); 0 where
    ``det[p]`` is 0 (or not a number: an unreachable pose).  The legs' joints are formed
    ``BLOCK`` poses at a time on the lanes of the frames kernel's ``chain`` (each lane the
    one pose's arithmetic)."""
    mr, nx = J.shape[1], X.shape[1]
    n, m = M[D].shape[0], M[D].shape[1]
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
        for g in range(groups.shape[0]):
            leg = groups[g, 0]
            if groups[g, 3] + groups[g, 2] - groups[g, 1] == 6:
                chain(M, leg, Xb, leg * m, FA[leg], RT, nb, BLOCK, False, Rsl, E, CS)
        for l in range(nb):
            p = p0 + l
            s = det[p]
            if s == 0.0 or s != s:
                out[p] = 0.0
                continue
            _unit_wrenches(J[p], centre, L, a)
            for g in range(groups.shape[0]):
                leg, r0, r1, mj = groups[g, 0], groups[g, 1], groups[g, 2], groups[g, 3]
                k = r1 - r0
                if mj + k == 6:
                    for j in range(mj):
                        for q in range(6):
                            fa[j, q] = FA[leg, j, q, l]
                    for j in range(mj):
                        joint_twist(M, leg, j, fa, TW[j])
                    _unit_twists(TW, fa, ball[leg], mj, centre, L, A)
                    for i in range(k):
                        for q in range(6):
                            A[mj + i, q] = a[r0 + i, q]
                    d = lu_factor(A, 6, piv)
                else:
                    d = _against(a, b, r0, k, G)
                if d == 0.0:
                    s = 0.0
                    break
                if d < 0.0:
                    s = -s
            out[p] = s


@parallel
def oriented_parallel(M, X, J, ball, groups, ref, centre, L, det, out, nchunks):
    N = J.shape[0]
    for c in prange(nchunks):
        oriented_range(M, X, J, ball, groups, ref, centre, L, det, out, c * N // nchunks,
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
        _unit(out, r)


@inner
def _unit_twists(T, FA, ball, m, c, L, out):
    """The twists ``T[:m] (6,)`` (an S joint's parts: the rotations about X, Y, Z through its
    point ``FA[j, 3:]``) about ``c``, velocities over ``L`` (:func:`._rows._normalise_twist`),
    at unit norm, into the first ``m`` rows of ``out``."""
    t = np.empty(6)
    for r in range(m):
        if ball[r] > 0:               # [s x e; e], e the world axis, s the S centre
            for q in range(3):
                t[3 + q] = 1.0 if ball[r] == q + 1 else 0.0
            s0, s1, s2 = FA[r, 3], FA[r, 4], FA[r, 5]
            t[0], t[1], t[2] = s1 * t[5] - s2 * t[4], s2 * t[3] - s0 * t[5], s0 * t[4] - s1 * t[3]
            _normalise_twist(t, c, L, out[r])
        else:
            _normalise_twist(T[r], c, L, out[r])
        _unit(out, r)


@inner
def _unit(out, r):
    n = 0.0
    for q in range(6):
        n += out[r, q] * out[r, q]
    n = max(math.sqrt(n), 1e-300)
    for q in range(6):
        out[r, q] /= n
