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
from ._jit import inlined, inner, one_lane

from ._kin import closure_sq, forward, platform_columns
from ._layout import LEG, L_SIZE, PLAT, P_C, P_L, ROT, STOP, TRN
from ._small import cholesky_solve

#: Relative Tikhonov shift of a leg's Gram matrix (exact legs) and of a leg with more joints
#: than twist-space dimensions (idle motions: least-norm steps).
SHIFT, SHIFT_IDLE = 1e-13, 1e-7
#: Shift of the reduced system: only guards against a zero pivot.
SHIFT_REDUCED = 1e-20
HALVINGS = 6

# the workspace tuple
(W_FA, W_FL, W_FE, W_FP, W_S, W_P6, W_T, W_PT, W_G, W_B, W_XS, W_AR, W_STEP, W_XN, W_FROZ,
 W_XC, W_XB, W_P6S, W_XR, W_IDX, W_RHS) = range(21)


@inner
def make_work(n, m, nx):
    """A thread's workspace for models of ``n`` legs, ``m`` slots and ``nx`` unknowns."""
    return (np.zeros((2, n, m, 6)), np.zeros((2, n, 12)), np.zeros((2, n, 6)),
            np.zeros((2, 27)), np.zeros((6, 3, 3)), np.zeros(6), np.zeros((n, m, 6)),
            np.zeros((6, 6)), np.zeros((m, m)), np.zeros((n, m, 7)), np.zeros((n, m, 7)),
            np.zeros((6, 7)), np.zeros(nx), np.zeros(nx), np.zeros((n, m), np.int64),
            np.zeros(nx), np.zeros(nx), np.zeros((4, 6)), np.zeros((6, nx)),
            np.zeros(m, np.int64), np.zeros((6, 1)))


@inlined
def newton_step(M, W, b, nu, frozen):
    """The Gauss-Newton step at the frames of buffer ``b`` into ``W[W_STEP]`` (the platform
    columns ``W[W_PT][:, :nu]`` set by the caller): :func:`step_of` given the arrays it
    reads (a call passing the model and workspace tuples whole cost about 0.4 us a step, a
    quarter of the step; this wrapper, inlined, passes 14 arrays)."""
    step_of(M[LEG], M[ROT], M[TRN], M[PLAT], W[W_FA], W[W_FE], W[W_T], W[W_PT], W[W_G],
            W[W_B], W[W_XS], W[W_AR], W[W_STEP], W[W_RHS], b, nu, frozen)


