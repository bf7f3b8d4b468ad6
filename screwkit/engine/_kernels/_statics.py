"""Conditioning and statics of one pose's Jacobian, compiled (private).

Rows ``[f; m]`` (moments about the base origin) are moved to the centroid ``c`` of the
legs' points and ``o``, their moments divided by the characteristic length ``L`` (the RMS
distance of those points from ``c``) and scaled to unit norm: ``Jn``, unit-free and
frame-free.  Its singular values come from one-sided Jacobi; the condition number is
``s_1 / s_6``.  The statics solves ``J^T F_r = -W``: by LU for a square ``Jn``; with more
rows (statically indeterminate) the solution minimising ``sum_k c_k F_k^2`` (compliances
``c``: ``1`` for forces and linear actuators, ``1 / L^2`` for couples and rotary actuators by
default: ``sum F^2 + sum (C / L)^2`` minimal), through the normal equations; where the
condition exceeds ``REFINE``, by the pseudo-inverse.

The statics workspace ``SW`` of a thread: see :func:`make_statics_work`.
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, inner, lanes

from ._kin import platform_point
from ._layout import A, AP, BLOCK, D, LEG, L_SIZE, RANK_RTOL, REFINE
from ._eigen import jacobi_rows, singular_values_lanes
from ._small import lu_factor, lu_apply

(SW_JN, SW_D, SW_U, SW_V, SW_LU, SW_PIV, SW_Y, SW_JW, SW_G, SW_WN, SW_AP, SW_Z, SW_W,
 SW_COMP, SW_SP) = range(15)
#: Statics modes of a pose: LU of Jn^T, LU of the normal equations, pseudo-inverse.
MODE_SQUARE, MODE_NORMAL, MODE_PINV = 0, 1, 2
(CW_JN, CW_D, CW_O, CW_SV, CW_SC, CW_RANK, CW_COND, CW_U, CW_E, CW_S, CW_I, CW_R, CW_LU, CW_PIV,
 CW_JW, CW_G, CW_Z, CW_Y, CW_W, CW_COMP) = range(20)


@inner
def make_statics_work(mr):
    """A thread's statics workspace for ``mr`` rows."""
    r = max(mr, 6)
    return (np.zeros((r, 6)), np.zeros(r), np.zeros((r, 6)), np.zeros((r, r)),
            np.zeros((6, 6)), np.zeros(6, np.int64), np.zeros(r), np.zeros((r, 6)), np.zeros(r),
            np.zeros(6), np.zeros(3), np.zeros(6), np.zeros(6), np.zeros(r),
            np.zeros(8))


@borrowing_inlined
def _add_point(S, k, ls, x0, x1, x2):
    """One point into lane ``k`` of :func:`spread_lanes`'s sums ``S``."""
    s = lanes(S)
    s[k] += x0
    s[ls + k] += x1
    s[2 * ls + k] += x2
    s[3 * ls + k] += x0 * x0 + x1 * x1 + x2 * x2
    s[4 * ls + k] = max(s[4 * ls + k], abs(x0), abs(x1), abs(x2))


