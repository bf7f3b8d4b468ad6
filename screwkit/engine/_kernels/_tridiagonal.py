"""The eigenvalues of small symmetric matrices on the lanes of a block, compiled (private).

Householder reduction to tridiagonal form, then the root-free implicit QL iteration
(Pal-Walker-Kahan, as LAPACK's ``dsterf``), for the lanes of a block at once (the lane axis
last, ``ls`` apart: :func:`~._jit.lanes`), one pose being a block of one
(:func:`symmetric_eigenvalues_lanes`; the conditioning's Gram matrices,
:func:`._eigen.singular_values_lanes`).

The QL iteration runs the lanes in step: the eigenvalues are deflated from the first row
down, ``d[t]`` by QL steps on rows ``t..n-1`` (Wilkinson's shift from the 2x2 at ``t``) until
``e[t]`` is negligible, the last 2x2 block solved directly.  A step is taken by every lane
whose ``e[t]`` is not yet negligible (its own test), the others left as they are (selects),
until none is left: every lane performs exactly the operations of its matrix alone, in the
same order, and a block gives the bits of its poses one at a time.  No lane splits its
matrix where an inner ``e[m]`` is negligible: the step passes through it (the rotation there
is the identity to rounding, and the rows above start the step afresh from ``d[m]``), so
the lanes share one range of rows, the shifts and rotations are branch-free lane loops
(vectorised), and nothing is decided lane by lane but whether to take the step.

Where every lane of the block takes a step (most steps: a lane rarely converges in fewer
than two), its rows are rotated without the selects (:func:`_rotation_row_all`); where no
lane skips a Householder row (all but rank-deficient Gram matrices), the update of the rows
above it has none either.  A select stored where its other value was loaded becomes a
masked store (LLVM's combine of a store of a select with a load of the same address), which
costs several cycles more than a store on AMD's Zen processors; the lanes' values are the
same either way.  The selects are :func:`~._jit.choose`'s: numba's conditional expressions
are branches, which kept some lane loops scalar.
"""

import math

from ._jit import borrowing, borrowing_inlined, choose, lanes

#: The square of the unit roundoff (the QL's convergence test on squared off-diagonals).
EPS2 = 2.220446049250313e-16 ** 2
#: The most QL steps a lane takes to deflate one eigenvalue (two or three, as a rule).
QL_STEPS = 60
#: The lanes still iterating finish their QL steps alone once at most one in this many.
QL_ALONE_SHARE = 8
#: The rows of the QL's lane scratch ``S``: a lane's shift, gamma, p, c and s of its step, and
#: whether it takes the step (1.0) or not, in units of the lane stride.
_SIG, _GAM, _P, _C, _SS, _ON = 0, 1, 2, 3, 4, 5


