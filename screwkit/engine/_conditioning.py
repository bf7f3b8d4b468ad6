"""Length-normalised conditioning of stacks of Jacobians, and their least-norm statics (private).

Rows ``[f; m]`` (moments about the base origin) are moved to the centroid ``c``
of the geometry and their moments divided by its characteristic length ``L``
(RMS distance of the points from ``c``), then scaled to unit norm.  The
condition number ``s_1 / s_6`` of that matrix is unit-free and frame-free.

The singular values come from the eigenvalues of the smaller Gram matrix (``Jn^T Jn``
6x6, one LAPACK call per pose; ``Jn Jn^T`` in closed form for up to 3 rows); where that
loses digits (condition above :data:`REFINE`, or 30 for the closed form) they are
recomputed by an SVD.  The statics solves ``Jn^T y = -W_n``: by LU for a square ``Jn``,
in the least-norm sense through ``Jn^T Jn`` for more rows, by the pseudo-inverse where the
condition exceeds :data:`REFINE`.
"""

from __future__ import annotations

import numpy as np
from ..screws import cross

__all__ = ["RANK_RTOL", "REFINE", "normalise_rows", "singular_values", "least_norm"]

#: Relative threshold on singular values below which a direction counts as lost.
RANK_RTOL = 1e-8
#: Above this condition number the fast paths are replaced by an SVD: the Gram matrix's
#: eigenvalues give the smallest singular value to about ``eps * cond^2 / 2`` relative
#: (1e-10 at 1e3; at 1e4 it was 1e-8, visible in a printed condition number).
REFINE = 1e3


def normalisation(points):
    """Centroid ``(N, 3)`` and characteristic length ``(N,)`` of point sets ``(N, p, 3)``."""
    c = points.mean(axis=1)
    L = np.sqrt(np.mean(np.sum((points - c[:, None]) ** 2, axis=2), axis=1))
    big = np.max(np.abs(points), axis=(1, 2))
    L = np.where(L <= 1e-12 * big, big, L)
    return c, np.where(L > 0, L, 1.0)


def normalise_rows(J, c, L):
    """Normalised, row-equilibrated rows ``Jn (N, m, 6)`` and the row norms ``d (N, m)``
    (``J[r] = d[r] * (back-transformed Jn[r])``)."""
    f = J[..., :3]
    m = (J[..., 3:] - cross(c[:, None, :], f)) / L[:, None, None]
    Jn = np.concatenate([f, m], axis=-1)
    d = np.linalg.norm(Jn, axis=-1)
    d = np.where(d > 0, d, 1.0)
    return Jn / d[..., None], d


def normalise_wrench(W, c, L):
    """``[f; (m - c x f) / L]`` for wrenches ``(N, ..., 6)``."""
    sh = (-1,) + (1,) * (W.ndim - 2) + (3,)
    f = W[..., :3]
    return np.concatenate([f, (W[..., 3:] - cross(c.reshape(sh), f)) /
                           L.reshape(sh[:-1] + (1,))], axis=-1)


def singular_values(Jn):
    """Singular values ``(N, min(m, 6))`` of ``Jn (N, m, 6)``, descending."""
    N, m, _ = Jn.shape
    k = min(m, 6)
    if N == 0 or m == 0:
        return np.zeros((N, k))
    # the smaller Gram matrix: J J^T (m x m) when m < 6, J^T J (6 x 6) otherwise
    Jt = np.swapaxes(Jn, 1, 2)
    M = Jn @ Jt if m < 6 else Jt @ Jn
    closed = M.shape[1] <= 3
    lam = (_eigvalsh3(M) if closed else np.linalg.eigvalsh(M))[:, ::-1][:, :k]
    s = np.sqrt(np.maximum(lam, 0.0))
    # the closed form keeps ~1e-14 absolute on the eigenvalues: refine from a ratio of 30
    bad = ~(s[:, k - 1] * (30.0 if closed else REFINE) > s[:, 0])
    if bad.any():
        s[bad] = np.linalg.svd(Jn[bad], compute_uv=False)[:, :k]
    return s


def _eigvalsh3(M):
    """Ascending eigenvalues of symmetric ``(N, k, k)`` matrices, ``k <= 3``, in closed form
    (the trigonometric solution of the characteristic cubic); the SVD refinement of
    :func:`singular_values` takes over where it loses digits."""
    k = M.shape[1]
    if k == 1:
        return M[:, :, 0].copy()
    if k == 2:
        a, b, d = M[:, 0, 0], M[:, 0, 1], M[:, 1, 1]
        h = np.sqrt(0.25 * (a - d) ** 2 + b * b)
        mid = 0.5 * (a + d)
        return np.stack([mid - h, mid + h], axis=1)
    a11, a22, a33 = M[:, 0, 0], M[:, 1, 1], M[:, 2, 2]
    a12, a13, a23 = M[:, 0, 1], M[:, 0, 2], M[:, 1, 2]
    q = (a11 + a22 + a33) / 3.0
    p1 = a12 ** 2 + a13 ** 2 + a23 ** 2
    p2 = (a11 - q) ** 2 + (a22 - q) ** 2 + (a33 - q) ** 2 + 2.0 * p1
    p = np.sqrt(p2 / 6.0)
    ps = np.where(p > 0, p, 1.0)
    b11, b22, b33 = (a11 - q) / ps, (a22 - q) / ps, (a33 - q) / ps
    b12, b13, b23 = a12 / ps, a13 / ps, a23 / ps
    r = 0.5 * (b11 * (b22 * b33 - b23 * b23) - b12 * (b12 * b33 - b23 * b13)
               + b13 * (b12 * b23 - b22 * b13))
    phi = np.arccos(np.clip(r, -1.0, 1.0)) / 3.0
    e1 = q + 2.0 * p * np.cos(phi)
    e3 = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
    e2 = 3.0 * q - e1 - e3
    return np.stack([e3, e2, e1], axis=1)


def least_norm(Jn, Wn, s):
    """Least-norm ``y (N, m)`` with ``Jn^T y = -Wn`` (least squares where it has no solution).

    ``s`` are the singular values of :func:`singular_values`; poses whose condition
    exceeds :data:`REFINE` are solved by the pseudo-inverse (numpy's cut-off).
    """
    N, m, _ = Jn.shape
    y = np.zeros((N, m))
    if N == 0 or m == 0:
        return y
    well = (s.shape[1] == 6) & (s[:, -1] * REFINE > s[:, 0]) if s.shape[1] == 6 else \
        np.zeros(N, bool)
    if well.any():
        if m == 6:          # square: the unique solution, without squaring the condition
            y[well] = np.linalg.solve(np.swapaxes(Jn[well], 1, 2), -Wn[well][..., None])[..., 0]
        else:
            M = np.einsum("nri,nrj->nij", Jn[well], Jn[well])
            z = np.linalg.solve(M, -Wn[well][..., None])[..., 0]
            y[well] = np.einsum("nrj,nj->nr", Jn[well], z)
    ill = ~well
    if ill.any():
        P = np.linalg.pinv(np.transpose(Jn[ill], (0, 2, 1)), rcond=max(m, 6) * np.finfo(float).eps)
        y[ill] = -np.einsum("nmj,nj->nm", P, Wn[ill])
    return y
