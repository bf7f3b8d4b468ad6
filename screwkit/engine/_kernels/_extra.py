"""Batch kernels on a solved batch (private): the statics of given Jacobians under one or
more workloads, the legs' wrenches and ``T_r``, the rows at given unknowns.

``statics_range``/``statics_parallel`` take the Jacobians ``J (N, mr, 6)`` and their
normalisation (``centre (N, 3)``, ``length (N,)``) and singular values ``sv (N, k)``, the
workloads ``Wall (N, K, 6)`` about O, the platform centres ``o (N, 3)``, the compliances
``comp`` (``(N or 1, mr)``, or none: the least-norm default from ``torque (mr,)``), and
fill ``values (N, K, mr)``, the equilibrium residuals ``eq (N, K)`` and the force
amplifications ``amp (N, K)``.
"""

import math

import numpy as np
from numba import prange

from ._closures import predict
from ._jit import entry, one_lane, parallel
from ._kin import chain, closure_one, joint_twist, platform
from ._geometry import eval_points, leg_setup
from ._layout import BLEN, BLOCK, D, DIRS, HINGE, LEG, L_SIZE, ORDER, PLAT, PTS, ROWS
from ._newton import home_vector
from ._rows import RW_CTX, RW_PV, RW_TW, make_rows_work
from ._small import lu_block, lu_sign

from ._statics import (CW_COND, CW_JN, CW_RANK, CW_SV, SW_COMP, SW_D, SW_JN, amplification,
                       conditioning_lanes, equilibrium, make_conditioning_work, make_statics_work,
                       normalise_lanes, normalise_rows, statics_apply, statics_prepare,
                       workload_about_origin)


@entry
def statics_range(J, centre, length, sv, comp, torque, Wall, o, values, eq, amp, start, stop):
    mr = J.shape[1]
    SW = make_statics_work(mr)
    cp = SW[SW_COMP]
    K = Wall.shape[1]
    for p in range(start, stop):
        L = length[p]
        c = centre[p]
        normalise_rows(J[p], mr, c, L, SW)
        for r in range(mr):
            if comp.shape[0] == 0:
                cp[r] = 1.0 / (L * L) if torque[r] else 1.0
            else:
                cp[r] = comp[p if comp.shape[0] > 1 else 0, r]
        mode, _ = statics_prepare(mr, sv[p], cp, SW)
        for k in range(K):
            statics_apply(mode, mr, Wall[p, k], c, L, SW, values[p, k])
            eq[p, k] = equilibrium(J[p], mr, values[p, k], Wall[p, k], c, L, SW[SW_D])
            amp[p, k] = amplification(values[p, k], mr, torque, Wall[p, k], o[p], L)


