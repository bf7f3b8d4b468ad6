"""A leg's constraint and actuation members by its row template, on lanes, compiled
(private).

The members a leg's template names (:mod:`screwkit.engine._templates`): groups of pure
couples and of forces through named points, recomputed as null spaces of the current joint
axes and given their canonical bases from the reference directions; the actuation force
on the line through two named points, scaled so that its reciprocal product with the
actuated joint's unit twist is 1.  Every function here works on lanes (poses) at once, the
lane axis last and ``ls`` apart (:func:`~._jit.lanes`), the arithmetic of each lane one
pose's in the same order: the rows of a block of poses (:func:`template_lanes`, inlined
into the block driver with ``ls`` its constant, where LLVM vectorises the lane loops) and
of one pose (a block of one, ``ls = 1``: ``_rows``, ``_probe``) are the same code, and a
lane gives its pose's bits.  The choices a pose makes on its values (the pair of rows whose
cross product spans a null line, the longest row, a sign) are selections per lane.

Arrays: a leg's frames ``FA (m, 6, ls)`` (axis, point), twists ``TW (m, 6, ls)``, context
``CTX (4, 3, ls)`` (``_geometry``), named points ``PV (p, 3, ls)`` and directions ``DV (d,
3, ls)``; scratch ``R (>= m, 3, ls)`` (a group's rows), ``V (>= 3, ls)`` (a null vector),
``BASIS (3, 3, ls)`` and ``SC (NSC, ls)`` (per lane values and flags, rows ``SC_*``).
"""

import math

from ._jit import borrowing, borrowing_inlined, choose, inlined, lanes
from ._geometry import is_prismatic
from ._small import cross
from ._layout import (A_NONE, GRP, G_COUPLE, KIND, LEG, L_ACT, L_AROW, L_SIZE, NSC, PAIR_ROWS,
                      REF_FLAG, SC_ACT, SC_BIG, SC_GROUPS, SC_NULL, SC_P0, SC_P1, SC_P2, SC_PAIR,
                      SC_REM, SC_RES, SC_STATUS, SC_WORST, TPL, T_AKIND, T_AP1, T_AP2, T_CROW,
                      T_K, T_NG, ZERO)

#: ``SC[SC_STATUS]`` of :func:`template_lanes`: the structure of home does not hold (the
#: general rules decide); the rows are done; done, but not well defined.
NOT_DONE, DONE, DONE_FLAGGED = 0.0, 1.0, 2.0


@inlined
def group_rows_lanes(kind, size, couple, PV, xp, FA, TW, CTX, R, nb, ls):
    """The dimensionless rows whose null space is a group's members into ``R``: for couples
    the rotation axes (rule 3); for forces through the named point ``PV[xp]`` the
    velocities ``v_j - X x w_j`` of that point under every joint (over the leg's length for
    R and H: rules 1 and 2).  ``kind`` the leg's joint kinds, ``size`` its joints.  Returns
    their count (the model's: every lane's)."""
    fa, tw, ctx, pv, r = lanes(FA), lanes(TW), lanes(CTX), lanes(PV), lanes(R)
    x = 3 * xp * ls
    cnt = 0
    for j in range(size):
        pris = is_prismatic(kind[j])
        if couple and pris:
            continue
        o, t = 3 * cnt * ls, 6 * j * ls
        if couple:
            for c in range(3):
                for k in range(nb):
                    r[o + c * ls + k] = fa[t + c * ls + k]
        else:
            for k in range(nb):
                f = 1.0 if pris else 1.0 / ctx[9 * ls + k]
                x0, x1, x2 = pv[x + k], pv[x + ls + k], pv[x + 2 * ls + k]
                t0, t1, t2 = tw[t + k], tw[t + ls + k], tw[t + 2 * ls + k]
                t3, t4, t5 = tw[t + 3 * ls + k], tw[t + 4 * ls + k], tw[t + 5 * ls + k]
                r[o + k] = (t0 - (x1 * t5 - x2 * t4)) * f
                r[o + ls + k] = (t1 - (x2 * t3 - x0 * t5)) * f
                r[o + 2 * ls + k] = (t2 - (x0 * t4 - x1 * t3)) * f
        cnt += 1
    return cnt


