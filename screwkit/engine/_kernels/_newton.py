"""Gauss-Newton on the loop closures of one pose, compiled (private).

Unknowns: the dependent pose parameters (lengths over ``L``), then every leg's joint values
slot by slot (P and Pa over ``L``).  Equations: each leg's closure error ``e_i = [d / L; w]``
vanishes.  The step is solved leg by leg (a Schur complement): with ``G_i = T_i^T T_i``,
``dq_i = G_i^-1 T_i^T (e_i + P dx)``, and ``dx`` makes every ``e_i + P dx`` lie in the span
of ``T_i``: ``sum_i P^T (I - T_i G_i^-1 T_i^T) (P dx + e_i) = 0``.  A small Tikhonov shift of
``G_i`` gives the least-norm motion of idle joints (the spin of an S-S leg).  Each step is
halved up to six times until the closure error decreases; a pose that cannot decrease
stops (stalled).

The workspace ``W`` of a thread (see :func:`make_work`) holds two frame buffers (current and
trial), the twists, the leg systems and the vectors of the continuation and of the
representation singularity.
"""

import math

import numpy as np

from ._jit import borrowing, borrowing_inlined, inlined, inner, lanes, one_lane

from ._kin import forward
from ._layout import BLOCK, LEG, L_SIZE, PLAT, P_C, P_L, P_R0, ROT, STOP, TRN
from ._small import cholesky_lanes
from ._trig import trig_exceeds

#: Relative Tikhonov shift of a leg's Gram matrix (exact legs) and of a leg with more joints
#: than twist-space dimensions (idle motions: least-norm steps).
SHIFT, SHIFT_IDLE = 1e-13, 1e-7
#: Shift of the reduced system: only guards against a zero pivot.
SHIFT_REDUCED = 1e-20
HALVINGS = 6

# the workspace tuple
(W_FA, W_FL, W_FE, W_FP, W_S, W_P6, W_T, W_PT, W_G, W_B, W_XS, W_AR, W_STEP, W_XN, W_FROZ,
 W_XC, W_XB, W_P6S, W_XR, W_IDX, W_RHS, W_LS, W_PZ) = range(23)


@inner
def make_work(n, m, nx):
    """A thread's workspace for models of ``n`` legs, ``m`` slots and ``nx`` unknowns."""
    return (np.zeros((2, n, m, 6)), np.zeros((2, n, 12)), np.zeros((2, n, 6)),
            np.zeros((2, 27)), np.zeros((6, 3, 3)), np.zeros(6), np.zeros((n, m, 6)),
            np.zeros((6, 6)), np.zeros((m, m)), np.zeros((n, m, 7)), np.zeros((n, m, 7)),
            np.zeros((6, 7)), np.zeros(nx), np.zeros(nx), np.zeros((n, m), np.int64),
            np.zeros(nx), np.zeros(nx), np.zeros((4, 6)), np.zeros((6, nx)),
            np.zeros(m, np.int64), np.zeros((6, 1)), np.zeros((4, 1)), np.zeros((12, 1)))


@inlined
def newton_step(M, W, b, nu, frozen):
    """The Gauss-Newton step of one pose at the frames of buffer ``b`` into ``W[W_STEP]``
    (the platform columns ``W[W_PT][:, :nu]`` set by the caller): :func:`step_lanes` on a
    block of one lane (:func:`step_one`)."""
    step_one(M[LEG], M[ROT], M[TRN], M[PLAT], W[W_FA], W[W_FE], W[W_PT], W[W_T], W[W_G],
             W[W_B], W[W_XS], W[W_AR], W[W_STEP], W[W_RHS], W[W_LS], b, nu, frozen)


@borrowing
def step_one(leg, rot, trn, plat, FA, FE, Pt, T, G, B, Xs, Ar, step, rhs, LS, b, nu, frozen):
    """:func:`step_lanes` on one pose's arrays (the lane axis added by
    :func:`~._jit.one_lane`; a call passing the model and workspace tuples whole cost about
    0.4 us a step: this one passes the arrays it reads)."""
    step_lanes(leg, rot, trn, plat, one_lane(FA), one_lane(FE), one_lane(Pt), one_lane(T[0]),
               one_lane(G), one_lane(B[0]), one_lane(Xs), one_lane(Ar), one_lane(step),
               one_lane(rhs), LS, b, nu, frozen, 1, 1)