@parallel
def statics_parallel(J, centre, length, sv, comp, torque, Wall, o, values, eq, amp, nchunks):
    N = J.shape[0]
    for c in prange(nchunks):
        statics_range(J, centre, length, sv, comp, torque, Wall, o, values, eq, amp,
                      c * N // nchunks, (c + 1) * N // nchunks)


@entry
def leg_wrenches_range(J, values, row_leg, n_act, A, a, con_w, leg_w, t_r, start, stop):
    """Each leg's constraint wrench ``con_w (N, K, n, 6)`` and total wrench ``leg_w`` about
    O (sums of its rows' ``F_r J_r``; ``leg_w`` of size 0: not formed), and ``T_r (N, K,
    n)``: the moment of the constraint wrench about ``A_i`` along ``(a_i - A_i) / r_i``."""
    mr = J.shape[1]
    n = A.shape[0]
    K = values.shape[1]
    total = leg_w.shape[0] > 0
    for p in range(start, stop):
        for k in range(K):
            cw = con_w[p, k]
            for i in range(n):
                for q in range(6):
                    cw[i, q] = 0.0
                    if total:
                        leg_w[p, k, i, q] = 0.0
            for r in range(mr):
                i = row_leg[r]
                v = values[p, k, r]
                for q in range(6):
                    x = v * J[p, r, q]
                    if r >= n_act:
                        cw[i, q] += x
                    if total:
                        leg_w[p, k, i, q] += x
            for i in range(n):
                d0, d1, d2 = a[p, i, 0] - A[i, 0], a[p, i, 1] - A[i, 1], a[p, i, 2] - A[i, 2]
                nd = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                f0, f1, f2 = cw[i, 0], cw[i, 1], cw[i, 2]
                m0 = cw[i, 3] - (A[i, 1] * f2 - A[i, 2] * f1)
                m1 = cw[i, 4] - (A[i, 2] * f0 - A[i, 0] * f2)
                m2 = cw[i, 5] - (A[i, 0] * f1 - A[i, 1] * f0)
                t_r[p, k, i] = (m0 * d0 + m1 * d1 + m2 * d2) / nd


@parallel
def leg_wrenches_parallel(J, values, row_leg, n_act, A, a, con_w, leg_w, t_r, nchunks):
    N = J.shape[0]
    for c in prange(nchunks):
        leg_wrenches_range(J, values, row_leg, n_act, A, a, con_w, leg_w, t_r,
                           c * N // nchunks, (c + 1) * N // nchunks)



@entry
def frames_range(M, unk, xs, P6, X, FAo, FPo, Rso, tso, bars, tw, res, start, stop):
    """The frames of the unknowns ``X (N, nx)``: every joint's current axis and point
    ``FAo (N, n, m, 6)``, the platform ``FPo (N, 27)``, the closure residual ``res``; with
    ``Rso``/``tso`` of N rows the displacement after each slot (padded slots: the leg's end),
    with ``bars`` of N rows the parallelograms' current bars ``|b| d x R_j h`` (the hinge
    turned with the link), with ``tw`` of N rows every joint's unit twist ``[v; w]`` about
    O (zero in padded slots)."""
    n, m = M[D].shape[0], M[D].shape[1]
    nu = unk.shape[0]
    S = np.zeros((6, 3, 3))
    p6 = np.zeros(6)
    R = np.zeros((3, 3))
    t = np.zeros(3)
    RT = np.zeros((12, 1))          # the end displacement of a block of one lane
    e = np.zeros(6)
    Rsl = np.zeros((m, 12, 1))      # the displacement after each slot (R row-major, t)
    CS = np.zeros((2, 1))
    slots = Rso.shape[0] > 0 or bars.shape[0] > 0
    blen, hinge, leg = M[BLEN], M[HINGE], M[LEG]
    for p in range(start, stop):
        for k in range(6):
            p6[k] = P6[p, k]
        for k in range(nu):
            p6[unk[k]] = X[p, k] * xs[k]
        for k in range(6):
            FPo[p, k] = p6[k]
        fpl = one_lane(FPo[p])          # blocks of one lane
        platform(M[ORDER], M[PLAT], fpl)
        r = 0.0
        for i in range(n):
            size = leg[i, L_SIZE]
            chain(M, i, one_lane(X[p]), nu + i * m, one_lane(FAo[p, i]), RT, 1, 1, slots, Rsl,
                  S[0], CS)
            for a in range(3):
                for b in range(3):
                    R[a, b] = RT[3 * a + b, 0]
                t[a] = RT[9 + a, 0]
            closure_one(M[PLAT], fpl, RT, one_lane(e), CS, S[0])
            for q in range(6):
                if not abs(e[q]) <= r:
                    r = abs(e[q])
            if tw.shape[0]:
                for j in range(size):
                    joint_twist(M, i, j, FAo[p, i], tw[p, i, j])
            if Rso.shape[0]:
                for j in range(m):
                    for a in range(3):
                        tso[p, i, j, a] = Rsl[j, 9 + a, 0] if j < size else t[a]
                        for b in range(3):
                            Rso[p, i, j, a, b] = Rsl[j, 3 * a + b, 0] if j < size else R[a, b]
            if bars.shape[0]:
                for j in range(size):
                    if blen[i, j] > 0.0:
                        h = hinge[i, j]
                        hn = np.zeros(3)
                        for a in range(3):
                            hn[a] = (Rsl[j, 3 * a, 0] * h[0] + Rsl[j, 3 * a + 1, 0] * h[1]
                                     + Rsl[j, 3 * a + 2, 0] * h[2])
                        d = FAo[p, i, j]
                        bars[p, i, j, 0] = blen[i, j] * (d[1] * hn[2] - d[2] * hn[1])
                        bars[p, i, j, 1] = blen[i, j] * (d[2] * hn[0] - d[0] * hn[2])
                        bars[p, i, j, 2] = blen[i, j] * (d[0] * hn[1] - d[1] * hn[0])
        res[p] = r


@parallel
def frames_parallel(M, unk, xs, P6, X, FAo, FPo, Rso, tso, bars, tw, res, nchunks):
    N = P6.shape[0]
    for c in prange(nchunks):
        frames_range(M, unk, xs, P6, X, FAo, FPo, Rso, tso, bars, tw, res, c * N // nchunks,
                     (c + 1) * N // nchunks)


@entry
def normalise_batch(J, centre, length, Jn, d):
    """The rows of ``J (N, m, 6)`` about the centroid, moments over the length, unit
    (``Jn``), and their norms ``d (N, m)``."""
    S = np.zeros(8)
    for p in range(J.shape[0]):
        for q in range(3):
            S[q] = centre[p, q]
        S[3] = length[p]
        normalise_lanes(J[p], J.shape[1], S, Jn[p], d[p], 1, 1)


@entry
def amplification_batch(values, torque, W, o, L, out):
    """The force amplification ``out (N, K)`` of ``values (N, K, m)`` under ``W (N, K, 6)``."""
    for p in range(values.shape[0]):
        for k in range(values.shape[1]):
            out[p, k] = amplification(values[p, k], values.shape[2], torque, W[p, k], o[p], L[p])


@entry
def row_points_range(M, unk, xs, P6, X, J, out, start, stop):
    """A point of each row's line ``out (N, mr, 3)`` (left NaN where there is none): the
    row's named point, or for a force without one the point of its line nearest the leg's
    centroid (``ROWS[:, 2]`` says which)."""
    n, m = M[D].shape[0], M[D].shape[1]
    nu = unk.shape[0]
    rows = M[ROWS]
    S = np.zeros((6, 3, 3))
    p6 = np.zeros(6)
    fp = np.zeros(27)
    fa = np.zeros((m, 6))
    RT, CS = np.zeros((12, 1)), np.zeros((2, 1))
    RW = make_rows_work(m, M[PTS].shape[1], M[DIRS].shape[1])
    ctx, tw, pv = RW[RW_CTX], RW[RW_TW], RW[RW_PV]
    for p in range(start, stop):
        for k in range(6):
            p6[k] = P6[p, k]
        for k in range(nu):
            p6[unk[k]] = X[p, k] * xs[k]
        for k in range(6):
            fp[k] = p6[k]
        platform(M[ORDER], M[PLAT], one_lane(fp))
        for r in range(rows.shape[0]):
            i, code = rows[r, 0], rows[r, 2]
            if code == -2:
                continue
            fal = one_lane(fa)         # a block of one lane
            chain(M, i, one_lane(X[p]), nu + i * m, fal, RT, 1, 1, False, fal, S[0], CS)
            leg_setup(M, i, fa, fp, ctx, tw)
            if code >= 0:
                eval_points(M, i, fa, ctx, pv)
                for q in range(3):
                    out[p, r, q] = pv[code, q]
                continue
            f0, f1, f2 = J[p, r, 0], J[p, r, 1], J[p, r, 2]
            nf = f0 * f0 + f1 * f1 + f2 * f2
            if not nf > 0:
                continue
            m0, m1, m2 = J[p, r, 3], J[p, r, 4], J[p, r, 5]
            q0, q1, q2 = (f1 * m2 - f2 * m1) / nf, (f2 * m0 - f0 * m2) / nf, \
                (f0 * m1 - f1 * m0) / nf
            s = math.sqrt(nf)
            d0, d1, d2 = f0 / s, f1 / s, f2 / s
            c = ctx[2]
            u = d0 * (c[0] - q0) + d1 * (c[1] - q1) + d2 * (c[2] - q2)
            out[p, r, 0], out[p, r, 1], out[p, r, 2] = q0 + d0 * u, q1 + d1 * u, q2 + d2 * u


@entry
def predict_batch(Z, P6, out):
    """The home predictor's starts ``out (N, nx)`` at the given parameters ``P6 (N, 6)``."""
    Xh = np.zeros(out.shape[1])
    z = np.zeros((12, 1))
    home_vector(Z[0], Z[1], Z[6], Xh)
    for p in range(P6.shape[0]):
        predict(Z[7], Z[4], Z[8], Z[9], Z[10][0], one_lane(P6[p]), Xh, one_lane(out[p]), z,
                1, 1)


@entry
def equilibrium_batch(J, values, W, centre, length, out):
    """The equilibrium residuals ``out (N, K)`` of ``values (N, K, m)`` under ``W (N, K, 6)``."""
    mr = J.shape[1]
    SW = make_statics_work(mr)
    for p in range(J.shape[0]):
        normalise_rows(J[p], mr, centre[p], length[p], SW)
        for k in range(values.shape[1]):
            out[p, k] = equilibrium(J[p], mr, values[p, k], W[p, k], centre[p], length[p],
                                    SW[SW_D])


@entry
def workload_batch(F, T, o, W):
    """``W (N, K, 6) = [F; T + o x F]``, the workloads ``F, T (N, K, 3)`` at the platform
    centres ``o (N, 3)`` about ``O``: :func:`._statics.workload_about_origin`, the statics
    kernels' own (so that a workload given later gives the same bits as one given to the
    analysis)."""
    for p in range(F.shape[0]):
        for k in range(F.shape[1]):
            workload_about_origin(F[p, k], T[p, k], o[p], W[p, k])


@entry
def det_sign_batch(J, out):
    """The signs of ``det J`` of square ``J (N, 6, 6)`` (LU with partial pivoting), ``BLOCK``
    matrices at a time on the lanes of :func:`._small.lu_block` (each lane the operations
    of :func:`._small.lu_factor` on its matrix: the same signs)."""
    N = J.shape[0]
    A = np.zeros((6, 6, BLOCK))
    piv = np.zeros((6, BLOCK), np.int64)
    for p0 in range(0, N, BLOCK):
        nb = min(BLOCK, N - p0)
        for r in range(6):
            for c in range(6):
                for l in range(nb):
                    A[r, c, l] = J[p0 + l, r, c]
        lu_block(A, 6, piv, nb)
        for l in range(nb):
            out[p0 + l] = lu_sign(A, 6, piv, l)


@entry
def conditioning_batch(J, centre, length, n_act, sv, rank, cond, crank, ccond):
    """The conditioning of given rows ``J (N, m, 6)`` (the first ``n_act`` the actuation
    rows): singular values ``sv (N, min(m, 6))``, rank, condition number, and those of the
    constraint rows (:func:`._statics.conditioning_lanes`, ``BLOCK`` poses at a time)."""
    N, mr = J.shape[0], J.shape[1]
    SW = make_statics_work(mr)
    CW = make_conditioning_work(mr, BLOCK)
    cj, cs, RK, CD = CW[CW_JN], CW[CW_SV], CW[CW_RANK], CW[CW_COND]
    for p0 in range(0, N, BLOCK):
        nb = min(BLOCK, N - p0)
        for l in range(nb):
            p = p0 + l
            normalise_rows(J[p], mr, centre[p], length[p], SW)
            for r in range(mr):
                for q in range(6):
                    cj[r, q, l] = SW[SW_JN][r, q]
        conditioning_lanes(CW, mr, n_act, nb)
        for l in range(nb):
            p = p0 + l
            rank[p], cond[p], crank[p], ccond[p] = RK[0, l], CD[0, l], RK[1, l], CD[1, l]
            for q in range(sv.shape[1]):
                sv[p, q] = cs[q, l]


@entry
def face_component(mask, shape, seed, out):
    """The cells of the N-D grid ``mask`` (flat, C order, of ``shape``) connected to cell
    ``seed`` through faces of the grid, each within ``mask``: ``out`` (flat, False on
    entry) True there (nowhere if ``mask[seed]`` is False).  A depth-first fill with a stack
    of cell indices; each cell is pushed at most once (marked when pushed).  Returns the
    number of cells."""
    nd = shape.shape[0]
    stride = np.ones(nd, np.int64)
    for d in range(nd - 2, -1, -1):
        stride[d] = stride[d + 1] * shape[d + 1]
    if not mask[seed]:
        return 0
    stack = np.empty(mask.shape[0], np.int64)
    stack[0] = seed
    out[seed] = True
    top, count = 1, 1
    while top:
        top -= 1
        i = stack[top]
        rest = i
        for d in range(nd - 1, -1, -1):        # i's coordinate along each axis
            c = rest % shape[d]
            rest //= shape[d]
            for step in (-1, 1):
                if 0 <= c + step < shape[d]:
                    j = i + step * stride[d]
                    if mask[j] and not out[j]:
                        out[j] = True
                        stack[top] = j
                        top += 1
                        count += 1
    return count


@entry
def platform_points(fp, pts, R, o, a):
    """The platform of each pose from the kernels' ``fp (N, 27)``: its rotation ``R (N, 3,
    3)``, origin ``o (N, 3)`` and the points ``a (N, k, 3)`` of ``pts (k, 3)`` (platform
    frame) in the base frame, ``a = R p + o``.  Each product's sum in the order of the
    ``einsum`` this replaced (``(R_i0 p_0 + R_i2 p_2) + R_i1 p_1``): the same bits."""
    for n in range(fp.shape[0]):
        for i in range(3):
            o[n, i] = fp[n, 15 + i]
            for j in range(3):
                R[n, i, j] = fp[n, 6 + 3 * i + j]
        for k in range(pts.shape[0]):
            for i in range(3):
                s = R[n, i, 0] * pts[k, 0] + R[n, i, 2] * pts[k, 2]
                a[n, k, i] = (s + R[n, i, 1] * pts[k, 1]) + o[n, i]