@borrowing_inlined
def _pair_lanes(R, SC, oa, ob, src, dst, nb, ls):
    """``R``'s rows at ``oa``, ``ob`` against the best pair so far (``SC``'s rows from ``src``),
    the better into those from ``dst`` (not in place: that select would be a masked store)."""
    rw, sc = lanes(R), lanes(SC)
    for k in range(nb):
        a0, a1, a2 = rw[oa + k], rw[oa + ls + k], rw[oa + 2 * ls + k]
        b0, b1, b2 = rw[ob + k], rw[ob + ls + k], rw[ob + 2 * ls + k]
        x0, x1, x2 = cross(a0, a1, a2, b0, b1, b2)
        size2 = x0 * x0 + x1 * x1 + x2 * x2
        take = size2 > sc[src + k]
        sc[dst + k] = choose(take, size2, sc[src + k])
        sc[dst + ls + k] = choose(take, a0 ** 2 + a1 ** 2 + a2 ** 2, sc[src + ls + k])
        sc[dst + 2 * ls + k] = choose(take, b0 ** 2 + b1 ** 2 + b2 ** 2, sc[src + 2 * ls + k])
        sc[dst + 3 * ls + k] = choose(take, x0, sc[src + 3 * ls + k])
        sc[dst + 4 * ls + k] = choose(take, x1, sc[src + 4 * ls + k])
        sc[dst + 5 * ls + k] = choose(take, x2, sc[src + 5 * ls + k])


@inlined
def null_space_lanes(R, r, g, V, SC, nb, ls):
    """The null space of dimension ``g`` of the rows ``R[:r]`` (dimensionless 3-vectors): for
    ``g = 1`` its unit vector, for ``g = 2`` the unit normal of the null plane, into ``V``;
    ``SC[SC_NULL]`` 1 where the rows leave a null space of exactly that dimension (within
    ``ZERO``), else 0."""
    rw, v, sc = lanes(R), lanes(V), lanes(SC)
    NUL, BIG, RES = SC_NULL * ls, SC_BIG * ls, SC_RES * ls
    if g >= 2:
        # the longest row (the first of the longest: a strict comparison)
        for k in range(nb):
            sc[BIG + k] = 0.0
            v[k], v[ls + k], v[2 * ls + k] = rw[k], rw[ls + k], rw[2 * ls + k]
        for q in range(r):
            o = 3 * q * ls
            for k in range(nb):
                a0, a1, a2 = rw[o + k], rw[o + ls + k], rw[o + 2 * ls + k]
                nq = math.sqrt(a0 ** 2 + a1 ** 2 + a2 ** 2)
                take = nq > sc[BIG + k]
                sc[BIG + k] = nq if take else sc[BIG + k]
                v[k] = a0 if take else v[k]
                v[ls + k] = a1 if take else v[ls + k]
                v[2 * ls + k] = a2 if take else v[2 * ls + k]
        if g >= 3:
            for k in range(nb):
                sc[NUL + k] = 1.0 if sc[BIG + k] < ZERO else 0.0
            return
        for k in range(nb):
            s = max(sc[BIG + k], 1e-300)
            v[k], v[ls + k], v[2 * ls + k] = v[k] / s, v[ls + k] / s, v[2 * ls + k] / s
            sc[RES + k] = 0.0
        for q in range(r):
            o = 3 * q * ls
            for k in range(nb):
                a0, a1, a2 = rw[o + k], rw[o + ls + k], rw[o + 2 * ls + k]
                x0, x1, x2 = cross(a0, a1, a2, v[k], v[ls + k], v[2 * ls + k])
                sc[RES + k] = max(sc[RES + k], math.sqrt(x0 * x0 + x1 * x1 + x2 * x2))
        for k in range(nb):
            sc[NUL + k] = 1.0 if (sc[BIG + k] > 1e-6) & (sc[RES + k] < ZERO) else 0.0
        return
    if r < 2:
        for k in range(nb):
            v[k], v[ls + k], v[2 * ls + k] = math.nan, math.nan, math.nan
            sc[NUL + k] = 0.0
        return
    # the largest cross product of two rows (dimensionless) by its square, the best so far
    # in one set of rows, each pair's verdict into the other (_pair_lanes), in turn
    S0, S1 = SC_PAIR * ls, (SC_PAIR + PAIR_ROWS) * ls
    for k in range(nb):
        sc[S0 + k] = -1.0
        sc[S0 + 3 * ls + k], sc[S0 + 4 * ls + k], sc[S0 + 5 * ls + k] = 0.0, 0.0, 0.0
    j = 0
    for a in range(r - 1):
        for b in range(a + 1, r):
            if j % 2 == 0:
                _pair_lanes(R, SC, 3 * a * ls, 3 * b * ls, S0, S1, nb, ls)
            else:
                _pair_lanes(R, SC, 3 * a * ls, 3 * b * ls, S1, S0, nb, ls)
            j += 1
    if j % 2 == 1:
        for q in range(PAIR_ROWS):
            for k in range(nb):
                sc[S0 + q * ls + k] = sc[S1 + q * ls + k]
    for k in range(nb):
        # (no pair compared, non-finite rows: -1 and 0; selects, no branch, so that the
        # loop vectorises: short-circuit `and` and branches in a lane loop keep it scalar)
        pair = sc[S0 + k] >= 0.0
        root = math.sqrt(sc[S0 + k])
        best = root if pair else -1.0
        rel = root / max(math.sqrt(sc[S0 + ls + k]) * math.sqrt(sc[S0 + 2 * ls + k]), 1e-300)
        brel = rel if pair else 0.0
        nv = max(best, 1e-300)
        v[k], v[ls + k] = sc[S0 + 3 * ls + k] / nv, sc[S0 + 4 * ls + k] / nv
        v[2 * ls + k] = sc[S0 + 5 * ls + k] / nv
        sc[NUL + k] = brel                # (the flag below, once the residual is known)
        sc[RES + k] = 0.0
    for q in range(r):
        o = 3 * q * ls
        for k in range(nb):
            d = rw[o + k] * v[k] + rw[o + ls + k] * v[ls + k] + rw[o + 2 * ls + k] * v[2 * ls + k]
            sc[RES + k] = max(sc[RES + k], abs(d))
    for k in range(nb):
        sc[NUL + k] = 1.0 if (sc[NUL + k] > 1e-6) & (sc[RES + k] < ZERO) else 0.0


