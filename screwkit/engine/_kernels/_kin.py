"""Forward kinematics, compiled: the platform, every leg's product of exponentials, the
loop-closure errors, the joint twists (private).

A pose's frames live in four arrays with a leading buffer index ``b`` (the Newton iteration
keeps the current frames and a trial's): ``FA (2, n, m, 6)`` every joint's current axis and
point, ``FL (2, n, 12)`` each leg's end displacement (R row-major, t), ``FE (2, n, 6)`` each
leg's length-normalised closure error ``[d / L; w]`` and ``FP (2, 27)`` the platform: the six
pose parameters, ``Rp`` (row-major), ``o`` and the world angular Jacobian ``E`` of the
Euler angles (row-major).

The forward pass is written once, on a block of lanes (poses) with the lane axis last and
innermost (``FA (2, n, m, 6, B)``, ``X (nx, B)``...): :func:`forward_block`, whose product
of exponentials (:func:`chain`) runs each joint's arithmetic across the lanes, where LLVM
vectorises it.  One pose is a block of one lane: :func:`forward` passes the one-pose arrays
through :func:`~._jit.one_lane` (the same memory with a trailing axis of length one).
:func:`forward_block` and :func:`legs_block` are inlined into their callers, so that a
caller's block of one reaches :func:`chain` as the constant 1 (LLVM then folds its lane
loops: with a lane count known only at run time, a block of one cost twice the pass).
The platform (:mod:`._platform`) and the closure errors (:func:`closure_lanes`) are lane
loops too, each compiled once per lane stride as a function of its own (:func:`platform`
and :func:`closure_one`: one pose; ``_platform.platform_block`` and :func:`closure_block`: a
block), which the inlined pass calls: the stride a constant in each, and not typed again
in every kernel the pass is inlined into (the first run's compile time).
"""

import math

from ._jit import borrowing, borrowing_inlined, flat, inlined, lanes, one_lane

from ._layout import (AP, BAR, BLEN, BLOCK, D, HINGE, LEG, L_SIZE, ORDER, P, PLAT, P_C, P_L,
                      P_PH, P_RH, QS, ROT, TRA)
from ._platform import platform_block, platform_lanes
from ._small import rodrigues, rotation_vector
from ._trig import SMALL_ANGLE, angle_over_sine, beyond_sin_cos, sin_cos, sin_cos_fix


@borrowing
def platform(order, plat, FPb):
    """One pose's platform into ``FPb (27, 1)`` (its ``fp (27,)`` through
    :func:`~._jit.one_lane`), its pose parameters already in rows 0-5
    (:func:`~._platform.platform_lanes` on a block of one lane; ``order``, ``plat``: the
    model's ``ORDER`` and ``PLAT``).  A block's: :func:`~._platform.platform_block`."""
    platform_lanes(order, plat, FPb, 1, 1)