@borrowing_inlined
def spread_lanes(M, FA, FP, S, nb, ls):
    """The centroid and RMS spread of every leg's points (``A``, ``a``, the joint points) and
    the platform's origin ``o``, the normalisation of the rank decisions, at ``nb`` lanes of
    the frames ``FA (n, m, 6, ls)`` and platforms ``FP (27, ls)`` (one pose: the arrays
    without their lane axis, ``ls = 1``): into ``S (8, ls)`` the centroid (rows 0-2), the
    spread ``L`` (row 3) and ``o`` (rows 5-7).  The lane loops of one pose's sums, in its
    order, so that each lane's values are the pose's alone, bit for bit."""
    Am, ap, leg = M[A], M[AP], M[LEG]
    n, m = M[D].shape[0], M[D].shape[1]
    fa, fp, s = lanes(FA), lanes(FP), lanes(S)
    S0, S1, S2, Q, BIG = 0, ls, 2 * ls, 3 * ls, 4 * ls
    for k in range(nb):
        s[S0 + k] = s[S1 + k] = s[S2 + k] = s[Q + k] = s[BIG + k] = 0.0
    count = 1
    for i in range(n + 1):
        size = leg[i, L_SIZE] if i < n else -1
        count += size + 2 if i < n else 0
        for j in range(-2, size):
            o = (i * m + j) * 6 * ls
            if i == n:
                for k in range(nb):
                    _add_point(S, k, ls, fp[15 * ls + k], fp[16 * ls + k], fp[17 * ls + k])
            elif j == -2:
                a0, a1, a2 = Am[i, 0], Am[i, 1], Am[i, 2]
                for k in range(nb):
                    _add_point(S, k, ls, a0, a1, a2)
            elif j == -1:
                for k in range(nb):
                    _add_point(S, k, ls, platform_point(ap, i, FP, k, ls, 0),
                               platform_point(ap, i, FP, k, ls, 1),
                               platform_point(ap, i, FP, k, ls, 2))
            else:
                for k in range(nb):
                    _add_point(S, k, ls, fa[o + 3 * ls + k], fa[o + 4 * ls + k],
                               fa[o + 5 * ls + k])
    for k in range(nb):
        s0, s1, s2 = s[S0 + k] / count, s[S1 + k] / count, s[S2 + k] / count
        big = s[BIG + k]
        s[S0 + k], s[S1 + k], s[S2 + k] = s0, s1, s2
        L = math.sqrt(max(s[Q + k] / count - (s0 * s0 + s1 * s1 + s2 * s2), 0.0))
        if L <= 1e-12 * big:
            L = big
        s[Q + k] = L if L > 0 else 1.0
        for r in range(3):
            s[(5 + r) * ls + k] = fp[(15 + r) * ls + k]


@borrowing_inlined
def normalise_lanes(J, mr, S, Jn, d, nb, ls):
    """The rows ``J[:mr] (mr, 6, ls)`` of ``nb`` lanes about their centroids ``S[0:3]``,
    moments over their spreads ``S[3]`` (:func:`spread_lanes`'s ``S (8, ls)``), unit, into
    ``Jn (mr, 6, ls)``, their norms into ``d (mr, ls)`` (one pose: the arrays without their
    lane axis, ``ls = 1``).  Each lane's operations are one pose's, so its values are the
    pose's alone, bit for bit."""
    for r in range(mr):
        _normalise_row(J, S, Jn, d, r, nb, ls)


@borrowing
def _normalise_row(J, S, Jn, d, r, nb, ls):
    """Row ``r`` of :func:`normalise_lanes` (a function of its own: inline, its loop's
    temporaries outlived it in the caller's loop over the rows, and LLVM left it scalar,
    nine divisions a row and lane one after the other)."""
    j, s, jn, dd = lanes(J), lanes(S), lanes(Jn), lanes(d)
    o = r * 6 * ls
    for k in range(nb):
        c0, c1, c2, L = s[k], s[ls + k], s[2 * ls + k], s[3 * ls + k]
        f0, f1, f2 = j[o + k], j[o + ls + k], j[o + 2 * ls + k]
        m0 = (j[o + 3 * ls + k] - (c1 * f2 - c2 * f1)) / L
        m1 = (j[o + 4 * ls + k] - (c2 * f0 - c0 * f2)) / L
        m2 = (j[o + 5 * ls + k] - (c0 * f1 - c1 * f0)) / L
        t = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2 + m0 * m0 + m1 * m1 + m2 * m2)
        t = t if t > 0 else 1.0
        dd[r * ls + k] = t
        jn[o + k], jn[o + ls + k], jn[o + 2 * ls + k] = f0 / t, f1 / t, f2 / t
        jn[o + 3 * ls + k], jn[o + 4 * ls + k], jn[o + 5 * ls + k] = m0 / t, m1 / t, m2 / t


