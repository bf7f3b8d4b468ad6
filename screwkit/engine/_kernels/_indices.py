"""The motion/force transmission and constraint indices of N poses, compiled (private).

The definitions (power coefficient, where a wrench acts, the twists reciprocal to all rows
but one, redundant constraint rows) are in :mod:`screwkit.engine._transmission`; these are
the kernels that compute them, one pose at a time, ``prange`` over chunks of poses.

Inputs of :func:`indices_range` (poses first): ``J (N, m, 6)`` the rows about O (finite),
``couple (m,)`` 1 for pure-couple rows, ``keep (K,)`` the rows that take part (the
``n_a`` actuation rows of the active legs first, then the constraint rows), ``lines (N, l,
LINE_WIDTH)`` the joints the indices read (``LN_*`` columns, as :func:`pose_lines` forms
them): at ``lines[:, i]`` the platform-side joint of leg ``i`` (``LN_OUT_*``, the legs
first), at ``lines[:, in_leg[r]]`` the actuated joint's unit twist (``LN_V``) and the
joint after it (``LN_IN_*``) of the ``r``-th actuation row, ``row_leg (m,)``, the
normalisation ``centre (N, 3)``, ``length (N,)``, ``crank (N,)`` the rank of the
constraint rows where known (``-1``: unknown).
"""

import math

import numpy as np
from numba import prange

from ._jit import borrowed, borrowing, borrowing_inlined, entry, inner, parallel
from ._kin import forward, joint_twist
from ._layout import (BLOCK, L_ACT, L_SIZE, LEG, LN_IN_D, LN_IN_Q, LN_OUT_D, LN_OUT_Q, LN_V,
                      QS, ROT, TRANSLATION_RTOL)
from ._reciprocal import inverse_lanes, leverage_redundant, null_twists, svd_rows, unit_rows
from ._small import lu_sign


@borrowing_inlined
def _turning(M, i, first, stop, step):
    """The first slot from ``first`` towards ``stop`` (exclusive, by ``step``) of leg ``i``
    that turns (a rotation per unit value), -1 if none."""
    rot = M[ROT]
    for j in range(first, stop, step):
        if rot[i, j] != 0:
            return j
    return -1


@borrowing_inlined
def _line(M, i, j, fa, out, q0, d0):
    """The point ``out[q0:q0+3]`` and the axis (the unit twist's angular part)
    ``out[d0:d0+3]`` of joint ``j`` of leg ``i`` (its twist formed in ``out[LN_V:]``)."""
    tw = out[LN_V:LN_V + 6]
    joint_twist(M, i, j, fa, tw)
    for a in range(3):
        out[q0 + a] = fa[j, 3 + a]
        out[d0 + a] = tw[3 + a]


@inner
def pose_lines(M, unk, xs, p6fix, X, FA, FL, FE, FP, b, S, p6, Xr, lines):
    """The joints the transmission indices read, at the unknowns ``X``, into ``lines (n,
    LINE_WIDTH)`` (``LN_*`` columns; :func:`screwkit.engine._transmission.leg_screws`): per
    leg its last turning joint (the platform side; slot 0 where none), the first turning
    joint after its actuator (slot 0 where none) and its actuated joint's twist.

    The frames are those of buffer ``b`` (the pose's frames, from the solve), formed again
    in the other buffer where they would not be bit for bit those of the joint values as
    the solution gives them (``q = X QS``, handed back as ``q / QS``: a rounding for prismatic
    joints; or a platform from other pose parameters).  Returns the buffer read (its
    platform ``FP[...]`` is the pose's)."""
    nu = unk.shape[0]
    rounded_unknowns(M, nu, X, Xr)
    exact = True
    for k in range(6):
        p6[k] = p6fix[k]
    for k in range(nu):
        p6[unk[k]] = X[k] * xs[k]
    fp = FP[b]
    for k in range(6):
        exact = exact and p6[k] == fp[k]
    for k in range(X.shape[0]):
        exact = exact and Xr[k] == X[k]
    if not exact:
        b = 1 - b
        forward(M, unk, xs, p6fix, Xr, FA, FL, FE, FP, b, S, p6)
    lines_at(M, FA, b, lines)
    return b


@borrowing_inlined
def rounded_unknowns(M, nu, X, Xr):
    """``Xr``: the unknowns ``X`` with each joint value as the solution hands it back
    (``(X QS) / QS``, :func:`pose_lines`)."""
    qs = M[QS]
    n, m = qs.shape[0], qs.shape[1]
    for k in range(nu):
        Xr[k] = X[k]
    for i in range(n):
        for j in range(m):
            k = nu + i * m + j
            Xr[k] = (X[k] * qs[i, j]) / qs[i, j]


@borrowing_inlined
def lines_at(M, FA, b, lines):
    """The lines of :func:`pose_lines` from the frames in buffer ``b`` of ``FA``."""
    leg = M[LEG]
    for i in range(lines.shape[0]):
        fa, out = FA[b, i], lines[i]
        size, act = leg[i, L_SIZE], leg[i, L_ACT]
        act = act if act >= 0 else 0
        last = _turning(M, i, size - 1, -1, -1)
        _line(M, i, last if last >= 0 else 0, fa, out, LN_OUT_Q, LN_OUT_D)
        nxt = _turning(M, i, act + 1, size, 1)
        _line(M, i, nxt if nxt >= 0 else 0, fa, out, LN_IN_Q, LN_IN_D)
        joint_twist(M, i, act, fa, out[LN_V:LN_V + 6])


