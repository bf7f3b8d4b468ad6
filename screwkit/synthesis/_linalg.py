"""Small 3-vector helpers of the synthesis: unit vectors, random directions, null spaces.

Everything here works on exact target geometry (``NULL_RTOL`` only absorbs rounding).
"""

from __future__ import annotations

import numpy as np

from ..screws import cross

__all__ = ["NULL_RTOL", "cross", "unit", "random_unit", "perpendicular_unit", "null_basis"]

#: Relative tolerance of the null spaces of the rule matrices (built exactly from the
#: target geometry, so only rounding separates a zero from a non-zero singular value).
NULL_RTOL = 1e-9


def unit(v):
    v = np.asarray(v, float)
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
    _, s, Vt = np.linalg.svd(M, full_matrices=True)
    scale = max(1.0, float(np.max(np.linalg.norm(M, axis=1))))
    r = int(np.sum(s > rtol * scale))
    return Vt[r:]