@borrowing
def symmetric_eigenvalues_lanes(A, n, d, e, S, nb, ls):
    """The eigenvalues of the symmetric ``A[:n, :n] (>= n, >= n, ls)`` of each lane ``0..nb-1``
    (its lower triangle read, overwritten; entries of order one, as in a Gram matrix of unit
    rows) into ``d[:n] (>= n, ls)``, in no order: Householder reduction to tridiagonal form,
    then the root-free implicit QL iteration (Pal-Walker-Kahan), the eigenvalues deflated
    from the first row down, the last 2x2 block solved directly; each lane exactly as alone
    (module docstring).  Scratch ``e, S (>= 6, ls)``.  About ``eps |A|`` absolute accuracy."""
    a, dd, ee, sc = lanes(A), lanes(d), lanes(e), lanes(S)
    nn = A.shape[1] * ls
    # the rows of S: Householder's h, f, hh, 1 / h and skip; QL's shift, gamma, p, c and s
    H, F, G, HI, SK = 0, ls, 2 * ls, 3 * ls, 4 * ls
    # Householder from the last row up (no scaling of the rows: the entries are of order one,
    # the Gram matrices of unit rows; a row whose part left of the diagonal is below 1e-125
    # is taken as reduced, so that 1 / h cannot overflow: that lane's update is not kept)
    for i in range(n - 1, 0, -1):
        lm = i - 1
        ai = i * nn
        if lm == 0:
            for k in range(nb):
                ee[i * ls + k] = a[ai + k]
            continue
        for k in range(nb):
            sc[H + k] = 0.0
        for q in range(lm + 1):
            for k in range(nb):
                x = a[ai + q * ls + k]
                sc[H + k] += x * x
        # (the square roots and the divisions in loops of their own, the selects in one with
        # neither: together, LLVM's cost model kept the loop scalar, a lane at a time)
        for k in range(nb):
            sc[G + k] = math.sqrt(sc[H + k])
        for k in range(nb):
            h = sc[H + k]
            skip = h <= 1e-250
            f = a[ai + lm * ls + k]
            root = sc[G + k]
            g = choose(f >= 0.0, -root, root)
            ee[i * ls + k] = choose(skip, f, g)
            h -= f * g
            a[ai + lm * ls + k] = choose(skip, f, f - g)
            sc[HI + k] = h
            sc[SK + k] = choose(skip, 1.0, 0.0)
            sc[F + k] = 0.0
        skips = 0.0
        for k in range(nb):
            sc[HI + k] = 1.0 / sc[HI + k]
            skips += sc[SK + k]
        for j in range(lm + 1):
            for k in range(nb):
                sc[G + k] = 0.0
            for q in range(j + 1):
                for k in range(nb):
                    sc[G + k] += a[j * nn + q * ls + k] * a[ai + q * ls + k]
            for q in range(j + 1, lm + 1):
                for k in range(nb):
                    sc[G + k] += a[q * nn + j * ls + k] * a[ai + q * ls + k]
            for k in range(nb):
                ej = sc[G + k] * sc[HI + k]
                ee[j * ls + k] = ej
                sc[F + k] += ej * a[ai + j * ls + k]
        for k in range(nb):
            sc[G + k] = 0.5 * sc[F + k] * sc[HI + k]          # hh
        for j in range(lm + 1):
            for k in range(nb):
                f = a[ai + j * ls + k]
                g = ee[j * ls + k] - sc[G + k] * f
                ee[j * ls + k] = g
                sc[F + k] = f                                 # (row j's f and g, read below)
                sc[H + k] = g
            if skips:                   # (a skipped lane keeps its rows: a select)
                for q in range(j + 1):
                    for k in range(nb):
                        old = a[j * nn + q * ls + k]
                        new = old - (sc[F + k] * ee[q * ls + k] + sc[H + k] * a[ai + q * ls + k])
                        a[j * nn + q * ls + k] = choose(sc[SK + k] != 0.0, old, new)
            else:                       # (every lane updates: no select, no masked store)
                for q in range(j + 1):
                    for k in range(nb):
                        old = a[j * nn + q * ls + k]
                        a[j * nn + q * ls + k] = old - (sc[F + k] * ee[q * ls + k]
                                                        + sc[H + k] * a[ai + q * ls + k])
    for i in range(n):
        for k in range(nb):
            dd[i * ls + k] = a[i * nn + i * ls + k]
    # root-free implicit QL (Pal-Walker-Kahan, as LAPACK's dsterf): the iteration runs on the
    # squares of the off-diagonal, so a rotation needs no square root; and with
    # ``gamma' r = p (alpha - sigma) - b^2 gamma`` one division by ``r p`` gives ``1 / r``,
    # ``gamma'`` and ``p' = gamma'^2 / c`` alike (one division a rotation, not a square root
    # and two)
    for i in range(1, n):
        for k in range(nb):
            x = ee[i * ls + k]
            ee[(i - 1) * ls + k] = x * x
    for k in range(nb):
        ee[(n - 1) * ls + k] = 0.0
    # the lanes in step (module docstring): d[t] deflated by QL steps on rows t..n-1, each
    # step taken by the lanes whose e[t] is not yet negligible, the others left as they are
    ON = _ON * ls
    for t in range(n - 2):
        for step in range(QL_STEPS):
            active = 0
            for k in range(nb):          # |e_t| > eps (|d_t| + |d_t+1|), squared
                x = abs(dd[t * ls + k]) + abs(dd[(t + 1) * ls + k])
                on = ee[t * ls + k] > EPS2 * x * x
                sc[ON + k] = 1.0 if on else 0.0
                active += 1 if on else 0
            if active == 0:
                break
            if active * QL_ALONE_SHARE <= nb:
                # the few lanes left finish alone: the same steps, the same bits, without
                # a whole block's rotations for each
                for k in range(nb):
                    if sc[ON + k] != 0.0:
                        _lane_alone(S, e, d, t, n, k, step, ls)
                break
            _shift_lanes(S, e, d, t, n - 1, 0, nb, ls)
            if active == nb:             # (every lane rotates: no selects)
                for i in range(n - 2, t - 1, -1):
                    _rotation_row_all(S, e, d, i, n - 1, nb, ls)
                _step_end_all(S, e, d, t, nb, ls)
            else:
                for i in range(n - 2, t - 1, -1):
                    _rotation_row(S, e, d, i, n - 1, 0, nb, ls)
                _step_end(S, e, d, t, 0, nb, ls)
    if n >= 2:                           # the 2x2 block left: its eigenvalues directly
        _last_pair(e, d, n - 2, nb, ls)


