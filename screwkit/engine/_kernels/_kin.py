"""Forward kinematics of one pose, compiled: the platform, every leg's product of
exponentials, the loop-closure errors, the joint twists (private).

A pose's frames live in four arrays with a leading buffer index ``b`` (the Newton iteration
keeps the current frames and a trial's): ``FA (2, n, m, 6)`` every joint's current axis and
point, ``FL (2, n, 12)`` each leg's end displacement (R row-major, t), ``FE (2, n, 6)`` each
leg's length-normalised closure error ``[d / L; w]`` and ``FP (2, 27)`` the platform: the six
pose parameters, ``Rp`` (row-major), ``o`` and the world angular Jacobian ``E`` of the
Euler angles (row-major).
"""

import math

from ._jit import inner

from ._layout import (AP, BAR, BLEN, D, HINGE, LEG, L_SIZE, ORDER, P, PLAT, P_C, P_L, P_P0,
                      P_PH, P_R0, P_RH, QS, ROT, TRA, TRN)
from ._small import matmul3, rodrigues, rotation_vector


@inner
def axis_rotation(ax, angle, R):
    """``R``: the rotation by ``angle`` about the base axis ``ax`` (0, 1, 2)."""
    c, s = math.cos(angle), math.sin(angle)
    j, k = (ax + 1) % 3, (ax + 2) % 3
    for r in range(3):
        for q in range(3):
            R[r, q] = 0.0
    R[ax, ax] = 1.0
    R[j, j] = c
    R[k, k] = c
    R[k, j] = s
    R[j, k] = -s


@inner
def platform(M, p6, fp, S):
    """The platform at the pose parameters ``p6`` (Xo Yo Zo alpha beta gamma) into ``fp``
    (module docstring); Euler angles as scipy's ``Rotation.from_euler`` defines them.
    ``S (6, 3, 3)`` scratch."""
    order, plat = M[ORDER], M[PLAT]
    a0, a1, a2 = order[0], order[1], order[2]
    R1, R2, R12, Rb = S[0], S[1], S[2], S[3]
    for k in range(6):
        fp[k] = p6[k]
    if order[3] == 1:              # intrinsic: R = R1(alpha) R2(beta) R3(gamma)
        axis_rotation(a0, p6[3], R1)
        axis_rotation(a1, p6[4], R2)
        matmul3(R1, R2, R12)
        axis_rotation(a2, p6[5], R2)
        matmul3(R12, R2, Rb)
        Eb = S[4]
        for r in range(3):
            Eb[r, 0] = 1.0 if r == a0 else 0.0
            Eb[r, 1] = R1[r, a1]
            Eb[r, 2] = R12[r, a2]
    else:                          # extrinsic: R = R3(gamma) R2(beta) R1(alpha)
        axis_rotation(a2, p6[5], R1)
        axis_rotation(a1, p6[4], R2)
        matmul3(R1, R2, R12)
        axis_rotation(a0, p6[3], R2)
        matmul3(R12, R2, Rb)
        Eb = S[4]
        for r in range(3):
            Eb[r, 0] = R12[r, a0]
            Eb[r, 1] = R1[r, a1]
            Eb[r, 2] = 1.0 if r == a2 else 0.0
    for r in range(3):
        x0, x1, x2 = plat[P_R0 + 3 * r], plat[P_R0 + 3 * r + 1], plat[P_R0 + 3 * r + 2]
        for q in range(3):
            fp[6 + 3 * r + q] = x0 * Rb[0, q] + x1 * Rb[1, q] + x2 * Rb[2, q]
            fp[18 + 3 * r + q] = x0 * Eb[0, q] + x1 * Eb[1, q] + x2 * Eb[2, q]
        fp[15 + r] = x0 * p6[0] + x1 * p6[1] + x2 * p6[2] + plat[P_P0 + r]