@inlined
def chain(M, i, X, off, fa, RT, nb, ls, slots, Rs, E, CS):
    """Leg ``i``'s product of exponentials on a block of ``nb`` lanes (poses), the lane axis
    last and innermost, of length ``ls`` in every array: the joint values ``X[off + j, l] *
    QS[i, j]`` (``X (nx, ls)``); every joint's current axis and point into ``fa (m, 6,
    ls)``, the end displacement into ``RT (12, ls)`` (``R`` row-major, then ``t``: a leg's
    row of the frames ``FL``); with ``slots``, the displacement after each slot into ``Rs (m,
    12, ls)`` (how the link after joint ``j`` moved from home).  ``G_j = G_{j-1} exp(xi_j
    q_j)``: the current axis of slot ``j`` is ``G_{j-1}`` applied to its home axis, whose
    point stays; a Pa moves its far link along a circle, ``Rot(h, s / |b|) b - b``, its
    current axis ``Rot(h, s / |b|) D``.  ``E (3, 3)`` and ``CS`` (``2 ls`` elements or more)
    scratch.  Each lane's
    arithmetic is the one pose's, in the same order (no reduction across lanes): a lane of a
    block equals a block of one bit for bit (a caller of one pose passes views of one lane,
    :func:`~._jit.one_lane`, and ``ls = 1``).

    ``ls`` is a constant at every call site (1, or :data:`._layout.BLOCK`), so that once
    this function is inlined LLVM sees the lane loops' entries at constant distances in one
    flat view per array (:func:`~._jit.flat`) and vectorises them."""
    Dm, Pm, rot, tra, qs = M[D], M[P], M[ROT], M[TRA], M[QS]
    blen = M[BLEN]
    rt, xf, cf = flat(RT), flat(X), flat(CS)
    S0, C0 = 0, ls                       # CS's rows: sine, cosine
    for k in range(nb):
        rt[k], rt[ls + k], rt[2 * ls + k], rt[9 * ls + k] = 1.0, 0.0, 0.0, 0.0
        rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k], rt[10 * ls + k] = 0.0, 1.0, 0.0, 0.0
        rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k], rt[11 * ls + k] = 0.0, 0.0, 1.0, 0.0
    for j in range(M[LEG][i, L_SIZE]):
        g, ro, tr = qs[i, j], rot[i, j], tra[i, j]
        xj = (off + j) * ls
        D0, D1, D2 = Dm[i, j, 0], Dm[i, j, 1], Dm[i, j, 2]
        P0, P1, P2 = Pm[i, j, 0], Pm[i, j, 1], Pm[i, j, 2]
        f = flat(fa[j])
        # the joint's current axis and point (before its own motion)
        for k in range(nb):
            a00, a01, a02 = rt[k], rt[ls + k], rt[2 * ls + k]
            a10, a11, a12 = rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k]
            a20, a21, a22 = rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k]
            f[k] = a00 * D0 + a01 * D1 + a02 * D2
            f[ls + k] = a10 * D0 + a11 * D1 + a12 * D2
            f[2 * ls + k] = a20 * D0 + a21 * D1 + a22 * D2
            f[3 * ls + k] = a00 * P0 + a01 * P1 + a02 * P2 + rt[9 * ls + k]
            f[4 * ls + k] = a10 * P0 + a11 * P1 + a12 * P2 + rt[10 * ls + k]
            f[5 * ls + k] = a20 * P0 + a21 * P1 + a22 * P2 + rt[11 * ls + k]
        if ro != 0.0:
            # Rodrigues about the home axis, composed on the right; the sines and cosines
            # in a loop of their own (vectorised), libm's beyond sin_cos's range after it
            for k in range(nb):
                cf[S0 + k], cf[C0 + k] = sin_cos(ro * (xf[xj + k] * g))
            far = 0
            for k in range(nb):
                far += beyond_sin_cos(ro * (xf[xj + k] * g))
            if far:
                for k in range(nb):
                    a = ro * (xf[xj + k] * g)
                    cf[S0 + k], cf[C0 + k] = sin_cos_fix(a, cf[S0 + k], cf[C0 + k])
            for k in range(nb):
                q = xf[xj + k] * g
                c, s = cf[C0 + k], cf[S0 + k]
                v = 1.0 - c
                e00, e11, e22 = D0 * D0 * v + c, D1 * D1 * v + c, D2 * D2 * v + c
                sym, skew = D0 * D1 * v, D2 * s
                e01, e10 = sym - skew, sym + skew
                sym, skew = D1 * D2 * v, D0 * s
                e12, e21 = sym - skew, sym + skew
                sym, skew = D2 * D0 * v, D1 * s
                e20, e02 = sym - skew, sym + skew
                a00, a01, a02 = rt[k], rt[ls + k], rt[2 * ls + k]
                a10, a11, a12 = rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k]
                a20, a21, a22 = rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k]
                n00 = a00 * e00 + a01 * e10 + a02 * e20
                n01 = a00 * e01 + a01 * e11 + a02 * e21
                n02 = a00 * e02 + a01 * e12 + a02 * e22
                n10 = a10 * e00 + a11 * e10 + a12 * e20
                n11 = a10 * e01 + a11 * e11 + a12 * e21
                n12 = a10 * e02 + a11 * e12 + a12 * e22
                n20 = a20 * e00 + a21 * e10 + a22 * e20
                n21 = a20 * e01 + a21 * e11 + a22 * e21
                n22 = a20 * e02 + a21 * e12 + a22 * e22
                rt[k], rt[ls + k], rt[2 * ls + k] = n00, n01, n02
                rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k] = n10, n11, n12
                rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k] = n20, n21, n22
                sh = tr * q
                rt[9 * ls + k] = f[3 * ls + k] - (n00 * P0 + n01 * P1 + n02 * P2) + sh * f[k]
                rt[10 * ls + k] = (f[4 * ls + k] - (n10 * P0 + n11 * P1 + n12 * P2)
                                   + sh * f[ls + k])
                rt[11 * ls + k] = (f[5 * ls + k] - (n20 * P0 + n21 * P1 + n22 * P2)
                                   + sh * f[2 * ls + k])
        elif blen[i, j] > 0.0:
            h = M[HINGE][i, j]
            b = M[BAR][i, j]
            bl = blen[i, j]
            for k in range(nb):          # (rare: one lane at a time)
                rodrigues(h[0], h[1], h[2], (xf[xj + k] * g) / bl, E)
                m0 = E[0, 0] * b[0] + E[0, 1] * b[1] + E[0, 2] * b[2] - b[0]
                m1 = E[1, 0] * b[0] + E[1, 1] * b[1] + E[1, 2] * b[2] - b[1]
                m2 = E[2, 0] * b[0] + E[2, 1] * b[1] + E[2, 2] * b[2] - b[2]
                h0 = E[0, 0] * D0 + E[0, 1] * D1 + E[0, 2] * D2
                h1 = E[1, 0] * D0 + E[1, 1] * D1 + E[1, 2] * D2
                h2 = E[2, 0] * D0 + E[2, 1] * D1 + E[2, 2] * D2
                a00, a01, a02 = rt[k], rt[ls + k], rt[2 * ls + k]
                a10, a11, a12 = rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k]
                a20, a21, a22 = rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k]
                rt[9 * ls + k] += a00 * m0 + a01 * m1 + a02 * m2
                rt[10 * ls + k] += a10 * m0 + a11 * m1 + a12 * m2
                rt[11 * ls + k] += a20 * m0 + a21 * m1 + a22 * m2
                f[k] = a00 * h0 + a01 * h1 + a02 * h2
                f[ls + k] = a10 * h0 + a11 * h1 + a12 * h2
                f[2 * ls + k] = a20 * h0 + a21 * h1 + a22 * h2
        else:
            for k in range(nb):
                sh = tr * (xf[xj + k] * g)
                rt[9 * ls + k] += sh * f[k]
                rt[10 * ls + k] += sh * f[ls + k]
                rt[11 * ls + k] += sh * f[2 * ls + k]
        if slots:
            rs = flat(Rs[j])
            for k in range(12 * ls):
                rs[k] = rt[k]


