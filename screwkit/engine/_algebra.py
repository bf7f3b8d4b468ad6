"""Batched small-matrix algebra in structure-of-arrays layout (private).

Every function here works on arrays whose *leading* axes are the components
(a vector is ``(3, ...)``, a matrix ``(3, 3, ...)``) and whose trailing axes
``...`` are batch axes (poses, legs).  numpy then runs each component
operation over the whole batch in one call, which for 3-vectors and 3x3
matrices is several times faster than numpy's batched ``matmul`` on
``(N, 3, 3)`` stacks, and the symmetric positive definite solves below replace
one LAPACK call per pose.
"""

from __future__ import annotations

import numpy as np

from ..screws._euler import cos_sin

__all__ = ["cross", "dot", "norm", "matvec", "matmul", "matmul_t", "rodrigues",
           "rotation_vector", "spd_solve", "sym_solve", "unit"]



def cross(a, b):
    """``a x b`` for vectors ``(3, ...)`` (broadcast)."""
    a0, a1, a2 = a[0], a[1], a[2]
    b0, b1, b2 = b[0], b[1], b[2]
    x = a1 * b2 - a2 * b1
    out = np.empty((3,) + x.shape)
    out[0] = x
    np.subtract(a2 * b0, a0 * b2, out=out[1])
    np.subtract(a0 * b1, a1 * b0, out=out[2])
    return out