@borrowing
def step_block(leg, rot, trn, plat, FA, FE, Pt, T, G, B, Xs, Ar, step, rhs, LS, b, nu, frozen,
               nb):
    """:func:`step_lanes` on the ``nb`` lanes of a block of :data:`._layout.BLOCK`."""
    step_lanes(leg, rot, trn, plat, FA, FE, Pt, T, G, B, Xs, Ar, step, rhs, LS, b, nu, frozen,
               nb, BLOCK)


@inlined
def step_lanes(leg, rot, trn, plat, FA, FE, Pt, T, G, B, Xs, Ar, step, rhs, LS, b, nu, frozen,
               nb, ls):
    """The Gauss-Newton step of ``nb`` lanes (poses) at their frames in buffer ``b`` of ``FA
    (2, n, m, 6, ls)`` and ``FE (2, n, 6, ls)``, with their platform columns ``Pt (6, >= nu,
    ls)``, into ``step (nx, ls)`` (module docstring: the Schur complement leg by leg).  The
    lane axis is last; each lane computes exactly what one pose computes, in the same order,
    so one pose (``ls = 1``, :func:`step_one`) and a lane of a block give the same bits.
    ``ls`` is a constant where this function is inlined (1 or :data:`._layout.BLOCK`), so that
    LLVM vectorises the lane loops over the flat views (:func:`~._jit.flat`).  Scratch: ``T
    (m, 6, ls)`` the free joints' length-normalised twists, ``G (m, m, ls)`` the leg's Gram
    matrix, ``B (m, 7, ls)`` and ``Xs (n, m, 7, ls)`` ``T^T [e, P]`` and its solve, ``Ar (6,
    7, ls)`` the reduced system, ``rhs (6, 1, ls)``, ``LS (4, >= ls)`` (rows 0-2: row 3 is left to the callers' decrease
    tests, :func:`closure_sq`)."""
    L = plat[P_L]
    c0, c1, c2 = plat[P_C], plat[P_C + 1], plat[P_C + 2]
    n, m = Xs.shape[0], Xs.shape[1]
    w = Xs.shape[2]
    tf, gf, bf, af, pf, sf = lanes(T), lanes(G), lanes(B), lanes(Ar), lanes(Pt), lanes(step)
    ef = lanes(FE[b])
    npc = Pt.shape[1]
    tr, sh, acc = lanes(LS[0]), lanes(LS[1]), lanes(LS[2])
    for r in range(nu * (nu + 1)):
        for k in range(nb):
            af[((r // (nu + 1)) * 7 + r % (nu + 1)) * ls + k] = 0.0
    for i in range(n):
        size = leg[i, L_SIZE]
        xf, ff = lanes(Xs[i]), lanes(FA[b, i])
        nl = 0
        for j in range(size):
            if not frozen[i, j]:
                nl += 1
        for k in range(nb):
            tr[k] = float(m - nl)            # padded and frozen slots: identity rows
        # each free joint's twist, its row of the Gram matrix and of T^T [e, P]
        a = 0
        for j in range(size):
            if frozen[i, j]:
                continue
            r = rot[i, j]
            rl = r / L
            tj = trn[i, j]
            fj, ta = j * 6 * ls, a * 6 * ls
            for k in range(nb):
                d0, d1, d2 = ff[fj + k], ff[fj + ls + k], ff[fj + 2 * ls + k]
                p0, p1, p2 = ff[fj + 3 * ls + k] - c0, ff[fj + 4 * ls + k] - c1, \
                    ff[fj + 5 * ls + k] - c2
                tf[ta + k] = (p1 * d2 - p2 * d1) * rl + tj * d0
                tf[ta + ls + k] = (p2 * d0 - p0 * d2) * rl + tj * d1
                tf[ta + 2 * ls + k] = (p0 * d1 - p1 * d0) * rl + tj * d2
                tf[ta + 3 * ls + k] = r * d0
                tf[ta + 4 * ls + k] = r * d1
                tf[ta + 5 * ls + k] = r * d2
            for c in range(a + 1):
                tc, gac = c * 6 * ls, (a * m + c) * ls
                for k in range(nb):
                    gf[gac + k] = (0.0 + tf[ta + k] * tf[tc + k]
                                   + tf[ta + ls + k] * tf[tc + ls + k]
                                   + tf[ta + 2 * ls + k] * tf[tc + 2 * ls + k]
                                   + tf[ta + 3 * ls + k] * tf[tc + 3 * ls + k]
                                   + tf[ta + 4 * ls + k] * tf[tc + 4 * ls + k]
                                   + tf[ta + 5 * ls + k] * tf[tc + 5 * ls + k])
            gaa = (a * m + a) * ls
            for k in range(nb):
                tr[k] += gf[gaa + k]
            ei, ba = i * 6 * ls, a * w * ls
            for k in range(nb):
                s = (0.0 + tf[ta + k] * ef[ei + k] + tf[ta + ls + k] * ef[ei + ls + k]
                     + tf[ta + 2 * ls + k] * ef[ei + 2 * ls + k]
                     + tf[ta + 3 * ls + k] * ef[ei + 3 * ls + k]
                     + tf[ta + 4 * ls + k] * ef[ei + 4 * ls + k]
                     + tf[ta + 5 * ls + k] * ef[ei + 5 * ls + k])
                bf[ba + k] = s
                xf[ba + k] = s
            for u in range(nu):
                bu = ba + (1 + u) * ls
                for k in range(nb):
                    s = (0.0 + tf[ta + k] * pf[u * ls + k]
                         + tf[ta + ls + k] * pf[(npc + u) * ls + k]
                         + tf[ta + 2 * ls + k] * pf[(2 * npc + u) * ls + k]
                         + tf[ta + 3 * ls + k] * pf[(3 * npc + u) * ls + k]
                         + tf[ta + 4 * ls + k] * pf[(4 * npc + u) * ls + k]
                         + tf[ta + 5 * ls + k] * pf[(5 * npc + u) * ls + k])
                    bf[bu + k] = s
                    xf[bu + k] = s
            a += 1
        for k in range(nb):
            sh[k] = tr[k] / size * (SHIFT_IDLE if size > 6 else SHIFT)
        cholesky_lanes(G, nl, Xs[i], 1 + nu, LS[1], LS[2], nb, ls)
        # the reduced system's terms of this leg
        for u in range(nu):
            for v in range(nu):
                for k in range(nb):
                    acc[k] = 0.0
                for a in range(nl):
                    bu, xv = (a * w + 1 + u) * ls, (a * w + 1 + v) * ls
                    for k in range(nb):
                        acc[k] += bf[bu + k] * xf[xv + k]
                uv = (u * 7 + v) * ls
                for k in range(nb):
                    af[uv + k] -= acc[k]
            for k in range(nb):
                acc[k] = 0.0
            for q in range(6):
                for k in range(nb):
                    acc[k] += pf[(q * npc + u) * ls + k] * ef[(i * 6 + q) * ls + k]
            for a in range(nl):
                xu, b0 = (a * w + 1 + u) * ls, a * w * ls
                for k in range(nb):
                    acc[k] -= xf[xu + k] * bf[b0 + k]
            un = (u * 7 + nu) * ls
            for k in range(nb):
                af[un + k] += acc[k]
    if nu:
        rf = lanes(rhs)
        for k in range(nb):
            tr[k] = 0.0
        for u in range(nu):
            for v in range(u + 1):
                for k in range(nb):
                    acc[k] = 0.0
                for q in range(6):
                    for k in range(nb):
                        acc[k] += pf[(q * npc + u) * ls + k] * pf[(q * npc + v) * ls + k]
                uv = (u * 7 + v) * ls
                for k in range(nb):
                    af[uv + k] += n * acc[k]
            uu, un = (u * 7 + u) * ls, (u * 7 + nu) * ls
            for k in range(nb):
                tr[k] += af[uu + k]
                af[un + k] = -af[un + k]
        # (the lower triangle is complete; solve in a copy of the right-hand side column)
        for u in range(nu):
            for k in range(nb):
                rf[u * ls + k] = af[(u * 7 + nu) * ls + k]
        for k in range(nb):
            sh[k] = tr[k] * (SHIFT_REDUCED / nu)
        cholesky_lanes(Ar, nu, rhs, 1, LS[1], LS[2], nb, ls)
        for u in range(nu):
            for k in range(nb):
                sf[u * ls + k] = rf[u * ls + k]
    for i in range(n):
        off = nu + i * m
        xf = lanes(Xs[i])
        for j in range(m):
            for k in range(nb):
                sf[(off + j) * ls + k] = 0.0
        nl = 0
        for j in range(leg[i, L_SIZE]):
            if not frozen[i, j]:
                x0 = nl * w * ls
                oj = (off + j) * ls
                for k in range(nb):
                    acc[k] = xf[x0 + k]
                for u in range(nu):
                    xu = x0 + (1 + u) * ls
                    for k in range(nb):
                        acc[k] += xf[xu + k] * sf[u * ls + k]
                for k in range(nb):
                    sf[oj + k] = acc[k]
                nl += 1


@borrowing
def gauss_newton(M, unk, xs, p6fix, X, tol, max_iter, W):
    """Solve the closures of one pose from ``X`` (in place).  Returns ``(residual,
    iterations, stalled, buffer)``: the buffer holds the frames of the final ``X``."""
    return newton_iterate(M, unk, xs, p6fix, X, tol, max_iter, W)


@inlined
def newton_iterate(M, unk, xs, p6fix, X, tol, max_iter, W):
    """:func:`gauss_newton`'s body, inlined where a pose's first Newton run is called (the
    common case: a call passing the model and workspace tuples costs about half a
    microsecond): the forward pass at ``X`` into buffer 0, then :func:`newton_loop`."""
    f = forward(M, unk, xs, p6fix, X, W[W_FA], W[W_FL], W[W_FE], W[W_FP], 0, W[W_S], W[W_P6])
    return newton_loop(M, unk, xs, p6fix, X, tol, max_iter, W, f)


@borrowing
def newton_from(M, unk, xs, p6fix, X, tol, max_iter, W, f):
    """:func:`gauss_newton` from ``X`` whose frames are already in buffer 0 of ``W`` and
    whose residual is ``f``: the rest of a block's lane's Newton run, finished alone
    (:func:`._block.block_newton`; the same iterations as the pose's own run)."""
    return newton_loop(M, unk, xs, p6fix, X, tol, max_iter, W, f)


@inlined
def newton_loop(M, unk, xs, p6fix, X, tol, max_iter, W, f):
    """The Newton iterations of one pose from ``X`` (in place), its frames in buffer 0 and
    its residual ``f``: the test (finite, at or below ``tol``), the step, its halving until
    the closure error decreases.  Returns ``(residual, iterations, stalled, buffer)``."""
    FA, FL, FE, FP, S, p6 = W[W_FA], W[W_FL], W[W_FE], W[W_FP], W[W_S], W[W_P6]
    step, Xn, frozen = W[W_STEP], W[W_XN], W[W_FROZ]
    nu = unk.shape[0]
    nx = nu + FA.shape[1] * FA.shape[2]
    cur = 0
    its = 0
    stalled = False
    for _ in range(max_iter):
        if not math.isfinite(f):
            stalled = True
            break
        if f <= tol:
            break
        platform_columns(M, one_lane(FP[cur]), unk, one_lane(W[W_PT]), 1, 1)
        newton_step(M, W, cur, nu, frozen)
        sq = W[W_LS][3]                 # (the step's scratch row it leaves free)
        closure_sq(one_lane(FE), cur, sq, 1, 1)
        e2 = sq[0]
        new = 1 - cur
        ok = False
        fn = f
        for h in range(HALVINGS + 1):
            if h:
                for k in range(nx):
                    step[k] *= 0.5
            for k in range(nx):
                Xn[k] = X[k] + step[k]
            fn = forward(M, unk, xs, p6fix, Xn, FA, FL, FE, FP, new, S, p6)
            closure_sq(one_lane(FE), new, sq, 1, 1)
            if sq[0] < e2:               # False for NaN and inf
                ok = True
                break
        its += 1
        if not ok:
            stalled = True
            break
        for k in range(nx):
            X[k] = Xn[k]
        cur = new
        f = fn
    return f, its, stalled and not f <= tol, cur


@borrowing
def tolerance(order, unk, xs, p6fix, X0):
    """Stopping residual of a pose: tighter near a representation singularity, where the
    dependent angle of the pair (alpha, gamma) is determined only to residual /
    sin(beta)."""
    pair = False
    kb = -1
    for k in range(unk.shape[0]):
        if unk[k] == 3 or unk[k] == 5:
            pair = True
        if unk[k] == 4:
            kb = k
    if not pair:
        return STOP
    b = X0[kb] * xs[kb] if kb >= 0 else p6fix[4]
    if trig_exceeds(b, order[4] == 1, 1e-2):
        return STOP                     # (s >= 1e-2: what the line below gives)
    s = abs(math.sin(b)) if order[4] == 1 else abs(math.cos(b))
    return max(STOP * min(1.0, s / 1e-2), 1e-16)


@borrowing
def home_vector(unk, xs, p6home, out):
    """The unknowns at home (joint values 0)."""
    out[:] = 0.0
    for k in range(unk.shape[0]):
        out[k] = p6home[unk[k]] / xs[k]


@borrowing_inlined
def platform_columns(M, FPb, unk, Pt, nb, ls):
    """Length-normalised platform twists per unit of each unknown parameter of the lanes
    ``0..nb-1`` of the platforms ``FPb (27, ls)``, into ``Pt (6, >= nu, ls)`` (a length
    parameter per unit of ``L``; one pose: its ``(27,)`` and ``(6, nu)`` through
    :func:`~._jit.one_lane`, ``nb = ls = 1``)."""
    plat = M[PLAT]
    L = plat[P_L]
    c0, c1, c2 = plat[P_C], plat[P_C + 1], plat[P_C + 2]
    fp, pt = lanes(FPb), lanes(Pt)
    npc = Pt.shape[1]
    for k in range(unk.shape[0]):
        u = unk[k]
        if u < 3:
            for r in range(3):
                v = plat[P_R0 + 3 * r + u]
                qa, qb = (r * npc + k) * ls, ((3 + r) * npc + k) * ls
                for j in range(nb):
                    pt[qa + j] = v
                    pt[qb + j] = 0.0
        else:
            a0, a1, a2 = (18 + u - 3) * ls, (21 + u - 3) * ls, (24 + u - 3) * ls
            q0, q1, q2 = k * ls, (npc + k) * ls, (2 * npc + k) * ls
            q3, q4, q5 = (3 * npc + k) * ls, (4 * npc + k) * ls, (5 * npc + k) * ls
            for j in range(nb):
                w0, w1, w2 = fp[a0 + j], fp[a1 + j], fp[a2 + j]
                o0 = fp[15 * ls + j] - c0
                o1 = fp[16 * ls + j] - c1
                o2 = fp[17 * ls + j] - c2
                pt[q0 + j] = (o1 * w2 - o2 * w1) / L
                pt[q1 + j] = (o2 * w0 - o0 * w2) / L
                pt[q2 + j] = (o0 * w1 - o1 * w0) / L
                pt[q3 + j], pt[q4 + j], pt[q5 + j] = w0, w1, w2


@borrowing_inlined
def closure_sq(FE, b, out, nb, ls):
    """Each lane's sum of squared closure errors in buffer ``b`` of ``FE (2, n, 6, ls)`` into
    ``out[:nb]`` (legs, then components, in order from ``0.0``: a pose's figure for Newton's
    decrease test; one pose passes its ``(2, n, 6)`` frames through :func:`~._jit.one_lane`
    and an ``out`` of one entry)."""
    fe = lanes(FE[b])
    for j in range(nb):
        out[j] = 0.0
    for q in range(FE.shape[1] * 6):
        o = q * ls
        for j in range(nb):
            out[j] += fe[o + j] * fe[o + j]
