"""One leg at one pose, compiled: its end points and twists, named points, reference
directions, the null spaces of its dimensionless rows and their canonical bases (private).

A leg's context ``ctx (4, 3)``: ``A``, ``a`` (world), its centroid (``A``, ``a`` and every
joint point) and ``[|a - A|, 0, 0]`` (its characteristic length).  Twists ``tw (m, 6)`` are
the physical unit twists ``[v; w]`` about the base origin.
"""

import math

from ._jit import borrowing, borrowing_inlined

from ._kin import joint_twist, platform_points
from ._layout import (A, DIRS, DIR_ALONG, DIR_BASE, DIR_BASE_OA, DIR_BASE_TANGENT, DIR_JOINT,
                      DIR_LEG, DIR_PERPENDICULAR, DIR_PLATFORM, DIR_PLATFORM_OA,
                      DIR_PLATFORM_TANGENT, KIND, K_P, K_PA, LEG, L_SIZE, PLAT, PTS, PT_A,
                      PT_JOINT, PT_MEET, PT_a, P_P0, P_R0, ZERO)


@borrowing
def leg_setup(M, i, fa, fp, ctx, tw):
    """The context and twists of leg ``i`` at the frames ``fa (m, 6)``, platform ``fp``."""
    Am = M[A]
    size = M[LEG][i, L_SIZE]
    platform_points(M, fp, i, ctx[1])
    s0, s1, s2 = 0.0, 0.0, 0.0
    for r in range(3):
        ctx[0, r] = Am[i, r]
    for j in range(size):
        s0 += fa[j, 3]
        s1 += fa[j, 4]
        s2 += fa[j, 5]
        joint_twist(M, i, j, fa, tw[j])
    k = 2.0 + size
    ctx[2, 0] = (ctx[0, 0] + ctx[1, 0] + s0) / k
    ctx[2, 1] = (ctx[0, 1] + ctx[1, 1] + s1) / k
    ctx[2, 2] = (ctx[0, 2] + ctx[1, 2] + s2) / k
    d0, d1, d2 = ctx[1, 0] - ctx[0, 0], ctx[1, 1] - ctx[0, 1], ctx[1, 2] - ctx[0, 2]
    ctx[3, 0] = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    ctx[3, 1] = 0.0
    ctx[3, 2] = 0.0


@borrowing
def eval_points(M, i, fa, ctx, out):
    """The leg's named points (``PTS``) into ``out (p, 3)``."""
    pts = M[PTS][i]
    for r in range(pts.shape[0]):
        t = pts[r, 0]
        if t < 0:
            break
        if t == PT_A or t == PT_a:
            for c in range(3):
                out[r, c] = ctx[0 if t == PT_A else 1, c]
        elif t == PT_JOINT:
            for c in range(3):
                out[r, c] = fa[pts[r, 1], 3 + c]
        elif t == PT_MEET:
            # the midpoint of the common perpendicular of the two axes
            f1, f2 = fa[pts[r, 1]], fa[pts[r, 2]]
            w0, w1, w2 = f1[3] - f2[3], f1[4] - f2[4], f1[5] - f2[5]
            b = f1[0] * f2[0] + f1[1] * f2[1] + f1[2] * f2[2]
            d = f1[0] * w0 + f1[1] * w1 + f1[2] * w2
            e = f2[0] * w0 + f2[1] * w1 + f2[2] * w2
            den = max(1.0 - b * b, 1e-300)
            s, u = (b * e - d) / den, (e - b * d) / den
            for c in range(3):
                out[r, c] = 0.5 * (f1[3 + c] + s * f1[c] + f2[3 + c] + u * f2[c])