def dot(a, b):
    """``a . b`` over the leading axis."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return np.sqrt(dot(a, a))


def unit(a, floor: float = 1e-300):
    return a / np.maximum(norm(a), floor)


def matvec(R, v):
    """``R @ v`` for ``R (3, 3, ...)`` and ``v (3, ...)``."""
    return R[:, 0] * v[0] + R[:, 1] * v[1] + R[:, 2] * v[2]


def matmul(R, S):
    """``R @ S`` for ``(3, 3, ...)`` stacks (broadcast over the batch axes)."""
    return np.einsum("ik...,kj...->ij...", R, S)


def matmul_t(R, S):
    """``R @ S.T`` (per batch element)."""
    return np.einsum("ik...,jk...->ij...", R, S)


def rodrigues(d, angle):
    """Rotations by ``angle (...)`` about unit axes ``d (3, ...)``: ``(3, 3, ...)``.

    ``R = c I + s [d]x + (1 - c) d d^T``.  The axis products are formed first: a home axis
    ``d (3, n, 1)`` is constant over the poses, so they cost nothing, and few pose-sized
    temporaries are alive at once (the working set of a chunk stays in cache).
    """
    c, s = cos_sin(angle)
    v = 1.0 - c
    x, y, z = d[0], d[1], d[2]
    R = np.empty((3, 3) + np.broadcast_shapes(x.shape, v.shape))
    for k, (a, b) in enumerate(((x, x), (y, y), (z, z))):
        np.multiply(a * b, v, out=R[k, k])
        R[k, k] += c
    for i, j, p, q, w in ((0, 1, x, y, z), (1, 2, y, z, x), (2, 0, z, x, y)):
        # (i, j, w) cyclic in (x, y, z): R[i, j] = p q v - w s and R[j, i] = p q v + w s
        sym, skew = (p * q) * v, w * s
        np.subtract(sym, skew, out=R[i, j])
        np.add(sym, skew, out=R[j, i])
    return R


def rotation_vector(R):
    """Rotation vectors ``(3, ...)`` of rotation matrices ``(3, 3, ...)`` (angle in [0, pi])."""
    w = 0.5 * np.stack([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    c = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    s = norm(w)
    small = s <= 1e-12
    f = np.where(small, 1.0, np.arctan2(s, c) / np.where(small, 1.0, s))
    out = w * f
    far = c < -0.9
    if np.any(far):
        # near pi the antisymmetric part vanishes: take the axis from the symmetric part
        Rf, cf, wf = R[:, :, far], c[far], w[:, far]
        B = 0.5 * (Rf + Rf.transpose(1, 0, 2)) - cf * np.eye(3)[:, :, None]
        k = np.argmax(np.stack([B[0, 0], B[1, 1], B[2, 2]]), axis=0)
        col = B[:, k, np.arange(B.shape[2])]
        axis = col / np.maximum(norm(col), 1e-300)
        sign = np.where(dot(axis, wf) < 0, -1.0, 1.0)
        out[:, far] = axis * (sign * np.arctan2(norm(wf), cf))
    return out


def spd_solve(G, B, shift=0.0):
    """Solve ``G X = B`` for symmetric positive (semi-)definite ``G``, batched (Cholesky).

    Parameters
    ----------
    G : sequence of sequences of ndarray
        ``G[i][j]`` for ``j <= i`` (the lower triangle), each of batch shape ``...``.
    B : sequence of ndarray
        ``B[i]`` of shape ``(r, ...)`` or ``...``: the right-hand sides, row by row (the
        products of the factor with them have the shape of ``B[i]``).
    shift : float or ndarray
        Added to the diagonal (Tikhonov regularisation of singular systems: the
        solution tends to the least-norm one).

    Returns
    -------
    X : list of ndarray
        Row ``i`` of the solution, shaped like ``B[i]``.
    pivots : list of ndarray
        The squared Cholesky pivots (a pivot near 0 marks a near-singular ``G``).
    """
    m = len(B)
    Lo = [[None] * m for _ in range(m)]
    inv, piv = [None] * m, [None] * m
    # in-place updates of the fresh arrays that the first operation of each entry makes
    # (the same operations as ``s = s - a * b``, without the temporaries)
    for j in range(m):
        s = G[j][j] + shift
        for k in range(j):
            s -= Lo[j][k] * Lo[j][k]
        piv[j] = s
        inv[j] = 1.0 / np.sqrt(np.maximum(s, 1e-300))
        for i in range(j + 1, m):
            if j == 0:
                Lo[i][j] = G[i][j] * inv[j]
                continue
            s = G[i][j] - Lo[i][0] * Lo[j][0]
            for k in range(1, j):
                s -= Lo[i][k] * Lo[j][k]
            s *= inv[j]
            Lo[i][j] = s
    Y = [None] * m
    for i in range(m):
        if i == 0:
            Y[i] = B[i] * inv[i]
            continue
        s = B[i] - Lo[i][0] * Y[0]
        for k in range(1, i):
            s -= Lo[i][k] * Y[k]
        s *= inv[i]
        Y[i] = s
    X = [None] * m
    for i in range(m - 1, -1, -1):
        s = Y[i]                  # owned by this loop (no other reference is kept)
        for k in range(i + 1, m):
            s -= Lo[k][i] * X[k]
        s *= inv[i]
        X[i] = s
    return X, piv


#: Largest batch (product of the batch axes) that :func:`sym_solve` hands to LAPACK in one
#: call; beyond it the component-wise Cholesky of :func:`spd_solve` is faster.
_LAPACK_BATCH = 64


def sym_solve(G, B, shift=0.0):
    """The solution rows of :func:`spd_solve` (``G X = B`` with ``shift`` on the diagonal),
    without the pivots.

    ``G`` is an array ``(m, m, ...)`` (both triangles filled) and ``B`` a sequence of ``m``
    right-hand-side rows.  A small batch (one pose) is solved by one batched LAPACK call
    instead of the ~m^3 component operations of the Cholesky loops (the same linear system;
    the solutions agree to round-off); a large batch, a zero pivot or a non-finite entry
    takes :func:`spd_solve`.
    """
    G = np.asarray(G)
    m = G.shape[0]
    batch = G.shape[2:]
    if m and int(np.prod(batch)) <= _LAPACK_BATCH:
        Bs = np.stack([np.asarray(b, float) for b in B])    # (m, [r,] ...)
        A = np.moveaxis(G, (0, 1), (-2, -1)) + np.multiply.outer(
            np.broadcast_to(np.asarray(shift, float), batch), np.eye(m))
        if np.all(np.isfinite(A)) and np.all(np.isfinite(Bs)):
            rhs = np.moveaxis(Bs.reshape((m, -1) + batch), (0, 1), (-2, -1))
            try:
                X = np.linalg.solve(A, rhs)                   # (..., m, r)
            except np.linalg.LinAlgError:
                X = None
            if X is not None and np.all(np.isfinite(X)):
                X = np.moveaxis(X, (-2, -1), (0, 1)).reshape(Bs.shape)
                return list(X)
    return spd_solve(G, B, shift)[0]