@borrowing
def normalise_rows(J, mr, c, L, SW):
    """One pose's rows ``J (mr, 6)`` about ``c (3,)``, moments over ``L``, unit
    (:func:`normalise_lanes`), into ``SW[SW_JN]``, their norms into ``SW[SW_D]``."""
    S = SW[SW_SP]
    S[0], S[1], S[2], S[3] = c[0], c[1], c[2], L
    normalise_lanes(J, mr, S, SW[SW_JN], SW[SW_D], 1, 1)


@inner
def make_conditioning_work(mr, B):
    """A thread's conditioning workspace for blocks of up to ``B`` lanes of ``mr`` rows: the
    lanes' normalised rows ``Jn (mr, 6, B)``, their norms ``d (mr, B)``, the platforms'
    origins ``o (3, B)``, the singular values of all rows and of the constraint rows ``(6,
    B)`` each, ranks ``(2, B)`` (int) and conditions ``(2, B)``, and the scratch of
    :func:`._eigen.singular_values_lanes`; then the statics of the lanes
    (:func:`._driver.statics_block`): the LU factors ``(6, 6, BLOCK)``, their interchanges
    ``(6, BLOCK)`` (int) and the right-hand sides ``(6, BLOCK)`` (the lane stride
    :func:`._small.lu_block` is compiled for, whatever ``B``), the weighted rows ``(mr, 6,
    B)`` and weights ``(mr, B)``, the efforts ``(mr, B)``, the workloads ``(6, B)`` and the
    compliances ``(mr, B)``.  (A launch of one pose takes ``B`` 1: for six rows a workspace of
    26 kB instead of 113 kB, zeroed each launch.)"""
    r = max(mr, 1)
    return (np.zeros((r, 6, B)), np.zeros((r, B)), np.zeros((3, B)),
            np.zeros((6, B)), np.zeros((6, B)), np.zeros((2, B), np.int64), np.zeros((2, B)),
            np.zeros((6, 6, B)), np.zeros((6, B)), np.zeros((6, B)), np.zeros((4, B), np.int64),
            np.zeros((max(mr, 6), 6)), np.zeros((6, 6, BLOCK)), np.zeros((6, BLOCK), np.int64),
            np.zeros((r, 6, B)), np.zeros((r, B)), np.zeros((6, BLOCK)), np.zeros((r, B)),
            np.zeros((6, B)), np.zeros((r, B)))


@borrowing
def conditioning_lanes(CW, mr, n_act, nb):
    """The conditioning of the lanes ``0..nb-1`` of ``CW`` (:func:`make_conditioning_work`; its
    ``Jn`` set): the singular values of ``Jn[:mr]`` into ``CW[CW_SV][:min(mr, 6)]`` (NaN
    beyond; all NaN for a lane with a non-finite ``Jn``), the rank and condition number into
    ``CW[CW_RANK][0]``, ``CW[CW_COND][0]``, those of the constraint rows (after the ``n_act``
    actuation rows) into ``CW[CW_RANK][1]``, ``CW[CW_COND][1]``."""
    Jn, sv, sc, RK, CD = CW[CW_JN], CW[CW_SV], CW[CW_SC], CW[CW_RANK], CW[CW_COND]
    U, E, S, I, R = CW[CW_U], CW[CW_E], CW[CW_S], CW[CW_I], CW[CW_R]
    ls = Jn.shape[2]
    k = min(mr, 6)
    # a lane with a NaN or an infinity in Jn: -1 (an entry times 0 is NaN exactly there;
    # lane loops of arithmetic, vectorised); E is free until the singular values
    acc = E[0]
    for l in range(nb):
        acc[l] = 0.0
    for r in range(mr):
        for q in range(6):
            for l in range(nb):
                acc[l] += Jn[r, q, l] * 0.0
    for l in range(nb):
        RK[0, l] = 0 if acc[l] == 0.0 else -1
    singular_values_lanes(Jn, 0, mr, U, sv, k, E, S, I, R, nb, ls)
    mc = mr - n_act
    kk = max(0, 6 - n_act)
    kc = min(mc, 6)
    if mc > 0:
        singular_values_lanes(Jn, n_act, mc, U, sc, kc, E, S, I, R, nb, ls)
    for l in range(nb):
        if RK[0, l] < 0:
            for q in range(6):
                sv[q, l] = math.nan
            RK[0, l], CD[0, l], RK[1, l], CD[1, l] = 0, math.nan, 0, math.nan
            continue
        top = max(sv[0, l], 1e-300) if k else 1.0
        rank = 0
        for q in range(k):
            if sv[q, l] > RANK_RTOL * top:
                rank += 1
        cond = math.inf
        if k >= 6 and sv[5, l] > 0:
            cond = sv[0, l] / sv[5, l]
        c_rank = 0
        c_cond = 1.0 if kk == 0 else math.inf
        if mc > 0:
            ctop = max(sc[0, l], 1e-300)
            for q in range(kc):
                if sc[q, l] > RANK_RTOL * ctop:
                    c_rank += 1
            if kk > 0 and kc >= kk and sc[kk - 1, l] > 0:
                c_cond = sc[0, l] / sc[kk - 1, l]
        RK[0, l], CD[0, l], RK[1, l], CD[1, l] = rank, cond, c_rank, c_cond


