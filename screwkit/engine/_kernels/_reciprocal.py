"""The twists reciprocal to all rows but one, compiled (private).

For the transmission and constraint indices (:mod:`screwkit.engine._kernels._indices`;
definitions in :mod:`screwkit.engine._transmission`): the unit rows ``Wu (K, 6)`` of a pose
in normalised coordinates, and per row ``k`` the unit twist reciprocal to every row but
``k``, the column ``k`` of the pseudo-inverse of ``Wu``.  Six rows that are not exactly
singular: the columns of the inverse, by LU factors (a block's poses at once, one lane
each, :func:`inverse_lanes`); otherwise a one-sided Jacobi SVD (:func:`null_twists`), which
also finds the redundant rows (no such twist) at :data:`~._layout.RANK_RTOL` and
:data:`~._layout.LEVERAGE_RTOL`.
"""

import math

from ._eigen import jacobi_rows
from ._jit import borrowing, borrowing_inlined
from ._layout import LEVERAGE_RTOL, RANK_RTOL
from ._small import lu_apply_block, lu_block


@borrowing
def svd_rows(A, k, B, Q, s, order):
    """One-sided Jacobi of ``A[:k] (k, 6)``: ``A = Q diag(s) Vt`` with the rows of ``Vt``
    ``B[j] / s_j``; ``order[:g]`` the ``g = min(k, 6)`` largest ``s`` descending.  Returns
    ``g``."""
    for i in range(k):
        for c in range(6):
            B[i, c] = A[i, c]
    jacobi_rows(B, k, Q, True)
    for i in range(k):
        t = 0.0
        for c in range(6):
            t += B[i, c] * B[i, c]
        s[i] = math.sqrt(t)
    g = min(k, 6)
    for q in range(g):
        best = -1.0
        bi = 0
        for i in range(k):
            seen = False
            for r in range(q):
                if order[r] == i:
                    seen = True
            if not seen and s[i] > best:
                best, bi = s[i], i
        order[q] = bi
    return g


@borrowing
def leverage_redundant(Q, s, order, g, k, out):
    """``out[:k]``: True where a row's leverage over the directions of rank (``s`` above
    ``RANK_RTOL`` of the largest) is below ``1 - LEVERAGE_RTOL``."""
    top = max(s[order[0]], 1e-300)
    for r in range(k):
        lev = 0.0
        for q in range(g):
            j = order[q]
            if s[j] > RANK_RTOL * top:
                lev += Q[r, j] * Q[r, j]
        out[r] = 1.0 - lev > LEVERAGE_RTOL


@borrowing_inlined
def unit_rows(J, keep, p, c0, c1, c2, L, Wn, Wu):
    """``Wn[:K]``: the rows ``keep`` of pose ``p`` about the centroid ``c``, moments over
    ``L``; ``Wu[:K]`` the same rows unit."""
    for r in range(keep.shape[0]):
        row = J[p, keep[r]]
        f0, f1, f2 = row[0], row[1], row[2]
        Wn[r, 0], Wn[r, 1], Wn[r, 2] = f0, f1, f2
        Wn[r, 3] = (row[3] - (c1 * f2 - c2 * f1)) / L
        Wn[r, 4] = (row[4] - (c2 * f0 - c0 * f2)) / L
        Wn[r, 5] = (row[5] - (c0 * f1 - c1 * f0)) / L
        t = 0.0
        for c in range(6):
            t += Wn[r, c] * Wn[r, c]
        t = math.sqrt(t)
        t = t if t > 0 else 1.0
        for c in range(6):
            Wu[r, c] = Wn[r, c] / t


@borrowing
def inverse_lanes(J, keep, centre, length, p0, nb, Wn, Wu, Lw, piv):
    """:func:`null_twists`' square case on the ``nb`` poses from ``p0`` at once, one lane
    each: the unit rows of each pose factored (``Lw[0] (6, 6, BLOCK)``, ``piv (6, BLOCK)``)
    and the columns of their inverses, unit, in ``Lw[2] (6, 6, BLOCK)`` (row ``k``: column
    ``k``).  Each lane's operations are those of the one-pose factors and solves
    (:func:`~screwkit.engine._kernels._small.lu_block`), in lanes the compiler vectorises;
    a lane whose factorisation stopped (:func:`~screwkit.engine._kernels._small.lu_sign`
    0: exactly singular) is left to :func:`null_twists`."""
    A, col, V = Lw
    for k in range(nb):
        p = p0 + k
        unit_rows(J, keep, p, centre[p, 0], centre[p, 1], centre[p, 2], length[p], Wn, Wu)
        for r in range(6):
            for c in range(6):
                A[r, c, k] = Wu[r, c]
    lu_block(A, 6, piv, nb)
    for kk in range(6):
        for c in range(6):
            for k in range(nb):
                col[c, k] = 1.0 if c == kk else 0.0
        lu_apply_block(A, 6, piv, col, nb)
        for k in range(nb):
            nrm = 0.0
            for c in range(6):
                nrm += col[c, k] * col[c, k]
            nrm = max(math.sqrt(nrm), 1e-300)
            for c in range(6):
                V[kk, c, k] = col[c, k] / nrm


@borrowing
def null_twists(Wu, K, Vn, none, B, Q, s, order):
    """Row ``k`` of ``Vn[:K]``: the unit twist (normalised coordinates) reciprocal to every
    row of ``Wu[:K]`` but ``k`` (the column ``k`` of the pseudo-inverse, by one-sided
    Jacobi); ``none[k]``: the row is redundant (no such twist).  Fewer than 6 rows: zeros.
    Six rows reach it only where :func:`inverse_lanes` found them exactly singular."""
    for r in range(K):
        none[r] = False
        for c in range(6):
            Vn[r, c] = 0.0
    if K < 6:
        return
    g = svd_rows(Wu, K, B, Q, s, order)
    top = max(s[order[0]], 1e-300)
    for r in range(K):
        nrm = 0.0
        for c in range(6):
            t = 0.0
            for q in range(g):
                j = order[q]
                sj = max(s[j], 1e-300 * top)
                t += Q[r, j] * B[j, c] / (sj * sj)
            Vn[r, c] = t
            nrm += t * t
        nrm = max(math.sqrt(nrm), 1e-300)
        for c in range(6):
            Vn[r, c] /= nrm
    leverage_redundant(Q, s, order, g, K, none)