@inlined
def remainder_lanes(g, V, BASIS, q, DV, dr, SC, nb, ls):
    """The reference direction ``DV[dr]`` in a null space of dimension ``g`` (``V`` as
    :func:`null_space_lanes` gives it) after the basis members ``BASIS[:q]``.  For ``g = 1``
    ``SC[SC_REM]`` is the signed cosine ``V . d``; else ``SC[SC_P0:SC_P2 + 1]`` is ``d``
    projected on the null space and orthogonalised against the members (Gram-Schmidt), and
    ``SC[SC_REM]`` its size.  The one rule of the rows (:func:`canonical_basis_lanes`) and of
    the home choice of the references (``_probe.home_groups``)."""
    v, bs, dv, sc = lanes(V), lanes(BASIS), lanes(DV), lanes(SC)
    P0, P1, P2, REM = SC_P0 * ls, SC_P1 * ls, SC_P2 * ls, SC_REM * ls
    o = 3 * dr * ls
    if g == 1:
        for k in range(nb):
            sc[REM + k] = v[k] * dv[o + k] + v[ls + k] * dv[o + ls + k] + \
                v[2 * ls + k] * dv[o + 2 * ls + k]
        return
    for k in range(nb):
        p0, p1, p2 = dv[o + k], dv[o + ls + k], dv[o + 2 * ls + k]
        if g == 2:
            c = v[k] * p0 + v[ls + k] * p1 + v[2 * ls + k] * p2
            p0, p1, p2 = p0 - v[k] * c, p1 - v[ls + k] * c, p2 - v[2 * ls + k] * c
        sc[P0 + k], sc[P1 + k], sc[P2 + k] = p0, p1, p2
    for e in range(q):
        b = 3 * e * ls
        for k in range(nb):
            b0, b1, b2 = bs[b + k], bs[b + ls + k], bs[b + 2 * ls + k]
            p0, p1, p2 = sc[P0 + k], sc[P1 + k], sc[P2 + k]
            c = b0 * p0 + b1 * p1 + b2 * p2
            sc[P0 + k], sc[P1 + k], sc[P2 + k] = p0 - b0 * c, p1 - b1 * c, p2 - b2 * c
    for k in range(nb):
        p0, p1, p2 = sc[P0 + k], sc[P1 + k], sc[P2 + k]
        sc[REM + k] = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)


