"""Forward kinematics (direct displacement) of one pose, compiled (private).

The loop closures are solved the other way round: the actuated joints are given (frozen)
and the unknowns are the platform's pose and every passive joint.  The platform moves by
its own twist (the six columns of the identity, length-normalised about the model's
centroid), so the iteration has no representation singularity.  The state of a pose:
``R (3, 3)``, ``o (3,)`` and ``X`` (``X[6 + i m + j] = q_ij / QS_ij``; the first six
entries are the step's platform twist).  The Newton step is the inverse displacement's
(:func:`~screwkit.engine._kernels._newton.newton_step` with ``nu = 6``); a step is halved up
to seven times until the closure error decreases.

:func:`continuation` moves the actuated values from a start to the targets in ``S`` steps
(``S`` from the largest change over :data:`STEP`, at most :data:`MAX_STEPS`), each started
from the last, then in four times as many, and last by Newton straight from the start.
"""

import math

import numpy as np
from numba import prange

from ._jit import entry, inner, one_lane, parallel
from ._kin import legs_forward
from ._layout import CONVERGED, D, LEG, L_ACT, L_ACTIVE, L_AROW, PLAT, P_C, P_L, QS
from ._newton import (W_FA, W_FE, W_FL, W_FP, W_FROZ, W_LS, W_PT, W_S, W_STEP, closure_sq,
                      make_work, newton_step)
from ._small import matmul3, rodrigues

#: Largest change of an actuated value per continuation step (``L`` or rad).
STEP = 0.05
MAX_STEPS = 32
#: Residual at which the forward iteration stops.
TOL = 1e-14
HALVINGS = 8


@inner
def _forward(M, R, o, X, W, b):
    fp = W[W_FP][b]
    for r in range(3):
        fp[15 + r] = o[r]
        for c in range(3):
            fp[6 + 3 * r + c] = R[r, c]
    return legs_forward(M, X, 6, W[W_FA], W[W_FL], W[W_FE], W[W_FP], b, W[W_S])


@inner
def setup(M, W):
    """Freeze the actuated joints and set the platform columns to the identity."""
    leg, frozen, Pt = M[LEG], W[W_FROZ], W[W_PT]
    frozen[:] = 0
    for i in range(leg.shape[0]):
        if leg[i, L_ACTIVE]:
            frozen[i, leg[i, L_ACT]] = 1
    for a in range(6):
        for c in range(6):
            Pt[a, c] = 1.0 if a == c else 0.0


@inner
def newton(M, R, o, X, tol, max_iter, W, R2, o2, X2, Rw):
    """Gauss-Newton from the state ``(R, o, X)`` (in place).  Returns ``(residual,
    iterations)``."""
    plat = M[PLAT]
    L = plat[P_L]
    c = plat[P_C:P_C + 3]
    nx = X.shape[0]
    step = W[W_STEP]
    res = _forward(M, R, o, X, W, 0)
    its = 0
    for _ in range(max_iter):
        if not math.isfinite(res) or res <= tol:
            break
        newton_step(M, W, 0, 6, W[W_FROZ])
        sq = W[W_LS][3]                 # (the step's scratch row it leaves free)
        closure_sq(one_lane(W[W_FE]), 0, sq, 1, 1)
        e2 = sq[0]
        done = False
        for h in range(HALVINGS):
            f = 0.5 ** h
            w0, w1, w2 = step[3] * f, step[4] * f, step[5] * f
            ang = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
            s = ang if ang > 0 else 1.0
            rodrigues(w0 / s, w1 / s, w2 / s, ang, Rw)
            matmul3(Rw, R, R2)
            for r in range(3):
                o2[r] = (Rw[r, 0] * (o[0] - c[0]) + Rw[r, 1] * (o[1] - c[1])
                         + Rw[r, 2] * (o[2] - c[2]) + c[r] + step[r] * f * L)
            for k in range(6, nx):
                X2[k] = X[k] + step[k] * f
            r2 = _forward(M, R2, o2, X2, W, 1)
            closure_sq(one_lane(W[W_FE]), 1, sq, 1, 1)
            if math.isfinite(r2) and sq[0] < e2:
                for r in range(3):
                    o[r] = o2[r]
                    for q in range(3):
                        R[r, q] = R2[r, q]
                for k in range(6, nx):
                    X[k] = X2[k]
                res = r2
                done = True
                break
        its += 1
        if not done:
            break
        res = _forward(M, R, o, X, W, 0)
    return res, its