@borrowing
def _lane_alone(S, e, d, t, n, k, step, ls):
    """Lane ``k``'s QL steps at row ``t`` from step ``step`` on, alone, as the lanes in step."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    for _ in range(step, QL_STEPS):
        x = abs(dd[t * ls + k]) + abs(dd[(t + 1) * ls + k])
        if not ee[t * ls + k] > EPS2 * x * x:
            return
        sc[_ON * ls + k] = 1.0
        _shift_lanes(S, e, d, t, n - 1, k, k + 1, ls)
        for i in range(n - 2, t - 1, -1):
            _rotation_row(S, e, d, i, n - 1, k, k + 1, ls)
        _step_end(S, e, d, t, k, k + 1, ls)


@borrowing_inlined
def _shift_lanes(S, e, d, t, m, k0, k1, ls):
    """Wilkinson's shift of each lane (the eigenvalue of its leading 2x2 at ``t`` nearer
    ``d[t]``) and the start of its step at row ``m`` (gamma, p, c, s into ``S``)."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    SIG, GAM, P, C, SS = _SIG * ls, _GAM * ls, _P * ls, _C * ls, _SS * ls
    for k in range(k0, k1):
        g = 0.5 * (dd[(t + 1) * ls + k] - dd[t * ls + k])
        el = ee[t * ls + k]
        r = math.sqrt(g * g + el)
        sigma = dd[t * ls + k] - el / (g + (r if g >= 0.0 else -r))
        gamma = dd[m * ls + k] - sigma
        sc[SIG + k] = sigma
        sc[GAM + k] = gamma
        sc[P + k] = gamma * gamma
        sc[C + k] = 1.0
        sc[SS + k] = 0.0


@borrowing_inlined
def _step_end(S, e, d, t, k0, k1, ls):
    """The end of a QL step at row ``t`` (the lanes that took it)."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    SIG, GAM, P, SS, ON = _SIG * ls, _GAM * ls, _P * ls, _SS * ls, _ON * ls
    for k in range(k0, k1):
        on = sc[ON + k] != 0.0
        e_t = sc[SS + k] * sc[P + k]
        d_t = sc[SIG + k] + sc[GAM + k]
        ee[t * ls + k] = choose(on, e_t, ee[t * ls + k])
        dd[t * ls + k] = choose(on, d_t, dd[t * ls + k])


@borrowing_inlined
def _last_pair(e, d, lo, nb, ls):
    """The eigenvalues of each lane's 2x2 block at ``lo`` (rows ``lo, lo + 1``), directly."""
    ee, dd = lanes(e), lanes(d)
    for k in range(nb):
        x, z = dd[lo * ls + k], dd[(lo + 1) * ls + k]
        b2 = ee[lo * ls + k]
        sm = x + z
        rt = math.sqrt((x - z) * (x - z) + 4.0 * b2)
        r1 = 0.5 * (sm + rt) if sm >= 0.0 else 0.5 * (sm - rt)
        dd[lo * ls + k] = r1
        # the smaller without cancellation
        dd[(lo + 1) * ls + k] = (x * z - b2) / r1 if r1 != 0.0 else 0.0
        ee[lo * ls + k] = 0.0