@inlined
def canonical_basis_lanes(g, V, refs, DV, BASIS, SC, nb, ls):
    """A basis ``BASIS[:g]`` of a null space from its reference directions ``DV[refs[q]]``:
    one member along its reference (``g = 1``), else the Gram-Schmidt orthonormalisation of
    the references projected on it (:func:`remainder_lanes`); the smallest remainder into
    ``SC[SC_WORST]``."""
    v, bs, sc = lanes(V), lanes(BASIS), lanes(SC)
    P0, P1, P2, REM, WORST = SC_P0 * ls, SC_P1 * ls, SC_P2 * ls, SC_REM * ls, SC_WORST * ls
    for k in range(nb):
        sc[WORST + k] = math.inf
    for q in range(g):
        remainder_lanes(g, V, BASIS, q, DV, refs[q], SC, nb, ls)
        b = 3 * q * ls
        for k in range(nb):
            rem = sc[REM + k]
            if g == 1:
                sg = -1.0 if rem < 0 else 1.0
                bs[b + k], bs[b + ls + k] = v[k] * sg, v[ls + k] * sg
                bs[b + 2 * ls + k] = v[2 * ls + k] * sg
                rem = abs(rem)
            else:
                s = max(rem, 1e-300)
                bs[b + k], bs[b + ls + k] = sc[P0 + k] / s, sc[P1 + k] / s
                bs[b + 2 * ls + k] = sc[P2 + k] / s
            sc[WORST + k] = min(sc[WORST + k], rem)


@inlined
def group_members_lanes(M, i, CTX, PV, DV, FA, TW, OUT, r0, SC, R, V, BASIS, nb, ls):
    """Leg ``i``'s constraint members, group by group, into the rows ``OUT[r0:r0 + k] (rows,
    6, ls)`` (physical: a unit couple ``[0; e]`` or a unit force ``[e; X x e]`` through the
    group's point); ``SC[SC_GROUPS]`` 1 where every group's structure and basis hold, else 0
    (the rows are then not to be used)."""
    grp, kind, size = M[GRP][i], M[KIND][i], M[LEG][i, L_SIZE]
    out, pv, bs, sc = lanes(OUT), lanes(PV), lanes(BASIS), lanes(SC)
    GR, NUL, WORST = SC_GROUPS * ls, SC_NULL * ls, SC_WORST * ls
    for k in range(nb):
        sc[GR + k] = 1.0
    r = r0
    for g in range(M[TPL][i, T_NG]):
        couple = grp[g, 0] == G_COUPLE
        dim, xp = grp[g, 2], grp[g, 1]
        cnt = group_rows_lanes(kind, size, couple, PV, xp, FA, TW, CTX, R, nb, ls)
        null_space_lanes(R, cnt, dim, V, SC, nb, ls)
        canonical_basis_lanes(dim, V, grp[g, 3:6], DV, BASIS, SC, nb, ls)
        for k in range(nb):
            ok = (sc[NUL + k] != 0.0) & (sc[GR + k] != 0.0) & (sc[WORST + k] > REF_FLAG)
            sc[GR + k] = 1.0 if ok else 0.0
        x = 3 * xp * ls
        for q in range(dim):
            b, o = 3 * q * ls, 6 * r * ls
            for k in range(nb):
                e0, e1, e2 = bs[b + k], bs[b + ls + k], bs[b + 2 * ls + k]
                if couple:
                    out[o + k], out[o + ls + k], out[o + 2 * ls + k] = 0.0, 0.0, 0.0
                    out[o + 3 * ls + k], out[o + 4 * ls + k], out[o + 5 * ls + k] = e0, e1, e2
                else:
                    x0, x1, x2 = pv[x + k], pv[x + ls + k], pv[x + 2 * ls + k]
                    out[o + k], out[o + ls + k], out[o + 2 * ls + k] = e0, e1, e2
                    out[o + 3 * ls + k], out[o + 4 * ls + k], out[o + 5 * ls + k] = \
                        cross(x0, x1, x2, e0, e1, e2)
            r += 1