@borrowing_inlined
def relative_rotation(plat, FPb, RT, k, ls):
    """Lane ``k``'s ``Rd = (Rp Rh^T) R^T`` (row-major): the rotation carrying a leg's end
    (``RT``, as :func:`chain` leaves it) onto the platform (``FPb``).  (The arrays, not their
    pointers: argument types with a text ``first_compile.txt`` can hold.)"""
    fp, rt = lanes(FPb), lanes(RT)
    h = (fp[6 * ls + k], fp[7 * ls + k], fp[8 * ls + k], fp[9 * ls + k], fp[10 * ls + k],
         fp[11 * ls + k], fp[12 * ls + k], fp[13 * ls + k], fp[14 * ls + k])
    H = (h[0] * plat[P_RH] + h[1] * plat[P_RH + 1] + h[2] * plat[P_RH + 2],
         h[0] * plat[P_RH + 3] + h[1] * plat[P_RH + 4] + h[2] * plat[P_RH + 5],
         h[0] * plat[P_RH + 6] + h[1] * plat[P_RH + 7] + h[2] * plat[P_RH + 8],
         h[3] * plat[P_RH] + h[4] * plat[P_RH + 1] + h[5] * plat[P_RH + 2],
         h[3] * plat[P_RH + 3] + h[4] * plat[P_RH + 4] + h[5] * plat[P_RH + 5],
         h[3] * plat[P_RH + 6] + h[4] * plat[P_RH + 7] + h[5] * plat[P_RH + 8],
         h[6] * plat[P_RH] + h[7] * plat[P_RH + 1] + h[8] * plat[P_RH + 2],
         h[6] * plat[P_RH + 3] + h[7] * plat[P_RH + 4] + h[8] * plat[P_RH + 5],
         h[6] * plat[P_RH + 6] + h[7] * plat[P_RH + 7] + h[8] * plat[P_RH + 8])
    R = (rt[k], rt[ls + k], rt[2 * ls + k], rt[3 * ls + k], rt[4 * ls + k], rt[5 * ls + k],
         rt[6 * ls + k], rt[7 * ls + k], rt[8 * ls + k])
    return (H[0] * R[0] + H[1] * R[1] + H[2] * R[2], H[0] * R[3] + H[1] * R[4] + H[2] * R[5],
            H[0] * R[6] + H[1] * R[7] + H[2] * R[8], H[3] * R[0] + H[4] * R[1] + H[5] * R[2],
            H[3] * R[3] + H[4] * R[4] + H[5] * R[5], H[3] * R[6] + H[4] * R[7] + H[5] * R[8],
            H[6] * R[0] + H[7] * R[1] + H[8] * R[2], H[6] * R[3] + H[7] * R[4] + H[8] * R[5],
            H[6] * R[6] + H[7] * R[7] + H[8] * R[8])


