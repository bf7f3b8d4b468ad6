"""Each leg's rows of the unified Jacobian at one pose, compiled (private).

What the rows are was decided once per leg at home (:mod:`screwkit.engine._templates`,
encoded in ``GRP``, ``TPL``, ``GREF``): groups of pure couples and of forces through named
points, recomputed exactly as null spaces of the current joint axes and given their
canonical bases from the reference directions (:mod:`._members`, on lanes; one pose here
is a block of one); or the generic rule (here: the constraint system by SVD of the
length-normalised joint twists, a basis from projected reference wrenches), which also
takes over at a pose where a group's structure does not hold.  The actuation row is the
force on the line through two named points (:mod:`._members`), or the least-norm wrench
reciprocal to the passive joints (here), scaled so that its reciprocal product with the
actuated joint's unit twist is 1 (:mod:`._members`).

The rows workspace ``RW`` of a thread: see :func:`make_rows_work`.  These kernels only
borrow arrays (compiled without reference counts, :func:`._jit.borrowing`); those a pose
calls for every leg are inlined into their callers (:func:`._jit.borrowing_inlined`), since
a call passing the model and workspace tuples costs more than their arithmetic.
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, inner, one_lane

from ._geometry import eval_directions, eval_points, leg_setup
from ._layout import (A_LINE, A_NONE, GREF, LEG, L_ACT, L_AROW, L_SIZE, REF_FLAG, T_AKIND,
                      T_CROW, T_GENERIC, T_K, TPL)
from ._eigen import jacobi_rows
from ._members import DONE, NOT_DONE, NSC, SC_ACT, SC_GROUPS, SC_STATUS, template_one
from ._small import cholesky_solve

(RW_CTX, RW_TW, RW_PV, RW_DV, RW_NR, RW_BASIS, RW_CONS, RW_TN, RW_REF, RW_G, RW_RHS,
 RW_VEC, RW_NRM, RW_TOP, RW_REM, RW_SC) = range(16)


@inner
def make_rows_work(m, npts, ndirs):
    """A thread's rows workspace for legs of up to ``m`` joints."""
    return (np.zeros((4, 3)), np.zeros((m, 6)), np.zeros((max(npts, 1), 3)),
            np.zeros((max(ndirs, 1), 3)), np.zeros((m, 3)), np.zeros((3, 3)),
            np.zeros((6, 6)), np.zeros((max(m, 1), 6)), np.zeros((6, 6)),
            np.zeros((m, m)), np.zeros((m, 1)), np.zeros(12), np.zeros(max(m, 1)),
            np.zeros(max(m, 1), np.int64), np.zeros(6), np.zeros((NSC, 1)))


@borrowing
def _normalise_wrench(f0, f1, f2, m0, m1, m2, c, L, out):
    out[0], out[1], out[2] = f0, f1, f2
    out[3] = (m0 - (c[1] * f2 - c[2] * f1)) / L
    out[4] = (m1 - (c[2] * f0 - c[0] * f2)) / L
    out[5] = (m2 - (c[0] * f1 - c[1] * f0)) / L


@borrowing
def _normalise_twist(t, c, L, out):
    """``[(v - c x w) / L; w]``: a twist about the centroid ``c``, length-normalised."""
    out[0] = (t[0] - (c[1] * t[5] - c[2] * t[4])) / L
    out[1] = (t[1] - (c[2] * t[3] - c[0] * t[5])) / L
    out[2] = (t[2] - (c[0] * t[4] - c[1] * t[3])) / L
    out[3], out[4], out[5] = t[3], t[4], t[5]


@borrowing
def unit_row(out, r):
    """Row ``r`` of ``out (., 6)`` at unit norm (a zero row stays zero)."""
    n = 0.0
    for q in range(6):
        n += out[r, q] * out[r, q]
    n = max(math.sqrt(n), 1e-300)
    for q in range(6):
        out[r, q] /= n