@borrowing_inlined
def statics_prepare(mr, sv, comp, SW):
    """Factor the statics of the pose in ``SW`` (``Jn``, ``d`` set; ``comp (mr,)`` the
    compliances); returns ``(mode, det_sign)`` (the sign of ``det J`` for a square ``J``)."""
    Jn, d, Jw, g, LU, piv = SW[SW_JN], SW[SW_D], SW[SW_JW], SW[SW_G], SW[SW_LU], SW[SW_PIV]
    k = min(mr, 6)
    well = k == 6 and sv[5] * REFINE > sv[0]
    sign = 0.0
    if mr == 6:
        for r in range(6):
            for q in range(6):
                LU[q, r] = Jn[r, q]
        sign = lu_factor(LU, 6, piv)
        if well:                        # the weighted rows are not needed: LU of Jn^T
            return MODE_SQUARE, sign
    for r in range(mr):
        g[r] = d[r] / math.sqrt(comp[r]) if mr > 6 else 1.0
        for q in range(6):
            Jw[r, q] = Jn[r, q] * g[r]
    if well:
        for a in range(6):
            for b in range(6):
                s = 0.0
                for r in range(mr):
                    s += Jw[r, a] * Jw[r, b]
                LU[a, b] = s
        lu_factor(LU, 6, piv)
        return MODE_NORMAL, sign
    U, V = SW[SW_U], SW[SW_V]
    for r in range(mr):
        for q in range(6):
            U[r, q] = Jw[r, q]
    jacobi_rows(U, mr, V, True)
    return MODE_PINV, sign


@borrowing_inlined
def normalise_wrench(W, c, L, out):
    f0, f1, f2 = W[0], W[1], W[2]
    out[0], out[1], out[2] = f0, f1, f2
    out[3] = (W[3] - (c[1] * f2 - c[2] * f1)) / L
    out[4] = (W[4] - (c[2] * f0 - c[0] * f2)) / L
    out[5] = (W[5] - (c[0] * f1 - c[1] * f0)) / L


