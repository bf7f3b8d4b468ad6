"""Eigenvalues and singular values of small matrices, compiled (private).

The conditioning's singular values come from the eigenvalues of the smaller Gram matrix
(Householder reduction to tridiagonal form, then the root-free QL iteration) where the
condition is moderate, and from one-sided Jacobi (high relative accuracy, so the condition
number keeps its digits up to the singular threshold without a second method) beyond;
one-sided Jacobi also gives the statics' pseudo-inverse and the indices' columns.

The Gram matrices and their eigenvalues are computed for the lanes of a block at once (the
lane axis last, ``ls`` apart: :func:`~._jit.lanes`), one pose being a block of one.  The QL
iteration runs the lanes in step: the eigenvalues are deflated from the first row down,
``d[t]`` by QL steps on rows ``t..n-1`` (Wilkinson's shift from the 2x2 at ``t``) until
``e[t]`` is negligible, the last 2x2 block solved directly.  A step is taken by every lane
whose ``e[t]`` is not yet negligible (its own test), the others left as they are (selects),
until none is left: every lane performs exactly the operations of its matrix alone, in the
same order, and a block gives the bits of its poses one at a time.  No lane splits its
matrix where an inner ``e[m]`` is negligible: the step passes through it (the rotation there
is the identity to rounding, and the rows above start the step afresh from ``d[m]``), so
the lanes share one range of rows, the shifts and rotations are branch-free lane loops
(vectorised), and nothing is decided lane by lane but whether to take the step.
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, lanes

#: Largest one-sided Jacobi sweeps (6x6 converges in 5 to 7).
JACOBI_SWEEPS = 30
#: Two rows count as orthogonal when their cosine is below this.
JACOBI_TOL = 1e-15
#: Below this condition number the singular values come from the Gram matrix's eigenvalues
#: (``s_k`` to about ``eps cond^2 / 2`` relative: 5e-12 at 300), beyond by Jacobi.
REFINE_GRAM = 300.0
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
def jacobi_rows(U, m, V, want_v):
    """One-sided Jacobi on the ``m`` rows of ``U (m, 6)``: rotates them (in place) until
    they are mutually orthogonal; their norms are then the singular values.  With
    ``want_v`` the rotations are accumulated in ``V (m, m)`` (``U_final = V^T U``).  A row
    whose squared norm is at most ``eps^2`` times the sum of all squared norms (the squared
    Frobenius norm, which rotations keep) is left alone: it is rounding noise, and rotating
    it against the others would change them by some ``eps^2 |U|`` while it shrinks towards
    the underflow (a rank-deficient ``U``, or more rows than columns, took all
    :data:`JACOBI_SWEEPS` that way).  Returns the number of sweeps."""
    if want_v:
        for i in range(m):
            for j in range(m):
                V[i, j] = 1.0 if i == j else 0.0
    tiny = 0.0
    for i in range(m):
        for k in range(6):
            tiny += U[i, k] * U[i, k]
    tiny *= EPS2
    for sweep in range(JACOBI_SWEEPS):
        rotated = False
        for i in range(m - 1):
            for j in range(i + 1, m):
                a = 0.0
                b = 0.0
                g = 0.0
                for k in range(6):
                    a += U[i, k] * U[i, k]
                    b += U[j, k] * U[j, k]
                    g += U[i, k] * U[j, k]
                if g == 0.0 or a <= tiny or b <= tiny or abs(g) <= JACOBI_TOL * math.sqrt(a * b):
                    continue
                rotated = True
                zeta = (b - a) / (2.0 * g)
                t = (1.0 if zeta >= 0 else -1.0) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                c = 1.0 / math.sqrt(1.0 + t * t)
                s = c * t
                for k in range(6):
                    x, y = U[i, k], U[j, k]
                    U[i, k] = c * x - s * y
                    U[j, k] = s * x + c * y
                if want_v:
                    for k in range(m):
                        x, y = V[k, i], V[k, j]
                        V[k, i] = c * x - s * y
                        V[k, j] = s * x + c * y
        if not rotated:
            return sweep + 1
    return JACOBI_SWEEPS


@borrowing
def singular_values_lanes(J, r0, m, U, s, k, e, S, I, R, nb, ls):
    """The ``k = min(m, 6)`` largest singular values of the rows ``J[r0:r0+m] (m, 6, ls)`` of
    each lane ``0..nb-1``, descending, into ``s[:k] (>= k, ls)`` (NaN beyond).  From the
    eigenvalues of the smaller Gram matrix where the condition ``s_1 / s_k`` is below
    :data:`REFINE_GRAM` (they give ``s_k`` to about ``eps cond^2 / 2`` relative), else (lane by
    lane) by one-sided Jacobi (high relative accuracy).  Scratch: ``U (6, 6, ls)`` the Gram
    matrices, ``e, S (6, ls)``, ``I (>= 1, ls)`` (int), ``R (>= max(m, 6), 6)`` one lane's rows; NaN
    singular values for a lane whose Gram matrix is not finite."""
    g = min(m, 6)
    if g == 0:
        for q in range(s.shape[0]):
            for l in range(nb):
                s[q, l] = np.nan
        return
    u, j = lanes(U), lanes(J)
    us = U.shape[1] * ls
    js = J.shape[1] * ls
    for a in range(g):
        for b in range(a + 1):
            o = a * us + b * ls
            for l in range(nb):
                u[o + l] = 0.0
            if m < 6:                      # J J^T
                for c in range(6):
                    pa, pb = (r0 + a) * js + c * ls, (r0 + b) * js + c * ls
                    for l in range(nb):
                        u[o + l] += j[pa + l] * j[pb + l]
            else:                          # J^T J
                for r in range(m):
                    pa, pb = (r0 + r) * js + a * ls, (r0 + r) * js + b * ls
                    for l in range(nb):
                        u[o + l] += j[pa + l] * j[pb + l]
    # a lane with a non-finite Gram matrix: NaN singular values (its matrix zero for the
    # iteration, which would otherwise run to its limit of steps on NaN).  Lane loops of
    # arithmetic (vectorised): an entry times 0 is NaN exactly where it is not finite, so
    # a lane's sum of them is 0 where every entry is finite
    bad, acc = I[0], e[0]                  # (e: free until the iteration)
    _non_finite(U, g, acc, bad, nb)
    symmetric_eigenvalues_lanes(U, g, s, e, S, nb, ls)
    for q in range(g):
        for l in range(nb):
            s[q, l] = math.sqrt(max(s[q, l], 0.0))
    # descending: a selection sort's exchanges (g <= 6), each a select on every lane
    for q in range(g):
        for r in range(q + 1, g):
            for l in range(nb):
                hi, lo = s[r, l], s[q, l]
                up = hi > lo
                s[q, l] = hi if up else lo
                s[r, l] = lo if up else hi
    for l in range(nb):
        if bad[l]:
            for q in range(s.shape[0]):
                s[q, l] = np.nan
            continue
        if not s[g - 1, l] * REFINE_GRAM > s[0, l]:
            for i in range(m):
                for c in range(6):
                    R[i, c] = J[r0 + i, c, l]
            jacobi_rows(R, m, R, False)
            for i in range(m):
                t = 0.0
                for c in range(6):
                    t += R[i, c] * R[i, c]
                R[i, 0] = math.sqrt(t)
            for q in range(k):             # the k largest norms, descending
                best = -1.0
                bi = 0
                for i in range(m):
                    if R[i, 0] > best:
                        best, bi = R[i, 0], i
                s[q, l] = best
                R[bi, 0] = -2.0
        for q in range(k, s.shape[0]):
            s[q, l] = np.nan


@borrowing_inlined
def _non_finite(U, g, acc, bad, nb):
    """``bad[l]`` 1 where lane ``l``'s lower triangle of ``U[:g, :g]`` holds a NaN or an
    infinity (that triangle then zero), else 0; ``acc`` scratch."""
    for l in range(nb):
        acc[l] = 0.0
    for a in range(g):
        for b in range(a + 1):
            for l in range(nb):
                acc[l] += U[a, b, l] * 0.0
    for l in range(nb):
        bad[l] = 0 if acc[l] == 0.0 else 1
    for a in range(g):
        for b in range(a + 1):
            for l in range(nb):
                U[a, b, l] = U[a, b, l] if bad[l] == 0 else 0.0


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
        for k in range(nb):
            h = sc[H + k]
            skip = h <= 1e-250
            f = a[ai + lm * ls + k]
            g = -math.sqrt(h) if f >= 0.0 else math.sqrt(h)
            ee[i * ls + k] = f if skip else g
            h -= f * g
            a[ai + lm * ls + k] = f if skip else f - g
            sc[HI + k] = 1.0 / h
            sc[SK + k] = 1.0 if skip else 0.0
            sc[F + k] = 0.0
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
            for q in range(j + 1):
                for k in range(nb):
                    old = a[j * nn + q * ls + k]
                    new = old - (sc[F + k] * ee[q * ls + k] + sc[H + k] * a[ai + q * ls + k])
                    a[j * nn + q * ls + k] = old if sc[SK + k] != 0.0 else new
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
        ee[t * ls + k] = e_t if on else ee[t * ls + k]
        dd[t * ls + k] = d_t if on else dd[t * ls + k]


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
        p = sc[P + k]
        s = sc[SS + k]
        c = sc[C + k]
        gamma = sc[GAM + k]
        sigma = sc[SIG + k]
        bb = ee[i * ls + k]
        r = p + bb
        up = ee[(i + 1) * ls + k]
        ee[(i + 1) * ls + k] = s * r if on & (i != m - 1) else up
        alpha = dd[i * ls + k]
        gt = p * (alpha - sigma) - bb * gamma     # the new gamma times r
        rp = r * p
        inv = 1.0 / rp
        ir = p * inv                              # 1 / r
        nz = rp != 0.0                            # else c = 0
        c1 = p * ir if nz else 0.0
        s1 = bb * ir if nz else 1.0
        ng = gt * ir if nz else -gamma
        p1 = gt * gt * inv if nz else c * bb      # gamma^2 / c
        dn = dd[(i + 1) * ls + k]
        dd[(i + 1) * ls + k] = gamma + (alpha - ng) if on else dn
        sc[C + k] = c1 if on else c
        sc[SS + k] = s1 if on else s
        sc[P + k] = p1 if on else p
        sc[GAM + k] = ng if on else gamma
