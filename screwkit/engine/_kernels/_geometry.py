"""One leg at one pose or the lanes of a block, compiled: its end points and twists, named
points and reference directions (private; its members from them: :mod:`._members`).

A leg's context ``ctx (4, 3)``: ``A``, ``a`` (world), its centroid (``A``, ``a`` and every
joint point) and ``[|a - A|, 0, 0]`` (its characteristic length).  Twists ``tw (m, 6)`` are
the physical unit twists ``[v; w]`` about the base origin.
"""

import math

from ._jit import borrowing, inlined, lanes

from ._kin import platform_point, twist_lane
from ._small import cross
from ._layout import (A, DIRS, DIR_ALONG, DIR_BASE, DIR_BASE_OA, DIR_BASE_TANGENT, DIR_JOINT,
                      DIR_LEG, DIR_PERPENDICULAR, DIR_PLATFORM, DIR_PLATFORM_OA,
                      DIR_PLATFORM_TANGENT, K_P, K_PA, LEG, L_SIZE, PLAT, PTS, PT_A,
                      PT_JOINT, PT_MEET, PT_a, P_P0, P_R0)
from ._layout import AP, BLOCK, D, RL_CTX, RL_DV, RL_PV, RL_TW, ROT, TRA


@borrowing
def leg_setup(M, i, fa, fp, ctx, tw):
    """The context and twists of leg ``i`` at the frames ``fa (m, 6)``, platform ``fp``
    (:func:`context_lanes` on one lane)."""
    context_lanes(M, i, fa, fp, ctx, tw, True, 1, 1)


@borrowing
def eval_points(M, i, fa, ctx, out):
    """The leg's named points (``PTS``) into ``out (p, 3)`` (:func:`points_lanes` on one
    lane)."""
    points_lanes(M, i, fa, ctx, out, 1, 1)


@borrowing
def eval_directions(M, i, fa, fp, ctx, out):
    """The leg's reference directions (``DIRS``), unit, into ``out (d, 3)``
    (:func:`directions_lanes` on one lane)."""
    directions_lanes(M, i, fa, fp, ctx, out, 1, 1)


@borrowing
def legs_frames_block(M, FA, FP, RL, nb):
    """Every leg's context and twists, named points and directions (:func:`leg_setup`,
    :func:`eval_points`, :func:`eval_directions`) for the ``nb`` lanes of a block at once:
    the frames ``FA (n, m, 6, BLOCK)`` and platforms ``FP (27, BLOCK)`` of one of the
    block's buffers into ``RL``: ``CTX (n, 4, 3, BLOCK)``, ``PV (n, p, 3, BLOCK)``, ``DV (n,
    d, 3, BLOCK)``, ``TW (n, m, 6, BLOCK)`` (``_block.make_rows_lanes``).  The lane loops of
    the one-pose functions with the block's stride (compiled once for it: the one-pose
    functions are the stride 1), so each lane's values are the pose's alone, bit for bit."""
    CTX, PV, DV, TW = RL[RL_CTX], RL[RL_PV], RL[RL_DV], RL[RL_TW]
    for i in range(M[D].shape[0]):
        context_lanes(M, i, FA[i], FP, CTX[i], TW[i], True, nb, BLOCK)
        points_lanes(M, i, FA[i], CTX[i], PV[i], nb, BLOCK)
        directions_lanes(M, i, FA[i], FP, CTX[i], DV[i], nb, BLOCK)