@inner
def chain(M, i, X, off, fa, R, t, E, T2, slots, Rs, ts):
    """Leg ``i``'s product of exponentials at the joint values ``X[off + j] * QS[i, j]``:
    current axes and points into ``fa (m, 6)``, the end displacement into ``R``, ``t``; with
    ``slots``, the displacement after each slot into ``Rs (m, 3, 3)``, ``ts (m, 3)`` (how the
    link after joint ``j`` moved from home).  ``G_j = G_{j-1} exp(xi_j q_j)``: the current
    axis of slot ``j`` is ``G_{j-1}`` applied to its home axis, whose point stays; a Pa moves
    its far link along a circle, ``Rot(h, s / |b|) b - b``, its current axis
    ``Rot(h, s / |b|) D``.  (``E``, ``T2`` are unused scratch, kept for the signature.)"""
    Dm, Pm, rot, tra, qs = M[D], M[P], M[ROT], M[TRA], M[QS]
    blen = M[BLEN]
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    t0 = t1 = t2 = 0.0
    for j in range(M[LEG][i, L_SIZE]):
        q = X[off + j] * qs[i, j]
        D0, D1, D2 = Dm[i, j, 0], Dm[i, j, 1], Dm[i, j, 2]
        P0, P1, P2 = Pm[i, j, 0], Pm[i, j, 1], Pm[i, j, 2]
        d0 = r00 * D0 + r01 * D1 + r02 * D2
        d1 = r10 * D0 + r11 * D1 + r12 * D2
        d2 = r20 * D0 + r21 * D1 + r22 * D2
        p0 = r00 * P0 + r01 * P1 + r02 * P2 + t0
        p1 = r10 * P0 + r11 * P1 + r12 * P2 + t1
        p2 = r20 * P0 + r21 * P1 + r22 * P2 + t2
        fa[j, 0], fa[j, 1], fa[j, 2] = d0, d1, d2
        fa[j, 3], fa[j, 4], fa[j, 5] = p0, p1, p2
        if rot[i, j] != 0.0:
            # Rodrigues about the home axis, composed on the right
            a = rot[i, j] * q
            c, s = math.cos(a), math.sin(a)
            v = 1.0 - c
            e00, e11, e22 = D0 * D0 * v + c, D1 * D1 * v + c, D2 * D2 * v + c
            sym, skew = D0 * D1 * v, D2 * s
            e01, e10 = sym - skew, sym + skew
            sym, skew = D1 * D2 * v, D0 * s
            e12, e21 = sym - skew, sym + skew
            sym, skew = D2 * D0 * v, D1 * s
            e20, e02 = sym - skew, sym + skew
            n00 = r00 * e00 + r01 * e10 + r02 * e20
            n01 = r00 * e01 + r01 * e11 + r02 * e21
            n02 = r00 * e02 + r01 * e12 + r02 * e22
            n10 = r10 * e00 + r11 * e10 + r12 * e20
            n11 = r10 * e01 + r11 * e11 + r12 * e21
            n12 = r10 * e02 + r11 * e12 + r12 * e22
            n20 = r20 * e00 + r21 * e10 + r22 * e20
            n21 = r20 * e01 + r21 * e11 + r22 * e21
            n22 = r20 * e02 + r21 * e12 + r22 * e22
            r00, r01, r02, r10, r11, r12, r20, r21, r22 = n00, n01, n02, n10, n11, n12, \
                n20, n21, n22
            sh = tra[i, j] * q
            t0 = p0 - (r00 * P0 + r01 * P1 + r02 * P2) + sh * d0
            t1 = p1 - (r10 * P0 + r11 * P1 + r12 * P2) + sh * d1
            t2 = p2 - (r20 * P0 + r21 * P1 + r22 * P2) + sh * d2
        elif blen[i, j] > 0.0:
            h = M[HINGE][i, j]
            b = M[BAR][i, j]
            rodrigues(h[0], h[1], h[2], q / blen[i, j], E)
            m0 = E[0, 0] * b[0] + E[0, 1] * b[1] + E[0, 2] * b[2] - b[0]
            m1 = E[1, 0] * b[0] + E[1, 1] * b[1] + E[1, 2] * b[2] - b[1]
            m2 = E[2, 0] * b[0] + E[2, 1] * b[1] + E[2, 2] * b[2] - b[2]
            h0 = E[0, 0] * D0 + E[0, 1] * D1 + E[0, 2] * D2
            h1 = E[1, 0] * D0 + E[1, 1] * D1 + E[1, 2] * D2
            h2 = E[2, 0] * D0 + E[2, 1] * D1 + E[2, 2] * D2
            t0 += r00 * m0 + r01 * m1 + r02 * m2
            t1 += r10 * m0 + r11 * m1 + r12 * m2
            t2 += r20 * m0 + r21 * m1 + r22 * m2
            fa[j, 0] = r00 * h0 + r01 * h1 + r02 * h2
            fa[j, 1] = r10 * h0 + r11 * h1 + r12 * h2
            fa[j, 2] = r20 * h0 + r21 * h1 + r22 * h2
        else:
            sh = tra[i, j] * q
            t0 += sh * d0
            t1 += sh * d1
            t2 += sh * d2
        if slots:
            ts[j, 0], ts[j, 1], ts[j, 2] = t0, t1, t2
            Rs[j, 0, 0], Rs[j, 0, 1], Rs[j, 0, 2] = r00, r01, r02
            Rs[j, 1, 0], Rs[j, 1, 1], Rs[j, 1, 2] = r10, r11, r12
            Rs[j, 2, 0], Rs[j, 2, 1], Rs[j, 2, 2] = r20, r21, r22
    R[0, 0], R[0, 1], R[0, 2] = r00, r01, r02
    R[1, 0], R[1, 1], R[1, 2] = r10, r11, r12
    R[2, 0], R[2, 1], R[2, 2] = r20, r21, r22
    t[0], t[1], t[2] = t0, t1, t2


