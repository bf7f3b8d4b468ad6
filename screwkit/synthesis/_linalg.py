"""Small 3-vector helpers of the synthesis: unit vectors, random directions, null spaces.

Everything here works on exact target geometry (``NULL_RTOL`` only absorbs rounding).
"""

from __future__ import annotations

import math

import numpy as np

from ..screws import cross
from ..screws._svd import decided_count, small_singular_values, svd_full, svd_values

__all__ = ["NULL_RTOL", "cross", "unit", "random_unit", "perpendicular_unit", "null_basis",
           "null_dimension"]

#: Relative tolerance of the null spaces of the rule matrices (built exactly from the
#: target geometry, so only rounding separates a zero from a non-zero singular value).
NULL_RTOL = 1e-9


def unit(v):
    v = np.asarray(v, float)
    if v.ndim == 1:
        # np.linalg.norm of a vector is sqrt(x.dot(x)) on its contiguous ravel: the same value
        x = v.ravel(order="K")
        return v / math.sqrt(x.dot(x))
    return v / np.linalg.norm(v)


def random_unit(rng):
    return unit(rng.standard_normal(3))


def perpendicular_unit(rng, *vs):
    """A random unit vector perpendicular to every vector in ``vs``."""
    x = rng.standard_normal(3)
    for v in vs:
        v = unit(v)
        x = x - np.dot(x, v) * v
    return unit(x)


def null_basis(M, rtol=NULL_RTOL) -> np.ndarray:
    """Orthonormal basis (rows) of the null space of M (rows of length 3)."""
    M = np.asarray(M, float).reshape(-1, 3)
    if len(M) == 0:
        return np.eye(3)
    _, s, Vt = svd_full(M)
    return Vt[_rank(M, s.tolist(), rtol):]


def null_dimension(M, rtol=NULL_RTOL) -> int:
    """``len(null_basis(M, rtol))`` from the singular values alone (no basis computed)."""
    M = np.asarray(M, float).reshape(-1, 3)
    if len(M) == 0:
        return 3
    rows = M.tolist()
    s = small_singular_values(rows)
    r = None if s is None else decided_count(s, _tol(rows, rtol))
    return 3 - (_rank(M, svd_values(M).tolist(), rtol) if r is None else r)


def _tol(rows, rtol) -> float:
    # threshold relative to the largest row norm (not below 1)
    return rtol * max(1.0, max(math.sqrt(a * a + b * b + c * c) for a, b, c in rows))


def _rank(M, s, rtol) -> int:
    tol = _tol(M.tolist(), rtol)
    return sum(x > tol for x in s)