@inlined
def context_lanes(M, i, FA, FP, CTX, TW, twists, nb, ls):
    """Leg ``i``'s context at ``nb`` lanes of its frames ``FA (m, 6, ls)`` and platforms
    ``FP (27, ls)`` into ``CTX (4, 3, ls)``, with ``twists`` its joints' twists into ``TW
    (m, 6, ls)`` (one pose: the arrays without their lane axis, ``ls = 1``).  Lane loops (the lane axis last, read
    through :func:`~._jit.lanes` at the constant stride ``ls``: LLVM vectorises the block's)
    whose arithmetic per lane is one pose's, in the same order.  Inlined into
    :func:`leg_setup` (stride 1) and :func:`legs_frames_block` (``BLOCK``) only."""
    Am, ap, rot, tra = M[A], M[AP], M[ROT], M[TRA]
    size = M[LEG][i, L_SIZE]
    fa, ctx = lanes(FA), lanes(CTX)
    for r in range(3):
        a = Am[i, r]
        for k in range(nb):
            ctx[r * ls + k] = a
            ctx[(3 + r) * ls + k] = platform_point(ap, i, FP, k, ls, r)
            ctx[(6 + r) * ls + k] = 0.0       # (the sum of the joints' points)
    for j in range(size):
        o = 6 * j * ls
        rj, tj, faj, twj = rot[i, j], tra[i, j], FA[j], TW[j]
        for k in range(nb):
            ctx[6 * ls + k] += fa[o + 3 * ls + k]
            ctx[7 * ls + k] += fa[o + 4 * ls + k]
            ctx[8 * ls + k] += fa[o + 5 * ls + k]
            if twists:
                twist_lane(rj, tj, faj, twj, k, ls)
    q = 2.0 + size
    for k in range(nb):
        for r in range(3):
            ctx[(6 + r) * ls + k] = (ctx[r * ls + k] + ctx[(3 + r) * ls + k]
                                     + ctx[(6 + r) * ls + k]) / q
        d0 = ctx[3 * ls + k] - ctx[k]
        d1 = ctx[4 * ls + k] - ctx[ls + k]
        d2 = ctx[5 * ls + k] - ctx[2 * ls + k]
        ctx[9 * ls + k] = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        ctx[10 * ls + k] = 0.0
        ctx[11 * ls + k] = 0.0


@inlined
def points_lanes(M, i, FA, CTX, OUT, nb, ls):
    """Leg ``i``'s named points (``PTS``) at ``nb`` lanes into ``OUT (p, 3, ls)``
    (:func:`context_lanes`'s layout and rules)."""
    pts = M[PTS][i]
    fa, ctx, out = lanes(FA), lanes(CTX), lanes(OUT)
    for r in range(pts.shape[0]):
        t = pts[r, 0]
        if t < 0:
            break
        o = 3 * r * ls
        if t == PT_A or t == PT_a or t == PT_JOINT:
            if t == PT_JOINT:
                src, so = fa, (6 * pts[r, 1] + 3) * ls
            else:
                src, so = ctx, (0 if t == PT_A else 3) * ls
            for c in range(3):
                for k in range(nb):
                    out[o + c * ls + k] = src[so + c * ls + k]
        elif t == PT_MEET:
            # the midpoint of the common perpendicular of the two axes
            e, f = 6 * pts[r, 1] * ls, 6 * pts[r, 2] * ls
            for k in range(nb):
                a0, a1, a2 = fa[e + k], fa[e + ls + k], fa[e + 2 * ls + k]
                b0, b1, b2 = fa[f + k], fa[f + ls + k], fa[f + 2 * ls + k]
                p0, p1, p2 = fa[e + 3 * ls + k], fa[e + 4 * ls + k], fa[e + 5 * ls + k]
                q0, q1, q2 = fa[f + 3 * ls + k], fa[f + 4 * ls + k], fa[f + 5 * ls + k]
                w0, w1, w2 = p0 - q0, p1 - q1, p2 - q2
                b = a0 * b0 + a1 * b1 + a2 * b2
                d = a0 * w0 + a1 * w1 + a2 * w2
                g = b0 * w0 + b1 * w1 + b2 * w2
                den = max(1.0 - b * b, 1e-300)
                s, u = (b * g - d) / den, (g - b * d) / den
                out[o + k] = 0.5 * (p0 + s * a0 + q0 + u * b0)
                out[o + ls + k] = 0.5 * (p1 + s * a1 + q1 + u * b1)
                out[o + 2 * ls + k] = 0.5 * (p2 + s * a2 + q2 + u * b2)