@inner
def closure_error(M, fp, R, t, e, S):
    """A leg's length-normalised closure error ``[d / L; w]`` into ``e (6,)``: the twist
    carrying its end pose ``(R Rh, R ph + t)`` onto the platform's (``fp``, whose
    ``Rp Rh^T`` the caller put in ``S[1]``: :func:`platform_home_rotation`)."""
    plat = M[PLAT]
    Rd, RpRh = S[0], S[1]
    for r in range(3):
        a0, a1, a2 = RpRh[r, 0], RpRh[r, 1], RpRh[r, 2]
        for c in range(3):
            Rd[r, c] = a0 * R[c, 0] + a1 * R[c, 1] + a2 * R[c, 2]
    L = plat[P_L]
    ph0, ph1, ph2 = plat[P_PH], plat[P_PH + 1], plat[P_PH + 2]
    c0, c1, c2 = plat[P_C], plat[P_C + 1], plat[P_C + 2]
    u0 = c0 - (R[0, 0] * ph0 + R[0, 1] * ph1 + R[0, 2] * ph2 + t[0])
    u1 = c1 - (R[1, 0] * ph0 + R[1, 1] * ph1 + R[1, 2] * ph2 + t[1])
    u2 = c2 - (R[2, 0] * ph0 + R[2, 1] * ph1 + R[2, 2] * ph2 + t[2])
    e[0] = (Rd[0, 0] * u0 + Rd[0, 1] * u1 + Rd[0, 2] * u2 + fp[15] - c0) / L
    e[1] = (Rd[1, 0] * u0 + Rd[1, 1] * u1 + Rd[1, 2] * u2 + fp[16] - c1) / L
    e[2] = (Rd[2, 0] * u0 + Rd[2, 1] * u1 + Rd[2, 2] * u2 + fp[17] - c2) / L
    rotation_vector(Rd, e, 3)


@inner
def platform_home_rotation(M, fp, S):
    """``S[1] = Rp Rh^T`` of the platform ``fp`` (once per pose, for :func:`closure_error`)."""
    plat = M[PLAT]
    RpRh = S[1]
    for r in range(3):
        for c in range(3):
            RpRh[r, c] = (fp[6 + 3 * r] * plat[P_RH + 3 * c] + fp[6 + 3 * r + 1] *
                          plat[P_RH + 3 * c + 1] + fp[6 + 3 * r + 2] * plat[P_RH + 3 * c + 2])


