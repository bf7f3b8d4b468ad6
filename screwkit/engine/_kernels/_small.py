"""Small dense linear algebra for one pose, compiled (private).

3-vectors and 3x3 matrices are written out component by component (no temporaries), and
the few small systems of a pose (a leg's Gram matrix, the reduced Newton system, the 6x6
statics) are solved by the textbook algorithms below: Cholesky with a floor on the pivots
(on a block's lanes, :func:`cholesky_lanes`; one system is one lane), LU with partial
pivoting.  Eigenvalues and singular values are in :mod:`._eigen`.
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, choose, inlined, inner, lanes, one_lane
from ._layout import BLOCK


@borrowing_inlined
def cross(a0, a1, a2, b0, b1, b2):
    """``a x b`` of two 3-vectors given by their components (a tuple of three)."""
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@borrowing
def matmul3(A, B, C):
    """``C = A @ B`` for 3x3 arrays (``C`` distinct from both)."""
    for i in range(3):
        a0, a1, a2 = A[i, 0], A[i, 1], A[i, 2]
        for j in range(3):
            C[i, j] = a0 * B[0, j] + a1 * B[1, j] + a2 * B[2, j]


@borrowing
def rodrigues(d0, d1, d2, angle, R):
    """``R = c I + s [d]x + (1 - c) d d^T``: the rotation by ``angle`` about the unit axis
    ``d``."""
    c, s = math.cos(angle), math.sin(angle)
    v = 1.0 - c
    R[0, 0] = d0 * d0 * v + c
    R[1, 1] = d1 * d1 * v + c
    R[2, 2] = d2 * d2 * v + c
    sym, skew = d0 * d1 * v, d2 * s
    R[0, 1] = sym - skew
    R[1, 0] = sym + skew
    sym, skew = d1 * d2 * v, d0 * s
    R[1, 2] = sym - skew
    R[2, 1] = sym + skew
    sym, skew = d2 * d0 * v, d1 * s
    R[2, 0] = sym - skew
    R[0, 2] = sym + skew


@borrowing
def rotation_vector(R, w0, w1, w2, c, s):
    """The rotation vector of ``R`` (angle in [0, pi]) from its antisymmetric part ``w =
    (R - R^T) / 2`` (axial), ``c = (tr R - 1) / 2`` and ``s = |w|`` (a lane loop of the
    closure errors computes these across the lanes, then calls this one lane at a time);
    ``R`` is read only near pi (``c < -0.9``)."""
    if c < -0.9:
        # near pi the antisymmetric part vanishes: the axis from the symmetric part
        kk = 0
        best = R[0, 0] - c
        for q in (1, 2):
            if R[q, q] - c > best:
                best, kk = R[q, q] - c, q
        x0 = 0.5 * (R[0, kk] + R[kk, 0])
        x1 = 0.5 * (R[1, kk] + R[kk, 1])
        x2 = 0.5 * (R[2, kk] + R[kk, 2])
        if kk == 0:
            x0 -= c
        elif kk == 1:
            x1 -= c
        else:
            x2 -= c
        nx = max(math.sqrt(x0 * x0 + x1 * x1 + x2 * x2), 1e-300)
        sign = -1.0 if x0 * w0 + x1 * w1 + x2 * w2 < 0 else 1.0
        f = sign * math.atan2(s, c) / nx
        return x0 * f, x1 * f, x2 * f
    f = 1.0 if s <= 1e-12 else math.atan2(s, c) / s
    return w0 * f, w1 * f, w2 * f


@inner
def cholesky_solve(G, n, B, nb, shift):
    """Solve ``(G + shift I) X = B`` in place (``B (>= n, >= nb)`` becomes ``X``) for the
    leading ``n x n`` block of a symmetric positive (semi-)definite ``G`` (lower triangle
    used and overwritten by the factor); pivots floored at 1e-300 (Tikhonov-regularised
    systems: the least-norm solution).  :func:`cholesky_lanes` on one lane."""
    S = np.empty((2, 1))                  # the shift and the lane's scratch
    S[0, 0] = shift
    cholesky_lanes(one_lane(G), n, one_lane(B), nb, S[0], S[1], 1, 1)


@inlined
def cholesky_lanes(G, n, X, nrhs, shift, acc, nb, ls):
    """:func:`cholesky_solve` on each of ``nb`` lanes (the lane axis last, of length ``ls``,
    a constant where this is inlined; each lane's operations those of one system, in the
    same order: the Newton step of a block, ``_newton.step_lanes``): ``(G + shift I) X = X`` for the
    leading ``n x n`` block of ``G (m, m, ls)`` (lower triangle overwritten by the factor,
    inverse pivots on the diagonal), ``X (m, w, ls)``'s first ``nrhs`` columns; ``shift
    (ls,)``, ``acc (ls,)`` scratch.  Pivots floored at 1e-300."""
    m, w = G.shape[1], X.shape[1]          # row lengths (G: (6, 7, ls) for the reduced system)
    g, x, shift, acc = lanes(G), lanes(X), lanes(shift), lanes(acc)
    for j in range(n):
        jj = (j * m + j) * ls
        for k in range(nb):
            acc[k] = g[jj + k] + shift[k]
        for q in range(j):
            jq = (j * m + q) * ls
            for k in range(nb):
                acc[k] -= g[jq + k] * g[jq + k]
        for k in range(nb):
            g[jj + k] = 1.0 / math.sqrt(max(acc[k], 1e-300))     # the inverse pivot, kept
        for i in range(j + 1, n):
            ij = (i * m + j) * ls
            for k in range(nb):
                acc[k] = g[ij + k]
            for q in range(j):
                iq, jq = (i * m + q) * ls, (j * m + q) * ls
                for k in range(nb):
                    acc[k] -= g[iq + k] * g[jq + k]
            for k in range(nb):
                g[ij + k] = acc[k] * g[jj + k]
    for c in range(nrhs):
        for i in range(n):
            ic, ii = (i * w + c) * ls, (i * m + i) * ls
            for k in range(nb):
                acc[k] = x[ic + k]
            for q in range(i):
                iq, qc = (i * m + q) * ls, (q * w + c) * ls
                for k in range(nb):
                    acc[k] -= g[iq + k] * x[qc + k]
            for k in range(nb):
                x[ic + k] = acc[k] * g[ii + k]
        for i in range(n - 1, -1, -1):
            ic, ii = (i * w + c) * ls, (i * m + i) * ls
            for k in range(nb):
                acc[k] = x[ic + k]
            for q in range(i + 1, n):
                qi, qc = (q * m + i) * ls, (q * w + c) * ls
                for k in range(nb):
                    acc[k] -= g[qi + k] * x[qc + k]
            for k in range(nb):
                x[ic + k] = acc[k] * g[ii + k]


@borrowing
def lu_factor(A, n, piv):
    """LU factors of ``A[:n, :n]`` in place, with partial pivoting (rows swapped as
    ``piv`` says); returns the sign of ``det A`` (0 for an exactly singular ``A``).
    :func:`lu_lanes` on one lane."""
    lu_lanes(one_lane(A), n, one_lane(piv), 1, 1)
    return lu_sign(one_lane(A), n, one_lane(piv), 0)


@borrowing
def lu_apply(A, n, piv, b):
    """Solve ``A x = b`` in place with the factors of :func:`lu_factor`.
    :func:`lu_apply_lanes` on one lane."""
    lu_apply_lanes(one_lane(A), n, one_lane(piv), one_lane(b), 1, 1)


@borrowing
def lu_block(A, n, piv, nb):
    """:func:`lu_lanes` on the ``nb`` lanes of a block (``A (m, m, BLOCK)``, ``piv (>= n,
    BLOCK)``), compiled once for the lane stride ``BLOCK``, as :func:`lu_factor` is once for
    one lane.  A function of its own, called rather than inlined, with its order ``n`` a
    run-time value: LLVM would otherwise unroll the loops over the rows and columns of a
    known order 6 around every lane loop, each copy vectorised with its checks and
    remainder (about 40 KiB of machine code that each kernel calling it compiles again:
    numba links a callee into every caller's module, where LLVM optimises and emits it once
    more)."""
    lu_lanes(A, n, piv, nb, BLOCK)


@borrowing
def lu_apply_block(A, n, piv, b, nb):
    """:func:`lu_apply_lanes` on the ``nb`` lanes of a block (``b (>= n, BLOCK)``), compiled
    once for the lane stride ``BLOCK`` (as :func:`lu_block`)."""
    lu_apply_lanes(A, n, piv, b, nb, BLOCK)


@borrowing_inlined
def lu_sign(A, n, piv, k):
    """The sign of ``det A`` of lane ``k`` from its factors (:func:`lu_lanes`): ``-1`` per
    interchange and per negative pivot, 0 at the first zero pivot (where the factorisation
    of that lane stopped)."""
    sign = 1.0
    for j in range(n):
        if piv[j, k] != j:
            sign = -sign
        if A[j, j, k] == 0.0:
            return 0.0
        if A[j, j, k] < 0.0:
            sign = -sign
    return sign


@inlined
def lu_lanes(A, n, piv, nb, ls):
    """LU factors with partial pivoting of ``A[:n, :n]`` of each of ``nb`` lanes in place
    (``A (m, m, ls)``, ``piv (>= n, ls)`` int; the lane axis last, of length ``ls``, a
    constant where this is inlined).  Each lane does the operations of the textbook
    algorithm for one matrix, in the same order: its own pivot (the first largest ``|A[i,
    j]|``, the same comparisons), the interchange of whole rows and the elimination by
    selects across the lanes.  A lane whose pivot is exactly zero stops there (its later
    ``piv`` entries -1, the rest of its ``A`` untouched): :func:`lu_sign` gives it 0.
    Inlined into :func:`lu_factor` (one lane) and :func:`lu_block` (``BLOCK`` lanes) only;
    one lane (``ls`` 1, ``nb`` 1) takes :func:`_lu_lane`, the same operations in the same
    order (``nb`` 0 does nothing)."""
    m = A.shape[1]
    a, pv = lanes(A), lanes(piv)
    if ls == 1:
        if nb == 1:
            _lu_lane(a, n, pv, m)
        return
    for j in range(n):
        jj = (j * m + j) * ls
        # each lane's pivot, its own comparisons in its order (the candidate rows in the outer
        # loop, the lanes inside, each against its best so far: a loop LLVM vectorises)
        for k in range(nb):
            pv[j * ls + k] = j
        for i in range(j + 1, n):
            ij = (i * m + j) * ls
            for k in range(nb):
                take = abs(a[ij + k]) > abs(a[(pv[j * ls + k] * m + j) * ls + k])
                pv[j * ls + k] = i if take else pv[j * ls + k]
        if j > 0:                         # a lane stopped at a zero pivot stays stopped
            q = ((j - 1) * m + j - 1) * ls
            for k in range(nb):
                live = (pv[(j - 1) * ls + k] >= 0) & (a[q + k] != 0.0)
                pv[j * ls + k] = pv[j * ls + k] if live else -1
        for i in range(j + 1, n):         # rows j and piv[j] interchanged (exact selects)
            hit = False                   # (a row no lane takes is left alone: one lane's
            for k in range(nb):           # LU swaps only where it pivots)
                hit |= pv[j * ls + k] == i
            if not hit:
                continue
            for c in range(n):
                jc, ic = (j * m + c) * ls, (i * m + c) * ls
                for k in range(nb):
                    s = pv[j * ls + k] == i
                    x, y = a[jc + k], a[ic + k]
                    a[jc + k] = y if s else x
                    a[ic + k] = x if s else y
        for i in range(j + 1, n):         # the elimination (f = A[i, j] / A[j, j] kept)
            ij = (i * m + j) * ls
            for k in range(nb):
                live = (pv[j * ls + k] >= 0) & (a[jj + k] != 0.0)
                f = a[ij + k] * (1.0 / a[jj + k])
                a[ij + k] = f if live else a[ij + k]
            for c in range(j + 1, n):
                ic, jc = (i * m + c) * ls, (j * m + c) * ls
                for k in range(nb):
                    live = (pv[j * ls + k] >= 0) & (a[jj + k] != 0.0)
                    x = a[ic + k]
                    a[ic + k] = x - a[ij + k] * a[jc + k] if live else x


@inlined
def _lu_lane(a, n, pv, m):
    """:func:`lu_lanes` of one lane (``a``, ``pv`` its flat ``A (m, m)`` and ``piv``): each
    comparison, interchange, multiplier ``a[i, j] * (1 / a[j, j])`` and update of the lanes'
    loops, in their order (the same bits, but for the sign of a NaN entry, which LLVM
    chooses: the block's vector and scalar lanes differ in it too;
    ``tests/test_kernels_lanes.py``), with the pivot's row and largest value, its
    reciprocal and whether the factorisation goes on held in registers across the row
    loops (the pivot's search by selects: a branch there is a coin toss for random
    matrices), the interchange and the elimination by branches.  The lanes' form, compiled
    for one lane, reloads them at every update (a store to ``a`` may alias them for all
    LLVM knows): some 1.6-1.8x the time of this form for a 6x6 matrix (best of alternated
    rounds, about 250 ns against 150 ns).  The one-lane factorisations are a pose's
    statics solved alone and, in a map, the orientation of each leg of each cell
    (``_orient``)."""
    for j in range(n):
        best, top = j, abs(a[j * m + j])
        for i in range(j + 1, n):
            v = abs(a[i * m + j])
            take = v > top                # (the lanes' comparison: top is |a[best, j]|)
            best, top = choose(take, i, best), choose(take, v, top)
        if j > 0 and not (pv[j - 1] >= 0 and a[(j - 1) * m + j - 1] != 0.0):
            best = -1                     # stopped at an earlier zero pivot: stays stopped
        pv[j] = best
        if best > j:
            for c in range(n):
                x, y = a[j * m + c], a[best * m + c]
                a[j * m + c] = y
                a[best * m + c] = x
        jj = j * m + j
        if best >= 0 and a[jj] != 0.0:
            inv = 1.0 / a[jj]
            for i in range(j + 1, n):
                f = a[i * m + j] * inv
                a[i * m + j] = f
                for c in range(j + 1, n):
                    a[i * m + c] = a[i * m + c] - f * a[j * m + c]


@inlined
def lu_apply_lanes(A, n, piv, b, nb, ls):
    """Solve ``A x = b`` in place on each of ``nb`` lanes with the factors of
    :func:`lu_lanes` (``b (>= n, ls)``), each lane's operations those of one system in the
    same order (the interchanges by selects).  Inlined into :func:`lu_apply` (one lane) and
    :func:`lu_apply_block` (``BLOCK`` lanes) only."""
    m = A.shape[1]
    a, pv, x = lanes(A), lanes(piv), lanes(b)
    for j in range(n):                    # the row interchanges, in order
        for i in range(j + 1, n):
            hit = False
            for k in range(nb):
                hit |= pv[j * ls + k] == i
            if not hit:
                continue
            for k in range(nb):
                s = pv[j * ls + k] == i
                u, v = x[j * ls + k], x[i * ls + k]
                x[j * ls + k] = v if s else u
                x[i * ls + k] = u if s else v
    for i in range(1, n):
        for q in range(i):
            iq = (i * m + q) * ls
            for k in range(nb):
                x[i * ls + k] -= a[iq + k] * x[q * ls + k]
    for i in range(n - 1, -1, -1):
        for q in range(i + 1, n):
            iq = (i * m + q) * ls
            for k in range(nb):
                x[i * ls + k] -= a[iq + k] * x[q * ls + k]
        ii = (i * m + i) * ls
        for k in range(nb):
            x[i * ls + k] = x[i * ls + k] / a[ii + k]