@inlined
def line_member_lanes(M, i, CTX, PV, TW, OUT, row, SC, nb, ls):
    """The unit force on the line through the leg's two named actuation points into ``OUT[row]``
    (physical); ``SC[SC_ACT]`` 1 where every passive joint leaves the first point's velocity
    normal to the line (the structure chosen at home holds), else 0."""
    tpl, kind = M[TPL][i], M[KIND][i]
    size, act = M[LEG][i, L_SIZE], M[LEG][i, L_ACT]
    ctx, pv, tw, out, sc = lanes(CTX), lanes(PV), lanes(TW), lanes(OUT), lanes(SC)
    X, Y, o, RES = 3 * tpl[T_AP1] * ls, 3 * tpl[T_AP2] * ls, 6 * row * ls, SC_RES * ls
    for k in range(nb):
        x0, x1, x2 = pv[X + k], pv[X + ls + k], pv[X + 2 * ls + k]
        d0, d1, d2 = pv[Y + k] - x0, pv[Y + ls + k] - x1, pv[Y + 2 * ls + k] - x2
        nd = max(math.sqrt(d0 * d0 + d1 * d1 + d2 * d2), 1e-300)
        d0, d1, d2 = d0 / nd, d1 / nd, d2 / nd
        out[o + k], out[o + ls + k], out[o + 2 * ls + k] = d0, d1, d2
        out[o + 3 * ls + k], out[o + 4 * ls + k], out[o + 5 * ls + k] = \
            cross(x0, x1, x2, d0, d1, d2)
        sc[RES + k] = 0.0
    # every passive joint leaves X's velocity normal to the line (a structural choice)
    for j in range(size):
        if j == act:
            continue
        t = 6 * j * ls
        pris = is_prismatic(kind[j])
        for k in range(nb):
            x0, x1, x2 = pv[X + k], pv[X + ls + k], pv[X + 2 * ls + k]
            t0, t1, t2 = tw[t + k], tw[t + ls + k], tw[t + 2 * ls + k]
            t3, t4, t5 = tw[t + 3 * ls + k], tw[t + 4 * ls + k], tw[t + 5 * ls + k]
            v0 = t0 - (x1 * t5 - x2 * t4)
            v1 = t1 - (x2 * t3 - x0 * t5)
            v2 = t2 - (x0 * t4 - x1 * t3)
            f = 1.0 if pris else 1.0 / ctx[9 * ls + k]
            d = v0 * out[o + k] + v1 * out[o + ls + k] + v2 * out[o + 2 * ls + k]
            sc[RES + k] = max(sc[RES + k], abs(d) * f)
    for k in range(nb):
        sc[SC_ACT * ls + k] = 1.0 if sc[RES + k] < ZERO else 0.0


@inlined
def scale_actuation_lanes(M, i, CTX, TW, OUT, row, SCALE, SC, nb, ls):
    """Scale the unit member ``OUT[row]`` so that its reciprocal product with the actuated
    joint's unit twist is 1 (``SCALE[row]`` the factor); where that product vanishes
    relative to the actuator's size (1 for a prismatic joint, the leg's length else) the
    member is dependent: scale 0, and ``SC[SC_ACT]`` set to 0."""
    act = M[LEG][i, L_ACT]
    pris = is_prismatic(M[KIND][i, act])
    ctx, tw, out, sl, sc = lanes(CTX), lanes(TW), lanes(OUT), lanes(SCALE), lanes(SC)
    o, t, ACT = 6 * row * ls, 6 * act * ls, SC_ACT * ls
    for k in range(nb):
        prod = 0.0
        for q in range(6):
            prod += out[o + q * ls + k] * tw[t + q * ls + k]
        size_a = 1.0 if pris else ctx[9 * ls + k]
        dependent = abs(prod) <= 1e-9 * max(size_a, 1e-300)
        scale = 0.0 if dependent else 1.0 / abs(prod)
        sg = -1.0 if prod < 0 else 1.0
        for q in range(6):
            out[o + q * ls + k] *= sg * scale
        sl[row * ls + k] = scale
        sc[ACT + k] = 0.0 if dependent else sc[ACT + k]