@borrowing
def eval_directions(M, i, fa, fp, ctx, out):
    """The leg's reference directions (``DIRS``), unit, into ``out (d, 3)``."""
    dirs, plat = M[DIRS][i], M[PLAT]
    for r in range(dirs.shape[0]):
        t, a1, a2 = dirs[r, 0], dirs[r, 1], dirs[r, 2]
        if t < 0:
            break
        x0, x1, x2 = 0.0, 0.0, 0.0
        if t == DIR_LEG:
            x0, x1, x2 = ctx[1, 0] - ctx[0, 0], ctx[1, 1] - ctx[0, 1], ctx[1, 2] - ctx[0, 2]
        elif t == DIR_BASE:
            x0, x1, x2 = plat[P_R0 + a1], plat[P_R0 + 3 + a1], plat[P_R0 + 6 + a1]
        elif t == DIR_PLATFORM:
            x0, x1, x2 = fp[6 + a1], fp[9 + a1], fp[12 + a1]
        elif t == DIR_BASE_OA or t == DIR_BASE_TANGENT:
            x0, x1, x2 = ctx[0, 0] - plat[P_P0], ctx[0, 1] - plat[P_P0 + 1], \
                ctx[0, 2] - plat[P_P0 + 2]
            if t == DIR_BASE_TANGENT:
                z0, z1, z2 = plat[P_R0 + 2], plat[P_R0 + 5], plat[P_R0 + 8]
                x0, x1, x2 = z1 * x2 - z2 * x1, z2 * x0 - z0 * x2, z0 * x1 - z1 * x0
        elif t == DIR_PLATFORM_OA or t == DIR_PLATFORM_TANGENT:
            x0, x1, x2 = ctx[1, 0] - fp[15], ctx[1, 1] - fp[16], ctx[1, 2] - fp[17]
            if t == DIR_PLATFORM_TANGENT:
                z0, z1, z2 = fp[8], fp[11], fp[14]
                x0, x1, x2 = z1 * x2 - z2 * x1, z2 * x0 - z0 * x2, z0 * x1 - z1 * x0
        elif t == DIR_JOINT:
            x0, x1, x2 = fa[a1, 0], fa[a1, 1], fa[a1, 2]
        elif t == DIR_PERPENDICULAR:
            u, v = out[a1], out[a2]
            x0 = u[1] * v[2] - u[2] * v[1]
            x1 = u[2] * v[0] - u[0] * v[2]
            x2 = u[0] * v[1] - u[1] * v[0]
            nx = max(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), 1e-300)
            x0, x1, x2 = x0 / nx, x1 / nx, x2 / nx
        elif t == DIR_ALONG:
            x0, x1, x2 = out[a1, 0], out[a1, 1], out[a1, 2]
        nx = max(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), 1e-300)
        sg = -1.0 if dirs[r, 3] else 1.0
        out[r, 0], out[r, 1], out[r, 2] = sg * x0 / nx, sg * x1 / nx, sg * x2 / nx


@borrowing
def is_prismatic(kind):
    return kind == K_P or kind == K_PA


@borrowing
def group_rows(M, i, couple, X, fa, tw, ctx, rows):
    """The dimensionless rows whose null space is a group's members: for couples the
    rotation axes (rule 3); for forces through ``X`` the velocities ``v_j - X x w_j`` of
    ``X`` under every joint (over the leg's length for R and H: rules 1 and 2).  Returns
    their count."""
    kind = M[KIND]
    cnt = 0
    L = ctx[3, 0]
    for j in range(M[LEG][i, L_SIZE]):
        if couple:
            if is_prismatic(kind[i, j]):
                continue
            for c in range(3):
                rows[cnt, c] = fa[j, c]
        else:
            t = tw[j]
            f = 1.0 if is_prismatic(kind[i, j]) else 1.0 / L
            rows[cnt, 0] = (t[0] - (X[1] * t[5] - X[2] * t[4])) * f
            rows[cnt, 1] = (t[1] - (X[2] * t[3] - X[0] * t[5])) * f
            rows[cnt, 2] = (t[2] - (X[0] * t[4] - X[1] * t[3])) * f
        cnt += 1
    return cnt