@borrowing
def generic_members(M, i, RW, cons):
    """The leg's constraint members by the generic rule into ``cons[:k]`` (physical, a unit
    force or couple each); returns False where they are not well defined."""
    ctx, tw, dv, Tn, Rf = RW[RW_CTX], RW[RW_TW], RW[RW_DV], RW[RW_TN], RW[RW_REF]
    size = M[LEG][i, L_SIZE]
    k = M[TPL][i, T_K]
    c, L = ctx[2], ctx[3, 0]
    for j in range(size):
        t = tw[j]
        _normalise_twist(t, c, L, Tn[j])
        unit_row(Tn, j)
    # the row space of the twists by one-sided Jacobi: rows orthogonal, norms the singular
    # values; the constraint space is its orthogonal complement (rank 6 - k)
    jacobi_rows(Tn, size, Tn, False)
    nrm, top = RW[RW_NRM], RW[RW_TOP]
    for j in range(size):
        s = 0.0
        for q in range(6):
            s += Tn[j, q] * Tn[j, q]
        nrm[j] = math.sqrt(s)
    rank = 6 - k
    ns = min(size, 6)
    # the singular values in descending order (indices into the rows)
    for q in range(size):
        top[q] = q
    for q in range(size):
        for r in range(q + 1, size):
            if nrm[top[r]] > nrm[top[q]]:
                top[q], top[r] = top[r], top[q]
    ok = True
    tol = 1e-8 * max(1.0, nrm[top[0]] if size else 0.0)
    if rank > 0:
        ok = ok and rank <= size and nrm[top[rank - 1]] > tol
    if ns > rank:
        ok = ok and nrm[top[rank]] <= tol
    A = ctx[0]
    gref = M[GREF][i]
    worst = math.inf
    for r in range(k):
        d = dv[gref[r, 1]]
        if gref[r, 0] == 0:           # a unit force along d through A
            _normalise_wrench(d[0], d[1], d[2], A[1] * d[2] - A[2] * d[1],
                              A[2] * d[0] - A[0] * d[2], A[0] * d[1] - A[1] * d[0], c, L, Rf[r])
        else:                         # a unit couple along d
            _normalise_wrench(0.0, 0.0, 0.0, d[0], d[1], d[2], c, L, Rf[r])
        nr = 0.0
        for q in range(6):
            nr += Rf[r, q] * Rf[r, q]
        nr = max(math.sqrt(nr), 1e-300)
        # projected on the constraint space (out of the twists' row space), Gram-Schmidt
        p = RW[RW_VEC]
        for q in range(6):
            p[q] = Rf[r, q] / nr
        for b in range(min(rank, size)):
            u = Tn[top[b]]
            nu2 = nrm[top[b]] * nrm[top[b]]
            if nu2 <= 0.0:
                continue
            s = 0.0
            for q in range(6):
                s += u[q] * p[q]
            s /= nu2
            for q in range(6):
                p[q] -= u[q] * s
        for e in range(r):
            s = 0.0
            for q in range(6):
                s += cons[e, q] * p[q]
            for q in range(6):
                p[q] -= cons[e, q] * s
        rem = 0.0
        for q in range(6):
            rem += p[q] * p[q]
        rem = math.sqrt(rem)
        RW[RW_REM][r] = rem
        worst = min(worst, rem)
        for q in range(6):
            cons[r, q] = p[q] / max(rem, 1e-300)
    ok = ok and worst > REF_FLAG
    for r in range(k):                # back to physical wrenches, unit force or couple
        f0, f1, f2 = cons[r, 0], cons[r, 1], cons[r, 2]
        m0 = cons[r, 3] * L + (c[1] * f2 - c[2] * f1)
        m1 = cons[r, 4] * L + (c[2] * f0 - c[0] * f2)
        m2 = cons[r, 5] * L + (c[0] * f1 - c[1] * f0)
        nf = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
        nw = 0.0
        for q in range(6):
            nw += cons[r, q] * cons[r, q]
        if nf <= 1e-9 * math.sqrt(nw):
            s = max(math.sqrt(m0 * m0 + m1 * m1 + m2 * m2), 1e-300)
        else:
            s = nf
        cons[r, 0], cons[r, 1], cons[r, 2] = f0 / s, f1 / s, f2 / s
        cons[r, 3], cons[r, 4], cons[r, 5] = m0 / s, m1 / s, m2 / s
    return ok