@borrowing
def closure_one(plat, FPb, RT, Eb, CS, Rd):
    """One pose's closure error of a leg (:func:`closure_lanes` on a block of one lane: the
    arrays with a lane axis of length one, :func:`~._jit.one_lane`)."""
    closure_lanes(plat, FPb, RT, Eb, 1, 1, CS, Rd)


@borrowing
def closure_block(plat, FPb, RT, Eb, nb, CS, Rd):
    """The closure errors of a leg on the ``nb`` lanes of a block of :data:`._layout.BLOCK`
    (:func:`closure_lanes`)."""
    closure_lanes(plat, FPb, RT, Eb, nb, BLOCK, CS, Rd)


@inlined
def closure_lanes(plat, FPb, RT, Eb, nb, ls, CS, Rd):
    """The length-normalised closure errors ``[d / L; w]`` of a leg on ``nb`` lanes into
    ``Eb (6, ls)``: the twist carrying its end pose ``(R Rh, R ph + t)`` (``RT (12, ls)``, as
    :func:`chain` leaves it) onto the platform's (``FPb (27, ls)``).  ``d`` and ``w``'s
    antisymmetric part across the lanes (vectorised), and the angle of a rotation below
    :data:`._trig.SMALL_ANGLE` by a series (every lane of a Newton run but the first steps of a
    far start); the others' (atan2, a call; the near-pi branch,
    :func:`~._small.rotation_vector`) one lane at a time.  ``plat`` the
    model's ``PLAT``; ``CS`` (``2 ls`` elements or more), ``Rd (3, 3)`` scratch.  Inlined
    into :func:`closure_one` and :func:`closure_block` only, where ``ls`` is a constant."""
    fp, rt, e, cs = lanes(FPb), lanes(RT), lanes(Eb), lanes(CS)
    L = plat[P_L]
    ph0, ph1, ph2 = plat[P_PH], plat[P_PH + 1], plat[P_PH + 2]
    c0, c1, c2 = plat[P_C], plat[P_C + 1], plat[P_C + 2]
    for k in range(nb):
        d = relative_rotation(plat, FPb, RT, k, ls)
        u0 = c0 - (rt[k] * ph0 + rt[ls + k] * ph1 + rt[2 * ls + k] * ph2 + rt[9 * ls + k])
        u1 = c1 - (rt[3 * ls + k] * ph0 + rt[4 * ls + k] * ph1 + rt[5 * ls + k] * ph2
                   + rt[10 * ls + k])
        u2 = c2 - (rt[6 * ls + k] * ph0 + rt[7 * ls + k] * ph1 + rt[8 * ls + k] * ph2
                   + rt[11 * ls + k])
        e[k] = (d[0] * u0 + d[1] * u1 + d[2] * u2 + fp[15 * ls + k] - c0) / L
        e[ls + k] = (d[3] * u0 + d[4] * u1 + d[5] * u2 + fp[16 * ls + k] - c1) / L
        e[2 * ls + k] = (d[6] * u0 + d[7] * u1 + d[8] * u2 + fp[17 * ls + k] - c2) / L
        w0, w1, w2 = 0.5 * (d[7] - d[5]), 0.5 * (d[2] - d[6]), 0.5 * (d[3] - d[1])
        c = 0.5 * (d[0] + d[4] + d[8] - 1.0)
        z = w0 * w0 + w1 * w1 + w2 * w2
        # a small angle (the closure errors of a Newton run): its ratio to its sine |w| by
        # the series of asin(s) / s, so that no lane calls atan2 (the others: the loop below)
        small = (z <= SMALL_ANGLE * SMALL_ANGLE) & (c > 0.0)
        f = angle_over_sine(z) if small else 1.0
        e[3 * ls + k], e[4 * ls + k], e[5 * ls + k] = w0 * f, w1 * f, w2 * f
        cs[k] = c
        cs[ls + k] = -1.0 if small else math.sqrt(z)      # (-1: done)
    for k in range(nb):
        c = cs[k]
        if cs[ls + k] < 0.0:
            continue
        if c < -0.9:               # (rare) the lane's Rd again, for the near-pi branch
            d = relative_rotation(plat, FPb, RT, k, ls)
            for r in range(3):
                Rd[r, 0], Rd[r, 1], Rd[r, 2] = d[3 * r], d[3 * r + 1], d[3 * r + 2]
        e[3 * ls + k], e[4 * ls + k], e[5 * ls + k] = rotation_vector(
            Rd, e[3 * ls + k], e[4 * ls + k], e[5 * ls + k], c, cs[ls + k])