@entry
def newton_range(M, R, o, X, tol, max_iter, res, its, start, stop):
    """:func:`newton` from each state ``R (N, 3, 3)``, ``o (N, 3)``, ``X (N, nx)`` (in
    place), to ``tol (N,)``."""
    n, m = M[D].shape[0], M[D].shape[1]
    nx = X.shape[1]
    W = make_work(n, m, nx)
    setup(M, W)
    R2, o2, X2, Rw = np.zeros((3, 3)), np.zeros(3), np.zeros(nx), np.zeros((3, 3))
    for p in range(start, stop):
        res[p], its[p] = newton(M, R[p], o[p], X[p], tol[p], max_iter, W, R2, o2, X2, Rw)


@parallel
def newton_parallel(M, R, o, X, tol, max_iter, res, its, nchunks):
    N = R.shape[0]
    for c in prange(nchunks):
        newton_range(M, R, o, X, tol, max_iter, res, its, c * N // nchunks,
                     (c + 1) * N // nchunks)


@entry
def continuation_range(M, R0, o0, X0, target, unit, R, o, X, res, its, how, start, stop):
    """From the start states ``(R0, o0, X0)`` (their actuated values included) to the
    actuated targets ``target (N, n_actuated)`` (joint values of the actuated legs, in leg
    order; ``unit`` likewise), continuation (module docstring).
    Solutions into ``R``, ``o``, ``X``; ``how``: the steps of the continuation that solved
    the pose (0: Newton straight from the start, -1: not solved)."""
    n, m = M[D].shape[0], M[D].shape[1]
    nx = X.shape[1]
    leg, qs = M[LEG], M[QS]
    W = make_work(n, m, nx)
    setup(M, W)
    R2, o2, X2, Rw = np.zeros((3, 3)), np.zeros(3), np.zeros(nx), np.zeros((3, 3))
    Rs, os_, Xs = np.zeros((3, 3)), np.zeros(3), np.zeros(nx)
    for p in range(start, stop):
        res[p] = np.inf
        how[p] = -1
        its[p] = 0
        big = 0.0
        for i in range(n):
            if leg[i, L_ACTIVE]:
                j, a = leg[i, L_ACT], leg[i, L_AROW]
                big = max(big, abs(target[p, a] - X0[p, 6 + i * m + j] * qs[i, j]) / unit[a])
        S0 = min(max(math.ceil(big / STEP), 1.0), MAX_STEPS)
        for mult in (1, 4, 0):
            if res[p] <= CONVERGED:
                break
            S = max(int(S0) * mult, 1)
            for r in range(3):
                os_[r] = o0[p, r]
                for q in range(3):
                    Rs[r, q] = R0[p, r, q]
            for k in range(nx):
                Xs[k] = X0[p, k]
            for s in range(1, S + 1):
                frac = min(1.0, s / S)
                for i in range(n):
                    if leg[i, L_ACTIVE]:
                        j, a = leg[i, L_ACT], leg[i, L_AROW]
                        qa = X0[p, 6 + i * m + j] * qs[i, j]
                        Xs[6 + i * m + j] = (qa + (target[p, a] - qa) * frac) / qs[i, j]
                last = frac >= 1
                r, it = newton(M, Rs, os_, Xs, TOL if last else 1e-8, 50 if mult == 0 else 30,
                               W, R2, o2, X2, Rw)
                its[p] += it
                if last:
                    if r < res[p]:
                        res[p] = r
                        how[p] = S if mult else 0
                        for q in range(3):
                            o[p, q] = os_[q]
                            for c in range(3):
                                R[p, q, c] = Rs[q, c]
                        for k in range(nx):
                            X[p, k] = Xs[k]
                elif not r <= 1e-4:
                    break              # off the branch: finer steps, or Newton straight


@parallel
def continuation_parallel(M, R0, o0, X0, target, unit, R, o, X, res, its, how, nchunks):
    N = R0.shape[0]
    for c in prange(nchunks):
        continuation_range(M, R0, o0, X0, target, unit, R, o, X, res, its, how,
                           c * N // nchunks, (c + 1) * N // nchunks)