@borrowing_inlined
def null_space(rows, r, g, vec):
    """The null space of dimension ``g`` of ``rows[:r]`` (dimensionless 3-vectors): for
    ``g = 1`` its unit vector, for ``g = 2`` the unit normal of the null plane, into
    ``vec``; returns False where the rows do not leave a null space of exactly that
    dimension (within ``ZERO``)."""
    big, kbig = 0.0, 0
    for q in range(r if g >= 2 else 0):   # the longest row (not needed for g = 1)
        nq = math.sqrt(rows[q, 0] ** 2 + rows[q, 1] ** 2 + rows[q, 2] ** 2)
        if nq > big:
            big, kbig = nq, q
    if g >= 3:
        return big < ZERO
    if g == 2:
        nb = max(big, 1e-300)
        for c in range(3):
            vec[c] = rows[kbig, c] / nb
        off = 0.0
        for q in range(r):
            x0 = rows[q, 1] * vec[2] - rows[q, 2] * vec[1]
            x1 = rows[q, 2] * vec[0] - rows[q, 0] * vec[2]
            x2 = rows[q, 0] * vec[1] - rows[q, 1] * vec[0]
            off = max(off, math.sqrt(x0 * x0 + x1 * x1 + x2 * x2))
        return big > 1e-6 and off < ZERO
    if r < 2:
        for c in range(3):
            vec[c] = math.nan
        return False
    # the largest cross product (rows are dimensionless), compared by its square: the
    # square roots only for the pair chosen
    best2, ba, bb = -1.0, 0, 1
    for a in range(r - 1):
        for b in range(a + 1, r):
            x0 = rows[a, 1] * rows[b, 2] - rows[a, 2] * rows[b, 1]
            x1 = rows[a, 2] * rows[b, 0] - rows[a, 0] * rows[b, 2]
            x2 = rows[a, 0] * rows[b, 1] - rows[a, 1] * rows[b, 0]
            size2 = x0 * x0 + x1 * x1 + x2 * x2
            if size2 > best2:
                best2, ba, bb = size2, a, b
                vec[0], vec[1], vec[2] = x0, x1, x2
    best, brel = -1.0, 0.0            # (no pair compared: non-finite rows)
    if best2 >= 0.0:
        best = math.sqrt(best2)
        na = math.sqrt(rows[ba, 0] ** 2 + rows[ba, 1] ** 2 + rows[ba, 2] ** 2)
        nb = math.sqrt(rows[bb, 0] ** 2 + rows[bb, 1] ** 2 + rows[bb, 2] ** 2)
        brel = best / max(na * nb, 1e-300)
    nv = max(best, 1e-300)
    for c in range(3):
        vec[c] /= nv
    res = 0.0
    for q in range(r):
        res = max(res, abs(rows[q, 0] * vec[0] + rows[q, 1] * vec[1] + rows[q, 2] * vec[2]))
    return brel > 1e-6 and res < ZERO


@borrowing
def reference_remainder(g, vec, basis, q, d):
    """``(p0, p1, p2, rem)``: a reference direction ``d (3,)`` in a null space of dimension
    ``g`` (``vec`` as :func:`null_space` gives it) after the basis members ``basis[:q]``.
    For ``g = 1`` ``rem`` is the signed cosine ``vec . d`` (``p`` unused); else ``p`` is
    ``d`` projected on the null space and orthogonalised against the members (Gram-Schmidt),
    ``rem`` its size.  The one rule of the rows (:func:`canonical_basis`) and of the home
    choice of the references (``_probe.home_groups``)."""
    if g == 1:
        return 0.0, 0.0, 0.0, vec[0] * d[0] + vec[1] * d[1] + vec[2] * d[2]
    p0, p1, p2 = d[0], d[1], d[2]
    if g == 2:
        c = vec[0] * d[0] + vec[1] * d[1] + vec[2] * d[2]
        p0, p1, p2 = p0 - vec[0] * c, p1 - vec[1] * c, p2 - vec[2] * c
    for e in range(q):
        c = basis[e, 0] * p0 + basis[e, 1] * p1 + basis[e, 2] * p2
        p0, p1, p2 = p0 - basis[e, 0] * c, p1 - basis[e, 1] * c, p2 - basis[e, 2] * c
    return p0, p1, p2, math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)


@borrowing_inlined
def canonical_basis(g, vec, refs, dv, basis):
    """A basis ``basis[:g]`` of a null space from its reference directions ``dv[refs[q]]``:
    one member along its reference (``g = 1``), else the Gram-Schmidt orthonormalisation of
    the references projected on it (:func:`reference_remainder`); returns the smallest
    remainder."""
    worst = math.inf
    for q in range(g):
        p0, p1, p2, rem = reference_remainder(g, vec, basis, q, dv[refs[q]])
        if g == 1:
            sg = -1.0 if rem < 0 else 1.0
            for k in range(3):
                basis[q, k] = vec[k] * sg
            rem = abs(rem)
        else:
            s = max(rem, 1e-300)
            basis[q, 0], basis[q, 1], basis[q, 2] = p0 / s, p1 / s, p2 / s
        worst = min(worst, rem)
    return worst
