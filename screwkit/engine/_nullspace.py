"""Null spaces of a leg's dimensionless rows and their canonical bases, batched (private).

Used by :mod:`screwkit.engine._rows` (see there for the rules they serve).
"""

from __future__ import annotations

import numpy as np

from . import _algebra as alg

__all__ = ["ZERO", "null_space", "canonical_basis", "pairs"]

#: Relative size below which a null-space test quantity counts as zero.
ZERO = 1e-8


def null_space(rows, g):
    """The null space of dimension ``g`` of dimensionless rows (list of ``(3, N)``).

    Returns ``(vec, ok)``: for ``g = 1`` the unit null vector, for ``g = 2`` the unit
    normal of the null plane, for ``g = 3`` None; ``ok (N,)`` is False where the rows
    do not leave a null space of exactly dimension ``g`` (within :data:`ZERO`).
    """
    R = np.stack(rows) if rows else np.zeros((0, 3, 1))
    N = R.shape[-1]
    nrm = alg.norm(R.transpose(1, 0, 2)) if len(R) else np.zeros((0, N))   # (r, N)
    if g >= 3:
        return None, np.max(nrm, axis=0, initial=0.0) < ZERO
    if g == 2:
        k = np.argmax(nrm, axis=0)
        n = R[k, :, np.arange(N)].T
        n = n / np.maximum(alg.norm(n), 1e-300)
        off = np.max(alg.norm(alg.cross(R.transpose(1, 0, 2), n[:, None])), axis=0)
        return n, (np.max(nrm, axis=0) > 1e-6) & (off < ZERO)
    r = len(R)
    if r < 2:
        return np.full((3, N), np.nan), np.zeros(N, bool)
    i1, i2 = pairs(r)
    C = alg.cross(R[i1].transpose(1, 0, 2), R[i2].transpose(1, 0, 2))   # (3, pairs, N)
    size = alg.norm(C)                       # rows are dimensionless: the largest cross wins
    k = np.argmax(size, axis=0)
    cols = np.arange(N)
    best = C[:, k, cols]
    brel = size[k, cols] / np.maximum(nrm[i1[k], cols] * nrm[i2[k], cols], 1e-300)
    u = best / np.maximum(alg.norm(best), 1e-300)
    res = np.max(np.abs(alg.dot(R.transpose(1, 0, 2), u[:, None])), axis=0)
    return u, (brel > 1e-6) & (res < ZERO)


_PAIRS: dict = {}


def pairs(r):
    """``np.triu_indices(r, 1)`` (memoised: the same few sizes recur at every pose)."""
    p = _PAIRS.get(r)
    if p is None:
        p = _PAIRS[r] = tuple(np.triu_indices(r, 1))
        for a in p:
            a.setflags(write=False)
    return p


def canonical_basis(g, vec, refs):
    """Canonical basis (list of ``(3, N)``) of a null space from its reference directions,
    and the smallest Gram-Schmidt remainder (N,)."""
    out, worst = [], None
    for r in refs[:g]:
        if g == 1:
            c = alg.dot(vec, r)
            e = vec * np.where(c < 0, -1.0, 1.0)
            rem = np.abs(c)
        else:
            p = r - vec * alg.dot(vec, r) if g == 2 else r
            for b in out:
                p = p - b * alg.dot(b, p)
            rem = alg.norm(p)
            e = p / np.maximum(rem, 1e-300)
        out.append(e)
        worst = rem if worst is None else np.minimum(worst, rem)
    return out, worst