@borrowing_inlined
def power_one(W, V, p, couple):
    """``(zeta, arm)`` of one wrench ``W (6,)`` on one twist ``V (6,)``, ``p (3,)`` a point of
    the wrench axis (the formulas of :func:`screwkit.engine.power_coefficient`)."""
    ff = W[0] * W[0] + W[1] * W[1] + W[2] * W[2]
    lam = (W[0] * W[3] + W[1] * W[4] + W[2] * W[5]) / (ff if ff > 0 else 1.0)
    w0, w1, w2 = V[3], V[4], V[5]
    vp0 = V[0] + (w1 * p[2] - w2 * p[1])
    vp1 = V[1] + (w2 * p[0] - w0 * p[2])
    vp2 = V[2] + (w0 * p[1] - w1 * p[0])
    u0, u1, u2 = vp0 + lam * w0, vp1 + lam * w1, vp2 + lam * w2
    ww = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    if couple:
        num = abs(W[3] * w0 + W[4] * w1 + W[5] * w2)
        den = math.sqrt(W[3] * W[3] + W[4] * W[4] + W[5] * W[5]) * ww
    else:
        num = abs(W[0] * u0 + W[1] * u1 + W[2] * u2)
        den = math.sqrt(ff * (u0 * u0 + u1 * u1 + u2 * u2))
    zeta = num / den if den > 0 else 0.0
    vv = 0.0
    for k in range(6):
        vv += V[k] * V[k]
    arm = math.nan
    if ww > TRANSLATION_RTOL * math.sqrt(vv) and not couple:
        h0, h1, h2 = w0 / ww, w1 / ww, w2 / ww
        t = vp0 * h0 + vp1 * h1 + vp2 * h2
        e0, e1, e2 = vp0 - t * h0, vp1 - t * h1, vp2 - t * h2
        arm = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2) / ww
    return min(zeta, 1.0), arm


@borrowing_inlined
def entry_point(W, q, d, out):
    """``out (3,)``: the point of the axis of ``W (6,)`` nearest the line ``q + s d`` (its
    point nearest ``q`` where the two are parallel or ``d`` is 0)."""
    ff = W[0] * W[0] + W[1] * W[1] + W[2] * W[2]
    ff = ff if ff > 0 else 1.0
    p0 = (W[1] * W[5] - W[2] * W[4]) / ff
    p1 = (W[2] * W[3] - W[0] * W[5]) / ff
    p2 = (W[0] * W[4] - W[1] * W[3]) / ff
    sf = math.sqrt(ff)
    u0, u1, u2 = W[0] / sf, W[1] / sf, W[2] / sf
    dn = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    dn = dn if dn > 0 else 1.0
    h0, h1, h2 = d[0] / dn, d[1] / dn, d[2] / dn
    x0, x1, x2 = p0 - q[0], p1 - q[1], p2 - q[2]
    b = u0 * h0 + u1 * h1 + u2 * h2
    dd = u0 * x0 + u1 * x1 + u2 * x2
    e = h0 * x0 + h1 * x1 + h2 * x2
    den = 1.0 - b * b
    t = (b * e - dd) / den if den > 1e-12 else -dd
    out[0], out[1], out[2] = p0 + t * u0, p1 + t * u1, p2 + t * u2


@entry
def indices_range(J, couple, keep, n_a, lines, in_leg, row_leg, centre, length, crank, iti,
                  oti, in_arm, out_arm, cti, c_arm, red, start, stop):
    """The indices of the poses ``start:stop`` (module docstring; outputs as in
    :func:`screwkit.engine.transmission_indices`).  Returns a number (the workspace's owners
    visibly outlive the loop, which borrows them)."""
    cap = max(keep.shape[0], 6)
    Fo = (np.zeros((cap, 6)), np.zeros((cap, 6)), np.zeros((cap, 6)), np.zeros((cap, 6)),
          np.zeros((cap, cap)))
    Vo = (np.zeros(cap), np.zeros(3), np.zeros(3), np.zeros(6))
    Io = np.zeros(6, np.int64)
    Bo = (np.zeros(cap, np.bool_), np.zeros(cap, np.bool_))
    Lo = (np.zeros((6, 6, BLOCK)), np.zeros((6, BLOCK)), np.zeros((6, 6, BLOCK)))
    piv_lanes = np.zeros((6, BLOCK), np.int64)
    _indices_poses(borrowed(J), borrowed(couple), borrowed(keep), n_a, borrowed(lines),
                   borrowed(in_leg), borrowed(row_leg), borrowed(centre), borrowed(length),
                   borrowed(crank), borrowed(iti), borrowed(oti), borrowed(in_arm),
                   borrowed(out_arm), borrowed(cti), borrowed(c_arm), borrowed(red), start,
                   stop, borrowed(Fo), borrowed(Vo), borrowed(Io), borrowed(Bo), borrowed(Lo),
                   borrowed(piv_lanes))
    return (Fo[0].shape[0] + Vo[0].shape[0] + Io.shape[0] + Bo[0].shape[0]
            + Lo[0].shape[0] + piv_lanes.shape[0])