@inner
def step_of(leg, rot, trn, plat, FA, FE, T, Pt, G, B, Xs, Ar, step, rhs, b, nu, frozen):
    """:func:`newton_step`'s work (the model's and the workspace's arrays it reads)."""
    L = plat[P_L]
    c0, c1, c2 = plat[P_C], plat[P_C + 1], plat[P_C + 2]
    n, m = T.shape[0], T.shape[1]
    e = FE[b]
    for a in range(nu):
        for c in range(nu + 1):
            Ar[a, c] = 0.0
    for i in range(n):
        size = leg[i, L_SIZE]
        Ti, Bi, Xi, fai = T[i], B[i], Xs[i], FA[b, i]
        e0, e1, e2, e3, e4, e5 = e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4], e[i, 5]
        nl = 0
        for j in range(size):
            if not frozen[i, j]:
                nl += 1
        tr = float(m - nl)                   # padded and frozen slots: identity rows
        # each free joint's twist, its row of the Gram matrix and of T^T [e, P], in one pass
        a = 0
        for j in range(size):
            if frozen[i, j]:
                continue
            f = fai[j]
            d0, d1, d2 = f[0], f[1], f[2]
            p0, p1, p2 = f[3] - c0, f[4] - c1, f[5] - c2
            r = rot[i, j]
            rl = r / L
            tj = trn[i, j]
            t0 = (p1 * d2 - p2 * d1) * rl + tj * d0
            t1 = (p2 * d0 - p0 * d2) * rl + tj * d1
            t2 = (p0 * d1 - p1 * d0) * rl + tj * d2
            t3, t4, t5 = r * d0, r * d1, r * d2
            Ta = Ti[a]
            Ta[0], Ta[1], Ta[2], Ta[3], Ta[4], Ta[5] = t0, t1, t2, t3, t4, t5
            for c in range(a + 1):
                Tc = Ti[c]
                G[a, c] = (0.0 + t0 * Tc[0] + t1 * Tc[1] + t2 * Tc[2] + t3 * Tc[3]
                           + t4 * Tc[4] + t5 * Tc[5])
            tr += G[a, a]
            s = 0.0 + t0 * e0 + t1 * e1 + t2 * e2 + t3 * e3 + t4 * e4 + t5 * e5
            Bi[a, 0] = s
            Xi[a, 0] = s
            for u in range(nu):
                s = (0.0 + t0 * Pt[0, u] + t1 * Pt[1, u] + t2 * Pt[2, u] + t3 * Pt[3, u]
                     + t4 * Pt[4, u] + t5 * Pt[5, u])
                Bi[a, 1 + u] = s
                Xi[a, 1 + u] = s
            a += 1
        shift = tr / size * (SHIFT_IDLE if size > 6 else SHIFT)
        cholesky_solve(G, nl, Xi, 1 + nu, shift)
        # the reduced system's terms of this leg
        for u in range(nu):
            for v in range(nu):
                s = 0.0
                for a in range(nl):
                    s += Bi[a, 1 + u] * Xi[a, 1 + v]
                Ar[u, v] -= s
            s = 0.0
            for k in range(6):
                s += Pt[k, u] * e[i, k]
            for a in range(nl):
                s -= Xi[a, 1 + u] * Bi[a, 0]
            Ar[u, nu] += s
    if nu:
        tra = 0.0
        for u in range(nu):
            for v in range(u + 1):
                s = 0.0
                for k in range(6):
                    s += Pt[k, u] * Pt[k, v]
                Ar[u, v] += n * s
            tra += Ar[u, u]
            Ar[u, nu] = -Ar[u, nu]
        # (the lower triangle is complete; solve in a copy of the right-hand side column)
        for u in range(nu):
            rhs[u, 0] = Ar[u, nu]
        cholesky_solve(Ar, nu, rhs, 1, tra * (SHIFT_REDUCED / nu))
        for u in range(nu):
            step[u] = rhs[u, 0]
    for i in range(n):
        off = nu + i * m
        for j in range(m):
            step[off + j] = 0.0
        nl = 0
        for j in range(leg[i, L_SIZE]):
            if not frozen[i, j]:
                s = Xs[i, nl, 0]
                for u in range(nu):
                    s += Xs[i, nl, 1 + u] * step[u]
                step[off + j] = s
                nl += 1


@inner
def gauss_newton(M, unk, xs, p6fix, X, tol, max_iter, W):
    """Solve the closures of one pose from ``X`` (in place).  Returns ``(residual,
    iterations, stalled, buffer)``: the buffer holds the frames of the final ``X``."""
    return newton_iterate(M, unk, xs, p6fix, X, tol, max_iter, W)


@inlined
def newton_iterate(M, unk, xs, p6fix, X, tol, max_iter, W):
    """:func:`gauss_newton`'s body, inlined where a pose's first Newton run is called (the
    common case: a call passing the model and workspace tuples costs about half a
    microsecond)."""
    FA, FL, FE, FP, S, p6 = W[W_FA], W[W_FL], W[W_FE], W[W_FP], W[W_S], W[W_P6]
    step, Xn, frozen = W[W_STEP], W[W_XN], W[W_FROZ]
    nu = unk.shape[0]
    nx = nu + FA.shape[1] * FA.shape[2]
    cur = 0
    f = forward(M, unk, xs, p6fix, X, FA, FL, FE, FP, cur, S, p6)
    its = 0
    stalled = False
    for _ in range(max_iter):
        if not math.isfinite(f):
            stalled = True
            break
        if f <= tol:
            break
        platform_columns(M, FP[cur], unk, W[W_PT])
        newton_step(M, W, cur, nu, frozen)
        e2 = closure_sq(one_lane(FE), cur, 0)
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
            e2n = closure_sq(one_lane(FE), new, 0)
            if e2n < e2:               # False for NaN and inf
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


@inner
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
    s = abs(math.sin(b)) if order[4] == 1 else abs(math.cos(b))
    return max(STOP * min(1.0, s / 1e-2), 1e-16)


@inner
def home_vector(unk, xs, p6home, out):
    """The unknowns at home (joint values 0)."""
    out[:] = 0.0
    for k in range(unk.shape[0]):
        out[k] = p6home[unk[k]] / xs[k]
