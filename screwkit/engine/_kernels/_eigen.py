"""Eigenvalues and singular values of one pose's small matrices, compiled (private).

The conditioning's singular values come from the eigenvalues of the smaller Gram matrix
(Householder reduction to tridiagonal form, then the root-free QL iteration) where the
condition is moderate, and from one-sided Jacobi (high relative accuracy, so the condition
number keeps its digits up to the singular threshold without a second method) beyond;
one-sided Jacobi also gives the statics' pseudo-inverse and the indices' columns.
"""

import math

import numpy as np
from ._jit import borrowing

#: Largest one-sided Jacobi sweeps (6x6 converges in 5 to 7).
JACOBI_SWEEPS = 30
#: Two rows count as orthogonal when their cosine is below this.
JACOBI_TOL = 1e-15
#: Below this condition number the singular values come from the Gram matrix's eigenvalues
#: (``s_k`` to about ``eps cond^2 / 2`` relative: 5e-12 at 300), beyond by Jacobi.
REFINE_GRAM = 300.0
#: The square of the unit roundoff (the QL's convergence test on squared off-diagonals).
EPS2 = 2.220446049250313e-16 ** 2


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


@borrowing
def symmetric_eigenvalues(A, n, d, e):
    """The eigenvalues of the symmetric ``A[:n, :n]`` (overwritten; entries of order one, as
    in a Gram matrix of unit rows) into ``d[:n]``, in no
    order: Householder reduction to tridiagonal form, then the root-free implicit QL
    iteration (Pal-Walker-Kahan; a 2x2 block left is solved directly) (``e (>= n)``
    scratch).  About ``eps |A|`` absolute accuracy."""
    # Householder from the last row up (no scaling of the rows: the entries are of order one,
    # the Gram matrices of unit rows; a row whose part left of the diagonal is below 1e-125
    # is taken as reduced, so that 1 / h cannot overflow)
    for i in range(n - 1, 0, -1):
        lm = i - 1
        if lm == 0:
            e[i] = A[i, 0]
            continue
        h = 0.0
        for k in range(lm + 1):
            h += A[i, k] * A[i, k]
        if h <= 1e-250:
            e[i] = A[i, lm]
            continue
        f = A[i, lm]
        g = -math.sqrt(h) if f >= 0.0 else math.sqrt(h)
        e[i] = g
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
        hh = 0.5 * f * hinv
        for j in range(lm + 1):
            f = A[i, j]
            g = e[j] - hh * f
            e[j] = g
            for k in range(j + 1):
                A[j, k] -= f * e[k] + g * A[i, k]
    for i in range(n):
        d[i] = A[i, i]
    # root-free implicit QL (Pal-Walker-Kahan, as LAPACK's dsterf): the iteration runs on the
    # squares of the off-diagonal, so a rotation needs no square root; and with
    # ``gamma' r = p (alpha - sigma) - b^2 gamma`` one division by ``r p`` gives ``1 / r``,
    # ``gamma'`` and ``p' = gamma'^2 / c`` alike (one division a rotation, not a square root
    # and two: the loop is latency-bound)
    for i in range(1, n):
        e[i - 1] = e[i] * e[i]
    e[n - 1] = 0.0
    lo = 0
    its = 0
    while lo < n:
        m = lo
        while m < n - 1:                  # |e_m| <= eps (|d_m| + |d_m+1|), squared
            t = abs(d[m]) + abs(d[m + 1])
            if e[m] <= EPS2 * t * t:
                break
            m += 1
        if m == lo:                       # d[lo] converged
            lo += 1
            its = 0
            continue
        if m == lo + 1:                   # a 2x2 block left: its eigenvalues directly
            a, c = d[lo], d[lo + 1]
            b2 = e[lo]
            sm = a + c
            rt = math.sqrt((a - c) * (a - c) + 4.0 * b2)
            r1 = 0.5 * (sm + rt) if sm >= 0.0 else 0.5 * (sm - rt)
            d[lo] = r1
            d[lo + 1] = (a * c - b2) / r1 if r1 != 0.0 else 0.0   # the smaller without cancellation
            e[lo] = 0.0
            lo += 2
            its = 0
            continue
        if its == 60:
            lo += 1
            its = 0
            continue
        its += 1
        # Wilkinson's shift: the eigenvalue of the leading 2x2 nearer d[lo] (one square root
        # and one division, from the squared off-diagonal)
        g = 0.5 * (d[lo + 1] - d[lo])
        r = math.sqrt(g * g + e[lo])
        sigma = d[lo] - e[lo] / (g + (r if g >= 0.0 else -r))
        c = 1.0
        s = 0.0
        gamma = d[m] - sigma
        p = gamma * gamma
        for i in range(m - 1, lo - 1, -1):
            bb = e[i]
            r = p + bb
            if i != m - 1:
                e[i + 1] = s * r
            alpha = d[i]
            gt = p * (alpha - sigma) - bb * gamma     # the new gamma times r
            rp = r * p
            if rp != 0.0:
                inv = 1.0 / rp
                ir = p * inv                          # 1 / r
                c = p * ir
                s = bb * ir
                ng = gt * ir
                p = gt * gt * inv                     # gamma^2 / c
            else:                                     # c = 0
                s = 1.0
                ng = -gamma
                p = c * bb
                c = 0.0
            d[i + 1] = gamma + (alpha - ng)
            gamma = ng
        e[lo] = s * p
        d[lo] = sigma + gamma
