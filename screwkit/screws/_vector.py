"""The cross product of 3-vectors without numpy's generic machinery (private).

``numpy.cross`` moves axes and validates its arguments on every call: ~15 us for two
3-vectors, which dominated the Table I validation (tens of thousands of calls).  This one
takes ``(..., 3)`` arrays (broadcast, last axis the components) and has a fast path for
two plain 3-vectors.
"""

from __future__ import annotations

import numpy as np

__all__ = ["cross"]


def cross(a, b) -> np.ndarray:
    """``a x b`` over the last axis (3 components), broadcasting the leading axes."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape == (3,) and b.shape == (3,):
        a0, a1, a2 = a.tolist()
        b0, b1, b2 = b.tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)
