"""Small dense linear algebra for one pose, compiled (private).

3-vectors and 3x3 matrices are written out component by component (no temporaries), and
the few small systems of a pose (a leg's Gram matrix, the reduced Newton system, the 6x6
statics) are solved by the textbook algorithms below: Cholesky with a floor on the pivots,
LU with partial pivoting, and one-sided Jacobi for singular values (high relative accuracy,
so the condition number keeps its digits up to the singular threshold without a second
method).
"""

import math

import numpy as np
from ._jit import inlined, inner, lanes, one_lane

#: Largest one-sided Jacobi sweeps (6x6 converges in 5 to 7).
JACOBI_SWEEPS = 30
#: Two rows count as orthogonal when their cosine is below this.
JACOBI_TOL = 1e-15
#: Below this condition number the singular values come from the Gram matrix's eigenvalues
#: (``s_k`` to about ``eps cond^2 / 2`` relative: 5e-12 at 300), beyond by Jacobi.
REFINE_GRAM = 300.0


@inner
def cross_to(a0, a1, a2, b0, b1, b2, out, k):
    out[k] = a1 * b2 - a2 * b1
    out[k + 1] = a2 * b0 - a0 * b2
    out[k + 2] = a0 * b1 - a1 * b0


@inner
def matmul3(A, B, C):
    """``C = A @ B`` for 3x3 arrays (``C`` distinct from both)."""
    for i in range(3):
        a0, a1, a2 = A[i, 0], A[i, 1], A[i, 2]
        for j in range(3):
            C[i, j] = a0 * B[0, j] + a1 * B[1, j] + a2 * B[2, j]


@inner
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


@inner
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


@inner
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


@inner
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


@inner
def jacobi_rows(U, m, V, want_v):
    """One-sided Jacobi on the ``m`` rows of ``U (m, 6)``: rotates them (in place) until
    they are mutually orthogonal; their norms are then the singular values.  With
    ``want_v`` the rotations are accumulated in ``V (m, m)`` (``U_final = V^T U``).
    Returns the number of sweeps."""
    if want_v:
        for i in range(m):
            for j in range(m):
                V[i, j] = 1.0 if i == j else 0.0
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
                if g == 0.0 or abs(g) <= JACOBI_TOL * math.sqrt(a * b):
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


@inner
def singular_values(J, m, U, s, k, e):
    """The ``k = min(m, 6)`` largest singular values of ``J[:m] (m, 6)``, descending, into
    ``s[:k]`` (NaN beyond; ``U (>= max(m, 6), >= 6)`` and ``e (6,)`` scratch).  From the eigenvalues of the
    smaller Gram matrix where the condition ``s_1 / s_k`` is below :data:`REFINE_GRAM` (they
    give ``s_k`` to about ``eps cond^2 / 2`` relative), else by one-sided Jacobi (high
    relative accuracy)."""
    g = min(m, 6)
    if g == 0:
        for q in range(s.shape[0]):
            s[q] = np.nan
        return
    for a in range(g):
        for b in range(a + 1):
            t = 0.0
            if m < 6:                      # J J^T
                for c in range(6):
                    t += J[a, c] * J[b, c]
            else:                          # J^T J
                for r in range(m):
                    t += J[r, a] * J[r, b]
            U[a, b] = t
    symmetric_eigenvalues(U, g, s, e)
    for q in range(g):
        s[q] = math.sqrt(max(s[q], 0.0))
    for q in range(g):                     # descending (g <= 6: a selection sort)
        for r in range(q + 1, g):
            if s[r] > s[q]:
                s[q], s[r] = s[r], s[q]
    if not s[g - 1] * REFINE_GRAM > s[0]:
        for i in range(m):
            for c in range(6):
                U[i, c] = J[i, c]
        jacobi_rows(U, m, U, False)
        for i in range(m):
            t = 0.0
            for c in range(6):
                t += U[i, c] * U[i, c]
            U[i, 0] = math.sqrt(t)
        for q in range(k):             # the k largest norms, descending
            best = -1.0
            bi = 0
            for i in range(m):
                if U[i, 0] > best:
                    best, bi = U[i, 0], i
            s[q] = best
            U[bi, 0] = -2.0
    for q in range(k, s.shape[0]):
        s[q] = np.nan


@inner
def symmetric_eigenvalues(A, n, d, e):
    """The eigenvalues of the symmetric ``A[:n, :n]`` (overwritten) into ``d[:n]``, in no
    order: Householder reduction to tridiagonal form, then the implicit QL iteration
    (``e (>= n)`` scratch).  About ``eps |A|`` absolute accuracy."""
    for i in range(n - 1, 0, -1):
        lm = i - 1
        h = 0.0
        if lm > 0:
            scale = 0.0
            for k in range(lm + 1):
                scale += abs(A[i, k])
            if scale == 0.0:
                e[i] = A[i, lm]
            else:
                sinv = 1.0 / scale
                for k in range(lm + 1):
                    A[i, k] *= sinv
                    h += A[i, k] * A[i, k]
                f = A[i, lm]
                g = -math.sqrt(h) if f >= 0.0 else math.sqrt(h)
                e[i] = scale * g
                h -= f * g
                A[i, lm] = f - g
                f = 0.0
                hinv = 1.0 / h
                for j in range(lm + 1):
                    g = 0.0
                    for k in range(j + 1):
                        g += A[j, k] * A[i, k]
                    for k in range(j + 1, lm + 1):
                        g += A[k, j] * A[i, k]
                    e[j] = g * hinv
                    f += e[j] * A[i, j]
                hh = f / (h + h)
                for j in range(lm + 1):
                    f = A[i, j]
                    g = e[j] - hh * f
                    e[j] = g
                    for k in range(j + 1):
                        A[j, k] -= f * e[k] + g * A[i, k]
        else:
            e[i] = A[i, lm]
    for i in range(n):
        d[i] = A[i, i]
    for i in range(1, n):
        e[i - 1] = e[i]
    e[n - 1] = 0.0
    for lo in range(n):
        for _ in range(60):
            m = lo
            while m < n - 1:
                dd = abs(d[m]) + abs(d[m + 1])
                if abs(e[m]) <= 2.220446049250313e-16 * dd:
                    break
                m += 1
            if m == lo:
                break
            g = (d[lo + 1] - d[lo]) / (2.0 * e[lo])
            r = math.sqrt(g * g + 1.0)
            g = d[m] - d[lo] + e[lo] / (g + (r if g >= 0.0 else -r))
            s = 1.0
            c = 1.0
            p = 0.0
            i = m - 1
            early = False
            while i >= lo:
                f = s * e[i]
                b = c * e[i]
                r = math.sqrt(f * f + g * g)
                e[i + 1] = r
                if r == 0.0:
                    d[i + 1] -= p
                    e[m] = 0.0
                    early = True
                    break
                inv = 1.0 / r             # (one division, not two: latency-bound)
                s = f * inv
                c = g * inv
                g = d[i + 1] - p
                r = (d[i] - g) * s + 2.0 * c * b
                p = s * r
                d[i + 1] = g + p
                g = c * r - b
                i -= 1
            if early:
                continue
            d[lo] -= p
            e[lo] = g
            e[m] = 0.0