@inlined
def directions_lanes(M, i, FA, FP, CTX, OUT, nb, ls):
    """Leg ``i``'s reference directions (``DIRS``), unit, at ``nb`` lanes into ``OUT (d, 3,
    ls)`` (:func:`context_lanes`'s layout and rules): each direction's vector first (its kind
    the model's: one lane loop per kind), then its sign and normalisation."""
    dirs, plat = M[DIRS][i], M[PLAT]
    fa, fp, ctx, out = lanes(FA), lanes(FP), lanes(CTX), lanes(OUT)
    for r in range(dirs.shape[0]):
        t, a1, a2 = dirs[r, 0], dirs[r, 1], dirs[r, 2]
        if t < 0:
            break
        o0, o1, o2 = 3 * r * ls, (3 * r + 1) * ls, (3 * r + 2) * ls
        if t == DIR_LEG:
            for k in range(nb):
                out[o0 + k] = ctx[3 * ls + k] - ctx[k]
                out[o1 + k] = ctx[4 * ls + k] - ctx[ls + k]
                out[o2 + k] = ctx[5 * ls + k] - ctx[2 * ls + k]
        elif t == DIR_BASE:
            x0, x1, x2 = plat[P_R0 + a1], plat[P_R0 + 3 + a1], plat[P_R0 + 6 + a1]
            for k in range(nb):
                out[o0 + k], out[o1 + k], out[o2 + k] = x0, x1, x2
        elif t == DIR_PLATFORM:
            for k in range(nb):
                out[o0 + k] = fp[(6 + a1) * ls + k]
                out[o1 + k] = fp[(9 + a1) * ls + k]
                out[o2 + k] = fp[(12 + a1) * ls + k]
        elif t == DIR_BASE_OA or t == DIR_BASE_TANGENT:
            c0, c1, c2 = plat[P_P0], plat[P_P0 + 1], plat[P_P0 + 2]
            z0, z1, z2 = plat[P_R0 + 2], plat[P_R0 + 5], plat[P_R0 + 8]
            tangent = t == DIR_BASE_TANGENT
            for k in range(nb):
                x0, x1, x2 = ctx[k] - c0, ctx[ls + k] - c1, ctx[2 * ls + k] - c2
                if tangent:
                    x0, x1, x2 = cross(z0, z1, z2, x0, x1, x2)
                out[o0 + k], out[o1 + k], out[o2 + k] = x0, x1, x2
        elif t == DIR_PLATFORM_OA or t == DIR_PLATFORM_TANGENT:
            tangent = t == DIR_PLATFORM_TANGENT
            for k in range(nb):
                x0 = ctx[3 * ls + k] - fp[15 * ls + k]
                x1 = ctx[4 * ls + k] - fp[16 * ls + k]
                x2 = ctx[5 * ls + k] - fp[17 * ls + k]
                if tangent:
                    z0, z1, z2 = fp[8 * ls + k], fp[11 * ls + k], fp[14 * ls + k]
                    x0, x1, x2 = cross(z0, z1, z2, x0, x1, x2)
                out[o0 + k], out[o1 + k], out[o2 + k] = x0, x1, x2
        elif t == DIR_JOINT:
            for k in range(nb):
                out[o0 + k] = fa[6 * a1 * ls + k]
                out[o1 + k] = fa[(6 * a1 + 1) * ls + k]
                out[o2 + k] = fa[(6 * a1 + 2) * ls + k]
        elif t == DIR_PERPENDICULAR:
            u, v = 3 * a1 * ls, 3 * a2 * ls
            for k in range(nb):
                u0, u1, u2 = out[u + k], out[u + ls + k], out[u + 2 * ls + k]
                v0, v1, v2 = out[v + k], out[v + ls + k], out[v + 2 * ls + k]
                x0, x1, x2 = cross(u0, u1, u2, v0, v1, v2)
                nx = max(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), 1e-300)
                out[o0 + k], out[o1 + k], out[o2 + k] = x0 / nx, x1 / nx, x2 / nx
        elif t == DIR_ALONG:
            u = 3 * a1 * ls
            for k in range(nb):
                out[o0 + k], out[o1 + k] = out[u + k], out[u + ls + k]
                out[o2 + k] = out[u + 2 * ls + k]
        else:
            for k in range(nb):
                out[o0 + k], out[o1 + k], out[o2 + k] = 0.0, 0.0, 0.0
        sg = -1.0 if dirs[r, 3] else 1.0
        for k in range(nb):
            x0, x1, x2 = out[o0 + k], out[o1 + k], out[o2 + k]
            nx = max(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), 1e-300)
            out[o0 + k], out[o1 + k], out[o2 + k] = sg * x0 / nx, sg * x1 / nx, sg * x2 / nx


@borrowing
def is_prismatic(kind):
    return kind == K_P or kind == K_PA