@borrowing_inlined
def _template(M, i, RW, fa, J, scale, groups, actuation, flag):
    """:func:`._members.template_one` on this pose's rows workspace: the leg's template
    rows into ``J`` and ``scale`` (``groups``, ``actuation`` as there); returns the flag of
    row ``flag`` of its scratch (``SC_GROUPS``, ``SC_ACT``, ``SC_STATUS``)."""
    SC = RW[RW_SC]
    template_one(M, i, one_lane(RW[RW_CTX]), one_lane(RW[RW_PV]), one_lane(RW[RW_DV]),
                 one_lane(fa), one_lane(RW[RW_TW]), one_lane(J), one_lane(scale), SC,
                 one_lane(RW[RW_NR]), one_lane(RW[RW_VEC]), one_lane(RW[RW_BASIS]), groups,
                 actuation)
    return SC[flag, 0]


@borrowing_inlined
def least_norm_member(M, i, RW, member):
    """The actuated twist projected (length-normalised metric about the leg's centroid) on
    the wrenches reciprocal to the passive joints: the least-norm actuation wrench, a unit
    force (``member (6,)``, physical).  Returns False where it is not defined."""
    ctx, tw, Tn, G, rhs = RW[RW_CTX], RW[RW_TW], RW[RW_TN], RW[RW_G], RW[RW_RHS]
    vec = RW[RW_VEC]
    size, act = M[LEG][i, L_SIZE], M[LEG][i, L_ACT]
    c, L = ctx[2], ctx[3, 0]
    # vec[0:6]: the normalised actuated twist; Tn: the passive ones
    npas = 0
    for j in range(size):
        if j != act:
            _normalise_twist(tw[j], c, L, Tn[npas])
            # each passive twist of unit norm: the span (and so the projection) is the same,
            # but a translation's twist, v / L, no longer sits 1 / L^2 below the rotations
            # in the Gram matrix, where the shift and the rounding made the row depend on
            # the length unit (a Delta's Pa: 5e-9 between mm and m)
            s = 0.0
            for q in range(6):
                s += Tn[npas, q] * Tn[npas, q]
            if s > 0.0:
                s = 1.0 / math.sqrt(s)
                for q in range(6):
                    Tn[npas, q] *= s
            npas += 1
    _normalise_twist(tw[act], c, L, vec)
    tr = 0.0
    for a in range(npas):
        for b in range(a + 1):
            s = 0.0
            for q in range(6):
                s += Tn[a, q] * Tn[b, q]
            G[a, b] = s
        tr += G[a, a]
        s = 0.0
        for q in range(6):
            s += Tn[a, q] * vec[q]
        rhs[a, 0] = s
    cholesky_solve(G, npas, rhs, 1, tr * 1e-13)
    for q in range(6):
        s = vec[q]
        for a in range(npas):
            s -= Tn[a, q] * rhs[a, 0]
        vec[6 + q] = s
    f0, f1, f2 = vec[6], vec[7], vec[8]
    m0 = vec[9] * L + (c[1] * f2 - c[2] * f1)
    m1 = vec[10] * L + (c[2] * f0 - c[0] * f2)
    m2 = vec[11] * L + (c[0] * f1 - c[1] * f0)
    nf = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
    nw = 0.0
    for q in range(6, 12):
        nw += vec[q] * vec[q]
    s = max(nf, 1e-300)
    member[0], member[1], member[2] = f0 / s, f1 / s, f2 / s
    member[3], member[4], member[5] = m0 / s, m1 / s, m2 / s
    return nf > 1e-9 * math.sqrt(nw)