@borrowing_inlined
def statics_apply(mode, mr, W, c, L, SW, values):
    """``F_r`` into ``values[:mr]`` for the workload ``W (6,)`` about O (after
    :func:`statics_prepare`)."""
    Jw, d, g, LU, piv, Wn, y = SW[SW_JW], SW[SW_D], SW[SW_G], SW[SW_LU], SW[SW_PIV], \
        SW[SW_WN], SW[SW_Y]
    normalise_wrench(W, c, L, Wn)
    if mode == MODE_SQUARE:
        for q in range(6):
            y[q] = -Wn[q]
        lu_apply(LU, 6, piv, y)
    elif mode == MODE_NORMAL:
        z = SW[SW_Z]
        for q in range(6):
            z[q] = -Wn[q]
        lu_apply(LU, 6, piv, z)
        for r in range(mr):
            s = 0.0
            for q in range(6):
                s += Jw[r, q] * z[q]
            y[r] = s
    else:
        # y = -pinv(Jw^T) Wn = -sum_i V[:, i] (u_i . Wn) / s_i^2, s_i = |u_i| above the cut-off
        U, V = SW[SW_U], SW[SW_V]
        smax = 0.0
        for i in range(mr):
            s = 0.0
            for q in range(6):
                s += U[i, q] * U[i, q]
            smax = max(smax, math.sqrt(s))
        cut = max(mr, 6) * 2.220446049250313e-16 * smax
        for r in range(mr):
            y[r] = 0.0
        for i in range(mr):
            s2 = 0.0
            p = 0.0
            for q in range(6):
                s2 += U[i, q] * U[i, q]
                p += U[i, q] * Wn[q]
            if math.sqrt(s2) > cut:
                f = p / s2
                for r in range(mr):
                    y[r] -= V[r, i] * f
    for r in range(mr):
        values[r] = y[r] * g[r] / d[r] if mr > 6 else y[r] / d[r]


@borrowing_inlined
def equilibrium(J, mr, values, W, c, L, d):
    """``|sum_r F_r J_r + W|`` over the largest of ``|W|`` and the row wrenches ``|F_r J_r|``,
    all length-normalised about the centroid (unit-free, frame-free)."""
    # the sum in scalars (no array allocated per pose)
    f0, f1, f2, m0, m1, m2 = W[0], W[1], W[2], W[3], W[4], W[5]
    rows = 0.0
    for r in range(mr):
        v = values[r]
        f0 += v * J[r, 0]
        f1 += v * J[r, 1]
        f2 += v * J[r, 2]
        m0 += v * J[r, 3]
        m1 += v * J[r, 4]
        m2 += v * J[r, 5]
        rows = max(rows, abs(v) * d[r])
    t3 = (m0 - (c[1] * f2 - c[2] * f1)) / L
    t4 = (m1 - (c[2] * f0 - c[0] * f2)) / L
    t5 = (m2 - (c[0] * f1 - c[1] * f0)) / L
    num = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2 + t3 * t3 + t4 * t4 + t5 * t5)
    f0, f1, f2 = W[0], W[1], W[2]
    t3 = (W[3] - (c[1] * f2 - c[2] * f1)) / L
    t4 = (W[4] - (c[2] * f0 - c[0] * f2)) / L
    t5 = (W[5] - (c[0] * f1 - c[1] * f0)) / L
    scale = max(math.sqrt(f0 * f0 + f1 * f1 + f2 * f2 + t3 * t3 + t4 * t4 + t5 * t5), rows)
    return num / (scale if scale > 0 else 1.0)


@borrowing_inlined
def amplification(values, mr, torque, W, o, L):
    """The largest effort over the workload's size, consistent units: couples and rotary
    actuator torques over ``L``; the size ``sqrt(|F|^2 + |T / L|^2)`` with ``T`` the torque
    at ``o`` (``m - o x f``)."""
    eff = 0.0
    for r in range(mr):
        e = abs(values[r]) / (L if torque[r] else 1.0)
        if e > eff:
            eff = e
    f0, f1, f2 = W[0], W[1], W[2]
    t0 = W[3] - (o[1] * f2 - o[2] * f1)
    t1 = W[4] - (o[2] * f0 - o[0] * f2)
    t2 = W[5] - (o[0] * f1 - o[1] * f0)
    size = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2 + (t0 * t0 + t1 * t1 + t2 * t2) / (L * L))
    return eff / max(size, 1e-300)


@borrowing_inlined
def workload_about_origin(F, T, o, W):
    """``W = [F; T + o x F]``."""
    W[0], W[1], W[2] = F[0], F[1], F[2]
    W[3] = T[0] + o[1] * F[2] - o[2] * F[1]
    W[4] = T[1] + o[2] * F[0] - o[0] * F[2]
    W[5] = T[2] + o[0] * F[1] - o[1] * F[0]