@borrowing_inlined
def _rotation(p, c, gamma, sigma, bb, alpha):
    """One lane's rotation of a QL step at a row (root-free: ``p``, ``c`` and ``gamma`` of the
    step so far, the shift ``sigma``, the row's squared off-diagonal ``bb`` and diagonal
    ``alpha``): ``(r, gamma', c', s', p')``, ``r`` the new squared off-diagonal over ``s``
    (:func:`symmetric_eigenvalues_lanes`)."""
    r = p + bb
    gt = p * (alpha - sigma) - bb * gamma         # the new gamma times r
    rp = r * p
    inv = 1.0 / rp
    ir = p * inv                                  # 1 / r
    nz = rp != 0.0                                # else c = 0
    return (r, choose(nz, gt * ir, -gamma), choose(nz, p * ir, 0.0), choose(nz, bb * ir, 1.0),
            choose(nz, gt * gt * inv, c * bb))    # (p' = gamma'^2 / c)


@borrowing_inlined
def _rotation_row(S, e, d, i, m, k0, k1, ls):
    """Row ``i`` of a QL step's rotations (the step from row ``m`` up), across the lanes
    ``0..nb-1`` (through :func:`~._jit.lanes`): a lane taking the step (``S``'s row ``_ON``)
    rotates, the others keep their values (selects, no branch).  A function of its
    own: written inline, the loop's temporaries outlived it in the caller's loops (Python's
    scoping) and LLVM left it scalar ("value ... used outside the loop"); alone it vectorises
    (packed divisions)."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    SIG, GAM, P, C, SS, ON = _SIG * ls, _GAM * ls, _P * ls, _C * ls, _SS * ls, _ON * ls
    for k in range(k0, k1):
        on = sc[ON + k] != 0.0
        p, s, c, gamma = sc[P + k], sc[SS + k], sc[C + k], sc[GAM + k]
        alpha = dd[i * ls + k]
        r, ng, c1, s1, p1 = _rotation(p, c, gamma, sc[SIG + k], ee[i * ls + k], alpha)
        ee[(i + 1) * ls + k] = choose(on & (i != m - 1), s * r, ee[(i + 1) * ls + k])
        dd[(i + 1) * ls + k] = choose(on, gamma + (alpha - ng), dd[(i + 1) * ls + k])
        sc[C + k] = choose(on, c1, c)
        sc[SS + k] = choose(on, s1, s)
        sc[P + k] = choose(on, p1, p)
        sc[GAM + k] = choose(on, ng, gamma)


@borrowing_inlined
def _step_end_all(S, e, d, t, nb, ls):
    """:func:`_step_end` where every lane ``0..nb-1`` took the step (no selects)."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    SIG, GAM, P, SS = _SIG * ls, _GAM * ls, _P * ls, _SS * ls
    for k in range(nb):
        ee[t * ls + k] = sc[SS + k] * sc[P + k]
        dd[t * ls + k] = sc[SIG + k] + sc[GAM + k]


@borrowing_inlined
def _rotation_row_all(S, e, d, i, m, nb, ls):
    """:func:`_rotation_row` where every lane ``0..nb-1`` takes the step: the same rotations
    without the selects between a lane's new and old values (each would become a masked
    store: module docstring)."""
    sc, ee, dd = lanes(S), lanes(e), lanes(d)
    SIG, GAM, P, C, SS = _SIG * ls, _GAM * ls, _P * ls, _C * ls, _SS * ls
    first = i == m - 1                            # (e[m] is left as it is)
    for k in range(nb):
        gamma, alpha = sc[GAM + k], dd[i * ls + k]
        r, ng, c1, s1, p1 = _rotation(sc[P + k], sc[C + k], gamma, sc[SIG + k],
                                      ee[i * ls + k], alpha)
        if not first:
            ee[(i + 1) * ls + k] = sc[SS + k] * r
        dd[(i + 1) * ls + k] = gamma + (alpha - ng)
        sc[C + k] = c1
        sc[SS + k] = s1
        sc[P + k] = p1
        sc[GAM + k] = ng
