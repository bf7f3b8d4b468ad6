"""Scale-aware numerical tolerances.

All rank decisions in screwkit are made on *length-normalised* screws: linear
parts of twists and moment parts of wrenches are divided by a characteristic
length of the geometry, and the frame is moved to the centroid of the geometry,
so that a decision does not change when every length is multiplied by 1000 or
when the base frame is moved.  The relative tolerances below are the only
literals that decide ranks; every function takes them as overridable arguments.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "RANK_RTOL",
    "GEOMETRY_RTOL",
    "characteristic_length",
]

#: Relative tolerance on singular values of length-normalised screw matrices:
#: a singular value below ``RANK_RTOL * max(1, s_max)`` counts as zero.
RANK_RTOL = 1e-8

#: Relative tolerance for geometric predicates on unit vectors and on distances
#: divided by the characteristic length (parallel, perpendicular, meets).
GEOMETRY_RTOL = 1e-7


def characteristic_length(points) -> float:
    """Characteristic length of a set of points.

    Parameters
    ----------
    points : array_like, shape (..., 3)

    Returns
    -------
    float
        The RMS distance of the points from their centroid; when all the points
        coincide, their largest coordinate magnitude; 1.0 when they all lie at the
        origin (a pure-direction geometry has no length of its own).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    if p.size == 0:
        return 1.0
    return _spread_length(p, p.mean(axis=0))


def _spread_length(p: np.ndarray, centroid: np.ndarray) -> float:
    """:func:`characteristic_length` of the points ``p``, shape (n, 3), given their centroid."""
    if p.size == 0:
        return 1.0
    spread = float(np.sqrt(np.mean(np.sum((p - centroid) ** 2, axis=1))))
    if not math.isfinite(spread):
        return 1.0
    # coincident points: no spread to measure, fall back to the distance from the origin
    # (so the result still scales with the units) or to 1 for points at the origin
    biggest = float(np.abs(p).max())
    if spread <= 1e-12 * biggest:
        spread = biggest
    return spread if spread > 0 else 1.0
