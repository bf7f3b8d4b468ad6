"""Small dense linear algebra for one pose, compiled (private).

3-vectors and 3x3 matrices are written out component by component (no temporaries), and
the few small systems of a pose (a leg's Gram matrix, the reduced Newton system, the 6x6
statics) are solved by the textbook algorithms below: Cholesky with a floor on the pivots
(on a block's lanes, :func:`cholesky_lanes`; one system is one lane), LU with partial
pivoting.  Eigenvalues and singular values are in :mod:`._eigen`.
"""

import math

import numpy as np
from ._jit import borrowing, inlined, inner, lanes, one_lane

@borrowing
def cross_to(a0, a1, a2, b0, b1, b2, out, k):
    out[k] = a1 * b2 - a2 * b1
    out[k + 1] = a2 * b0 - a0 * b2
    out[k + 2] = a0 * b1 - a1 * b0


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
    ``piv`` says); returns the sign of ``det A`` (0 for an exactly singular ``A``)."""
    sign = 1.0
    for j in range(n):
        p = j
        big = abs(A[j, j])
        for i in range(j + 1, n):
            if abs(A[i, j]) > big:
                big, p = abs(A[i, j]), i
        piv[j] = p
        if p != j:
            sign = -sign
            for k in range(n):
                A[j, k], A[p, k] = A[p, k], A[j, k]
        if A[j, j] == 0.0:
            return 0.0
        if A[j, j] < 0.0:
            sign = -sign
        inv = 1.0 / A[j, j]
        for i in range(j + 1, n):
            f = A[i, j] * inv
            A[i, j] = f
            for k in range(j + 1, n):
                A[i, k] -= f * A[j, k]
    return sign


@borrowing
def lu_apply(A, n, piv, b):
    """Solve ``A x = b`` in place with the factors of :func:`lu_factor`."""
    for j in range(n):                  # the row interchanges, in order (whole rows)
        p = piv[j]
        if p != j:
            b[j], b[p] = b[p], b[j]
    for i in range(1, n):
        s = b[i]
        for k in range(i):
            s -= A[i, k] * b[k]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= A[i, k] * b[k]
        b[i] = s / A[i, i]