@borrowing_inlined
def actuation_row(M, i, RW, fa, J, scale, arow):
    """The actuation row of leg ``i`` (frames ``fa``) into ``J[arow]`` (``[f; m]`` about O,
    reciprocal product 1 with the actuated joint's unit twist) and its scale into
    ``scale[arow]`` (``row = scale * unit member``).  Returns whether it is well defined."""
    akind = M[TPL][i, T_AKIND]
    if akind == A_NONE:
        for q in range(6):
            J[arow, q] = 0.0
        scale[arow] = 0.0
        return False
    if akind == A_LINE:
        return _template(M, i, RW, fa, J, scale, False, 1, SC_ACT) != 0.0
    RW[RW_SC][SC_ACT, 0] = 1.0 if least_norm_member(M, i, RW, J[arow]) else 0.0
    return _template(M, i, RW, fa, J, scale, False, 2, SC_ACT) != 0.0


@borrowing_inlined
def leg_frames(M, i, RW, fa, fp):
    """Leg ``i``'s context, twists, template points and directions at the frames ``fa``,
    ``fp`` (into ``RW``): what both ways of building its rows start from."""
    ctx = RW[RW_CTX]
    leg_setup(M, i, fa, fp, ctx, RW[RW_TW])
    eval_points(M, i, fa, ctx, RW[RW_PV])
    eval_directions(M, i, fa, fp, ctx, RW[RW_DV])


@borrowing_inlined
def put_constraints(cons, k, r0, J, scale):
    """The ``k`` constraint rows ``cons`` into ``J`` from row ``r0`` (scale 1)."""
    for r in range(k):
        scale[r0 + r] = 1.0
        for q in range(6):
            J[r0 + r, q] = cons[r, q]


@borrowing
def leg_rows(M, i, RW, fa, fp, J, scale):
    """Leg ``i``'s rows into ``J (rows, 6)`` and ``scale``: its actuation row at its index
    (active legs) and its constraint rows from ``TPL[i, T_CROW]``, at its frames ``fa``,
    ``fp`` whose context, twists, points and directions are in ``RW`` (:func:`leg_frames`,
    or a block's lane, ``_block.lane_frames_into``).  Returns ``(ok, structure_ok)``."""
    tpl = M[TPL][i]
    cons = RW[RW_CONS]
    k = tpl[T_K]
    ok = True
    structure = True
    if tpl[T_GENERIC]:
        ok = generic_members(M, i, RW, cons)
        put_constraints(cons, k, tpl[T_CROW], J, scale)
    elif k:
        # the groups' members straight into J (unit scales)
        ok = _template(M, i, RW, fa, J, scale, True, 0, SC_GROUPS) != 0.0
        structure = ok
        if not ok:            # the structure of home does not hold here: the generic rule
            ok = generic_members(M, i, RW, cons)
            put_constraints(cons, k, tpl[T_CROW], J, scale)
    arow = M[LEG][i, L_AROW]
    if arow >= 0:
        ok = actuation_row(M, i, RW, fa, J, scale, arow) and ok
    return ok, structure


@borrowing_inlined
def template_rows(M, i, RW, fa, fp, J, scale):
    """:func:`leg_rows` for a leg whose rows follow its template (groups, a line or no
    actuation): the common case, kept free of the calls of the general rules (a call site
    of a large kernel costs every call of its caller, taken or not); one pose, a block of
    one of :func:`._members.template_lanes`.  Returns ``(ok, structure_ok, done)``; not
    ``done`` where the leg needs :func:`leg_rows` (the generic rule, a least-norm actuation,
    or a group whose structure does not hold at this pose), which then writes all its rows
    again.  Its frames' context, twists, points and directions are in ``RW`` already (as for
    :func:`leg_rows`, which reads them unchanged)."""
    tpl = M[TPL][i]
    akind = tpl[T_AKIND]
    if tpl[T_GENERIC] or (akind != A_LINE and akind != A_NONE):
        return False, False, False
    status = _template(M, i, RW, fa, J, scale, True, 1, SC_STATUS)
    if status == NOT_DONE:
        return False, False, False
    return status == DONE, True, True