@inlined
def template_lanes(M, i, CTX, PV, DV, FA, TW, OUT, SCALE, SC, R, V, BASIS, groups, actuation,
                   nb, ls):
    """Leg ``i``'s rows by its template into ``OUT (rows, 6, ls)`` and ``SCALE (rows, ls)`` at
    its rows (``T_CROW`` on, ``L_AROW``): with ``groups`` its group members (else
    ``SC[SC_GROUPS]`` set to 1); ``actuation`` 1 its actuation row by the template (none, or
    the force on its line, scaled), 2 the scaling of the unit member already in its row
    (``SC[SC_ACT]`` set by the caller), 0 none.  ``SC[SC_STATUS]`` per lane: :data:`NOT_DONE`
    where a group's structure or basis does not hold at that pose (the general rules
    decide, ``_rows.leg_rows``), :data:`DONE`, or :data:`DONE_FLAGGED` (no actuation, or its
    line's structure does not hold, or the member is dependent)."""
    tpl = M[TPL][i]
    k_rows, crow = tpl[T_K], tpl[T_CROW]
    sc, sl, out = lanes(SC), lanes(SCALE), lanes(OUT)
    GR, ACT, ST = SC_GROUPS * ls, SC_ACT * ls, SC_STATUS * ls
    if groups and k_rows:
        group_members_lanes(M, i, CTX, PV, DV, FA, TW, OUT, crow, SC, R, V, BASIS, nb, ls)
        for r in range(k_rows):
            for k in range(nb):
                sl[(crow + r) * ls + k] = 1.0
    else:
        for k in range(nb):
            sc[GR + k] = 1.0
    arow = M[LEG][i, L_AROW]
    if arow < 0 or actuation == 0:
        for k in range(nb):
            sc[ST + k] = DONE if sc[GR + k] != 0.0 else NOT_DONE
        return
    if actuation == 1 and tpl[T_AKIND] == A_NONE:
        o = 6 * arow * ls
        for q in range(6):
            for k in range(nb):
                out[o + q * ls + k] = 0.0
        for k in range(nb):
            sl[arow * ls + k] = 0.0
            sc[ST + k] = DONE_FLAGGED if sc[GR + k] != 0.0 else NOT_DONE
        return
    if actuation == 1:
        line_member_lanes(M, i, CTX, PV, TW, OUT, arow, SC, nb, ls)
    scale_actuation_lanes(M, i, CTX, TW, OUT, arow, SCALE, SC, nb, ls)
    for k in range(nb):
        done = DONE if sc[ACT + k] != 0.0 else DONE_FLAGGED
        sc[ST + k] = done if sc[GR + k] != 0.0 else NOT_DONE


@borrowing
def template_one(M, i, CTX, PV, DV, FA, TW, OUT, SCALE, SC, R, V, BASIS, groups, actuation):
    """:func:`template_lanes` on one pose (a block of one: each array with its lane axis of
    one), compiled once for every one-pose use (``_rows``: the template rows, the groups and
    the actuation of the general rule)."""
    template_lanes(M, i, CTX, PV, DV, FA, TW, OUT, SCALE, SC, R, V, BASIS, groups, actuation,
                   1, 1)


@borrowing
def home_null_space(kind, size, couple, PV, xp, FA, TW, CTX, R, g, V, SC):
    """A group's rows and their null space at one pose (:func:`group_rows_lanes`,
    :func:`null_space_lanes` on a block of one; ``_probe.home_groups``).  Returns the rows'
    count."""
    cnt = group_rows_lanes(kind, size, couple, PV, xp, FA, TW, CTX, R, 1, 1)
    null_space_lanes(R, cnt, g, V, SC, 1, 1)
    return cnt


@borrowing
def home_remainder(g, V, BASIS, q, DV, dr, SC):
    """:func:`remainder_lanes` on a block of one (``_probe.home_groups``)."""
    remainder_lanes(g, V, BASIS, q, DV, dr, SC, 1, 1)