@inner
def forward(M, unk, xs, p6fix, X, FA, FL, FE, FP, b, S, p6):
    """The frames of the unknowns ``X`` (given parameters ``p6fix``) into buffer ``b``;
    returns the residual (largest closure error component, NaN-propagating).  ``S (6, 3,
    3)``, ``p6 (6,)`` scratch."""
    for k in range(6):
        p6[k] = p6fix[k]
    for k in range(unk.shape[0]):
        p6[unk[k]] = X[k] * xs[k]
    platform(M, p6, FP[b], S)
    return legs_forward(M, X, unk.shape[0], FA, FL, FE, FP, b, S)


@inner
def legs_forward(M, X, nu, FA, FL, FE, FP, b, S):
    """Every leg's frames and closure error at the joint values ``X[nu:]`` against the
    platform already in ``FP[b]``; returns the residual."""
    fp = FP[b]
    n, m = M[D].shape[0], M[D].shape[1]
    platform_home_rotation(M, fp, S)
    res = 0.0
    for i in range(n):
        Rl = S[3]
        tl = S[4, 0]
        chain(M, i, X, nu + i * m, FA[b, i], Rl, tl, S[0], S[2], False, S, S[0])
        fl = FL[b, i]
        for r in range(3):
            fl[9 + r] = tl[r]
            for c in range(3):
                fl[3 * r + c] = Rl[r, c]
        e = FE[b, i]
        closure_error(M, fp, Rl, tl, e, S)
        for k in range(6):
            a = abs(e[k])
            if not a <= res:            # NaN propagates
                res = a
    return res


@inner
def platform_columns(M, fp, unk, Pt):
    """Length-normalised platform twists per unit of each unknown parameter, ``Pt (6, nu)``
    (a length parameter per unit of ``L``)."""
    plat = M[PLAT]
    L = plat[P_L]
    for k in range(unk.shape[0]):
        u = unk[k]
        if u < 3:
            for r in range(3):
                Pt[r, k] = plat[P_R0 + 3 * r + u]
                Pt[3 + r, k] = 0.0
        else:
            w0, w1, w2 = fp[18 + u - 3], fp[21 + u - 3], fp[24 + u - 3]
            o0 = fp[15] - plat[P_C]
            o1 = fp[16] - plat[P_C + 1]
            o2 = fp[17] - plat[P_C + 2]
            Pt[0, k] = (o1 * w2 - o2 * w1) / L
            Pt[1, k] = (o2 * w0 - o0 * w2) / L
            Pt[2, k] = (o0 * w1 - o1 * w0) / L
            Pt[3, k], Pt[4, k], Pt[5, k] = w0, w1, w2


@inner
def platform_points(M, fp, i, out):
    """``a_i`` (world) at the platform ``fp`` into ``out (3,)``."""
    ap = M[AP]
    for r in range(3):
        out[r] = (fp[6 + 3 * r] * ap[i, 0] + fp[6 + 3 * r + 1] * ap[i, 1]
                  + fp[6 + 3 * r + 2] * ap[i, 2] + fp[15 + r])


@inner
def joint_twist(M, i, j, fa, out):
    """Joint ``j`` of leg ``i``'s unit twist ``[v; w]`` about the base origin (physical)."""
    rot, tra = M[ROT][i, j], M[TRA][i, j]
    d0, d1, d2, p0, p1, p2 = fa[j, 0], fa[j, 1], fa[j, 2], fa[j, 3], fa[j, 4], fa[j, 5]
    w0, w1, w2 = rot * d0, rot * d1, rot * d2
    out[0] = p1 * w2 - p2 * w1 + tra * d0
    out[1] = p2 * w0 - p0 * w2 + tra * d1
    out[2] = p0 * w1 - p1 * w0 + tra * d2
    out[3], out[4], out[5] = w0, w1, w2
