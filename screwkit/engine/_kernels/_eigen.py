"""Eigenvalues and singular values of small matrices, compiled (private).

The conditioning's singular values come from the eigenvalues of the smaller Gram matrix
(Householder reduction to tridiagonal form, then the root-free QL iteration) where the
condition is moderate, and from one-sided Jacobi (high relative accuracy, so the condition
number keeps its digits up to the singular threshold without a second method) beyond;
one-sided Jacobi also gives the statics' pseudo-inverse and the indices' columns.

The Gram matrices and their eigenvalues are computed for the lanes of a block at once (the
lane axis last, ``ls`` apart: :func:`~._jit.lanes`), one pose being a block of one; the
eigenvalues by :func:`._tridiagonal.symmetric_eigenvalues_lanes` (the lanes in step, each
exactly as alone).
"""

import math

import numpy as np
from ._jit import borrowing, borrowing_inlined, lanes
from ._tridiagonal import EPS2, symmetric_eigenvalues_lanes

#: Largest one-sided Jacobi sweeps (6x6 converges in 5 to 7).
JACOBI_SWEEPS = 30
#: Two rows count as orthogonal when their cosine is below this.
JACOBI_TOL = 1e-15
#: Below this condition number the singular values come from the Gram matrix's eigenvalues
#: (``s_k`` to about ``eps cond^2 / 2`` relative: 5e-12 at 300), beyond by Jacobi.
REFINE_GRAM = 300.0


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