@inlined
def forward_block(M, unk, xs, P6, X, FA, FL, FE, FP, b, S, nb, ls, res, CS):
    """The forward pass of a block of ``nb`` lanes (poses), the lane axis last: the frames of
    the unknowns ``X (nx, B)`` (given parameters ``P6 (6, B)``) into buffer ``b`` of ``FA (2,
    n, m, 6, B)``, ``FL (2, n, 12, B)``, ``FE (2, n, 6, B)``, ``FP (2, 27, B)``; each lane's
    residual (largest closure error component, NaN-propagating) into ``res (B,)``.  ``S (6,
    3, 3)``, ``CS (2, B)`` scratch."""
    fp, p6, x = lanes(FP[b]), lanes(P6), lanes(X)
    for q in range(6):
        for k in range(nb):
            fp[q * ls + k] = p6[q * ls + k]
    for u in range(unk.shape[0]):
        row, s = unk[u] * ls, xs[u]
        for k in range(nb):
            fp[row + k] = x[u * ls + k] * s
    if ls == 1:                    # (ls is a constant here: LLVM keeps one of the calls)
        platform(M[ORDER], M[PLAT], FP[b])
    else:
        platform_block(M[ORDER], M[PLAT], FP[b], nb)
    legs_block(M, X, unk.shape[0], FA, FL, FE, FP, b, S, nb, ls, res, CS)


@inlined
def legs_block(M, X, nu, FA, FL, FE, FP, b, S, nb, ls, res, CS):
    """Every leg's frames and closure error of ``nb`` lanes at the joint values ``X[nu:]``
    against the platforms already in ``FP[b]``; each lane's residual into ``res``
    (:func:`forward_block`'s arrays)."""
    n, m = M[D].shape[0], M[D].shape[1]
    plat = M[PLAT]
    for i in range(n):
        chain(M, i, X, nu + i * m, FA[b, i], FL[b, i], nb, ls, False, FA[b, i], S[0], CS)
    r = lanes(res)
    for k in range(nb):
        r[k] = 0.0
    for i in range(n):
        if ls == 1:                # (a constant, as in forward_block)
            closure_one(plat, FP[b], FL[b, i], FE[b, i], CS, S[0])
        else:
            closure_block(plat, FP[b], FL[b, i], FE[b, i], nb, CS, S[0])
        e = lanes(FE[b, i])
        for k in range(nb):            # the largest component so far (NaN propagates)
            a, x = abs(e[k]), r[k]
            x = a if not a <= x else x
            a = abs(e[ls + k])
            x = a if not a <= x else x
            a = abs(e[2 * ls + k])
            x = a if not a <= x else x
            a = abs(e[3 * ls + k])
            x = a if not a <= x else x
            a = abs(e[4 * ls + k])
            x = a if not a <= x else x
            a = abs(e[5 * ls + k])
            r[k] = a if not a <= x else x