@borrowing
def _indices_poses(J, couple, keep, n_a, lines, in_leg, row_leg, centre, length, crank,
                   iti, oti, in_arm, out_arm, cti, c_arm, red, start, stop, Fw, Vw, Iw, Bw, Lw,
                   piv_lanes):
    """:func:`indices_range`'s loop over its poses, on borrowed views (no reference counts:
    a row view a wrench, a call of the kernels below with a dozen arrays), its workspace
    ``Fw, Vw, Iw, Bw`` (float matrices, float vectors, the order of singular values, flags) and ``Lw,
    piv_lanes`` (a block's lanes, :func:`._reciprocal.inverse_lanes`)."""
    K = keep.shape[0]
    kc = K - n_a
    Wn, Wu, Vn, B, Q = Fw
    s, pt, qn, vin = Vw
    order = Iw
    none, rc = Bw
    A_lanes, V_lanes = Lw[0], Lw[2]
    for p in range(start, stop):
        lane = (p - start) % BLOCK
        if K == 6 and lane == 0:
            inverse_lanes(J, keep, centre, length, p, min(BLOCK, stop - p), Wn, Wu, Lw,
                          piv_lanes)
        c0, c1, c2 = centre[p, 0], centre[p, 1], centre[p, 2]
        L = length[p]
        unit_rows(J, keep, p, c0, c1, c2, L, Wn, Wu)
        if K == 6 and lu_sign(A_lanes, 6, piv_lanes, lane) != 0.0:
            for r in range(6):          # (null_twists on this pose: the same operations)
                none[r] = False
                for c in range(6):
                    Vn[r, c] = V_lanes[r, c, lane]
        else:
            null_twists(Wu, K, Vn, none, B, Q, s, order)
        # redundant constraint rows (their leverage among the constraint rows)
        for r in range(kc):
            rc[r] = False
        if kc >= 2 and not (crank[p] >= kc):
            g = svd_rows(Wu[n_a:], kc, B, Q, s, order)
            leverage_redundant(Q, s, order, g, kc, rc)
        for r in range(kc):
            red[p, r] = rc[r]
            none[n_a + r] = none[n_a + r] or rc[r]
        for r in range(K):
            line = lines[p, row_leg[keep[r]]]
            qn[0] = (line[LN_OUT_Q] - c0) / L
            qn[1] = (line[LN_OUT_Q + 1] - c1) / L
            qn[2] = (line[LN_OUT_Q + 2] - c2) / L
            entry_point(Wn[r], qn, line[LN_OUT_D:LN_OUT_D + 3], pt)
            z, arm = power_one(Wn[r], Vn[r], pt, couple[keep[r]] != 0)
            if none[r]:
                z, arm = math.nan, math.nan
            if r < n_a:
                oti[p, r], out_arm[p, r] = z, arm * L
            else:
                cti[p, r - n_a], c_arm[p, r - n_a] = z, arm * L
        for r in range(n_a):
            line = lines[p, in_leg[r]]
            w0, w1, w2 = line[LN_V + 3], line[LN_V + 4], line[LN_V + 5]
            vin[0] = line[LN_V] + (w1 * c2 - w2 * c1)
            vin[1] = line[LN_V + 1] + (w2 * c0 - w0 * c2)
            vin[2] = line[LN_V + 2] + (w0 * c1 - w1 * c0)
            vin[3], vin[4], vin[5] = w0 * L, w1 * L, w2 * L
            qn[0] = (line[LN_IN_Q] - c0) / L
            qn[1] = (line[LN_IN_Q + 1] - c1) / L
            qn[2] = (line[LN_IN_Q + 2] - c2) / L
            entry_point(Wn[r], qn, line[LN_IN_D:LN_IN_D + 3], pt)
            z, arm = power_one(Wn[r], vin, pt, couple[keep[r]] != 0)
            iti[p, r], in_arm[p, r] = z, arm * L


@parallel
def indices_parallel(J, couple, keep, n_a, lines, in_leg, row_leg, centre, length, crank,
                     iti, oti, in_arm, out_arm, cti, c_arm, red, nchunks):
    N = J.shape[0]
    for c in prange(nchunks):
        indices_range(J, couple, keep, n_a, lines, in_leg, row_leg, centre, length, crank,
                      iti, oti, in_arm, out_arm, cti, c_arm, red,
                      c * N // nchunks, (c + 1) * N // nchunks)


@entry
def power_batch(W, V, p, couple, zeta, arm):
    """:func:`power_one` over ``M`` rows: ``W, V (M, 6)``, ``p (M, 3)``, ``couple (M,)``."""
    for i in range(W.shape[0]):
        zeta[i], arm[i] = power_one(W[i], V[i], p[i], couple[i] != 0)