@borrowing
def forward(M, unk, xs, p6fix, X, FA, FL, FE, FP, b, S, p6):
    """One pose's forward pass (:func:`forward_block` on a block of one lane: the arrays of
    :func:`forward_block` without the lane axis; ``S[5]`` holds the lane's scratch); returns
    the residual."""
    CS = S[5]
    forward_block(M, unk, xs, one_lane(p6fix), one_lane(X), one_lane(FA), one_lane(FL),
                  one_lane(FE), one_lane(FP), b, S, 1, 1, CS[2], CS)
    return CS[2, 0]


@borrowing
def legs_forward(M, X, nu, FA, FL, FE, FP, b, S):
    """One pose's legs against the platform already in ``FP[b]`` (:func:`legs_block` on a
    block of one lane); returns the residual."""
    CS = S[5]
    legs_block(M, one_lane(X), nu, one_lane(FA), one_lane(FL), one_lane(FE), one_lane(FP), b,
               S, 1, 1, CS[2], CS)
    return CS[2, 0]


@borrowing_inlined
def platform_point(ap, i, FPb, k, ls, r):
    """Coordinate ``r`` of ``a_i`` (world) at lane ``k`` of the platforms ``FPb (27, ls)``
    (one pose: ``fp (27,)``, ``k = 0``, ``ls = 1``): the one formula of
    :func:`platform_points` and of the rows' lane loops (``_geometry.context_lanes``)."""
    fp = lanes(FPb)
    return (fp[(6 + 3 * r) * ls + k] * ap[i, 0] + fp[(7 + 3 * r) * ls + k] * ap[i, 1]
            + fp[(8 + 3 * r) * ls + k] * ap[i, 2] + fp[(15 + r) * ls + k])


@borrowing
def platform_points(M, fp, i, out):
    """``a_i`` (world) at the platform ``fp`` into ``out (3,)``."""
    ap = M[AP]
    for r in range(3):
        out[r] = platform_point(ap, i, fp, 0, 1, r)


@borrowing_inlined
def twist_lane(rot, tra, FAj, TWj, k, ls):
    """Lane ``k``'s unit twist ``[v; w]`` about the base origin (physical) of the joint of
    frames ``FAj (6, ls)`` (axis, point) into ``TWj (6, ls)``; ``rot``, ``tra`` its rotation
    and translation per unit joint value.  :func:`joint_twist` (one pose: ``k = 0``, ``ls =
    1``) without the model tuple, for loops over a leg's joints and lanes
    (``_geometry.context_lanes``, ``_rows.lane_frames_into``)."""
    fa, out = lanes(FAj), lanes(TWj)
    d0, d1, d2 = fa[k], fa[ls + k], fa[2 * ls + k]
    p0, p1, p2 = fa[3 * ls + k], fa[4 * ls + k], fa[5 * ls + k]
    w0, w1, w2 = rot * d0, rot * d1, rot * d2
    out[k] = p1 * w2 - p2 * w1 + tra * d0
    out[ls + k] = p2 * w0 - p0 * w2 + tra * d1
    out[2 * ls + k] = p0 * w1 - p1 * w0 + tra * d2
    out[3 * ls + k], out[4 * ls + k], out[5 * ls + k] = w0, w1, w2


@borrowing
def joint_twist(M, i, j, fa, out):
    """Joint ``j`` of leg ``i``'s unit twist ``[v; w]`` about the base origin (physical)."""
    twist_lane(M[ROT][i, j], M[TRA][i, j], fa[j], out, 0, 1)
